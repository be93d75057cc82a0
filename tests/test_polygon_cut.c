/* test_polygon_cut.c - non-convex polygons cut into convex pieces (src/scene/polygon_cut.c):
 * the pieces cover the polygon (area to 1e-9, every border edge in exactly one piece), each
 * piece is convex, and there are few of them: 1 for a convex polygon, 2 for an L, the teeth
 * plus a few for a comb or a gear, at most 2r + 1 for r reflex corners (Hertel and Mehlhorn's
 * bound). Polygons that cross themselves end in n - 2 triangles, not in a hang. Convex polygons
 * of 1,000 and 10,000 corners split into pieces of at most 64 (rad_polygon_split) cover them,
 * are convex, share each corner among a few, and are thin only as far as they are short. */
#include "radiosity.h"
#include "core/vec3.h"
#include "scene/polygon_cut.h"
#include "test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef double point[2];

static double signed_area(point *p, const uint32_t *index, size_t n) {
    double twice = 0;
    for (size_t k = 0; k < n; ++k) {
        const double *a = p[index ? index[k] : k], *b = p[index ? index[(k + 1) % n] : (k + 1) % n];
        twice += a[0] * b[1] - a[1] * b[0];
    }
    return 0.5 * twice;
}

static size_t reflex_corners(point *p, size_t n) {
    size_t reflex = 0;
    for (size_t k = 0; k < n; ++k) {
        const double *a = p[(k + n - 1) % n], *b = p[k], *c = p[(k + 1) % n];
        reflex += (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < 0;
    }
    return reflex;
}

/* Convex: every corner turns left or goes straight (to rounding), and the turns add up to one
 * turn (so the piece does not wind twice). */
static int piece_convex(point *p, const uint32_t *index, size_t n) {
    double turning = 0;
    for (size_t k = 0; k < n; ++k) {
        const double *a = p[index[k]], *b = p[index[(k + 1) % n]], *c = p[index[(k + 2) % n]];
        double ax = b[0] - a[0], ay = b[1] - a[1], bx = c[0] - b[0], by = c[1] - b[1];
        double sine = ax * by - ay * bx, cosine = ax * bx + ay * by;
        if (sine < -1e-12 * hypot(ax, ay) * hypot(bx, by)) return 0;
        turning += atan2(sine, cosine);
    }
    return fabs(turning - 2 * RAD_PI) < 1e-6;
}

/* Cuts p and checks cover and convexity; returns the piece count (0 on failure). */
static size_t check_cut(rad_context *ctx, point *p, size_t n, const char *name) {
    rad_polygon_pieces pieces = {0};
    if (rad_polygon_cut(ctx, p[0], n, 0, 0, &pieces)) {
        fprintf(stderr, "%s: %s\n", name, rad_context_error(ctx));
        CHECK(0);
        return 0;
    }
    CHECK(pieces.simple);
    double area = 0;
    size_t concave = 0, small = 0;
    /* Every border edge (k, k+1) once, in a piece, in the polygon's direction. */
    unsigned char *border = calloc(n, 1);
    for (size_t k = 0; k < pieces.count; ++k) {
        const uint32_t *index = pieces.corners + pieces.first[k];
        size_t count = pieces.first[k + 1] - pieces.first[k];
        small += count < 3;
        if (count < 3) continue;
        area += signed_area(p, index, count);
        concave += !piece_convex(p, index, count);
        for (size_t i = 0; i < count; ++i)
            if (index[(i + 1) % count] == (index[i] + 1) % n) border[index[i]]++;
    }
    size_t border_once = 0;
    for (size_t k = 0; k < n; ++k) border_once += border[k] == 1;
    free(border);
    double expected = signed_area(p, NULL, n);
    if (fabs(area - expected) > 1e-9 * expected || concave || small || border_once != n)
        fprintf(stderr, "%s: area %.15g of %.15g, %zu concave, %zu small pieces, %zu of %zu "
                "border edges once\n", name, area, expected, concave, small, border_once, n);
    CHECK(fabs(area - expected) <= 1e-9 * expected);
    CHECK(concave == 0);
    CHECK(small == 0);
    CHECK(border_once == n);
    size_t count = pieces.count;
    rad_polygon_pieces_free(ctx, &pieces);
    return count;
}

/* A gear of `teeth` teeth, 4 corners each (as scripts/make_gear.py). */
static point *gear(size_t teeth, double root, double tip) {
    point *p = malloc(4 * teeth * sizeof *p);
    double pitch = 2 * RAD_PI / (double)teeth;
    for (size_t k = 0; k < teeth; ++k) {
        double a = (double)k * pitch;
        double angle[4] = {a, a + 0.125 * pitch, a + 0.375 * pitch, a + 0.5 * pitch};
        double radius[4] = {root, tip, tip, root};
        for (int i = 0; i < 4; ++i) {
            p[4 * k + i][0] = radius[i] * cos(angle[i]);
            p[4 * k + i][1] = radius[i] * sin(angle[i]);
        }
    }
    return p;
}

/* A comb: a bar with `teeth` teeth standing on it, counter-clockwise. */
static point *comb(size_t teeth, size_t *n) {
    *n = 2 + 4 * teeth;
    point *p = malloc(*n * sizeof *p);
    double width = 2.0 / (double)teeth;
    size_t at = 0;
    p[at][0] = 0, p[at++][1] = 0;
    p[at][0] = 2, p[at++][1] = 0;
    for (size_t k = teeth; k-- > 0;) {
        double x0 = (double)k * width;
        double xs[4] = {x0 + 0.75 * width, x0 + 0.75 * width, x0 + 0.25 * width, x0 + 0.25 * width};
        double ys[4] = {0.2, 1.2, 1.2, 0.2};
        for (int i = 0; i < 4; ++i) p[at][0] = xs[i], p[at++][1] = ys[i];
    }
    return p;
}

static void test_small_shapes(rad_context *ctx) {
    point square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    CHECK(check_cut(ctx, square, 4, "square") == 1);
    point square_midpoints[8] = {{0, 0}, {0.5, 0}, {1, 0}, {1, 0.5}, {1, 1}, {0.5, 1}, {0, 1}, {0, 0.5}};
    CHECK(check_cut(ctx, square_midpoints, 8, "square with midpoints") == 1);
    point ell[6] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    CHECK(check_cut(ctx, ell, 6, "L") == 2);
    point tee[8] = {{1, 0}, {2, 0}, {2, 2}, {3, 2}, {3, 3}, {0, 3}, {0, 2}, {1, 2}};
    CHECK(check_cut(ctx, tee, 8, "T") <= 3);
    point arrow[4] = {{0, 0}, {2, 1}, {0, 2}, {1, 1}}; /* a dart: one reflex corner */
    CHECK(check_cut(ctx, arrow, 4, "dart") == 2);
    /* A square with a square hole, bridged the way files do (two edges there and back). */
    point keyhole[12] = {{0, 0}, {3, 0}, {3, 3}, {0, 3}, {0, 1.5}, {1, 1.5},
                         {1, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 1.5}, {0, 1.5}};
    size_t ring = check_cut(ctx, keyhole, 12, "keyhole");
    CHECK(ring >= 4 && ring <= 6);
    point notch[10] = {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}, {0, 2}, {0, 1}};
    size_t u = check_cut(ctx, notch, 10, "U with collinear corners");
    CHECK(u >= 2 && u <= 3);
}

