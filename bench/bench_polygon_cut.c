/* bench_polygon_cut.c - the cut of non-convex polygons into convex pieces against corner count
 * (src/scene/polygon_cut.c): gears (4 corners a tooth, as scripts/make_gear.py), combs, and
 * star-shaped polygons of random radii, and corners at random (crossing themselves: the
 * fallback's time); and circles split into pieces of at most 64 corners, by rad_polygon_split
 * and by rad_polygon_cut with that limit (the readers' two paths). Prints a Markdown table:
 * shape, corners, reflex corners, pieces, the fewest possible where known (teeth + 1), and
 * processor seconds of the cut (best of 3). Timings only: nothing here passes or fails.
 * Usage: bench_polygon_cut [LARGEST (100000)] */
#include "core/context.h"
#include "core/vec3.h"
#include "radiosity.h"
#include "scene/polygon_cut.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static void gear(double *xy, size_t teeth) {
    double pitch = 2 * RAD_PI / (double)teeth;
    for (size_t k = 0; k < teeth; ++k) {
        double a = (double)k * pitch;
        double angle[4] = {a, a + 0.125 * pitch, a + 0.375 * pitch, a + 0.5 * pitch};
        double radius[4] = {0.8, 1, 1, 0.8};
        for (int i = 0; i < 4; ++i) {
            xy[2 * (4 * k + i)] = radius[i] * cos(angle[i]);
            xy[2 * (4 * k + i) + 1] = radius[i] * sin(angle[i]);
        }
    }
}

static void comb(double *xy, size_t teeth) {
    double width = 2.0 / (double)teeth;
    size_t at = 0;
    xy[at++] = 0, xy[at++] = 0, xy[at++] = 2, xy[at++] = 0;
    for (size_t k = teeth; k-- > 0;) {
        double x0 = (double)k * width;
        double xs[4] = {x0 + 0.75 * width, x0 + 0.75 * width, x0 + 0.25 * width, x0 + 0.25 * width};
        double ys[4] = {0.2, 1.2, 1.2, 0.2};
        for (int i = 0; i < 4; ++i) xy[at++] = xs[i], xy[at++] = ys[i];
    }
}

static void star(double *xy, size_t n) {
    srand(16);
    for (size_t k = 0; k < n; ++k) {
        double angle = 2 * RAD_PI * ((double)k + 0.9 * rand() / (double)RAND_MAX) / (double)n;
        double radius = 0.2 + rand() / (double)RAND_MAX;
        xy[2 * k] = radius * cos(angle);
        xy[2 * k + 1] = radius * sin(angle);
    }
}

/* Corners at random in the unit square: a polygon crossing itself everywhere. */
static void tangle(double *xy, size_t n) {
    srand(7);
    for (size_t k = 0; k < 2 * n; ++k) xy[k] = rand() / (double)RAND_MAX;
}

static size_t reflex_corners(const double *xy, size_t n) {
    size_t reflex = 0;
    for (size_t k = 0; k < n; ++k) {
        const double *a = xy + 2 * ((k + n - 1) % n), *b = xy + 2 * k, *c = xy + 2 * ((k + 1) % n);
        reflex += (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < 0;
    }
    return reflex;
}

/* The way a row is cut: rad_polygon_cut with no limit or with 64 corners, or rad_polygon_split. */
enum { CUT, CUT_64, SPLIT_64 };

static void row(rad_context *ctx, const char *shape, const double *xy, size_t n, size_t fewest,
                int how) {
    double best = INFINITY;
    rad_polygon_pieces pieces = {0};
    for (int trial = 0; trial < 3; ++trial) {
        rad_polygon_pieces_free(ctx, &pieces);
        double start = rad_processor_seconds();
        size_t limit = how == CUT_64 ? RAD_POLYGON_CORNERS_MAX : 0;
        rad_status status = how == SPLIT_64
                                ? rad_polygon_split(ctx, xy, n, RAD_POLYGON_CORNERS_MAX, 0, &pieces)
                                : rad_polygon_cut(ctx, xy, n, 0, limit, &pieces);
        if (status) {
            printf("| %s | %zu | failed: %s |\n", shape, n, rad_context_error(ctx));
            return;
        }
        best = fmin(best, rad_processor_seconds() - start);
    }
    char few[32] = "";
    if (fewest) snprintf(few, sizeof few, "%zu", fewest);
    printf("| %s | %zu | %zu | %zu | %s | %.4f |\n", shape, n, reflex_corners(xy, n), pieces.count,
           few, best);
    rad_polygon_pieces_free(ctx, &pieces);
}

int main(int argc, char **argv) {
    size_t largest = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 100000;
    rad_context *ctx = NULL;
    rad_context_options options = {0};
    if (rad_context_create(&options, &ctx)) return 1;
    double *xy = malloc(2 * (largest + 8) * sizeof *xy);
    if (!xy) return 1;
    printf("| shape | corners | reflex | pieces | fewest | seconds |\n|---|---:|---:|---:|---:|---:|\n");
    const size_t sizes[] = {1000, 10000, 40000, 100000, 400000, 1000000};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes && sizes[i] <= largest; ++i) {
        gear(xy, sizes[i] / 4);
        row(ctx, "gear", xy, sizes[i] / 4 * 4, sizes[i] / 4 + 1, CUT);
    }
    for (size_t n = 1000; n <= largest; n *= 10) {
        size_t teeth = (n - 2) / 4;
        comb(xy, teeth);
        row(ctx, "comb", xy, 2 + 4 * teeth, teeth + 1, CUT);
    }
    for (size_t n = 1000; n <= largest; n *= 10) {
        star(xy, n);
        row(ctx, "star", xy, n, 0, CUT);
    }
    for (size_t n = 1000; n <= largest; n *= 10) {
        tangle(xy, n);
        row(ctx, "tangle", xy, n, 0, CUT);
    }
    for (size_t n = 1000; n <= largest; n *= 10) {
        for (size_t k = 0; k < n; ++k) {
            xy[2 * k] = cos(2 * RAD_PI * (double)k / (double)n);
            xy[2 * k + 1] = sin(2 * RAD_PI * (double)k / (double)n);
        }
        row(ctx, "circle, split to 64", xy, n, 0, SPLIT_64);
        row(ctx, "circle, cut to 64", xy, n, 0, CUT_64);
    }
    free(xy);
    rad_context_destroy(ctx);
    return 0;
}
