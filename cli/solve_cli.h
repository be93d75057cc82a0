/* solve_cli.h - the pieces of `radiosity solve`: its options (cmd_solve.c), the solver
 * comparison (solve_compare.c) and snapshots (solve_snapshots.c). */
#ifndef RAD_CLI_SOLVE_CLI_H
#define RAD_CLI_SOLVE_CLI_H

#include "camera_options.h"
#include "light_options.h"
#include "pipeline.h"
#include "radiosity.h"
#include "solve_watch.h"

#include <stdint.h>

typedef struct solve_args {
    cli_pipeline_args pipe; /* --solver, --iterations, form factors, meshing, ... */
    int trace, json;
    /* Progressive refinement and importance. */
    int overshoot, compare, snapshot_every, width, height;
    double time_budget; /* NaN when not given */
    const char *log, *plot, *save, *resume, *snapshots;
    cli_camera_args camera; /* --eye, --look, --up, --fov (importance, snapshots) */
    cli_light_args lights;  /* --sky, --sun, --ies */
    double exposure;
    const char *tonemap;
    const char *scene_name; /* the SCENE argument */
} solve_args;

/* `radiosity solve SCENE --compare-solvers`: every solver on the same system, their error
 * against a converged reference over time, a table and (with --plot) one chart. Returns the
 * exit status. */
int solve_compare(rad_context *ctx, const rad_scene *scene, const rad_mesh_options *mesh,
                  const rad_ff_options *ff, const solve_args *args, const rad_camera_desc *camera);

/* Snapshots (--snapshots DIR --snapshot-every K): a renderer over the system, and the
 * snapshot function for solve_watch. */
typedef struct solve_snapshots solve_snapshots;
int solve_snapshots_create(rad_context *ctx, const rad_scene *scene, const rad_system *system,
                           const solve_args *args, const rad_camera_desc *camera,
                           solve_snapshots **out);
int solve_snapshot_take(void *snapshots, long step);
void solve_snapshots_destroy(solve_snapshots *snapshots);

#endif
