/* fuzz_options.c - libFuzzer target for the command-line option parser (cli/options.c
 * cli_parse): the input is split at NUL bytes into argv and parsed against a table with one
 * option of every kind. The parser prints usage errors and help: scripts/fuzz.sh runs it with
 * -close_fd_mask=3 (libFuzzer keeps its own reports). */
#include "cli.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_MAX_ARGS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    /* argv: the input split at NUL bytes, each argument its own exact-size allocation. */
    char *argv[FUZZ_MAX_ARGS];
    int argc = 0;
    for (size_t start = 0; start <= size && argc < FUZZ_MAX_ARGS;) {
        const uint8_t *nul = memchr(data + start, 0, size - start);
        size_t length = nul ? (size_t)(nul - (data + start)) : size - start;
        argv[argc] = malloc(length + 1);
        if (!argv[argc]) break;
        memcpy(argv[argc], data + start, length);
        argv[argc++][length] = '\0';
        start += length + 1;
    }

    int flag = 0, whole = 0;
    size_t count = 0;
    double number = 0, vector[3] = {0, 0, 0};
    const char *text = NULL;
    const cli_option options[] = {
        {"--flag", CLI_FLAG, &flag, "a flag"},
        {"--int", CLI_INT, &whole, "N  a whole number"},
        {"--size", CLI_SIZE, &count, "N  a count"},
        {"--double", CLI_DOUBLE, &number, "X  a number"},
        {"--string", CLI_STRING, &text, "S  a string"},
        {"--vec3", CLI_VEC3, vector, "X,Y,Z  a vector"},
        {"-o", CLI_STRING, &text, "PATH  a short option"},
        {0},
    };
    const char *positional[2];
    int positional_count = 0;
    int status = cli_parse("fuzz", "[A [B]]", options, argc, argv, positional, 2,
                           &positional_count);
    /* What the parser promises: a known status, at most two positionals, finite numbers. */
    if (status != 0 && status != -1 && status != EXIT_USAGE) abort();
    if (positional_count < 0 || positional_count > 2) abort();
    if (status == 0) {
        if (whole < 0 || number != number || vector[0] != vector[0]) abort();
        for (int i = 0; i < positional_count; ++i)
            if (strlen(positional[i]) > size) abort();
    }
    for (int i = 0; i < argc; ++i) free(argv[i]);
    return 0;
}
