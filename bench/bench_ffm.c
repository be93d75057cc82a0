/* bench_ffm.c - .ffm parsing time against the number of patches (n patch lines, then n ff lines).
 * Large systems stop at the memory budget of their dense matrix (8 n^2 bytes), which is checked
 * after the whole file is read: the time is the parse, names and pairs looked up through the
 * parser's hash index. Timings only: nothing here passes or fails. */
#include "radiosity.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* n patches p0..p{n-1}, and one form factor leaving each: p_i -> p_{(7919 i + 1) mod n}. */
static char *make_text(size_t n, size_t *length) {
    size_t capacity = n * 96 + 1;
    char *text = malloc(capacity);
    if (!text) return NULL;
    size_t at = 0;
    for (size_t i = 0; i < n; ++i)
        at += (size_t)snprintf(text + at, capacity - at,
                               "patch p%zu area 1 reflectance 0.5 emission 1\n", i);
    for (size_t i = 0; i < n; ++i)
        at += (size_t)snprintf(text + at, capacity - at, "ff p%zu p%zu 0.1\n", i,
                               (7919 * i + 1) % n);
    *length = at;
    return text;
}

int main(void) {
    rad_context_options options = {.max_memory = 256ull << 20};
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return 1;
    printf("## .ffm parsing (n patch lines + n ff lines, budget 256 MiB)\n\n");
    printf("| patches | file MB | seconds | result |\n|---|---|---|---|\n");
    size_t sizes[] = {2000, 10000, 50000, 100000};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; ++s) {
        size_t length = 0;
        char *text = make_text(sizes[s], &length);
        if (!text) return 1;
        rad_scene *scene = NULL;
        double start = now();
        rad_status status = rad_scene_parse_ffm(ctx, text, length, "bench.ffm", &scene);
        double seconds = now() - start;
        printf("| %zu | %.1f | %.3f | %s |\n", sizes[s], (double)length / 1e6, seconds,
               status == RAD_OK ? "parsed"
               : status == RAD_ERROR_MEMORY_BUDGET ? "matrix over budget (after parsing)"
                                                   : rad_context_error(ctx));
        rad_scene_destroy(scene);
        free(text);
    }
    rad_context_destroy(ctx);
    return 0;
}
