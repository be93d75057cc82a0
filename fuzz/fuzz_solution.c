/* fuzz_solution.c - libFuzzer target for saved solution files (src/io/solution.c,
 * rad_system_load_solution) into the four-walls system, then a resumed shooting step; when the
 * first input byte has bit 2 set, into two-squares built for the hierarchy (one element per
 * polygon), then resumed hierarchical steps (src/io/solution_hier.c, version 3 files).
 *
 * The file ends with a checksum, which random mutations almost never keep. So when the first
 * input byte is odd the target rewrites the checksum of the rest before loading, and mutations
 * reach the fields behind it; when it is even the bytes are loaded as they are. Either way the
 * rest of the input is written to a temporary file, since the loader takes a path. */
#include "input_file.h"
#include "io/solution.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Huge radiosities also make the gathering rounds run to their cap of 1000 (each round shrinks
 * them by the reflectance only): the solve is cancelled, as Ctrl-C would, after this many
 * progress reports (a count, so the same for every run). */
#define PROGRESS_REPORTS 32

static int stop_after_reports(void *user, const char *phase, double done, double total) {
    (void)phase;
    (void)done;
    (void)total;
    int *reports = user;
    return ++*reports > PROGRESS_REPORTS;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    size_t length = size - 1;
    uint8_t *bytes = malloc(length ? length : 1);
    if (!bytes) return 0;
    memcpy(bytes, data + 1, length);
    if ((data[0] & 1) && length >= 8) {
        uint64_t checksum = rad_fnv1a(RAD_FNV1A_START, bytes, length - 8);
        for (int k = 0; k < 8; ++k) bytes[length - 8 + k] = (uint8_t)(checksum >> (8 * k));
    }
    const char *path = fuzz_write_input("sol", bytes, length);
    free(bytes);

    rad_context_options options = {0};
    options.threads = 1;
    /* A file whose radiosities are huge (checksum fixed) makes the oracle split every link down
     * to the memory budget in the first step: 64 MiB took 0.65 s in a release build and over
     * 10 s under ASan on a loaded machine (libFuzzer's timeout, CI 2026-12-04). 8 MiB still
     * holds the seed solutions' links (17) and bounds that case at an eighth of the work. */
    options.max_memory = 8u << 20;
    int reports = 0;
    options.progress = stop_after_reports;
    options.progress_user = &reports;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return 0;
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    int hierarchy = (data[0] & 2) != 0;
    rad_mesh_options mesh = {0};
    mesh.polygons_only = hierarchy;
    if (rad_scene_builtin(ctx, hierarchy ? "two-squares" : "four-walls", &scene) == RAD_OK &&
        rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_OK) {
        rad_solution_info info;
        if (rad_system_load_solution(system, path, &info) == RAD_OK) {
            /* What was loaded must be usable: go on from it for a few shots or steps. */
            rad_solve_options solve = {0};
            solve.solver = hierarchy ? RAD_SOLVER_HIERARCHICAL : RAD_SOLVER_SHOOTING;
            solve.max_iterations = 3;
            solve.resume = 1;
            rad_solve(system, &solve, NULL);
        }
    }
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return 0;
}
