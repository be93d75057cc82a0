/* output_path.c - refuses an output path that names an input file (see output_path.h). */
#include "output_path.h"

#include "cli.h"

#include <sys/stat.h>

int cli_check_output_path(const char *command, const char *output, const char *const *inputs,
                          size_t input_count) {
    struct stat out;
    if (!output || stat(output, &out) != 0) return 0; /* a new file cannot be an input */
    for (size_t i = 0; i < input_count; ++i) {
        struct stat in;
        if (!inputs[i] || stat(inputs[i], &in) != 0) continue;
        if (in.st_dev == out.st_dev && in.st_ino == out.st_ino)
            return cli_error(EXIT_USAGE, "%s: the output '%s' is the input '%s'; writing it would "
                             "destroy the input", command, output, inputs[i]);
    }
    return 0;
}
