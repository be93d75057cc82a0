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

#include "formfactor/geometric.h"

static void montecarlo_block(const rad_ff_row *row, rad_ff_block *b, float *out) {
    const rad_mesh *mesh = row->mesh;
    const rad_ff_patch *p = row->p;
    const rad_vec3 np = row->np;
    const double epsilon = row->epsilon;
    const int samples = row->samples;
    double sums[RAD_FF_BLOCK] = {0};
    for (long e = b->first; e < b->last; ++e) {
        const int slot = (int)(e - b->first);
        if (!rad_ff_block_receives(row, b, e)) continue;
        const int test = rad_ff_block_needs_rays(row, b, e, 1);
        const rad_vec3 ny = mesh->element_normal[e];
        const rad_ff_element_map receiver = rad_ff_element_map_make(mesh, (size_t)e);
        rad_rng rng = rad_rng_make(row->seed, (uint64_t)e);
        const rad_ff_jitter jitter = rad_ff_jitter_make(&rng);
        const double r1 = rad_rng_uniform(&rng), r2 = rad_rng_uniform(&rng);
        /* Near pairs: the kernel's 1 / r^2 gives the point-pair estimate unbounded variance
         * where elements touch; there the source integral is taken in closed form at each
         * receiver point, F(dA_y -> p), and only y (and visibility) are sampled. */
        const int near = rad_ff_near(row->c, p, (size_t)e, 2);
        rad_ff_cursor cursor = rad_ff_cursor_make(&row->source, &jitter, samples);
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
                rad_ff_queue_segment(&b->queue, row->rays, sums,
                                     v3_add(y, v3_scale(ny, epsilon)),
                                     v3_add(x, v3_scale(np, epsilon)), f, slot);
            else sums[slot] += f;
        }
    }
    rad_ff_queue_flush(&b->queue, row->rays, sums);
    rad_ff_block_write(row, b, sums, out);
}

static rad_status montecarlo_row(rad_ff_provider *self, size_t patch, float *out) {
    return rad_ff_row_run((rad_ff_common *)self, patch, montecarlo_block, out);
}

static rad_status montecarlo_rows(rad_ff_provider *self, const size_t *patches, size_t count,
                              float *const *out) {
    return rad_ff_rows_run((rad_ff_common *)self, patches, count, montecarlo_block, out);
}

static void montecarlo_destroy(rad_ff_provider *self) {
    rad_ff_common_destroy((rad_ff_common *)self);
}

rad_status rad_ff_montecarlo_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_ff_common *common;
    rad_status status = rad_ff_common_create(context, sizeof *common, "montecarlo",
                                             montecarlo_row, montecarlo_destroy, &common);
    if (status) return status;
    common->base.rows = montecarlo_rows;
    *out = &common->base;
    return RAD_OK;
}

/* The registration (factory.c lists it). */
static const rad_method_option montecarlo_options[] = {
    {"ff-samples", "point pairs per form factor (16)"},
};
const rad_ff_method_entry rad_ff_method_montecarlo = {
    {"montecarlo", "area to area, random point pairs with visibility", 16, montecarlo_options, sizeof montecarlo_options / sizeof montecarlo_options[0]},
    0,
    rad_ff_montecarlo_create,
};
