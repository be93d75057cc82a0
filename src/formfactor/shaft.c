/* shaft.c - shaft culling (Haines & Wallace 1991, "Shaft culling for efficient ray-traced
 * radiosity"): before casting rays between a shooting patch and a receiving element, find the
 * input polygons that could possibly block any segment between them. When there are none the
 * pair is fully visible and no ray is cast.
 *
 * A convex polygon Q cannot block a segment when
 *   - both ends lie on the same side of Q's plane (or on it), or
 *   - Q lies outside the shaft: the convex hull of the bounding boxes of patch and element,
 *     bounded by the faces of the box around both and by the planes through the edges where
 *     one box reaches further along one axis and the other further along another.
 * Applied to all corners of the patch and the element, both tests hold for every segment
 * between them (the set of segments lies in the convex hull of the corners).
 *
 * Both tests hold as well for a set of polygons in one plane, taken with all their corners: no
 * segment with both ends on one side of the plane crosses any of them, and corners all beyond
 * a line keep every one of them out. So the polygons are first gathered into planes
 * (occluders below): a wall cut into hundreds of triangles is one occluder of up to 64 corners,
 * and the tables below are per occluder.
 *
 * Per shooting patch (rad_ff_shaft_begin) the plane test is made against every receiving
 * occluder R as a whole, giving for each R a short list of candidate occluders; per element
 * (rad_ff_shaft_clear) the candidates of its plane are tested against the element itself. The
 * pairwise side table costs occluders^2 bytes, so scenes of more than RAD_FF_SHAFT_OCCLUDERS
 * planes (curved meshes) skip culling and every pair is ray tested; a hierarchy, which tests
 * every occluder for each link (rad_ff_shaft_pair_clear), asks for fewer. */
#include "formfactor/geometric.h"

#include "scene/scene.h"

#include <stdlib.h>
#include <string.h>

#define OCCLUDER_CORNERS 64 /* at most, so planes of many polygons make several occluders */

enum { SIDE_FRONT = 1, SIDE_BACK = 2 };

static inline double min2(double a, double b) { return a < b ? a : b; }
static inline double max2(double a, double b) { return a > b ? a : b; }

struct rad_ff_shaft {
    rad_context *ctx;
    const rad_mesh *mesh;
    size_t polygon_count; /* occluders: input polygons gathered by plane */
    uint32_t *occluder_of; /* scene polygon -> occluder */
    rad_vec3 *normal;    /* unit plane normal of occluder Q */
    double *offset;      /* plane: normal . x = offset */
    double *tolerance;   /* distances within this count as "on the plane" */
    rad_vec3 *lo, *hi;   /* bounds, widened by the tolerance */
    uint32_t *corner_first; /* count + 1: occluder Q's corners are corners[first[Q] .. first[Q+1]) */
    rad_vec3 *corners;
    uint8_t *side;       /* side[R * count + Q]: where occluder R's corners lie against Q's plane */
};

/* Per shooting patch (rad_ff_shaft_begin): one for each row in flight. */
struct rad_ff_shaft_view {
    rad_context *ctx;
    uint8_t *patch_side; /* where the patch's corners lie against Q's plane */
    rad_vec3 patch_lo, patch_hi;
    uint32_t *candidate_first; /* count + 1 */
    uint32_t *candidates;
};

static uint8_t classify(const rad_ff_shaft *shaft, size_t q, const rad_vec3 *points, int count) {
    uint8_t bits = 0;
    for (int k = 0; k < count; ++k) {
        double d = v3_dot(shaft->normal[q], points[k]) - shaft->offset[q];
        if (d > shaft->tolerance[q]) bits |= SIDE_FRONT;
        else if (d < -shaft->tolerance[q]) bits |= SIDE_BACK;
    }
    return bits;
}

void rad_ff_shaft_destroy(rad_ff_shaft *shaft) {
    if (!shaft) return;
    rad_context *ctx = shaft->ctx;
    rad_free(ctx, shaft->occluder_of);
    rad_free(ctx, shaft->normal);
    rad_free(ctx, shaft->offset);
    rad_free(ctx, shaft->tolerance);
    rad_free(ctx, shaft->lo);
    rad_free(ctx, shaft->hi);
    rad_free(ctx, shaft->corner_first);
    rad_free(ctx, shaft->corners);
    rad_free(ctx, shaft->side);
    rad_free(ctx, shaft);
}

