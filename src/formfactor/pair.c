/* pair.c - the pair kernel (pair.h): the point-to-polygon factor with its front from the
 * corners, receiver quadrature, and the polygon-to-polygon estimate a hierarchy asks for one
 * pair at a time. */
#include "formfactor/pair.h"

#include "scene/rays.h"

#include <string.h>

double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count) {
    return rad_ff_point_polygon_front(x, n, polygon, count, rad_ff_polygon_front(polygon, count));
}

int rad_ff_piece_quadrature(const rad_ff_piece *piece, rad_vec3 out[4]) {
    const rad_vec3 *c = piece->corners;
    if (piece->corner_count == 3) {
        for (int k = 0; k < 3; ++k)
            out[k] = v3_add(v3_scale(c[k], 2.0 / 3),
                            v3_scale(v3_add(c[(k + 1) % 3], c[(k + 2) % 3]), 1.0 / 6));
        return 3;
    }
    if (piece->corner_count == 4) {
        const double g = 0.5 - 0.5 / sqrt(3.0);
        const double uv[4][2] = {{g, g}, {1 - g, g}, {1 - g, 1 - g}, {g, 1 - g}};
        for (int k = 0; k < 4; ++k) {
            double u = uv[k][0], v = uv[k][1];
            out[k] = v3_add(v3_add(v3_scale(c[0], (1 - u) * (1 - v)), v3_scale(c[1], u * (1 - v))),
                            v3_add(v3_scale(c[2], u * v), v3_scale(c[3], (1 - u) * v)));
        }
        return 4;
    }
    rad_vec3 centre = v3(0, 0, 0);
    for (int k = 0; k < piece->corner_count; ++k) centre = v3_add(centre, c[k]);
    out[0] = v3_scale(centre, 1.0 / piece->corner_count);
    return 1;
}

/* Nonzero when some corner of `piece` lies strictly in front of the plane through p, normal n. */
static int any_in_front(const rad_ff_piece *piece, rad_vec3 p, rad_vec3 n) {
    for (int k = 0; k < piece->corner_count; ++k)
        if (v3_dot(n, v3_sub(piece->corners[k], p)) > 0) return 1;
    return 0;
}

int rad_ff_pair_estimate(const rad_ff_piece *receiver, const rad_ff_piece *source,
                         const rad_rays *rays, rad_ff_pair *out) {
    memset(out, 0, sizeof *out);
    if (receiver->corner_count < 3 || receiver->corner_count > RAD_FF_PAIR_MAX_CORNERS ||
        source->corner_count < 3 || source->corner_count > RAD_FF_PAIR_MAX_CORNERS)
        return 0;
    rad_vec3 nr = receiver->normal, ns = source->normal;
    /* Light passes only from the front of the source to the front of the receiver. */
    if (!any_in_front(source, receiver->corners[0], nr) ||
        !any_in_front(receiver, source->corners[0], ns))
        return 0;

    /* The factor: the point factor averaged over the receiver's quadrature points. */
    rad_vec3 x[4], y[4];
    int rn = rad_ff_piece_quadrature(receiver, x), sn = rad_ff_piece_quadrature(source, y);
    double lo, hi;
    double unoccluded = rad_ff_pair_mean_factor(x, rn, nr, source->corners,
                                                source->corner_count, ns, &lo, &hi);
    if (!(unoccluded > 0)) return 0;
    /* Its spread also looks at the corners (pulled in a little, off neighbouring planes): the
     * point factor peaks at an edge shared with the source, where the quadrature points see
     * least. */
    rad_vec3 centre = v3(0, 0, 0);
    for (int k = 0; k < receiver->corner_count; ++k) centre = v3_add(centre, receiver->corners[k]);
    centre = v3_scale(centre, 1.0 / receiver->corner_count);
    rad_vec3 corners[RAD_FF_PAIR_MAX_CORNERS];
    for (int k = 0; k < receiver->corner_count; ++k)
        corners[k] = v3_lerp(receiver->corners[k], centre, 0.01);
    double corner_lo, corner_hi;
    rad_ff_pair_mean_factor(corners, receiver->corner_count, nr, source->corners,
                            source->corner_count, ns, &corner_lo, &corner_hi);
    lo = fmin(lo, corner_lo);
    hi = fmax(hi, corner_hi);

    /* Visibility: a ray from every receiver point to every source point. Rays that all hit
     * something do not prove the pair hidden (a sliver of the receiver may see past the
     * occluder): such a pair is "partial" with visibility 0, and its whole factor is error. */
    int visible = rn * sn, count = rn * sn;
    if (rays) {
        rad_vec3 a[16], b[16];
        uint8_t occluded[16];
        for (int i = 0; i < rn; ++i)
            for (int j = 0; j < sn; ++j) {
                a[i * sn + j] = x[i];
                b[i * sn + j] = y[j];
            }
        rad_rays_occluded_batch(rays, a, b, (size_t)count, occluded);
        visible = 0;
        for (int i = 0; i < count; ++i) visible += !occluded[i];
        out->rays = count;
    }
    double fraction = (double)visible / count;
    out->partial = visible < count;
    out->unoccluded = unoccluded;
    out->visibility = fraction;
    out->form_factor = unoccluded * fraction;
    out->error = (hi - lo) * fraction + (out->partial ? unoccluded : 0);
    return 1;
}
