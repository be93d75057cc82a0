/* test_images.c - image files: PFM, HDR and EXR (float and half) round trips, damaged EXR files, PFM row order and byte layout, PNG tone
 * mapping decoded with stb_image, unknown extensions and unwritable paths. */
#include "image/image.h"
#include "image/compare.h"
#include "image/tonemap.h"
#include "test.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <stb/stb_image.h>

static rad_context *ctx;

static rad_image *gradient(int width, int height) {
    rad_image *image;
    if (rad_image_new(ctx, width, height, &image)) return NULL;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float *p = image->pixels + 3 * ((size_t)y * width + x);
            p[0] = 0.01f * (float)x + 0.5f;
            p[1] = 3.0f * (float)y + 0.25f;
            p[2] = (float)(x * y) * 1e-3f + 1e-4f;
        }
    return image;
}

static int file_exists(const char *path) { return access(path, F_OK) == 0; }

static void test_pfm_round_trip(void) {
    rad_image *image = gradient(7, 5);
    CHECK(image != NULL);
    if (!image) return;
    CHECK(rad_image_write(image, "test_images.pfm", NULL) == RAD_OK);
    rad_image *back = NULL;
    CHECK(rad_image_read(ctx, "test_images.pfm", &back) == RAD_OK);
    if (back) {
        CHECK(back->width == 7 && back->height == 5);
        CHECK(memcmp(back->pixels, image->pixels, 7 * 5 * 3 * sizeof(float)) == 0);
    }
    /* The file itself: header, then the BOTTOM row first, little-endian floats. */
    FILE *file = fopen("test_images.pfm", "rb");
    CHECK(file != NULL);
    if (file) {
        char header[32] = {0};
        size_t header_length = strlen("PF\n7 5\n-1.0\n");
        CHECK(fread(header, 1, header_length, file) == header_length);
        CHECK(strcmp(header, "PF\n7 5\n-1.0\n") == 0);
        uint8_t bytes[4];
        CHECK(fread(bytes, 1, 4, file) == 4);
        uint32_t bits = (uint32_t)bytes[0] | (uint32_t)bytes[1] << 8 | (uint32_t)bytes[2] << 16 |
                        (uint32_t)bytes[3] << 24;
        float first;
        memcpy(&first, &bits, 4);
        CHECK(first == image->pixels[3 * (4 * 7) + 0]); /* pixel (0, 4): bottom-left, red */
        fclose(file);
    }
    rad_image_free(back);
    rad_image_free(image);
}

static void test_pfm_big_endian_and_grey(void) {
    /* A hand-made big-endian greyscale file: "Pf", positive scale, 2x1. */
    FILE *file = fopen("test_images_be.pfm", "wb");
    if (!file) {
        CHECK(0);
        return;
    }
    fputs("Pf\n2 1\n1.0\n", file);
    const uint8_t data[] = {0x3f, 0x80, 0x00, 0x00, 0x40, 0x00, 0x00, 0x00}; /* 1.0, 2.0 */
    fwrite(data, 1, sizeof data, file);
    fclose(file);
    rad_image *image = NULL;
    CHECK(rad_image_read(ctx, "test_images_be.pfm", &image) == RAD_OK);
    if (image) {
        CHECK(image->width == 2 && image->height == 1);
        CHECK(image->pixels[0] == 1.0f && image->pixels[1] == 1.0f && image->pixels[2] == 1.0f);
        CHECK(image->pixels[3] == 2.0f && image->pixels[5] == 2.0f);
    }
    rad_image_free(image);
    /* Truncated data is a parse error. */
    file = fopen("test_images_short.pfm", "wb");
    if (file) {
        fputs("PF\n4 4\n-1.0\n", file);
        fwrite(data, 1, sizeof data, file);
        fclose(file);
    }
    image = NULL;
    CHECK(rad_image_read(ctx, "test_images_short.pfm", &image) == RAD_ERROR_PARSE);
    CHECK(image == NULL);
    CHECK(strstr(rad_context_error(ctx), "ends early") != NULL);
    remove("test_images_be.pfm");
    remove("test_images_short.pfm");
}