rad_ff_shaft_view *rad_ff_shaft_view_create(const rad_ff_shaft *shaft) {
    if (!shaft) return NULL;
    rad_context *ctx = shaft->ctx;
    size_t n = shaft->polygon_count;
    rad_ff_shaft_view *view = rad_alloc_zero(ctx, 1, sizeof *view);
    if (!view) return NULL;
    view->ctx = ctx;
    view->patch_side = rad_alloc(ctx, n, sizeof *view->patch_side);
    view->candidate_first = rad_alloc(ctx, n + 1, sizeof *view->candidate_first);
    view->candidates = rad_alloc(ctx, n * n + 1, sizeof *view->candidates);
    if (!view->patch_side || !view->candidate_first || !view->candidates) {
        rad_ff_shaft_view_destroy(view);
        return NULL;
    }
    return view;
}

void rad_ff_shaft_view_destroy(rad_ff_shaft_view *view) {
    if (!view) return;
    rad_free(view->ctx, view->patch_side);
    rad_free(view->ctx, view->candidate_first);
    rad_free(view->ctx, view->candidates);
    rad_free(view->ctx, view);
}

/* A polygon's plane. */
typedef struct plane_fit {
    rad_vec3 normal, centre;
    int degenerate; /* no plane: never blocks */
} plane_fit;

/* A polygon in the sort by plane. */
typedef struct plane_entry {
    double key[4]; /* the plane rounded: polygons of one plane sort next to each other */
    int alone;     /* not gathered with others (degenerate, or too many corners) */
    uint32_t polygon;
} plane_entry;

static int by_plane(const void *a, const void *b) {
    const plane_entry *p = a, *q = b;
    if (p->alone != q->alone) return p->alone - q->alone;
    for (int i = 0; i < 4; ++i)
        if (p->key[i] != q->key[i]) return p->key[i] < q->key[i] ? -1 : 1;
    return (p->polygon > q->polygon) - (p->polygon < q->polygon);
}

