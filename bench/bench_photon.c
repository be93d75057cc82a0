/* bench_photon.c - photon mapping (docs/photonmapping.md): photon tracing rate on the Cornell
 * box (target: at least 2 million photons per second on 2 cores), the map's build and its
 * queries. Prints Markdown tables with wall and processor seconds. Timings only: nothing here
 * passes or fails.
 * Usage: bench_photon [PHOTONS]   (default 1,000,000 emitted per run) */
#include "radiosity.h"
#include "core/context.h"
#include "render/photon_map.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>

static rad_context *make_context(int threads) {
    rad_context_options options = {0};
    options.threads = threads;
    options.seed = 1;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return NULL;
    return ctx;
}

/* Photon tracing through rad_photonmap with a 4x4 image (the rendering is negligible). */
static void tracing(const char *scene_name, int threads, uint64_t photons) {
    rad_context *ctx = make_context(threads);
    rad_scene *scene = NULL;
    rad_image *image = NULL;
    if (!ctx || rad_scene_builtin(ctx, scene_name, &scene)) {
        fprintf(stderr, "bench_photon: %s\n", ctx ? rad_context_error(ctx) : "no context");
        rad_context_destroy(ctx);
        return;
    }
    rad_photonmap_options o = {0};
    o.width = o.height = 4;
    o.samples_per_pixel = 1;
    o.gather_rays = 1;
    o.photons = photons;
    o.caustic_photons = photons;
    rad_photonmap_stats stats = {0};
    if (rad_photonmap(ctx, scene, &o, &image, &stats)) {
        fprintf(stderr, "bench_photon: %s\n", rad_context_error(ctx));
    } else {
        double rate = stats.photons_emitted / stats.trace_seconds * 1e-6;
        double cpu_rate = stats.photons_emitted / stats.trace_cpu_seconds * 1e-6;
        printf("| %-14s | %7d | %9llu | %7.3f | %7.3f | %10.2f | %12.2f | %9llu | %8.3f |\n",
               scene_name, threads, (unsigned long long)stats.photons_emitted,
               stats.trace_seconds, stats.trace_cpu_seconds, rate, cpu_rate,
               (unsigned long long)(stats.global_stored + stats.caustic_stored),
               stats.build_seconds);
    }
    rad_image_destroy(image);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static double uniform(uint64_t *state) {
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*state >> 11) * 0x1p-53;
}

/* Photons spread over the six faces of a unit box (as on walls), the map built, then queries. */
static void map(int threads, size_t count) {
    rad_context *ctx = make_context(threads);
    if (!ctx) return;
    rad_photon *p = malloc(count * sizeof *p);
    if (!p) return;
    uint64_t state = 5;
    for (size_t i = 0; i < count; ++i) {
        int face = (int)(i % 6), axis = face / 2;
        double c[3] = {uniform(&state), uniform(&state), uniform(&state)};
        c[axis] = face % 2;
        double n[3] = {0, 0, 0}, power[3] = {1.0 / count, 1.0 / count, 1.0 / count};
        n[axis] = face % 2 ? -1 : 1;
        rad_vec3 normal = {n[0], n[1], n[2]};
        p[i] = rad_photon_pack((rad_vec3){c[0], c[1], c[2]}, power, normal, normal);
    }
    rad_photon *copy = rad_alloc(ctx, count, sizeof *copy);
    for (size_t i = 0; i < count && copy; ++i) copy[i] = p[i];
    free(p);
    if (!copy) return;
    /* The radius holding 50 photons on average: 50 = n / 6 * pi r^2. */
    double radius = sqrt(50 * 6.0 / (3.14159265358979 * count));
    rad_photon_map m;
    double wall = rad_seconds(), cpu = rad_processor_seconds();
    if (rad_photon_map_build(ctx, copy, count, radius, threads, &m)) {
        fprintf(stderr, "bench_photon: %s\n", rad_context_error(ctx));
        rad_context_destroy(ctx);
        return;
    }
    double build_wall = rad_seconds() - wall, build_cpu = rad_processor_seconds() - cpu;
    /* Queries on one thread: k = 50 nearest, and the box estimate with the radius. */
    int queries = 200000;
    rad_photon_near found[50];
    double sum = 0;
    state = 9;
    cpu = rad_processor_seconds();
    for (int q = 0; q < queries; ++q) {
        rad_vec3 x = {uniform(&state), uniform(&state), 0};
        double e[3];
        rad_photon_map_irradiance(&m, x, (rad_vec3){0, 0, 1}, radius, 50, found, e);
        sum += e[0];
    }
    double knn = rad_processor_seconds() - cpu;
    cpu = rad_processor_seconds();
    for (int q = 0; q < queries; ++q) {
        rad_vec3 x = {uniform(&state), uniform(&state), 0};
        double e[3];
        rad_photon_map_irradiance(&m, x, (rad_vec3){0, 0, 1}, radius, 0, NULL, e);
        sum += e[0];
    }
    double box = rad_processor_seconds() - cpu;
    printf("| %9zu | %7d | %8.3f | %11.3f | %15.2f | %14.2f | %8.3g |\n", count, threads,
           build_wall, build_cpu, queries / knn * 1e-6, queries / box * 1e-6, sum / (2 * queries));
    rad_photon_map_free(ctx, &m);
    rad_context_destroy(ctx);
}

int main(int argc, char **argv) {
    uint64_t photons = argc > 1 ? strtoull(argv[1], NULL, 10) : 1000000;
    if (photons < 1) photons = 1000000;
    printf("## Photon tracing, %llu global + %llu caustic photons emitted\n\n",
           (unsigned long long)photons, (unsigned long long)photons);
    printf("target: cornell at >= 2 M photons/s on 2 cores (threads 0 = all cores). Build: the\n"
           "global, caustic and precomputed-irradiance maps.\n\n");
    printf("| scene          | threads |   photons | wall s  | cpu s   | Mphotons/s | M/cpu-second "
           "|    stored | build s  |\n");
    printf("|----------------|---------|-----------|---------|---------|------------|--------------"
           "|-----------|----------|\n");
    tracing("cornell", 1, photons);
    tracing("cornell", 0, photons);
    tracing("cornell-mirror", 0, photons);
    printf("\n## The hash grid: build, and 200,000 queries on one thread\n\n");
    printf("Photons on the faces of a unit box, the radius holding 50 on average; k nearest with "
           "k = 50, and the box estimate; query rates per processor-second.\n\n");
    printf("|   photons | threads | build s  | build cpu s | Mqueries/s k=50 | Mqueries/s box | "
           "(mean E) |\n");
    printf("|-----------|---------|----------|-------------|-----------------|----------------|----------|\n");
    map(1, 1000000);
    map(2, 1000000);
    return 0;
}
