/* main.c - the radiosity command-line tool: dispatch to commands. */
#include "cli.h"

#include <errno.h>
#include <limits.h>
#include <string.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"solve", cmd_solve, "solve a scene and print the radiosity of each surface"},
    {"formfactors", cmd_formfactors, "print the form factors between a scene's surfaces"},
    {"render", cmd_render, "render an image of the radiosity solution"},
    {"pathtrace", cmd_pathtrace, "render a path-traced reference image"},
    {"compare", cmd_compare, "compare two images (RMSE, relative MSE, PSNR)"},
    {"bake", cmd_bake, "export the solution as a mesh with vertex colours"},
    {"scenes", cmd_scenes, "list the built-in scenes (or export one)"},
    {"solvers", cmd_solvers, "list the solvers and form-factor methods, with their options"},
    {"photonmap", cmd_photonmap, "render an image by photon mapping"},
};
#define COMMAND_COUNT (sizeof commands / sizeof commands[0])

static void usage(FILE *out) {
    fprintf(out, "usage: radiosity COMMAND [options]\n\n"
                 "Radiosity global illumination: patches exchanging diffuse light.\n\ncommands:\n");
    for (size_t i = 0; i < COMMAND_COUNT; ++i)
        fprintf(out, "  %-12s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\nradiosity COMMAND --help shows a command's options; radiosity --version its "
                 "version.\n");
}

/* Every command's output to stdout is checked once, here: a full disk or a closed pipe
 * (`solve --json > /dev/full`) is an error, not exit 0. */
static int finish(int status) {
    int failed = fflush(stdout) != 0 || ferror(stdout);
    int error = errno;
    if (fclose(stdout) != 0 && !failed) {
        failed = 1;
        error = errno;
    }
    if (failed && status == 0)
        return cli_error(1, "cannot write to standard output: %s",
                         error ? strerror(error) : "write error");
    return status;
}

static int run(int argc, char **argv) {
    if (argc < 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    const char *name = argv[1];
    if (strcmp(name, "--help") == 0 || strcmp(name, "-h") == 0 || strcmp(name, "help") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(name, "--version") == 0) {
        printf("radiosity %s\n", rad_version());
        return 0;
    }
    for (size_t i = 0; i < COMMAND_COUNT; ++i)
        if (strcmp(commands[i].name, name) == 0) return commands[i].run(argc - 2, argv + 2);
    return cli_error(EXIT_USAGE, "unknown command '%s' (radiosity --help lists them)", name);
}

int main(int argc, char **argv) {
#if defined(__GLIBC__)
    /* Large arrays from the heap and kept there when freed, not fresh mapped pages each time:
     * the hierarchy allocates and frees its link arrays (about 90 MB on Sponza) at every
     * refinement, and zeroing their new pages was 7% of Sponza's processor time. Measured
     * (docs/hierarchical.md): Sponza's solve 10% less processor time, 50 MB more peak memory.
     * Blocks of MMAP_FROM and more are still mapped, and unmapped when freed: at 10^6
     * triangles the refinement's link arrays of several hundred MB each, kept in the heap,
     * left holes the next ones did not fit: its peak 4.0 -> 2.9 GB (docs/hierarchical.md,
     * "Sixteenth session"). */
    enum { MMAP_FROM = 128 << 20 };
    mallopt(M_MMAP_THRESHOLD, MMAP_FROM);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
    /* No M_TOP_PAD: the importer's child runs under RLIMIT_AS (--max-memory), and a padded
     * heap asked for more address space than a small budget allows (cli_formfactors). */
#endif
    return finish(run(argc, argv));
}
