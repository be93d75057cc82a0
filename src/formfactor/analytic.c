/* analytic.c - form factors from the closed-form point-to-polygon factor.
 *
 * Lambert's contour integral (Baum, Rushmeier & Winget 1989): for a differential area at x with
 * normal n and a polygon with vertices v_i,
 *     F(dA -> polygon) = 1 / (2 pi) * sum_i  angle(r_i, r_i+1) * n . unit(r_i x r_i+1),
 * with r_i = v_i - x, exact when nothing is in between. By reciprocity the fraction of the
 * energy leaving patch p that arrives at element e is F_pe = A_e / A_p * F(dA_e -> p), evaluated
 * at the element's centroid. Visibility is the fraction of `samples` rays from the centroid to
 * points spread over the patch that Embree finds unblocked in the input geometry. */
#include "formfactor/geometric.h"

#include "core/rng.h"

#include <string.h>

#define MAX_CLIPPED 70

double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count) {
    if (count < 3 || count > MAX_CLIPPED / 2) return 0;
    /* Only the front of the polygon sends light: x must be in front of it. */
    rad_vec3 front = v3(0, 0, 0);
    for (int i = 0; i < count; ++i)
        front = v3_add(front, v3_cross(polygon[i], polygon[(i + 1) % count]));
    if (v3_dot(front, v3_sub(x, polygon[0])) <= 0) return 0;

    /* Clip to the hemisphere above x (Sutherland-Hodgman against the plane n . (p - x) = 0). */
    rad_vec3 clipped[MAX_CLIPPED];
    int kept = 0;
    for (int i = 0; i < count; ++i) {
        rad_vec3 a = polygon[i], b = polygon[(i + 1) % count];
        double da = v3_dot(n, v3_sub(a, x)), db = v3_dot(n, v3_sub(b, x));
        if (da >= 0) clipped[kept++] = a;
        if ((da >= 0) != (db >= 0)) clipped[kept++] = v3_lerp(a, b, da / (da - db));
    }
    if (kept < 3) return 0;

    double sum = 0;
    for (int i = 0; i < kept; ++i) {
        rad_vec3 r0 = v3_sub(clipped[i], x), r1 = v3_sub(clipped[(i + 1) % kept], x);
        rad_vec3 c = v3_cross(r0, r1);
        double length = v3_length(c);
        if (length <= 0) continue;
        sum += atan2(length, v3_dot(r0, r1)) * v3_dot(n, c) / length;
    }
    return fabs(sum) / (2 * RAD_PI);
}

typedef struct analytic_provider {
    rad_ff_provider base;
    rad_ff_context c;
    rad_rays *rays;
} analytic_provider;

/* The corners of every element of a patch, for the contour sums. */
static int patch_polygons(const rad_mesh *mesh, size_t patch, rad_vec3 (*corners)[4], int *counts,
                          int max) {
    int n = 0;
    for (size_t q = mesh->patch_first[patch]; q < mesh->patch_first[patch + 1] && n < max; ++q, ++n) {
        counts[n] = rad_mesh_corner_count(mesh, q);
        for (int k = 0; k < counts[n]; ++k) corners[n][k] = rad_element_corner(mesh, q, k);
    }
    return n;
}

static rad_status analytic_row(rad_ff_provider *self, size_t patch, float *row) {
    analytic_provider *a = (analytic_provider *)self;
    const rad_mesh *mesh = a->c.mesh;
    size_t first = mesh->patch_first[patch], last = mesh->patch_first[patch + 1];
    int members = (int)(last - first);
    rad_vec3(*corners)[4] = rad_alloc(a->c.ctx, (size_t)members, sizeof *corners);
    int *counts = rad_alloc(a->c.ctx, (size_t)members, sizeof *counts);
    if (!corners || !counts) {
        rad_free(a->c.ctx, corners);
        rad_free(a->c.ctx, counts);
        return RAD_ERROR_NO_MEMORY;
    }
    patch_polygons(mesh, patch, corners, counts, members);
    double patch_area = 0;
    for (size_t q = first; q < last; ++q) patch_area += mesh->element_area[q];
    int samples = a->c.options.samples;
    double epsilon = a->rays->epsilon;
    uint64_t seed = a->c.ctx->seed;
    long n = (long)mesh->element_count;

#pragma omp parallel for schedule(dynamic, 64) num_threads(rad_thread_count(a->c.ctx))
    for (long e = 0; e < n; ++e) {
        row[e] = 0;
        if (mesh->element_patch[e] == patch) continue;
        rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
        double f = 0;
        for (int q = 0; q < members; ++q) f += rad_ff_point_polygon(y, ny, corners[q], counts[q]);
        if (f <= 0) continue;
        /* Visibility: rays from the centroid to points spread over the patch. */
        rad_rng rng = rad_rng_make(seed ^ (0x9e3779b97f4a7c15ull * (patch + 1)), (uint64_t)e);
        rad_vec3 from = v3_add(y, v3_scale(ny, epsilon));
        int visible = 0;
        for (int s = 0; s < samples; ++s) {
            size_t q = first + (size_t)((s + rad_rng_next(&rng) % (unsigned)members) % members);
            double u1 = (s + rad_rng_uniform(&rng)) / samples, u2 = rad_rng_uniform(&rng);
            rad_vec3 to = rad_element_sample(mesh, q, u1, u2);
            to = v3_add(to, v3_scale(mesh->element_normal[q], epsilon));
            visible += !rad_rays_occluded(a->rays, from, to);
        }
        row[e] = (float)(mesh->element_area[e] / patch_area * f * visible / samples);
    }
    rad_free(a->c.ctx, corners);
    rad_free(a->c.ctx, counts);
    return RAD_OK;
}

static void analytic_destroy(rad_ff_provider *self) {
    analytic_provider *a = (analytic_provider *)self;
    rad_rays_destroy(a->rays);
    rad_free(a->c.ctx, a);
}

rad_status rad_ff_analytic_create(const rad_ff_context *context, rad_ff_provider **out) {
    analytic_provider *a = rad_alloc_zero(context->ctx, 1, sizeof *a);
    if (!a) return RAD_ERROR_NO_MEMORY;
    a->c = *context;
    a->rays = (rad_rays *)context->rays;
    a->base.method = "analytic";
    a->base.row = analytic_row;
    a->base.destroy = analytic_destroy;
    *out = &a->base;
    return RAD_OK;
}
