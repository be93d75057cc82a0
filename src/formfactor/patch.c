/* patch.c - shooting patches as the methods see them: the convex outline of a patch's elements
 * (for contour integrals and culling), maps from the unit square onto elements, and stratified
 * point sets over a patch. */
#include "formfactor/geometric.h"

#include <stdlib.h>
#include <string.h>

rad_ff_element_map rad_ff_element_map_make(const rad_mesh *mesh, size_t element) {
    rad_ff_element_map m;
    rad_vec3 a = rad_element_corner(mesh, element, 0), b = rad_element_corner(mesh, element, 1),
             c = rad_element_corner(mesh, element, 2);
    m.origin = a;
    m.area = mesh->element_area[element];
    if (rad_mesh_corner_count(mesh, element) == 4) {
        rad_vec3 d = rad_element_corner(mesh, element, 3);
        m.triangle = 0;
        m.e1 = v3_sub(b, a);
        m.e2 = v3_sub(d, a);
        m.e3 = v3_add(v3_sub(a, b), v3_sub(c, d));
    } else {
        m.triangle = 1;
        m.e1 = v3_sub(b, a);
        m.e2 = v3_sub(c, a);
        m.e3 = v3(0, 0, 0);
    }
    return m;
}

rad_vec3 rad_element_sample(const rad_mesh *mesh, size_t element, double u1, double u2) {
    rad_ff_element_map m = rad_ff_element_map_make(mesh, element);
    return rad_ff_element_map_point(&m, u1, u2);
}

void rad_ff_source_begin(rad_ff_source *source, const rad_ff_context *context, size_t patch,
                         int count, rad_ff_element_map *scratch) {
    const rad_mesh *mesh = context->mesh;
    size_t first = mesh->patch_first[patch], last = mesh->patch_first[patch + 1];
    source->patch = &context->patches[patch];
    source->members = (int)(last - first);
    source->count = count;
    source->maps = scratch;
    for (size_t q = first; q < last; ++q) scratch[q - first] = rad_ff_element_map_make(mesh, q);
}

int rad_ff_facing_away(const rad_mesh *mesh, const rad_ff_patch *patch, size_t element) {
    double tolerance = 1e-7 * sqrt(patch->area);
    int corners = rad_mesh_corner_count(mesh, element), in_front = 0;
    for (int k = 0; k < corners && !in_front; ++k)
        in_front = v3_dot(patch->normal, v3_sub(rad_element_corner(mesh, element, k),
                                                patch->centre)) > tolerance;
    if (!in_front) return 1;
    rad_vec3 n = mesh->element_normal[element], y = mesh->element_centroid[element];
    for (int k = 0; k < patch->corner_count; ++k)
        if (v3_dot(n, v3_sub(patch->corners[k], y)) > tolerance) return 0;
    return 1;
}

int rad_ff_patch_facing(const rad_ff_patch *shooter, const rad_ff_patch *receiver) {
    /* rad_ff_facing_away's two tests with the receiver's outline and plane in place of one
     * element's corners and plane. The outline's corners bound every element corner's height
     * over the shooter's plane to within twice the patch's warp; an element's plane differs
     * from the patch's by its tilt and warp. Answers that hold with that slack and a margin of
     * the tolerance cannot differ from the element test. Each test is tried first with the
     * spheres around the outlines (no corners read), then with the corners. */
    const double tolerance = 1e-7 * sqrt(shooter->area), low = 0.5 * tolerance, high = 2 * tolerance;
    const rad_vec3 between = v3_sub(receiver->centre, shooter->centre);
    const double warp = 2 * receiver->warp;
    /* Receiver corners over the shooter's plane, within its radius of the centre's height. */
    double centre = v3_dot(shooter->normal, between);
    double ahead = centre + receiver->radius, behind = centre - receiver->radius;
    if (ahead + warp > low && behind - warp <= high) {
        ahead = -INFINITY;
        behind = INFINITY;
        for (int k = 0; k < receiver->corner_count; ++k) {
            double d = v3_dot(shooter->normal, v3_sub(receiver->corners[k], shooter->centre));
            ahead = d > ahead ? d : ahead;
            behind = d < behind ? d : behind;
        }
    }
    if (ahead + warp <= low) return RAD_FF_AWAY;
    /* The highest shooter corner over the receiver's plane: at least the centre's height (the
     * centre lies inside the outline), at most that plus the radius. |corner - element
     * centroid| is at most the distance of the centres plus both radii (the L1 norm bounds the
     * distance). */
    const double reach = fabs(between.x) + fabs(between.y) + fabs(between.z) + shooter->radius +
                         2 * receiver->radius;
    const double slack = receiver->tilt * reach + receiver->warp;
    double least = -v3_dot(receiver->normal, between), most = least + shooter->radius;
    if (most + slack > low && least - slack <= high) {
        most = -INFINITY;
        for (int k = 0; k < shooter->corner_count; ++k) {
            double height = v3_dot(receiver->normal, v3_sub(shooter->corners[k], receiver->centre));
            most = height > most ? height : most;
        }
        least = most;
    }
    if (most + slack <= low) return RAD_FF_AWAY;
    if (behind - warp > high && least - slack > high) return RAD_FF_FACING;
    return RAD_FF_MIXED;
}

/* ------------------------------------------------------------------------------------------- */
/* Outlines: the convex hull of the patch's element corners in its plane (Andrew's monotone
 * chain). A patch is a block of the grid of one convex polygon, so the hull is the patch. */

