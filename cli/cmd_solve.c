/* cmd_solve.c - `radiosity solve`: solve a scene, print each surface's radiosity, optionally
 * every round or shot (--trace) and as JSON (--json). Watching it converge (--log, --plot,
 * --snapshots, the progress line), stopping and going on (--time-budget, --save, --resume) and
 * the solver comparison (--compare-solvers) are in solve_watch.c, solve_compare.c and
 * solve_snapshots.c. */
#include "cli.h"
#include "interrupt.h"
#include "json.h"
#include "output_path.h"
#include "progress.h"
#include "solve_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The trace, kept for JSON or printed as it comes. */
typedef struct trace_log {
    const rad_system *system;
    int json, shooting;
    FILE *out;
    char *buffer;
    size_t size;
    int count;
} trace_log;

static int grey(const double rgb[3]) { return rgb[0] == rgb[1] && rgb[1] == rgb[2]; }

static void print_rgb(FILE *out, const double rgb[3]) {
    if (grey(rgb)) fprintf(out, "%.4g", rgb[0]);
    else fprintf(out, "%.4g %.4g %.4g", rgb[0], rgb[1], rgb[2]);
}

static void json_named_map(FILE *out, const rad_system *system, const double (*values)[3]) {
    fputc('{', out);
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        if (i) fputs(", ", out);
        json_string(out, info.name);
        fputs(": ", out);
        json_rgb(out, values[i]);
    }
    fputc('}', out);
}

static void on_trace(void *user, const rad_trace_event *event) {
    trace_log *log = user;
    const rad_system *system = log->system;
    FILE *out = log->out;
    rad_surface_info shooter = {0};
    if (event->shooter >= 0) rad_system_surface(system, (size_t)event->shooter, &shooter);
    if (log->json) {
        fputs(log->count++ ? ",\n  " : "\n  ", out);
        fprintf(out, "{\"iteration\": %d", event->iteration);
        if (event->shooter >= 0) {
            fputs(", \"shooter\": ", out);
            json_string(out, shooter.name);
        }
        fputs(", \"received\": ", out);
        json_named_map(out, system, event->received);
        if (event->reflected) {
            fputs(", \"reflected\": ", out);
            json_named_map(out, system, event->reflected);
        }
        fputs(", \"radiosity\": ", out);
        json_named_map(out, system, event->radiosity);
        if (event->unshot) {
            fputs(", \"unshot\": ", out);
            json_named_map(out, system, event->unshot);
        }
        fputc('}', out);
        return;
    }
    if (event->shooter >= 0) fprintf(out, "shot %d from %s\n", event->iteration, shooter.name);
    else fprintf(out, "round %d\n", event->iteration);
    for (size_t i = 0; i < event->surface_count; ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        fprintf(out, "  %-14s received ", info.name);
        print_rgb(out, event->received[i]);
        if (event->reflected) {
            fputs("  reflected ", out);
            print_rgb(out, event->reflected[i]);
        }
        fputs("  radiosity ", out);
        print_rgb(out, event->radiosity[i]);
        if (event->unshot) {
            fputs("  unshot ", out);
            print_rgb(out, event->unshot[i]);
        }
        fputc('\n', out);
    }
}

static const char *stop_name(rad_solve_stop stop) {
    switch (stop) {
    case RAD_STOP_CONVERGED: return "converged";
    case RAD_STOP_ITERATIONS: return "iterations";
    case RAD_STOP_TIME_BUDGET: return "time-budget";
    case RAD_STOP_CALLBACK: return "interrupted";
    case RAD_STOP_MEMORY_BUDGET: return "memory-budget";
    case RAD_STOP_TAIL: return "tail";
    case RAD_STOP_ERROR: break;
    }
    return "error";
}

static void print_table(const rad_system *system, const rad_solve_options *options,
                        const rad_solve_report *report, long steps) {
    printf("%s: %ld %s, %s", rad_solver_kind_name(options->solver), steps,
           cli_step_word(options->solver, steps),
           cli_solve_outcome(report));
    if (report->stop == RAD_STOP_TAIL)
        printf(": the last step refined at most 0.2%% of its %zu links and solved them; every "
               "link passed the oracle at the radiosities it was refined with", report->links);
    else if (report->stop == RAD_STOP_TIME_BUDGET)
        printf(": time budget of %g s used up", options->time_budget);
    else if (report->stop == RAD_STOP_CALLBACK)
        printf(": interrupted");
    else if (report->stop == RAD_STOP_MEMORY_BUDGET)
        printf(": memory budget reached (--max-memory) at %zu links, the solution so far",
               report->links);
    char residual[32];
    printf(" (residual %s)\n", cli_residual_text(residual, sizeof residual, report));
    printf("%-16s %12s  %-38s %s\n", "surface", "area", "radiosity (R G B)", "power (R G B)");
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        printf("%-16s %12.6g  %12.6f %12.6f %12.6f  %12.6g %12.6g %12.6g\n", info.name, info.area,
               info.radiosity[0], info.radiosity[1], info.radiosity[2], info.power[0],
               info.power[1], info.power[2]);
    }
}

