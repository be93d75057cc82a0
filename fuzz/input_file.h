/* input_file.h - for fuzz targets whose reader takes a path: fuzz_write_input writes the input
 * to input.EXTENSION in a directory of its own (in /dev/shm when it can, so the disk is spared),
 * made on the first call and removed at exit with every file written there. */
#ifndef RAD_FUZZ_INPUT_FILE_H
#define RAD_FUZZ_INPUT_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FUZZ_MAX_EXTENSIONS 8

static char fuzz_directory[64];
static char fuzz_paths[FUZZ_MAX_EXTENSIONS][96];
static int fuzz_path_count;

static void fuzz_remove_directory(void) {
    for (int i = 0; i < fuzz_path_count; ++i) unlink(fuzz_paths[i]);
    rmdir(fuzz_directory);
}

/* Writes `size` bytes to the file for `extension` and returns its path (aborts on failure: the
 * fuzzer must not go on without its input). */
static const char *fuzz_write_input(const char *extension, const uint8_t *data, size_t size) {
    if (!fuzz_directory[0]) {
        const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        snprintf(fuzz_directory, sizeof fuzz_directory, "%s/rad-fuzz-XXXXXX", base);
        if (!mkdtemp(fuzz_directory)) abort();
        atexit(fuzz_remove_directory);
    }
    char path[96];
    snprintf(path, sizeof path, "%s/input.%s", fuzz_directory, extension);
    int slot = 0;
    while (slot < fuzz_path_count && strcmp(fuzz_paths[slot], path) != 0) ++slot;
    if (slot == fuzz_path_count) {
        if (slot == FUZZ_MAX_EXTENSIONS) abort();
        memcpy(fuzz_paths[fuzz_path_count++], path, sizeof path);
    }
    FILE *file = fopen(fuzz_paths[slot], "wb");
    if (!file) abort();
    if (size && fwrite(data, 1, size, file) != size) abort();
    if (fclose(file)) abort();
    return fuzz_paths[slot];
}

#endif
