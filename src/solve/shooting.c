/* shooting.c - progressive refinement (Cohen, Chen, Wallace & Greenberg 1988).
 *
 * Every element keeps its radiosity B and the part not yet shot, the unshot radiosity dB.
 * Each step shoots from the patch with the most unshot power (dB * A): every element j
 * receives dB_p A_p F_pj / A_j, reflects rho_j times that, and adds it to B_j and dB_j.
 * Rows of F come from the provider on demand, so memory stays O(n).
 *
 * Over-relaxation (omega > 1): the shooter sends omega * dB_p and keeps (1 - omega) * dB_p, a
 * negative unshot radiosity that later shots pay back (over-relaxed Southwell iteration;
 * Gortler et al. 1993, Feda & Purgathofer 1992). Patches are then chosen by |unshot power|.
 *
 * The ambient term (Cohen et al. 1988) estimates the light not yet shot for display:
 * ambient = R * sum(dB_i A_i) / sum(A_i), R = 1 / (1 - mean reflectance). */
#include "solve/solver.h"

#include <math.h>
#include <string.h>

typedef struct shooting_state {
    float *row;
    double emitted_power;      /* sum over elements and channels of E A */
    double mean_reflectance[3];
    double total_area;
} shooting_state;

static double unshot_power(const rad_system *s, size_t p) {
    double power = 0;
    for (size_t e = s->patch_first[p]; e < s->patch_first[p + 1]; ++e)
        power += (s->unshot[e][0] + s->unshot[e][1] + s->unshot[e][2]) * s->area[e];
    return power;
}

static rad_status shooting_begin(rad_solver_run *run) {
    rad_system *s = run->system;
    shooting_state *state = rad_alloc_zero(s->ctx, 1, sizeof *state);
    if (!state) return RAD_ERROR_NO_MEMORY;
    run->state = state;
    state->row = rad_alloc(s->ctx, s->element_count, sizeof *state->row);
    if (!state->row) return RAD_ERROR_NO_MEMORY;
    for (size_t e = 0; e < s->element_count; ++e) {
        state->total_area += s->area[e];
        for (int c = 0; c < 3; ++c) {
            state->emitted_power += s->emission[e][c] * s->area[e];
            state->mean_reflectance[c] += s->reflectance[e][c] * s->area[e];
        }
    }
    for (int c = 0; c < 3; ++c) state->mean_reflectance[c] /= state->total_area;
    return RAD_OK;
}

static void update_ambient(rad_system *s, const shooting_state *state) {
    double unshot[3] = {0, 0, 0};
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c) unshot[c] += s->unshot[e][c] * s->area[e];
    for (int c = 0; c < 3; ++c) {
        double r = state->mean_reflectance[c] < 1 ? 1.0 / (1.0 - state->mean_reflectance[c]) : 0;
        s->ambient[c] = r * unshot[c] / state->total_area;
    }
}

static rad_status shooting_step(rad_solver_run *run, int iteration, double *residual) {
    (void)iteration;
    rad_system *s = run->system;
    shooting_state *state = run->state;
    if (state->emitted_power <= 0) {
        *residual = 0;
        return RAD_OK;
    }

    /* Pick the patch with the most unshot power. */
    size_t shooter = 0;
    double best = -1;
    for (size_t p = 0; p < s->patch_count; ++p) {
        double power = fabs(unshot_power(s, p));
        if (power > best) {
            best = power;
            shooter = p;
        }
    }
    run->shooter_surface = (long)s->element_surface[s->patch_first[shooter]];

    /* Take its unshot radiosity; it keeps (1 - omega) of it. */
    double shot[3];
    rad_system_patch_mean(s, (const rad_rgb *)s->unshot, shooter, shot);
    double omega = run->omega;
    for (size_t e = s->patch_first[shooter]; e < s->patch_first[shooter + 1]; ++e)
        for (int c = 0; c < 3; ++c) s->unshot[e][c] *= 1 - omega;
    double power[3];
    for (int c = 0; c < 3; ++c) power[c] = omega * shot[c] * s->patch_area[shooter];

    /* Distribute: every element receives dB_p A_p F_pj / A_j and reflects rho_j of it. */
    rad_status status = s->ff->row(s->ff, shooter, state->row);
    if (status) return status;
    const float *row = state->row;
    size_t n = s->element_count;
    int tracing = run->tracing;
    for (size_t j = 0; j < n; ++j) {
        double f = (double)row[j] / s->area[j];
        for (int c = 0; c < 3; ++c) {
            double received = power[c] * f;
            double reflected = s->reflectance[j][c] * received;
            s->radiosity[j][c] += reflected;
            s->unshot[j][c] += reflected;
            if (tracing) {
                run->received[j][c] = received;
                run->reflected[j][c] = reflected;
            }
        }
    }

    /* Stopping measure: unshot power left as a fraction of the power emitted. */
    double left = 0;
    for (size_t p = 0; p < s->patch_count; ++p) left += fabs(unshot_power(s, p));
    *residual = left / state->emitted_power;
    if (run->options->ambient) update_ambient(s, state);
    return RAD_OK;
}

static void shooting_end(rad_solver_run *run) {
    shooting_state *state = run->state;
    if (!state) return;
    rad_free(run->system->ctx, state->row);
    rad_free(run->system->ctx, state);
    run->state = NULL;
}

const rad_solver_impl rad_solver_shooting = {
    RAD_SOLVER_SHOOTING, "shooting", 1, 1, shooting_begin, shooting_step, shooting_end,
};
