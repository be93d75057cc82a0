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

static void analytic_block(const rad_ff_row *row, rad_ff_block *b, float *out) {
    const rad_mesh *mesh = row->mesh;
    const rad_ff_patch *p = row->p;
    const rad_vec3 np = row->np;
    const double epsilon = row->epsilon;
    const int samples = row->samples;
    const long first = b->first, last = b->last;
    /* Per receiver: the unoccluded factor, and for those that need rays the kernel weight
     * of all points and of the points seen. */
    double factor[RAD_FF_BLOCK], all[RAD_FF_BLOCK], seen[RAD_FF_BLOCK] = {0};
    double simple[3][RAD_FF_BLOCK], simple_normal[3][RAD_FF_BLOCK];
    int simple_slot[RAD_FF_BLOCK], simple_count = 0;
    for (long e = first; e < last; ++e) {
        const int slot = (int)(e - first);
        factor[slot] = 0;
        all[slot] = 0;
        if (!rad_ff_block_receives(row, b, e)) continue;
        const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
        if (!rad_ff_near(row->c, p, (size_t)e, 4)) {
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
                factor[slot] = rad_ff_point_polygon_front(y, ny, p->corners, p->corner_count, np);
            }
        } else {
            /* Close to the patch the factor varies across the element (the centroid's
             * value is 1-2% low next to a shared edge): average it over the 2 x 2 Gauss
             * points. Out to 4 times the radii this costs 8% and takes a fifth off the row
             * error (bench_formfactors, section 3). */
            const rad_ff_element_map map = rad_ff_element_map_make(mesh, (size_t)e);
            static const double g[2] = {RAD_FF_GAUSS_LOW, RAD_FF_GAUSS_HIGH};
            rad_vec3 points[4];
            for (int k = 0; k < 4; ++k)
                points[k] = rad_ff_element_map_point(&map, g[k & 1], g[k >> 1]);
            factor[slot] = rad_ff_pair_mean_factor(points, 4, ny, p->corners,
                                                   p->corner_count, np, NULL, NULL);
        }
    }
    if (simple_count) {
        double values[RAD_FF_BLOCK];
        const double *points[3] = {simple[0], simple[1], simple[2]};
        const double *normals[3] = {simple_normal[0], simple_normal[1], simple_normal[2]};
        rad_ff_contour_quads(p->corners, simple_count, points, normals, values);
        for (int i = 0; i < simple_count; ++i) factor[simple_slot[i]] = values[i];
    }
    for (long e = first; e < last; ++e) {
        const int slot = (int)(e - first);
        if (factor[slot] <= 0 || !rad_ff_block_needs_rays(row, b, e, 0)) continue;
        const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
        /* Visibility: the kernel-weighted fraction of rays that reach the patch. */
        const rad_vec3 from = v3_add(y, v3_scale(ny, epsilon));
        rad_rng rng = rad_rng_make(row->seed, (uint64_t)e);
        const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
        rad_ff_cursor cursor = rad_ff_cursor_make(&row->source, &jitter, samples);
        for (int s = 0; s < samples; ++s) {
            double weight;
            rad_vec3 x = rad_ff_cursor_next(&cursor, &weight);
            double kernel = rad_ff_point_kernel(y, ny, x, np, weight);
            if (kernel <= 0) continue;
            all[slot] += kernel;
            rad_ff_queue_segment(&b->queue, row->rays, seen, from,
                                 v3_add(x, v3_scale(np, epsilon)), kernel, slot);
        }
        /* All points behind one of the planes while part of the patch is in front: one
         * ray to the centre of the part in front decides. */
        if (all[slot] <= 0) {
            all[slot] = 1;
            rad_ff_queue_segment(&b->queue, row->rays, seen, from,
                                 v3_add(p->centre, v3_scale(np, epsilon)), 1, slot);
        }
    }
    rad_ff_queue_flush(&b->queue, row->rays, seen);
    for (int slot = 0; slot < (int)(last - first); ++slot)
        if (all[slot] > 0) factor[slot] *= seen[slot] / all[slot];
    rad_ff_block_write(row, b, factor, out);
}

static rad_status analytic_row(rad_ff_provider *self, size_t patch, float *out) {
    return rad_ff_row_run((rad_ff_common *)self, patch, analytic_block, out);
}

static rad_status analytic_rows(rad_ff_provider *self, const size_t *patches, size_t count,
                            float *const *out) {
    return rad_ff_rows_run((rad_ff_common *)self, patches, count, analytic_block, out);
}

static void analytic_destroy(rad_ff_provider *self) { rad_ff_common_destroy((rad_ff_common *)self); }

rad_status rad_ff_analytic_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_ff_common *common;
    rad_status status = rad_ff_common_create(context, sizeof *common, "analytic", analytic_row,
                                             analytic_destroy, &common);
    if (status) return status;
    common->base.rows = analytic_rows;
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
