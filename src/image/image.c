/* image.c - float RGB images and their files (see image.h).
 *
 *   .png  exposure, tone curve and sRGB (image/tonemap.h), 8 bit, through stb_image_write.
 *   .hdr  Radiance RGBE (Ward 1991), run-length encoded, through stb_image_write; read by
 *         read_hdr below (stb_image's reader hangs on truncated run-length scanlines).
 *   .exr  OpenEXR, 32-bit float (or half) linear RGB, ZIP compressed: image_exr.c.
 *   .pfm  Portable Float Map: "PF\n<width> <height>\n<scale>\n" then 32-bit floats, rows from
 *         the BOTTOM of the image to the top; a negative scale means little endian. Written and
 *         read here.
 *
 * Every write goes through rad_atomic_open/commit: a failure never leaves a half-written file. */
#include "image/image.h"

#include "core/atomic_file.h"
#include "image/image_exr.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <stb/stb_image_write.h>

/* Largest side accepted when reading; larger files are almost surely corrupt. */
#define RAD_IMAGE_MAX_SIDE 65536

rad_status rad_image_new(rad_context *ctx, int width, int height, rad_image **out) {
    *out = NULL;
    if (width < 1 || height < 1 || width > RAD_IMAGE_MAX_SIDE || height > RAD_IMAGE_MAX_SIDE)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "image size %dx%d: each side must be 1 to %d pixels", width, height,
                        RAD_IMAGE_MAX_SIDE);
    size_t count;
    if (rad_size_mul((size_t)width * (size_t)height, 3, &count))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "image size %dx%d is too large", width,
                        height);
    rad_status status = rad_check_budget(ctx, (double)count * sizeof(float), "the image");
    if (status) return status;
    rad_image *image = rad_alloc(ctx, 1, sizeof *image);
    if (!image) return RAD_ERROR_NO_MEMORY;
    image->ctx = ctx;
    image->width = width;
    image->height = height;
    image->pixels = rad_alloc_zero(ctx, count, sizeof(float));
    if (!image->pixels) {
        rad_free(ctx, image);
        return RAD_ERROR_NO_MEMORY;
    }
    *out = image;
    return RAD_OK;
}

void rad_image_free(rad_image *image) {
    if (!image) return;
    rad_free(image->ctx, image->pixels);
    rad_free(image->ctx, image);
}

typedef enum image_format { FORMAT_UNKNOWN = 0, FORMAT_PNG, FORMAT_HDR, FORMAT_PFM, FORMAT_EXR } image_format;

static image_format format_of(const char *path) {
    if (!path) return FORMAT_UNKNOWN;
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash)) return FORMAT_UNKNOWN;
    if (strcasecmp(dot, ".png") == 0) return FORMAT_PNG;
    if (strcasecmp(dot, ".hdr") == 0) return FORMAT_HDR;
    if (strcasecmp(dot, ".pfm") == 0) return FORMAT_PFM;
    if (strcasecmp(dot, ".exr") == 0) return FORMAT_EXR;
    return FORMAT_UNKNOWN;
}

int rad_image_extension_known(const char *path) { return format_of(path) != FORMAT_UNKNOWN; }

/* stb_image_write's output callback: append to the atomic file. */
static void write_to_file(void *user, void *data, int size) {
    FILE *file = user;
    if (size > 0) fwrite(data, 1, (size_t)size, file);
}

static rad_status write_png(const rad_image *image, FILE *file,
                            const rad_image_write_options *options) {
    rad_context *ctx = image->ctx;
    size_t pixel_count = (size_t)image->width * (size_t)image->height;
    uint8_t *bytes = rad_alloc(ctx, pixel_count, 3);
    if (!bytes) return RAD_ERROR_NO_MEMORY;
    double exposure = options ? options->exposure : 0;
    rad_tonemap curve = options ? options->curve : RAD_TONEMAP_CLAMP;
    for (size_t i = 0; i < pixel_count; ++i) {
        float display[3];
        rad_tonemap_apply(curve, exposure, image->pixels + 3 * i, display);
        for (int c = 0; c < 3; ++c) bytes[3 * i + c] = rad_srgb_encode(display[c]);
    }
    int ok = stbi_write_png_to_func(write_to_file, file, image->width, image->height, 3, bytes,
                                    image->width * 3);
    rad_free(ctx, bytes);
    return ok ? RAD_OK : rad_fail(ctx, RAD_ERROR_IO, "cannot encode the PNG image");
}

