/* registry.c - the CLI's view of the library's registries of solvers and form-factor methods
 * (rad_solver_at, rad_ff_method_at): the name lists of help lines and errors, and the
 * capability questions the commands ask. No command names a solver or a method itself. */
#include "cli.h"

#include <string.h>

/* Appends `text` to out (size bytes, NUL-terminated), as far as it fits. */
static void append(char *out, size_t size, const char *text) {
    size_t used = strlen(out);
    if (used + 1 < size) snprintf(out + used, size - used, "%s", text);
}

static int registers(const rad_method_option *options, size_t count, const char *name) {
    for (size_t i = 0; i < count; ++i)
        if (strcmp(options[i].name, name) == 0) return 1;
    return 0;
}

static int solver_has_option(const rad_solver_info *info, const char *option) {
    return registers(info->options, info->option_count, option);
}

static int solver_selected(const cli_solver_filter *filter, const rad_solver_info *info) {
    if ((info->capabilities & filter->need) != filter->need) return 0;
    if (info->capabilities & filter->without) return 0;
    return !filter->option || solver_has_option(info, filter->option);
}

const char *cli_solver_names(char *out, size_t size, const cli_solver_filter *filter,
                             const char *separator, const char *last_separator) {
    static const cli_solver_filter all = {0};
    if (!filter) filter = &all;
    size_t total = 0, written = 0;
    for (size_t i = 0; i < rad_solver_count(); ++i) total += solver_selected(filter, rad_solver_at(i));
    out[0] = '\0';
    for (size_t i = 0; i < rad_solver_count(); ++i) {
        const rad_solver_info *info = rad_solver_at(i);
        if (!solver_selected(filter, info)) continue;
        if (written) append(out, size, written + 1 == total ? last_separator : separator);
        append(out, size, info->name);
        ++written;
    }
    return out;
}

/* "METAVAR  names: help" (or "names: help" for a flag): a registered help that starts with
 * its value's name ("E  the threshold ...") keeps it in front, as every option's help does. */
static const char *option_help(char *out, size_t size, const char *names, const char *help,
                               const char *metavar) {
    out[0] = '\0';
    const char *gap = strstr(help, "  ");
    int named = gap && gap > help && strspn(help, "ABCDEFGHIJKLMNOPQRSTUVWXYZ") == (size_t)(gap - help);
    if (named) snprintf(out, size, "%.*s  ", (int)(gap - help), help);
    else if (metavar) snprintf(out, size, "%s  ", metavar);
    append(out, size, names);
    append(out, size, ": ");
    append(out, size, named ? gap + 2 : help);
    return out;
}

const char *cli_solver_option_help(char *out, size_t size, const char *option) {
    char names[200];
    cli_solver_filter filter = {0, 0, option};
    cli_solver_names(names, sizeof names, &filter, ", ", ", ");
    out[0] = '\0';
    for (size_t i = 0; i < rad_solver_count(); ++i) {
        const rad_solver_info *info = rad_solver_at(i);
        for (size_t k = 0; k < info->option_count; ++k)
            if (strcmp(info->options[k].name, option) == 0)
                return option_help(out, size, names, info->options[k].help, NULL);
    }
    return out;
}

const char *cli_ff_option_help(char *out, size_t size, const char *metavar, const char *option) {
    char names[200] = "";
    const char *help = NULL;
    for (size_t i = 0; i < rad_ff_method_count(); ++i) {
        const rad_ff_method_info *info = rad_ff_method_at(i);
        for (size_t k = 0; k < info->option_count; ++k)
            if (strcmp(info->options[k].name, option) == 0) {
                if (names[0]) append(names, sizeof names, ", ");
                append(names, sizeof names, info->name);
                if (!help) help = info->options[k].help;
            }
    }
    out[0] = '\0';
    return help ? option_help(out, size, names, help, metavar) : out;
}

const char *cli_ff_method_names(char *out, size_t size, const char *separator) {
    out[0] = '\0';
    for (size_t i = 0; i < rad_ff_method_count(); ++i) {
        if (i) append(out, size, separator);
        append(out, size, rad_ff_method_at(i)->name);
    }
    return out;
}

int cli_solver_shoots(rad_solver_kind kind) {
    const rad_solver_info *info = rad_solver_get(kind);
    return info && (info->capabilities & RAD_SOLVER_SHOOTS);
}

const char *cli_step_word(rad_solver_kind kind, long n) {
    int one = n == 1;
    if (cli_solver_shoots(kind)) return one ? "shot" : "shots";
    if (kind == RAD_SOLVER_HIERARCHICAL) return one ? "step" : "steps";
    return one ? "round" : "rounds";
}

int cli_solver_takes(rad_solver_kind kind, const char *option) {
    const rad_solver_info *info = rad_solver_get(kind);
    return info && solver_has_option(info, option);
}

int cli_parse_ff_method(const char *name) { return rad_ff_method_parse(name); }

void cli_solver_option(rad_options *bag, rad_solver_kind kind, const char *name, double value) {
    const rad_solver_info *info = rad_solver_get(kind);
    if (value != 0 && info && registers(info->options, info->option_count, name))
        rad_options_set_number(bag, name, value);
}

void cli_ff_option(rad_options *bag, rad_ff_method method, const char *name, double value) {
    const char *method_name = rad_ff_method_name(method); /* the default's own name for 0 */
    for (size_t i = 0; value != 0 && method_name && i < rad_ff_method_count(); ++i) {
        const rad_ff_method_info *info = rad_ff_method_at(i);
        if (strcmp(info->name, method_name) == 0 &&
            registers(info->options, info->option_count, name))
            rad_options_set_number(bag, name, value);
    }
}

int cli_unknown_solver(const char *command, const char *name) {
    char names[200];
    return cli_error(EXIT_USAGE, "%s: unknown solver '%s' (%s)", command, name,
                     cli_solver_names(names, sizeof names, NULL, ", ", ", "));
}

int cli_unknown_ff_method(const char *command, const char *name) {
    char names[200];
    return cli_error(EXIT_USAGE, "%s: unknown form-factor method '%s' (%s)", command, name,
                     cli_ff_method_names(names, sizeof names, ", "));
}
