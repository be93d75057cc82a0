/* analytic.c - form factors from the closed-form point-to-polygon factor.
 *
 * Lambert's contour integral (Baum, Rushmeier & Winget 1989): for a differential area at x with
 * normal n and a polygon with vertices v_i,
 *     F(dA -> polygon) = 1 / (2 pi) * sum_i  angle(r_i, r_i+1) * n . unit(r_i x r_i+1),
 * with r_i = v_i - x, exact when nothing is in between. By reciprocity the fraction of the
 * energy leaving patch p that arrives at element e is F_pe = A_e / A_p * F(dA_e -> p), evaluated
 * at the element's centroid over the patch's outline (patch.c; the edges between the patch's own
 * elements would cancel).
 *
 * Visibility: when shaft culling (shaft.c) finds no polygon that could be in between the two
 * patches, the pair is fully visible and no ray is cast (testing single elements of patches
 * that are not clear costs more than their four rays). Otherwise `samples` rays go from the centroid to points
 * spread over the patch; the visible fraction is weighted by each point's share of the point
 * kernel cos cos / r^2, so a partly hidden patch loses what its hidden part would have sent. */

#include "formfactor/geometric.h"

#include <string.h>

#define MAX_CLIPPED 70

/* atan2(y, x) for y >= 0, to 2 ulp and three times as fast as the C library's: the angle is
 * reduced to t in [0, tan(pi/8)], where atan(t) = t P(t^2) with P the degree-10 Chebyshev fit
 * of atan(sqrt(z)) / sqrt(z) on [0, tan^2(pi/8)] (relative error 3.5e-17, fitted with mpmath).
 * Branch-free, so the compiler can keep it in vector registers. */
static inline double angle_from(double y, double x) {
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

/* The contour integral for a polygon whose front normal (any length) is known. */
static inline double point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count,
                                   rad_vec3 front) {
    if (count < 3 || count > MAX_CLIPPED / 2) return 0;
    /* Only the front of the polygon sends light: x must be in front of it. */
    if (v3_dot(front, v3_sub(x, polygon[0])) <= 0) return 0;

    /* Clip to the hemisphere above x (Sutherland-Hodgman against the plane n . (p - x) = 0);
     * work with r_i = v_i - x from here on. */
    rad_vec3 r[MAX_CLIPPED];
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
    double sine[MAX_CLIPPED], cosine[MAX_CLIPPED], weight[MAX_CLIPPED], angle[MAX_CLIPPED];
    for (int i = 0; i < kept; ++i) {
        rad_vec3 r0 = r[i], r1 = r[i + 1 < kept ? i + 1 : 0];
        rad_vec3 c = v3_cross(r0, r1);
        double length = sqrt(v3_dot(c, c));
        sine[i] = length;
        cosine[i] = v3_dot(r0, r1);
        weight[i] = length > 0 ? v3_dot(n, c) / length : 0;
    }
#pragma omp simd
    for (int i = 0; i < kept; ++i) angle[i] = angle_from(sine[i], cosine[i]);
    double sum = 0;
    for (int i = 0; i < kept; ++i) sum += angle[i] * weight[i];
    return fabs(sum) / (2 * RAD_PI);
}

double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count) {
    rad_vec3 front = v3(0, 0, 0);
    for (int i = 0; i < count; ++i)
        front = v3_add(front, v3_cross(polygon[i], polygon[(i + 1) % count]));
    return point_polygon(x, n, polygon, count, front);
}

/* One edge's term of the contour integral, seen from (px, py, pz) with normal (nx, ny, nz). */
static inline double edge_term(double ax, double ay, double az, double bx, double by, double bz,
                               double px, double py, double pz, double nx, double ny, double nz) {
    ax -= px;
    ay -= py;
    az -= pz;
    bx -= px;
    by -= py;
    bz -= pz;
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    double cc = cx * cx + cy * cy + cz * cz;
    double inverse = cc > 0 ? rad_inverse_sqrt(cc) : 0;
    return angle_from(cc * inverse, ax * bx + ay * by + az * bz) * (nx * cx + ny * cy + nz * cz) *
           inverse;
}

