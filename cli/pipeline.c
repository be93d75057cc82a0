/* pipeline.c - the shared load, mesh and solve steps of the commands (see pipeline.h). */
#include "pipeline.h"

#include "progress.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double cli_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void cli_pipeline_options(cli_pipeline_args *a, rad_solver_kind default_solver, cli_option *o) {
    /* The help lines that list or name solvers and methods, from the registries. */
    static char solver_help[256], ff_help[160], ambient_help[160], link_help[200],
        resolution_help[160], names[200];
    char by_size[96] = "";
    if (default_solver == RAD_SOLVER_SHOOTING) /* rad_scene_default_solver */
        snprintf(by_size, sizeof by_size, "; hierarchical for scenes of %d polygons or more",
                 RAD_HIERARCHY_DEFAULT_POLYGONS);
    snprintf(solver_help, sizeof solver_help, "NAME  %s (%s%s)",
             cli_solver_names(names, sizeof names, NULL, "|", "|"),
             rad_solver_kind_name(default_solver), by_size);
    snprintf(ff_help, sizeof ff_help, "METHOD  %s", cli_ff_method_names(names, sizeof names, "|"));
    cli_solver_option_help(ambient_help, sizeof ambient_help, "ambient");
    cli_solver_option_help(link_help, sizeof link_help, "link-error");
    cli_ff_option_help(resolution_help, sizeof resolution_help, "N", "hemicube-res");
    const cli_option shared[CLI_PIPELINE_OPTION_COUNT] = {
        {"--solver", CLI_STRING, &a->solver, solver_help},
        {"--iterations", CLI_INT, &a->iterations, "N  stop after N rounds or shots"},
        {"--tolerance", CLI_DOUBLE, &a->tolerance,
         "T  stop at this measure: a round's largest relative change, or the unshot power "
         "fraction after a shot (1e-6)"},
        {"--omega", CLI_DOUBLE, &a->omega, "W  over-relaxation in (0, 2) (1)"},
        {"--ambient", CLI_FLAG, &a->ambient, ambient_help},
        {"--ff", CLI_STRING, &a->ff, ff_help},
        {"--ff-samples", CLI_INT, &a->ff_samples, "N  rays or point pairs per form factor"},
        {"--hemicube-res", CLI_INT, &a->hemicube_res, resolution_help},
        {"--patch-size", CLI_DOUBLE, &a->patch_size, "S  longest patch edge (scene units)"},
        {"--element-size", CLI_DOUBLE, &a->element_size, "S  longest element edge (scene units)"},
        {"--elements", CLI_SIZE, &a->elements, "N  approximate element count (2500)"},
        {"--discontinuity", CLI_INT, &a->discontinuity,
         "N  0: cut the mesh at contacts; 1: and at the shadow boundaries of area lights (0)"},
        {"--max-memory", CLI_MEMORY, &a->max_memory, "MIB  memory budget for matrices, in MiB or as 512M, 2G (2048)"},
        {"--threads", CLI_INT, &a->threads, "N  worker threads (all cores)"},
        {"--seed", CLI_SIZE, &a->seed, "S  random seed (0)"},
        {"--quiet", CLI_FLAG, &a->quiet, "no notes or progress on stderr"},
        {"--link-error", CLI_STRING, &a->link_error, link_help},
        {"--importance", CLI_FLAG, &a->importance,
         "let the camera guide the solve: hierarchical refines links where the view needs them, "
         "shooting becomes --solver importance (shots ordered by what the view sees)"},
    };
    for (int i = 0; i < CLI_PIPELINE_OPTION_COUNT; ++i) o[i] = shared[i];
}

void cli_pipeline_table(cli_option *table, const cli_option *own, size_t own_count,
                        int shared_first, cli_pipeline_args *args,
                        rad_solver_kind default_solver) {
    cli_option *own_start = shared_first ? table + CLI_PIPELINE_OPTION_COUNT : table;
    cli_pipeline_options(args, default_solver, shared_first ? table : table + own_count);
    for (size_t i = 0; i < own_count; ++i) own_start[i] = own[i];
    table[own_count + CLI_PIPELINE_OPTION_COUNT] = (cli_option){0};
}