/* `importance`: the camera guided the solve (--importance, or a solver that needs a camera). */
static void print_json(const rad_system *system, const rad_solve_options *options,
                       const rad_solve_report *report, long steps, int importance,
                       const trace_log *trace) {
    printf("{\"solver\": \"%s\", \"iterations\": %ld, \"converged\": %s, \"residual\": ",
           rad_solver_kind_name(options->solver), steps, report->converged ? "true" : "false");
    json_number(stdout, report->residual);
    printf(", \"stop\": \"%s\", \"importance\": %s, \"seconds\": ", stop_name(report->stop),
           importance ? "true" : "false");
    json_number(stdout, report->seconds);
    if (report->links) {
        printf(", \"links\": %zu, \"leaves\": %zu, \"largest_error\": ", report->links,
               report->leaves);
        json_number(stdout, report->largest_error);
    }
    printf(",\n \"patches\": [");
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        json_surface_open(stdout, i, info.name, info.area);
        printf(", \"radiosity\": ");
        json_rgb(stdout, info.radiosity);
        printf(", \"power\": ");
        json_rgb(stdout, info.power);
        printf("}");
    }
    printf("]");
    /* Where the emitted power went: a leak in a closed scene shows as escaped power. */
    rad_energy_balance energy;
    rad_system_energy_balance(system, &energy);
    const char *parts[4] = {"emitted", "absorbed", "unshot", "escaped"};
    const double *values[4] = {energy.emitted, energy.absorbed, energy.unshot, energy.escaped};
    printf(",\n \"energy\": {");
    for (int k = 0; k < 4; ++k) {
        printf("%s\"%s\": ", k ? ", " : "", parts[k]);
        json_rgb(stdout, values[k]);
    }
    printf(", \"escaped_fraction\": ");
    json_number(stdout, energy.escaped_fraction);
    printf(", \"black_area\": ");
    json_number(stdout, energy.black_area);
    printf("}");
    if (trace) {
        printf(",\n \"trace\": [");
        fwrite(trace->buffer, 1, trace->size, stdout);
        printf("]");
    }
    printf("}\n");
}

/* "--overshoot is for the shooting and importance solvers" (those that take it). */
static int overshoot_error(void) {
    char names[200];
    cli_solver_filter takes = {0, 0, "overshoot"};
    return cli_error(EXIT_USAGE, "solve: --overshoot is for the %s solvers",
                     cli_solver_names(names, sizeof names, &takes, ", ", " and "));
}

/* Usage checks that need no scene. Returns 0 or the exit status after printing the message. */
static int check_args(solve_args *a, int kind) {
    if (!isnan(a->time_budget) && !(a->time_budget > 0))
        return cli_error(EXIT_USAGE, "solve: --time-budget must be a positive number of seconds, "
                                     "not %g", a->time_budget);
    int status = cli_camera_check("solve", &a->camera);
    if (status) return status;
    if ((a->width == 0) != (a->height == 0) && a->width + a->height > 0) {
        if (a->width == 0) a->width = a->height;
        else a->height = a->width;
    }
    if (a->snapshot_every && !a->snapshots)
        return cli_error(EXIT_USAGE, "solve: --snapshot-every needs --snapshots DIR");
    if (a->overshoot && kind >= 0 && !cli_solver_takes((rad_solver_kind)kind, "overshoot"))
        return overshoot_error();
    if (a->compare && (a->resume || a->save || a->snapshots || a->trace))
        return cli_error(EXIT_USAGE, "solve: --compare-solvers takes no --resume, --save, "
                                     "--snapshots or --trace");
    if (a->resume && a->save && strcmp(a->resume, a->save) == 0) return 0; /* fine: replaced whole */
    return 0;
}

/* Before any long work: every output can be written. */
static int check_outputs(const solve_args *a) {
    if (a->log && cli_check_writable(a->log)) return 1;
    if (a->plot && cli_check_writable(a->plot)) return 1;
    if (a->save && cli_check_writable(a->save)) return 1;
    if (a->snapshots && cli_check_directory(a->snapshots)) return 1;
    return 0;
}

