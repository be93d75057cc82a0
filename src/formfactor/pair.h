/* pair.h - the pair kernel: the form factor between two pieces of surface (issue 11, item 5).
 *
 * Every form-factor method is built from the same few estimates between two pieces of surface;
 * this header holds them, and the row methods (analytic.c, raycast.c, montecarlo.c, hemicube.c)
 * call them:
 *
 *   point - polygon     rad_ff_point_polygon: F(dA -> polygon), Lambert's contour integral
 *                       (Baum, Rushmeier & Winget 1989), exact without occluders;
 *                       rad_ff_contour_quads the same for many points and one quadrilateral,
 *                       vectorised; rad_ff_pair_mean_factor its mean over quadrature points.
 *   point - disc        rad_ff_disc_factor: a small source of area w standing for a disc facing
 *                       the receiver, w cos cos / (pi r^2 + w) (Wallace, Elmquist & Haines 1989)
 *   point - point       rad_ff_point_kernel: cos cos / r^2 with a quadrature weight, the weight a
 *                       visibility ray carries
 *   polygon - polygon   rad_ff_pair_estimate: one pair at a time, as a hierarchy asks for it:
 *                       the factor averaged over the receiver's quadrature points, a bound on
 *                       its error (the spread of the point factor over the receiver) and a
 *                       visibility estimate (rays between the two pieces).
 *
 * Pieces are planar convex polygons with 3 to 35 corners, counter-clockwise seen from the front,
 * given with their unit front normal; only the front of a source sends light and only the front
 * of a receiver takes it. */
#ifndef RAD_FORMFACTOR_PAIR_H
#define RAD_FORMFACTOR_PAIR_H

#include "core/vec3.h"

#include <math.h>
#include <stdint.h>

struct rad_rays;

#define RAD_FF_PAIR_MAX_CORNERS 35

/* ------------------------------------------------------------------------------------------- */
/* Point - polygon                                                                             */

/* atan2(y, x) for y >= 0, to 2 ulp and three times as fast as the C library's: the angle is
 * reduced to t in [0, tan(pi/8)], where atan(t) = t P(t^2) with P the degree-10 Chebyshev fit
 * of atan(sqrt(z)) / sqrt(z) on [0, tan^2(pi/8)] (relative error 3.5e-17, fitted with mpmath).
 * Branch-free, so the compiler can keep it in vector registers. */
static inline double rad_ff_angle_from(double y, double x) {
    double ax = fabs(x);
    int steep = y > ax;
    double num = steep ? ax : y, den = steep ? y : ax;
    double t = den > 0 ? num / den : 0;
    int reduce = t > 0.41421356237309504880; /* tan(pi/8): atan(t) = pi/4 + atan((t-1)/(t+1)) */
    double u = reduce ? (t - 1) / (t + 1) : t;
    double z = u * u;
    double p = 0.0211353731576932452057;
    p = fma(p, z, -0.043480522157164624777);
    p = fma(p, z, 0.0568834922680901047935);
    p = fma(p, z, -0.0664023393042940858874);
    p = fma(p, z, 0.0768995349630685775628);
    p = fma(p, z, -0.0909077307480841378967);
    p = fma(p, z, 0.111111061804559452198);
    p = fma(p, z, -0.142857141809764668302);
    p = fma(p, z, 0.199999999988551101336);
    p = fma(p, z, -0.333333333333284385718);
    p = fma(p, z, 0.99999999999999996532);
    double a = fma(u, p, reduce ? RAD_PI / 4 : 0);
    a = steep ? RAD_PI / 2 - a : a;
    return x < 0 ? RAD_PI - a : a;
}

/* A polygon's front normal from its corners' order (twice its area in length when flat): the sum
 * of v_i x v_i+1, which rad_ff_point_polygon_front takes. */
static inline rad_vec3 rad_ff_polygon_front(const rad_vec3 *polygon, int count) {
    rad_vec3 front = v3(0, 0, 0);
    for (int i = 0; i < count; ++i)
        front = v3_add(front, v3_cross(polygon[i], polygon[(i + 1) % count]));
    return front;
}

/* F(dA at x with normal n -> polygon), the contour integral, for a polygon whose front normal
 * (any length) is known:
 *     F = 1 / (2 pi) * sum_i  angle(r_i, r_i+1) * n . unit(r_i x r_i+1),   r_i = v_i - x,
 * after clipping the polygon to the hemisphere above x. Zero when x is behind the polygon. */
