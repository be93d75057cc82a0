/* cmd_photonmap.c - `radiosity photonmap`: an image by photon mapping (docs/photonmapping.md),
 * with the path tracer's camera and output options. Everything that can be refused cheaply
 * (flags, the output path, the camera, the photon budget) is refused before any photon is
 * traced, so a bad command fails at once and never leaves a file. */
#include "camera_options.h"
#include "image_options.h"
#include "cli.h"
#include "light_options.h"
#include "output_path.h"
#include "pipeline.h"
#include "progress.h"

#include <math.h>
#include <stdlib.h>

typedef struct photonmap_args {
    int spp, gather, nearest, progressive, threads, quiet, stats;
    size_t seed, photons, caustic_photons;
    double radius, max_memory;
    cli_image_args image;
    cli_camera_args camera;
    cli_light_args lights; /* --sky, --sun, --ies, --two-sided */
} photonmap_args;

int cmd_photonmap(int argc, char **argv) {
    static const char synopsis[] =
        "[SCENE] -o FILE [options]   (SCENE: a file or a built-in name; default cornell)";
    photonmap_args a = {0};
    cli_image_args_init(&a.image);
    a.spp = 4;
    a.gather = 16;
    a.nearest = 20;
    a.photons = 200000;
    a.caustic_photons = (size_t)-1; /* as many as --photons */
    a.radius = NAN;                 /* chosen from --nearest */
    cli_camera_args_init(&a.camera);
    const cli_option options[] = {
        CLI_IMAGE_OUTPUT_OPTIONS(&a.image),
        {"--photons", CLI_SIZE, &a.photons, "N  photons emitted for the global map (200000)"},
        {"--caustic-photons", CLI_SIZE, &a.caustic_photons,
         "N  photons emitted more for the caustic map, when there is a mirror or glass (as many "
         "as --photons)"},
        {"--radius", CLI_DOUBLE, &a.radius,
         "R  largest density-estimation radius, scene units (the radius holding --nearest "
         "photons on average)"},
        {"--nearest", CLI_INT, &a.nearest, "K  photons in a density estimate, k nearest (20)"},
        {"--gather", CLI_INT, &a.gather, "N  final-gather rays per camera sample (16)"},
        {"--spp", CLI_INT, &a.spp, "N  camera samples per pixel, box filter (4)"},
        {"--progressive", CLI_INT, &a.progressive,
         "N  progressive photon mapping: N passes of fresh photons, radii shrinking (off)"},
        {"--seed", CLI_SIZE, &a.seed, "S  random seed; the same seed gives the same image (0)"},
        CLI_IMAGE_SIZE_OPTIONS(&a.image),
        CLI_CAMERA_OPTIONS(&a.camera),
        CLI_LIGHT_OPTIONS(&a.lights),
        CLI_TWO_SIDED_OPTION(&a.lights),
        CLI_IMAGE_FILE_OPTIONS(&a.image),
        {"--threads", CLI_INT, &a.threads, "N  worker threads (all cores)"},
        {"--max-memory", CLI_MEMORY, &a.max_memory, "MIB  memory budget for photons and image, in MiB or as 512M, 2G (2048)"},
        {"--stats", CLI_FLAG, &a.stats, "print the stages' times, photons per second and radii"},
        {"--quiet", CLI_FLAG, &a.quiet, "no progress bar or notes on stderr"},
        {NULL, 0, NULL, NULL},
    };
    const char *positional[1];
    int positional_count;
    int status =
        cli_parse("photonmap", synopsis, options, argc, argv, positional, 1, &positional_count);
    if (status) return status < 0 ? 0 : status;
    if ((status = cli_image_check("photonmap", &a.image))) return status;
    if (a.spp < 1) return cli_error(EXIT_USAGE, "photonmap: --spp must be at least 1");
    if (a.gather < 1) return cli_error(EXIT_USAGE, "photonmap: --gather must be at least 1");
    if (a.nearest < 2) return cli_error(EXIT_USAGE, "photonmap: --nearest must be at least 2");
    if (a.progressive < 0)
        return cli_error(EXIT_USAGE, "photonmap: --progressive must be at least 1 (passes)");
    if (a.photons < 1) return cli_error(EXIT_USAGE, "photonmap: --photons must be at least 1");
    if (a.caustic_photons < 1)
        return cli_error(EXIT_USAGE, "photonmap: --caustic-photons must be at least 1");
    if (a.caustic_photons == (size_t)-1) a.caustic_photons = a.photons;
    if (!isnan(a.radius) && !(a.radius > 0))
        return cli_error(EXIT_USAGE, "photonmap: --radius must be positive, not %g", a.radius);
    if ((status = cli_camera_check("photonmap", &a.camera))) return status;
    if ((status = cli_lights_check("photonmap", &a.lights))) return status;
    if (a.max_memory < 0) return cli_error(EXIT_USAGE, "photonmap: --max-memory must be positive");

    cli_image_run run;
    const char *scene_name = positional_count ? positional[0] : "cornell";
    if ((status = cli_image_open("photonmap", &a.image, a.threads, (uint64_t)a.seed, a.max_memory,
                                 a.quiet, scene_name, &run)))
        return status;
    rad_image *image = NULL;
    rad_photonmap_stats stats = {0};
    double write_seconds = 0;
    if (!run.status) {
        rad_camera_desc camera;
        cli_camera_get(&a.camera, run.scene, &camera);
        rad_photonmap_options o = {0};
        o.width = a.image.width;
        o.height = a.image.height;
        o.camera = &camera;
        o.samples_per_pixel = a.spp;
        o.gather_rays = a.gather;
        o.photons = a.photons;
        o.caustic_photons = a.caustic_photons;
        o.radius = isnan(a.radius) ? 0 : a.radius;
        o.nearest = a.nearest;
        o.iterations = a.progressive;
        cli_stage("photonmap", "%dx%d pixels, %d samples per pixel, %zu + %zu photons%s",
                  a.image.width, a.image.height, a.spp, a.photons, a.caustic_photons,
                  a.progressive > 1 ? ", progressive" : "");
        run.status = rad_photonmap(run.ctx, run.scene, &o, &image, &stats);
    }
    cli_image_write(&run, &a.image, image, &write_seconds);
    int exit_status = 0;
    if (run.status) exit_status = cli_fail(run.ctx, run.status);
    else if (a.stats) {
        double trace = stats.trace_seconds > 0 ? stats.trace_seconds : 1e-9;
        printf("photon tracing %8.3f s   %llu photons, %.3g Mphotons/s (processor time %.3f s: "
               "%.3g Mphotons per processor-second)\n",
               stats.trace_seconds, (unsigned long long)stats.photons_emitted,
               stats.photons_emitted / trace * 1e-6, stats.trace_cpu_seconds,
               stats.trace_cpu_seconds > 0 ? stats.photons_emitted / stats.trace_cpu_seconds * 1e-6
                                           : 0);
        printf("maps           %8.3f s   %llu global, %llu caustic photons stored; radius %.4g, "
               "caustic %.4g\n",
               stats.build_seconds, (unsigned long long)stats.global_stored,
               (unsigned long long)stats.caustic_stored, stats.radius, stats.caustic_radius);
        printf("rendering      %8.3f s   %llu rays\n", stats.render_seconds,
               (unsigned long long)stats.rays);
        printf("total          %8.3f s\n", stats.seconds);
        printf("write          %8.3f s\n", write_seconds);
    }
    rad_image_destroy(image);
    cli_image_close(&run);
    return exit_status;
}
