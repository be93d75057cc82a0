/* bench_solvers.c - the solvers on generated dense systems (n = 1000 and 4000): seconds per
 * gathering round, seconds to converge, memory. Prints a Markdown table. Timings only: nothing
 * here passes or fails. */
#include "radiosity.h"

#include "core/rng.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* An open room-like system: each row of F sums to 0.9, reflectances 0.2..0.8, 2% emitters. */
static rad_system *make_system(rad_context *ctx, size_t n) {
    rad_patch_desc *patches = calloc(n, sizeof *patches);
    float *ff = malloc(n * n * sizeof *ff);
    rad_rng rng = rad_rng_make(1234, n);
    for (size_t i = 0; i < n; ++i) {
        double rho = 0.2 + 0.6 * rad_rng_uniform(&rng);
        double e = i % 50 == 0 ? 10.0 : 0.0;
        patches[i] = (rad_patch_desc){NULL, 0.5 + rad_rng_uniform(&rng), {rho, rho, rho}, {e, e, e}};
    }
    for (size_t i = 0; i < n; ++i) {
        double sum = 0;
        for (size_t j = 0; j < n; ++j) {
            float f = i == j ? 0.0f : (float)rad_rng_uniform(&rng);
            ff[i * n + j] = f;
            sum += f;
        }
        for (size_t j = 0; j < n; ++j) ff[i * n + j] = (float)(ff[i * n + j] * 0.9 / sum);
    }
    rad_system *system = NULL;
    if (rad_system_create_dense(ctx, patches, n, ff, &system)) fprintf(stderr, "%s\n", rad_context_error(ctx));
    free(patches);
    free(ff);
    return system;
}

static double solve_seconds(rad_system *system, rad_solver_kind kind, int iterations, double tolerance,
                            int *done) {
    rad_solve_options options = {.solver = kind, .max_iterations = iterations, .tolerance = tolerance};
    rad_solve_report report;
    double start = now();
    rad_solve(system, &options, &report);
    if (done) *done = report.iterations;
    return now() - start;
}

int main(int argc, char **argv) {
    int skip_direct_4000 = argc > 1 && argv[1][0] == 'q';
    printf("## Solvers on generated dense systems\n\n");
    printf("| n | threads | solver | s per round | rounds/shots to 1e-6 | s to converge | matrix MiB |\n");
    printf("|---|---|---|---|---|---|---|\n");
    size_t sizes[] = {1000, 4000};
    for (int si = 0; si < 2; ++si) {
        size_t n = sizes[si];
        for (int threads = 1; threads <= 2; ++threads) {
            rad_context_options options = {.threads = threads, .max_memory = 8ull << 30};
            rad_context *ctx;
            rad_context_create(&options, &ctx);
            rad_system *system = make_system(ctx, n);
            double matrix_mib = 4.0 * (double)n * (double)n / 1048576.0;
            rad_solver_kind kinds[] = {RAD_SOLVER_JACOBI, RAD_SOLVER_GAUSS_SEIDEL, RAD_SOLVER_SHOOTING,
                                       RAD_SOLVER_DIRECT};
            for (int k = 0; k < 4; ++k) {
                if (kinds[k] == RAD_SOLVER_GAUSS_SEIDEL && threads > 1) continue; /* sequential */
                if (kinds[k] == RAD_SOLVER_DIRECT && (threads > 1 || (n > 1000 && skip_direct_4000)))
                    continue;
                double per_round = 0;
                if (kinds[k] == RAD_SOLVER_JACOBI || kinds[k] == RAD_SOLVER_GAUSS_SEIDEL) {
                    /* A round is the difference between 11 and 1 rounds, over 10 (the set-up,
                     * storing the matrix, is in both). */
                    double one = solve_seconds(system, kinds[k], 1, 0, NULL);
                    double eleven = solve_seconds(system, kinds[k], 11, 1e-300, NULL);
                    per_round = (eleven - one) / 10;
                }
                int done = 0;
                double total = solve_seconds(system, kinds[k], 0, 1e-6, &done);
                double mib = kinds[k] == RAD_SOLVER_SHOOTING ? 4.0 * n / 1048576.0 :
                             kinds[k] == RAD_SOLVER_DIRECT ? 3 * matrix_mib : matrix_mib;
                if (per_round > 0)
                    printf("| %zu | %d | %s | %.4f | %d | %.3f | %.1f |\n", n, threads,
                           rad_solver_kind_name(kinds[k]), per_round, done, total, mib);
                else
                    printf("| %zu | %d | %s | - | %d | %.3f | %.1f |\n", n, threads,
                           rad_solver_kind_name(kinds[k]), done, total, mib);
                fflush(stdout);
            }
            rad_system_destroy(system);
            rad_context_destroy(ctx);
        }
    }
    printf("\nMatrix MiB: the float32 gathering matrix (Jacobi, Gauss-Seidel), plus the float64 "
           "LU matrix (direct); shooting keeps one float32 row.\n");
    return 0;
}
