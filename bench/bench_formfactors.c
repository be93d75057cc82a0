/* bench_formfactors.c - how fast the form factors are, and at what accuracy.
 *
 *   1. Rays: raw Embree occlusion throughput on the Cornell box (single rays, packets, streams)
 *      against the rays the ray-cast method casts per second inside its rows.
 *   2. Threads: rows per second with 1 and 2 threads, every method.
 *   3. Accuracy against speed: each method at several settings, row error against a reference,
 *      and form factors per second at equal accuracy (this chose the default method).
 *   4. Shooting the Cornell box at 10,000 elements to 1% unshot power.
 *
 * Usage: bench_formfactors [--quick] [--section N]. Timings on a busy machine are noisy; the
 * numbers in bench/README.md come from a quiet one. */
#include "core/context.h"
#include "formfactor/geometric.h"
#include "scene/scene.h"
#include "system/system.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int quick;

static rad_context *context_with(int threads, uint64_t seed) {
    rad_context_options options = {0};
    options.threads = threads;
    options.seed = seed;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) {
        fprintf(stderr, "bench: cannot create a context\n");
        exit(1);
    }
    return ctx;
}

typedef struct setup {
    rad_context *ctx;
    rad_scene *scene;
    rad_mesh *mesh;
} setup;

static setup cornell(int threads, size_t elements) {
    setup s = {context_with(threads, 1), NULL, NULL};
    rad_mesh_options mesh = {0};
    mesh.elements = elements;
    if (rad_scene_builtin(s.ctx, "cornell", &s.scene) ||
        rad_mesh_create(s.ctx, s.scene, &mesh, &s.mesh)) {
        fprintf(stderr, "bench: %s\n", rad_context_error(s.ctx));
        exit(1);
    }
    return s;
}

static void setup_free(setup *s) {
    rad_mesh_destroy(s->mesh);
    rad_scene_destroy(s->scene);
    rad_context_destroy(s->ctx);
}

/* A provider straight from the method table: no row cache; `cull` 0 turns shaft culling off. */
static rad_ff_provider *provider(const setup *s, rad_ff_method method, int samples,
                                 int resolution, int cull) {
    rad_ff_options options = {method, samples, resolution, NULL};
    rad_ff_context context;
    rad_ff_provider *p = NULL;
    if (rad_ff_context_build(s->ctx, s->scene, s->mesh, &options, cull, &context) ||
        rad_ff_method_find(method)->create(&context, &p)) {
        fprintf(stderr, "bench: %s\n", rad_context_error(s->ctx));
        exit(1);
    }
    return p;
}

/* Patches spread over the scene, the same for every measurement. */
static size_t sample_patch(const rad_mesh *mesh, int i, int count) {
    return (size_t)(((double)i + 0.5) / count * (double)mesh->patch_count);
}

/* Seconds for `count` rows (patches spread over the scene). */
static double time_rows(rad_ff_provider *p, const rad_mesh *mesh, int count, float *row) {
    double start = rad_seconds();
    for (int i = 0; i < count; ++i) p->row(p, sample_patch(mesh, i, count), row);
    return rad_seconds() - start;
}

/* ------------------------------------------------------------------------------------------- */
/* 1. Rays                                                                                      */

