/* solve.c - the solver driver: picks the solver, runs its steps until the stopping measure
 * falls under the tolerance or the iterations run out, and reports each step to the trace. */
#include "solve/solver.h"

#include <math.h>
#include <string.h>

#define RAD_DEFAULT_TOLERANCE 1e-6
#define RAD_GATHER_ROUND_CAP 100000

static const rad_solver_impl *const solvers[] = {
    &rad_solver_direct, &rad_solver_jacobi, &rad_solver_gauss_seidel, &rad_solver_shooting,
};
#define SOLVER_COUNT (sizeof solvers / sizeof solvers[0])

int rad_solver_kind_parse(const char *name) {
    if (!name) return -1;
    for (size_t i = 0; i < SOLVER_COUNT; ++i)
        if (strcmp(solvers[i]->name, name) == 0) return (int)solvers[i]->kind;
    return -1;
}

const char *rad_solver_kind_name(rad_solver_kind kind) {
    for (size_t i = 0; i < SOLVER_COUNT; ++i)
        if (solvers[i]->kind == kind) return solvers[i]->name;
    return "unknown";
}

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

rad_status rad_solve(rad_system *system, const rad_solve_options *options,
                     rad_solve_report *report) {
    if (!system || !options) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = system->ctx;
    const rad_solver_impl *impl = NULL;
    for (size_t i = 0; i < SOLVER_COUNT; ++i)
        if (solvers[i]->kind == options->solver) impl = solvers[i];
    if (!impl) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "unknown solver %d", options->solver);
    if (options->max_iterations < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "iterations must not be negative");
    if (options->tolerance < 0 || !isfinite(options->tolerance))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "tolerance must be a finite number >= 0");
    double omega = options->omega == 0 ? 1.0 : options->omega;
    if (!(omega > 0 && omega < 2))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "omega must be in (0, 2), not %g", omega);

    double start = rad_seconds();
    rad_solve_report local = {0};
    rad_solver_run run = {system, options, omega, options->trace != NULL, NULL, NULL, -1, NULL};
    rad_system_reset(system);
    rad_status status = RAD_OK;
    if (run.tracing) {
        run.received = rad_alloc_zero(ctx, system->element_count, sizeof *run.received);
        run.reflected = rad_alloc_zero(ctx, system->element_count, sizeof *run.reflected);
        if (!run.received || !run.reflected) status = RAD_ERROR_NO_MEMORY;
    }
    if (!status) status = impl->begin(&run);
    if (!status) {
        double tolerance = options->tolerance > 0 ? options->tolerance : RAD_DEFAULT_TOLERANCE;
        int cap = options->max_iterations;
        if (cap == 0) {
            double shots = 1000.0 * (double)system->patch_count;
            cap = impl->default_is_power ? (int)fmin(shots, 1e8) : RAD_GATHER_ROUND_CAP;
        }
        if (!impl->iterative) cap = 1;
        double residual = INFINITY;
        for (int iteration = 1; iteration <= cap; ++iteration) {
            status = impl->step(&run, iteration, &residual);
            if (status) break;
            local.iterations = iteration;
            if (run.tracing && (status = emit_trace(&run, iteration, impl->default_is_power)))
                break;
            if (residual <= tolerance || !impl->iterative) {
                local.converged = 1;
                break;
            }
            if (rad_progress(ctx, impl->name, (double)iteration, (double)cap)) {
                status = rad_fail(ctx, RAD_ERROR_CANCELLED, "cancelled after %d iterations",
                                  iteration);
                break;
            }
        }
        local.residual = residual;
        impl->end(&run);
    }
    rad_free(ctx, run.received);
    rad_free(ctx, run.reflected);
    local.seconds = rad_seconds() - start;
    if (report) *report = local;
    return status;
}