static inline double rad_ff_point_polygon_front(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon,
                                                int count, rad_vec3 front) {
    if (count < 3 || count > RAD_FF_PAIR_MAX_CORNERS) return 0;
    /* Only the front of the polygon sends light: x must be in front of it. */
    if (v3_dot(front, v3_sub(x, polygon[0])) <= 0) return 0;

    /* Clip to the hemisphere above x (Sutherland-Hodgman against the plane n . (p - x) = 0);
     * work with r_i = v_i - x from here on. */
    rad_vec3 r[2 * RAD_FF_PAIR_MAX_CORNERS];
    int kept = 0;
    double da = v3_dot(n, v3_sub(polygon[0], x));
    for (int i = 0; i < count; ++i) {
        rad_vec3 a = v3_sub(polygon[i], x), b = v3_sub(polygon[i + 1 < count ? i + 1 : 0], x);
        double db = v3_dot(n, b);
        if (da >= 0) r[kept++] = a;
        if ((da >= 0) != (db >= 0)) r[kept++] = v3_lerp(a, b, da / (da - db));
        da = db;
    }
    if (kept < 3) return 0;

    /* Each edge: the angle it subtends and the cosine of its plane's normal with n. The
     * angles are independent, so they are taken in a separate loop the compiler vectorises. */
    double sine[2 * RAD_FF_PAIR_MAX_CORNERS], cosine[2 * RAD_FF_PAIR_MAX_CORNERS];
    double weight[2 * RAD_FF_PAIR_MAX_CORNERS], angle[2 * RAD_FF_PAIR_MAX_CORNERS];
    for (int i = 0; i < kept; ++i) {
        rad_vec3 r0 = r[i], r1 = r[i + 1 < kept ? i + 1 : 0];
        rad_vec3 c = v3_cross(r0, r1);
        double length = sqrt(v3_dot(c, c));
        sine[i] = length;
        cosine[i] = v3_dot(r0, r1);
        weight[i] = length > 0 ? v3_dot(n, c) / length : 0;
    }
#pragma omp simd
    for (int i = 0; i < kept; ++i) angle[i] = rad_ff_angle_from(sine[i], cosine[i]);
    double sum = 0;
    for (int i = 0; i < kept; ++i) sum += angle[i] * weight[i];
    return fabs(sum) / (2 * RAD_PI);
}

/* rad_ff_point_polygon_front at each of points[0 .. count) (count at most RAD_FF_MANY), into
 * out: the same values to the bit. The points that see the whole polygon on their side of the
 * plane (the usual case: nothing to clip) are taken together, edge by edge across the points in
 * the same operations and order as one point's, which the compiler vectorises; the others one at
 * a time. A hierarchy's link asks for eight points against one source (its four quadrature
 * points and four corners), where the single calls were 16% of the solve's samples. */
#define RAD_FF_MANY 8
static inline void rad_ff_point_polygon_front_many(const rad_vec3 *points, int count, rad_vec3 n,
                                                   const rad_vec3 *polygon, int corners,
                                                   rad_vec3 front, double *out) {
    for (int k = 0; k < count; ++k) out[k] = 0;
    if (corners < 3 || corners > RAD_FF_PAIR_MAX_CORNERS) return;
    double px[RAD_FF_MANY], py[RAD_FF_MANY], pz[RAD_FF_MANY];
    int slot[RAD_FF_MANY], lanes = 0;
    for (int k = 0; k < count; ++k) {
        rad_vec3 x = points[k];
        if (v3_dot(front, v3_sub(x, polygon[0])) <= 0) continue;
        int whole = 1;
        for (int i = 0; i < corners; ++i) whole &= v3_dot(n, v3_sub(polygon[i], x)) >= 0;
        if (!whole) {
            out[k] = rad_ff_point_polygon_front(x, n, polygon, corners, front);
            continue;
        }
        px[lanes] = x.x;
        py[lanes] = x.y;
        pz[lanes] = x.z;
        slot[lanes++] = k;
    }
    if (!lanes) return;
    for (int l = lanes; l < RAD_FF_MANY; ++l) { /* unused lanes: a copy of the first */
        px[l] = px[0];
        py[l] = py[0];
        pz[l] = pz[0];
    }
    double sum[RAD_FF_MANY] = {0};
    for (int i = 0; i < corners; ++i) {
        const rad_vec3 a = polygon[i], b = polygon[i + 1 < corners ? i + 1 : 0];
#pragma omp simd
        for (int l = 0; l < RAD_FF_MANY; ++l) {
            double ax = a.x - px[l], ay = a.y - py[l], az = a.z - pz[l];
            double bx = b.x - px[l], by = b.y - py[l], bz = b.z - pz[l];
            double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
            double length = sqrt(cx * cx + cy * cy + cz * cz);
            double cosine = ax * bx + ay * by + az * bz;
            double weight = length > 0 ? (n.x * cx + n.y * cy + n.z * cz) / length : 0;
            sum[l] += rad_ff_angle_from(length, cosine) * weight;
        }
    }
    for (int l = 0; l < lanes; ++l) out[slot[l]] = fabs(sum[l]) / (2 * RAD_PI);
}