static void test_hdr_round_trip(void) {
    rad_image *image = gradient(9, 4);
    if (!image) {
        CHECK(0);
        return;
    }
    CHECK(rad_image_write(image, "test_images.hdr", NULL) == RAD_OK);
    rad_image *back = NULL;
    CHECK(rad_image_read(ctx, "test_images.hdr", &back) == RAD_OK);
    if (back) {
        CHECK(back->width == 9 && back->height == 4);
        /* RGBE keeps 8 bits of mantissa relative to the largest channel of a pixel. */
        double worst = 0;
        for (int i = 0; i < 9 * 4; ++i) {
            const float *a = image->pixels + 3 * i, *b = back->pixels + 3 * i;
            float largest = fmaxf(a[0], fmaxf(a[1], a[2]));
            for (int c = 0; c < 3; ++c) worst = fmax(worst, fabs(a[c] - b[c]) / largest);
        }
        CHECK(worst < 1.0 / 128);
        /* Row order: the top row (y = 0) has the smallest green. */
        CHECK(back->pixels[1] < back->pixels[3 * 9 * 3 + 1]);
    }
    rad_image_free(back);
    rad_image_free(image);
}

/* EXR through OpenEXR: float is exact, half within its 11-bit mantissa; negative and large
 * values survive (EXR is linear and signed); truncated or garbage files fail with a message. */
static void test_exr(void) {
    rad_image *image = gradient(37, 19); /* more lines than one ZIP chunk (16) */
    CHECK(image != NULL);
    if (!image) return;
    image->pixels[0] = -2.5f;
    image->pixels[4] = 65000.0f;
    rad_image_write_options options = {0, RAD_TONEMAP_CLAMP, 0};
    for (int half = 0; half <= 1; ++half) {
        options.exr_half = half;
        CHECK(rad_image_write(image, "test_images.exr", &options) == RAD_OK);
        rad_image *back = NULL;
        CHECK(rad_image_read(ctx, "test_images.exr", &back) == RAD_OK);
        if (!back) continue;
        CHECK(back->width == 37 && back->height == 19);
        double worst = 0;
        for (size_t i = 0; i < (size_t)37 * 19 * 3; ++i) {
            double want = image->pixels[i], got = back->pixels[i];
            double error = fabs(got - want) / (fabs(want) > 1e-3 ? fabs(want) : 1e-3);
            if (error > worst) worst = error;
        }
        if (half) CHECK(worst > 0 && worst < 1.0 / 1024); /* half rounds, to 2^-11 relative */
        else CHECK(worst == 0);
        rad_image_free(back);
    }
    /* Damaged copies of the file: every cut and a garbage header give one message, no image. */
    options.exr_half = 0;
    CHECK(rad_image_write(image, "test_images.exr", &options) == RAD_OK);
    FILE *file = fopen("test_images.exr", "rb");
    static unsigned char bytes[1 << 16];
    size_t size = file ? fread(bytes, 1, sizeof bytes, file) : 0;
    if (file) fclose(file);
    CHECK(size > 400 && size < sizeof bytes);
    const size_t cuts[] = {0, 3, 40, 200, 340, size / 2, size - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; ++k) {
        file = fopen("test_images_cut.exr", "wb");
        if (!file) break;
        fwrite(bytes, 1, cuts[k], file);
        fclose(file);
        rad_image *back = NULL;
        rad_status status = rad_image_read(ctx, "test_images_cut.exr", &back);
        CHECK(status == RAD_ERROR_PARSE && back == NULL);
        CHECK(strstr(rad_context_error(ctx), "test_images_cut.exr: ") != NULL);
        CHECK(strchr(rad_context_error(ctx), '\n') == NULL);
        rad_image_free(back);
    }
    bytes[0] ^= 0xff; /* not the EXR magic number */
    file = fopen("test_images_cut.exr", "wb");
    if (file) {
        fwrite(bytes, 1, size, file);
        fclose(file);
    }
    rad_image *back = NULL;
    CHECK(rad_image_read(ctx, "test_images_cut.exr", &back) == RAD_ERROR_PARSE && back == NULL);
    remove("test_images_cut.exr");
    rad_image_free(image);
}

