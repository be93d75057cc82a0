/* image.h - float RGB images and their files: .png (tone mapped, sRGB, 8 bit), .hdr (Radiance
 * RGBE), .pfm (32-bit float, linear), .exr (OpenEXR, 32-bit float or half, linear). Writes go to a temporary file renamed into place, so a
 * failure never leaves a half-written image. */
#ifndef RAD_IO_IMAGE_H
#define RAD_IO_IMAGE_H

#include "core/context.h"
#include "image/tonemap.h"

typedef struct rad_image {
    rad_context *ctx;
    int width, height;
    float *pixels; /* width * height * 3, linear radiance, row 0 at the top */
} rad_image;

rad_status rad_image_new(rad_context *ctx, int width, int height, rad_image **out);
void rad_image_free(rad_image *image);

typedef struct rad_image_write_options {
    double exposure;   /* stops, PNG only */
    rad_tonemap curve; /* PNG only */
    int exr_half;      /* EXR only: 16-bit half floats instead of 32-bit floats */
} rad_image_write_options;

/* Nonzero when the extension of path is one rad_image_write knows. */
int rad_image_extension_known(const char *path);

/* Writes by extension (.png, .hdr, .pfm, .exr); unknown extension: RAD_ERROR_INVALID_ARGUMENT. */
rad_status rad_image_write(const rad_image *image, const char *path,
                           const rad_image_write_options *options);

/* Reads .pfm, .hdr or .exr (linear). */
rad_status rad_image_read(rad_context *ctx, const char *path, rad_image **out);

#endif