rad_status rad_ff_shaft_create(rad_context *ctx, const rad_scene *scene, const rad_mesh *mesh,
                               size_t most, rad_ff_shaft **out) {
    *out = NULL;
    const size_t polygons = scene->polygon_count;
    /* An occluder holds at most OCCLUDER_CORNERS / 3 polygons: so many polygons make more
     * occluders than `most`. */
    const size_t per_occluder = OCCLUDER_CORNERS / 3;
    if (polygons == 0 || (polygons + per_occluder - 1) / per_occluder > most) return RAD_OK;
    rad_vec3 scene_lo, scene_hi;
    rad_scene_bounds(scene, &scene_lo, &scene_hi);
    const double base = 1e-6 * v3_length(v3_sub(scene_hi, scene_lo));

    /* Each polygon's plane, rounded to a key: polygons of one plane sort next to each other. */
    plane_fit *fit = rad_alloc(ctx, polygons, sizeof *fit);
    plane_entry *order = rad_alloc(ctx, polygons, sizeof *order);
    uint32_t *occluder_of = rad_alloc(ctx, polygons, sizeof *occluder_of);
    uint32_t *leader = rad_alloc(ctx, polygons, sizeof *leader); /* an occluder's first polygon */
    if (!fit || !order || !occluder_of || !leader) {
        rad_free(ctx, fit);
        rad_free(ctx, order);
        rad_free(ctx, occluder_of);
        rad_free(ctx, leader);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t q = 0; q < polygons; ++q) {
        const rad_polygon *polygon = &scene->polygons[q];
        plane_fit *f = &fit[q];
        plane_entry *entry = &order[q];
        f->normal = rad_polygon_normal(scene, polygon);
        f->centre = v3(0, 0, 0);
        for (uint32_t k = 0; k < polygon->count; ++k)
            f->centre = v3_add(f->centre, rad_polygon_vertex(scene, polygon, k));
        f->centre = v3_scale(f->centre, 1.0 / polygon->count);
        /* Degenerate polygons never block (the mesher skips them; Embree hardly hits them);
         * they and polygons of over OCCLUDER_CORNERS corners stand alone. */
        f->degenerate = !isfinite(f->normal.x) || v3_length(f->normal) < 0.5;
        double offset = f->degenerate ? 0 : v3_dot(f->normal, f->centre);
        entry->polygon = (uint32_t)q;
        entry->alone = f->degenerate || polygon->count > OCCLUDER_CORNERS || !isfinite(offset);
        /* + 0.0: no -0, the keys are compared bytewise. */
        entry->key[0] = entry->alone ? 0 : round(f->normal.x * 1e4) + 0.0;
        entry->key[1] = entry->alone ? 0 : round(f->normal.y * 1e4) + 0.0;
        entry->key[2] = entry->alone ? 0 : round(f->normal.z * 1e4) + 0.0;
        entry->key[3] = entry->alone || !(base > 0) ? 0 : round(offset / (1000 * base)) + 0.0;
    }
    qsort(order, polygons, sizeof *order, by_plane);

    /* Occluders: runs of polygons with the same key whose corners all lie within 10 base of the
     * plane of the run's first polygon (the lowest index: the sort breaks ties by index), up to
     * OCCLUDER_CORNERS corners. */
    size_t n = 0, corner_total = 0;
    uint32_t corners_in = 0;
    const plane_entry *first = NULL;
    for (size_t i = 0; i < polygons; ++i) {
        const plane_entry *entry = &order[i];
        const uint32_t q = entry->polygon;
        const rad_polygon *polygon = &scene->polygons[q];
        int join = first && !entry->alone && !first->alone &&
                   memcmp(entry->key, first->key, sizeof entry->key) == 0 &&
                   corners_in + polygon->count <= OCCLUDER_CORNERS;
        const plane_fit *plane = first ? &fit[first->polygon] : NULL;
        for (uint32_t k = 0; k < polygon->count && join; ++k)
            join = fabs(v3_dot(plane->normal, v3_sub(rad_polygon_vertex(scene, polygon, k),
                                                    plane->centre))) <= 10 * base;
        if (!join) {
            first = entry;
            leader[n++] = q;
            corners_in = 0;
        }
        occluder_of[q] = (uint32_t)(n - 1);
        corners_in += polygon->count;
        corner_total += polygon->count;
    }
    if (n > most) {
        rad_free(ctx, fit);
        rad_free(ctx, order);
        rad_free(ctx, occluder_of);
        rad_free(ctx, leader);
        return RAD_OK;
    }

    rad_free(ctx, order);
    rad_ff_shaft *shaft = rad_alloc_zero(ctx, 1, sizeof *shaft);
    if (!shaft) {
        rad_free(ctx, fit);
        rad_free(ctx, occluder_of);
        rad_free(ctx, leader);
        return RAD_ERROR_NO_MEMORY;
    }
    shaft->ctx = ctx;
    shaft->mesh = mesh;
    shaft->polygon_count = n;
    shaft->occluder_of = occluder_of;
    shaft->normal = rad_alloc(ctx, n, sizeof *shaft->normal);
    shaft->offset = rad_alloc(ctx, n, sizeof *shaft->offset);
    shaft->tolerance = rad_alloc(ctx, n, sizeof *shaft->tolerance);
    shaft->lo = rad_alloc(ctx, n, sizeof *shaft->lo);
    shaft->hi = rad_alloc(ctx, n, sizeof *shaft->hi);
    shaft->side = rad_alloc(ctx, n * n, sizeof *shaft->side);
    uint32_t *fill = rad_alloc(ctx, n + 1, sizeof *fill);
    shaft->corner_first = rad_alloc_zero(ctx, n + 1, sizeof *shaft->corner_first);
    shaft->corners = rad_alloc(ctx, corner_total + 1, sizeof *shaft->corners);
    if (!shaft->normal || !shaft->offset || !shaft->tolerance || !shaft->lo || !shaft->hi ||
        !shaft->corner_first || !shaft->corners ||
        !shaft->side || !fill) {
        rad_free(ctx, fill);
        rad_free(ctx, fit);
        rad_free(ctx, leader);
        rad_ff_shaft_destroy(shaft);
        return RAD_ERROR_NO_MEMORY;
    }
    /* Each occluder's corners, in one run (counted first, then placed). */
    for (size_t q = 0; q < polygons; ++q) shaft->corner_first[occluder_of[q] + 1] += scene->polygons[q].count;
    for (size_t g = 0; g < n; ++g) shaft->corner_first[g + 1] += shaft->corner_first[g];
    memcpy(fill, shaft->corner_first, n * sizeof *fill);
    for (size_t q = 0; q < polygons; ++q) {
        const rad_polygon *polygon = &scene->polygons[q];
        for (uint32_t k = 0; k < polygon->count; ++k)
            shaft->corners[fill[occluder_of[q]]++] = rad_polygon_vertex(scene, polygon, k);
    }
    rad_free(ctx, fill);
    /* Each occluder's plane: that of its first polygon, the band widened by how far its
     * corners stray from it (a polygon that is not quite planar: Embree sees its fan of
     * triangles), so the tests stay conservative. */
    for (size_t g = 0; g < n; ++g) {
        const plane_fit *plane = &fit[leader[g]];
        const rad_vec3 *corners = shaft->corners + shaft->corner_first[g];
        const int count = (int)(shaft->corner_first[g + 1] - shaft->corner_first[g]);
        rad_vec3 normal = plane->normal, lo = corners[0], hi = corners[0];
        double warp = 0;
        for (int k = 0; k < count; ++k) {
            lo = v3(fmin(lo.x, corners[k].x), fmin(lo.y, corners[k].y), fmin(lo.z, corners[k].z));
            hi = v3(fmax(hi.x, corners[k].x), fmax(hi.y, corners[k].y), fmax(hi.z, corners[k].z));
            warp = fmax(warp, fabs(v3_dot(normal, v3_sub(corners[k], plane->centre))));
        }
        double tolerance = base + 2 * warp;
        if (plane->degenerate) {
            normal = v3(0, 0, 1);
            tolerance = INFINITY;
        }
        shaft->normal[g] = normal;
        shaft->offset[g] = isfinite(tolerance) ? v3_dot(normal, plane->centre) : 0;
        shaft->tolerance[g] = tolerance;
        rad_vec3 widen = isfinite(tolerance) ? v3(tolerance, tolerance, tolerance) : v3(0, 0, 0);
        shaft->lo[g] = v3_sub(lo, widen);
        shaft->hi[g] = v3_add(hi, widen);
    }
    rad_free(ctx, leader);
    rad_free(ctx, fit);
    for (size_t r = 0; r < n; ++r) {
        const rad_vec3 *corners = shaft->corners + shaft->corner_first[r];
        const int count = (int)(shaft->corner_first[r + 1] - shaft->corner_first[r]);
        for (size_t q = 0; q < n; ++q) shaft->side[r * n + q] = classify(shaft, q, corners, count);
    }
    *out = shaft;
    return RAD_OK;
}

