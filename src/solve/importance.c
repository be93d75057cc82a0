/* importance.c - importance-driven progressive refinement (Smits, Arvo & Salesin 1992, "An
 * importance-driven radiosity algorithm").
 *
 * Importance is the adjoint of light: Y_i, the effect that unit radiosity on element i has on
 * the image, obeys the transposed system
 *
 *     Y_i = R_i + sum_j F_ij rho_j Y_j,
 *
 * where the emitted importance R_i = (share of the screen element i covers) / A_i, so that
 * sum_i A_i R_i dB_i is the change of the image's mean radiosity when element i changes by dB_i
 * (system/element_rays.h traces one ray per pixel, screen_share.c).
 *
 * 1. Emitted importance from the camera (begin).
 * 2. Spread it with the same form-factor rows as light: a shooting pass of Z = rho Y, where
 *    element j receives dZ_q F_jq from patch q and adds rho_j times that to its unshot
 *    importance. What arrives, G_j = sum_q F_jq Z_q, is the importance of the light j sends
 *    out: shooting the unshot radiosity dB_p changes the image by dB_p A_p G_p. The pass
 *    stops when 5% of the emitted importance is left unshot: the order of light shots needs
 *    importance roughly, not exactly. Its rows are kept for the light shots from the same
 *    patches (within an eighth of the memory budget).
 * 3. Shoot light from the patch with the most unshot power times importance,
 *    sum_c |dB_pc| A_p (G_pc + Gmean_c), where Gmean is the area-weighted mean importance.
 *    Why the added mean: ordering by G alone halves the view error early on but then falls
 *    behind plain shooting, because light piles up on patches of middling importance while
 *    shots go to patches whose light only bounces on to other important patches (shooting p
 *    removes dB_p A_p G_p of future view error but only the one-bounce part of it for good).
 *    Adding the mean keeps the early gain and plain shooting's pace later (measured on the
 *    Cornell box: docs/solvers.md, "Importance"). Surfaces no camera path reaches are shot too,
 *    so the result is still a full radiosity solution, with the same stopping measure (unshot
 *    power) as plain shooting; only the order of the shots, and so where the error goes first,
 *    differs.
 *
 * Importance depends only on the camera and the form factors, so a resumed run recomputes the
 * same importance and takes the same shots as one that never stopped. */
#include "system/screen_share.h"
#include "solve/shooting.h"

#include <math.h>
#include <string.h>

#define IMPORTANCE_TOLERANCE 0.05 /* unshot importance left after the importance pass */
#define IMPORTANCE_BLEND 1.0      /* times the mean importance, added to every patch's */
#define IMPORTANCE_MAX_SIDE 256   /* pixels along the longer side of the importance image */
#define KEPT_ROWS_SHARE 0.125     /* of the memory budget, for rows of the importance pass */

typedef struct importance_state {
    rad_shooting shooting;
    rad_rgb *weight; /* per patch: G_p + mean G, the importance of the light it sends */
    /* Rows the importance pass computed, kept (within KEPT_ROWS_SHARE of the memory budget)
     * for the light shots from the same patches: those are the patches the camera sees, which
     * light shoots early. Rows are deterministic, so a kept row is the row. */
    float **kept_row; /* per patch, or NULL */
    size_t kept_bytes;
} importance_state;

void rad_importance_view_size(const rad_solve_options *o, int *width, int *height) {
    int w = o->view_width, h = o->view_height;
    if (w <= 0 || h <= 0) w = h = IMPORTANCE_MAX_SIDE;
    int side = w > h ? w : h;
    if (side > IMPORTANCE_MAX_SIDE) {
        w = (int)fmax(1, round((double)w * IMPORTANCE_MAX_SIDE / side));
        h = (int)fmax(1, round((double)h * IMPORTANCE_MAX_SIDE / side));
    }
    *width = w;
    *height = h;
}

