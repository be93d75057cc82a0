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
/* sqrt never sees a negative number here; without errno to set it vectorises. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-math-errno")
#endif

#include "formfactor/geometric.h"

static rad_status raycast_row(rad_ff_provider *self, size_t patch, float *row) {
    rad_ff_common *r = (rad_ff_common *)self;
    const rad_ff_context *c = &r->c;
    const rad_mesh *mesh = c->mesh;
    rad_ff_source source;
    rad_ff_source_begin(&source, c, patch, c->options.samples, r->maps);
    rad_ff_shaft_begin(c->shaft, source.patch);
    const rad_ff_patch *p = source.patch;
    const rad_vec3 np = p->normal;
    const rad_rays *rays = c->rays;
    const double epsilon = rays->epsilon, inverse_area = 1.0 / p->area, near = 2 * p->radius;
    const int samples = c->options.samples;
    const uint64_t seed = rad_ff_row_seed(c, patch);
    const long n = (long)mesh->element_count, blocks = (n + RAD_FF_BLOCK - 1) / RAD_FF_BLOCK;
    uint64_t receivers = 0, cast = 0;

#pragma omp parallel for schedule(dynamic, 1) num_threads(rad_thread_count(c->ctx)) \
    reduction(+ : receivers, cast)
    for (long block = 0; block < blocks; ++block) {
        const long first = block * RAD_FF_BLOCK;
        const long last = first + RAD_FF_BLOCK < n ? first + RAD_FF_BLOCK : n;
        double sums[RAD_FF_BLOCK] = {0};
        rad_ff_ray_queue queue;
        rad_ray_packet_init(&queue.packet);
        size_t tested_patch = SIZE_MAX, facing_patch = SIZE_MAX;
        int facing = RAD_FF_MIXED;
        int patch_clear = 0;
        for (long e = first; e < last; ++e) {
            const int slot = (int)(e - first);
            if (rad_ff_skip(c, p, patch, (size_t)e, &facing_patch, &facing)) continue;
            ++receivers;
            const int test = !rad_ff_unoccluded(c, (size_t)e, &tested_patch, &patch_clear, 1);
            const rad_vec3 y = mesh->element_centroid[e], ny = mesh->element_normal[e];
            const rad_vec3 from = v3_add(y, v3_scale(ny, epsilon));
            rad_rng rng = rad_rng_make(seed, (uint64_t)e);
            const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
            /* Where the source is not small against the distance the disc approximation fails:
             * cut the source finer (Wallace et al. 1989), up to 16 times the samples. */
            int points = samples;
            double distance = v3_length(v3_sub(y, p->centre));
            if (distance < near) {
                double finer = distance > near / 4 ? ceil(near * near / (distance * distance)) : 16;
                points = samples * (int)finer;
            }
            rad_ff_cursor cursor = rad_ff_cursor_make(&source, &jitter, points);
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
                    f[k] = faces ? weight[k] * cos_e * cos_p * inverse_r * inverse_r /
                                       (RAD_PI * r2 + weight[k])
                                 : 0;
                    margin[k] = epsilon * inverse_r;
                }
                for (int k = 0; k < count; ++k) {
                    if (f[k] <= 0) continue;
                    if (test) {
                        rad_vec3 to = v3(px[k] + epsilon * np.x, py[k] + epsilon * np.y,
                                         pz[k] + epsilon * np.z);
                        cast += (uint64_t)rad_ff_queue_ray(&queue, rays, sums, from, v3_sub(to, from),
                                                           margin[k], f[k], slot);
                    } else {
                        sums[slot] += f[k];
                    }
                }
            }
        }
        rad_ff_queue_flush(&queue, rays, sums);
        for (long e = first; e < last; ++e)
            row[e] = (float)(mesh->element_area[e] * inverse_area * sums[e - first]);
    }
    r->stats.rows++;
    r->stats.receivers += receivers;
    r->stats.rays += cast;
    return RAD_OK;
}

static void raycast_destroy(rad_ff_provider *self) { rad_ff_common_destroy((rad_ff_common *)self); }

rad_status rad_ff_raycast_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_ff_common *common;
    rad_status status = rad_ff_common_create(context, sizeof *common, "raycast", raycast_row,
                                             raycast_destroy, &common);
    if (status) return status;
    *out = &common->base;
    return RAD_OK;
}
