/* solve.c - the solver driver: picks the solver, runs its steps until the stopping measure
 * falls under the tolerance, the iterations or the time budget run out or the caller asks to
 * stop, and reports each step to the trace and the iteration callback. One loop serves every
 * solver; starting from B = E or resuming from the system's state is decided here. */
#include "solve/solver.h"

#include "system/solution_view.h"

#include <math.h>
#include <string.h>

#define RAD_DEFAULT_TOLERANCE 1e-6
#define RAD_GATHER_ROUND_CAP 100000

/* Per-surface means of the step's per-element values, handed to the trace callback. */
static rad_status emit_trace(rad_solver_run *run, int iteration, int shooting) {
    rad_system *s = run->system;
    size_t n = s->surface_count;
    rad_rgb *table = rad_alloc(s->ctx, 4 * n, sizeof *table);
    if (!table) return RAD_ERROR_NO_MEMORY;
    rad_system_surface_means(s, (const rad_rgb *)run->received, table);
    rad_system_surface_means(s, (const rad_rgb *)run->reflected, table + n);
    rad_system_surface_means(s, (const rad_rgb *)s->radiosity, table + 2 * n);
    rad_system_surface_means(s, (const rad_rgb *)s->unshot, table + 3 * n);
    rad_trace_event event = {
        .iteration = iteration,
        .shooter = shooting ? run->shooter_surface : -1,
        .surface_count = n,
        .received = (const double(*)[3])table,
        .reflected = shooting ? (const double(*)[3])(table + n) : NULL,
        .radiosity = (const double(*)[3])(table + 2 * n),
        .unshot = shooting ? (const double(*)[3])(table + 3 * n) : NULL,
    };
    run->options->trace(run->options->trace_user, &event);
    rad_free(s->ctx, table);
    return RAD_OK;
}

/* The iteration callback's view of the step just done. Returns nonzero when it asks to stop;
 * the time it takes is added to *callback_seconds so that reported times are the solver's. */
static int emit_iteration(const rad_solver_run *run, const rad_solver_impl *impl, int iteration,
                          double residual, double start, double *callback_seconds) {
    const rad_solve_options *o = run->options;
    double now = rad_seconds();
    int shooting = (impl->info.capabilities & RAD_SOLVER_SHOOTS) != 0;
    rad_iteration_event event = {
        .iteration = iteration,
        .seconds = now - start - *callback_seconds,
        .shots = shooting ? iteration : 0,
        .rounds = shooting ? 0 : iteration,
        .unshot_fraction = shooting ? run->unshot_fraction : NAN,
        .residual = residual,
        .shooter = shooting ? run->shooter_patch : -1,
        .links = run->links,
        .leaves = run->leaves,
        .largest_error = run->largest_error,
    };
    int stop = o->on_iteration(o->iteration_user, &event);
    *callback_seconds += rad_seconds() - now;
    return stop;
}

/* The time budget inside a step. A hierarchy's step is long (the first refinement of the 10^5
 * office: about 10 processor-s) and stops cleanly when the progress callback asks, keeping what
 * it did as for Ctrl-C; past the budget the callback asks, and the loop below then stops for
 * the budget. Other solvers' steps (a shot, a round) are short and are not asked. */
typedef struct step_deadline {
    rad_progress_fn progress; /* the caller's, asked until the deadline */
    void *user;
    double end;
} step_deadline;

static int deadline_progress(void *user, const char *phase, double done, double total) {
    const step_deadline *d = user;
    if (rad_seconds() >= d->end) return 1;
    return d->progress ? d->progress(d->user, phase, done, total) : 0;
}