static int boxes_overlap(rad_vec3 alo, rad_vec3 ahi, rad_vec3 blo, rad_vec3 bhi) {
    return alo.x <= bhi.x && blo.x <= ahi.x && alo.y <= bhi.y && blo.y <= ahi.y &&
           alo.z <= bhi.z && blo.z <= ahi.z;
}

/* The edge planes of the shaft between boxes a and b. In the projection on axes (i, j), where
 * one box reaches further along i (direction si) and the other further along j (direction sj),
 * the line through their corner edges bounds the hull: points with ni qi + nj qj > offset lie
 * outside it. */
typedef struct shaft_lines {
    int count;
    int i[12], j[12];
    double ni[12], nj[12], offset[12], length[12];
} shaft_lines;

static void shaft_lines_make(shaft_lines *lines, const double a_lo[3], const double a_hi[3],
                             const double b_lo[3], const double b_hi[3]) {
    static const int axes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    lines->count = 0;
    for (int pair = 0; pair < 3; ++pair) {
        const int i = axes[pair][0], j = axes[pair][1];
        for (int signs = 0; signs < 4; ++signs) {
            const double si = signs & 1 ? 1 : -1, sj = signs & 2 ? 1 : -1;
            double ai = si > 0 ? a_hi[i] : a_lo[i], aj = sj > 0 ? a_hi[j] : a_lo[j];
            double bi = si > 0 ? b_hi[i] : b_lo[i], bj = sj > 0 ? b_hi[j] : b_lo[j];
            double reach_i = si * (ai - bi), reach_j = sj * (aj - bj);
            if (!((reach_i > 0 && reach_j < 0) || (reach_i < 0 && reach_j > 0))) continue;
            double ni = bj - aj, nj = -(bi - ai);
            if (ni * si + nj * sj < 0) {
                ni = -ni;
                nj = -nj;
            }
            int k = lines->count++;
            lines->i[k] = i;
            lines->j[k] = j;
            lines->ni[k] = ni;
            lines->nj[k] = nj;
            lines->offset[k] = ni * ai + nj * aj;
            lines->length[k] = fabs(ni) + fabs(nj); /* >= the Euclidean length: conservative */
        }
    }
}

