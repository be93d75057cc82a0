/* output_path.c - refuses an output path that names an input file (see output_path.h). */
#include "output_path.h"

#include "cli.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>
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

/* The file written beside an output: FILE.gltf -> FILE.bin (bake), FILE.obj -> FILE.mtl
 * (scenes --export). malloc'd; NULL when there is none. */
static char *companion_of(const char *output) {
    size_t n = strlen(output);
    const char *suffix = n >= 5 && strcasecmp(output + n - 5, ".gltf") == 0  ? ".bin"
                         : n >= 4 && strcasecmp(output + n - 4, ".obj") == 0 ? ".mtl"
                                                                             : NULL;
    if (!suffix) return NULL;
    size_t stem = n - (suffix[1] == 'b' ? 5 : 4);
    char *companion = malloc(stem + 5);
    if (companion) {
        memcpy(companion, output, stem);
        memcpy(companion + stem, suffix, 5);
    }
    return companion;
}

int cli_check_outputs_against_scene(const char *command, const rad_scene *scene,
                                    const char *const *outputs, size_t output_count) {
    size_t count = rad_scene_file_count(scene);
    if (count == 0) return 0;
    const char **files = malloc(count * sizeof *files);
    if (!files) return cli_error(1, "%s: out of memory", command);
    for (size_t i = 0; i < count; ++i) files[i] = rad_scene_file(scene, i);
    int status = 0;
    for (size_t i = 0; i < output_count && !status; ++i) {
        if (!outputs[i]) continue;
        status = cli_check_output_path(command, outputs[i], files, count);
        char *companion = status ? NULL : companion_of(outputs[i]);
        if (companion) status = cli_check_output_path(command, companion, files, count);
        free(companion);
    }
    free(files);
    return status;
}