static rad_status write_hdr(const rad_image *image, FILE *file) {
    /* RGBE cannot hold negative or non-finite values: clamp them to zero. */
    rad_context *ctx = image->ctx;
    size_t count = (size_t)image->width * (size_t)image->height * 3;
    float *clean = rad_alloc(ctx, count, sizeof(float));
    if (!clean) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < count; ++i) {
        float value = image->pixels[i];
        clean[i] = isfinite(value) && value > 0 ? value : 0;
    }
    int ok = stbi_write_hdr_to_func(write_to_file, file, image->width, image->height, 3, clean);
    rad_free(ctx, clean);
    return ok ? RAD_OK : rad_fail(ctx, RAD_ERROR_IO, "cannot encode the HDR image");
}

static int host_is_little_endian(void) {
    const uint16_t probe = 1;
    return *(const uint8_t *)&probe == 1;
}

static uint32_t swap32(uint32_t x) {
    return (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);
}

static rad_status write_pfm(const rad_image *image, FILE *file) {
    rad_context *ctx = image->ctx;
    size_t row_floats = (size_t)image->width * 3;
    uint32_t *row = rad_alloc(ctx, row_floats, sizeof *row);
    if (!row) return RAD_ERROR_NO_MEMORY;
    fprintf(file, "PF\n%d %d\n-1.0\n", image->width, image->height);
    int swap = !host_is_little_endian();
    for (int y = image->height - 1; y >= 0; --y) { /* bottom row first */
        memcpy(row, image->pixels + (size_t)y * row_floats, row_floats * sizeof(float));
        if (swap)
            for (size_t i = 0; i < row_floats; ++i) row[i] = swap32(row[i]);
        if (fwrite(row, sizeof *row, row_floats, file) != row_floats) break;
    }
    rad_free(ctx, row);
    return RAD_OK; /* write errors surface in rad_atomic_commit */
}

rad_status rad_image_write(const rad_image *image, const char *path,
                           const rad_image_write_options *options) {
    rad_context *ctx = image->ctx;
    image_format format = format_of(path);
    if (format == FORMAT_UNKNOWN)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: unknown image format (use .png, .hdr, .pfm or .exr)", path ? path : "");
    rad_atomic_file file;
    rad_status status = rad_atomic_open(ctx, path, &file);
    if (status) return status;
    switch (format) {
    case FORMAT_PNG: status = write_png(image, file.file, options); break;
    case FORMAT_HDR: status = write_hdr(image, file.file); break;
    case FORMAT_PFM: status = write_pfm(image, file.file); break;
    case FORMAT_EXR: status = rad_exr_write(image, file.file, path, options && options->exr_half); break;
    case FORMAT_UNKNOWN: break;
    }
    if (status) {
        rad_atomic_abandon(&file);
        return status;
    }
    return rad_atomic_commit(&file);
}

/* ---- reading ------------------------------------------------------------------------------ */

/* Reads one whitespace-delimited token of a PFM header. */
static int pfm_token(FILE *file, char *token, size_t size) {
    int c;
    do c = fgetc(file);
    while (c != EOF && isspace(c));
    size_t n = 0;
    while (c != EOF && !isspace(c)) {
        if (n + 1 >= size) return 0;
        token[n++] = (char)c;
        c = fgetc(file);
    }
    token[n] = '\0';
    return n > 0 && c != EOF; /* exactly one whitespace character ends the header's last token */
}