/* Steps 1 and 2: received importance G per element, from a shooting pass of importance. */
static rad_status spread_importance(rad_solver_run *run, importance_state *state,
                                    const double *share, rad_rgb *received) {
    rad_system *s = run->system;
    rad_context *ctx = s->ctx;
    size_t n = s->element_count;
    rad_rgb *unshot = rad_alloc(ctx, n, sizeof *unshot);
    float *row = rad_alloc(ctx, n, sizeof *row);
    if (!unshot || !row) {
        rad_free(ctx, unshot);
        rad_free(ctx, row);
        return RAD_ERROR_NO_MEMORY;
    }
    double keep_budget =
        KEPT_ROWS_SHARE * (double)(ctx->max_memory ? ctx->max_memory : RAD_DEFAULT_MAX_MEMORY);
    double emitted = 0;
    for (size_t e = 0; e < n; ++e)
        for (int c = 0; c < 3; ++c) {
            received[e][c] = 0;
            unshot[e][c] = s->reflectance[e][c] * share[e] / s->area[e];
            emitted += unshot[e][c] * s->area[e];
        }
    rad_status status = RAD_OK;
    int shots = 0;
    while (emitted > 0 && shots < (int)s->patch_count) {
        /* The patch with the most unshot importance. */
        size_t shooter = 0;
        double best = -1, left = 0;
        for (size_t p = 0; p < s->patch_count; ++p) {
            double power = 0;
            for (size_t e = s->patch_first[p]; e < s->patch_first[p + 1]; ++e)
                power += (unshot[e][0] + unshot[e][1] + unshot[e][2]) * s->area[e];
            left += power;
            if (power > best) {
                best = power;
                shooter = p;
            }
        }
        if (left <= IMPORTANCE_TOLERANCE * emitted) break;
        double shot[3];
        rad_system_patch_mean(s, (const rad_rgb *)unshot, shooter, shot);
        for (size_t e = s->patch_first[shooter]; e < s->patch_first[shooter + 1]; ++e)
            unshot[e][0] = unshot[e][1] = unshot[e][2] = 0;
        if ((status = s->ff->row(s->ff, shooter, row))) break;
        ++shots;
        size_t bytes = n * sizeof *row;
        if (!state->kept_row[shooter] && (double)(state->kept_bytes + bytes) <= keep_budget) {
            float *kept = rad_alloc(ctx, n, sizeof *kept);
            if (kept) { /* out of memory here only means the row is asked for again later */
                memcpy(kept, row, bytes);
                state->kept_row[shooter] = kept;
                state->kept_bytes += bytes;
            }
        }
        double area = s->patch_area[shooter];
        for (size_t j = 0; j < n; ++j) {
            double f = area * (double)row[j] / s->area[j];
            for (int c = 0; c < 3; ++c) {
                double arriving = shot[c] * f;
                received[j][c] += arriving;
                unshot[j][c] += s->reflectance[j][c] * arriving;
            }
        }
        if (rad_progress(ctx, "importance", (double)shots, (double)s->patch_count)) {
            status = rad_fail(ctx, RAD_ERROR_CANCELLED, "cancelled while spreading importance");
            break;
        }
    }
    run->importance_shots = shots;
    rad_free(ctx, unshot);
    rad_free(ctx, row);
    return status;
}