/* The same with the front normal taken from the corners' order (pair.c). */
double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count);

/* 1 / sqrt(x) for x > 0 to about one ulp, with no library call: the magic-constant first guess
 * (3.4% off) and four Newton steps, each doubling the correct digits. Unlike sqrt() (which may
 * set errno) it lets the compiler vectorise the loops that weigh source points. */
static inline double rad_inverse_sqrt(double x) {
    union {
        double d;
        uint64_t u;
    } bits = {x};
    bits.u = 0x5fe6eb50c7b537a9ull - (bits.u >> 1);
    double y = bits.d, half = 0.5 * x;
    y = y * (1.5 - half * y * y);
    y = y * (1.5 - half * y * y);
    y = y * (1.5 - half * y * y);
    y = y * (1.5 - half * y * y);
    return y;
}

/* One edge's term of the contour integral, seen from (px, py, pz) with normal (nx, ny, nz). */
static inline double rad_ff_edge_term(double ax, double ay, double az, double bx, double by,
                                      double bz, double px, double py, double pz, double nx,
                                      double ny, double nz) {
    ax -= px;
    ay -= py;
    az -= pz;
    bx -= px;
    by -= py;
    bz -= pz;
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    double cc = cx * cx + cy * cy + cz * cz;
    double inverse = cc > 0 ? rad_inverse_sqrt(cc) : 0;
    return rad_ff_angle_from(cc * inverse, ax * bx + ay * by + az * bz) *
           (nx * cx + ny * cy + nz * cz) * inverse;
}

/* The contour integral of a quadrilateral q for m receiving points at once (points y_i,
 * normals n_i, as three coordinate arrays each) that all see it whole in front of them (nothing
 * to clip): the loop runs across receivers with the corners held in registers, so the compiler
 * vectorises it. */
static inline void rad_ff_contour_quads(const rad_vec3 *q, int m, const double *y[3],
                                        const double *n[3], double *out) {
    const double x0 = q[0].x, y0 = q[0].y, z0 = q[0].z, x1 = q[1].x, y1 = q[1].y, z1 = q[1].z;
    const double x2 = q[2].x, y2 = q[2].y, z2 = q[2].z, x3 = q[3].x, y3 = q[3].y, z3 = q[3].z;
#pragma omp simd
    for (int i = 0; i < m; ++i) {
        const double px = y[0][i], py = y[1][i], pz = y[2][i];
        const double nx = n[0][i], ny = n[1][i], nz = n[2][i];
        double sum = rad_ff_edge_term(x0, y0, z0, x1, y1, z1, px, py, pz, nx, ny, nz) +
                     rad_ff_edge_term(x1, y1, z1, x2, y2, z2, px, py, pz, nx, ny, nz) +
                     rad_ff_edge_term(x2, y2, z2, x3, y3, z3, px, py, pz, nx, ny, nz) +
                     rad_ff_edge_term(x3, y3, z3, x0, y0, z0, px, py, pz, nx, ny, nz);
        out[i] = fabs(sum) / (2 * RAD_PI);
    }
}

/* The mean of the point factor over `count` points of a receiver with normal n (a quadrature
 * rule with equal weights); *low and *high (may be NULL) get the smallest and largest point
 * factor, whose difference bounds how far the mean can be from the exact polygon factor when
 * the factor is monotone across the receiver. */