int cmd_solve(int argc, char **argv) {
    static const char synopsis[] = "SCENE [options]   (SCENE: a file or a built-in name)";
    solve_args a = {0};
    a.pipe.ff = "default";
    a.time_budget = NAN;
    cli_camera_args_init(&a.camera);
    /* Help lines that name solvers, from the registry: those that take --overshoot and those
     * that need a camera. */
    static char overshoot_help[160], eye_help[160], width_help[160];
    char viewers[120];
    cli_solver_filter needs_camera = {RAD_SOLVER_NEEDS_CAMERA, 0, NULL};
    cli_solver_names(viewers, sizeof viewers, &needs_camera, ", ", ", ");
    cli_solver_option_help(overshoot_help, sizeof overshoot_help, "overshoot");
    snprintf(eye_help, sizeof eye_help, "X,Y,Z  camera position (%s, snapshots)", viewers);
    snprintf(width_help, sizeof width_help, "W  image width for %s and snapshots (256)", viewers);
    const cli_option own[] = {
        {"--time-budget", CLI_DOUBLE, &a.time_budget,
         "S  stop after S seconds with the solution so far"},
        {"--overshoot", CLI_FLAG, &a.overshoot, overshoot_help},
        {"--trace", CLI_FLAG, &a.trace, "show every round or shot"},
        {"--json", CLI_FLAG, &a.json, "print one JSON object"},
        {"--log", CLI_STRING, &a.log, "FILE.csv  one row per round or shot"},
        {"--plot", CLI_STRING, &a.plot, "FILE.svg  residual (or error) against time"},
        {"--save", CLI_STRING, &a.save, "FILE  save the solution (to go on with --resume)"},
        {"--resume", CLI_STRING, &a.resume, "FILE  go on from a saved solution"},
        {"--snapshots", CLI_STRING, &a.snapshots, "DIR  write an image every --snapshot-every steps"},
        {"--snapshot-every", CLI_INT, &a.snapshot_every,
         "K  shots or rounds between snapshots (100; 1)"},
        {"--compare-solvers", CLI_FLAG, &a.compare,
         "run every solver and compare their convergence (table; chart with --plot)"},
        {"--eye", CLI_VEC3, a.camera.eye, eye_help},
        {"--look", CLI_VEC3, a.camera.look, "X,Y,Z  point the camera looks at"},
        {"--up", CLI_VEC3, a.camera.up, "X,Y,Z  camera up direction"},
        {"--fov", CLI_DOUBLE, &a.camera.fov, "DEG  vertical field of view"},
        {"--width", CLI_INT, &a.width, width_help},
        {"--height", CLI_INT, &a.height, "H  image height (256)"},
        {"--exposure", CLI_DOUBLE, &a.exposure, "EV  snapshot exposure in stops (0)"},
        {"--tonemap", CLI_STRING, &a.tonemap, "CURVE  snapshots: none|clamp|reinhard|aces (clamp)"},
        CLI_LIGHT_OPTIONS(&a.lights),
        CLI_TWO_SIDED_OPTION(&a.lights),
        CLI_SPECULAR_OPTIONS(&a.lights),
    };
    /* The shared solver, form-factor and meshing options (cli/pipeline.h), then our own. */
    cli_option options[CLI_PIPELINE_TABLE_SIZE(own)];
    cli_pipeline_table(options, own, sizeof own / sizeof own[0], 1, &a.pipe, RAD_SOLVER_SHOOTING);
    const char *positional[1];
    int count;
    int status = cli_parse("solve", synopsis, options, argc, argv, positional, 1, &count);
    if (status) return status < 0 ? 0 : status;
    if (count != 1) return cli_error(EXIT_USAGE, "solve: which scene? (usage: radiosity solve %s)", synopsis);
    a.scene_name = positional[0];
    /* The shared checks and option structs, as render's and bake's (cli/pipeline.c): a bad
     * value is a usage error (2). Without --solver, a resumed run takes the saved solver. */
    int solver_given = a.pipe.solver != NULL;
    if (!solver_given) a.pipe.solver = rad_solver_kind_name(RAD_SOLVER_SHOOTING);
    /* Resumed without --solver: the saved solver's system (a hierarchy's needs no uniform mesh;
     * an unreadable file is refused by the load below). */
    rad_solution_info saved;
    if (!solver_given && a.resume && rad_solution_file_info(NULL, a.resume, &saved) == RAD_OK)
        a.pipe.solver = rad_solver_kind_name(saved.solver);
    /* Not given and not resumed (a resumed run takes the saved solver): the scene's default. */
    a.pipe.solver_default = !solver_given && !a.resume;
    rad_solve_options solve;
    rad_mesh_options mesh;
    rad_ff_options ff;
    if ((status = cli_pipeline_check("solve", &a.pipe, &solve, &mesh, &ff))) return status;
    int kind = (int)solve.solver;
    if ((status = check_args(&a, solver_given || !a.resume ? kind : -1))) return status;
    if ((status = cli_lights_check("solve", &a.lights))) return status;
    double link_error;
    cli_pipeline_link_error("solve", &a.pipe, &link_error); /* checked above */
    if ((status = check_outputs(&a))) return status;
    /* No output may be the scene; --save may be --resume (read whole, then replaced whole). */
    const char *inputs[] = {positional[0], a.resume};
    if ((status = cli_check_output_path("solve", a.save, inputs, 1)) ||
        (status = cli_check_output_path("solve", a.log, inputs, 2)) ||
        (status = cli_check_output_path("solve", a.plot, inputs, 2)))
        return status;

    rad_context *ctx = cli_context_with_progress(a.pipe.threads, (uint64_t)a.pipe.seed,
                                                 a.pipe.max_memory, a.pipe.quiet);
    cli_interrupt_install();
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    solve_snapshots *snapshots = NULL;
    plot_series series = {0};
    int exit_status = 0;
    rad_status rs = cli_load_scene(ctx, positional[0], &scene);
    const char *outputs[] = {a.save, a.log, a.plot}; /* none may be the scene's .mtl, .bin, ... */
    if (!rs && (exit_status = cli_check_outputs_against_scene("solve", scene, outputs, 3)))
        goto done;
    rad_camera_desc camera;
    if (!rs) cli_camera_get(&a.camera, scene, &camera);
    if (!rs && a.compare) {
        exit_status = solve_compare(ctx, scene, &mesh, &ff, &a, &camera);
        goto done;
    }
    if (!rs) {
        cli_pipeline_default_solver("solve", &a.pipe, scene, &solve, &mesh);
        kind = (int)solve.solver;
    }
    double mesh_start = cli_seconds();
    if (!rs) rs = rad_system_create(ctx, scene, &mesh, &ff, &system);
    if (!rs) cli_stage_mesh(system, cli_seconds() - mesh_start);

    /* Going on from a saved solution. */
    rad_solution_info resumed = {(rad_solver_kind)kind, 0};
    if (!rs && a.resume) {
        rs = rad_system_load_solution(system, a.resume, &resumed);
        if (!rs) {
            if (!solver_given) { /* the saved solver, with --importance as for any other */
                kind = cli_pipeline_importance_solver(resumed.solver, a.pipe.importance);
                if (kind < 0) {
                    exit_status = cli_importance_error("solve", resumed.solver);
                    goto done;
                }
            }
            if (!rad_solver_can_resume((rad_solver_kind)kind, resumed.solver)) {
                /* The iterative solvers that need no unshot light can go on from it. */
                char names[200];
                cli_solver_filter can = {RAD_SOLVER_ITERATIVE, RAD_SOLVER_NEEDS_UNSHOT, NULL};
                exit_status = cli_error(EXIT_USAGE,
                                        "%s holds a %s solution, whose unshot light is unknown; go on "
                                        "with --solver %s", a.resume,
                                        rad_solver_kind_name(resumed.solver),
                                        cli_solver_names(names, sizeof names, &can, ", ", " or "));
                goto done;
            }
            if (a.overshoot && !cli_solver_takes((rad_solver_kind)kind, "overshoot")) {
                exit_status = overshoot_error();
                goto done;
            }
            if (!a.pipe.quiet)
                fprintf(stderr, "radiosity: going on from %s (%ld %s by %s)\n", a.resume,
                        resumed.steps, cli_step_word(resumed.solver, resumed.steps),
                        rad_solver_kind_name(resumed.solver));
        }
    }
    if (!rs && a.snapshots)
        exit_status = solve_snapshots_create(ctx, scene, system, &a, &camera, &snapshots);
    if (exit_status) goto done;

    trace_log trace = {system, a.json, cli_solver_shoots((rad_solver_kind)kind), stdout, NULL, 0, 0};
    if (!rs) {
        /* The solver may be the resumed one: its own options again, with ours. */
        solve.solver = (rad_solver_kind)kind;
        rad_options *own = &a.pipe.solver_options;
        *own = (rad_options){0};
        cli_solver_option(own, solve.solver, "ambient", a.pipe.ambient || a.snapshots);
        cli_solver_option(own, solve.solver, "overshoot", a.overshoot);
        cli_solver_option(own, solve.solver, "link-error", link_error);
        cli_solver_option(own, solve.solver, "importance", a.pipe.importance);
        solve.method_options = own;
        solve.time_budget = isnan(a.time_budget) ? 0 : a.time_budget;
        solve.resume = a.resume != NULL;
        solve.camera = &camera;
        solve.view_width = a.width;
        solve.view_height = a.height;
        if (a.trace) {
            solve.trace = on_trace;
            solve.trace_user = &trace;
            if (a.json) trace.out = open_memstream(&trace.buffer, &trace.size);
        }
        solve_watch watch = {0};
        watch.system = system;
        watch.solver_name = rad_solver_kind_name(solve.solver);
        watch.shooting = cli_solver_shoots(solve.solver);
        watch.hierarchy = (rad_solver_get(solve.solver)->capabilities & RAD_SOLVER_OWN_LEAVES) != 0;
        watch.step_offset = a.resume ? resumed.steps : 0;
        watch.tolerance = solve.tolerance > 0 ? solve.tolerance : 1e-6;
        watch.time_budget = solve.time_budget;
        watch.progress = !a.pipe.quiet && !a.trace && isatty(STDERR_FILENO);
        watch.error_seconds = watch.view_error_seconds = -1;
        if (a.log) {
            watch.log = open_memstream(&watch.log_buffer, &watch.log_size);
            if (watch.log) fputs(watch.hierarchy ? "iteration,seconds,shots,sweeps,unshot_fraction,"
                                                   "residual,links,leaves,largest_error\n"
                                                 : "iteration,seconds,shots,sweeps,unshot_fraction,"
                                                   "residual\n", watch.log);
        }
        if (a.plot) {
            snprintf(series.name, sizeof series.name, "%s", watch.solver_name);
            watch.series = &series;
        }
        if (snapshots) {
            watch.snapshot_every = a.snapshot_every ? a.snapshot_every : watch.shooting ? 100 : 1;
            watch.snapshot = solve_snapshot_take;
            watch.snapshot_user = snapshots;
        }
        solve.on_iteration = solve_watch_iteration;
        solve.iteration_user = &watch;

        rad_solve_report report;
        rs = rad_solve(system, &solve, &report);
        solve_watch_finish(&watch);
        if (!rs) cli_stage_solve(&solve, &report);
        if (trace.out != stdout && trace.out) fclose(trace.out);
        if (watch.log) fclose(watch.log);
        long steps = watch.step_offset + report.iterations;
        if (watch.failed) exit_status = 1;
        /* The final snapshot, unless the last step made one. */
        if (!rs && !exit_status && snapshots && steps % watch.snapshot_every != 0 &&
            solve_snapshot_take(snapshots, steps))
            exit_status = 1;
        /* Save first: the solution is what a long run must not lose. */
        if (!rs && a.save) {
            rad_solution_info info = {solve.solver, steps};
            rs = rad_system_save_solution(system, a.save, &info);
            if (!rs && !a.pipe.quiet)
                fprintf(stderr, "radiosity: saved the solution to %s (%ld %s)\n", a.save, steps,
                        cli_step_word(solve.solver, steps));
        }
        if (!rs && !exit_status && a.log && cli_write_whole(a.log, watch.log_buffer, watch.log_size))
            exit_status = 1;
        if (!rs && !exit_status && a.plot) {
            plot_chart chart = {"Convergence", "seconds",
                                watch.shooting    ? "unshot power / emitted power"
                                : watch.hierarchy ? "oracle's largest error / emitted power"
                                                  : "largest change / largest radiosity", 0};
            exit_status = plot_write_svg(a.plot, &chart, &series, 1);
        }
        free(watch.log_buffer);
        if (!rs && !exit_status) {
            int guided = a.pipe.importance ||
                         (rad_solver_get(solve.solver)->capabilities & RAD_SOLVER_NEEDS_CAMERA);
            if (a.json) print_json(system, &solve, &report, steps, guided, a.trace ? &trace : NULL);
            else print_table(system, &solve, &report, steps);
        }
        if (!rs && !exit_status && cli_interrupted()) exit_status = cli_interrupt_exit_status();
    }
    free(trace.buffer);
done:
    if (rs) exit_status = cli_fail(ctx, rs);
    plot_series_free(&series);
    solve_snapshots_destroy(snapshots);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
