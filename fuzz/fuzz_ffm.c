/* fuzz_ffm.c - libFuzzer target for the patch-system parser (rad_scene_parse_ffm), and for what
 * a parsed system goes through next: rad_system_create and a few steps of every solver. */
#include "radiosity.h"

#include <stdint.h>
#include <stdio.h>

/* Bounds each input's work: a few rounds or shots, a small memory budget. */
#define FUZZ_MAX_ITERATIONS 4
#define FUZZ_MAX_MEMORY (64u << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    rad_context_options options = {0};
    options.threads = 1;
    options.max_memory = FUZZ_MAX_MEMORY;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return 0;
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    if (rad_scene_parse_ffm(ctx, (const char *)data, size, "fuzz.ffm", &scene) == RAD_OK &&
        rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK) {
        static const rad_solver_kind kinds[] = {RAD_SOLVER_DIRECT, RAD_SOLVER_JACOBI,
                                                RAD_SOLVER_GAUSS_SEIDEL, RAD_SOLVER_SHOOTING};
        for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
            rad_solve_options solve = {0};
            solve.solver = kinds[k];
            solve.max_iterations = FUZZ_MAX_ITERATIONS;
            rad_solve_report report;
            rad_solve(system, &solve, &report);
        }
        for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
            rad_surface_info info;
            rad_system_surface(system, i, &info);
        }
    }
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return 0;
}
