/* cmd_bake.c - `radiosity bake`: solve a scene and write the solution as vertex colours that
 * other tools open: glTF 2.0 (.glb, .gltf + .bin), PLY or OBJ (docs/bake.md). The solver,
 * form-factor and meshing options are the ones every solving command shares (pipeline.h). */
#include "camera_options.h"
#include "cli.h"
#include "light_options.h"
#include "output_path.h"
#include "pipeline.h"
#include "progress.h"

#include <stdlib.h>
#include <string.h>

int cmd_bake(int argc, char **argv) {
    static const char synopsis[] =
        "SCENE -o FILE.glb|FILE.gltf|FILE.ply|FILE.obj [options]   "
        "(SCENE: a file or a built-in name)";
    cli_pipeline_args p = {0};
    p.ff = "default";
    const char *output = NULL, *tonemap = "clamp";
    const char *solution = NULL;
    double exposure = 0, scale = 0, aspect = 0, time_budget = 0;
    int final_gather = 0;
    cli_light_args lights = {0};
    const cli_option own[] = {
        {"-o", CLI_STRING, &output, "FILE  .glb, .gltf (writes FILE.bin beside it), .ply or .obj"},
        {"--output", CLI_STRING, &output, "FILE  the same as -o"},
        {"--exposure", CLI_DOUBLE, &exposure, "STOPS  PLY and OBJ display colours: exposure (0)"},
        {"--tonemap", CLI_STRING, &tonemap,
         "CURVE  PLY and OBJ display colours: none|clamp|reinhard|aces (clamp)"},
        {"--scale", CLI_DOUBLE, &scale, "S  multiply positions, e.g. 0.001 for mm to m (1)"},
        {"--aspect", CLI_DOUBLE, &aspect, "A  glTF camera aspect ratio, width / height (1)"},
        {"--final-gather", CLI_INT, &final_gather,
         "N  each vertex gathered again: direct light sampled + N rays into the solution (0: "
         "the mean of the elements around it; at 256 about 2% noise a vertex)"},
        {"--time-budget", CLI_DOUBLE, &time_budget,
         "S  stop the solve after S seconds and bake the solution so far"},
        {"--solution", CLI_STRING, &solution,
         "FILE  bake a solution saved by solve --save (same scene and meshing/ff options) "
         "instead of solving"},
        CLI_LIGHT_OPTIONS(&lights),
        CLI_TWO_SIDED_OPTION(&lights),
        CLI_SPECULAR_OPTIONS(&lights),
    };
    cli_option options[CLI_PIPELINE_TABLE_SIZE(own)];
    cli_pipeline_table(options, own, sizeof own / sizeof own[0], 0, &p, RAD_SOLVER_SHOOTING);

    const char *positional[1];
    int count;
    int status = cli_parse("bake", synopsis, options, argc, argv, positional, 1, &count);
    if (status) return status < 0 ? 0 : status;
    if (count != 1)
        return cli_error(EXIT_USAGE, "bake: which scene? (usage: radiosity bake %s)", synopsis);
    if (!output)
        return cli_error(EXIT_USAGE, "bake: where to? -o FILE.glb|FILE.gltf|FILE.ply|FILE.obj");
    if (scale < 0 || aspect < 0)
        return cli_error(EXIT_USAGE, "bake: --scale and --aspect must be positive");
    if (time_budget < 0 || time_budget != time_budget)
        return cli_error(EXIT_USAGE, "bake: --time-budget must be a positive number of seconds");
    const char *inputs[2] = {positional[0], solution};
    if ((status = cli_check_output_path("bake", output, inputs, solution ? 2 : 1))) return status;
    rad_solve_options solve;
    rad_mesh_options mesh;
    rad_ff_options ff;
    status = cli_pipeline_check("bake", &p, &solve, &mesh, &ff);
    if (status) return status;
    /* A saved solution is baked on the mesh it was saved for: no default by scene size. */
    if (solution) {
        p.solver_default = 0;
        cli_pipeline_saved_mesh(solution, &mesh);
    }
    if ((status = cli_lights_check("bake", &lights))) return status;
    solve.time_budget = time_budget;

    rad_context *ctx = cli_context_with_progress(p.threads, p.seed, p.max_memory, p.quiet);
    rad_bake_options bake = {0};
    bake.exposure = exposure;
    bake.tonemap = tonemap;
    bake.scale = scale;
    bake.aspect = aspect;
    bake.ambient = p.ambient;
    bake.final_gather = final_gather;
    /* Refuse a bad name or an unwritable place before the work, not after it. */
    rad_status rs = rad_bake_check(ctx, output, &bake);
    if (rs) {
        int exit_status = rs == RAD_ERROR_INVALID_ARGUMENT ? EXIT_USAGE : 1;
        cli_error(exit_status, "%s", rad_context_error(ctx));
        rad_context_destroy(ctx);
        return exit_status;
    }

    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_solve_report report = {0};
    int exit_status = 0;
    rs = cli_pipeline_build(ctx, positional[0], &p, &solve, &mesh, &ff, &scene, &system, NULL);
    if (!rs && (exit_status = cli_check_outputs_against_scene("bake", scene, &output, 1)))
        goto done; /* not the scene's .mtl, .bin, textures, ... */
    if (!rs && !rad_scene_is_geometric(scene)) {
        cli_progress_clear();
        exit_status = cli_error(1, "bake: %s is a patch system (.ffm): it has no geometry to bake",
                                positional[0]);
        goto done;
    }
    if (!rs && solution) {
        /* A saved solution replaces the solve; it is refused for another scene or mesh. */
        rs = rad_system_load_solution(system, solution, NULL);
        if (!rs) cli_stage("solve", "loaded from %s", solution);
    } else if (!rs) {
        /* --importance weighs the hierarchy's links by what the scene's camera sees (the one
         * the baked glTF carries). */
        rad_camera_desc camera;
        cli_camera_args view;
        cli_camera_args_init(&view);
        cli_camera_get(&view, scene, &camera);
        solve.camera = &camera;
        rs = cli_pipeline_solve(system, &solve, &report, NULL);
    }
    if (!rs) cli_stage("bake", "%s", output);
    bake.scene = scene;
    if (!rs) rs = rad_bake(system, output, &bake);
    cli_progress_clear();
    if (rs) {
        exit_status = cli_fail(ctx, rs);
        goto done;
    }
    /* What was baked: the elements, or a hierarchy's leaves (some drawn as fans). */
    size_t polygons, leaves = rad_system_leaf_count(system, &polygons);
    char baked[96];
    if (leaves == polygons && leaves == rad_system_element_count(system))
        snprintf(baked, sizeof baked, "%zu elements", leaves);
    else
        snprintf(baked, sizeof baked, "%zu leaves (%zu polygons)", leaves, polygons);
    if (!p.quiet && solution) {
        printf("baked %s of %zu surfaces into %s (solution from %s)\n", baked,
               rad_system_surface_count(system), output, solution);
    } else if (!p.quiet) {
        printf("baked %s of %zu surfaces into %s (%s", baked, rad_system_surface_count(system),
               output, rad_solver_kind_name(solve.solver));
        if (solve.solver != RAD_SOLVER_DIRECT)
            printf(": %d %s, %s", report.iterations,
                   cli_step_word(solve.solver, report.iterations),
                   cli_solve_outcome(&report));
        printf(")\n");
    }
done:
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
