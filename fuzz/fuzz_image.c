/* fuzz_image.c - libFuzzer target for the linear image readers that `compare` uses
 * (src/image/image.c rad_image_read: .pfm and .hdr parsed there, .exr through OpenEXR's C API in
 * src/image/image_exr.c). The first byte picks the format (low two bits 2: EXR, else bit 0: HDR or
 * PFM); the rest is written to a temporary file, since the reader takes a path. */
#include "input_file.h"
#include "image/image.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FUZZ_MAX_MEMORY (64u << 20)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A private directory for the temporary images, removed at exit. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    const char *format = (data[0] & 3) == 2 ? "exr" : (data[0] & 1) ? "hdr" : "pfm";
    const char *path = fuzz_write_input(format, data + 1, size - 1);

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
