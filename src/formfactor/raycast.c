/* raycast.c - form factors by ray casting from the receivers to the source (Wallace, Elmquist &
 * Haines 1989, "A ray tracing algorithm for progressive radiosity").
 *
 * For a shooting patch p and a receiving element e, the factor from the differential area at
 * e's centroid y to p is a sum over n sample points x_s spread over p, each standing for a disc
 * of area w_s = A_p / n facing the receiver:
 *     F(dA_e -> p) = sum_s  V(y, x_s) w_s cos(theta_e) cos(theta_p) / (pi r^2 + w_s),
 * which stays finite as r -> 0 and is exact for a disc seen on its axis. V is 0 or 1, from an
 * Embree occlusion ray against the input geometry (not the mesh). By reciprocity
 *     F_pe = A_e / A_p * F(dA_e -> p).
 * Points are stratified over p's elements and within them (an R2 lattice, rotated at random per
 * receiver, which breaks up aliasing between neighbouring receivers). Where a receiver is
 * closer to the patch than twice the patch's radius, the discs would not be small against the
 * distance, so the source is cut finer, (2 radius / r)^2 times the samples up to 16 times, as
 * Wallace et al. subdivide the source adaptively. Pairs that shaft culling proves unoccluded
 * cast no ray. */

#include "formfactor/geometric.h"

static void raycast_block(const rad_ff_row *row, rad_ff_block *b, float *out) {
    const rad_mesh *mesh = row->mesh;
    const rad_ff_patch *p = row->p;
    const rad_vec3 np = row->np;
    const double epsilon = row->epsilon, near = 2 * p->radius;
    double sums[RAD_FF_BLOCK] = {0};
    for (long e = b->first; e < b->last; ++e) {
        const int slot = (int)(e - b->first);
        if (!rad_ff_block_receives(row, b, e)) continue;
        const int test = rad_ff_block_needs_rays(row, b, e, 1);
        const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
        const rad_vec3 from = v3_add(y, v3_scale(ny, epsilon));
        rad_rng rng = rad_rng_make(row->seed, (uint64_t)e);
        const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
        /* Where the source is not small against the distance the disc approximation fails:
         * cut the source finer (Wallace et al. 1989), up to 16 times the samples. */
        int points = row->samples;
        double distance = v3_length(v3_sub(y, p->centre));
        if (distance < near) {
            double finer = distance > near / 4 ? ceil(near * near / (distance * distance)) : 16;
            points = row->samples * (int)finer;
        }
        rad_ff_cursor cursor = rad_ff_cursor_make(&row->source, &jitter, points);
        for (int start = 0; start < points; start += RAD_FF_BATCH) {
            const int count = points - start < RAD_FF_BATCH ? points - start : RAD_FF_BATCH;
            /* The points first (the cursor walks in order), then the arithmetic in a loop
             * the compiler vectorises, then the rays. */
            double px[RAD_FF_BATCH], py[RAD_FF_BATCH], pz[RAD_FF_BATCH], weight[RAD_FF_BATCH];
            double f[RAD_FF_BATCH], margin[RAD_FF_BATCH];
            for (int k = 0; k < count; ++k) {
                rad_vec3 x = rad_ff_cursor_next(&cursor, &weight[k]);
                px[k] = x.x;
                py[k] = x.y;
                pz[k] = x.z;
            }
#pragma omp simd
            for (int k = 0; k < count; ++k) {
                double dx = px[k] - y.x, dy = py[k] - y.y, dz = pz[k] - y.z;
                double cos_e = ny.x * dx + ny.y * dy + ny.z * dz;
                double cos_p = -(np.x * dx + np.y * dy + np.z * dz);
                /* Disc of area w at distance r: w cos cos / (pi r^2 + w), cosines
                 * unnormalised; the ray's ends are kept epsilon / r from the surfaces. */
                double r2 = dx * dx + dy * dy + dz * dz, inverse_r = rad_inverse_sqrt(r2);
                int faces = cos_e > 0 && cos_p > 0;
                f[k] = faces ? rad_ff_disc_factor(weight[k], cos_e, cos_p, r2, inverse_r) : 0;
                margin[k] = epsilon * inverse_r;
            }
            for (int k = 0; k < count; ++k) {
                if (f[k] <= 0) continue;
                if (test) {
                    rad_vec3 to = v3(px[k] + epsilon * np.x, py[k] + epsilon * np.y,
                                     pz[k] + epsilon * np.z);
                    rad_ff_queue_ray(&b->queue, row->rays, sums, from,
                                     v3_sub(to, from), margin[k], f[k], slot);
                } else {
                    sums[slot] += f[k];
                }
            }
        }
    }
    rad_ff_queue_flush(&b->queue, row->rays, sums);
    rad_ff_block_write(row, b, sums, out);
}

static rad_status raycast_row(rad_ff_provider *self, size_t patch, float *out) {
    return rad_ff_row_run((rad_ff_common *)self, patch, raycast_block, out);
}

static rad_status raycast_rows(rad_ff_provider *self, const size_t *patches, size_t count,
                           float *const *out) {
    return rad_ff_rows_run((rad_ff_common *)self, patches, count, raycast_block, out);
}

static void raycast_destroy(rad_ff_provider *self) { rad_ff_common_destroy((rad_ff_common *)self); }

rad_status rad_ff_raycast_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_ff_common *common;
    rad_status status = rad_ff_common_create(context, sizeof *common, "raycast", raycast_row,
                                             raycast_destroy, &common);
    if (status) return status;
    common->base.rows = raycast_rows;
    *out = &common->base;
    return RAD_OK;
}

/* The registration (factory.c lists it). */
static const rad_method_option raycast_options[] = {
    {"ff-samples", "discs on the source per receiver, one ray each (16)"},
};
const rad_ff_method_entry rad_ff_method_raycast = {
    {"raycast", "rays from the receivers to points on the source (Wallace, Elmquist & Haines 1989)", 16, raycast_options, sizeof raycast_options / sizeof raycast_options[0]},
    0,
    rad_ff_raycast_create,
};
