/* bench_emitters.c - the emitter table's choice by receiver against the lamp count
 * (src/light/emitters.c): a square grid of unit ceiling lamps 2 apart, 2.5 above receivers
 * spread over the floor under them. For each count, nanoseconds per emitter sample and per
 * density (rad_emitter_table_pdf) with the exact choice (a loop over every lamp, up to
 * RAD_EMITTERS_LOCAL_MAX lamps), the light tree (above it) and, for reference, the global choice
 * (the same lamps in one group). Also the share of samples on the receiver's nearest lamp.
 * The timings include the uniform numbers' stream (a few ns). Timings only: nothing here passes
 * or fails.
 * Usage: bench_emitters [SAMPLES PER ROW (1000000)] */
#include "core/context.h"
#include "light/emitters.h"
#include "radiosity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Uniform numbers in [0, 1) from a xorshift64* stream: receivers and samples independent. */
static double uniform(unsigned long long *state) {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    return (double)((*state * 2685821657736338717ull) >> 11) * 0x1p-53;
}

static volatile double sink; /* keeps the timed loops' results alive */

static void row(rad_context *ctx, int side, int grouped, long samples) {
    rad_emitter_table table = {0};
    size_t lamps = (size_t)side * (size_t)side;
    const double radiance[3] = {10, 10, 10};
    if (rad_emitter_table_reserve(ctx, &table, lamps)) return;
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) {
            rad_vec3 corner = v3(2.0 * i, 2.5, 2.0 * j);
            rad_emitter_table_add_parallelogram(&table, corner, v3(0, 0, 1), v3(1, 0, 0),
                                                v3(0, -1, 0), radiance);
            if (grouped) rad_emitter_table_close_group(&table);
        }
    if (rad_emitter_table_finish(ctx, &table, RAD_EMITTERS_BY_POWER)) {
        rad_emitter_table_free(ctx, &table);
        return;
    }
    /* Receivers uniform over the floor under the lamps, a new one every 16 samples. */
    unsigned long long state = 0x9e3779b97f4a7c15ull;
    double start = rad_processor_seconds(), sum = 0;
    long nearest = 0;
    rad_emitter_point out;
    rad_vec3 x = v3(0, 0, 0);
    for (long s = 0; s < samples; ++s) {
        if (s % 16 == 0) x = v3(uniform(&state) * 2.0 * side, 0, uniform(&state) * 2.0 * side);
        double u0 = uniform(&state), u1 = uniform(&state);
        if (rad_emitter_table_sample(&table, u0, u1, x, v3(0, 1, 0), &out)) {
            sum += out.pdf;
            int i = (int)floor(x.x / 2), j = (int)floor(x.z / 2);
            nearest += (long)out.index == (long)i * side + j;
        }
    }
    double sample_ns = 1e9 * (rad_processor_seconds() - start) / (double)samples;
    start = rad_processor_seconds();
    for (long s = 0; s < samples; ++s) {
        rad_vec3 y = v3(uniform(&state) * 2.0 * side, 0, uniform(&state) * 2.0 * side);
        size_t k = (size_t)s % table.count;
        const rad_emitter *e = &table.emitters[k];
        rad_vec3 d = v3_sub(v3_add(e->p0, v3(0.5, 0, 0.5)), y);
        double distance = v3_length(d);
        sum += rad_emitter_table_pdf(&table, k, y, v3(0, 1, 0), v3_scale(d, 1 / distance),
                                     distance);
    }
    double pdf_ns = 1e9 * (rad_processor_seconds() - start) / (double)samples;
    const char *choice = !grouped ? "global" : lamps > RAD_EMITTERS_LOCAL_MAX ? "light tree" : "exact";
    sink = sum;
    printf("| %zu | %s | %.0f | %.0f | %.1f%% |\n", lamps, choice, sample_ns, pdf_ns,
           100.0 * (double)nearest / (double)samples);
    rad_emitter_table_free(ctx, &table);
}

int main(int argc, char **argv) {
    long samples = argc > 1 ? atol(argv[1]) : 1000000;
    if (samples < 64) samples = 64;
    rad_context *ctx = NULL;
    if (rad_context_create(NULL, &ctx)) return 1;
    printf("Emitter choice by receiver: ns per sample and per density, share of samples on the "
           "receiver's nearest lamp (%ld samples a row, one thread)\n\n", samples);
    printf("| lamps | choice | ns / sample | ns / density | on the nearest lamp |\n");
    printf("|---|---|---|---|---|\n");
    const int sides[] = {8, 16, 17, 32, 64, 100};
    for (size_t s = 0; s < sizeof sides / sizeof *sides; ++s) {
        row(ctx, sides[s], 0, samples);
        row(ctx, sides[s], 1, samples);
    }
    rad_context_destroy(ctx);
    return 0;
}