static void test_png_values(void) {
    rad_image *image;
    if (rad_image_new(ctx, 4, 2, &image)) {
        CHECK(0);
        return;
    }
    const float values[8] = {0.0f, 0.001f, 0.18f, 0.5f, 1.0f, 4.0f, -1.0f, 0.25f};
    for (int i = 0; i < 8; ++i) {
        image->pixels[3 * i + 0] = values[i];
        image->pixels[3 * i + 1] = values[i] * 0.5f;
        image->pixels[3 * i + 2] = 0;
    }
    rad_image_write_options options = {0, RAD_TONEMAP_CLAMP, 0};
    CHECK(rad_image_write(image, "test_images.png", &options) == RAD_OK);
    int width, height, channels;
    unsigned char *png = stbi_load("test_images.png", &width, &height, &channels, 3);
    CHECK(png != NULL);
    if (png) {
        CHECK(width == 4 && height == 2);
        /* Known sRGB codes: 0.18 -> 118, 0.5 -> 188, 0.09 -> 85, 0.25 -> 137, clamps at 1. */
        CHECK(png[0] == 0);
        CHECK(png[3 * 2] == 118);
        CHECK(png[3 * 2 + 1] == 85);
        CHECK(png[3 * 3] == 188);
        CHECK(png[3 * 4] == 255);
        CHECK(png[3 * 5] == 255 && png[3 * 5 + 1] == 255);
        CHECK(png[3 * 6] == 0); /* negative clamps to black */
        CHECK(png[3 * 7] == 137);
        CHECK(png[3 * 1] == rad_srgb_encode(0.001f));
        stbi_image_free(png);
    }
    /* Exposure +1 stop doubles the linear value: 0.25 -> 0.5 -> 188. */
    options.exposure = 1;
    CHECK(rad_image_write(image, "test_images.png", &options) == RAD_OK);
    png = stbi_load("test_images.png", &width, &height, &channels, 3);
    if (png) {
        CHECK(png[3 * 7] == 188);
        stbi_image_free(png);
    }
    rad_image_free(image);
}

