/* bench_pathtrace.c - path tracer throughput on the Cornell box (target: at least 1 million paths
 * per second on 2 cores; a path is one camera sample traced to its end) and on cornell-mirror.
 * Prints a Markdown table. Timings only: nothing here passes or fails.
 * Usage: bench_pathtrace [SPP]   (default 16 paths per pixel at 512 x 512) */
#include "radiosity.h"

#include <stdio.h>
#include <stdlib.h>

static void run(const char *scene_name, int threads, int spp) {
    rad_context_options options = {0};
    options.threads = threads;
    options.seed = 1;
    rad_context *ctx = NULL;
    rad_scene *scene = NULL;
    rad_image *image = NULL;
    if (rad_context_create(&options, &ctx) || rad_scene_builtin(ctx, scene_name, &scene)) {
        fprintf(stderr, "bench_pathtrace: %s\n", ctx ? rad_context_error(ctx) : "no context");
        rad_context_destroy(ctx);
        return;
    }
    rad_pathtrace_options trace = {0};
    trace.width = trace.height = 512;
    trace.samples_per_pixel = spp;
    rad_pathtrace_stats stats = {0};
    if (rad_pathtrace(ctx, scene, &trace, &image, &stats)) {
        fprintf(stderr, "bench_pathtrace: %s\n", rad_context_error(ctx));
    } else {
        printf("| %-14s | %7d | %10llu | %7.3f | %8.3f | %8.2f | %9.2f |\n", scene_name,
               threads ? threads : 0, (unsigned long long)stats.paths, stats.seconds,
               stats.paths / stats.seconds * 1e-6, stats.rays / stats.seconds * 1e-6,
               (double)stats.rays / (double)stats.paths);
    }
    rad_image_destroy(image);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

int main(int argc, char **argv) {
    int spp = argc > 1 ? atoi(argv[1]) : 16;
    if (spp < 1) spp = 16;
    printf("## Path tracer, 512 x 512, %d paths per pixel\n\n", spp);
    printf("target: cornell at >= 1 Mpaths/s on 2 cores (threads 0 = all cores)\n\n");
    printf("| scene          | threads |      paths | seconds | Mpaths/s |  Mrays/s | rays/path |\n");
    printf("|----------------|---------|------------|---------|----------|----------|-----------|\n");
    run("cornell", 1, spp);
    run("cornell", 0, spp);
    run("cornell-mirror", 0, spp);
    return 0;
}