static inline double rad_ff_pair_mean_factor(const rad_vec3 *points, int count, rad_vec3 n,
                                             const rad_vec3 *polygon, int corners,
                                             rad_vec3 front, double *low, double *high) {
    double sum = 0, lo = INFINITY, hi = 0;
    for (int start = 0; start < count; start += RAD_FF_MANY) {
        double f[RAD_FF_MANY];
        int batch = count - start < RAD_FF_MANY ? count - start : RAD_FF_MANY;
        rad_ff_point_polygon_front_many(points + start, batch, n, polygon, corners, front, f);
        for (int k = 0; k < batch; ++k) {
            sum += f[k];
            lo = fmin(lo, f[k]);
            hi = fmax(hi, f[k]);
        }
    }
    if (low) *low = lo;
    if (high) *high = hi;
    return sum * (1.0 / count);
}

/* ------------------------------------------------------------------------------------------- */
/* Point - disc, point - point                                                                 */

/* A source point standing for area w, as a disc facing the receiver at squared distance r2
 * (inverse_r = 1 / sqrt(r2)), with unnormalised cosines cos_e = n_e . d and cos_p = -n_p . d
 * (d from receiver to source): w cos cos / (pi r^2 + w), finite as r -> 0 and exact for a disc
 * seen on its axis (Wallace, Elmquist & Haines 1989). Callers check both cosines are > 0. */
static inline double rad_ff_disc_factor(double w, double cos_e, double cos_p, double r2,
                                        double inverse_r) {
    return w * cos_e * cos_p * inverse_r * inverse_r / (RAD_PI * r2 + w);
}

/* The point-to-point kernel cos cos / r^2 times a quadrature weight, unnormalised cosines as
 * above (so divided by r^4): what a visibility ray from y to x is worth. Zero when either
 * faces away. */
static inline double rad_ff_point_kernel(rad_vec3 y, rad_vec3 ny, rad_vec3 x, rad_vec3 nx,
                                         double weight) {
    rad_vec3 d = v3_sub(x, y);
    double cos_e = v3_dot(ny, d), cos_p = -v3_dot(nx, d), r2 = v3_dot(d, d);
    if (cos_e <= 0 || cos_p <= 0) return 0;
    return weight * cos_e * cos_p / (r2 * r2);
}

/* ------------------------------------------------------------------------------------------- */
/* Polygon - polygon, one pair at a time                                                       */

/* A piece of surface: a planar convex polygon, counter-clockwise seen from the front. */
typedef struct rad_ff_piece {
    const rad_vec3 *corners;
    int corner_count; /* 3 .. RAD_FF_PAIR_MAX_CORNERS; quadrature rules for 3 and 4 */
    rad_vec3 normal;  /* unit front normal */
} rad_ff_piece;

typedef struct rad_ff_pair {
    double form_factor; /* F(receiver -> source): unoccluded times visibility */
    double unoccluded;  /* the mean point factor over the receiver's quadrature points */
    double error;       /* bound on |form_factor - exact|: the point factor's spread over the
                           receiver (quadrature points and corners) times the visibility, plus
                           the whole unoccluded factor when the visibility is partial */
    double visibility;  /* the fraction of rays between the pieces that arrive, in [0, 1] */
    int partial;        /* some rays arrived and some did not, or none did: the visibility is
                           an estimate (a hidden verdict from rays is never proof) */
    int rays;           /* rays cast */
} rad_ff_pair;

/* The receiver's quadrature points (at most 4): the 2 x 2 Gauss rule in a quad's bilinear
 * parameters, the three-point rule (2/3, 1/6, 1/6) on a triangle; the centroid for larger
 * polygons. Returns how many. */
int rad_ff_piece_quadrature(const rad_ff_piece *piece, rad_vec3 out[4]);

/* Estimates the pair receiver <- source. Visibility: a ray from each of the receiver's
 * quadrature points to each of the source's, against `rays` (the input geometry, scene/rays.h;
 * NULL: everything visible, no ray cast). Returns 0 (and a zero pair) when no light can pass:
 * the pieces face away from each other. Thread safe; deterministic (no random numbers). */
int rad_ff_pair_estimate(const rad_ff_piece *receiver, const rad_ff_piece *source,
                         const struct rad_rays *rays, rad_ff_pair *out);

#endif
