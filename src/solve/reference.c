/* reference.c - a converged reference solution and the error of a solution against it: what
 * `radiosity solve --compare-solvers` measures every solver with (docs/solvers.md, "Comparing
 * the solvers"). */
#include "solve/solver.h"

#include <math.h>

rad_status rad_system_solve_reference(rad_system *system, double *reference,
                                      rad_solver_kind *used, double *tolerance) {
    if (!system || !reference) return RAD_ERROR_INVALID_ARGUMENT;
    rad_solve_options options = {0};
    options.solver = RAD_SOLVER_GAUSS_SEIDEL;
    options.tolerance = 1e-10;
    rad_status status = rad_solve(system, &options, NULL);
    if (status == RAD_ERROR_MEMORY_BUDGET) {
        options.solver = RAD_SOLVER_SHOOTING;
        status = rad_solve(system, &options, NULL);
    }
    if (used) *used = options.solver;
    if (tolerance) *tolerance = options.tolerance;
    if (status) return status;
    for (size_t e = 0; e < system->element_count; ++e)
        for (int c = 0; c < 3; ++c) reference[3 * e + c] = system->radiosity[e][c];
    return RAD_OK;
}

double rad_system_solution_error(const rad_system *system, const double *reference,
                                 const double *weights) {
    if (!system || !reference) return NAN;
    double error = 0, norm = 0;
    for (size_t e = 0; e < system->element_count; ++e) {
        const double *b = system->radiosity[e], *r = reference + 3 * e;
        double weight = weights ? weights[e] : rad_system_element_area(system, e);
        error += weight * (fabs(b[0] - r[0]) + fabs(b[1] - r[1]) + fabs(b[2] - r[2]));
        norm += weight * (fabs(r[0]) + fabs(r[1]) + fabs(r[2]));
    }
    if (weights) return norm > 0 ? error / norm : NAN;
    return norm > 0 ? error / norm : 0;
}
