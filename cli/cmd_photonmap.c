/* cmd_photonmap.c - `radiosity photonmap`: an image by photon mapping (docs/photonmapping.md),
 * with the path tracer's camera and output options. Everything that can be refused cheaply
 * (flags, the output path, the camera, the photon budget) is refused before any photon is
 * traced, so a bad command fails at once and never leaves a file. */
#include "camera_options.h"
#include "cli.h"
#include "light_options.h"
#include "output_path.h"
#include "pipeline.h"
#include "progress.h"

#include <math.h>
#include <stdlib.h>

#define MAX_SIDE 16384

typedef struct photonmap_args {
    const char *output, *tonemap;
    int width, height, spp, gather, nearest, progressive, threads, quiet, stats, half;
    size_t seed, photons, caustic_photons;
    double radius, exposure, max_memory;
    cli_camera_args camera;
    cli_light_args lights; /* --two-sided */
} photonmap_args;

int cmd_photonmap(int argc, char **argv) {
    static const char synopsis[] =
        "[SCENE] -o FILE [options]   (SCENE: a file or a built-in name; default cornell)";
    photonmap_args a = {0};
    a.tonemap = "clamp";
    a.width = a.height = 512;
    a.spp = 4;
    a.gather = 16;
    a.nearest = 50;
    a.photons = 200000;
    a.caustic_photons = (size_t)-1; /* as many as --photons */
    a.radius = NAN;                 /* chosen from --nearest */
    cli_camera_args_init(&a.camera);
    const cli_option options[] = {
        {"-o", CLI_STRING, &a.output, "FILE  output image: .png, .hdr, .pfm, .exr (required)"},
        {"--output", CLI_STRING, &a.output, "FILE  the same as -o"},
        {"--photons", CLI_SIZE, &a.photons, "N  photons emitted for the global map (200000)"},
        {"--caustic-photons", CLI_SIZE, &a.caustic_photons,
         "N  photons emitted more for the caustic map, when there is a mirror or glass (as many "
         "as --photons)"},
        {"--radius", CLI_DOUBLE, &a.radius,
         "R  largest density-estimation radius, scene units (the radius holding --nearest "
         "photons on average)"},
        {"--nearest", CLI_INT, &a.nearest, "K  photons in a density estimate, k nearest (50)"},
        {"--gather", CLI_INT, &a.gather, "N  final-gather rays per camera sample (16)"},
        {"--spp", CLI_INT, &a.spp, "N  camera samples per pixel, box filter (4)"},
        {"--progressive", CLI_INT, &a.progressive,
         "N  progressive photon mapping: N passes of fresh photons, radii shrinking (off)"},
        {"--seed", CLI_SIZE, &a.seed, "S  random seed; the same seed gives the same image (0)"},
        {"--width", CLI_INT, &a.width, "W  image width in pixels (512)"},
        {"--height", CLI_INT, &a.height, "H  image height in pixels (512)"},
        CLI_CAMERA_OPTIONS(&a.camera),
        CLI_TWO_SIDED_OPTION(&a.lights),
        {"--exposure", CLI_DOUBLE, &a.exposure, "EV  exposure in stops, PNG only (0)"},
        {"--tonemap", CLI_STRING, &a.tonemap, "CURVE  none|clamp|reinhard|aces, PNG only (clamp)"},
        {"--half", CLI_FLAG, &a.half, "EXR only: 16-bit half floats (default 32-bit float)"},
        {"--threads", CLI_INT, &a.threads, "N  worker threads (all cores)"},
        {"--max-memory", CLI_DOUBLE, &a.max_memory, "MIB  memory budget for photons and image (2048)"},
        {"--stats", CLI_FLAG, &a.stats, "print the stages' times, photons per second and radii"},
        {"--quiet", CLI_FLAG, &a.quiet, "no progress bar or notes on stderr"},
        {NULL, 0, NULL, NULL},
    };
    const char *positional[1];
    int positional_count;
    int status =
        cli_parse("photonmap", synopsis, options, argc, argv, positional, 1, &positional_count);
    if (status) return status < 0 ? 0 : status;
    if (!a.output)
        return cli_error(EXIT_USAGE, "photonmap: an output file is required (-o FILE)");
    if (a.width < 1 || a.width > MAX_SIDE || a.height < 1 || a.height > MAX_SIDE)
        return cli_error(EXIT_USAGE, "photonmap: image size %dx%d: each side must be 1 to %d pixels",
                         a.width, a.height, MAX_SIDE);
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

    rad_context *ctx = cli_context_with_progress(a.threads, (uint64_t)a.seed, a.max_memory, a.quiet);
    rad_image_save_options save = {a.exposure, a.tonemap, a.half};
    rad_status rs = rad_image_check_path(ctx, a.output, &save);
    if (rs) {
        /* A bad extension or tone curve is a usage error; an unwritable place is not. */
        int usage = rs == RAD_ERROR_INVALID_ARGUMENT;
        cli_fail(ctx, rs);
        rad_context_destroy(ctx);
        return usage ? EXIT_USAGE : 1;
    }
    const char *scene_name = positional_count ? positional[0] : "cornell";
    rad_scene *scene = NULL;
    rad_image *image = NULL;
    rad_photonmap_stats stats = {0};
    double write_seconds = 0;
    rs = cli_load_scene(ctx, scene_name, &scene);
    if (!rs && (status = cli_check_outputs_against_scene("photonmap", scene, &a.output, 1))) {
        rad_scene_destroy(scene); /* the output is the scene's .mtl, .bin, a texture, ... */
        rad_context_destroy(ctx);
        return status;
    }
    if (!rs) {
        rad_camera_desc camera;
        cli_camera_get(&a.camera, scene, &camera);
        rad_photonmap_options o = {0};
        o.width = a.width;
        o.height = a.height;
        o.camera = &camera;
        o.samples_per_pixel = a.spp;
        o.gather_rays = a.gather;
        o.photons = a.photons;
        o.caustic_photons = a.caustic_photons;
        o.radius = isnan(a.radius) ? 0 : a.radius;
        o.nearest = a.nearest;
        o.iterations = a.progressive;
        cli_stage("photonmap", "%dx%d pixels, %d samples per pixel, %zu + %zu photons%s",
                  a.width, a.height, a.spp, a.photons, a.caustic_photons,
                  a.progressive > 1 ? ", progressive" : "");
        rs = rad_photonmap(ctx, scene, &o, &image, &stats);
    }
    if (!rs) {
        double start = cli_seconds();
        rs = rad_image_save(image, a.output, &save);
        write_seconds = cli_seconds() - start;
    }
    cli_progress_clear();
    int exit_status = 0;
    if (rs) exit_status = cli_fail(ctx, rs);
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
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
