/* test_sampler.c - the Owen-scrambled Sobol' sampler (core/sampler.h) and what it buys:
 *   - the fast second dimension and the nibble tables of the third and fourth against the
 *     direction-number recurrence of Sobol' (Joe & Kuo 2008);
 *   - stratification: for every m <= 10, any aligned run of 2^m indices (the first 2^m points,
 *     the points of one pixel, of a block of pixels) puts exactly one point of the first two
 *     coordinates in each elementary interval [a 2^-k, (a+1) 2^-k) x [b 2^-(m-k), ...) for
 *     every k, in 2D and 4D dimensions, for several seeds and dimensions; each coordinate of a
 *     4D point alone is stratified into 2^m intervals; every value is in [0, 1);
 *   - direct light on "two-squares" (a unit emitter under a parallel receiver at distance 1)
 *     at 64 points, 64 paths each, against the closed-form point-to-polygon form factor: the
 *     RMS relative error with the sampler against independent numbers;
 *   - the path tracer on a small Cornell box at 16 paths per pixel: the worst-block and the
 *     4x4-block relative RMSE against an image of 64 times as many paths, with the sampler
 *     against independent numbers (each path at a random 64-bit index: every index run of 2^32
 *     is scrambled on its own, so the paths are independent); the ratio is stated and held;
 *     and the same with the path tracer's Russian roulette against the textbook one. */
#include "core/rng.h"
#include "core/sampler.h"
#include "formfactor/geometric.h"
#include "render/pathtrace.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void sobol_directions(int s, uint32_t a, const uint32_t *m, uint32_t v[32]) {
    for (int i = 1; i <= 32; ++i) {
        if (i <= s) {
            v[i - 1] = m[i - 1] << (32 - i);
            continue;
        }
        uint32_t x = v[i - s - 1] ^ (v[i - s - 1] >> s);
        for (int k = 1; k < s; ++k)
            if ((a >> (s - 1 - k)) & 1u) x ^= v[i - k - 1];
        v[i - 1] = x;
    }
}

static uint32_t sobol_value(const uint32_t v[32], uint32_t index) {
    uint32_t r = 0;
    for (int k = 0; k < 32; ++k)
        if ((index >> k) & 1u) r ^= v[k];
    return r;
}

static void test_generator_matrices(void) {
    uint32_t second[32], third[32], fourth[32];
    sobol_directions(1, 0, (const uint32_t[]){1}, second);
    sobol_directions(2, 1, (const uint32_t[]){1, 3}, third);
    sobol_directions(3, 1, (const uint32_t[]){1, 3, 1}, fourth);
    rad_rng rng = rad_rng_make(3, 0);
    int bad = 0;
    for (int i = 0; i < 20000; ++i) {
        uint32_t index = i < 4096 ? (uint32_t)i : rad_rng_next(&rng);
        if (rad_reverse_bits32(rad_sobol_second_reversed(index)) != sobol_value(second, index)) ++bad;
        uint32_t t = 0, f = 0;
        for (int k = 0; k < 8; ++k) {
            t ^= rad_sobol_nibbles[0][k][(index >> (4 * k)) & 15u];
            f ^= rad_sobol_nibbles[1][k][(index >> (4 * k)) & 15u];
        }
        if (t != sobol_value(third, index) || f != sobol_value(fourth, index)) ++bad;
    }
    CHECK(bad == 0);
}

/* Whether the points (x, y) (32-bit fractions) hold one point per elementary interval of
 * volume 2^-m, for every shape. */
static int is_net(const uint32_t (*points)[2], int m, int *counts) {
    for (int k = 0; k <= m; ++k) {
        memset(counts, 0, sizeof(int) << m);
        for (uint32_t i = 0; i < (1u << m); ++i) {
            uint32_t a = k ? points[i][0] >> (32 - k) : 0;
            uint32_t b = m - k ? points[i][1] >> (32 - (m - k)) : 0;
            if (counts[(a << (m - k)) | b]++) return 0;
        }
    }
    return 1;
}

static int is_stratified_1d(const uint32_t (*points)[4], int coordinate, int m, int *counts) {
    memset(counts, 0, sizeof(int) << m);
    for (uint32_t i = 0; i < (1u << m); ++i) {
        uint32_t a = m ? points[i][coordinate] >> (32 - m) : 0;
        if (counts[a]++) return 0;
    }
    return 1;
}

