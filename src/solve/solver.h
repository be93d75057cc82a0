/* solver.h - the internal shape of a solver: its registration (name, description,
 * capabilities, own options), begin, one step (a gathering round or a shot), end. The driver
 * in solve.c owns the loop, stopping, cancelling, timing and tracing, so a new solver is one
 * new file defining rad_solver_<name> plus one line in RAD_SOLVERS (registry.c). */
#ifndef RAD_SOLVE_SOLVER_H
#define RAD_SOLVE_SOLVER_H

#include "core/options.h"
#include "system/system.h"

typedef struct rad_solver_run {
    rad_system *system;
    const rad_solve_options *options;
    double omega;
    int tracing;
    /* Per-element scratch for the trace: what each element received and reflected. */
    rad_rgb *received;
    rad_rgb *reflected;
    long shooter_surface; /* set by shooting steps */
    long shooter_patch;   /* set by shooting steps */
    double unshot_fraction; /* set by shooting steps: unshot power / emitted power */
    int importance_shots;   /* set by the importance solver's begin */
    void *state;          /* the solver's own */
    /* Set by a step after which the solver itself ends the solve: RAD_STOP_MEMORY_BUDGET (it
     * cannot go on within the memory budget, not converged) or RAD_STOP_TAIL (its own rule
     * ends the solve converged, the hierarchical tail rule); zero (RAD_STOP_CONVERGED) leaves
     * it to the measure, or to own_converged. */
    rad_solve_stop own_stop;
    /* Set by begin when the solver judges its own convergence (the hierarchy: its residual is
     * the oracle's error in the units of its link error, which need not be the tolerance):
     * the driver then ends the solve as converged when a step sets own_converged, and does
     * not compare the residual with the tolerance. */
    int own_measure, own_converged;
    size_t links, leaves;      /* set by hierarchical steps (rad_iteration_event) */
    double largest_error;      /* set by hierarchical steps; NaN otherwise */
} rad_solver_run;

/* The number the solver's own option `name` is set to in the caller's option bag
 * (rad_solve_options.method_options, checked by the driver against the solver's registered
 * options), else `fallback`: the older per-solver field of rad_solve_options. */
static inline double rad_run_option(const rad_solver_run *run, const char *name, double fallback) {
    return rad_options_number(run->options->method_options, name, fallback);
}

typedef struct rad_solver_impl {
    rad_solver_info info; /* what the public registry shows (rad_solver_at) */
    rad_status (*begin)(rad_solver_run *run);
    /* One round or shot; *residual is the stopping measure after it. */
    rad_status (*step)(rad_solver_run *run, int iteration, double *residual);
    void (*end)(rad_solver_run *run);
} rad_solver_impl;

/* The registered solver of a kind (RAD_SOLVER_DEFAULT: the default's), or NULL (registry.c). */
const rad_solver_impl *rad_solver_impl_get(rad_solver_kind kind);

/* The number a solution file stores for a solver, and back (-1 when unknown): its position in
 * the registry, which never changes for a registered solver. */
uint32_t rad_solver_file_code(rad_solver_kind kind);
int rad_solver_from_file_code(uint32_t code);

/* The gathering matrix, stored in float32 when it fits the memory budget:
 * G[e * patch_count + p] = A_p F_pe / A_e, so that element e gathers sum_p G_ep B_p. */
rad_status rad_gather_matrix(rad_system *system, float **out);

/* Largest |B| over elements and channels (at least a tiny positive number). */
double rad_max_radiosity(const rad_system *system);

/* The image size importance is computed at (importance.c, and the hierarchical solver's
 * --importance): the caller's view_width x view_height (256 x 256 when unset), scaled to at
 * most 256 pixels a side. */
void rad_importance_view_size(const rad_solve_options *options, int *width, int *height);

#endif
