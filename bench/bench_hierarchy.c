/* bench_hierarchy.c - hierarchical radiosity against shooting on the Cornell box: solve seconds
 * and the error of the interpolated image (final gather off, so the error is the solution's)
 * against a path-traced reference, for shooting at 10,000 elements and the hierarchy at several
 * link errors. Prints a Markdown table. Timings only: nothing here passes or fails.
 * Usage: bench_hierarchy [REFERENCE_SPP (1024)] */
#include "radiosity.h"

#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#define SIZE 64

typedef struct run {
    const char *label;
    rad_solver_kind solver;
    size_t elements;
    double tolerance, link_error;
} run;

int main(int argc, char **argv) {
    int spp = argc > 1 ? atoi(argv[1]) : 1024;
    rad_context_options co = {0};
    rad_context *ctx = NULL;
    if (rad_context_create(&co, &ctx)) return 1;
    rad_scene *scene = NULL;
    if (rad_builtin_geometry(ctx, "cornell", &scene)) return 1;
    rad_pathtrace_options trace = {0};
    trace.width = trace.height = SIZE;
    trace.samples_per_pixel = spp;
    rad_image *reference = NULL;
    double t0 = now();
    if (rad_pathtrace(ctx, scene, &trace, &reference, NULL)) {
        fprintf(stderr, "%s\n", rad_context_error(ctx));
        return 1;
    }
    printf("reference: path tracer, %dx%d, %d paths per pixel, %.1f s\n\n", SIZE, SIZE, spp,
           now() - t0);
    const run runs[] = {
        {"shooting, 10k elements, 1% unshot", RAD_SOLVER_SHOOTING, 10000, 0.01, 0},
        {"shooting, 10k elements, 0.1% unshot", RAD_SOLVER_SHOOTING, 10000, 0.001, 0},
        {"hierarchical, link error 1e-3", RAD_SOLVER_HIERARCHICAL, 10000, 0, 1e-3},
        {"hierarchical, link error 3e-4", RAD_SOLVER_HIERARCHICAL, 10000, 0, 3e-4},
        {"hierarchical, link error 1e-4", RAD_SOLVER_HIERARCHICAL, 10000, 0, 1e-4},
        {"hierarchical, link error 3e-5", RAD_SOLVER_HIERARCHICAL, 10000, 0, 3e-5},
    };
    printf("| solver | system s | solve s | steps | relative MSE | mean ratio |\n");
    printf("|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; ++i) {
        rad_mesh_options mesh = {0};
        mesh.elements = runs[i].elements;
        rad_system *system = NULL;
        double start = now();
        if (rad_system_create(ctx, scene, &mesh, NULL, &system)) return 1;
        double built = now();
        rad_solve_options solve = {0};
        solve.solver = runs[i].solver;
        solve.tolerance = runs[i].tolerance;
        solve.link_error = runs[i].link_error;
        rad_solve_report report;
        if (rad_solve(system, &solve, &report)) {
            fprintf(stderr, "%s\n", rad_context_error(ctx));
            return 1;
        }
        double solved = now();
        rad_render_options options = {0};
        options.width = options.height = SIZE;
        options.samples_per_pixel = 16;
        rad_image *image = NULL;
        rad_image_comparison c = {0};
        if (rad_render(scene, system, &options, &image) || rad_image_compare(ctx, image, reference, &c))
            return 1;
        printf("| %s | %.2f | %.2f | %d | %.5f | %.4f |\n", runs[i].label, built - start,
               solved - built, report.iterations, c.relative_mse, c.mean_ratio);
        fflush(stdout);
        rad_image_destroy(image);
        rad_system_destroy(system);
    }
    rad_image_destroy(reference);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return 0;
}