typedef struct hull_point {
    double x, y;
    rad_vec3 p;
} hull_point;

static int by_xy(const void *a, const void *b) {
    const hull_point *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return 0;
}

static double turn(const hull_point *o, const hull_point *a, const hull_point *b) {
    return (a->x - o->x) * (b->y - o->y) - (a->y - o->y) * (b->x - o->x);
}

/* Convex hull, counter-clockwise in (x, y); returns the count. The chain itself is exact (a
 * tolerance there can drop a true corner next to a point one rounding error away); corners
 * that lie between their neighbours on a straight line are dropped afterwards. */
static int convex_hull(hull_point *points, int n, hull_point *hull) {
    qsort(points, (size_t)n, sizeof *points, by_xy);
    int k = 0;
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && turn(&hull[k - 2], &hull[k - 1], &points[i]) <= 0) --k;
        hull[k++] = points[i];
    }
    for (int i = n - 2, lower = k + 1; i >= 0; --i) {
        while (k >= lower && turn(&hull[k - 2], &hull[k - 1], &points[i]) <= 0) --k;
        hull[k++] = points[i];
    }
    int count = k > 1 ? k - 1 : k;
    for (int i = 0; i < count && count > 3;) {
        const hull_point *a = &hull[(i + count - 1) % count], *b = &hull[i], *c = &hull[(i + 1) % count];
        double ab = hypot(b->x - a->x, b->y - a->y), bc = hypot(c->x - b->x, c->y - b->y);
        if (fabs(turn(a, b, c)) <= 1e-9 * ab * bc || ab <= 1e-12 * bc || bc <= 1e-12 * ab) {
            memmove(&hull[i], &hull[i + 1], (size_t)(count - i - 1) * sizeof *hull);
            --count;
        } else {
            ++i;
        }
    }
    return count;
}

rad_status rad_ff_patches_create(rad_context *ctx, const rad_mesh *mesh, rad_ff_patch **out,
                                 int *max_members) {
    *out = NULL;
    size_t np = mesh->patch_count;
    int most = 1;
    for (size_t p = 0; p < np; ++p) {
        size_t members = mesh->patch_first[p + 1] - mesh->patch_first[p];
        if (members > (size_t)most) most = (int)members;
    }
    rad_ff_patch *patches = rad_alloc_zero(ctx, np ? np : 1, sizeof *patches);
    hull_point *points = rad_alloc(ctx, 4 * (size_t)most, sizeof *points);
    hull_point *hull = rad_alloc(ctx, 8 * (size_t)most + 2, sizeof *hull);
    if (!patches || !points || !hull) {
        rad_free(ctx, patches);
        rad_free(ctx, points);
        rad_free(ctx, hull);
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for %zu patch outlines", np);
    }
    for (size_t p = 0; p < np; ++p) {
        rad_ff_patch *patch = &patches[p];
        size_t first = mesh->patch_first[p], last = mesh->patch_first[p + 1];
        rad_vec3 centre = v3(0, 0, 0), normal = v3(0, 0, 0);
        double area = 0;
        for (size_t e = first; e < last; ++e) {
            double a = mesh->element_area[e];
            area += a;
            centre = v3_add(centre, v3_scale(mesh->element_centroid[e], a));
            normal = v3_add(normal, v3_scale(mesh->element_normal[e], a));
        }
        patch->area = area;
        patch->centre = area > 0 ? v3_scale(centre, 1.0 / area) : mesh->element_centroid[first];
        patch->normal = v3_normalize(normal);
        rad_vec3 t, b;
        v3_basis(patch->normal, &t, &b);
        int n = 0;
        for (size_t e = first; e < last; ++e)
            for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
                rad_vec3 c = rad_element_corner(mesh, e, k), d = v3_sub(c, patch->centre);
                points[n++] = (hull_point){v3_dot(d, t), v3_dot(d, b), c};
            }
        int count = convex_hull(points, n, hull);
        if (count > RAD_FF_MAX_OUTLINE) count = RAD_FF_MAX_OUTLINE; /* cannot happen for grids */
        patch->corner_count = count;
        patch->radius = 0;
        for (int k = 0; k < count; ++k)
            patch->radius = fmax(patch->radius, v3_length(v3_sub(hull[k].p, patch->centre)));
        /* How far its elements stray from its plane and normal (rounding, or a warped input
         * polygon): the slack of rad_ff_patch_facing. */
        patch->warp = patch->tilt = 0;
        for (size_t e = first; e < last; ++e) {
            patch->tilt = fmax(patch->tilt, v3_length(v3_sub(mesh->element_normal[e], patch->normal)));
            for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k)
                patch->warp = fmax(patch->warp, fabs(v3_dot(patch->normal, v3_sub(rad_element_corner(mesh, e, k), patch->centre))));
        }
        patch->lo = patch->hi = hull[0].p;
        for (int k = 0; k < count; ++k) {
            rad_vec3 c = hull[k].p;
            patch->corners[k] = c;
            patch->lo = v3(fmin(patch->lo.x, c.x), fmin(patch->lo.y, c.y), fmin(patch->lo.z, c.z));
            patch->hi = v3(fmax(patch->hi.x, c.x), fmax(patch->hi.y, c.y), fmax(patch->hi.z, c.z));
        }
    }
    rad_free(ctx, points);
    rad_free(ctx, hull);
    *out = patches;
    *max_members = most;
    return RAD_OK;
}
