/* cmd_render.c - `radiosity render`: solve a scene and render the solution as an image, by
 * default with the final gather (4 rays per sample, 16 samples per pixel), and with the
 * ray-traced second pass for mirrors and glass (docs/rendering.md).
 *
 * Order of work: everything that can be refused cheaply is refused before the solve (flags, the
 * output path, the camera), so a bad command fails in milliseconds and never leaves a file. */
#include "camera_options.h"
#include "light_options.h"
#include "cli.h"
#include "output_path.h"
#include "pipeline.h"
#include "progress.h"

#include <stdlib.h>
#include <string.h>

#define MAX_SIDE 16384

typedef struct render_args {
    cli_pipeline_args pipeline;
    const char *output, *tonemap, *shading, *solution;
    int width, height, spp, final_gather, light_samples, max_depth, stats, half, no_filter;
    double exposure, time_budget;
    cli_camera_args camera;
    cli_light_args lights;
} render_args;

/* "scenes/room.obj" -> "room.png"; "cornell" -> "cornell.png". */
static char *default_output(const char *scene) {
    const char *base = strrchr(scene, '/');
    base = base ? base + 1 : scene;
    const char *dot = strrchr(base, '.');
    size_t length = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    char *path = malloc(length + 5);
    if (!path) return NULL;
    memcpy(path, base, length);
    memcpy(path + length, ".png", 5);
    return path;
}

static void print_stats(const cli_timings *t, double renderer_seconds, double write_seconds,
                        const rad_solve_report *report, const rad_solve_options *solve,
                        const rad_render_stats *stats, size_t elements, const char *solution) {
    double total = t->load + t->system + t->solve + renderer_seconds + stats->seconds + write_seconds;
    uint64_t rays = stats->camera_rays + stats->gather_rays + stats->shadow_rays + stats->specular_rays;
    printf("load           %8.3f s\n", t->load);
    printf("mesh, setup    %8.3f s   %zu elements\n", t->system, elements);
    if (solution)
        printf("solve          %8.3f s   loaded from %s\n", t->solve, solution);
    else
        printf("solve          %8.3f s   %s, %d %s, %s\n", t->solve,
               rad_solver_kind_name(solve->solver), report->iterations,
               cli_step_word(solve->solver, report->iterations),
               cli_solve_outcome(report));
    printf("ray structures %8.3f s\n", renderer_seconds);
    printf("render         %8.3f s   %.3g Mrays/s (camera %llu, gather %llu, shadow %llu, "
           "specular %llu)\n", stats->seconds, stats->seconds > 0 ? rays / stats->seconds * 1e-6 : 0,
           (unsigned long long)stats->camera_rays, (unsigned long long)stats->gather_rays,
           (unsigned long long)stats->shadow_rays, (unsigned long long)stats->specular_rays);
    printf("write          %8.3f s\n", write_seconds);
    printf("total          %8.3f s\n", total);
}