static void bench_rays(void) {
    const int samples = 16, rows = quick ? 4 : 12;
    setup s = cornell(1, 10000);
    const rad_mesh *mesh = s.mesh;
    printf("\n## 1. Occlusion rays, Cornell box, %zu elements, 1 thread\n\n", mesh->element_count);

    /* The segments the ray-cast method casts for `rows` rows, without shaft culling: from each
     * receiver's centroid to `samples` points on the patch (the same points it uses). */
    rad_ff_provider *raycast = provider(&s, RAD_FF_RAYCAST, samples, 0, 0);
    const rad_ff_context *c = &((rad_ff_common *)raycast)->c;
    size_t capacity = (size_t)rows * mesh->element_count * 16 * (size_t)samples, count = 0;
    rad_vec3 *from = malloc(capacity * sizeof *from), *to = malloc(capacity * sizeof *to);
    uint32_t *group = malloc(((size_t)rows * mesh->element_count + 1) * sizeof *group);
    size_t groups = 0;
    rad_ff_element_map *maps = malloc((size_t)c->max_members * sizeof *maps);
    for (int i = 0; i < rows; ++i) {
        size_t patch = sample_patch(mesh, i, rows);
        rad_ff_source source;
        rad_ff_source_begin(&source, c, patch, samples, maps);
        const rad_ff_patch *p = source.patch;
        for (size_t e = 0; e < mesh->element_count; ++e) {
            if (mesh->element_patch[e] == patch || rad_ff_facing_away(mesh, p, e)) continue;
            rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
            rad_rng rng = rad_rng_make(rad_ff_row_seed(c, patch), e);
            rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
            group[groups++] = (uint32_t)count;
            rad_ff_cursor cursor = rad_ff_cursor_make(&source, &jitter, samples);
            for (int k = 0; k < samples && count < capacity; ++k) {
                double w;
                rad_vec3 x = rad_ff_cursor_next(&cursor, &w), d = v3_sub(x, y);
                if (v3_dot(ny, d) <= 0 || v3_dot(p->normal, d) >= 0) continue;
                from[count] = v3_add(y, v3_scale(ny, c->rays->epsilon));
                to[count++] = v3_add(x, v3_scale(p->normal, c->rays->epsilon));
            }
        }
    }
    group[groups] = (uint32_t)count;
    uint8_t *occluded = malloc(count + 1);
    printf("%zu segments from %d rows (receiver to points on the shooting patch)\n\n", count, rows);
    printf("| Embree call | Mrays/s |\n|---|---|\n");
    static const int modes[] = {1, 4, 8, 16, 0};
    static const char *const names[] = {"rtcOccluded1", "rtcOccluded4", "rtcOccluded8",
                                        "rtcOccluded16", "rtcOccluded1M (stream)"};
    double raw = 0;
    for (int m = 0; m < 5; ++m) {
        rad_rays_set_batch_mode(modes[m]);
        double best = INFINITY;
        for (int repeat = 0; repeat < 3; ++repeat) {
            double start = rad_seconds();
            for (size_t g = 0; g < groups; ++g)
                rad_rays_occluded_batch(c->rays, from + group[g], to + group[g], group[g + 1] - group[g],
                                        occluded + group[g]);
            best = fmin(best, rad_seconds() - start);
        }
        printf("| %s | %.2f |\n", names[m], count / best * 1e-6);
        if (count / best > raw) raw = count / best;
    }
    /* Best case: the whole array in full packets of 16 (consecutive receivers mixed). */
    rad_rays_set_batch_mode(16);
    {
        double best = INFINITY;
        for (int repeat = 0; repeat < 3; ++repeat) {
            double start = rad_seconds();
            rad_rays_occluded_batch(c->rays, from, to, count, occluded);
            best = fmin(best, rad_seconds() - start);
        }
        printf("| rtcOccluded16, full packets | %.2f |\n", count / best * 1e-6);
        if (count / best > raw) raw = count / best;
    }
    size_t blocked = 0;
    for (size_t i = 0; i < count; ++i) blocked += occluded[i];

    /* The same rows through the ray-cast method (culling off: it casts exactly these rays). */
    float *row = malloc(mesh->element_count * sizeof *row);
    double best = INFINITY, best_raw = INFINITY;
    uint64_t rays = 0;
    /* Interleaved with the raw full-packet run, best of 5 each, so both see the same machine. */
    for (int repeat = 0; repeat < 5; ++repeat) {
        rad_ff_stats before = rad_ff_provider_stats(raycast);
        double seconds = time_rows(raycast, mesh, rows, row);
        rays = rad_ff_provider_stats(raycast).rays - before.rays;
        best = fmin(best, seconds);
        double start = rad_seconds();
        rad_rays_occluded_batch(c->rays, from, to, count, occluded);
        best_raw = fmin(best_raw, rad_seconds() - start);
    }
    if (count / best_raw > raw) raw = count / best_raw;
    double ff = (double)rays / best;
    printf("\nray-cast form factors (%d samples, culling off): %.2f Mrays/s = %.0f%% of the best raw "
           "rate (%.2f Mrays/s); %.1f%% of the rays are blocked\n",
           samples, ff * 1e-6, 100 * ff / raw, raw * 1e-6, 100.0 * blocked / count);

    /* With shaft culling (the default): rays saved. */
    rad_ff_provider *culled = provider(&s, RAD_FF_RAYCAST, samples, 0, 1);
    double culled_seconds = time_rows(culled, mesh, rows, row);
    rad_ff_stats st = rad_ff_provider_stats(culled);
    printf("with shaft culling: %.0f%% of the rays cast, rows %.1fx faster\n",
           100.0 * (double)st.rays / (double)rays, best / culled_seconds);
    rad_ff_provider_destroy(culled);
    rad_ff_provider_destroy(raycast);
    free(row);
    free(from);
    free(to);
    free(group);
    free(maps);
    free(occluded);
    setup_free(&s);
}

