/* cmd_solve.c - `radiosity solve`: solve a scene, print each surface's radiosity, optionally
 * every round or shot (--trace) and as JSON (--json). */
#include "cli.h"
#include "json.h"

#include <stdlib.h>
#include <string.h>

typedef struct solve_args {
    const char *solver, *ff;
    int iterations, trace, json, ambient, threads, quiet, ff_samples, hemicube_res;
    double tolerance, omega, max_memory, patch_size, element_size;
    size_t elements;
    uint64_t seed;
} solve_args;

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

static void print_table(const rad_system *system, const rad_solve_options *options,
                        const rad_solve_report *report) {
    printf("%s: %d %s, %s (residual %.3g)\n", rad_solver_kind_name(options->solver),
           report->iterations, options->solver == RAD_SOLVER_SHOOTING ? "shots" : "rounds",
           report->converged ? "converged" : "not converged", report->residual);
    printf("%-16s %12s  %-38s %s\n", "surface", "area", "radiosity (R G B)", "power (R G B)");
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        printf("%-16s %12.6g  %12.6f %12.6f %12.6f  %12.6g %12.6g %12.6g\n", info.name, info.area,
               info.radiosity[0], info.radiosity[1], info.radiosity[2], info.power[0],
               info.power[1], info.power[2]);
    }
}

static void print_json(const rad_system *system, const rad_solve_options *options,
                       const rad_solve_report *report, const trace_log *trace) {
    printf("{\"solver\": \"%s\", \"iterations\": %d, \"converged\": %s, \"residual\": ",
           rad_solver_kind_name(options->solver), report->iterations,
           report->converged ? "true" : "false");
    json_number(stdout, report->residual);
    printf(",\n \"patches\": [");
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        printf(i ? ",\n  " : "\n  ");
        printf("{\"name\": ");
        json_string(stdout, info.name);
        printf(", \"area\": ");
        json_number(stdout, info.area);
        printf(", \"radiosity\": ");
        json_rgb(stdout, info.radiosity);
        printf(", \"power\": ");
        json_rgb(stdout, info.power);
        printf("}");
    }
    printf("]");
    if (trace) {
        printf(",\n \"trace\": [");
        fwrite(trace->buffer, 1, trace->size, stdout);
        printf("]");
    }
    printf("}\n");
}

int cmd_solve(int argc, char **argv) {
    static const char synopsis[] = "SCENE [options]   (SCENE: a file or a built-in name)";
    solve_args a = {0};
    a.solver = "shooting";
    a.ff = "default";
    const cli_option options[] = {
        {"--solver", CLI_STRING, &a.solver, "NAME  direct|jacobi|gauss-seidel|shooting (shooting)"},
        {"--iterations", CLI_INT, &a.iterations, "N  stop after N rounds or shots"},
        {"--tolerance", CLI_DOUBLE, &a.tolerance,
         "T  gathering: largest relative change; shooting: unshot power fraction (1e-6)"},
        {"--omega", CLI_DOUBLE, &a.omega, "W  over-relaxation in (0, 2) (1)"},
        {"--ambient", CLI_FLAG, &a.ambient, "shooting: report the ambient term"},
        {"--trace", CLI_FLAG, &a.trace, "show every round or shot"},
        {"--json", CLI_FLAG, &a.json, "print one JSON object"},
        {"--ff", CLI_STRING, &a.ff, "METHOD  analytic|hemicube|raycast|montecarlo"},
        {"--ff-samples", CLI_INT, &a.ff_samples, "N  rays or point pairs per form factor"},
        {"--hemicube-res", CLI_INT, &a.hemicube_res, "N  hemicube top-face resolution"},
        {"--patch-size", CLI_DOUBLE, &a.patch_size, "S  longest patch edge (scene units)"},
        {"--element-size", CLI_DOUBLE, &a.element_size, "S  longest element edge (scene units)"},
        {"--elements", CLI_SIZE, &a.elements, "N  approximate element count"},
        {"--max-memory", CLI_DOUBLE, &a.max_memory, "MIB  memory budget for matrices (2048)"},
        {"--threads", CLI_INT, &a.threads, "N  worker threads (all cores)"},
        {"--seed", CLI_SIZE, &a.seed, "S  random seed (0)"},
        {"--quiet", CLI_FLAG, &a.quiet, "no notes on stderr"},
        {0},
    };
    const char *positional[1];
    int count;
    int status = cli_parse("solve", synopsis, options, argc, argv, positional, 1, &count);
    if (status) return status < 0 ? 0 : status;
    if (count != 1) return cli_error(EXIT_USAGE, "solve: which scene? (usage: radiosity solve %s)", synopsis);
    int kind = rad_solver_kind_parse(a.solver);
    if (kind < 0)
        return cli_error(EXIT_USAGE, "solve: unknown solver '%s' (direct, jacobi, gauss-seidel, "
                                     "shooting)", a.solver);
    int ff_method = cli_parse_ff_method(a.ff);
    if (ff_method < 0)
        return cli_error(EXIT_USAGE, "solve: unknown form-factor method '%s' (analytic, hemicube, "
                                     "raycast, montecarlo)", a.ff);
    if (a.max_memory < 0) return cli_error(EXIT_USAGE, "solve: --max-memory must be positive");
    if (a.patch_size < 0 || a.element_size < 0)
        return cli_error(EXIT_USAGE, "solve: sizes must be positive");

    rad_context *ctx = cli_context(a.threads, a.seed, a.max_memory, a.quiet);
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    int exit_status = 0;
    rad_status rs = cli_load_scene(ctx, positional[0], &scene);
    rad_mesh_options mesh = {a.patch_size, a.element_size, a.elements};
    rad_ff_options ff = {(rad_ff_method)ff_method, a.ff_samples, a.hemicube_res};
    if (!rs) rs = rad_system_create(ctx, scene, &mesh, &ff, &system);
    trace_log trace = {system, a.json, kind == RAD_SOLVER_SHOOTING, stdout, NULL, 0, 0};
    if (!rs) {
        rad_solve_options solve = {0};
        solve.solver = (rad_solver_kind)kind;
        solve.max_iterations = a.iterations;
        solve.tolerance = a.tolerance;
        solve.omega = a.omega;
        solve.ambient = a.ambient;
        if (a.trace) {
            solve.trace = on_trace;
            solve.trace_user = &trace;
            if (a.json) trace.out = open_memstream(&trace.buffer, &trace.size);
        }
        rad_solve_report report;
        rs = rad_solve(system, &solve, &report);
        if (trace.out != stdout && trace.out) fclose(trace.out);
        if (!rs) {
            if (a.json) print_json(system, &solve, &report, a.trace ? &trace : NULL);
            else print_table(system, &solve, &report);
        }
    }
    if (rs) exit_status = cli_fail(ctx, rs);
    free(trace.buffer);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