static void test_stratification(void) {
    enum { MAX_M = 10 };
    static uint32_t pair[1 << MAX_M][2], quad[1 << MAX_M][4];
    static int counts[1 << MAX_M];
    int nets = 0, failures = 0, out_of_range = 0;
    for (uint64_t seed = 0; seed < 3; ++seed)
        for (uint32_t dimension = 0; dimension < 6; ++dimension)
            for (int m = 0; m <= MAX_M; ++m) {
                /* The first points, one pixel's run, and a run beyond 2^32. */
                const uint64_t bases[3] = {0, (uint64_t)37 << m, ((uint64_t)5 << 40) + ((uint64_t)3 << m)};
                for (int b = 0; b < 3; ++b) {
                    rad_sampler s = rad_sampler_make(seed, 0);
                    for (uint32_t i = 0; i < (1u << m); ++i) {
                        rad_sampler_point_bits(s.seed, bases[b] + i, dimension, pair[i]);
                        rad_sampler_point4_bits(s.seed, bases[b] + i, dimension, quad[i]);
                        s.index = bases[b] + i;
                        s.dimension = dimension;
                        double u[4];
                        rad_sampler_4d(&s, u);
                        for (int c = 0; c < 4; ++c) out_of_range += !(u[c] >= 0 && u[c] < 1);
                    }
                    nets += 2;
                    failures += !is_net((const uint32_t(*)[2])pair, m, counts);
                    uint32_t front[1 << MAX_M][2];
                    for (uint32_t i = 0; i < (1u << m); ++i) {
                        front[i][0] = quad[i][0];
                        front[i][1] = quad[i][1];
                    }
                    failures += !is_net((const uint32_t(*)[2])front, m, counts);
                    for (int c = 0; c < 4; ++c)
                        failures += !is_stratified_1d((const uint32_t(*)[4])quad, c, m, counts);
                }
            }
    fprintf(stderr, "sampler: %d point sets of up to 1024 points checked, %d not stratified\n",
            nets, failures);
    CHECK(failures == 0);
    CHECK(out_of_range == 0);
    /* Scrambled: another seed gives other points (else the scramble could be the identity). */
    uint32_t a[2], b[2];
    rad_sampler_point_bits(rad_sampler_make(1, 0).seed, 5, 0, a);
    rad_sampler_point_bits(rad_sampler_make(2, 0).seed, 5, 0, b);
    CHECK(a[0] != b[0] && a[1] != b[1]);
}

/* ---- the path tracer's error at equal paths ------------------------------------------------ */

enum { SIZE = 32, BLOCK = 4 };

/* The random index of an independent path. */
static uint64_t random_index(rad_rng *rng) {
    uint64_t high = rad_rng_next(rng);
    return high << 32 | rad_rng_next(rng);
}

/* A SIZE x SIZE Cornell image (grey) at `spp`; random: each path at a random index. */
static void trace(const rad_tracer *tracer, const rad_view *view, uint64_t seed, int spp,
                  int random, double *grey) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int pixel = 0; pixel < SIZE * SIZE; ++pixel) {
        uint32_t x = (uint32_t)(pixel % SIZE), y = (uint32_t)(pixel / SIZE);
        rad_sampler sampler = rad_sampler_make(seed, 0);
        rad_rng rng = rad_rng_make(seed, (uint64_t)pixel);
        rad_trace_counts counts = {0};
        double sum = 0;
        for (int s = 0; s < spp; ++s) {
            sampler.index = random ? random_index(&rng)
                                   : rad_sampler_pixel_index(x, y, (uint32_t)spp, (uint32_t)s);
            sampler.dimension = RAD_PATH_DIM_PIXEL;
            double jitter[4], radiance[3];
            rad_sampler_4d(&sampler, jitter);
            rad_tracer_radiance(tracer, &sampler, view->eye,
                                rad_view_direction(view, x + jitter[0], y + jitter[1]), &counts,
                                radiance);
            sum += radiance[0] + radiance[1] + radiance[2];
        }
        grey[pixel] = sum / spp;
    }
}

/* Relative RMSE over the BLOCK x BLOCK blocks, and the worst block. */
static double block_error(const double *test, const double *reference, double *worst) {
    double sum = 0;
    int blocks = 0;
    *worst = 0;
    for (int by = 0; by < SIZE / BLOCK; ++by)
        for (int bx = 0; bx < SIZE / BLOCK; ++bx) {
            double t = 0, r = 0;
            for (int y = by * BLOCK; y < (by + 1) * BLOCK; ++y)
                for (int x = bx * BLOCK; x < (bx + 1) * BLOCK; ++x) {
                    t += test[y * SIZE + x];
                    r += reference[y * SIZE + x];
                }
            if (!(r > 0)) continue;
            double e = (t - r) / r;
            sum += e * e;
            *worst = fmax(*worst, fabs(e));
            ++blocks;
        }
    return sqrt(sum / blocks);
}

