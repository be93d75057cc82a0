/* options.c - the declarative option parser and the shared helpers of every command. */
#include "cli.h"
#include "light_options.h"
#include "interrupt.h"
#include "progress.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int cli_error(int exit_status, const char *format, ...) {
    va_list args;
    va_start(args, format);
    fputs("radiosity: ", stderr);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
    return exit_status;
}

void cli_print_help(FILE *out, const char *command, const char *synopsis,
                    const cli_option *options) {
    fprintf(out, "usage: radiosity %s %s\n", command, synopsis);
    if (!options || !options->name) return;
    fprintf(out, "\noptions:\n");
    for (const cli_option *o = options; o->name; ++o) fprintf(out, "  %-18s %s\n", o->name, o->help);
    fprintf(out, "  %-18s %s\n", "--help", "show this help");
}

/* A memory size's unit after its number (CLI_MEMORY): none or M (MiB, MB) is MiB; K, G and T (each with
 * an optional iB or B) scale it by 1024 steps. *end moves past a unit it knows; 1 otherwise. */
static double memory_unit(const char *unit, char **end) {
    static const char letters[] = "KMGT";
    const char *at = *unit ? strchr(letters, unit[0] & ~0x20) : NULL;
    if (!at) return 1;
    const char *rest = unit + 1;
    if ((rest[0] == 'i' || rest[0] == 'I') && (rest[1] == 'B' || rest[1] == 'b')) rest += 2;
    else if (rest[0] == 'B' || rest[0] == 'b') rest += 1;
    if (*rest) return 1;
    *end = (char *)rest;
    return ldexp(1.0, 10 * (int)(at - letters - 1));
}

static int parse_value(const char *command, const cli_option *o, const char *text) {
    char *end;
    errno = 0;
    switch (o->kind) {
    case CLI_FLAG: break;
    case CLI_INT: {
        long value = strtol(text, &end, 10);
        if (end == text || *end || errno || value < 0 || value > 2147483647L)
            return cli_error(EXIT_USAGE, "%s: %s wants a whole number >= 0, not '%s'", command,
                             o->name, text);
        *(int *)o->target = (int)value;
        break;
    }
    case CLI_SIZE: {
        if (text[0] == '-')
            return cli_error(EXIT_USAGE, "%s: %s wants a whole number >= 0, not '%s'", command,
                             o->name, text);
        unsigned long long value = strtoull(text, &end, 10);
        if (end == text || *end || errno)
            return cli_error(EXIT_USAGE, "%s: %s wants a whole number >= 0, not '%s'", command,
                             o->name, text);
        *(size_t *)o->target = (size_t)value;
        break;
    }
    case CLI_DOUBLE:
    case CLI_MEMORY: {
        double value = strtod(text, &end);
        int memory = o->kind == CLI_MEMORY;
        if (memory && end != text) value *= memory_unit(end, &end);
        if (end != text && !*end && errno == ERANGE)
            return cli_error(EXIT_USAGE, "%s: %s: '%s' is out of range (a double is %g to %g)",
                             command, o->name, text, DBL_MIN, DBL_MAX);
        if (end == text || *end || errno || !isfinite(value))
            return cli_error(EXIT_USAGE, "%s: %s wants a number%s, not '%s'", command, o->name,
                             memory ? " of MiB, or a size such as 512M or 2G" : "", text);
        if (memory && !(value >= 1 && value <= 1073741824.0))
            return cli_error(EXIT_USAGE, "%s: %s wants MiB from 1 to 1073741824 (1 PiB), not %g",
                             command, o->name, value);
        *(double *)o->target = value;
        break;
    }
    case CLI_STRING: *(const char **)o->target = text; break;
    case CLI_VEC3: {
        double *v = o->target;
        const char *s = text;
        for (int k = 0; k < 3; ++k) {
            v[k] = strtod(s, &end);
            if (end == s || !isfinite(v[k]) || (k < 2 && *end != ',') || (k == 2 && *end))
                return cli_error(EXIT_USAGE, "%s: %s wants X,Y,Z, not '%s'", command, o->name, text);
            s = end + 1;
        }
        break;
    }
    }
    return 0;
}

/* Bounds of the options every command shares (docs/errors.md, "Limits"): given explicitly,
 * --threads is 1 to 4096 (left out, it takes its default; --max-memory's bounds are its kind's,
 * CLI_MEMORY). */
