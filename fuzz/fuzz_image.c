/* fuzz_image.c - libFuzzer target for the linear image readers that `compare` uses
 * (src/io/image.c rad_image_read: .pfm parsed here, .hdr through stb_image). The first byte
 * picks the format; the rest is written to a temporary file, since the reader takes a path. */
#include "io/image.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FUZZ_MAX_MEMORY (64u << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A private directory for the temporary images, removed at exit. */
static char directory[64];
static void remove_directory(void) {
    char path[96];
    snprintf(path, sizeof path, "%s/input.pfm", directory);
    unlink(path);
    snprintf(path, sizeof path, "%s/input.hdr", directory);
    unlink(path);
    rmdir(directory);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (!directory[0]) {
        const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        snprintf(directory, sizeof directory, "%s/rad-fuzz-image-XXXXXX", base);
        if (!mkdtemp(directory)) abort();
        atexit(remove_directory);
    }
    if (size < 1) return 0;
    char path[96];
    snprintf(path, sizeof path, "%s/input.%s", directory, (data[0] & 1) ? "hdr" : "pfm");
    FILE *file = fopen(path, "wb");
    if (!file) abort();
    if (size > 1 && fwrite(data + 1, 1, size - 1, file) != size - 1) abort();
    if (fclose(file)) abort();

    rad_context_options options = {0};
    options.threads = 1;
    options.max_memory = FUZZ_MAX_MEMORY;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return 0;
    rad_image *image = NULL;
    if (rad_image_read(ctx, path, &image) == RAD_OK) {
        /* Every pixel of an image that was read must be readable. */
        double sum = 0;
        size_t count = (size_t)image->width * (size_t)image->height * 3;
        for (size_t i = 0; i < count; ++i) sum += image->pixels[i];
        if (image->width < 1 || image->height < 1) abort();
        (void)sum;
    }
    rad_image_free(image);
    rad_context_destroy(ctx);
    return 0;
}