static void test_error_at_equal_paths(void) {
    rad_context_options options = {0};
    rad_context *ctx = NULL;
    rad_context_create(&options, &ctx);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK);
    rad_tracer *tracer = NULL;
    if (scene) CHECK(rad_tracer_create(ctx, scene, 0, &tracer) == RAD_OK);
    if (!tracer) {
        rad_scene_destroy(scene);
        rad_context_destroy(ctx);
        return;
    }
    rad_camera camera = rad_scene_camera(scene);
    rad_view view;
    rad_view_make(ctx, &camera, SIZE, SIZE, &view);
    static double reference[SIZE * SIZE], image[SIZE * SIZE];
    trace(tracer, &view, 1000, 1024, 0, reference);
    /* Several seeds: the ratio of the mean squared errors. */
    double squared[2] = {0, 0}, worst[2] = {0, 0};
    for (int random = 0; random < 2; ++random)
        for (uint64_t seed = 1; seed <= 4; ++seed) {
            trace(tracer, &view, seed, 16, random, image);
            double block_worst, e = block_error(image, reference, &block_worst);
            squared[random] += e * e / 4;
            worst[random] += block_worst / 4;
        }
    double error[2] = {sqrt(squared[0]), sqrt(squared[1])};
    fprintf(stderr, "cornell %dx%d, 16 spp, %dx%d blocks against 1024 spp: relative RMSE %.2f%% "
            "(sampler) vs %.2f%% (independent): %.2fx; mean worst block %.1f%% vs %.1f%%\n",
            SIZE, SIZE, BLOCK, BLOCK, 100 * error[0], 100 * error[1], error[1] / error[0],
            100 * worst[0], 100 * worst[1]);
    CHECK(error[1] > 1.05 * error[0]); /* measured 1.12x */
    CHECK(worst[1] > worst[0]); /* measured 46.2% vs 42.3% */

    /* Russian roulette on light paths only (throughput below 0.1) against the textbook
     * q = throughput, at equal paths: the paths it cuts carried the light of bounces 3 on. */
    double roulette[2] = {0, 0};
    for (int textbook = 0; textbook < 2; ++textbook) {
        tracer->roulette_weight = textbook ? 1.0 : 0.1;
        for (uint64_t seed = 1; seed <= 4; ++seed) {
            trace(tracer, &view, seed, 16, 0, image);
            double block_worst, e = block_error(image, reference, &block_worst);
            roulette[textbook] += e * e / 4;
        }
    }
    fprintf(stderr, "the same, Russian roulette below throughput 0.1 vs q = throughput: %.2f%% vs "
            "%.2f%%: %.2fx\n", 100 * sqrt(roulette[0]), 100 * sqrt(roulette[1]),
            sqrt(roulette[1] / roulette[0]));
    CHECK(roulette[1] > 1.05 * 1.05 * roulette[0]); /* measured 1.16x */
    rad_tracer_destroy(tracer);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static void test_direct_light_error(void) {
    rad_context_options options = {0};
    options.threads = 1;
    rad_context *ctx = NULL;
    rad_context_create(&options, &ctx);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(ctx, "two-squares", &scene) == RAD_OK);
    rad_tracer *tracer = NULL;
    if (scene) CHECK(rad_tracer_create(ctx, scene, 1, &tracer) == RAD_OK);
    if (!tracer) {
        rad_scene_destroy(scene);
        rad_context_destroy(ctx);
        return;
    }
    const rad_vec3 emitter[4] = {v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0), v3(0, 1, 0)};
    const double rho = 0.5, radiance = 1 / RAD_PI;
    enum { POINTS = 8, PATHS = 64 };
    double squared[2] = {0, 0};
    for (int random = 0; random < 2; ++random) {
        rad_rng rng = rad_rng_make(11, 0);
        for (int p = 0; p < POINTS * POINTS; ++p) {
            rad_vec3 x = v3(0.02 + 0.96 * (p % POINTS + 0.5) / POINTS,
                            0.02 + 0.96 * (p / POINTS + 0.5) / POINTS, 1);
            double expected = rho * radiance * rad_ff_point_polygon(x, v3(0, 0, -1), emitter, 4);
            rad_sampler sampler = rad_sampler_make(7, 0);
            rad_trace_counts counts = {0};
            double sum = 0;
            for (int s = 0; s < PATHS; ++s) {
                sampler.index = random ? random_index(&rng) : (uint64_t)p * PATHS + (uint64_t)s;
                double out[3];
                rad_tracer_radiance(tracer, &sampler, v3_add(x, v3(0, 0, -0.5)), v3(0, 0, 1),
                                    &counts, out);
                sum += out[0];
            }
            double e = (sum / PATHS - expected) / expected;
            squared[random] += e * e / (POINTS * POINTS);
        }
    }
    double error[2] = {sqrt(squared[0]), sqrt(squared[1])};
    fprintf(stderr, "direct light, %d points x %d paths: RMS relative error %.3f%% (sampler) vs "
            "%.3f%% (independent): %.1fx\n", POINTS * POINTS, PATHS, 100 * error[0],
            100 * error[1], error[1] / error[0]);
    CHECK(error[1] > 4 * error[0]); /* measured 6.0x */
    rad_tracer_destroy(tracer);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

int main(void) {
    test_generator_matrices();
    test_stratification();
    test_direct_light_error();
    test_error_at_equal_paths();
    return test_finish();
}
