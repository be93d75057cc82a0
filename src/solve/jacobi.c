/* jacobi.c - gathering, Jacobi style: each round computes every element's new radiosity from
 * the previous round's, B_k = E_k + rho_k sum_j B_j A_j F_jk / A_k (Goral et al. 1984). */
#include "solve/gathering.h"

#include <math.h>

typedef struct jacobi_state {
    rad_gathering gathering;
    rad_rgb *next;
} jacobi_state;

static rad_status jacobi_begin(rad_solver_run *run) {
    rad_system *s = run->system;
    jacobi_state *state = rad_alloc_zero(s->ctx, 1, sizeof *state);
    if (!state) return RAD_ERROR_NO_MEMORY;
    run->state = state;
    state->next = rad_alloc(s->ctx, s->element_count, sizeof *state->next);
    if (!state->next) return RAD_ERROR_NO_MEMORY;
    return rad_gathering_begin(run, &state->gathering);
}

static rad_status jacobi_step(rad_solver_run *run, int iteration, double *residual) {
    (void)iteration;
    rad_system *s = run->system;
    jacobi_state *state = run->state;
    size_t n = s->element_count, np = s->patch_count;
    double change = 0;
    /* Every element gathers from the previous round's patch radiosities. */
#pragma omp parallel for schedule(static) reduction(max : change) num_threads(rad_thread_count(s->ctx))
    for (size_t e = 0; e < n; ++e) {
        double received[3];
        rad_gathering_gather(&state->gathering, np, e, received);
        for (int c = 0; c < 3; ++c) {
            double b = s->emission[e][c] + s->reflectance[e][c] * received[c];
            change = fmax(change, fabs(b - s->radiosity[e][c]));
            state->next[e][c] = b;
            if (run->tracing) run->received[e][c] = received[c];
        }
    }
    for (size_t e = 0; e < n; ++e)
        for (int c = 0; c < 3; ++c) s->radiosity[e][c] = state->next[e][c];
    for (size_t p = 0; p < np; ++p) rad_gathering_update_patch(s, &state->gathering, p);
    *residual = change / rad_max_radiosity(s);
    return RAD_OK;
}

static void jacobi_end(rad_solver_run *run) {
    jacobi_state *state = run->state;
    if (!state) return;
    rad_gathering_end(run, &state->gathering);
    rad_free(run->system->ctx, state->next);
    rad_free(run->system->ctx, state);
    run->state = NULL;
}

static const rad_solver_variant jacobi_variants[] = {{"jacobi", 0, 0}};

const rad_solver_impl rad_solver_jacobi = {
    {"jacobi", "gathering, each round from the previous round's radiosity (Goral et al. 1984)",
     RAD_SOLVER_ITERATIVE | RAD_SOLVER_NEEDS_MATRIX, NULL, 0, jacobi_variants, 1, 0},
    jacobi_begin, jacobi_step, jacobi_end,
};