/* Nonzero when all of polygon Q's corners lie beyond one of the lines (with Q's tolerance). */
static int outside_shaft(const rad_ff_shaft *shaft, size_t q, const shaft_lines *lines) {
    const rad_vec3 *corners = shaft->corners + shaft->corner_first[q];
    const int count = (int)(shaft->corner_first[q + 1] - shaft->corner_first[q]);
    for (int k = 0; k < lines->count; ++k) {
        const double limit = lines->offset[k] + shaft->tolerance[q] * lines->length[k];
        const int i = lines->i[k], j = lines->j[k];
        int all_outside = 1;
        for (int c = 0; c < count && all_outside; ++c)
            all_outside = lines->ni[k] * v3_get(corners[c], i) + lines->nj[k] * v3_get(corners[c], j) > limit;
        if (all_outside) return 1;
    }
    return 0;
}

void rad_ff_shaft_begin(const rad_ff_shaft *shaft, rad_ff_shaft_view *view,
                        const rad_ff_patch *patch) {
    if (!shaft || !view) return;
    size_t n = shaft->polygon_count;
    for (size_t q = 0; q < n; ++q)
        view->patch_side[q] = classify(shaft, q, patch->corners, patch->corner_count);
    view->patch_lo = patch->lo;
    view->patch_hi = patch->hi;
    /* Candidates for each receiving polygon R: the same tests with all of R in place of one
     * element (the shaft from the patch to R holds the shafts to each of its elements). */
    double a_lo[3] = {patch->lo.x, patch->lo.y, patch->lo.z};
    double a_hi[3] = {patch->hi.x, patch->hi.y, patch->hi.z};
    uint32_t used = 0;
    for (size_t r = 0; r < n; ++r) {
        view->candidate_first[r] = used;
        rad_vec3 lo = shaft->lo[r], hi = shaft->hi[r];
        double b_lo[3] = {lo.x, lo.y, lo.z}, b_hi[3] = {hi.x, hi.y, hi.z};
        lo = v3(min2(lo.x, patch->lo.x), min2(lo.y, patch->lo.y), min2(lo.z, patch->lo.z));
        hi = v3(max2(hi.x, patch->hi.x), max2(hi.y, patch->hi.y), max2(hi.z, patch->hi.z));
        shaft_lines lines;
        shaft_lines_make(&lines, a_lo, a_hi, b_lo, b_hi);
        for (size_t q = 0; q < n; ++q) {
            if ((view->patch_side[q] | shaft->side[r * n + q]) != (SIDE_FRONT | SIDE_BACK)) continue;
            if (!boxes_overlap(lo, hi, shaft->lo[q], shaft->hi[q])) continue;
            if (outside_shaft(shaft, q, &lines)) continue;
            view->candidates[used++] = (uint32_t)q;
        }
    }
    view->candidate_first[n] = used;
}

/* The box of points p[0 .. count). */
static void points_box(const rad_vec3 *p, int count, double lo[3], double hi[3]) {
    for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = INFINITY;
        hi[axis] = -INFINITY;
    }
    for (int k = 0; k < count; ++k)
        for (int axis = 0; axis < 3; ++axis) {
            double value = v3_get(p[k], axis);
            lo[axis] = value < lo[axis] ? value : lo[axis];
            hi[axis] = value > hi[axis] ? value : hi[axis];
        }
}

