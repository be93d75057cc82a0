/* cmd_pathtrace.c - `radiosity pathtrace`: a path-traced reference image of a scene
 * (docs/pathtracing.md). Everything that can be refused cheaply (flags, the output path, the
 * camera) is refused before any path is traced, so a bad command fails at once and never leaves
 * a file. */
#include "camera_options.h"
#include "light_options.h"
#include "cli.h"
#include "output_path.h"
#include "pipeline.h"
#include "progress.h"

#include <stdlib.h>

#define MAX_SIDE 16384

typedef struct pathtrace_args {
    const char *output, *tonemap;
    int width, height, spp, max_bounces, threads, quiet, stats, half;
    size_t seed;
    double exposure, max_memory;
    cli_camera_args camera;
    cli_light_args lights;
} pathtrace_args;

int cmd_pathtrace(int argc, char **argv) {
    static const char synopsis[] =
        "[SCENE] -o FILE [options]   (SCENE: a file or a built-in name; default cornell)";
    pathtrace_args a = {0};
    a.tonemap = "clamp";
    a.width = a.height = 512;
    a.spp = 64;
    a.max_bounces = -1;
    cli_camera_args_init(&a.camera);
    const cli_option options[] = {
        {"-o", CLI_STRING, &a.output, "FILE  output image: .png, .hdr, .pfm, .exr (required)"},
        {"--output", CLI_STRING, &a.output, "FILE  the same as -o"},
        {"--spp", CLI_INT, &a.spp, "N  paths per pixel, jittered, box filter (64)"},
        {"--max-bounces", CLI_INT, &a.max_bounces,
         "N  scattering events per path, 1: direct light only (no limit: Russian roulette)"},
        {"--seed", CLI_SIZE, &a.seed, "S  random seed; the same seed gives the same image (0)"},
        {"--width", CLI_INT, &a.width, "W  image width in pixels (512)"},
        {"--height", CLI_INT, &a.height, "H  image height in pixels (512)"},
        CLI_CAMERA_OPTIONS(&a.camera),
        CLI_LIGHT_OPTIONS(&a.lights),
        CLI_TWO_SIDED_OPTION(&a.lights),
        {"--exposure", CLI_DOUBLE, &a.exposure, "EV  exposure in stops, PNG only (0)"},
        {"--tonemap", CLI_STRING, &a.tonemap, "CURVE  none|clamp|reinhard|aces, PNG only (clamp)"},
        {"--half", CLI_FLAG, &a.half, "EXR only: 16-bit half floats (default 32-bit float)"},
        {"--threads", CLI_INT, &a.threads, "N  worker threads (all cores)"},
        {"--max-memory", CLI_DOUBLE, &a.max_memory, "MIB  memory budget for the image (2048)"},
        {"--stats", CLI_FLAG, &a.stats, "print time, paths and rays per second"},
        {"--quiet", CLI_FLAG, &a.quiet, "no progress bar or notes on stderr"},
        {NULL, 0, NULL, NULL},
    };
    const char *positional[1];
    int positional_count;
    int status =
        cli_parse("pathtrace", synopsis, options, argc, argv, positional, 1, &positional_count);
    if (status) return status < 0 ? 0 : status;
    if (!a.output)
        return cli_error(EXIT_USAGE, "pathtrace: an output file is required (-o FILE)");
    if (a.width < 1 || a.width > MAX_SIDE || a.height < 1 || a.height > MAX_SIDE)
        return cli_error(EXIT_USAGE, "pathtrace: image size %dx%d: each side must be 1 to %d pixels",
                         a.width, a.height, MAX_SIDE);
    if (a.spp < 1) return cli_error(EXIT_USAGE, "pathtrace: --spp must be at least 1");
    if (a.max_bounces == 0)
        return cli_error(EXIT_USAGE, "pathtrace: --max-bounces must be at least 1");
    if ((status = cli_camera_check("pathtrace", &a.camera))) return status;
    if ((status = cli_lights_check("pathtrace", &a.lights))) return status;
    if (a.max_memory < 0) return cli_error(EXIT_USAGE, "pathtrace: --max-memory must be positive");

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
    rad_pathtrace_stats stats = {0};
    double write_seconds = 0;
    rs = cli_load_scene(ctx, scene_name, &scene);
    if (!rs && (status = cli_check_outputs_against_scene("pathtrace", scene, &a.output, 1))) {
        rad_scene_destroy(scene); /* the output is the scene's .mtl, .bin, a texture, ... */
        rad_context_destroy(ctx);
        return status;
    }
    if (!rs) {
        rad_camera_desc camera;
        cli_camera_get(&a.camera, scene, &camera);
        rad_pathtrace_options trace = {0};
        trace.width = a.width;
        trace.height = a.height;
        trace.camera = &camera;
        trace.samples_per_pixel = a.spp;
        trace.max_bounces = a.max_bounces > 0 ? a.max_bounces : 0;
        cli_stage("pathtrace", "%dx%d pixels, %d paths per pixel", a.width, a.height, a.spp);
        rs = rad_pathtrace(ctx, scene, &trace, &image, &stats);
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
        double seconds = stats.seconds > 0 ? stats.seconds : 1e-9;
        printf("path tracing %8.3f s   %dx%d, %d spp, %llu paths, %.3g Mpaths/s, %.3g Mrays/s "
               "(%.2f rays per path)\n",
               stats.seconds, a.width, a.height, a.spp, (unsigned long long)stats.paths,
               stats.paths / seconds * 1e-6, stats.rays / seconds * 1e-6,
               stats.paths ? (double)stats.rays / stats.paths : 0);
        printf("write        %8.3f s\n", write_seconds);
    }
    rad_image_destroy(image);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
