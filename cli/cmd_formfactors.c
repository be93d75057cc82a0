/* cmd_formfactors.c - `radiosity formfactors`: the form factors between the named input
 * surfaces of a scene (each surface's elements combined by area), as a table or JSON. Row i is
 * the fraction of the energy leaving surface i that arrives at surface j. */
#include "cli.h"
#include "json.h"

#include <stdlib.h>
#include <string.h>

typedef struct formfactors_args {
    const char *ff;
    int ff_samples, hemicube_res, json, threads, quiet;
    double patch_size, element_size, max_memory;
    size_t elements;
    uint64_t seed;
} formfactors_args;

static void print_json(const rad_system *system, const double *matrix) {
    size_t n = rad_system_surface_count(system);
    printf("{\"surfaces\": [");
    for (size_t i = 0; i < n; ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        json_surface_open(stdout, i, info.name, info.area);
        printf("}");
    }
    printf("],\n \"form_factors\": [");
    for (size_t i = 0; i < n; ++i) {
        printf(i ? ",\n  [" : "\n  [");
        for (size_t j = 0; j < n; ++j) {
            if (j) printf(", ");
            json_number(stdout, matrix[i * n + j]);
        }
        printf("]");
    }
    printf("]}\n");
}

static void print_table(const rad_system *system, const double *matrix, const char *method,
                        double seconds) {
    size_t n = rad_system_surface_count(system);
    int width = 8;
    for (size_t i = 0; i < n; ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        int length = (int)strlen(info.name);
        if (length > width) width = length;
    }
    if (width > 16) width = 16;
    printf("form factors (%s): %zu surfaces, %zu patches, %zu elements, %.3g s\n", method, n,
           rad_system_patch_count(system), rad_system_element_count(system), seconds);
    printf("row i: the fraction of the energy leaving surface i that arrives at surface j\n\n");
    printf("%-*s %12s ", width, "from \\ to", "area");
    for (size_t j = 0; j < n; ++j) {
        rad_surface_info info;
        rad_system_surface(system, j, &info);
        printf(" %*.*s", width > 9 ? width : 9, width, info.name);
    }
    printf("  %9s\n", "sum");
    for (size_t i = 0; i < n; ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        printf("%-*.*s %12.6g ", width, width, info.name, info.area);
        double sum = 0;
        for (size_t j = 0; j < n; ++j) {
            printf(" %*.6f", width > 9 ? width : 9, matrix[i * n + j]);
            sum += matrix[i * n + j];
        }
        printf("  %9.6f\n", sum);
    }
}

int cmd_formfactors(int argc, char **argv) {
    static const char synopsis[] = "SCENE [options]   (SCENE: a file or a built-in name)";
    formfactors_args a = {0};
    a.ff = "default";
    char ff_help[200], names[160];
    snprintf(ff_help, sizeof ff_help, "METHOD  %s (default: docs/formfactors.md)",
             cli_ff_method_names(names, sizeof names, "|"));
    char resolution_help[160];
    const cli_option options[] = {
        {"--ff", CLI_STRING, &a.ff, ff_help},
        {"--ff-samples", CLI_INT, &a.ff_samples, "N  rays or point pairs per form factor"},
        {"--hemicube-res", CLI_INT, &a.hemicube_res,
         cli_ff_option_help(resolution_help, sizeof resolution_help, "N", "hemicube-res")},
        {"--patch-size", CLI_DOUBLE, &a.patch_size, "S  longest patch edge (scene units)"},
        {"--element-size", CLI_DOUBLE, &a.element_size, "S  longest element edge (scene units)"},
        {"--elements", CLI_SIZE, &a.elements, "N  approximate element count"},
        {"--json", CLI_FLAG, &a.json, "print one JSON object"},
        {"--max-memory", CLI_MEMORY, &a.max_memory, "MIB  memory budget, in MiB or as 512M, 2G (2048)"},
        {"--threads", CLI_INT, &a.threads, "N  worker threads (all cores)"},
        {"--seed", CLI_SIZE, &a.seed, "S  random seed (0)"},
        {"--quiet", CLI_FLAG, &a.quiet, "no notes on stderr"},
        {0},
    };
    const char *positional[1];
    int count;
    int status = cli_parse("formfactors", synopsis, options, argc, argv, positional, 1, &count);
    if (status) return status < 0 ? 0 : status;
    if (count != 1)
        return cli_error(EXIT_USAGE, "formfactors: which scene? (usage: radiosity formfactors %s)",
                         synopsis);
    int method = cli_parse_ff_method(a.ff);
    if (method < 0) return cli_unknown_ff_method("formfactors", a.ff);
    if (a.max_memory < 0) return cli_error(EXIT_USAGE, "formfactors: --max-memory must be positive");
    if (a.patch_size < 0 || a.element_size < 0)
        return cli_error(EXIT_USAGE, "formfactors: sizes must be positive");

    rad_context *ctx = cli_context(a.threads, a.seed, a.max_memory, a.quiet);
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    double *matrix = NULL;
    rad_mesh_options mesh = {a.patch_size, a.element_size, a.elements, 0, 0};
    rad_options own = {0};
    cli_ff_option(&own, (rad_ff_method)method, "ff-samples", a.ff_samples);
    cli_ff_option(&own, (rad_ff_method)method, "hemicube-res", a.hemicube_res);
    rad_ff_options ff = {(rad_ff_method)method, 0, 0, &own};
    double start = cli_seconds();
    int exit_status = 0;
    rad_status rs = cli_load_scene(ctx, positional[0], &scene);
    if (!rs) rs = rad_system_create(ctx, scene, &mesh, &ff, &system);
    if (!rs) {
        /* The surface-to-surface table is allocated here, for the library: held to the same
         * budget before any form factor is computed. */
        size_t n = rad_system_surface_count(system);
        char what[64];
        snprintf(what, sizeof what, "the form-factor table of %zu surfaces", n);
        rs = rad_context_check_memory(ctx, 8.0 * (double)n * (double)n, what);
        if (!rs) matrix = calloc(n > 0 ? n * n : 1, sizeof *matrix);
        if (!rs) rs = matrix ? rad_system_surface_form_factors(system, matrix) : RAD_ERROR_NO_MEMORY;
    }
    if (rs) exit_status = cli_fail(ctx, rs);
    else if (a.json) print_json(system, matrix);
    else {
        const char *name = rad_system_ff_method(system);
        print_table(system, matrix, name ? name : a.ff, cli_seconds() - start);
    }
    free(matrix);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
