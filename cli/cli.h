/* cli.h - shared pieces of the command-line tool: option parsing, the context, error exits.
 * The tool uses only the public header. Exit status: 0 ok, 1 error, 2 usage error. */
#ifndef RAD_CLI_H
#define RAD_CLI_H

#include "radiosity.h"

#include <stdio.h>

#define EXIT_USAGE 2
/* The most worker threads --threads may ask for (libgomp crashes on a million). */
#define CLI_MAX_THREADS RAD_MAX_THREADS

typedef enum cli_option_kind {
    CLI_FLAG,    /* int, set to 1 */
    CLI_INT,     /* int, >= 0 */
    CLI_SIZE,    /* size_t */
    CLI_DOUBLE,  /* double, finite */
    CLI_MEMORY,  /* double, MiB: a number of MiB or a size with its unit (512M, 2G), from 1 MiB
                    to 1 PiB (--max-memory) */
    CLI_STRING,  /* const char * */
    CLI_VEC3     /* double[3], "X,Y,Z" */
} cli_option_kind;

typedef struct cli_option {
    const char *name; /* "--iterations" */
    cli_option_kind kind;
    void *target;
    const char *help; /* "N  stop after N rounds or shots" */
} cli_option;

/* Parses argv against the options; positional arguments go to positional[] (at most
 * max_positional). Prints a usage error and returns EXIT_USAGE, or 0 when fine, or -1 after
 * printing help for --help. */
int cli_parse(const char *command, const char *synopsis, const cli_option *options, int argc,
              char **argv, const char **positional, int max_positional, int *positional_count);

/* Prints help for a command: synopsis and options. */
void cli_print_help(FILE *out, const char *command, const char *synopsis,
                    const cli_option *options);

/* A context whose warnings go to stderr (unless quiet). Exits with 1 when it cannot. */
rad_context *cli_context(int threads, uint64_t seed, double max_memory_mib, int quiet);

/* Prints "radiosity: message" for the context's error and returns 1. */
int cli_fail(rad_context *ctx, rad_status status);

/* Prints "radiosity: ..." and returns the given exit status. */
int cli_error(int exit_status, const char *format, ...) __attribute__((format(printf, 2, 3)));

/* Loads SCENE as a built-in name or a file. */
rad_status cli_load_scene(rad_context *ctx, const char *name, rad_scene **out);

/* Parses a form-factor method name; -1 when unknown. */
int cli_parse_ff_method(const char *name);

/* The registries (registry.c). Which solvers a list names: those with every capability in
 * `need`, none in `without`, and (unless NULL) the solver's own option `option`. */
typedef struct cli_solver_filter {
    unsigned need, without;
    const char *option;
} cli_solver_filter;

/* The selected solvers' names joined ("a, b and c" with ", " and " and "); NULL: all. */
const char *cli_solver_names(char *out, size_t size, const cli_solver_filter *filter,
                             const char *separator, const char *last_separator);
/* "shooting, importance: overshooting (...)": the solvers that take an option, and its help. */
const char *cli_solver_option_help(char *out, size_t size, const char *option);
/* "N  hemicube: pixels along the top face (256)": the methods that take an option, the help of
 * the first, after `metavar`. */
const char *cli_ff_option_help(char *out, size_t size, const char *metavar, const char *option);
/* The form-factor methods' names, joined. */
const char *cli_ff_method_names(char *out, size_t size, const char *separator);
/* Nonzero when the solver shoots (RAD_SOLVER_SHOOTS) / takes its own option `option`. */
int cli_solver_shoots(rad_solver_kind kind);
int cli_solver_takes(rad_solver_kind kind, const char *option);
/* What a solver counts, for `n` of them: "shots" (shooting), "steps" (the hierarchy: refine
 * and solve), "rounds" (gathering); singular when n is 1. */
const char *cli_step_word(rad_solver_kind kind, long n);
/* Per-method option bags (rad_options): sets `name` to `value` when the value is nonzero (the
 * flag or number was given) and the chosen solver / form-factor method registered `name`; the
 * others never read it. */
void cli_solver_option(rad_options *bag, rad_solver_kind kind, const char *name, double value);
void cli_ff_option(rad_options *bag, rad_ff_method method, const char *name, double value);
/* The usage errors for a name the registry does not have, listing the names it has; return
 * EXIT_USAGE. */
int cli_unknown_solver(const char *command, const char *name);
int cli_unknown_ff_method(const char *command, const char *name);

/* Wall-clock seconds (monotonic), for timings and progress (pipeline.c). */
double cli_seconds(void);

/* Commands. */
int cmd_solve(int argc, char **argv);
int cmd_scenes(int argc, char **argv);
int cmd_formfactors(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_pathtrace(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_bake(int argc, char **argv);
int cmd_solvers(int argc, char **argv);
int cmd_photonmap(int argc, char **argv);

#endif