/* The test for a convex receiver with these corners, lying in input polygon r. */
static int clear_to(const rad_ff_shaft *shaft, const rad_ff_shaft_view *view, uint32_t r, const rad_vec3 *corners, int count) {
    uint32_t first = view->candidate_first[r], last = view->candidate_first[r + 1];
    if (first == last) return 1;
    rad_vec3 lo = view->patch_lo, hi = view->patch_hi;
    for (int k = 0; k < count; ++k) {
        rad_vec3 c = corners[k];
        lo = v3(min2(lo.x, c.x), min2(lo.y, c.y), min2(lo.z, c.z));
        hi = v3(max2(hi.x, c.x), max2(hi.y, c.y), max2(hi.z, c.z));
    }
    shaft_lines lines;
    lines.count = -1; /* made when first needed */
    for (uint32_t i = first; i < last; ++i) {
        uint32_t q = view->candidates[i];
        if (!boxes_overlap(lo, hi, shaft->lo[q], shaft->hi[q])) continue;
        if ((view->patch_side[q] | classify(shaft, q, corners, count)) != (SIDE_FRONT | SIDE_BACK))
            continue;
        if (lines.count < 0) {
            double a_lo[3] = {view->patch_lo.x, view->patch_lo.y, view->patch_lo.z};
            double a_hi[3] = {view->patch_hi.x, view->patch_hi.y, view->patch_hi.z};
            double b_lo[3], b_hi[3];
            points_box(corners, count, b_lo, b_hi);
            shaft_lines_make(&lines, a_lo, a_hi, b_lo, b_hi);
        }
        if (outside_shaft(shaft, q, &lines)) continue;
        return 0;
    }
    return 1;
}

int rad_ff_shaft_clear(const rad_ff_shaft *shaft, const rad_ff_shaft_view *view, size_t element) {
    if (!shaft || !view) return 0;
    const rad_mesh *mesh = shaft->mesh;
    rad_vec3 corners[4];
    int count = rad_mesh_corner_count(mesh, element);
    for (int k = 0; k < count; ++k) corners[k] = rad_element_corner(mesh, element, k);
    return clear_to(shaft, view, shaft->occluder_of[mesh->element_polygon[element]], corners, count);
}

int rad_ff_shaft_clear_patch(const rad_ff_shaft *shaft, const rad_ff_shaft_view *view,
                             const rad_ff_patch *receiver, uint32_t polygon) {
    if (!shaft || !view) return 0;
    return clear_to(shaft, view, shaft->occluder_of[polygon], receiver->corners, receiver->corner_count);
}

int rad_ff_shaft_pair_clear(const rad_ff_shaft *shaft, const rad_vec3 *a, int na,
                            const rad_vec3 *b, int nb) {
    if (!shaft || na < 1 || nb < 1 || na > 4 || nb > 4) return 0;
    double a_lo[3], a_hi[3], b_lo[3], b_hi[3];
    points_box(a, na, a_lo, a_hi);
    points_box(b, nb, b_lo, b_hi);
    const rad_vec3 lo = v3(min2(a_lo[0], b_lo[0]), min2(a_lo[1], b_lo[1]), min2(a_lo[2], b_lo[2]));
    const rad_vec3 hi = v3(max2(a_hi[0], b_hi[0]), max2(a_hi[1], b_hi[1]), max2(a_hi[2], b_hi[2]));
    shaft_lines lines;
    lines.count = -1; /* made when first needed */
    for (size_t q = 0; q < shaft->polygon_count; ++q) {
        if (!boxes_overlap(lo, hi, shaft->lo[q], shaft->hi[q])) continue;
        if ((classify(shaft, q, a, na) | classify(shaft, q, b, nb)) != (SIDE_FRONT | SIDE_BACK))
            continue;
        if (lines.count < 0) shaft_lines_make(&lines, a_lo, a_hi, b_lo, b_hi);
        if (outside_shaft(shaft, q, &lines)) continue;
        return 0;
    }
    return 1;
}
