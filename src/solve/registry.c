/* registry.c - the list of solvers. Each solver is one file defining rad_solver_<name> (its
 * name, description, capabilities, own options and steps, solver.h) and one line here. A
 * solver's kind is its position in the list plus one (zero is RAD_SOLVER_DEFAULT), and that
 * position is also what solution files store: append new solvers at the end. */
#include "solve/solver.h"

#include "scene/scene.h"

#include <string.h>

#define RAD_SOLVERS(X) X(direct) X(jacobi) X(gauss_seidel) X(shooting) X(importance) \
    X(hierarchical)

#define RAD_SOLVER_DECLARE(name) extern const rad_solver_impl rad_solver_##name;
RAD_SOLVERS(RAD_SOLVER_DECLARE)
#define RAD_SOLVER_LIST(name) &rad_solver_##name,
static const rad_solver_impl *const solvers[] = {RAD_SOLVERS(RAD_SOLVER_LIST)};
#define SOLVER_COUNT (sizeof solvers / sizeof solvers[0])

/* What a zeroed rad_solve_options runs. */
#define DEFAULT_SOLVER RAD_SOLVER_SHOOTING

const rad_solver_impl *rad_solver_impl_get(rad_solver_kind kind) {
    if (kind == RAD_SOLVER_DEFAULT) kind = DEFAULT_SOLVER;
    if ((int)kind < 1 || (size_t)kind > SOLVER_COUNT) return NULL;
    return solvers[kind - 1];
}

size_t rad_solver_count(void) { return SOLVER_COUNT; }

const rad_solver_info *rad_solver_at(size_t index) {
    return index < SOLVER_COUNT ? &solvers[index]->info : NULL;
}

const rad_solver_info *rad_solver_get(rad_solver_kind kind) {
    const rad_solver_impl *impl = rad_solver_impl_get(kind);
    return impl ? &impl->info : NULL;
}

int rad_solver_can_resume(rad_solver_kind solver, rad_solver_kind saved_by) {
    const rad_solver_info *to = rad_solver_get(solver), *from = rad_solver_get(saved_by);
    if (!to || !from) return 0;
    return !(to->capabilities & RAD_SOLVER_NEEDS_UNSHOT) ||
           (from->capabilities & RAD_SOLVER_KEEPS_UNSHOT);
}

int rad_solver_kind_parse(const char *name) {
    if (!name) return -1;
    for (size_t i = 0; i < SOLVER_COUNT; ++i)
        if (strcmp(solvers[i]->info.name, name) == 0) return (int)i + 1;
    return -1;
}

rad_solver_kind rad_scene_default_solver(const rad_scene *scene) {
    if (scene && scene->geometric && scene->polygon_count >= RAD_HIERARCHY_DEFAULT_POLYGONS)
        return RAD_SOLVER_HIERARCHICAL;
    return RAD_SOLVER_SHOOTING;
}

const char *rad_solver_kind_name(rad_solver_kind kind) {
    const rad_solver_impl *impl = rad_solver_impl_get(kind);
    return impl ? impl->info.name : "unknown";
}

uint32_t rad_solver_file_code(rad_solver_kind kind) {
    if (kind == RAD_SOLVER_DEFAULT) kind = DEFAULT_SOLVER;
    return (int)kind >= 1 ? (uint32_t)kind - 1u : 0u;
}

int rad_solver_from_file_code(uint32_t code) {
    return code < SOLVER_COUNT ? (int)code + 1 : -1;
}
