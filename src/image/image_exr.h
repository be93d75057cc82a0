/* image_exr.h - OpenEXR images through OpenEXR's C API (OpenEXRCore, <OpenEXR/openexr.h>):
 * written as one scanline part with R, G, B channels (32-bit float, or half when asked), ZIP
 * compressed, linear; read back from any scanline part that has R, G, B or a Y channel. */
#ifndef RAD_IMAGE_IMAGE_EXR_H
#define RAD_IMAGE_IMAGE_EXR_H

#include "image/image.h"

#include <stdio.h>

/* Encodes image into file (already open for writing, e.g. a rad_atomic_file); half selects
 * 16-bit half floats instead of 32-bit floats. path is for messages. */
rad_status rad_exr_write(const rad_image *image, FILE *file, const char *path, int half);

/* Reads the first part of an EXR file. Tiled, deep or subsampled images, and images without
 * R, G, B or Y: RAD_ERROR_UNSUPPORTED; damage: RAD_ERROR_PARSE; each with one clear message. */
rad_status rad_exr_read(rad_context *ctx, const char *path, rad_image **out);

#endif