static rad_status importance_begin(rad_solver_run *run) {
    rad_system *s = run->system;
    rad_context *ctx = s->ctx;
    const rad_solve_options *o = run->options;
    if (!o->camera)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the importance solver needs a camera (rad_solve_options.camera)");
    importance_state *state = rad_alloc_zero(ctx, 1, sizeof *state);
    if (!state) return RAD_ERROR_NO_MEMORY;
    run->state = state;
    rad_status status = rad_shooting_begin(run, &state->shooting);
    if (status) return status;

    /* 1. Emitted importance: the screen share of every element. */
    int width, height;
    rad_importance_view_size(o, &width, &height);
    size_t n = s->element_count;
    double *share = rad_alloc(ctx, n, sizeof *share);
    rad_rgb *received = rad_alloc(ctx, n, sizeof *received);
    state->weight = rad_alloc(ctx, s->patch_count, sizeof *state->weight);
    state->kept_row = rad_alloc_zero(ctx, s->patch_count, sizeof *state->kept_row);
    if (!share || !received || !state->weight || !state->kept_row) status = RAD_ERROR_NO_MEMORY;
    if (!status) status = rad_system_screen_share(s, o->camera, width, height, share);

    /* 2. Spread it. */
    if (!status) status = spread_importance(run, state, share, received);

    /* 3. Per patch: G_p, plus the mean. */
    if (!status) {
        double mean[3] = {0, 0, 0}, total_area = 0;
        for (size_t p = 0; p < s->patch_count; ++p) {
            rad_system_patch_mean(s, (const rad_rgb *)received, p, state->weight[p]);
            for (int c = 0; c < 3; ++c) mean[c] += state->weight[p][c] * s->patch_area[p];
            total_area += s->patch_area[p];
        }
        int seen = mean[0] + mean[1] + mean[2] > 0;
        if (!seen)
            rad_warn(ctx, "importance: the camera sees no lit surface; shooting in plain order");
        for (int c = 0; c < 3; ++c) {
            double blend = seen ? IMPORTANCE_BLEND * mean[c] / total_area : 1;
            for (size_t p = 0; p < s->patch_count; ++p) state->weight[p][c] += blend;
        }
    }
    rad_free(ctx, share);
    rad_free(ctx, received);
    return status;
}

static rad_status importance_step(rad_solver_run *run, int iteration, double *residual) {
    (void)iteration;
    rad_system *s = run->system;
    importance_state *state = run->state;
    if (state->shooting.emitted_power <= 0) {
        *residual = run->unshot_fraction = 0;
        return RAD_OK;
    }
    /* Pick the patch whose unshot light matters most to the image (ties: the lowest index). */
    size_t shooter = 0;
    double best = -1;
    for (size_t p = 0; p < s->patch_count; ++p) {
        double unshot[3] = {0, 0, 0};
        for (size_t e = s->patch_first[p]; e < s->patch_first[p + 1]; ++e)
            for (int c = 0; c < 3; ++c) unshot[c] += s->unshot[e][c] * s->area[e];
        double priority = 0;
        for (int c = 0; c < 3; ++c) priority += fabs(unshot[c]) * state->weight[p][c];
        if (priority > best) {
            best = priority;
            shooter = p;
        }
    }
    rad_status status =
        rad_shooting_shoot(run, &state->shooting, shooter, state->kept_row[shooter]);
    if (status) return status;
    *residual = rad_shooting_finish(run, &state->shooting);
    return RAD_OK;
}

static void importance_end(rad_solver_run *run) {
    importance_state *state = run->state;
    if (!state) return;
    rad_shooting_end(run, &state->shooting);
    if (state->kept_row)
        for (size_t p = 0; p < run->system->patch_count; ++p)
            rad_free(run->system->ctx, state->kept_row[p]);
    rad_free(run->system->ctx, state->kept_row);
    rad_free(run->system->ctx, state->weight);
    rad_free(run->system->ctx, state);
    run->state = NULL;
}

static const rad_method_option importance_options[] = {
    {"overshoot", "overshooting (Feda & Purgathofer 1992)"},
    {"ambient", "add the ambient term"},
};
static const rad_solver_variant importance_variants[] = {{"importance", 0, 0}};

const rad_solver_impl rad_solver_importance = {
    {"importance", "shooting ordered by what the camera sees (Smits, Arvo & Salesin 1992)",
     RAD_SOLVER_SHOOTS | RAD_SOLVER_ITERATIVE | RAD_SOLVER_NEEDS_CAMERA | RAD_SOLVER_KEEPS_UNSHOT |
         RAD_SOLVER_NEEDS_UNSHOT,
     importance_options, sizeof importance_options / sizeof importance_options[0],
     importance_variants, 1, 0},
    importance_begin, importance_step, importance_end,
};
