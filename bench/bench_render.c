/* bench_render.c - rendering a solved Cornell box (target: 512 x 512 smooth in under 0.2 s on 2
 * cores), and time to equal error: how long `render --final-gather` takes to come as close to a
 * high-spp path-traced reference as a 1024-spp path-traced image does (target: a tenth of the
 * path tracer's time). Prints Markdown tables. Timings only: nothing here passes or fails.
 * Usage: bench_render [quick]   (quick: 64 x 64 and a 1024-spp reference, for a smoke run) */
#include "radiosity.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int fail(rad_context *ctx, const char *what) {
    fprintf(stderr, "bench_render: %s: %s\n", what, rad_context_error(ctx));
    return 1;
}

/* Best of `runs` renders; the image of the last is kept in *out when out is not NULL. */
static double render_seconds(rad_renderer *renderer, int runs, rad_image **out) {
    double best = 1e30;
    for (int i = 0; i < runs; ++i) {
        rad_image *image = NULL;
        rad_render_stats stats = {0};
        if (rad_renderer_render(renderer, &image, &stats)) return -1;
        if (stats.seconds < best) best = stats.seconds;
        if (out && i == runs - 1) *out = image;
        else rad_image_destroy(image);
    }
    return best;
}

static void smooth_timings(rad_context *ctx, const rad_scene *scene, const rad_system *system) {
    printf("## Rendering a solved Cornell box, 512 x 512 (best of 5)\n\n");
    printf("| shading | samples/pixel | final gather | seconds | Mrays/s |\n|---|---|---|---|---|\n");
    static const struct { rad_shading shading; int spp, gather; } runs[] = {
        {RAD_SHADING_SMOOTH, 1, 0}, {RAD_SHADING_SMOOTH, 4, 0}, {RAD_SHADING_FLAT, 4, 0},
        {RAD_SHADING_SMOOTH, 4, 4},
    };
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; ++i) {
        rad_render_options options = {0};
        options.width = options.height = 512;
        options.shading = runs[i].shading;
        options.samples_per_pixel = runs[i].spp;
        options.final_gather = runs[i].gather;
        rad_renderer *renderer = NULL;
        if (rad_renderer_create(scene, system, &options, &renderer)) {
            fail(ctx, "renderer");
            return;
        }
        double best = render_seconds(renderer, runs[i].gather ? 1 : 5, NULL);
        rad_image *image = NULL;
        rad_render_stats stats = {0};
        rad_renderer_render(renderer, &image, &stats);
        double rays = (double)(stats.camera_rays + stats.gather_rays + stats.shadow_rays +
                               stats.specular_rays);
        printf("| %s | %d | %d | %.3f | %.1f |\n", runs[i].shading ? "flat" : "smooth",
               runs[i].spp, runs[i].gather, best, rays / stats.seconds * 1e-6);
        rad_image_destroy(image);
        rad_renderer_destroy(renderer);
    }
    printf("\n");
}

static double relative_mse(rad_context *ctx, const rad_image *test, const rad_image *reference) {
    rad_image_comparison c;
    if (rad_image_compare(ctx, test, reference, &c)) return -1;
    return c.relative_mse;
}

static int equal_error(rad_context *ctx, const rad_scene *scene, int size, int reference_spp) {
    printf("## Time to equal error, Cornell box %d x %d\n\n", size, size);
    /* The reference and the path-traced image to match. */
    rad_pathtrace_options trace = {0};
    trace.width = trace.height = size;
    trace.samples_per_pixel = reference_spp;
    rad_image *reference = NULL, *traced = NULL;
    rad_pathtrace_stats stats = {0};
    if (rad_pathtrace(ctx, scene, &trace, &reference, &stats)) return fail(ctx, "reference");
    printf("Reference: path tracer, %d paths per pixel (%.1f s).\n\n", reference_spp, stats.seconds);
    rad_context_options other = {0};
    other.seed = 12345; /* independent of the reference's paths */
    rad_context *ctx2 = NULL;
    if (rad_context_create(&other, &ctx2)) return 1;
    trace.samples_per_pixel = 1024;
    if (rad_pathtrace(ctx2, scene, &trace, &traced, &stats)) return fail(ctx2, "path tracer");
    double pt_seconds = stats.seconds, pt_error = relative_mse(ctx, traced, reference);

    /* The radiosity solution the final gather reads. */
    rad_system *system = NULL;
    double start = now();
    if (rad_system_create(ctx, scene, NULL, NULL, &system)) return fail(ctx, "system");
    rad_solve_options solve = {0};
    solve.solver = RAD_SOLVER_GAUSS_SEIDEL;
    if (rad_solve(system, &solve, NULL)) return fail(ctx, "solve");
    double solve_seconds = now() - start;

    printf("| image | relative MSE | render s | render / path tracer | with solve s | with solve / "
           "path tracer |\n|---|---|---|---|---|---|\n");
    printf("| path tracer, 1024 paths/pixel | %.6f | %.2f | 1 | | |\n", pt_error, pt_seconds);
    static const int ladder[][2] = {{64, 0}, {16, 1}, {36, 1}, {64, 1}, {64, 2},
                                    {100, 2}, {64, 4}, {144, 4}, {64, 16}};
    int matched = 0;
    for (size_t i = 0; i < sizeof ladder / sizeof ladder[0]; ++i) {
        rad_render_options options = {0};
        options.width = options.height = size;
        options.samples_per_pixel = ladder[i][0];
        options.final_gather = ladder[i][1];
        rad_renderer *renderer = NULL;
        rad_image *image = NULL;
        if (rad_renderer_create(scene, system, &options, &renderer)) return fail(ctx, "renderer");
        double seconds = render_seconds(renderer, 1, &image);
        double total = seconds + solve_seconds;
        double error = relative_mse(ctx, image, reference);
        int good = error >= 0 && error <= pt_error;
        char label[64];
        if (ladder[i][1]) snprintf(label, sizeof label, "final gather %d, %d samples/pixel", ladder[i][1], ladder[i][0]);
        else snprintf(label, sizeof label, "smooth, %d samples/pixel", ladder[i][0]);
        printf("| %s%s | %.6f | %.2f | %.3f | %.2f | %.3f |\n", label,
               good && ladder[i][1] && !matched ? " **" : "", error, seconds, seconds / pt_seconds,
               total, total / pt_seconds);
        if (good && ladder[i][1] && !matched) matched = 1;
        rad_image_destroy(image);
        rad_renderer_destroy(renderer);
    }
    printf("\nSolve (Gauss-Seidel, default mesh): %.2f s. ** the cheapest final gather at the path "
           "tracer's error.\n\n", solve_seconds);
    rad_system_destroy(system);
    rad_image_destroy(reference);
    rad_image_destroy(traced);
    rad_context_destroy(ctx2);
    return 0;
}

int main(int argc, char **argv) {
    int quick = argc > 1 && strcmp(argv[1], "quick") == 0;
    rad_context_options options = {0};
    options.seed = 1;
    rad_context *ctx = NULL;
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    if (rad_context_create(&options, &ctx)) return 1;
    if (rad_scene_builtin(ctx, "cornell", &scene)) return fail(ctx, "scene");
    if (rad_system_create(ctx, scene, NULL, NULL, &system)) return fail(ctx, "system");
    rad_solve_options solve = {0};
    solve.solver = RAD_SOLVER_GAUSS_SEIDEL;
    if (rad_solve(system, &solve, NULL)) return fail(ctx, "solve");
    smooth_timings(ctx, scene, system);
    rad_system_destroy(system);
    int status = equal_error(ctx, scene, quick ? 64 : 128, quick ? 1024 : 4096);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return status;
}
