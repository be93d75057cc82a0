/* test_image.h - what the image tests share: a context, block comparisons. */
#ifndef RAD_TEST_IMAGE_H
#define RAD_TEST_IMAGE_H

#include "radiosity.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

/* A context of `threads` threads and random seed `seed`; NULL when it cannot be made. */
static inline rad_context *test_context(int threads, uint64_t seed) {
    rad_context_options options = {0};
    options.threads = threads;
    options.seed = seed;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return NULL;
    return ctx;
}

/* The mean of every pixel's channels. */
static inline double test_image_mean(const rad_image *image) {
    size_t n = (size_t)rad_image_width(image) * rad_image_height(image) * 3;
    const float *p = rad_image_pixels(image);
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += p[i];
    return sum / (double)n;
}

/* Relative RMSE of the block x block means (RGB summed) of `test` against `reference`; blocks
 * whose reference is black are left out (scripts/block_compare.py --emitter inf). */
static inline double test_block_rmse(const rad_image *test, const rad_image *reference,
                                     int block) {
    int width = rad_image_width(test), height = rad_image_height(test);
    const float *t = rad_image_pixels(test), *r = rad_image_pixels(reference);
    double sum = 0;
    int count = 0;
    for (int by = 0; by + block <= height; by += block)
        for (int bx = 0; bx + block <= width; bx += block) {
            double a = 0, b = 0;
            for (int y = by; y < by + block; ++y)
                for (int x = bx; x < bx + block; ++x)
                    for (int c = 0; c < 3; ++c) {
                        a += t[3 * (y * width + x) + c];
                        b += r[3 * (y * width + x) + c];
                    }
            if (b <= 1e-6) continue;
            sum += (a - b) * (a - b) / (b * b);
            ++count;
        }
    return count ? sqrt(sum / count) : 0;
}

#endif
