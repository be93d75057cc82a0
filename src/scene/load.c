/* load.c - scene loading by file kind, and the list of built-in scenes. */
#include "scene/scene.h"
#include "scene/camera.h"

#include "scene/mgf.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char four_walls_ffm[] =
    "# The four-surface room of the lecture notes, seen in cross-section.\n"
    "# Adjacent surfaces receive 1/4 of the energy leaving a surface, the opposite one 1/2.\n"
    "patch ceiling area 1 reflectance 0.75 emission 0\n"
    "patch floor   area 1 reflectance 0.10 emission 0\n"
    "patch left    area 1 reflectance 0.75 emission 0\n"
    "patch right   area 1 reflectance 0.01 emission 1   # a window\n"
    "ff ceiling floor 0.5\nff ceiling left 0.25\nff ceiling right 0.25\n"
    "ff floor ceiling 0.5\nff floor left 0.25\nff floor right 0.25\n"
    "ff left right 0.5\nff left ceiling 0.25\nff left floor 0.25\n"
    "ff right left 0.5\nff right ceiling 0.25\nff right floor 0.25\n";

typedef struct builtin_entry {
    const char *name;
    const char *description;
    const char *ffm; /* NULL: geometry, built by rad_builtin_geometry */
} builtin_entry;

static const builtin_entry builtins[] = {
    {"four-walls", "the four-surface room of the lecture notes (patch system)", four_walls_ffm},
    {"cornell", "the Cornell box, Cornell University Program of Computer Graphics data (mm)", NULL},
    {"cornell-mirror", "the Cornell box with a mirror tall block and a glass sphere", NULL},
    {"two-squares", "two opposed unit squares one unit apart, one emitting", NULL},
    {"unit-cube", "a closed unit cube facing inwards, reflectance 0.5, the top emitting", NULL},
};
#define BUILTIN_COUNT (sizeof builtins / sizeof builtins[0])

size_t rad_builtin_scene_count(void) { return BUILTIN_COUNT; }
const char *rad_builtin_scene_name(size_t index) {
    return index < BUILTIN_COUNT ? builtins[index].name : NULL;
}
const char *rad_builtin_scene_description(size_t index) {
    return index < BUILTIN_COUNT ? builtins[index].description : NULL;
}

rad_status rad_scene_builtin(rad_context *ctx, const char *name, rad_scene **out) {
    if (!ctx || !name || !out) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    for (size_t i = 0; i < BUILTIN_COUNT; ++i) {
        if (strcmp(builtins[i].name, name) != 0) continue;
        if (builtins[i].ffm)
            return rad_scene_parse_ffm(ctx, builtins[i].ffm, strlen(builtins[i].ffm), name, out);
        return rad_builtin_geometry(ctx, name, out);
    }
    return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                    "no built-in scene '%s' (radiosity scenes lists them)", name);
}

static int has_extension(const char *path, const char *extension) {
    size_t n = strlen(path), m = strlen(extension);
    if (n < m) return 0;
    for (size_t i = 0; i < m; ++i) {
        char a = path[n - m + i], b = extension[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

/* Reads a whole file into memory (NUL-terminated), once, so a pipe or a device will do. It is
 * opened without blocking (a FIFO with no writer reads as empty instead of waiting for one). */
static rad_status read_file(rad_context *ctx, const char *path, char **text, size_t *length) {
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat info;
    if (fd < 0 || fstat(fd, &info) != 0) {
        int error = errno;
        if (fd >= 0) close(fd);
        return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(error));
    }
    if (S_ISDIR(info.st_mode)) {
        close(fd);
        return rad_fail(ctx, RAD_ERROR_IO, "%s: is a directory, not a file", path);
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    FILE *file = fdopen(fd, "rb");
    if (!file) {
        int error = errno;
        close(fd);
        return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(error));
    }
    size_t capacity = 4096, used = 0;
    char *buffer = rad_alloc(ctx, capacity, 1);
    if (!buffer) {
        fclose(file);
        return RAD_ERROR_NO_MEMORY;
    }
    for (;;) {
        if (used + 1 >= capacity) {
            /* A file without end (/dev/zero, a runaway pipe) stops at the memory budget. */
            rad_status over = rad_check_budget(ctx, 2.0 * (double)capacity, path);
            if (over) {
                rad_free(ctx, buffer);
                fclose(file);
                return over;
            }
            char *grown = rad_realloc(ctx, buffer, capacity * 2, 1);
            if (!grown) {
                rad_free(ctx, buffer);
                fclose(file);
                return RAD_ERROR_NO_MEMORY;
            }
            buffer = grown;
            capacity *= 2;
        }
        size_t got = fread(buffer + used, 1, capacity - used - 1, file);
        used += got;
        if (got == 0) break;
    }
    int failed = ferror(file);
    fclose(file);
    if (failed) {
        rad_free(ctx, buffer);
        return rad_fail(ctx, RAD_ERROR_IO, "%s: read error", path);
    }
    buffer[used] = '\0';
    *text = buffer;
    *length = used;
    return RAD_OK;
}

/* Scene files are read more than once (the import checks, assimp, its .mtl and .bin), so only
 * regular files are taken: a FIFO, a device (/dev/zero) or a directory is refused with one
 * line. The file is opened without blocking (a FIFO with no writer would wait forever). */
static rad_status check_regular(rad_context *ctx, const char *path) {
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
    struct stat info;
    int failed = fstat(fd, &info);
    int error = errno;
    close(fd);
    if (failed) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(error));
    if (S_ISREG(info.st_mode)) return RAD_OK;
    const char *kind = S_ISDIR(info.st_mode)    ? "a directory"
                       : S_ISFIFO(info.st_mode) ? "a FIFO (pipe)"
                       : S_ISCHR(info.st_mode)  ? "a character device"
                       : S_ISBLK(info.st_mode)  ? "a block device"
                       : S_ISSOCK(info.st_mode) ? "a socket"
                                                : "something else";
    return rad_fail(ctx, RAD_ERROR_IO, "%s: is %s, not a regular file; scenes are read from "
                    "files (save it to one first)", path, kind);
}

rad_status rad_scene_load(rad_context *ctx, const char *path, rad_scene **out) {
    if (!ctx || !path || !out) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    if (has_extension(path, ".mgf")) {
        rad_status regular = check_regular(ctx, path);
        return regular ? regular : rad_scene_load_mgf(ctx, path, out);
    }
    if (!has_extension(path, ".ffm")) {
        rad_status regular = check_regular(ctx, path);
        rad_status status = regular ? regular : rad_scene_import(ctx, path, out);
        if (!status) status = rad_scene_add_back_faces(*out); /* glTF doubleSided */
        if (status) {
            rad_scene_destroy(*out);
            *out = NULL;
        }
        if (!status) rad_scene_auto_camera(*out); /* no camera in the file: an automatic one */
        return status;
    }
    char *text = NULL;
    size_t length = 0;
    rad_status status = read_file(ctx, path, &text, &length);
    if (status) return status;
    if (length == 0) {
        rad_free(ctx, text);
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: empty file", path);
    }
    status = rad_scene_parse_ffm(ctx, text, length, path, out);
    rad_free(ctx, text);
    if (!status && (status = rad_file_list_add(ctx, &(*out)->files, path))) {
        rad_scene_destroy(*out);
        *out = NULL;
    }
    return status;
}
