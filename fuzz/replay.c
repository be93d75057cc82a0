/* replay.c - runs a fuzz target's LLVMFuzzerTestOneInput over files, without libFuzzer, so every
 * build (gcc included) replays the seed corpus and every crash ever found as a ctest.
 *
 *   fuzz_NAME_replay PATH...     each PATH is a file or a directory of files (not recursive);
 *                                a PATH that does not exist is skipped.
 *
 * An input passes when the target returns; a crash or a sanitizer report ends the program with
 * a failing status. The last line is `N passed, 0 failed`. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int replayed;

static int replay_file(const char *path) {
    FILE *file = fopen(path, "rb");
    if (!file) {
        fprintf(stderr, "replay: cannot open %s\n", path);
        return 1;
    }
    size_t capacity = 4096, size = 0;
    uint8_t *data = malloc(capacity);
    for (size_t got; data && (got = fread(data + size, 1, capacity - size, file)) > 0;) {
        size += got;
        if (size == capacity) {
            uint8_t *grown = realloc(data, capacity *= 2);
            if (!grown) free(data);
            data = grown;
        }
    }
    fclose(file);
    if (!data) {
        fprintf(stderr, "replay: out of memory reading %s\n", path);
        return 1;
    }
    /* A copy of exactly `size` bytes, so ASan sees reads past the end of the input. */
    uint8_t *exact = malloc(size ? size : 1);
    if (!exact) {
        free(data);
        return 1;
    }
    memcpy(exact, data, size);
    free(data);
    fprintf(stderr, "replay: %s (%zu bytes)\n", path, size);
    LLVMFuzzerTestOneInput(exact, size);
    free(exact);
    ++replayed;
    return 0;
}

static int compare_names(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int replay_directory(const char *path) {
    DIR *dir = opendir(path);
    if (!dir) return 1;
    char **names = NULL;
    size_t count = 0, capacity = 0;
    int failed = 0;
    for (struct dirent *entry; (entry = readdir(dir));) {
        if (entry->d_name[0] == '.') continue;
        if (count == capacity) {
            capacity = capacity ? 2 * capacity : 64;
            char **grown = realloc(names, capacity * sizeof *names);
            if (!grown) { failed = 1; break; }
            names = grown;
        }
        size_t length = strlen(path) + strlen(entry->d_name) + 2;
        if (!(names[count] = malloc(length))) { failed = 1; break; }
        snprintf(names[count++], length, "%s/%s", path, entry->d_name);
    }
    closedir(dir);
    qsort(names, count, sizeof *names, compare_names); /* the same order every run */
    for (size_t i = 0; i < count; ++i) {
        struct stat info;
        if (!failed && stat(names[i], &info) == 0 && S_ISREG(info.st_mode))
            failed = replay_file(names[i]);
        free(names[i]);
    }
    free(names);
    return failed;
}

int main(int argc, char **argv) {
    int failed = 0;
    for (int i = 1; i < argc && !failed; ++i) {
        struct stat info;
        if (stat(argv[i], &info) != 0) {
            fprintf(stderr, "replay: %s does not exist; skipped\n", argv[i]);
            continue;
        }
        failed = S_ISDIR(info.st_mode) ? replay_directory(argv[i]) : replay_file(argv[i]);
    }
    if (!failed && replayed == 0) {
        fprintf(stderr, "replay: no inputs\n");
        failed = 1;
    }
    printf("%d passed, %d failed\n", replayed, failed);
    return failed;
}
