/* shooting.c - progressive refinement (Cohen, Chen, Wallace & Greenberg 1988).
 *
 * Every element keeps its radiosity B and the part not yet shot, the unshot radiosity dB.
 * Each step shoots from the patch with the most unshot power (dB * A): every element j
 * receives dB_p A_p F_pj / A_j, reflects rho_j times that, and adds it to B_j and dB_j.
 * Rows of F come from the provider on demand, so memory stays O(n). Whatever is shot keeps the
 * invariant B = E + rho K (B - dB), so any order of shots, and any amount shot, converges to
 * the same solution once dB is 0.
 *
 * Over-relaxation (omega > 1): the shooter sends omega * dB_p and keeps (1 - omega) * dB_p, a
 * negative unshot radiosity that later shots pay back (over-relaxed Southwell iteration;
 * Gortler, Cohen & Slusallek 1993). Patches are then chosen by |unshot power|.
 *
 * Overshooting (Feda & Purgathofer 1992, "Accelerating radiosity by overshooting"): the
 * shooter also sends, in advance, what it will reflect of the light still to come, estimated
 * from the ambient term: rho_p * ambient. Its unshot radiosity goes negative by that much and
 * is settled when the light really arrives.
 *
 * The ambient term (Cohen et al. 1988) estimates the light not yet shot for display:
 * ambient = R * sum(dB_i A_i) / sum(A_i), R = 1 / (1 - mean reflectance). */
#include "solve/shooting.h"

#include "core/team.h"

#include <math.h>
#include <string.h>

/* Patches are visited in fixed chunks, each summing its own share of the unshot totals; the
 * shares are then added in chunk order. The chunks do not depend on the thread count, so
 * neither do the sums, and a shot's running totals stay bit-identical to a fresh recount. */
#define CHUNK_PATCHES 128
#define PARALLEL_ELEMENTS 4096 /* below this a shot is too short to share out */

static size_t chunk_count(const rad_system *s) {
    return (s->patch_count + CHUNK_PATCHES - 1) / CHUNK_PATCHES;
}

typedef struct {
    rad_solver_run *run;
    rad_shooting *state;
    const float *row;
    const double *power;
    int totals; /* recount the unshot totals too */
} pass_job;

/* The unshot totals feed only the ambient term (and the overshoot made from it): a shot
 * recounts them only when that is asked for; the first pass (rad_shooting_begin) always does. */
static int pass_totals(const rad_shooting *state, const double *power) {
    return !power || state->overshoot || state->with_ambient;
}

/* One chunk of patches: when `power` is given, first add the light it sends through `row`
 * (every element j receives power F_pj / A_j and reflects rho_j of it; elements the row does not
 * reach are left as they are); always recount the chunk's patches' unshot powers, and its share
 * of the unshot totals when the ambient term will be made from them (pass_totals). */
