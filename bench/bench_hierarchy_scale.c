/* bench_hierarchy_scale.c - the hierarchical solver's cost against scene size: generated offices
 * (rad_scene_generate_office) of 10^4 and 10^5 triangles (and 10^6 when asked), each solved as
 * `radiosity solve office.obj --solver hierarchical` does (one element per polygon, default link
 * error). Prints a Markdown table: faces, links, leaves, processor and wall seconds of the
 * system build and solve, the process's peak resident memory so far (sizes run smallest first,
 * so each row's peak is its own), and the growth from the row above against n log n.
 * Timings only: nothing here passes or fails.
 * Usage: bench_hierarchy_scale [LARGEST_TRIANGLES (100000)] */
#include "radiosity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

static double seconds(clockid_t clock) {
    struct timespec t;
    clock_gettime(clock, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The solver's last step line: "hierarchical step N: L links (...), V leaves, ...". */
typedef struct step_line {
    size_t links, leaves;
} step_line;

static void on_log(void *user, rad_log_level level, const char *message) {
    (void)level;
    step_line *last = user;
    const char *at = strstr(message, "hierarchical step ");
    const char *colon = at ? strchr(at, ':') : NULL;
    const char *leaves = colon ? strstr(colon, " links (") : NULL;
    leaves = leaves ? strstr(leaves, "), ") : NULL;
    if (!colon || !leaves) return;
    last->links = strtoull(colon + 1, NULL, 10);
    last->leaves = strtoull(leaves + 3, NULL, 10);
}

int main(int argc, char **argv) {
    size_t largest = argc > 1 ? strtoull(argv[1], NULL, 10) : 100000;
    step_line last = {0, 0};
    rad_context_options co = {0};
    co.log = on_log;
    co.log_user = &last;
    rad_context *ctx = NULL;
    if (rad_context_create(&co, &ctx)) return 1;
    printf("| triangles asked | faces | links | leaves | steps | processor s | wall s | peak MB "
           "| bytes per link (peak) | x links | x processor | x n log n |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    double previous_cpu = 0, previous_n = 0;
    size_t previous_links = 0;
    for (size_t triangles = 10000; triangles <= largest; triangles *= 10) {
        rad_scene *scene = NULL;
        if (rad_scene_generate_office(ctx, triangles, &scene)) {
            fprintf(stderr, "%s\n", rad_context_error(ctx));
            return 1;
        }
        double cpu0 = seconds(CLOCK_PROCESS_CPUTIME_ID), wall0 = seconds(CLOCK_MONOTONIC);
        rad_mesh_options mesh = {0};
        mesh.polygons_only = 1;
        rad_system *system = NULL;
        rad_solve_options solve = {0};
        solve.solver = RAD_SOLVER_HIERARCHICAL;
        rad_solve_report report;
        if (rad_system_create(ctx, scene, &mesh, NULL, &system) ||
            rad_solve(system, &solve, &report)) {
            fprintf(stderr, "%s\n", rad_context_error(ctx));
            return 1;
        }
        double cpu = seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu0, wall = seconds(CLOCK_MONOTONIC) - wall0;
        struct rusage usage;
        getrusage(RUSAGE_SELF, &usage);
        double peak = (double)usage.ru_maxrss * 1024.0; /* kilobytes on Linux */
        size_t faces = rad_system_element_count(system);
        printf("| %zu | %zu | %zu | %zu | %d | %.1f | %.1f | %.0f | %.0f |", triangles, faces,
               last.links, last.leaves, report.iterations, cpu, wall, peak / 1e6,
               last.links ? peak / (double)last.links : 0);
        if (previous_links)
            printf(" %.1f | %.1f | %.1f |\n", (double)last.links / (double)previous_links,
                   cpu / previous_cpu,
                   (double)faces * log((double)faces) / (previous_n * log(previous_n)));
        else
            printf(" | | |\n");
        fflush(stdout);
        previous_cpu = cpu;
        previous_n = (double)faces;
        previous_links = last.links;
        rad_system_destroy(system);
        rad_scene_destroy(scene);
    }
    rad_context_destroy(ctx);
    return 0;
}