static int check_shared_option(const char *command, const cli_option *o) {
    if (strcmp(o->name, "--threads") == 0 && o->kind == CLI_INT &&
        (*(int *)o->target < 1 || *(int *)o->target > CLI_MAX_THREADS))
        return cli_error(EXIT_USAGE, "%s: --threads wants a whole number from 1 to %d, not %d",
                         command, CLI_MAX_THREADS, *(int *)o->target);
    return 0;
}

int cli_parse(const char *command, const char *synopsis, const cli_option *options, int argc,
              char **argv, const char **positional, int max_positional, int *positional_count) {
    *positional_count = 0;
    for (int i = 0; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            cli_print_help(stdout, command, synopsis, options);
            return -1;
        }
        if (arg[0] == '-' && arg[1] != '\0') {
            const char *equals = strchr(arg, '=');
            size_t name_length = equals ? (size_t)(equals - arg) : strlen(arg);
            const cli_option *found = NULL;
            for (const cli_option *o = options; o && o->name; ++o)
                if (strlen(o->name) == name_length && strncmp(o->name, arg, name_length) == 0)
                    found = o;
            if (!found)
                return cli_error(EXIT_USAGE, "%s: unknown option '%s' (radiosity %s --help)",
                                 command, arg, command);
            if (found->kind == CLI_FLAG) {
                if (equals) return cli_error(EXIT_USAGE, "%s: %s takes no value", command, found->name);
                *(int *)found->target = 1;
                continue;
            }
            const char *value = equals ? equals + 1 : (i + 1 < argc ? argv[++i] : NULL);
            if (!value) return cli_error(EXIT_USAGE, "%s: %s needs a value", command, found->name);
            int status = parse_value(command, found, value);
            if (!status) status = check_shared_option(command, found);
            if (status) return status;
            continue;
        }
        if (*positional_count >= max_positional)
            return cli_error(EXIT_USAGE, "%s: unexpected argument '%s' (usage: radiosity %s %s)",
                             command, arg, command, synopsis);
        positional[(*positional_count)++] = arg;
    }
    return 0;
}

static void log_to_stderr(void *user, rad_log_level level, const char *message) {
    int quiet = *(int *)user;
    if (quiet && level != RAD_LOG_WARNING) return;
    fprintf(stderr, "radiosity: %s%s\n", level == RAD_LOG_WARNING ? "warning: " : "", message);
}

static int quiet_flag;

/* The progress callback: no display, only Ctrl-C (interrupt.h) asking the library to stop. */
static int stop_when_interrupted(void *user, const char *phase, double done, double total) {
    (void)user, (void)phase, (void)done, (void)total;
    return cli_interrupted();
}

rad_context *cli_context(int threads, uint64_t seed, double max_memory_mib, int quiet) {
    quiet_flag = quiet;
    cli_interrupt_install();
    rad_context_options options = {0};
    options.log = log_to_stderr;
    options.log_user = &quiet_flag;
    options.progress = stop_when_interrupted;
    options.threads = threads;
    options.seed = seed;
    options.max_memory = max_memory_mib > 0 ? (uint64_t)(max_memory_mib * 1048576.0) : 0;
    rad_context *ctx = NULL;
    rad_status status = rad_context_create(&options, &ctx);
    if (status) {
        cli_error(1, "cannot create a context: %s", rad_status_name(status));
        exit(1);
    }
    return ctx;
}

int cli_fail(rad_context *ctx, rad_status status) {
    const char *message = rad_context_error(ctx);
    if (status == RAD_ERROR_CANCELLED && cli_interrupted()) {
        cli_error(1, "interrupted (%s)", message && *message ? message : "cancelled");
        return cli_interrupt_exit_status();
    }
    return cli_error(1, "%s", message && *message ? message : rad_status_name(status));
}

rad_status cli_load_scene(rad_context *ctx, const char *name, rad_scene **out) {
    double start = cli_seconds();
    int builtin = 0;
    for (size_t i = 0; i < rad_builtin_scene_count() && !builtin; ++i)
        builtin = strcmp(rad_builtin_scene_name(i), name) == 0;
    rad_status status = builtin ? rad_scene_builtin(ctx, name, out) : rad_scene_load(ctx, name, out);
    if (!status && (status = cli_lights_apply(*out))) { /* --sky, --sun, --ies */
        rad_scene_destroy(*out);
        *out = NULL;
    }
    if (!status)
        cli_stage("scene", "%s%s, %.2f s", name, builtin ? " (built in)" : "", cli_seconds() - start);
    return status;
}