/* The contour integral of a quadrilateral for many receivers at once (points y_i, normals n_i)
 * that all see it whole in front of them (nothing to clip): the loop runs across receivers with
 * the corners held in registers, so the compiler vectorises it. */
static void contour_quads(const rad_vec3 *q, int m, const double *y[3], const double *n[3],
                          double *out) {
    const double x0 = q[0].x, y0 = q[0].y, z0 = q[0].z, x1 = q[1].x, y1 = q[1].y, z1 = q[1].z;
    const double x2 = q[2].x, y2 = q[2].y, z2 = q[2].z, x3 = q[3].x, y3 = q[3].y, z3 = q[3].z;
#pragma omp simd
    for (int i = 0; i < m; ++i) {
        const double px = y[0][i], py = y[1][i], pz = y[2][i];
        const double nx = n[0][i], ny = n[1][i], nz = n[2][i];
        double sum = edge_term(x0, y0, z0, x1, y1, z1, px, py, pz, nx, ny, nz) +
                     edge_term(x1, y1, z1, x2, y2, z2, px, py, pz, nx, ny, nz) +
                     edge_term(x2, y2, z2, x3, y3, z3, px, py, pz, nx, ny, nz) +
                     edge_term(x3, y3, z3, x0, y0, z0, px, py, pz, nx, ny, nz);
        out[i] = fabs(sum) / (2 * RAD_PI);
    }
}

