/* compare.c - how far an image is from a reference (docs/images.md, "Comparing images"):
 * RMSE, relative MSE as pbrt's imgtool computes it, PSNR, the ratio of the means, and a
 * false-colour map of the per-pixel error. */
#include "image/compare.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The epsilon of the relative MSE: keeps black reference pixels from dominating. */
#define RELATIVE_EPSILON 0.01

static rad_status check_pair(rad_context *ctx, const rad_image *test, const rad_image *reference) {
    if (!test || !reference)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "compare: no image");
    if (test->width != reference->width || test->height != reference->height)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "images differ in size: %dx%d against a %dx%d reference", test->width,
                        test->height, reference->width, reference->height);
    size_t count = (size_t)test->width * (size_t)test->height * 3;
    for (size_t i = 0; i < count; ++i) {
        const rad_image *bad = !isfinite(test->pixels[i])        ? test
                               : !isfinite(reference->pixels[i]) ? reference
                                                                 : NULL;
        if (bad) {
            size_t pixel = i / 3;
            return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                            "the %s image has a value that is not finite at pixel (%zu, %zu)",
                            bad == test ? "test" : "reference", pixel % (size_t)test->width,
                            pixel / (size_t)test->width);
        }
    }
    return RAD_OK;
}

#define RAD_PSNR_PEAK 1.0

rad_status rad_image_compare(rad_context *ctx, const rad_image *test, const rad_image *reference,
                             rad_image_comparison *out) {
    rad_status status = check_pair(ctx, test, reference);
    if (status) return status;
    size_t count = (size_t)test->width * (size_t)test->height * 3;
    double squared = 0, relative = 0, sum_test = 0, sum_reference = 0;
    for (size_t i = 0; i < count; ++i) {
        double t = test->pixels[i], r = reference->pixels[i], d = t - r;
        squared += d * d;
        relative += d * d / (r * r + RELATIVE_EPSILON);
        sum_test += t;
        sum_reference += r;
    }
    double mse = squared / (double)count;
    out->rmse = sqrt(mse);
    out->relative_mse = relative / (double)count;
    /* The usual definition, with the peak of display-referred images: 1 (white). Not the
     * brightest reference pixel, which in a render is the lamp and flatters every error. */
    out->psnr = mse > 0 ? 10 * log10(RAD_PSNR_PEAK * RAD_PSNR_PEAK / mse) : INFINITY;
    out->mean_test = sum_test / (double)count;
    out->mean_reference = sum_reference / (double)count;
    out->mean_ratio = out->mean_reference != 0 ? out->mean_test / out->mean_reference
                      : out->mean_test == 0     ? 1
                                                : INFINITY;
    return RAD_OK;
}

/* The colour scale: black, deep blue, magenta, orange, pale yellow (sRGB, after matplotlib's
 * "inferno"), evenly spaced. */
static const float heat_srgb[5][3] = {
    {0.000f, 0.000f, 0.016f}, {0.341f, 0.063f, 0.431f}, {0.737f, 0.216f, 0.329f},
    {0.976f, 0.557f, 0.035f}, {0.988f, 1.000f, 0.643f},
};

static float srgb_to_linear(float s) {
    return s <= 0.04045f ? s / 12.92f : powf((s + 0.055f) / 1.055f, 2.4f);
}

void rad_heat_colour(double value, float out[3]) {
    double x = value < 0 ? 0 : value > 1 ? 1 : value;
    if (!isfinite(value)) x = 1;
    double position = x * 4;
    int k = position >= 4 ? 3 : (int)position;
    double f = position - k;
    for (int c = 0; c < 3; ++c)
        out[c] = srgb_to_linear((float)((1 - f) * heat_srgb[k][c] + f * heat_srgb[k + 1][c]));
}

static int compare_floats(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

rad_status rad_image_error_map(rad_context *ctx, const rad_image *test, const rad_image *reference,
                               double *scale, rad_image **out) {
    *out = NULL;
    rad_status status = check_pair(ctx, test, reference);
    if (status) return status;
    size_t pixels = (size_t)test->width * (size_t)test->height;
    float *error = rad_alloc(ctx, pixels, sizeof *error);
    if (!error) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < pixels; ++i) {
        double sum = 0;
        for (int c = 0; c < 3; ++c) {
            double t = test->pixels[3 * i + c], r = reference->pixels[3 * i + c], d = t - r;
            sum += d * d / (r * r + RELATIVE_EPSILON);
        }
        error[i] = (float)sqrt(sum / 3);
    }
    double top = scale && *scale > 0 ? *scale : 0;
    if (!(top > 0)) {
        /* The 99th percentile, so a few outliers do not wash the map out. */
        float *sorted = rad_alloc(ctx, pixels, sizeof *sorted);
        if (!sorted) {
            rad_free(ctx, error);
            return RAD_ERROR_NO_MEMORY;
        }
        memcpy(sorted, error, pixels * sizeof *sorted);
        qsort(sorted, pixels, sizeof *sorted, compare_floats);
        top = sorted[(size_t)(0.99 * (double)(pixels - 1))];
        if (!(top > 0)) top = sorted[pixels - 1];
        if (!(top > 0)) top = 1; /* identical images: everything black */
        rad_free(ctx, sorted);
    }
    rad_image *map;
    status = rad_image_new(ctx, test->width, test->height, &map);
    if (!status) {
        for (size_t i = 0; i < pixels; ++i) rad_heat_colour(error[i] / top, map->pixels + 3 * i);
        if (scale) *scale = top;
        *out = map;
    }
    rad_free(ctx, error);
    return status;
}