int cli_pipeline_check_values(const char *command, const cli_pipeline_args *a) {
    if (a->max_memory < 0) return cli_error(EXIT_USAGE, "%s: --max-memory must be positive", command);
    if (a->patch_size < 0 || a->element_size < 0)
        return cli_error(EXIT_USAGE, "%s: sizes must be positive", command);
    if (a->tolerance < 0) return cli_error(EXIT_USAGE, "%s: --tolerance must be positive", command);
    if (a->discontinuity != 0 && a->discontinuity != 1)
        return cli_error(EXIT_USAGE, "%s: --discontinuity must be 0 or 1, not %d", command,
                         a->discontinuity);
    if (a->omega != 0 && !(a->omega > 0 && a->omega < 2))
        return cli_error(EXIT_USAGE, "%s: --omega must be in (0, 2), not %g", command, a->omega);
    return 0;
}

int cli_pipeline_check(const char *command, cli_pipeline_args *a, rad_solve_options *solve,
                       rad_mesh_options *mesh, rad_ff_options *ff) {
    if (!a->solver) { /* not given: shooting, or the scene's default once it is loaded */
        a->solver = rad_solver_kind_name(RAD_SOLVER_SHOOTING);
        a->solver_default = 1;
    }
    int kind = rad_solver_kind_parse(a->solver);
    if (kind < 0) return cli_unknown_solver(command, a->solver);
    int method = cli_parse_ff_method(a->ff);
    if (method < 0) return cli_unknown_ff_method(command, a->ff);
    int status = cli_pipeline_check_values(command, a);
    if (status) return status;
    rad_solve_options s = {0};
    double link_error;
    status = cli_pipeline_link_error(command, a, &link_error);
    if (status) return status;
    /* --importance follows the solver: shooting becomes the importance solver. */
    int guided = cli_pipeline_importance_solver((rad_solver_kind)kind, a->importance);
    if (guided < 0) return cli_importance_error(command, (rad_solver_kind)kind);
    if (guided != kind) a->solver = rad_solver_kind_name((rad_solver_kind)guided);
    kind = guided;
    s.solver = (rad_solver_kind)kind;
    s.max_iterations = a->iterations;
    s.tolerance = a->tolerance;
    s.omega = a->omega;
    /* Each method's own options go in its bag, read from the registry's names. */
    a->solver_options = (rad_options){0};
    cli_solver_option(&a->solver_options, s.solver, "ambient", a->ambient);
    cli_solver_option(&a->solver_options, s.solver, "link-error", link_error);
    cli_solver_option(&a->solver_options, s.solver, "importance", a->importance);
    cli_solver_option(&a->solver_options, s.solver, "final-gather", a->final_gather);
    s.method_options = &a->solver_options;
    *solve = s;
    *mesh = (rad_mesh_options){a->patch_size, a->element_size, a->elements, 0, a->discontinuity};
    /* A solver that draws its own leaves needs no uniform mesh. */
    mesh->polygons_only = (rad_solver_get(s.solver)->capabilities & RAD_SOLVER_OWN_LEAVES) != 0;
    a->ff_options = (rad_options){0};
    cli_ff_option(&a->ff_options, (rad_ff_method)method, "ff-samples", a->ff_samples);
    cli_ff_option(&a->ff_options, (rad_ff_method)method, "hemicube-res", a->hemicube_res);
    *ff = (rad_ff_options){(rad_ff_method)method, 0, 0, &a->ff_options};
    return 0;
}

int cli_pipeline_importance_solver(rad_solver_kind kind, int importance) {
    if (!importance || cli_solver_takes(kind, "importance")) return (int)kind;
    if (kind == RAD_SOLVER_SHOOTING) return (int)RAD_SOLVER_IMPORTANCE;
    const rad_solver_info *info = rad_solver_get(kind);
    return info && (info->capabilities & RAD_SOLVER_NEEDS_CAMERA) ? (int)kind : -1;
}