/* ------------------------------------------------------------------------------------------- */
/* 2. Threads                                                                                   */

static int by_value(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static const rad_ff_method all_methods[] = {RAD_FF_ANALYTIC, RAD_FF_HEMICUBE, RAD_FF_RAYCAST,
                                            RAD_FF_MONTECARLO};

static void bench_threads(void) {
    /* Short runs, alternating one and two threads, best of each: the machine's noise (other
     * jobs, frequency changes) then hits both alike, and the ratio is taken within one run. */
    enum { most_repeats = 15 };
    const int rows = quick ? 8 : 40, repeats = quick ? 3 : most_repeats;
    setup one = cornell(1, 10000), two = cornell(2, 10000);
    printf("\n## 2. Threads: Cornell box, %zu elements, %d rows, default settings\n\n",
           one.mesh->element_count, rows);
    printf("%d runs of %d rows each, alternating one and two threads; times are the best run, "
           "the speed-up is the median over the pairs of neighbouring runs. Processor ms/row "
           "adds up both threads: equal to the one-thread time when the split costs nothing.\n\n",
           repeats, rows);
    printf("| method | ms/row, 1 thread | ms/row, 2 threads | speed-up (median) | processor ms/row, "
           "1 / 2 threads |\n|---|---|---|---|---|\n");
    float *row = malloc(one.mesh->element_count * sizeof *row);
    for (int m = 0; m < 4; ++m) {
        double seconds[2] = {INFINITY, INFINITY}, processor[2] = {INFINITY, INFINITY};
        rad_ff_provider *p[2] = {provider(&one, all_methods[m], 0, 0, 1),
                                 provider(&two, all_methods[m], 0, 0, 1)};
        for (int t = 0; t < 2; ++t) time_rows(p[t], one.mesh, 4, row); /* warm up */
        double ratio[most_repeats];
        for (int repeat = 0; repeat < repeats; ++repeat) {
            double pair[2];
            for (int t = 0; t < 2; ++t) {
                /* Let the idle OpenMP worker of the last two-thread run stop spinning first: it
                 * would count as processor time of the one-thread run, and compete with it. */
                nanosleep(&(struct timespec){0, 20000000}, NULL);
                double cpu = rad_processor_seconds();
                pair[t] = time_rows(p[t], one.mesh, rows, row);
                seconds[t] = fmin(seconds[t], pair[t]);
                processor[t] = fmin(processor[t], rad_processor_seconds() - cpu);
            }
            ratio[repeat] = pair[0] / pair[1];
        }
        qsort(ratio, (size_t)repeats, sizeof *ratio, by_value);
        for (int t = 0; t < 2; ++t) rad_ff_provider_destroy(p[t]);
        printf("| %s | %.2f | %.2f | %.2fx | %.2f / %.2f |\n",
               rad_ff_method_find(all_methods[m])->info.name, 1e3 * seconds[0] / rows,
               1e3 * seconds[1] / rows, ratio[repeats / 2], 1e3 * processor[0] / rows,
               1e3 * processor[1] / rows);
    }
    free(row);
    setup_free(&one);
    setup_free(&two);
}

/* ------------------------------------------------------------------------------------------- */
/* 3. Accuracy against speed                                                                    */

typedef struct trial {
    rad_ff_method method;
    int setting; /* samples, or hemicube resolution */
    double error, ms_per_row;
} trial;

/* The reference row: F_pe = 1 / A_p int_e F(dA_y -> p) V(y) dy, with y on a 4 x 4 grid of
 * midpoints of e, F(dA_y -> p) the contour integral and V(y) the kernel-weighted fraction of
 * 256 stratified rays that reach the patch (1 where shaft culling proves it). */
static void reference_row(const rad_ff_context *c, size_t patch, rad_ff_element_map *maps,
                          float *row) {
    const rad_mesh *mesh = c->mesh;
    const rad_ff_patch *p = &c->patches[patch];
    const int grid = 4, rays_per_point = 256;
    rad_ff_source source;
    rad_ff_source_begin(&source, c, patch, rays_per_point, maps);
    rad_ff_shaft_view *view = rad_ff_shaft_view_create(c->shaft);
    rad_ff_shaft_begin(c->shaft, view, p);
#pragma omp parallel for schedule(dynamic, 16)
    for (long e = 0; e < (long)mesh->element_count; ++e) {
        row[e] = 0;
        if (mesh->element_patch[e] == patch || rad_ff_facing_away(mesh, p, (size_t)e)) continue;
        int clear = rad_ff_shaft_clear(c->shaft, view, (size_t)e);
        rad_ff_element_map receiver = rad_ff_element_map_make(mesh, (size_t)e);
        rad_vec3 ny = mesh->element_normal[e];
        double sum = 0;
        for (int k = 0; k < grid * grid; ++k) {
            rad_vec3 y = rad_ff_element_map_point(&receiver, (k % grid + 0.5) / grid,
                                                  (k / grid + 0.5) / grid);
            double f = rad_ff_point_polygon(y, ny, p->corners, p->corner_count);
            if (f > 0 && !clear) {
                rad_rng rng = rad_rng_make(977, (uint64_t)e * 64 + (uint64_t)k);
                rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
                rad_vec3 from[16], to[16];
                double kernel[16], seen = 0, all = 0;
                uint8_t blocked[16];
                rad_ff_cursor cursor = rad_ff_cursor_make(&source, &jitter, rays_per_point);
                for (int start = 0; start < rays_per_point; start += 16) {
                    for (int s = 0; s < 16; ++s) {
                        double w;
                        rad_vec3 x = rad_ff_cursor_next(&cursor, &w);
                        rad_vec3 d = v3_sub(x, y);
                        double ce = v3_dot(ny, d), cp = -v3_dot(p->normal, d), r2 = v3_dot(d, d);
                        kernel[s] = ce > 0 && cp > 0 ? w * ce * cp / (r2 * r2) : 0;
                        from[s] = v3_add(y, v3_scale(ny, c->rays->epsilon));
                        to[s] = v3_add(x, v3_scale(p->normal, c->rays->epsilon));
                    }
                    rad_rays_occluded_batch(c->rays, from, to, 16, blocked);
                    for (int s = 0; s < 16; ++s) {
                        all += kernel[s];
                        if (!blocked[s]) seen += kernel[s];
                    }
                }
                f *= all > 0 ? seen / all : 0;
            }
            sum += f;
        }
        row[e] = (float)(mesh->element_area[e] / p->area * sum / (grid * grid));
    }
    rad_ff_shaft_view_destroy(view);
}

static void bench_accuracy(void) {
    const int rows = quick ? 6 : 16;
    setup s = cornell(1, 2500);
    const rad_mesh *mesh = s.mesh;
    size_t n = mesh->element_count;
    printf("\n## 3. Accuracy against speed: Cornell box, %zu elements, %d rows, 1 thread, "
           "processor time\n\n", n, rows);
    float *reference = malloc((size_t)rows * n * sizeof *reference), *row = malloc(n * sizeof *row);
    {
        rad_ff_provider *ref = provider(&s, RAD_FF_ANALYTIC, 0, 0, 1);
        const rad_ff_context *c = &((rad_ff_common *)ref)->c;
        rad_ff_element_map *maps = malloc((size_t)c->max_members * sizeof *maps);
        for (int i = 0; i < rows; ++i)
            reference_row(c, sample_patch(mesh, i, rows), maps, reference + (size_t)i * n);
        free(maps);
        rad_ff_provider_destroy(ref);
    }
    printf("Reference: F_pe = 1/A_p int_e F(dA_y -> p) V(y) dy on a 4 x 4 grid of points y per "
           "element, F(dA_y -> p) in closed form, V(y) from 256 rays. Row error: sum over the "
           "row of |F - F_ref| / sum of F_ref (the share of a shot's energy sent to the wrong "
           "elements), mean over the rows.\n\n");
    printf("| method | setting | row error | ms/row | form factors/s |\n|---|---|---|---|---|\n");
    trial trials[64];
    int count = 0;
    static const int sample_steps[] = {1, 2, 4, 8, 16, 32, 64, 128};
    static const int resolution_steps[] = {32, 64, 128, 256, 512, 1024};
    for (int m = 0; m < 4; ++m) {
        rad_ff_method method = all_methods[m];
        int hemicube = method == RAD_FF_HEMICUBE;
        int steps = hemicube ? 6 : 8;
        for (int k = 0; k < steps; ++k) {
            int setting = hemicube ? resolution_steps[k] : sample_steps[k];
            if (quick && setting > (hemicube ? 512 : 64)) continue;
            if (method == RAD_FF_ANALYTIC && setting > 32) continue;
            rad_ff_provider *p = provider(&s, method, hemicube ? 0 : setting, hemicube ? setting : 0, 1);
            double error = 0, seconds = 0;
            for (int i = 0; i < rows; ++i) {
                double start = rad_processor_seconds();
                p->row(p, sample_patch(mesh, i, rows), row);
                seconds += rad_processor_seconds() - start;
                double wrong = 0, total = 0;
                for (size_t e = 0; e < n; ++e) {
                    wrong += fabs((double)row[e] - reference[(size_t)i * n + e]);
                    total += reference[(size_t)i * n + e];
                }
                error += wrong / total / rows;
            }
            rad_ff_provider_destroy(p);
            trial t = {method, setting, error, 1e3 * seconds / rows};
            trials[count++] = t;
            printf("| %s | %s %d | %.2f%% | %.2f | %.2fM |\n", rad_ff_method_find(method)->info.name,
                   hemicube ? "resolution" : "samples", setting, 100 * error, t.ms_per_row,
                   (double)n / (t.ms_per_row * 1e-3) * 1e-6);
        }
    }
    static const double targets[] = {0.10, 0.05, 0.03, 0.02};
    printf("\nAt equal accuracy: the cheapest setting of each method whose row error is below the "
           "target (form factors per second).\n\n| target | analytic | hemicube | raycast | "
           "montecarlo |\n|---|---|---|---|---|\n");
    for (int k = 0; k < 4; ++k) {
        printf("| %.0f%% |", 100 * targets[k]);
        for (int m = 0; m < 4; ++m) {
            const trial *best = NULL;
            for (int i = 0; i < count; ++i)
                if (trials[i].method == all_methods[m] && trials[i].error <= targets[k] &&
                    (!best || trials[i].ms_per_row < best->ms_per_row))
                    best = &trials[i];
            if (best)
                printf(" %.2fM (%s %d) |", (double)n / (best->ms_per_row * 1e-3) * 1e-6,
                       all_methods[m] == RAD_FF_HEMICUBE ? "res" : "n", best->setting);
            else printf(" - |");
        }
        printf("\n");
    }
    free(reference);
    free(row);
    setup_free(&s);
}

/* ------------------------------------------------------------------------------------------- */
/* 4. Shooting                                                                                  */

/* One shooting run; prints a table row. patches_of: elements per patch side (0: the default). */
static void shoot(rad_ff_method method, int threads, double patch_factor) {
    rad_context *ctx = context_with(threads, 1);
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_mesh_options mesh = {0};
    mesh.elements = 10000;
    rad_ff_options ff = {method, 0, 0, NULL};
    double start = rad_seconds();
    if (rad_scene_builtin(ctx, "cornell", &scene)) {
        fprintf(stderr, "bench: %s\n", rad_context_error(ctx));
        exit(1);
    }
    if (patch_factor > 0) {
        /* The element size the mesher picks for 10,000 elements, times the factor. */
        double area = 0;
        for (size_t i = 0; i < scene->polygon_count; ++i)
            area += rad_polygon_area(scene, &scene->polygons[i]);
        mesh.patch_size = patch_factor * sqrt(area / (double)mesh.elements);
    }
    if (rad_system_create(ctx, scene, &mesh, &ff, &system)) {
        fprintf(stderr, "bench: %s\n", rad_context_error(ctx));
        exit(1);
    }
    double setup_seconds = rad_seconds() - start;
    rad_solve_options options = {0};
    options.solver = RAD_SOLVER_SHOOTING;
    options.tolerance = 0.01;
    rad_solve_report report;
    double cpu = rad_processor_seconds();
    rad_solve(system, &options, &report);
    cpu = rad_processor_seconds() - cpu;
    rad_ff_stats stats = rad_ff_provider_stats(system->ff);
    printf("| %s%s | %zu / %zu | %d | %.3f | %.3f | %.3f | %d | %llu |\n",
           rad_ff_method_find(method)->info.name, method == RAD_FF_DEFAULT ? " (default)" : "",
           system->element_count, system->patch_count, threads, setup_seconds, report.seconds, cpu,
           report.iterations, (unsigned long long)stats.rows);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static void bench_shooting(void) {
    printf("\n## 4. Shooting the Cornell box, 10,000 elements, to 1%% unshot power\n\n");
    printf("Default patches are 2 x 2 elements; the last rows use 4 x 4 (--patch-size, Cohen et "
           "al. 1986: the form factors are paid per patch). Processor seconds add up the threads."
           "\n\n");
    printf("| form factors | elements / patches | threads | set-up s | shooting s | processor s | "
           "shots | rows computed |\n|---|---|---|---|---|---|---|---|\n");
    shoot(RAD_FF_DEFAULT, 2, 0);
    shoot(RAD_FF_DEFAULT, 1, 0);
    if (!quick) {
        shoot(RAD_FF_HEMICUBE, 2, 0);
        shoot(RAD_FF_RAYCAST, 2, 0);
        shoot(RAD_FF_MONTECARLO, 2, 0);
    }
    shoot(RAD_FF_DEFAULT, 2, 4);
    shoot(RAD_FF_DEFAULT, 1, 4);
}

int main(int argc, char **argv) {
    int section = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0) quick = 1;
        else if (strcmp(argv[i], "--section") == 0 && i + 1 < argc) section = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: bench_formfactors [--quick] [--section 1-4]\n");
            return 2;
        }
    }
    printf("# Form-factor benchmark%s\n", quick ? " (quick)" : "");
    if (!section || section == 1) bench_rays();
    if (!section || section == 2) bench_threads();
    if (!section || section == 3) bench_accuracy();
    if (!section || section == 4) bench_shooting();
    return 0;
}