rad_status rad_solve(rad_system *system, const rad_solve_options *options,
                     rad_solve_report *report) {
    if (!system || !options) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = system->ctx;
    const rad_solver_impl *impl = rad_solver_impl_get(options->solver);
    if (!impl) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "unknown solver %d", options->solver);
    if (options->max_iterations < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "iterations must not be negative");
    if (options->tolerance < 0 || !isfinite(options->tolerance))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "tolerance must be a finite number >= 0");
    if (options->time_budget < 0 || !isfinite(options->time_budget))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "time budget must be a positive number of seconds, not %g",
                        options->time_budget);
    double omega = options->omega == 0 ? 1.0 : options->omega;
    if (!(omega > 0 && omega < 2))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "omega must be in (0, 2), not %g", omega);
    /* The solver's own options: only the names it registered. */
    rad_status checked = rad_options_check(ctx, options->method_options, impl->info.options,
                                           impl->info.option_count, "solver", impl->info.name);
    if (checked) return checked;
    /* A system built with one element per polygon (rad_mesh_options.polygons_only) has no
     * form factors: only a solver that computes its own can run on it. */
    if (!system->ff && !(impl->info.capabilities & RAD_SOLVER_OWN_LEAVES))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the %s solver needs form factors; this system was built with one "
                        "element per polygon (polygons_only) for a solver that draws its own "
                        "leaves", impl->info.name);
    /* A solver that still reads its option from the shared struct gets the bag's value there
     * (the hierarchical solver's link_error, until it reads "link-error" itself). */
    rad_solve_options resolved = *options;
    resolved.link_error = rad_options_number(options->method_options, "link-error",
                                             options->link_error);
    options = &resolved;

    double start = rad_seconds(), callback_seconds = 0;
    rad_solve_report local = {0};
    local.stop = RAD_STOP_ERROR;
    local.unshot_fraction = NAN;
    rad_solver_run run = {0};
    run.system = system;
    run.options = options;
    run.omega = omega;
    run.tracing = options->trace != NULL;
    run.shooter_surface = run.shooter_patch = -1;
    run.unshot_fraction = NAN;
    run.largest_error = NAN;
    if (!options->resume) {
        rad_system_remove_specular_reflection(system); /* a previous solve's: added again below */
        rad_system_reset(system);
    }
    /* A solver on the elements is drawn by them, not by the leaves of a hierarchy solved (or
     * loaded) before; going on from a hierarchy starts from its values on the elements. */
    if (!(impl->info.capabilities & RAD_SOLVER_OWN_LEAVES) &&
        rad_system_view(system)->ops != &rad_uniform_view_ops)
        rad_system_set_view(system, &rad_uniform_view_ops, system);
    rad_status status = RAD_OK;
    if (run.tracing) {
        run.received = rad_alloc_zero(ctx, system->element_count, sizeof *run.received);
        run.reflected = rad_alloc_zero(ctx, system->element_count, sizeof *run.reflected);
        if (!run.received || !run.reflected) status = RAD_ERROR_NO_MEMORY;
    }
    int begun = 0;
    if (!status) {
        begun = 1;
        status = impl->begin(&run);
    }
    const int shooting = (impl->info.capabilities & RAD_SOLVER_SHOOTS) != 0;
    const int iterative = (impl->info.capabilities & RAD_SOLVER_ITERATIVE) != 0;
    if (!status) {
        double tolerance = options->tolerance > 0 ? options->tolerance : RAD_DEFAULT_TOLERANCE;
        int cap = options->max_iterations;
        if (cap == 0) {
            double shots = 1000.0 * (double)system->patch_count;
            cap = shooting ? (int)fmin(shots, 1e8) : RAD_GATHER_ROUND_CAP;
        }
        if (!iterative) cap = 1;
        double residual = INFINITY;
        local.stop = RAD_STOP_ITERATIONS;
        /* One loop for every solver: step, report, then decide whether to go on. */
        int step_budget = options->time_budget > 0 &&
                          (impl->info.capabilities & RAD_SOLVER_OWN_LEAVES);
        step_deadline deadline = {ctx->progress, ctx->progress_user, start + options->time_budget};
        for (int iteration = 1; iteration <= cap; ++iteration) {
            if (step_budget) {
                ctx->progress = deadline_progress;
                ctx->progress_user = &deadline;
            }
            status = impl->step(&run, iteration, &residual);
            ctx->progress = deadline.progress;
            ctx->progress_user = deadline.user;
            if (status) break;
            local.iterations = iteration;
            if (run.tracing && (status = emit_trace(&run, iteration, shooting)))
                break;
            int asked_to_stop = options->on_iteration &&
                emit_iteration(&run, impl, iteration, residual, start, &callback_seconds);
            if (run.own_stop == RAD_STOP_MEMORY_BUDGET) {
                local.stop = run.own_stop;
                break;
            }
            if (run.own_measure ? run.own_converged : residual <= tolerance || !iterative) {
                local.converged = 1;
                local.stop = run.own_stop == RAD_STOP_TAIL ? RAD_STOP_TAIL : RAD_STOP_CONVERGED;
                break;
            }
            if (asked_to_stop) {
                local.stop = RAD_STOP_CALLBACK;
                break;
            }
            if (options->time_budget > 0 && rad_seconds() - start >= options->time_budget) {
                local.stop = RAD_STOP_TIME_BUDGET;
                break;
            }
            /* The iteration callback, when there is one, replaces the progress reports of
             * the loop: it sees more and can stop the solve itself. */
            if (!options->on_iteration &&
                rad_progress(ctx, impl->info.name, (double)iteration, (double)cap)) {
                status = rad_fail(ctx, RAD_ERROR_CANCELLED, "cancelled after %d iterations",
                                  iteration);
                break;
            }
        }
        local.residual = residual;
    }
    /* End also after a failed begin: it frees whatever begin got as far as allocating. */
    if (begun) impl->end(&run);
    if (status) local.stop = RAD_STOP_ERROR;
    local.unshot_fraction = run.unshot_fraction;
    local.importance_shots = run.importance_shots;
    local.links = run.links;
    local.leaves = run.leaves;
    local.largest_error = run.largest_error;
    rad_free(ctx, run.received);
    rad_free(ctx, run.reflected);
    local.seconds = rad_seconds() - start - callback_seconds;
    /* The specular-first pass's second half (docs/specular-first.md): the solved radiosity of
     * the diffuse elements through mirrors and glass onto diffuse elements, which the form
     * factors leave out; added as unshot light, then the solve resumes to spread it. A
     * resumed solve does it too when it knows whether it was done: a hierarchy's solution file
     * keeps that light (RAD_SOLVER_OWN_LEAVES), an element file does not. */
    int pass_known = !options->resume || (impl->info.capabilities & RAD_SOLVER_OWN_LEAVES);
    if (!status && local.converged && pass_known &&
        system->specular_emission && !system->specular_reflection) {
        status = rad_system_add_specular_reflection(system);
        rad_solve_report second = {0};
        rad_solve_options resumed = *options;
        resumed.resume = 1;
        if (options->time_budget > 0) /* what is left of it */
            resumed.time_budget = fmax(options->time_budget - (rad_seconds() - start), 1e-3);
        if (!status && system->specular_reflection) {
            status = rad_solve(system, &resumed, &second);
            local.iterations += second.iterations;
            local.seconds += second.seconds;
            local.stop = second.stop;
            local.converged = second.converged;
            local.residual = second.residual;
            local.unshot_fraction = second.unshot_fraction;
            local.links = second.links;
            local.leaves = second.leaves;
            local.largest_error = second.largest_error;
        }
        if (status) local.stop = RAD_STOP_ERROR;
    }
    if (report) *report = local;
    return status;
}