int cli_importance_error(const char *command, rad_solver_kind kind) {
    char names[200] = "";
    size_t count = 0, written = 0;
    for (size_t i = 0; i < rad_solver_count(); ++i)
        count += cli_pipeline_importance_solver((rad_solver_kind)(i + 1), 1) >= 0;
    for (size_t i = 0; i < rad_solver_count(); ++i) {
        if (cli_pipeline_importance_solver((rad_solver_kind)(i + 1), 1) < 0) continue;
        size_t used = strlen(names);
        snprintf(names + used, sizeof names - used, "%s%s",
                 written == 0 ? "" : written + 1 == count ? " and " : ", ", rad_solver_at(i)->name);
        ++written;
    }
    return cli_error(EXIT_USAGE, "%s: --importance is for the %s solvers, not %s", command, names,
                     rad_solver_kind_name(kind));
}

int cli_pipeline_link_error(const char *command, const cli_pipeline_args *a, double *out) {
    *out = 0;
    if (!a->link_error) return 0;
    char *end;
    double value = strtod(a->link_error, &end);
    if (end == a->link_error || *end || !(value > 0) || !isfinite(value))
        return cli_error(EXIT_USAGE, "%s: --link-error must be a positive number, not '%s'",
                         command, a->link_error);
    *out = value;
    return 0;
}

void cli_pipeline_default_solver(const char *command, cli_pipeline_args *a,
                                 const rad_scene *scene, rad_solve_options *solve,
                                 rad_mesh_options *mesh) {
    rad_solver_kind kind = rad_scene_default_solver(scene);
    if (!a->solver_default || cli_pipeline_importance_solver(kind, a->importance) == (int)solve->solver)
        return;
    const char *was = a->solver;
    a->solver = rad_solver_kind_name(kind);
    rad_solve_options s;
    rad_mesh_options m;
    rad_ff_options f;
    if (cli_pipeline_check(command, a, &s, &m, &f)) { /* cannot be: the values were checked */
        a->solver = was;
        return;
    }
    solve->solver = s.solver;
    solve->tolerance = s.tolerance; /* not a default meant for the solver it replaces */
    solve->method_options = s.method_options;
    mesh->polygons_only = m.polygons_only;
    if (!a->quiet)
        fprintf(stderr, "radiosity: %d polygons or more: solving with --solver %s (give --solver "
                        "to choose another)\n", RAD_HIERARCHY_DEFAULT_POLYGONS, a->solver);
}

void cli_pipeline_saved_mesh(const char *path, rad_mesh_options *mesh) {
    rad_solution_info saved;
    if (rad_solution_file_info(NULL, path, &saved)) return; /* the load will say why */
    const rad_solver_info *info = rad_solver_get(saved.solver);
    if (info && (info->capabilities & RAD_SOLVER_OWN_LEAVES)) mesh->polygons_only = 1;
}

rad_status cli_pipeline_build(rad_context *ctx, const char *scene_name, cli_pipeline_args *a,
                              rad_solve_options *solve, rad_mesh_options *mesh,
                              const rad_ff_options *ff, rad_scene **scene, rad_system **system,
                              cli_timings *timings) {
    *scene = NULL;
    *system = NULL;
    double start = cli_seconds();
    rad_status status = cli_load_scene(ctx, scene_name, scene);
    if (!status) cli_pipeline_default_solver("", a, *scene, solve, mesh);
    double loaded = cli_seconds();
    if (!status) status = rad_system_create(ctx, *scene, mesh, ff, system);
    if (!status) cli_stage_mesh(*system, cli_seconds() - loaded);
    if (timings) {
        timings->load = loaded - start;
        timings->system = cli_seconds() - loaded;
    }
    return status;
}

rad_status cli_pipeline_solve(rad_system *system, const rad_solve_options *solve,
                              rad_solve_report *report, cli_timings *timings) {
    double start = cli_seconds();
    rad_status status = rad_solve(system, solve, report);
    if (timings) timings->solve = cli_seconds() - start;
    if (!status && report) cli_stage_solve(solve, report);
    return status;
}
