/* bench_contact.c - the contact cut's pair search against scene size (src/mesh/contact.c, step
 * 2): triangles stacked one apart along z (all overlapping in x and y, touching none: the MGF
 * array that took 16 s at 10^5 when the pairs came from a sweep along x) and generated offices
 * (rad_scene_generate_office), cut as the mesher cuts them (contacts, near-parallel lines,
 * T-points) and as the hierarchy's roots are (no near-parallel lines, sparing). Prints a Markdown
 * table: polygons, contact lines, pieces, the bounds compared (rad_contact_cut.bound_tests) and
 * per polygon, processor seconds of the whole cut, and the growth of the bounds compared from the
 * row above against n log n. Timings only: nothing here passes or fails.
 * Usage: bench_contact [LARGEST (100000)] */
#include "core/context.h"
#include "mesh/contact.h"
#include "radiosity.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* n triangles, one surface, stacked along z one apart. */
static rad_scene *stacked(rad_context *ctx, size_t n) {
    rad_scene *scene = NULL;
    rad_material grey = {0};
    grey.reflectance[0] = grey.reflectance[1] = grey.reflectance[2] = 0.5;
    uint32_t material, surface;
    if (rad_scene_new(ctx, 1, "stacked", &scene) ||
        rad_scene_add_material(scene, &grey, &material) ||
        rad_scene_add_surface(scene, "stack", material, &surface)) {
        rad_scene_destroy(scene);
        return NULL;
    }
    for (size_t i = 0; i < n; ++i) {
        rad_vec3 t[3] = {{0, 0, (double)i}, {1, 0, (double)i}, {0, 1, (double)i}};
        if (rad_scene_add_polygon_points(scene, surface, t, 3)) {
            rad_scene_destroy(scene);
            return NULL;
        }
    }
    return scene;
}

static void row(rad_context *ctx, const char *name, const rad_scene *scene, int roots,
                double *last_tests, size_t *last_n) {
    rad_contact_options options = {.t_points = 1, .quiet = 1};
    if (roots) options = (rad_contact_options){.no_near = 1, .sparing = 1, .quiet = 1};
    rad_contact_cut *cut = NULL;
    double start = rad_processor_seconds();
    if (rad_contact_cut_create_with(ctx, scene, &options, &cut)) {
        printf("| %s | %s | failed: %s |\n", name, roots ? "roots" : "mesh", rad_context_error(ctx));
        return;
    }
    double seconds = rad_processor_seconds() - start;
    size_t n = scene->polygon_count;
    char growth[64] = "";
    if (*last_n && *last_tests > 0)
        snprintf(growth, sizeof growth, "%.1f (n log n: %.1f)", (double)cut->bound_tests / *last_tests,
                 (double)n * log((double)n) / ((double)*last_n * log((double)*last_n)));
    printf("| %s | %s | %zu | %zu | %zu | %zu | %.1f | %.3f | %s |\n", name, roots ? "roots" : "mesh",
           n, cut->contact_lines, cut->piece_count, cut->bound_tests,
           (double)cut->bound_tests / (double)n, seconds, growth);
    *last_tests = (double)cut->bound_tests;
    *last_n = n;
    rad_contact_cut_destroy(ctx, cut);
}

int main(int argc, char **argv) {
    size_t largest = argc > 1 ? strtoull(argv[1], NULL, 10) : 100000;
    rad_context *ctx = NULL;
    if (rad_context_create(NULL, &ctx)) return 1;
    printf("| scene | cut | polygons | contact lines | pieces | bounds compared | per polygon | "
           "processor s | growth |\n|---|---|---:|---:|---:|---:|---:|---:|---|\n");
    for (int roots = 0; roots < 2; ++roots) {
        double last_tests = 0;
        size_t last_n = 0;
        for (size_t n = 10000; n <= largest; n *= 10) {
            rad_scene *scene = stacked(ctx, n);
            char name[64];
            snprintf(name, sizeof name, "stacked %zu", n);
            if (scene) row(ctx, name, scene, roots, &last_tests, &last_n);
            rad_scene_destroy(scene);
        }
    }
    for (int roots = 0; roots < 2; ++roots) {
        double last_tests = 0;
        size_t last_n = 0;
        for (size_t n = 10000; n <= largest; n *= 10) {
            rad_scene *scene = NULL;
            char name[64];
            snprintf(name, sizeof name, "office %zu", n);
            if (rad_scene_generate_office(ctx, n, &scene) == RAD_OK)
                row(ctx, name, scene, roots, &last_tests, &last_n);
            rad_scene_destroy(scene);
        }
    }
    rad_context_destroy(ctx);
    return 0;
}
