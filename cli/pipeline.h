/* pipeline.h - what commands that mesh and solve a scene before using it (solve, render) share:
 * the solver, form-factor and meshing options, their checks, and the load-build-solve steps,
 * timed for --stats. */
#ifndef RAD_CLI_PIPELINE_H
#define RAD_CLI_PIPELINE_H

#include "cli.h"

typedef struct cli_pipeline_args {
    const char *solver, *ff, *link_error;
    int iterations, ambient, threads, quiet, ff_samples, hemicube_res;
    double tolerance, omega, max_memory, patch_size, element_size;
    size_t elements;
    size_t seed;
    int importance; /* --importance: the hierarchical solver weighs links by the camera's view */
    int discontinuity; /* --discontinuity 1: cut at shadow boundaries too (D1/D2) */
    int final_gather;  /* render: gather rays per sample (0: none), for the solvers that choose
                          their defaults by it (the hierarchy's link error on small scenes) */
    /* --solver was not given (cli_pipeline_check sets it when `solver` is NULL): the solver is
     * the scene's default (rad_scene_default_solver, cli_pipeline_default_solver). */
    int solver_default;
    /* Filled by cli_pipeline_check: the chosen solver's and form-factor method's own options,
     * which the option structs it writes point to. */
    rad_options solver_options, ff_options;
} cli_pipeline_args;

/* How many entries cli_pipeline_options writes. */
#define CLI_PIPELINE_OPTION_COUNT 18

/* Writes the shared options (--solver ... --quiet) into `options`, which must have room for
 * CLI_PIPELINE_OPTION_COUNT entries; `default_solver` is the solver shown as the default. */
void cli_pipeline_options(cli_pipeline_args *args, rad_solver_kind default_solver,
                          cli_option *options);

/* The entries a command's whole option table needs: its own array `own` (a true array, not a
 * pointer), the shared ones and the terminator. */
#define CLI_PIPELINE_TABLE_SIZE(own) (sizeof(own) / sizeof((own)[0]) + CLI_PIPELINE_OPTION_COUNT + 1)

/* Fills `table` (CLI_PIPELINE_TABLE_SIZE entries) with the command's `own_count` options and the
 * shared ones, the shared first when `shared_first`, then the terminator. The table is sized
 * from the arrays themselves, so adding an option to a command needs no count kept by hand. */
void cli_pipeline_table(cli_option *table, const cli_option *own, size_t own_count,
                        int shared_first, cli_pipeline_args *args,
                        rad_solver_kind default_solver);

/* The value checks of cli_pipeline_check alone (sizes, budget, --tolerance, --omega): a usage
 * error (EXIT_USAGE, message printed) or 0. */
int cli_pipeline_check_values(const char *command, const cli_pipeline_args *args);

/* The library's option structs from the arguments, checked. Prints a usage error and returns
 * EXIT_USAGE, or 0. */
int cli_pipeline_check(const char *command, cli_pipeline_args *args, rad_solve_options *solve,
                       rad_mesh_options *mesh, rad_ff_options *ff);

/* --link-error, checked (a positive number; zero when not given). Prints a usage error and
 * returns EXIT_USAGE, or 0. */
int cli_pipeline_link_error(const char *command, const cli_pipeline_args *args, double *out);

/* The solver that runs with --importance (`importance` nonzero) in place of `kind`: the same
 * when it takes the option (the hierarchy: links refined where the view needs them) or needs a
 * camera anyway (the importance solver); the importance solver for shooting (shots ordered by
 * what the view sees); -1 when the solver has no use for a camera. `kind` without --importance. */
int cli_pipeline_importance_solver(rad_solver_kind kind, int importance);

/* "--importance is for the hierarchical, shooting and importance solvers, not KIND": a usage
 * error (EXIT_USAGE, printed). */
int cli_importance_error(const char *command, rad_solver_kind kind);

/* When --solver was not given, the scene's default solver (rad_scene_default_solver:
 * hierarchical for a geometric scene of RAD_HIERARCHY_DEFAULT_POLYGONS polygons or more) in
 * place of shooting: `solve` and `mesh` are changed to it (with a note on stderr), so that solve,
 * render and bake agree. Nothing changes when the default is the solver already chosen. */
void cli_pipeline_default_solver(const char *command, cli_pipeline_args *args,
                                 const rad_scene *scene, rad_solve_options *solve,
                                 rad_mesh_options *mesh);

/* For render and bake --solution FILE: a hierarchy's file is drawn on one element per input
 * polygon (`mesh->polygons_only`), as it was solved: the hierarchy reads no element mesh, and
 * the uniform mesh of a large scene costs time and memory for nothing. Other files, and files
 * that cannot be read (the load says why), change nothing. */
void cli_pipeline_saved_mesh(const char *path, rad_mesh_options *mesh);

/* Seconds spent in each step, for --stats. */
typedef struct cli_timings {
    double load, system, solve;
} cli_timings;

/* Loads SCENE (a built-in name or a file), takes its default solver when --solver was not
 * given (cli_pipeline_default_solver: `solve` and `mesh` may change) and builds its system. */
rad_status cli_pipeline_build(rad_context *ctx, const char *scene_name, cli_pipeline_args *args,
                              rad_solve_options *solve, rad_mesh_options *mesh,
                              const rad_ff_options *ff, rad_scene **scene, rad_system **system,
                              cli_timings *timings);

/* Solves, timed. */
rad_status cli_pipeline_solve(rad_system *system, const rad_solve_options *solve,
                              rad_solve_report *report, cli_timings *timings);

#endif