static void test_bad_outputs(void) {
    rad_image *image = gradient(2, 2);
    if (!image) {
        CHECK(0);
        return;
    }
    CHECK(!rad_image_extension_known("picture.jpg"));
    CHECK(!rad_image_extension_known("no_extension"));
    CHECK(!rad_image_extension_known("dir.png/file"));
    CHECK(rad_image_extension_known("UPPER.PNG"));
    CHECK(rad_image_write(image, "test_images.jpg", NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "unknown image format") != NULL);
    CHECK(!file_exists("test_images.jpg"));
    CHECK(rad_image_write(image, "no-such-directory/x.pfm", NULL) == RAD_ERROR_IO);
    CHECK(strstr(rad_context_error(ctx), "no-such-directory/x.pfm") != NULL);
    rad_image *none = NULL;
    CHECK(rad_image_read(ctx, "missing.pfm", &none) == RAD_ERROR_IO);
    CHECK(rad_image_read(ctx, "test_images.png", &none) == RAD_ERROR_UNSUPPORTED);
    CHECK(rad_image_new(ctx, 0, 4, &none) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(none == NULL);
    rad_image_free(image);
}

/* Metrics on images whose answers are known. */
static void test_compare(void) {
    rad_image *reference, *test, *other;
    if (rad_image_new(ctx, 4, 2, &reference) || rad_image_new(ctx, 4, 2, &test) ||
        rad_image_new(ctx, 2, 4, &other)) {
        CHECK(0);
        return;
    }
    for (int i = 0; i < 24; ++i) {
        reference->pixels[i] = 1.0f;
        test->pixels[i] = 1.1f;
    }
    rad_image_comparison c;
    CHECK(rad_image_compare(ctx, test, reference, &c) == RAD_OK);
    CHECK_NEAR(c.rmse, 0.1, 1e-6);
    CHECK_NEAR(c.relative_mse, 0.01 / 1.01, 1e-6);
    CHECK_NEAR(c.psnr, 20, 1e-4); /* peak 1, MSE 0.01 */
    CHECK_NEAR(c.mean_ratio, 1.1, 1e-6);
    CHECK_NEAR(c.mean_test, 1.1, 1e-6);
    /* Half the values off by 2 against a reference of 0 and 3: pbrt's relative MSE. */
    for (int i = 0; i < 24; ++i) {
        reference->pixels[i] = i % 2 ? 3.0f : 0.0f;
        test->pixels[i] = i % 4 == 0 ? 2.0f : reference->pixels[i];
    }
    CHECK(rad_image_compare(ctx, test, reference, &c) == RAD_OK);
    CHECK_NEAR(c.relative_mse, (6.0 * 4 / 0.01) / 24, 1e-3);
    CHECK_NEAR(c.rmse, sqrt(6.0 * 4 / 24), 1e-6);
    CHECK_NEAR(c.psnr, 10 * log10(1 / (6.0 * 4 / 24)), 1e-4); /* peak 1, not the largest, 3 */
    CHECK_NEAR(c.mean_ratio, (12 * 3 + 6 * 2) / 36.0, 1e-6);
    /* Identical: infinite PSNR, zero error. */
    CHECK(rad_image_compare(ctx, reference, reference, &c) == RAD_OK);
    CHECK(c.rmse == 0 && c.relative_mse == 0 && isinf(c.psnr) && c.mean_ratio == 1);
    /* Size mismatch and non-finite values are refused with a clear message. */
    CHECK(rad_image_compare(ctx, test, other, &c) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "4x2 against a 2x4") != NULL);
    test->pixels[5] = NAN;
    CHECK(rad_image_compare(ctx, test, reference, &c) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "pixel (1, 0)") != NULL);
    test->pixels[5] = 3.0f;
    /* Error map: black where equal, the top colour where the error reaches the scale. */
    rad_image *map = NULL;
    double scale = 0;
    CHECK(rad_image_error_map(ctx, test, reference, &scale, &map) == RAD_OK);
    if (map) {
        /* Pixel 0 has errors 20/sqrt(3) relative (2 / 0.1 in one channel of three). */
        CHECK_NEAR(scale, sqrt(400.0 / 3), 1e-3);
        float top[3], black[3];
        rad_heat_colour(1, top);
        rad_heat_colour(0, black);
        CHECK_NEAR(map->pixels[0], top[0], 1e-6);
        CHECK_NEAR(map->pixels[3 * 3 + 1], black[1], 1e-6); /* pixel 3: exact */
        CHECK(black[0] < 1e-3 && top[1] > 0.9);
        rad_image_free(map);
    }
    scale = 1e6;
    CHECK(rad_image_error_map(ctx, test, reference, &scale, &map) == RAD_OK);
    if (map) {
        CHECK(map->pixels[0] < 0.01); /* far below the scale: nearly black */
        rad_image_free(map);
    }
    rad_image_free(reference);
    rad_image_free(test);
    rad_image_free(other);
}

int main(void) {
    if (rad_context_create(NULL, &ctx)) return 1;
    test_pfm_round_trip();
    test_pfm_big_endian_and_grey();
    test_hdr_round_trip();
    test_exr();
    test_png_values();
    test_bad_outputs();
    test_compare();
    remove("test_images.pfm");
    remove("test_images.hdr");
    remove("test_images.png");
    remove("test_images.exr");
    rad_context_destroy(ctx);
    return test_finish();
}