static void test_combs_and_gears(rad_context *ctx) {
    for (size_t teeth = 1; teeth <= 1000; teeth *= 10) {
        size_t n;
        point *p = comb(teeth, &n);
        size_t pieces = check_cut(ctx, p, n, "comb");
        /* The fewest: the teeth and the bar. */
        if (pieces > 2 * (teeth + 1)) fprintf(stderr, "comb of %zu: %zu pieces\n", teeth, pieces);
        CHECK(pieces >= teeth + 1 && pieces <= 2 * (teeth + 1));
        free(p);
    }
    for (size_t teeth = 8; teeth <= 25000; teeth *= 5) {
        point *p = gear(teeth, 0.8, 1.0);
        size_t pieces = check_cut(ctx, p, 4 * teeth, "gear");
        if (pieces > 2 * (teeth + 1)) fprintf(stderr, "gear of %zu: %zu pieces\n", teeth, pieces);
        CHECK(pieces >= teeth + 1 && pieces <= 2 * (teeth + 1));
        free(p);
    }
}

/* Star-shaped polygons with random radii: simple, with many reflex corners. */
static void test_random_stars(rad_context *ctx) {
    srand(16);
    for (int trial = 0; trial < 200; ++trial) {
        size_t n = 3 + (size_t)(rand() % (trial < 150 ? 40 : 2000));
        point *p = malloc(n * sizeof *p);
        for (size_t k = 0; k < n; ++k) {
            double angle = 2 * RAD_PI * ((double)k + 0.9 * rand() / (double)RAND_MAX) / (double)n;
            double radius = 0.2 + rand() / (double)RAND_MAX;
            p[k][0] = radius * cos(angle);
            p[k][1] = radius * sin(angle);
        }
        size_t pieces = check_cut(ctx, p, n, "star");
        CHECK(pieces >= 1 && pieces <= 2 * reflex_corners(p, n) + 1);
        free(p);
    }
}

