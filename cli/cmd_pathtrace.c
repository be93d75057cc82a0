/* cmd_pathtrace.c - `radiosity pathtrace`: a path-traced reference image of a scene
 * (docs/pathtracing.md). Everything that can be refused cheaply (flags, the output path, the
 * camera) is refused before any path is traced, so a bad command fails at once and never leaves
 * a file. */
#include "camera_options.h"
#include "image_options.h"
#include "light_options.h"
#include "cli.h"
#include "output_path.h"
#include "pipeline.h"
#include "interrupt.h"
#include "progress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct pathtrace_args {
    int spp, max_bounces, threads, quiet, stats;
    size_t seed;
    double max_memory, clamp, time_budget;
    cli_image_args image;
    cli_camera_args camera;
    cli_light_args lights;
} pathtrace_args;

int cmd_pathtrace(int argc, char **argv) {
    static const char synopsis[] =
        "[SCENE] -o FILE [options]   (SCENE: a file or a built-in name; default cornell)";
    pathtrace_args a = {0};
    cli_image_args_init(&a.image);
    a.spp = 64;
    a.max_bounces = -1;
    cli_camera_args_init(&a.camera);
    const cli_option options[] = {
        CLI_IMAGE_OUTPUT_OPTIONS(&a.image),
        {"--spp", CLI_INT, &a.spp, "N  paths per pixel, jittered, box filter (64)"},
        {"--max-bounces", CLI_INT, &a.max_bounces,
         "N  scattering events per path, 1: direct light only (no limit: Russian roulette)"},
        {"--clamp", CLI_DOUBLE, &a.clamp,
         "V  biased: light that scattered twice or more counts at most V (R+G+B) per sample, "
         "as Cycles' Clamp Indirect (0: off)"},
        {"--seed", CLI_SIZE, &a.seed, "S  random seed; the same seed gives the same image (0)"},
        {"--time-budget", CLI_DOUBLE, &a.time_budget,
         "S  stop after S seconds (and at least one path per pixel) with the image so far"},
        CLI_IMAGE_SIZE_OPTIONS(&a.image),
        CLI_CAMERA_OPTIONS(&a.camera),
        CLI_LIGHT_OPTIONS(&a.lights),
        CLI_TWO_SIDED_OPTION(&a.lights),
        CLI_IMAGE_FILE_OPTIONS(&a.image),
        {"--threads", CLI_INT, &a.threads, "N  worker threads (all cores)"},
        {"--max-memory", CLI_MEMORY, &a.max_memory, "MIB  memory budget for the image, in MiB or as 512M, 2G (2048)"},
        {"--stats", CLI_FLAG, &a.stats, "print time, paths and rays per second"},
        {"--quiet", CLI_FLAG, &a.quiet, "no progress bar or notes on stderr"},
        {NULL, 0, NULL, NULL},
    };
    const char *positional[1];
    int positional_count;
    int status =
        cli_parse("pathtrace", synopsis, options, argc, argv, positional, 1, &positional_count);
    if (status) return status < 0 ? 0 : status;
    if ((status = cli_image_check("pathtrace", &a.image))) return status;
    if (a.spp < 1) return cli_error(EXIT_USAGE, "pathtrace: --spp must be at least 1");
    if (a.max_bounces == 0)
        return cli_error(EXIT_USAGE, "pathtrace: --max-bounces must be at least 1");
    if ((status = cli_camera_check("pathtrace", &a.camera))) return status;
    if ((status = cli_lights_check("pathtrace", &a.lights))) return status;
    if (a.max_memory < 0) return cli_error(EXIT_USAGE, "pathtrace: --max-memory must be positive");
    if (a.time_budget < 0 || isnan(a.time_budget))
        return cli_error(EXIT_USAGE, "pathtrace: --time-budget must be a positive number of seconds");
    if (!(a.clamp >= 0) || isinf(a.clamp))
        return cli_error(EXIT_USAGE, "pathtrace: --clamp must be 0 (off) or a positive number");

    cli_image_run run;
    const char *scene_name = positional_count ? positional[0] : "cornell";
    if ((status = cli_image_open("pathtrace", &a.image, a.threads, (uint64_t)a.seed, a.max_memory,
                                 a.quiet, scene_name, &run)))
        return status;
    rad_image *image = NULL;
    rad_pathtrace_stats stats = {0};
    double write_seconds = 0;
    if (!run.status) {
        rad_camera_desc camera;
        cli_camera_get(&a.camera, run.scene, &camera);
        rad_pathtrace_options trace = {0};
        trace.width = a.image.width;
        trace.height = a.image.height;
        trace.camera = &camera;
        trace.samples_per_pixel = a.spp;
        trace.max_bounces = a.max_bounces > 0 ? a.max_bounces : 0;
        trace.clamp_indirect = a.clamp;
        trace.time_budget = a.time_budget;
        cli_stage("pathtrace", "%dx%d pixels, %d paths per pixel", a.image.width, a.image.height, a.spp);
        run.status = rad_pathtrace(run.ctx, run.scene, &trace, &image, &stats);
    }
    cli_image_write(&run, &a.image, image, &write_seconds);
    int exit_status = 0;
    if (run.status) exit_status = cli_fail(run.ctx, run.status);
    else if (stats.stopped) {
        /* Stopped early (Ctrl-C, --time-budget): the image written has fewer paths; say how
         * many (the rows the last pass finished have one pass more). */
        char counts[96];
        if (stats.samples_max > stats.samples_min)
            snprintf(counts, sizeof counts, "%d to %d", stats.samples_min, stats.samples_max);
        else snprintf(counts, sizeof counts, "%d", stats.samples_min);
        fprintf(stderr, "radiosity: path tracing stopped (%s) after %.1f s: %s of %d paths per "
                        "pixel in %s\n",
                stats.stopped == RAD_PATHTRACE_CANCELLED ? "Ctrl-C" : "time budget",
                stats.seconds, counts, a.spp, a.image.output);
        if (stats.stopped == RAD_PATHTRACE_CANCELLED) exit_status = cli_interrupt_exit_status();
    }
    if (!run.status && a.stats) {
        double seconds = stats.seconds > 0 ? stats.seconds : 1e-9;
        printf("path tracing %8.3f s   %dx%d, %d spp, %llu paths, %.3g Mpaths/s, %.3g Mrays/s "
               "(%.2f rays per path)\n",
               stats.seconds, a.image.width, a.image.height, stats.samples_min,
               (unsigned long long)stats.paths,
               stats.paths / seconds * 1e-6, stats.rays / seconds * 1e-6,
               stats.paths ? (double)stats.rays / stats.paths : 0);
        printf("write        %8.3f s\n", write_seconds);
    }
    rad_image_destroy(image);
    cli_image_close(&run);
    return exit_status;
}
