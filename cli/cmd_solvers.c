/* cmd_solvers.c - `radiosity solvers`: what the library's registries hold, the solvers and the
 * form-factor methods, each with its description, capabilities and own options. */
#include "cli.h"

static void print_options(const rad_method_option *options, size_t count) {
    for (size_t k = 0; k < count; ++k)
        printf("      --%-14s %s\n", options[k].name, options[k].help);
}

int cmd_solvers(int argc, char **argv) {
    static const char synopsis[] = "  (lists the solvers and form-factor methods)";
    const char *positional[1];
    int count;
    int status = cli_parse("solvers", synopsis, NULL, argc, argv, positional, 0, &count);
    if (status) return status < 0 ? 0 : status;
    static const struct {
        unsigned flag;
        const char *name;
    } capabilities[] = {
        {RAD_SOLVER_SHOOTS, "shoots"},           {RAD_SOLVER_ITERATIVE, "iterative"},
        {RAD_SOLVER_NEEDS_MATRIX, "needs the matrix"}, {RAD_SOLVER_NEEDS_CAMERA, "needs a camera"},
        {RAD_SOLVER_KEEPS_UNSHOT, "keeps unshot light"},
        {RAD_SOLVER_NEEDS_UNSHOT, "resumes only from solutions with unshot light"},
    };
    const rad_solver_info *preferred = rad_solver_get(RAD_SOLVER_DEFAULT);
    printf("solvers (--solver NAME):\n");
    for (size_t i = 0; i < rad_solver_count(); ++i) {
        const rad_solver_info *info = rad_solver_at(i);
        printf("  %-14s %s%s\n", info->name, info->description,
               info == preferred ? " (default)" : "");
        printf("      %-16s", (info->capabilities & RAD_SOLVER_SHOOTS) ? "shoots" : "gathers");
        int first = 1;
        for (size_t k = 1; k < sizeof capabilities / sizeof capabilities[0]; ++k)
            if (info->capabilities & capabilities[k].flag) {
                printf("%s%s", first ? "" : ", ", capabilities[k].name);
                first = 0;
            }
        printf("\n");
        print_options(info->options, info->option_count);
    }
    const char *default_method = rad_ff_method_name(RAD_FF_DEFAULT);
    printf("\nform-factor methods (--ff METHOD):\n");
    for (size_t i = 0; i < rad_ff_method_count(); ++i) {
        const rad_ff_method_info *info = rad_ff_method_at(i);
        printf("  %-14s %s%s\n", info->name, info->description,
               info->name == default_method ? " (default)" : "");
        print_options(info->options, info->option_count);
    }
    return 0;
}