/* A double spiral (simple, the hard case for ear searches): still cut. */
static void test_spiral(rad_context *ctx) {
    size_t turns_n = 400, n = 2 * turns_n;
    point *p = malloc(n * sizeof *p);
    for (size_t k = 0; k < turns_n; ++k) {
        double angle = 0.05 * (double)k, radius = 1 + 0.05 * (double)k;
        p[k][0] = radius * cos(angle);
        p[k][1] = radius * sin(angle);
        p[n - 1 - k][0] = (radius + 0.02) * cos(angle);
        p[n - 1 - k][1] = (radius + 0.02) * sin(angle);
    }
    /* Clockwise as built (inner arm out, outer arm back): turn it. */
    for (size_t k = 0; k < n / 2; ++k) {
        double x = p[k][0], y = p[k][1];
        p[k][0] = p[n - 1 - k][0], p[k][1] = p[n - 1 - k][1];
        p[n - 1 - k][0] = x, p[n - 1 - k][1] = y;
    }
    CHECK(signed_area(p, NULL, n) > 0);
    size_t pieces = check_cut(ctx, p, n, "spiral");
    CHECK(pieces >= 1 && pieces <= 2 * reflex_corners(p, n) + 1);
    free(p);
}

/* Self-crossing polygons: triangles as clipped, n - 2 of them at most, and no hang. */
static void test_tangled(rad_context *ctx) {
    point bowtie[4] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    rad_polygon_pieces pieces = {0};
    CHECK(rad_polygon_cut(ctx, bowtie[0], 4, 0, 0, &pieces) == RAD_OK);
    CHECK(pieces.count == 2);
    rad_polygon_pieces_free(ctx, &pieces);
    srand(7);
    size_t n = 20000;
    point *p = malloc(n * sizeof *p);
    for (size_t k = 0; k < n; ++k) {
        p[k][0] = rand() / (double)RAND_MAX;
        p[k][1] = rand() / (double)RAND_MAX;
    }
    CHECK(rad_polygon_cut(ctx, p[0], n, 0, 0, &pieces) == RAD_OK);
    CHECK(!pieces.simple);
    CHECK(pieces.count >= 1 && pieces.count <= n - 2);
    for (size_t k = 0; k < pieces.count; ++k) CHECK(pieces.first[k + 1] - pieces.first[k] == 3);
    rad_polygon_pieces_free(ctx, &pieces);
    free(p);
    /* All corners on one line: nothing to cut, and no hang. */
    point line[5] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}};
    CHECK(rad_polygon_cut(ctx, line[0], 5, 0, 0, &pieces) == RAD_OK);
    double area = 0;
    for (size_t k = 0; k < pieces.count; ++k)
        area += fabs(signed_area(line, pieces.corners + pieces.first[k],
                                 pieces.first[k + 1] - pieces.first[k]));
    CHECK(area == 0);
    rad_polygon_pieces_free(ctx, &pieces);
    CHECK(rad_polygon_cut(ctx, line[0], 2, 0, 0, &pieces) == RAD_ERROR_INVALID_ARGUMENT);
}

/* A dent below `dent` does not split a piece; above it does. */
static void test_dent(rad_context *ctx) {
    point dented[5] = {{0, 0}, {1, 0}, {1, 1}, {0.5, 1 - 1e-7}, {0, 1}};
    rad_polygon_pieces pieces = {0};
    CHECK(rad_polygon_cut(ctx, dented[0], 5, 1e-6, 0, &pieces) == RAD_OK);
    CHECK(pieces.count == 1);
    rad_polygon_pieces_free(ctx, &pieces);
    CHECK(rad_polygon_cut(ctx, dented[0], 5, 0, 0, &pieces) == RAD_OK);
    CHECK(pieces.count == 2);
    rad_polygon_pieces_free(ctx, &pieces);
}

/* Thickness: twice the area over the perimeter times the bounds' diagonal (a disk 0.354, a
 * square 0.354, a cap of a circle over an angle t about t / 8.5, a needle near 0). */