int cmd_render(int argc, char **argv) {
    static const char synopsis[] =
        "[SCENE] [-o FILE] [options]   (SCENE: a file or a built-in name; default cornell)";
    render_args a = {0};
    /* solve's default, so that render and solve agree */
    a.pipeline.ff = "default";
    a.tonemap = "clamp";
    a.shading = "smooth";
    a.width = a.height = 512;
    /* The production path: 16 samples per pixel for clean edges (the light is 150 times brighter
     * than the ceiling around it), 4 gather rays each, stratified over the pixel (64 per pixel).
     * Against a path-traced reference this halves the error of 4 samples x 16 rays, in less
     * time (docs/rendering.md). --final-gather 0 shows the interpolated solution alone. */
    a.spp = 16;
    a.final_gather = 4;
    cli_camera_args_init(&a.camera);
    /* render's own options; the shared solver, form-factor and meshing ones follow them. */
    const cli_option own[] = {
        {"-o", CLI_STRING, &a.output, "FILE  output image: .png, .hdr, .pfm, .exr (SCENE.png)"},
        {"--output", CLI_STRING, &a.output, "FILE  the same as -o"},
        {"--width", CLI_INT, &a.width, "W  image width in pixels (512)"},
        {"--height", CLI_INT, &a.height, "H  image height in pixels (512)"},
        {"--spp", CLI_INT, &a.spp, "N  jittered samples per pixel, box filter (16)"},
        CLI_CAMERA_OPTIONS(&a.camera),
        CLI_LIGHT_OPTIONS(&a.lights),
        CLI_TWO_SIDED_OPTION(&a.lights),
        CLI_SPECULAR_OPTIONS(&a.lights),
        {"--exposure", CLI_DOUBLE, &a.exposure, "EV  exposure in stops, PNG only (0)"},
        {"--tonemap", CLI_STRING, &a.tonemap, "CURVE  none|clamp|reinhard|aces, PNG only (clamp)"},
        {"--half", CLI_FLAG, &a.half, "EXR only: 16-bit half floats (default 32-bit float)"},
        {"--shading", CLI_STRING, &a.shading, "MODE  smooth|flat (smooth)"},
        {"--final-gather", CLI_INT, &a.final_gather,
         "N  direct light sampled + N gather rays per sample into the solution (4; 0: the "
         "interpolated solution alone)"},
        {"--light-samples", CLI_INT, &a.light_samples,
         "N  final gather: emitter samples per sample (half of --final-gather, a quarter with "
         "--no-gather-filter; twice that with more than 256 lamps)"},
        {"--no-gather-filter", CLI_FLAG, &a.no_filter,
         "final gather: each pixel keeps its own gathered light (default: filtered over its "
         "neighbours on the same surface)"},
        {"--max-depth", CLI_INT, &a.max_depth, "N  mirror and glass bounces per path (16)"},
        {"--stats", CLI_FLAG, &a.stats, "print the time of each step and ray counts"},
        {"--time-budget", CLI_DOUBLE, &a.time_budget,
         "S  stop the solve after S seconds and render the solution so far"},
        {"--solution", CLI_STRING, &a.solution,
         "FILE  render a solution saved by solve --save (same scene and meshing/ff options) "
         "instead of solving"},
    };
    cli_option options[CLI_PIPELINE_TABLE_SIZE(own)];
    cli_pipeline_table(options, own, sizeof own / sizeof own[0], 0, &a.pipeline,
                       RAD_SOLVER_SHOOTING);
    const char *positional[1];
    int positional_count;
    int status = cli_parse("render", synopsis, options, argc, argv, positional, 1, &positional_count);
    if (status) return status < 0 ? 0 : status;

    rad_solve_options solve;
    rad_mesh_options mesh;
    rad_ff_options ff;
    a.pipeline.final_gather = a.final_gather; /* the hierarchy's link error on small scenes */
    status = cli_pipeline_check("render", &a.pipeline, &solve, &mesh, &ff);
    if (status) return status;
    /* A saved solution is drawn on the mesh it was saved for: no default by scene size. */
    if (a.solution) {
        a.pipeline.solver_default = 0;
        cli_pipeline_saved_mesh(a.solution, &mesh);
    }
    if (a.width < 1 || a.width > MAX_SIDE || a.height < 1 || a.height > MAX_SIDE)
        return cli_error(EXIT_USAGE, "render: image size %dx%d: each side must be 1 to %d pixels",
                         a.width, a.height, MAX_SIDE);
    if (a.spp < 1) return cli_error(EXIT_USAGE, "render: --spp must be at least 1");
    if (a.time_budget < 0 || a.time_budget != a.time_budget)
        return cli_error(EXIT_USAGE, "render: --time-budget must be a positive number of seconds");
    solve.time_budget = a.time_budget;
    /* With the final gather the solution is seen one bounce away: shooting (and the importance
     * solver, shooting in another order, as --importance makes it) to 1e-3 unshot power
     * draws the Cornell box within 0.11% of 1e-6 in 4x4 blocks (noise 1.5%) in 60% of the
     * solve's time (docs/rendering.md, "Choosing the defaults"). Not overshot: 20 ms less
     * here, but the importance solver never converges with it (docs/solvers.md, "Every row at
     * once"). */
    if (a.pipeline.tolerance == 0 && a.final_gather > 0 && cli_solver_shoots(solve.solver))
        solve.tolerance = 1e-3;
    if ((status = cli_camera_check("render", &a.camera))) return status;
    if ((status = cli_lights_check("render", &a.lights))) return status;
    int shading = rad_shading_parse(a.shading);
    if (shading < 0)
        return cli_error(EXIT_USAGE, "render: unknown shading '%s' (smooth, flat)", a.shading);
    const char *scene_name = positional_count ? positional[0] : "cornell";
    char *fallback_output = a.output ? NULL : default_output(scene_name);
    const char *output = a.output ? a.output : fallback_output;
    if (!output) return cli_error(1, "render: out of memory");
    const char *inputs[2] = {scene_name, a.solution};
    status = cli_check_output_path("render", output, inputs, a.solution ? 2 : 1);
    if (status) {
        free(fallback_output);
        return status;
    }

    cli_pipeline_args *p = &a.pipeline;
    rad_context *ctx = cli_context_with_progress(p->threads, p->seed, p->max_memory, p->quiet);
    rad_image_save_options save = {a.exposure, a.tonemap, a.half};
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_renderer *renderer = NULL;
    rad_image *image = NULL;
    cli_timings timings = {0, 0, 0};
    rad_solve_report report = {0};
    rad_render_stats stats = {0};
    double renderer_seconds = 0, write_seconds = 0;

    rad_status rs = rad_image_check_path(ctx, output, &save);
    if (rs) {
        /* A bad extension or tone curve is a usage error; an unwritable place is not. */
        int usage = rs == RAD_ERROR_INVALID_ARGUMENT;
        cli_fail(ctx, rs);
        rad_context_destroy(ctx);
        free(fallback_output);
        return usage ? EXIT_USAGE : 1;
    }
    rs = cli_pipeline_build(ctx, scene_name, &a.pipeline, &solve, &mesh, &ff, &scene, &system,
                            &timings);
    if (!rs && (status = cli_check_outputs_against_scene("render", scene, &output, 1))) {
        rad_system_destroy(system); /* the output is the scene's .mtl, .bin, a texture, ... */
        rad_scene_destroy(scene);
        rad_context_destroy(ctx);
        free(fallback_output);
        return status;
    }
    rad_camera_desc camera;
    if (!rs) {
        cli_camera_get(&a.camera, scene, &camera);
        rad_render_options render = {0};
        render.width = a.width;
        render.height = a.height;
        render.camera = &camera;
        render.samples_per_pixel = a.spp;
        render.shading = (rad_shading)shading;
        render.final_gather = a.final_gather;
        render.light_samples = a.light_samples;
        render.max_depth = a.max_depth;
        render.ambient = p->ambient;
        render.no_gather_filter = a.no_filter;
        double start = cli_seconds();
        rs = rad_renderer_create(scene, system, &render, &renderer);
        renderer_seconds = cli_seconds() - start;
    }
    /* The importance solver refines what this camera sees. */
    solve.camera = &camera;
    solve.view_width = a.width;
    solve.view_height = a.height;
    if (!rs && a.solution) {
        /* A saved solution replaces the solve; it is refused for another scene or mesh. */
        double start = cli_seconds();
        rs = rad_system_load_solution(system, a.solution, NULL);
        timings.solve = cli_seconds() - start;
        if (!rs) cli_stage("solve", "loaded from %s", a.solution);
    } else if (!rs) {
        rs = cli_pipeline_solve(system, &solve, &report, &timings);
    }
    if (!rs)
        cli_stage("render", "%dx%d pixels, %d samples per pixel, final gather %d, %s shading",
                  a.width, a.height, a.spp, a.final_gather, a.shading);
    if (!rs) rs = rad_renderer_render(renderer, &image, &stats);
    if (!rs) {
        double start = cli_seconds();
        rs = rad_image_save(image, output, &save);
        write_seconds = cli_seconds() - start;
    }
    cli_progress_clear();
    int exit_status = 0;
    if (rs) exit_status = cli_fail(ctx, rs);
    else if (a.stats)
        print_stats(&timings, renderer_seconds, write_seconds, &report, &solve, &stats,
                    rad_system_element_count(system), a.solution);
    rad_image_destroy(image);
    rad_renderer_destroy(renderer);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    free(fallback_output);
    return exit_status;
}