static rad_status analytic_row(rad_ff_provider *self, size_t patch, float *out) {
    rad_ff_row row;
    rad_ff_row_begin((rad_ff_common *)self, patch, &row);
    const rad_mesh *mesh = row.mesh;
    const rad_ff_patch *p = row.p;
    const rad_vec3 np = row.np;
    const double epsilon = row.epsilon;
    const int samples = row.samples;
    uint64_t receivers = 0, cast = 0;

#pragma omp parallel for schedule(dynamic, 1) num_threads(row.threads) reduction(+ : receivers, cast)
    for (long block = 0; block < row.blocks; ++block) {
        rad_ff_block b;
        rad_ff_block_begin(&row, block, &b);
        const long first = b.first, last = b.last;
        /* Per receiver: the unoccluded factor, and for those that need rays the kernel weight
         * of all points and of the points seen. */
        double factor[RAD_FF_BLOCK], all[RAD_FF_BLOCK], seen[RAD_FF_BLOCK] = {0};
        double simple[3][RAD_FF_BLOCK], simple_normal[3][RAD_FF_BLOCK];
        int simple_slot[RAD_FF_BLOCK], simple_count = 0;
        for (long e = first; e < last; ++e) {
            const int slot = (int)(e - first);
            factor[slot] = 0;
            all[slot] = 0;
            if (!rad_ff_block_receives(&row, &b, e)) continue;
            ++receivers;
            const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
            if (!rad_ff_near(row.c, p, (size_t)e, 4)) {
                /* The common case, a quadrilateral patch whole in front of the centroid's
                 * tangent plane: queued for the vectorised contour integral; otherwise (clipped,
                 * or a patch of triangles) done here. */
                int whole = p->corner_count == 4 && v3_dot(np, v3_sub(y, p->corners[0])) > 0;
                for (int k = 0; k < p->corner_count && whole; ++k)
                    whole = v3_dot(ny, v3_sub(p->corners[k], y)) > 0;
                if (whole) {
                    simple[0][simple_count] = y.x;
                    simple[1][simple_count] = y.y;
                    simple[2][simple_count] = y.z;
                    simple_normal[0][simple_count] = ny.x;
                    simple_normal[1][simple_count] = ny.y;
                    simple_normal[2][simple_count] = ny.z;
                    simple_slot[simple_count++] = slot;
                    factor[slot] = -1; /* to come */
                } else {
                    factor[slot] = point_polygon(y, ny, p->corners, p->corner_count, np);
                }
            } else {
                /* Close to the patch the factor varies across the element (the centroid's
                 * value is 1-2% low next to a shared edge): average it over the 2 x 2 Gauss
                 * points. Out to 4 times the radii this costs 8% and takes a fifth off the row
                 * error (bench_formfactors, section 3). */
                const rad_ff_element_map map = rad_ff_element_map_make(mesh, (size_t)e);
                static const double g[2] = {RAD_FF_GAUSS_LOW, RAD_FF_GAUSS_HIGH};
                double f = 0;
                for (int k = 0; k < 4; ++k)
                    f += point_polygon(rad_ff_element_map_point(&map, g[k & 1], g[k >> 1]), ny,
                                       p->corners, p->corner_count, np);
                factor[slot] = 0.25 * f;
            }
        }
        if (simple_count) {
            double values[RAD_FF_BLOCK];
            const double *points[3] = {simple[0], simple[1], simple[2]};
            const double *normals[3] = {simple_normal[0], simple_normal[1], simple_normal[2]};
            contour_quads(p->corners, simple_count, points, normals, values);
            for (int i = 0; i < simple_count; ++i) factor[simple_slot[i]] = values[i];
        }
        for (long e = first; e < last; ++e) {
            const int slot = (int)(e - first);
            if (factor[slot] <= 0 || !rad_ff_block_needs_rays(&row, &b, e, 0)) continue;
            const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
            /* Visibility: the kernel-weighted fraction of rays that reach the patch. */
            const rad_vec3 from = v3_add(y, v3_scale(ny, epsilon));
            rad_rng rng = rad_rng_make(row.seed, (uint64_t)e);
            const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
            rad_ff_cursor cursor = rad_ff_cursor_make(&row.source, &jitter, samples);
            for (int s = 0; s < samples; ++s) {
                double weight;
                rad_vec3 x = rad_ff_cursor_next(&cursor, &weight);
                rad_vec3 d = v3_sub(x, y);
                double cos_e = v3_dot(ny, d), cos_p = -v3_dot(np, d), r2 = v3_dot(d, d);
                if (cos_e <= 0 || cos_p <= 0) continue;
                double kernel = weight * cos_e * cos_p / (r2 * r2);
                all[slot] += kernel;
                cast += (uint64_t)rad_ff_queue_segment(&b.queue, row.rays, seen, from,
                                                       v3_add(x, v3_scale(np, epsilon)), kernel, slot);
            }
            /* All points behind one of the planes while part of the patch is in front: one
             * ray to the centre of the part in front decides. */
            if (all[slot] <= 0) {
                all[slot] = 1;
                cast += (uint64_t)rad_ff_queue_segment(&b.queue, row.rays, seen, from,
                                                       v3_add(p->centre, v3_scale(np, epsilon)), 1, slot);
            }
        }
        rad_ff_queue_flush(&b.queue, row.rays, seen);
        for (int slot = 0; slot < (int)(last - first); ++slot)
            if (all[slot] > 0) factor[slot] *= seen[slot] / all[slot];
        rad_ff_block_write(&row, &b, factor, out);
    }
    rad_ff_row_end((rad_ff_common *)self, receivers, cast);
    return RAD_OK;
}

static void analytic_destroy(rad_ff_provider *self) { rad_ff_common_destroy((rad_ff_common *)self); }

rad_status rad_ff_analytic_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_ff_common *common;
    rad_status status = rad_ff_common_create(context, sizeof *common, "analytic", analytic_row,
                                             analytic_destroy, &common);
    if (status) return status;
    *out = &common->base;
    return RAD_OK;
}

/* The registration (factory.c lists it). */
static const rad_method_option analytic_options[] = {
    {"ff-samples", "visibility rays per form factor (4)"},
};
const rad_ff_method_entry rad_ff_method_analytic = {
    {"analytic", "point-to-polygon contour integral (Baum, Rushmeier & Winget 1989), ray-tested visibility", 4, analytic_options, sizeof analytic_options / sizeof analytic_options[0]},
    0,
    rad_ff_analytic_create,
};