static double thickness(point *p, const uint32_t *index, size_t n, double *diagonal) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, perimeter = 0;
    for (size_t k = 0; k < n; ++k) {
        const double *a = p[index ? index[k] : k], *b = p[index ? index[(k + 1) % n] : (k + 1) % n];
        perimeter += hypot(b[0] - a[0], b[1] - a[1]);
        for (int axis = 0; axis < 2; ++axis) {
            lo[axis] = fmin(lo[axis], a[axis]);
            hi[axis] = fmax(hi[axis], a[axis]);
        }
    }
    *diagonal = hypot(hi[0] - lo[0], hi[1] - lo[1]);
    return 2 * signed_area(p, index, n) / (perimeter * *diagonal);
}

/* Splits the convex polygon p into pieces of at most 64 corners and checks them; returns the
 * worst ratio of a piece's thickness to what the polygon's allows it at its size (thickness of
 * the polygon times the piece's diagonal over the polygon's): a piece may be thin only as far as
 * it is short, as a cap over a short chord is; a fan's slivers reach across the polygon. */
static double check_split(rad_context *ctx, point *p, size_t n, const char *name) {
    rad_polygon_pieces pieces = {0};
    if (rad_polygon_split(ctx, p[0], n, RAD_POLYGON_CORNERS_MAX, 0, &pieces)) {
        fprintf(stderr, "%s: %s\n", name, rad_context_error(ctx));
        CHECK(0);
        return 0;
    }
    double diagonal, whole = thickness(p, NULL, n, &diagonal), area = 0, worst = INFINITY;
    size_t concave = 0, large = 0, most = 0;
    size_t *uses = calloc(n, sizeof *uses);
    for (size_t k = 0; k < pieces.count; ++k) {
        const uint32_t *index = pieces.corners + pieces.first[k];
        size_t count = pieces.first[k + 1] - pieces.first[k];
        large += count < 3 || count > RAD_POLYGON_CORNERS_MAX;
        if (count < 3) continue;
        area += signed_area(p, index, count);
        concave += !piece_convex(p, index, count);
        double size, thick = thickness(p, index, count, &size);
        worst = fmin(worst, thick / (whole * size / diagonal));
        for (size_t i = 0; i < count; ++i)
            if (++uses[index[i]] > most) most = uses[index[i]];
    }
    free(uses);
    double expected = signed_area(p, NULL, n);
    printf("%s: %zu pieces, a corner in %zu at most, thinnest %.3f of what its size allows\n",
           name, pieces.count, most, worst);
    if (fabs(area - expected) > 1e-9 * expected || concave || large)
        fprintf(stderr, "%s: area %.15g of %.15g, %zu concave, %zu too small or large\n", name,
                area, expected, concave, large);
    CHECK(fabs(area - expected) <= 1e-9 * expected);
    CHECK(concave == 0 && large == 0);
    CHECK(most <= 8);
    rad_polygon_pieces_free(ctx, &pieces);
    return worst;
}