static void pass_chunk(void *user, long chunk, int worker) {
    (void)worker;
    const pass_job *job = user;
    rad_solver_run *run = job->run;
    rad_system *s = run->system;
    const float *row = job->row;
    const double *power = job->power;
    const int tracing = run->tracing && power;
    const int totals = job->totals;
    double unshot[3] = {0, 0, 0};
    size_t first = (size_t)chunk * CHUNK_PATCHES, last = first + CHUNK_PATCHES;
    if (last > s->patch_count) last = s->patch_count;
    for (size_t p = first; p < last; ++p) {
        double patch_power = 0;
        for (size_t j = s->patch_first[p]; j < s->patch_first[p + 1]; ++j) {
            if (power && (row[j] != 0 || tracing)) {
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
            patch_power += (s->unshot[j][0] + s->unshot[j][1] + s->unshot[j][2]) * s->area[j];
            if (totals)
                for (int c = 0; c < 3; ++c) unshot[c] += s->unshot[j][c] * s->area[j];
        }
        job->state->patch_power[p] = patch_power;
    }
    if (totals) memcpy(job->state->chunk_unshot[chunk], unshot, sizeof unshot);
}

/* One pass over the elements, chunk by chunk (pass_chunk); the chunks' shares are then added
 * in chunk order. Large systems share the chunks out to the context's worker threads, which
 * sleep between shots (core/team.h). */
static void pass(rad_solver_run *run, rad_shooting *state, const float *row, const double *power) {
    rad_system *s = run->system;
    const long chunks = (long)chunk_count(s);
    pass_job job = {run, state, row, power, pass_totals(state, power)};
    if (s->element_count >= PARALLEL_ELEMENTS) rad_team_for(s->ctx, chunks, pass_chunk, &job);
    else
        for (long chunk = 0; chunk < chunks; ++chunk) pass_chunk(&job, chunk, 0);
    if (!job.totals) return;
    double total[3] = {0, 0, 0};
    for (long chunk = 0; chunk < chunks; ++chunk)
        for (int c = 0; c < 3; ++c) total[c] += state->chunk_unshot[chunk][c];
    memcpy(state->unshot_total, total, sizeof total);
}

static void compute_ambient(rad_shooting *state) {
    for (int c = 0; c < 3; ++c) {
        double r = state->mean_reflectance[c] < 1 ? 1.0 / (1.0 - state->mean_reflectance[c]) : 0;
        state->ambient[c] = r * state->unshot_total[c] / state->total_area;
    }
}

rad_status rad_shooting_begin(rad_solver_run *run, rad_shooting *state) {
    rad_system *s = run->system;
    memset(state, 0, sizeof *state);
    state->overshoot = rad_run_option(run, "overshoot", run->options->overshoot) != 0;
    state->with_ambient = rad_run_option(run, "ambient", run->options->ambient) != 0;
    state->row = rad_alloc(s->ctx, s->element_count, sizeof *state->row);
    state->patch_power = rad_alloc(s->ctx, s->patch_count, sizeof *state->patch_power);
    state->chunk_unshot = rad_alloc(s->ctx, chunk_count(s) + 1, sizeof *state->chunk_unshot);
    if (!state->row || !state->patch_power || !state->chunk_unshot) return RAD_ERROR_NO_MEMORY;
    for (size_t e = 0; e < s->element_count; ++e) {
        state->total_area += s->area[e];
        for (int c = 0; c < 3; ++c) {
            state->emitted_power += s->emission[e][c] * s->area[e];
            state->mean_reflectance[c] += s->reflectance[e][c] * s->area[e];
        }
    }
    for (int c = 0; c < 3; ++c) state->mean_reflectance[c] /= state->total_area;
    /* A resumed run starts from whatever is unshot now. */
    pass(run, state, NULL, NULL);
    compute_ambient(state);
    if (state->with_ambient) memcpy(s->ambient, state->ambient, sizeof s->ambient);
    return RAD_OK;
}

void rad_shooting_end(rad_solver_run *run, rad_shooting *state) {
    rad_free(run->system->ctx, state->row);
    rad_free(run->system->ctx, state->patch_power);
    rad_free(run->system->ctx, state->chunk_unshot);
    state->row = NULL;
    state->patch_power = NULL;
    state->chunk_unshot = NULL;
}

rad_status rad_shooting_shoot(rad_solver_run *run, rad_shooting *state, size_t shooter,
                              const float *row) {
    rad_system *s = run->system;
    run->shooter_patch = (long)shooter;
    run->shooter_surface = (long)s->element_surface[s->patch_first[shooter]];

    /* Take its unshot radiosity; it keeps (1 - omega) of it, less the overshoot. */
    double shot[3], over[3] = {0, 0, 0};
    rad_system_patch_mean(s, (const rad_rgb *)s->unshot, shooter, shot);
    if (state->overshoot) {
        double reflectance[3];
        rad_system_patch_mean(s, (const rad_rgb *)s->reflectance, shooter, reflectance);
        for (int c = 0; c < 3; ++c) over[c] = reflectance[c] * state->ambient[c];
    }
    double omega = run->omega;
    for (size_t e = s->patch_first[shooter]; e < s->patch_first[shooter + 1]; ++e)
        for (int c = 0; c < 3; ++c) s->unshot[e][c] = (1 - omega) * s->unshot[e][c] - over[c];
    double power[3];
    for (int c = 0; c < 3; ++c) power[c] = (omega * shot[c] + over[c]) * s->patch_area[shooter];

    /* Distribute, and recount the unshot powers in the same pass. */
    if (!row) {
        rad_status status = s->ff->row(s->ff, shooter, state->row);
        if (status) return status;
        row = state->row;
    }
    pass(run, state, row, power);
    return RAD_OK;
}

double rad_shooting_finish(rad_solver_run *run, rad_shooting *state) {
    rad_system *s = run->system;
    /* Stopping measure: unshot power left as a fraction of the power emitted. */
    double left = 0;
    for (size_t p = 0; p < s->patch_count; ++p) left += fabs(state->patch_power[p]);
    double fraction = state->emitted_power > 0 ? left / state->emitted_power : 0;
    run->unshot_fraction = fraction;
    if (state->overshoot || state->with_ambient) compute_ambient(state);
    if (state->with_ambient) memcpy(s->ambient, state->ambient, sizeof s->ambient);
    return fraction;
}

/* ------------------------------------------------------------------------------------------- */
/* Plain shooting: the patch with the most unshot power goes next.                               */

/* A small system (up to ALL_ROWS_ENTRIES form factors) has the rows of every patch that can be
 * shot (emitting or reflecting) computed before the first shot, in a few parallel loops of many
 * rows (rad_ff_rows_run, one row a task), kept by the row cache while they fit: guessed eight at
 * a time, the Cornell box's (2,634 elements) woke the sleeping workers about 200 times, each
 * waking a wait of tens of microseconds on this project's virtual machines. The loops grow to
 * about ALL_ROWS_STEP seconds each, between them the progress callback is asked (Ctrl-C), and
 * after ALL_ROWS_SECONDS the rest come as they are shot (costly rows: Monte Carlo with many
 * samples). Not when an iteration count or a time budget cuts the run short. The same rows,
 * so the same solution. */
#define ALL_ROWS_ENTRIES (1 << 22)
#define ALL_ROWS_STEP 0.05
#define ALL_ROWS_SECONDS 0.5

static void prefetch_all(rad_solver_run *run) {
    rad_system *s = run->system;
    rad_ff_provider *ff = s->ff;
    if (!ff->prefetch || run->options->max_iterations > 0 || run->options->time_budget > 0 ||
        (double)s->patch_count * (double)s->element_count > ALL_ROWS_ENTRIES)
        return;
    size_t *patches = rad_alloc(s->ctx, s->patch_count + 1, sizeof *patches), count = 0;
    if (!patches) {
        rad_fail(s->ctx, RAD_OK, "%s", ""); /* the rows come as they are shot */
        return;
    }
    for (size_t p = 0; p < s->patch_count; ++p) {
        int lit = 0;
        for (size_t e = s->patch_first[p]; e < s->patch_first[p + 1] && !lit; ++e)
            for (int c = 0; c < 3; ++c) lit |= s->emission[e][c] > 0 || s->reflectance[e][c] > 0;
        if (lit) patches[count++] = p;
    }
    const double start = rad_seconds();
    size_t chunk = rad_ff_rows_ahead;
    for (size_t first = 0; first < count;) {
        size_t n = count - first < chunk ? count - first : chunk;
        /* A failure (out of memory) leaves the rows to come as they are shot. */
        if (ff->prefetch(ff, patches + first, n)) break;
        first += n;
        if (rad_progress(s->ctx, "form factors", (double)first, (double)count))
            break; /* cancelled: the solve's loop sees it at its first report */
        double elapsed = rad_seconds() - start;
        if (elapsed > ALL_ROWS_SECONDS) break;
        double rows = elapsed > 0 ? (double)first * ALL_ROWS_STEP / elapsed : 1e9;
        chunk = rows < rad_ff_rows_ahead ? rad_ff_rows_ahead : rows > 4096 ? 4096 : (size_t)rows;
    }
    rad_free(s->ctx, patches);
}

static rad_status shooting_begin(rad_solver_run *run) {
    rad_shooting *state = rad_alloc_zero(run->system->ctx, 1, sizeof *state);
    if (!state) return RAD_ERROR_NO_MEMORY;
    run->state = state;
    rad_status status = rad_shooting_begin(run, state);
    if (!status) prefetch_all(run);
    return status;
}

/* When the shooter's row is not kept yet, compute it together with those of the patches
 * likely to be shot next (the most unshot power after it, rows not kept), in one parallel loop:
 * a row alone keeps two threads only partly busy (each row wakes the workers, and its last
 * blocks run on one). Rows are the same whenever they are computed, so is the solution. */
static void prefetch_rows(rad_solver_run *run, rad_shooting *state, size_t shooter) {
    rad_system *s = run->system;
    rad_ff_provider *ff = s->ff;
    if (!ff->prefetch || !ff->holds || ff->holds(ff, shooter)) return;
    size_t next[rad_ff_rows_ahead];
    double power[rad_ff_rows_ahead];
    size_t count = 1;
    next[0] = shooter;
    for (size_t p = 0; p < s->patch_count; ++p) {
        double unshot = fabs(rad_shooting_patch_power(state, p));
        if (p == shooter || !(unshot > 0) ||
            (count == rad_ff_rows_ahead && unshot <= power[count - 1]) || ff->holds(ff, p))
            continue;
        /* Insert, keeping next[1 ..] by decreasing power. */
        size_t k = count < rad_ff_rows_ahead ? count++ : count - 1;
        while (k > 1 && power[k - 1] < unshot) {
            next[k] = next[k - 1];
            power[k] = power[k - 1];
            --k;
        }
        next[k] = p;
        power[k] = unshot;
    }
    ff->prefetch(ff, next, count); /* a failure leaves the row to be computed alone */
}

static rad_status shooting_step(rad_solver_run *run, int iteration, double *residual) {
    (void)iteration;
    rad_system *s = run->system;
    rad_shooting *state = run->state;
    if (state->emitted_power <= 0) {
        *residual = run->unshot_fraction = 0;
        return RAD_OK;
    }

    /* Pick the patch with the most unshot power (ties: the lowest index). */
    size_t shooter = 0;
    double best = -1;
    for (size_t p = 0; p < s->patch_count; ++p) {
        double power = fabs(rad_shooting_patch_power(state, p));
        if (power > best) {
            best = power;
            shooter = p;
        }
    }
    prefetch_rows(run, state, shooter);
    rad_status status = rad_shooting_shoot(run, state, shooter, NULL);
    if (status) return status;
    *residual = rad_shooting_finish(run, state);
    return RAD_OK;
}

static void shooting_end(rad_solver_run *run) {
    rad_shooting *state = run->state;
    if (!state) return;
    rad_shooting_end(run, state);
    rad_free(run->system->ctx, state);
    run->state = NULL;
}

static const rad_method_option shooting_options[] = {
    {"overshoot", "overshooting (Feda & Purgathofer 1992)"},
    {"ambient", "add the ambient term"},
};
static const rad_solver_variant shooting_variants[] = {
    {"shooting", 0, 0},
    {"overshooting", 0, 1},
};

const rad_solver_impl rad_solver_shooting = {
    {"shooting", "progressive refinement: shoot the most unshot power (Cohen et al. 1988)",
     RAD_SOLVER_SHOOTS | RAD_SOLVER_ITERATIVE | RAD_SOLVER_KEEPS_UNSHOT | RAD_SOLVER_NEEDS_UNSHOT,
     shooting_options, 2, shooting_variants, 2, 0},
    shooting_begin, shooting_step, shooting_end,
};
