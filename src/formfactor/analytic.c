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
 * Visibility: when shaft culling (shaft.c) finds no polygon that could be in between, the pair
 * is fully visible and no ray is cast. Otherwise `samples` rays go from the centroid to points
 * spread over the patch; the visible fraction is weighted by each point's share of the point
 * kernel cos cos / r^2, so a partly hidden patch loses what its hidden part would have sent. */
#include "formfactor/geometric.h"

#include <string.h>

#define MAX_CLIPPED 70

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

    double sum = 0;
    for (int i = 0; i < kept; ++i) {
        rad_vec3 r0 = r[i], r1 = r[i + 1 < kept ? i + 1 : 0];
        rad_vec3 c = v3_cross(r0, r1);
        double length = sqrt(v3_dot(c, c));
        if (length <= 0) continue;
        sum += atan2(length, v3_dot(r0, r1)) * v3_dot(n, c) / length;
    }
    return fabs(sum) / (2 * RAD_PI);
}

double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count) {
    rad_vec3 front = v3(0, 0, 0);
    for (int i = 0; i < count; ++i)
        front = v3_add(front, v3_cross(polygon[i], polygon[(i + 1) % count]));
    return point_polygon(x, n, polygon, count, front);
}

static rad_status analytic_row(rad_ff_provider *self, size_t patch, float *row) {
    rad_ff_common *a = (rad_ff_common *)self;
    const rad_ff_context *c = &a->c;
    const rad_mesh *mesh = c->mesh;
    rad_ff_source source;
    rad_ff_source_begin(&source, c, patch, c->options.samples, a->maps);
    rad_ff_shaft_begin(c->shaft, source.patch);
    const rad_ff_patch *p = source.patch;
    const rad_vec3 np = p->normal;
    const rad_rays *rays = c->rays;
    const double epsilon = rays->epsilon, inverse_area = 1.0 / p->area;
    const int samples = c->options.samples;
    const uint64_t seed = rad_ff_row_seed(c, patch);
    const long n = (long)mesh->element_count, blocks = (n + RAD_FF_BLOCK - 1) / RAD_FF_BLOCK;
    uint64_t receivers = 0, cast = 0;

#pragma omp parallel for schedule(dynamic, 1) num_threads(rad_thread_count(c->ctx)) \
    reduction(+ : receivers, cast)
    for (long block = 0; block < blocks; ++block) {
        const long first = block * RAD_FF_BLOCK;
        const long last = first + RAD_FF_BLOCK < n ? first + RAD_FF_BLOCK : n;
        /* Per receiver: the unoccluded factor, and for those that need rays the kernel weight
         * of all points and of the points seen. */
        double factor[RAD_FF_BLOCK], all[RAD_FF_BLOCK], seen[RAD_FF_BLOCK] = {0};
        rad_ff_ray_queue queue;
        queue.packet.count = 0;
        for (long e = first; e < last; ++e) {
            const int slot = (int)(e - first);
            factor[slot] = 0;
            all[slot] = 0;
            if (mesh->element_patch[e] == patch || rad_ff_facing_away(mesh, p, (size_t)e)) continue;
            ++receivers;
            const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
            factor[slot] = point_polygon(y, ny, p->corners, p->corner_count, np);
            if (factor[slot] <= 0 || rad_ff_shaft_clear(c->shaft, (size_t)e)) continue;
            /* Visibility: the kernel-weighted fraction of rays that reach the patch. */
            const rad_vec3 from = v3_add(y, v3_scale(ny, epsilon));
            rad_rng rng = rad_rng_make(seed, (uint64_t)e);
            const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
            for (int s = 0; s < samples; ++s) {
                double weight;
                rad_vec3 x = rad_ff_source_point(&source, &jitter, s, samples, &weight);
                rad_vec3 d = v3_sub(x, y);
                double cos_e = v3_dot(ny, d), cos_p = -v3_dot(np, d), r2 = v3_dot(d, d);
                if (cos_e <= 0 || cos_p <= 0) continue;
                double kernel = weight * cos_e * cos_p / (r2 * r2);
                all[slot] += kernel;
                cast += (uint64_t)rad_ff_queue_segment(&queue, rays, seen, from,
                                                       v3_add(x, v3_scale(np, epsilon)), kernel, slot);
            }
            /* All points behind one of the planes while part of the patch is in front: one
             * ray to the centre of the part in front decides. */
            if (all[slot] <= 0) {
                all[slot] = 1;
                cast += (uint64_t)rad_ff_queue_segment(&queue, rays, seen, from,
                                                       v3_add(p->centre, v3_scale(np, epsilon)), 1, slot);
            }
        }
        rad_ff_queue_flush(&queue, rays, seen);
        for (long e = first; e < last; ++e) {
            const int slot = (int)(e - first);
            double f = factor[slot];
            if (all[slot] > 0) f *= seen[slot] / all[slot];
            row[e] = (float)(mesh->element_area[e] * inverse_area * f);
        }
    }
    a->stats.rows++;
    a->stats.receivers += receivers;
    a->stats.rays += cast;
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