static void test_split(rad_context *ctx) {
    /* Circles, ellipses with corners spaced at random, and a square with many corners along
     * each side (straight ones). */
    srand(64);
    for (size_t n = 1000; n <= 10000; n *= 10)
        for (int shape = 0; shape < 3; ++shape) {
            point *p = malloc(n * sizeof *p);
            double angle = 0;
            for (size_t k = 0; k < n; ++k) {
                if (shape == 0) angle = 2 * RAD_PI * (double)k / (double)n;
                else if (shape == 1) angle = 2 * RAD_PI * ((double)k + 0.8 * rand() / (double)RAND_MAX) / (double)n;
                double side = 4.0 * (double)k / (double)n, along = side - floor(side);
                static const double corner[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
                int s = (int)side;
                p[k][0] = shape == 2 ? corner[s][0] + along * (corner[s + 1][0] - corner[s][0])
                                     : (shape ? 10 : 1) * cos(angle);
                p[k][1] = shape == 2 ? corner[s][1] + along * (corner[s + 1][1] - corner[s][1])
                                     : sin(angle);
            }
            static const char *names[3] = {"circle", "ellipse", "square"};
            char name[64];
            snprintf(name, sizeof name, "%s of %zu corners", names[shape], n);
            /* Measured 0.664 and 0.500 on the circles, where a fan of 64-gons around corner 0
             * gives 0.32 and 0.039 and the old importer's core (corners every n / 64th) 0.025
             * at 10,000 corners. The ellipse's caps along its flat sides are as thin as the
             * flat boundary under their chords (0.214 and 0.074): chords only between corners
             * cannot make them thicker. */
            double worst = check_split(ctx, p, n, name);
            CHECK(worst >= (shape == 1 ? 0.05 : 0.4));
            free(p);
        }
    /* Small and degenerate input: one piece, or an error; no hang. */
    point square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    rad_polygon_pieces pieces = {0};
    CHECK(rad_polygon_split(ctx, square[0], 4, 64, 0, &pieces) == RAD_OK && pieces.count == 1);
    rad_polygon_pieces_free(ctx, &pieces);
    CHECK(rad_polygon_split(ctx, square[0], 4, 2, 0, &pieces) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(rad_polygon_split(ctx, square[0], 4, 3, 0, &pieces) == RAD_OK && pieces.count == 2);
    rad_polygon_pieces_free(ctx, &pieces);
    enum { LINE = 500 };
    point *line = malloc(LINE * sizeof *line);
    for (size_t k = 0; k < LINE; ++k) line[k][0] = k < LINE / 2 ? (double)k : (double)(LINE - k), line[k][1] = 0;
    CHECK(rad_polygon_split(ctx, line[0], LINE, 64, 0, &pieces) == RAD_OK);
    double area = 0;
    for (size_t k = 0; k < pieces.count; ++k) {
        CHECK(pieces.first[k + 1] - pieces.first[k] <= 64);
        area += fabs(signed_area(line, pieces.corners + pieces.first[k], pieces.first[k + 1] - pieces.first[k]));
    }
    CHECK(area == 0);
    rad_polygon_pieces_free(ctx, &pieces);
    free(line);
    /* A triangle with one corner repeated 200,000 times (edges of no length), and corners that
     * are not numbers: split by count, the area kept, no deep recursion, no hang. */
    enum { REPEATED = 200000 };
    point *spike = malloc((REPEATED + 2) * sizeof *spike);
    spike[0][0] = 0, spike[0][1] = 0;
    for (size_t k = 1; k <= REPEATED; ++k) spike[k][0] = 1, spike[k][1] = 0;
    spike[REPEATED + 1][0] = 0, spike[REPEATED + 1][1] = 1;
    CHECK(rad_polygon_split(ctx, spike[0], REPEATED + 2, 64, 0, &pieces) == RAD_OK);
    area = 0;
    for (size_t k = 0; k < pieces.count; ++k) {
        CHECK(pieces.first[k + 1] - pieces.first[k] <= 64);
        area += signed_area(spike, pieces.corners + pieces.first[k], pieces.first[k + 1] - pieces.first[k]);
    }
    CHECK_NEAR(area, 0.5, 1e-12);
    rad_polygon_pieces_free(ctx, &pieces);
    for (size_t k = 0; k < REPEATED + 2; ++k) spike[k][0] = spike[k][1] = NAN;
    CHECK(rad_polygon_split(ctx, spike[0], REPEATED + 2, 64, 0, &pieces) == RAD_OK);
    for (size_t k = 0; k < pieces.count; ++k) CHECK(pieces.first[k + 1] - pieces.first[k] <= 64);
    rad_polygon_pieces_free(ctx, &pieces);
    free(spike);
    /* A non-convex polygon whose convex pieces are large: a gear of 400 teeth has a core of
     * 400 root corners, cut to pieces of at most 64 inside rad_polygon_cut. */
    point *g = gear(400, 0.8, 1.0);
    CHECK(rad_polygon_cut(ctx, g[0], 1600, 0, 64, &pieces) == RAD_OK);
    double expected = signed_area(g, NULL, 1600);
    area = 0;
    size_t largest = 0, concave = 0;
    for (size_t k = 0; k < pieces.count; ++k) {
        size_t count = pieces.first[k + 1] - pieces.first[k];
        if (count > largest) largest = count;
        area += signed_area(g, pieces.corners + pieces.first[k], count);
        concave += !piece_convex(g, pieces.corners + pieces.first[k], count);
    }
    CHECK(largest <= 64 && concave == 0);
    CHECK(fabs(area - expected) <= 1e-9 * expected);
    rad_polygon_pieces_free(ctx, &pieces);
    free(g);
}

int main(void) {
    rad_context *ctx = NULL;
    rad_context_options options = {0};
    if (rad_context_create(&options, &ctx)) return 1;
    test_small_shapes(ctx);
    test_combs_and_gears(ctx);
    test_random_stars(ctx);
    test_spiral(ctx);
    test_tangled(ctx);
    test_dent(ctx);
    test_split(ctx);
    rad_context_destroy(ctx);
    return test_finish();
}