static rad_status read_pfm(rad_context *ctx, const char *path, FILE *file, rad_image **out) {
    char magic[8], width_text[16], height_text[16], scale_text[64];
    if (!pfm_token(file, magic, sizeof magic) || !pfm_token(file, width_text, sizeof width_text) ||
        !pfm_token(file, height_text, sizeof height_text) ||
        !pfm_token(file, scale_text, sizeof scale_text))
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: not a PFM file (bad header)", path);
    int channels = strcmp(magic, "PF") == 0 ? 3 : strcmp(magic, "Pf") == 0 ? 1 : 0;
    if (!channels)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: not a PFM file (starts with '%s', not PF or Pf)",
                        path, magic);
    char *end;
    long width = strtol(width_text, &end, 10);
    int bad = *end != '\0';
    long height = strtol(height_text, &end, 10);
    bad |= *end != '\0';
    double scale = strtod(scale_text, &end);
    bad |= *end != '\0' || !isfinite(scale) || scale == 0;
    if (bad || width < 1 || height < 1 || width > RAD_IMAGE_MAX_SIDE || height > RAD_IMAGE_MAX_SIDE)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: bad PFM header (size %s x %s, scale %s)", path,
                        width_text, height_text, scale_text);
    rad_image *image;
    rad_status status = rad_image_new(ctx, (int)width, (int)height, &image);
    if (status) return status;
    size_t row_floats = (size_t)width * (size_t)channels;
    uint32_t *row = rad_alloc(ctx, row_floats, sizeof *row);
    if (!row) {
        rad_image_free(image);
        return RAD_ERROR_NO_MEMORY;
    }
    int swap = (scale < 0) != host_is_little_endian();
    for (long y = height - 1; y >= 0; --y) {
        if (fread(row, sizeof *row, row_floats, file) != row_floats) {
            rad_free(ctx, row);
            rad_image_free(image);
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s: PFM data ends early (%ldx%ld expected)",
                            path, width, height);
        }
        float *pixels = image->pixels + (size_t)y * (size_t)width * 3;
        for (long x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                uint32_t bits = row[x * channels + (channels == 3 ? c : 0)];
                if (swap) bits = swap32(bits);
                float value;
                memcpy(&value, &bits, sizeof value);
                pixels[3 * x + c] = value;
            }
    }
    rad_free(ctx, row);
    *out = image;
    return RAD_OK;
}

/* Radiance RGBE reading (Ward 1991), written here with every read bounded by the file:
 * stb_image's decoder loops forever on a truncated run-length scanline (the zero it returns at
 * the end of the file is taken as a count that never advances; found by fuzz_image). Reads the
 * standard orientation "-Y H +X W", flat or new-style run-length scanlines. */
static rad_status read_hdr(rad_context *ctx, const char *path, FILE *file, rad_image **out) {
    /* The whole file: headers and pixels are bounded by its length. */
    if (fseek(file, 0, SEEK_END) != 0) return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read", path);
    long length = ftell(file);
    if (length < 0 || fseek(file, 0, SEEK_SET) != 0)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read", path);
    unsigned char *bytes = rad_alloc(ctx, (size_t)length + 1, 1);
    if (!bytes) return RAD_ERROR_NO_MEMORY;
    size_t size = fread(bytes, 1, (size_t)length, file), at = 0;
    bytes[size] = '\0';
    rad_status status = RAD_OK;
    rad_image *image = NULL;
#define HDR_FAIL(...) do { status = rad_fail(ctx, RAD_ERROR_PARSE, __VA_ARGS__); goto done; } while (0)
    if (size < 2 || bytes[0] != '#' || bytes[1] != '?') HDR_FAIL("%s: not a Radiance HDR file", path);
    /* Header lines up to an empty line. */
    for (;;) {
        size_t end = at;
        while (end < size && bytes[end] != '\n') ++end;
        if (end >= size) HDR_FAIL("%s: truncated HDR header", path);
        if (end == at) {
            at = end + 1;
            break;
        }
        static const char format[] = "FORMAT=32-bit_rle_rgbe";
        if (end - at >= 7 && memcmp(bytes + at, format, 7) == 0 &&
            !(end - at == sizeof format - 1 && memcmp(bytes + at, format, sizeof format - 1) == 0))
            HDR_FAIL("%s: unsupported HDR format (only 32-bit_rle_rgbe)", path);
        at = end + 1;
    }
    int width = 0, height = 0, used = 0;
    char resolution[64];
    size_t line_end = at;
    while (line_end < size && bytes[line_end] != '\n' && line_end - at < sizeof resolution - 1) ++line_end;
    memcpy(resolution, bytes + at, line_end - at);
    resolution[line_end - at] = '\0';
    if (line_end >= size || bytes[line_end] != '\n' ||
        sscanf(resolution, "-Y %d +X %d%n", &height, &width, &used) != 2 || resolution[used] != '\0')
        HDR_FAIL("%s: unsupported HDR resolution line (only \"-Y H +X W\")", path);
    at = line_end + 1;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        HDR_FAIL("%s: HDR size %dx%d out of range (1 to 16384 per side)", path, width, height);
    if ((status = rad_image_new(ctx, width, height, &image))) goto done;
    unsigned char *scanline = rad_alloc(ctx, (size_t)width, 4);
    if (!scanline) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    for (int y = 0; y < height && !status; ++y) {
        int rle = width >= 8 && width < 32768 && at + 4 <= size && bytes[at] == 2 &&
                  bytes[at + 1] == 2 && ((bytes[at + 2] << 8) | bytes[at + 3]) == width;
        if (rle) {
            at += 4;
            /* Four planes (R, G, B, E), each runs (count > 128: repeat) or literals. */
            for (int c = 0; c < 4 && !status; ++c) {
                for (int x = 0; x < width;) {
                    if (at >= size) { status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated HDR pixels", path); break; }
                    int count = bytes[at++];
                    int run = count > 128;
                    if (run) count -= 128;
                    if (count == 0 || x + count > width || at + (run ? 1 : (size_t)count) > size) {
                        status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: damaged HDR scanline %d", path, y);
                        break;
                    }
                    for (int k = 0; k < count; ++k, ++x)
                        scanline[4 * x + c] = run ? bytes[at] : bytes[at + (size_t)k];
                    at += run ? 1 : (size_t)count;
                }
            }
        } else {
            if (at + 4 * (size_t)width > size) {
                status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated HDR pixels", path);
                break;
            }
            memcpy(scanline, bytes + at, 4 * (size_t)width);
            at += 4 * (size_t)width;
        }
        float *row = image->pixels + (size_t)y * (size_t)width * 3;
        for (int x = 0; x < width && !status; ++x) {
            const unsigned char *p = scanline + 4 * x;
            float scale = p[3] ? ldexpf(1.0f, (int)p[3] - (128 + 8)) : 0.0f;
            for (int c = 0; c < 3; ++c) row[3 * x + c] = (float)p[c] * scale;
        }
    }
    rad_free(ctx, scanline);
done:
#undef HDR_FAIL
    rad_free(ctx, bytes);
    if (status) {
        rad_image_free(image);
        return status;
    }
    *out = image;
    return RAD_OK;
}

rad_status rad_image_read(rad_context *ctx, const char *path, rad_image **out) {
    *out = NULL;
    image_format format = format_of(path);
    if (format == FORMAT_EXR) return rad_exr_read(ctx, path, out);
    if (format != FORMAT_PFM && format != FORMAT_HDR)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED,
                        "%s: can only read linear images (.pfm, .hdr or .exr)", path ? path : "");
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    rad_status status = format == FORMAT_PFM ? read_pfm(ctx, path, file, out)
                                             : read_hdr(ctx, path, file, out);
    fclose(file);
    return status;
}

