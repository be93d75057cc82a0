/* gauss_seidel.c - gathering in place: each element's new radiosity is used as soon as its
 * patch is done, so light travels further in one round than with Jacobi. With omega != 1 this
 * is successive over-relaxation: B <- (1 - omega) B + omega (E + rho * gathered). */
#include "solve/gathering.h"

#include <math.h>

static rad_status gauss_seidel_begin(rad_solver_run *run) {
    rad_gathering *g = rad_alloc_zero(run->system->ctx, 1, sizeof *g);
    if (!g) return RAD_ERROR_NO_MEMORY;
    run->state = g;
    return rad_gathering_begin(run, g);
}

static rad_status gauss_seidel_step(rad_solver_run *run, int iteration, double *residual) {
    (void)iteration;
    rad_system *s = run->system;
    rad_gathering *g = run->state;
    size_t np = s->patch_count;
    double omega = run->omega, change = 0;
    for (size_t p = 0; p < np; ++p) {
        for (size_t e = s->patch_first[p]; e < s->patch_first[p + 1]; ++e) {
            double received[3];
            rad_gathering_gather(g, np, e, received);
            for (int c = 0; c < 3; ++c) {
                double gathered = s->emission[e][c] + s->reflectance[e][c] * received[c];
                double b = (1 - omega) * s->radiosity[e][c] + omega * gathered;
                change = fmax(change, fabs(b - s->radiosity[e][c]));
                s->radiosity[e][c] = b;
                if (run->tracing) run->received[e][c] = received[c];
            }
        }
        rad_gathering_update_patch(s, g, p);
    }
    *residual = change / rad_max_radiosity(s);
    return RAD_OK;
}

static void gauss_seidel_end(rad_solver_run *run) {
    rad_gathering *g = run->state;
    if (!g) return;
    rad_gathering_end(run, g);
    rad_free(run->system->ctx, g);
    run->state = NULL;
}

/* Plain, and over-relaxed with omega 1.1, measured best for the Cornell box. */
static const rad_solver_variant gauss_seidel_variants[] = {
    {"gauss-seidel", 0, 0},
    {"SOR, omega %g", 1, 0},
};

const rad_solver_impl rad_solver_gauss_seidel = {
    {"gauss-seidel", "gathering in place; with omega != 1 successive over-relaxation",
     RAD_SOLVER_ITERATIVE | RAD_SOLVER_NEEDS_MATRIX, NULL, 0, gauss_seidel_variants, 2, 1.1},
    gauss_seidel_begin, gauss_seidel_step, gauss_seidel_end,
};
