/* montecarlo.c - area-to-area form factors by Monte Carlo integration over point pairs.
 *
 * The form factor between patch p and element e is the double area integral
 *     F_pe = 1 / A_p  int_p int_e  V(x, y) cos(theta_x) cos(theta_y) / (pi r^2)  dy dx.
 * With n pairs (x_s on p with area weight w_s, y_s uniform on e)
 *     F_pe ~= A_e / A_p  sum_s  w_s V(x_s, y_s) cos(theta_x) cos(theta_y) / (pi r^2),
 * unbiased, with V from an Embree occlusion ray against the input geometry. Both ends are
 * stratified (R2 lattices with random rotations, see patch.c), which makes the error fall
 * faster than n^-1/2 for smooth integrands. The 1 / r^2 kernel makes the variance of point
 * pairs unbounded between elements that touch (along a corner of the room); for pairs closer
 * than twice their radii the integral over the source is therefore taken in closed form at each
 * sampled receiver point (the contour integral of analytic.c), which keeps it unbiased with
 * bounded variance. Pairs that shaft culling proves unoccluded cast no ray. */
/* sqrt never sees a negative number here; without errno to set it vectorises. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-math-errno")
#endif

#include "formfactor/geometric.h"

static rad_status montecarlo_row(rad_ff_provider *self, size_t patch, float *row) {
    rad_ff_common *m = (rad_ff_common *)self;
    const rad_ff_context *c = &m->c;
    const rad_mesh *mesh = c->mesh;
    rad_ff_source source;
    rad_ff_source_begin(&source, c, patch, c->options.samples, m->maps);
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
            const rad_vec3 ny = mesh->element_normal[e];
            const rad_ff_element_map receiver = rad_ff_element_map_make(mesh, (size_t)e);
            rad_rng rng = rad_rng_make(seed, (uint64_t)e);
            const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
            const double r1 = rad_rng_uniform(&rng), r2 = rad_rng_uniform(&rng);
            /* Near pairs: the kernel's 1 / r^2 gives the point-pair estimate unbounded variance
             * where elements touch; there the source integral is taken in closed form at each
             * receiver point, F(dA_y -> p), and only y (and visibility) are sampled. */
            const int near = rad_ff_near(c, p, (size_t)e, 2);
            rad_ff_cursor cursor = rad_ff_cursor_make(&source, &jitter, samples);
            for (int s = 0; s < samples; ++s) {
                double weight, u, v, f;
                rad_vec3 x = rad_ff_cursor_next(&cursor, &weight);
                /* The receiver's lattice runs with the axes swapped, so pairs do not line up. */
                rad_r2_point(s, r1, r2, &v, &u);
                rad_vec3 y = rad_ff_element_map_point(&receiver, u, v);
                rad_vec3 d = v3_sub(x, y);
                double cos_y = v3_dot(ny, d), cos_x = -v3_dot(np, d);
                if (near) {
                    /* Closed form over the source; the pair only decides visibility. */
                    f = rad_ff_point_polygon(y, ny, p->corners, p->corner_count) / samples;
                    if (f <= 0) continue;
                } else {
                    if (cos_y <= 0 || cos_x <= 0) continue;
                    double distance2 = v3_dot(d, d);
                    f = weight * cos_x * cos_y / (RAD_PI * distance2 * distance2);
                }
                if (test)
                    cast += (uint64_t)rad_ff_queue_segment(&queue, rays, sums,
                                                           v3_add(y, v3_scale(ny, epsilon)),
                                                           v3_add(x, v3_scale(np, epsilon)), f, slot);
                else sums[slot] += f;
            }
        }
        rad_ff_queue_flush(&queue, rays, sums);
        for (long e = first; e < last; ++e)
            row[e] = (float)(mesh->element_area[e] * inverse_area * sums[e - first]);
    }
    m->stats.rows++;
    m->stats.receivers += receivers;
    m->stats.rays += cast;
    return RAD_OK;
}

static void montecarlo_destroy(rad_ff_provider *self) {
    rad_ff_common_destroy((rad_ff_common *)self);
}

rad_status rad_ff_montecarlo_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_ff_common *common;
    rad_status status = rad_ff_common_create(context, sizeof *common, "montecarlo",
                                             montecarlo_row, montecarlo_destroy, &common);
    if (status) return status;
    *out = &common->base;
    return RAD_OK;
}