/* ---- the public interface (include/radiosity.h, "Rendering") ------------------------------- */

int rad_image_width(const rad_image *image) { return image ? image->width : 0; }
int rad_image_height(const rad_image *image) { return image ? image->height : 0; }
const float *rad_image_pixels(const rad_image *image) { return image ? image->pixels : NULL; }
void rad_image_destroy(rad_image *image) { rad_image_free(image); }

static rad_status write_options(rad_context *ctx, const rad_image_save_options *options,
                                rad_image_write_options *out) {
    out->exposure = options ? options->exposure : 0;
    out->curve = RAD_TONEMAP_CLAMP;
    out->exr_half = options ? options->exr_half : 0;
    if (!isfinite(out->exposure))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "exposure must be finite");
    const char *name = options ? options->tonemap : NULL;
    if (!name) return RAD_OK;
    int curve = rad_tonemap_parse(name);
    if (curve < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "unknown tone curve '%s' (none, clamp, reinhard or aces)", name);
    out->curve = (rad_tonemap)curve;
    return RAD_OK;
}

rad_status rad_image_check_path(rad_context *ctx, const char *path,
                                const rad_image_save_options *options) {
    if (!rad_image_extension_known(path))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: unknown image format (use .png, .hdr, .pfm or .exr)", path ? path : "");
    rad_image_write_options write;
    rad_status status = write_options(ctx, options, &write);
    if (status) return status;
    /* Make (and drop) the temporary file the write will use: the directory takes new files. */
    status = rad_atomic_check(ctx, path);
    if (status) return status;
    return RAD_OK;
}

rad_status rad_image_save(const rad_image *image, const char *path,
                          const rad_image_save_options *options) {
    if (!image) return RAD_ERROR_INVALID_ARGUMENT;
    rad_image_write_options write;
    rad_status status = write_options(image->ctx, options, &write);
    if (status) return status;
    return rad_image_write(image, path, &write);
}
