/* emitters.c - the emitter table (see emitters.h). */
#include "light/emitters.h"

#include <math.h>
#include <stdlib.h>

rad_status rad_emitter_table_reserve(rad_context *ctx, rad_emitter_table *table, size_t capacity) {
    table->count = 0;
    table->capacity = 0;
    table->group_count = 0;
    if (capacity == 0) return RAD_OK;
    table->emitters = rad_alloc(ctx, capacity, sizeof *table->emitters);
    table->cdf = rad_alloc(ctx, capacity, sizeof *table->cdf);
    table->guide = capacity < UINT32_MAX ? rad_alloc(ctx, capacity + 1, sizeof *table->guide) : NULL;
    table->group_first = rad_alloc_zero(ctx, capacity + 1, sizeof *table->group_first);
    table->groups = rad_alloc(ctx, capacity, sizeof *table->groups);
    if (!table->emitters || !table->cdf || !table->guide || !table->group_first || !table->groups)
        return RAD_ERROR_NO_MEMORY;
    table->capacity = capacity;
    return RAD_OK;
}

int32_t rad_emitter_table_add(rad_emitter_table *table, rad_vec3 a, rad_vec3 b, rad_vec3 c,
                              rad_vec3 normal, const double radiance[3]) {
    if (table->count >= table->capacity) return -1;
    rad_emitter t;
    t.p0 = a;
    t.e1 = v3_sub(b, a);
    t.e2 = v3_sub(c, a);
    t.area = 0.5 * v3_length(v3_cross(t.e1, t.e2));
    if (!(t.area > 0)) return -1;
    t.normal = normal;
    for (int k = 0; k < 3; ++k) t.radiance[k] = radiance[k];
    t.parallelogram = 0;
    table->emitters[table->count] = t;
    return (int32_t)table->count++;
}

int32_t rad_emitter_table_add_parallelogram(rad_emitter_table *table, rad_vec3 p0, rad_vec3 e1,
                                            rad_vec3 e2, rad_vec3 normal, const double radiance[3]) {
    int32_t k = rad_emitter_table_add(table, p0, v3_add(p0, e1), v3_add(p0, e2), normal, radiance);
    if (k < 0) return k;
    table->emitters[k].area *= 2;
    table->emitters[k].parallelogram = 1;
    return k;
}

void rad_emitter_table_close_group(rad_emitter_table *table) {
    if (!table->capacity || table->count == table->group_first[table->group_count]) return;
    table->group_first[++table->group_count] = (uint32_t)table->count;
}

/* The point of entry `light` for (u0, u1): uniform on its parallelogram or triangle (Turk 1990). */
static rad_vec3 emitter_point(const rad_emitter *light, double u0, double u1) {
    if (light->parallelogram)
        return v3_add(light->p0, v3_add(v3_scale(light->e1, u0), v3_scale(light->e2, u1)));
    double root = sqrt(u0);
    return v3_add(light->p0, v3_add(v3_scale(light->e1, root * (1 - u1)),
                                    v3_scale(light->e2, root * u1)));
}

/* Entry e's corners into corner[]; their count (4 for a parallelogram, 3 for a triangle). */
static int emitter_corners(const rad_emitter *e, rad_vec3 corner[4]) {
    corner[0] = e->p0;
    corner[1] = v3_add(e->p0, e->e1);
    corner[2] = v3_add(e->p0, e->e2);
    corner[3] = v3_add(corner[1], e->e2);
    return e->parallelogram ? 4 : 3;
}

static rad_status build_tree(rad_context *ctx, rad_emitter_table *table);

/* table->group_fields: field f of group g at [f * group_count + g], in single precision (the
 * weights only guide the choice: sample and density read the same numbers, so precision cannot
 * bias it, and twice the lanes a vector halve the loop's time). */
enum { FIELD_CX, FIELD_CY, FIELD_CZ, FIELD_NX, FIELD_NY, FIELD_NZ, FIELD_AREA, FIELD_RADIUS,
       FIELD_POWER, GROUP_FIELDS };

static rad_status fill_group_fields(rad_context *ctx, rad_emitter_table *table) {
    size_t n = table->group_count;
    float *f = table->group_fields = rad_alloc(ctx, n * GROUP_FIELDS, sizeof *f);
    if (!f) return RAD_ERROR_NO_MEMORY;
    for (size_t g = 0; g < n; ++g) {
        const struct rad_emitter_group *group = &table->groups[g];
        f[FIELD_CX * n + g] = (float)group->centre.x;
        f[FIELD_CY * n + g] = (float)group->centre.y;
        f[FIELD_CZ * n + g] = (float)group->centre.z;
        f[FIELD_NX * n + g] = (float)group->normal.x;
        f[FIELD_NY * n + g] = (float)group->normal.y;
        f[FIELD_NZ * n + g] = (float)group->normal.z;
        f[FIELD_AREA * n + g] = (float)group->area;
        f[FIELD_RADIUS * n + g] = (float)group->radius;
        f[FIELD_POWER * n + g] = (float)group->probability;
    }
    return RAD_OK;
}

rad_status rad_emitter_table_finish(rad_context *ctx, rad_emitter_table *table,
                                    rad_emitter_selection selection) {
    /* Cumulative weights, then normalised: the last entry is exactly 1. */
    double total = 0;
    for (size_t i = 0; i < table->count; ++i) {
        const rad_emitter *e = &table->emitters[i];
        double weight = selection == RAD_EMITTERS_BY_AREA
                            ? e->area
                            : e->area * (e->radiance[0] + e->radiance[1] + e->radiance[2]);
        total += weight;
        table->cdf[i] = total;
    }
    if (!(total > 0)) {
        table->count = 0;
        return RAD_OK;
    }
    for (size_t i = 0; i < table->count; ++i) table->cdf[i] /= total;
    table->cdf[table->count - 1] = 1;
    /* Entries added after the last group ended (or in a table without groups) make none. */
    if (table->group_count && table->group_first[table->group_count] != table->count)
        table->group_count = 0;
    for (size_t g = 0; g < table->group_count; ++g) {
        struct rad_emitter_group *group = &table->groups[g];
        uint32_t first = table->group_first[g], end = table->group_first[g + 1];
        rad_vec3 weighted = v3(0, 0, 0);
        group->area = 0;
        for (uint32_t k = first; k < end; ++k) {
            const rad_emitter *e = &table->emitters[k];
            double to_centre = e->parallelogram ? 0.5 : 1.0 / 3;
            rad_vec3 centre = v3_add(e->p0, v3_scale(v3_add(e->e1, e->e2), to_centre));
            weighted = v3_add(weighted, v3_scale(centre, e->area));
            group->area += e->area;
        }
        group->normal = table->emitters[first].normal;
        group->centre = v3_scale(weighted, 1 / group->area);
        group->radius = 0;
        for (uint32_t k = first; k < end; ++k) {
            rad_vec3 corner[4];
            for (int c = 0, n = emitter_corners(&table->emitters[k], corner); c < n; ++c)
                group->radius = fmax(group->radius, v3_length(v3_sub(corner[c], group->centre)));
        }
        group->probability = table->cdf[end - 1] - (first ? table->cdf[first - 1] : 0);
    }
    size_t first = 0;
    for (size_t b = 0; b <= table->count; ++b) {
        double u = (double)b / (double)table->count;
        while (first + 1 < table->count && table->cdf[first] <= u) ++first;
        table->guide[b] = (uint32_t)first;
    }
    if (table->group_count < 2) return RAD_OK;
    rad_status status = fill_group_fields(ctx, table);
    if (status == RAD_OK && table->group_count > RAD_EMITTERS_LOCAL_MAX)
        status = build_tree(ctx, table);
    return status;
}

/* ------------------------------------------------------------------------------------------- */
/* The light tree (Conty Estevez & Kulla 2018, "Importance sampling of many lights with adaptive
 * tree splitting"), for tables of more groups than the exact choice below loops over: a binary
 * tree over the groups, split at the median of their centres along the widest axis down to
 * leaves of at most LEAF_GROUPS. A node bounds its groups by a box (and the sphere around it)
 * and their fronts by a cone (axis, spread). Its importance at x is its power times
 * cos(theta') / d^2, theta' the smallest angle any of its points' fronts can make with the
 * direction to x (the angle to the axis less the spread and the half-angle the sphere
 * subtends), zero past 90 degrees (no front faces x), and d the distance from x to the box (at
 * least 1% of the radius; the paper's distance to the centre, clamped to the radius, splits
 * every node around x by power alone). A receiver descends from the root choosing a child by
 * the two importances, then a group of the leaf by the exact weights (weight_of); P_g(x) is
 * the product of its choices. */

/* A node of at most this many groups is a leaf: the choice among them is the exact one. */
#define LEAF_GROUPS 8

typedef struct keyed {
    double key;
    uint32_t group;
} keyed;

static int compare_keyed(const void *a, const void *b) {
    const keyed *p = a, *q = b;
    if (p->key != q->key) return p->key < q->key ? -1 : 1;
    return p->group < q->group ? -1 : p->group > q->group;
}

/* Group g's bounds: the corners of its entries. */
static void group_bounds(const rad_emitter_table *table, size_t g, rad_vec3 bounds[2]) {
    bounds[0] = bounds[1] = table->emitters[table->group_first[g]].p0;
    for (uint32_t k = table->group_first[g]; k < table->group_first[g + 1]; ++k) {
        rad_vec3 corner[4];
        for (int c = 0, n = emitter_corners(&table->emitters[k], corner); c < n; ++c) {
            bounds[0] = v3_min(bounds[0], corner[c]);
            bounds[1] = v3_max(bounds[1], corner[c]);
        }
    }
}

/* Node `at` over order[lo .. hi); its children at *next and *next + 1. `bounds` holds each
 * group's, `scratch` hi - lo keys. Recursion depth is log2 of the group count (median splits). */
static void build_node(rad_emitter_table *table, const rad_vec3 (*bounds)[2], uint32_t *order,
                       keyed *scratch, size_t lo, size_t hi, uint32_t at, uint32_t parent,
                       uint32_t *next) {
    struct rad_emitter_node *n = &table->nodes[at];
    rad_vec3 low = bounds[order[lo]][0], high = bounds[order[lo]][1];
    rad_vec3 clow = table->groups[order[lo]].centre, chigh = clow;
    rad_vec3 axis = v3(0, 0, 0);
    double power = 0;
    for (size_t i = lo; i < hi; ++i) {
        const struct rad_emitter_group *g = &table->groups[order[i]];
        low = v3_min(low, bounds[order[i]][0]);
        high = v3_max(high, bounds[order[i]][1]);
        clow = v3_min(clow, g->centre);
        chigh = v3_max(chigh, g->centre);
        axis = v3_add(axis, v3_scale(g->normal, g->probability));
        power += g->probability;
    }
    n->low = low;
    n->high = high;
    n->centre = v3_scale(v3_add(low, high), 0.5);
    n->radius = 0.5 * v3_length(v3_sub(high, low));
    n->power = power;
    n->parent = parent;
    double length = v3_length(axis);
    n->cos_spread = -1;
    n->axis = v3(0, 0, 1);
    if (length > 1e-9 * power) {
        n->axis = v3_scale(axis, 1 / length);
        double lowest = 1;
        for (size_t i = lo; i < hi; ++i) lowest = fmin(lowest, v3_dot(n->axis, table->groups[order[i]].normal));
        n->cos_spread = fmax(-1, fmin(1, lowest));
    }
    n->sin_spread = sqrt(fmax(0, 1 - n->cos_spread * n->cos_spread));
    if (hi - lo <= LEAF_GROUPS) {
        n->leaf = (uint32_t)(hi - lo);
        n->child = (uint32_t)lo;
        for (size_t i = lo; i < hi; ++i) table->leaf_of[order[i]] = at;
        return;
    }
    n->leaf = 0;
    rad_vec3 extent = v3_sub(chigh, clow);
    int widest = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    for (size_t i = lo; i < hi; ++i) {
        scratch[i - lo].key = v3_get(table->groups[order[i]].centre, widest);
        scratch[i - lo].group = order[i];
    }
    qsort(scratch, hi - lo, sizeof *scratch, compare_keyed);
    for (size_t i = lo; i < hi; ++i) order[i] = scratch[i - lo].group;
    size_t middle = lo + (hi - lo) / 2;
    uint32_t child = *next;
    *next += 2;
    n->child = child;
    build_node(table, bounds, order, scratch, lo, middle, child, at, next);
    build_node(table, bounds, order, scratch, middle, hi, child + 1, at, next);
}

static rad_status build_tree(rad_context *ctx, rad_emitter_table *table) {
    size_t groups = table->group_count;
    table->nodes = rad_alloc(ctx, 2 * groups - 1, sizeof *table->nodes);
    table->leaf_of = rad_alloc(ctx, groups, sizeof *table->leaf_of);
    uint32_t *order = table->tree_order = rad_alloc(ctx, groups, sizeof *order);
    keyed *scratch = rad_alloc(ctx, groups, sizeof *scratch);
    rad_vec3 (*bounds)[2] = rad_alloc(ctx, groups, sizeof *bounds);
    rad_status status = RAD_ERROR_NO_MEMORY;
    if (table->nodes && table->leaf_of && order && scratch && bounds) {
        for (size_t g = 0; g < groups; ++g) {
            order[g] = (uint32_t)g;
            group_bounds(table, g, bounds[g]);
        }
        uint32_t next = 1;
        build_node(table, (const rad_vec3(*)[2])bounds, order, scratch, 0, groups, 0, UINT32_MAX, &next);
        status = RAD_OK;
    } else { /* no tree: no half of one for local_choice to find */
        rad_free(ctx, table->nodes);
        rad_free(ctx, table->leaf_of);
        rad_free(ctx, table->tree_order);
        table->nodes = NULL;
        table->leaf_of = NULL;
        table->tree_order = NULL;
    }
    rad_free(ctx, scratch);
    rad_free(ctx, bounds);
    return status;
}

/* How far v lies outside [low, high]. */
static inline double outside(double v, double low, double high) {
    return v < low ? low - v : v > high ? v - high : 0;
}

/* A receiver: the point x and its front (unit; zero: light from every direction counts). */
typedef struct receiver {
    rad_vec3 x, normal;
} receiver;

static int any_direction(const receiver *r) {
    return r->normal.x == 0 && r->normal.y == 0 && r->normal.z == 0;
}

/* Node n's importance at x (above), times a bound on the receiver's cosine over its box: every
 * point p of the box has n . (p - x) <= rise (the box's highest corner over the receiver's
 * plane) and |p - x| >= the distance to the box, so cos <= rise / distance (1 inside the box
 * or for a receiver without a front; 0 when the box lies wholly behind the plane, from where x
 * reflects nothing). */
static double node_importance(const struct rad_emitter_node *n, const receiver *r) {
    rad_vec3 x = r->x;
    rad_vec3 d = v3_sub(x, n->centre);
    double d2 = v3_dot(d, d), r2 = n->radius * n->radius;
    double ox = outside(x.x, n->low.x, n->high.x), oy = outside(x.y, n->low.y, n->high.y),
           oz = outside(x.z, n->low.z, n->high.z), o2 = ox * ox + oy * oy + oz * oz;
    double facing = 1;
    if (!any_direction(r)) {
        rad_vec3 half = v3_scale(v3_sub(n->high, n->low), 0.5);
        double rise = fabs(r->normal.x) * half.x + fabs(r->normal.y) * half.y +
                      fabs(r->normal.z) * half.z - v3_dot(r->normal, d);
        if (rise < 0) return 0;
        if (rise * rise < o2) facing = rise / sqrt(o2);
    }
    /* The distance to the bounds, not to the centre: */
    double near2 = 1e-4 * r2 > 1e-300 ? 1e-4 * r2 : 1e-300;
    if (o2 > near2) near2 = o2;
    double power = n->power * facing;
    /* x within the sphere, or a cone wider than a hemisphere: no angle bound. */
    if (d2 <= r2 || n->cos_spread <= 0) return power / near2;
    /* theta' = theta - slack, slack = spread + asin(radius / d) in [0, pi), without
     * trigonometry: theta <= slack when cos(theta) >= cos(slack); else
     * cos(theta') = cos(theta) cos(slack) + sin(theta) sin(slack). */
    double distance = sqrt(d2);
    double cos_angle = v3_dot(n->axis, d) / distance;
    cos_angle = cos_angle < -1 ? -1 : cos_angle > 1 ? 1 : cos_angle;
    double sin_angle = sqrt(1 - cos_angle * cos_angle);
    double sin_u = n->radius / distance, cos_u = sqrt(1 - sin_u * sin_u); /* radius < distance */
    double cos_slack = n->cos_spread * cos_u - n->sin_spread * sin_u;
    double sin_slack = n->sin_spread * cos_u + n->cos_spread * sin_u;
    if (cos_angle >= cos_slack) return power / near2;
    double cos_least = cos_angle * cos_slack + sin_angle * sin_slack;
    return cos_least > 0 ? power * cos_least / near2 : 0;
}

/* The probability of choosing `child` (one of two siblings at `first`, `first + 1`) at x. */
static double child_share(const rad_emitter_table *table, uint32_t first, uint32_t child,
                          const receiver *x) {
    const struct rad_emitter_node *a = &table->nodes[first], *b = &table->nodes[first + 1];
    double ia = node_importance(a, x), ib = node_importance(b, x);
    double pa = ia + ib > 0                   ? ia / (ia + ib)
                : a->power + b->power > 0 ? a->power / (a->power + b->power)
                                          : 0.5;
    return child == first ? pa : 1 - pa;
}

/* Group g's exact weight at x: its power times h / (d^2 + A)^(3/2) (below, "the choice for a
 * receiver"), times an estimate of the receiver's cosine: (h_x + R) / sqrt(d^2 + A) within
 * [0, 1], h_x the height of the group's centre above the receiver's plane and R the group's
 * radius (the height of the sphere's highest point over the softened distance the weight
 * uses: not a bound, but zero exactly when the sphere lies wholly behind the plane).
 * Together: power * clamp(h_x + R, 0, sqrt(s)) * h / s^2, s = d^2 + A; a receiver without a
 * front (`any`) takes the clamp's top. h is the group's normal times x minus the centre (the
 * centre lies in the group's plane). From table->group_fields (n groups). */
static inline float weight_of(const float *f, size_t n, size_t g, const float x[3],
                              const float normal[3], int any) {
    float dx = x[0] - f[FIELD_CX * n + g], dy = x[1] - f[FIELD_CY * n + g],
          dz = x[2] - f[FIELD_CZ * n + g];
    float h = dx * f[FIELD_NX * n + g] + dy * f[FIELD_NY * n + g] + dz * f[FIELD_NZ * n + g];
    float s = dx * dx + dy * dy + dz * dz + f[FIELD_AREA * n + g], root = sqrtf(s);
    float rise = any ? root
                     : f[FIELD_RADIUS * n + g] - (normal[0] * dx + normal[1] * dy + normal[2] * dz);
    rise = rise > 0 ? rise : 0;
    rise = rise < root ? rise : root;
    float w = f[FIELD_POWER * n + g] * rise * h / (s * s);
    return h > 0 ? w : 0;
}

/* The receiver in single precision, as weight_of reads it. */
static void receiver_floats(const receiver *r, float x[3], float normal[3]) {
    x[0] = (float)r->x.x, x[1] = (float)r->x.y, x[2] = (float)r->x.z;
    normal[0] = (float)r->normal.x, normal[1] = (float)r->normal.y, normal[2] = (float)r->normal.z;
}

/* Within leaf `at`: the groups' exact weights at x into w[], their sum returned; all zero (x
 * behind every one) falls back to their power. */
static double leaf_weights(const rad_emitter_table *table, uint32_t at, const receiver *x,
                           double *w) {
    const struct rad_emitter_node *n = &table->nodes[at];
    float point[3], normal[3];
    receiver_floats(x, point, normal);
    int any = any_direction(x);
    double total = 0;
    for (uint32_t i = 0; i < n->leaf; ++i)
        total += (w[i] = weight_of(table->group_fields, table->group_count,
                                   table->tree_order[n->child + i], point, normal, any));
    if (total > 0) return total;
    for (uint32_t i = 0; i < n->leaf; ++i)
        total += (w[i] = table->groups[table->tree_order[n->child + i]].probability);
    if (total > 0) return total;
    for (uint32_t i = 0; i < n->leaf; ++i) w[i] = 1;
    return n->leaf;
}

/* The tree's P_g(x) for group g: its choices from the root down, multiplied. */
static double tree_probability(const rad_emitter_table *table, size_t g, const receiver *x) {
    uint32_t at = table->leaf_of[g];
    const struct rad_emitter_node *leaf = &table->nodes[at];
    double w[LEAF_GROUPS], total = leaf_weights(table, at, x, w), probability = 0;
    for (uint32_t i = 0; i < leaf->leaf; ++i)
        if (table->tree_order[leaf->child + i] == g) probability = w[i] / total;
    while (table->nodes[at].parent != UINT32_MAX) {
        uint32_t parent = table->nodes[at].parent;
        probability *= child_share(table, table->nodes[parent].child, at, x);
        at = parent;
    }
    return probability;
}

/* A group for x down the tree for u in [0, 1), u rescaled inside the group's share; the tree's
 * P_g(x) in *probability (what tree_probability gives for it). */
static size_t tree_pick(const rad_emitter_table *table, const receiver *x, double *u,
                        double *probability) {
    uint32_t at = 0;
    double product = 1;
    while (!table->nodes[at].leaf) {
        uint32_t first = table->nodes[at].child;
        double pa = child_share(table, first, first, x);
        if (*u < pa) {
            *u = pa > 0 ? *u / pa : 0;
            product *= pa;
            at = first;
        } else {
            *u = pa < 1 ? (*u - pa) / (1 - pa) : 0;
            product *= 1 - pa;
            at = first + 1;
        }
        *u = fmin(fmax(*u, 0), 0x1.fffffffffffffp-1);
    }
    const struct rad_emitter_node *leaf = &table->nodes[at];
    double w[LEAF_GROUPS], total = leaf_weights(table, at, x, w), before = 0;
    uint32_t i = 0;
    while (i + 1 < leaf->leaf && *u * total >= before + w[i]) before += w[i++];
    *u = w[i] > 0 ? fmin(fmax((*u * total - before) / w[i], 0), 0x1.fffffffffffffp-1) : 0;
    *probability = product * w[i] / total;
    return table->tree_order[leaf->child + i];
}

void rad_emitter_table_free(rad_context *ctx, rad_emitter_table *table) {
    rad_free(ctx, table->emitters);
    rad_free(ctx, table->cdf);
    rad_free(ctx, table->guide);
    rad_free(ctx, table->group_first);
    rad_free(ctx, table->groups);
    rad_free(ctx, table->group_fields);
    rad_free(ctx, table->nodes);
    rad_free(ctx, table->leaf_of);
    rad_free(ctx, table->tree_order);
    *table = (rad_emitter_table){0};
}

/* The triangle whose share of the cumulative distribution holds u, and u rescaled to [0, 1)
 * inside that share (so one number picks the triangle and places the point). */
static size_t pick(const rad_emitter_table *table, double *u) {
    /* The first entry with cdf > u lies between the guides of u's bucket and the next one. */
    size_t bucket = (size_t)(*u * (double)table->count);
    if (bucket >= table->count) bucket = table->count - 1;
    size_t lo = table->guide[bucket], hi = table->guide[bucket + 1];
    while (lo < hi) { /* the first entry with cdf > u */
        size_t mid = (lo + hi) / 2;
        if (table->cdf[mid] <= *u) lo = mid + 1;
        else hi = mid;
    }
    /* u's bucket by rounding may be one off where a cdf entry lies within an ulp of its edge. */
    while (lo > 0 && table->cdf[lo - 1] > *u) --lo;
    while (lo + 1 < table->count && table->cdf[lo] <= *u) ++lo;
    double before = lo ? table->cdf[lo - 1] : 0;
    double p = table->cdf[lo] - before;
    *u = p > 0 ? fmin((*u - before) / p, 0x1.fffffffffffffp-1) : 0;
    return lo;
}

/* The choice for a receiver (tables of 2 to RAD_EMITTERS_LOCAL_MAX groups). Group g's local
 * weight at x is its global probability (its power) times h / (d^2 + A)^(3/2), h the height of
 * x in front of g's plane, d the distance to g's centre and A its area: the irradiance a small
 * lamp gives at distance d and height h (L A cos_y / d^2 with cos_y = h / d), kept finite near
 * large ones; 0 behind the plane, from where g sends nothing to x. The group's probability
 * mixes it with the global one, LOCAL_GLOBAL_SHARE of it, so that a lamp near x but behind a
 * wall cannot take every sample from the lamps that do light x: occlusion is not known here. */
#define LOCAL_GLOBAL_SHARE 0.25

static int local_choice(const rad_emitter_table *table) {
    return table->group_count > 1 && (table->group_count <= RAD_EMITTERS_LOCAL_MAX || table->nodes);
}

/* The groups' probabilities P_g(x) into p[0 .. group_count) (at most RAD_EMITTERS_LOCAL_MAX). */
static void group_probabilities(const rad_emitter_table *table, const receiver *x, double *p) {
    double total = 0;
    const float *f = table->group_fields;
    size_t n = table->group_count;
    float at[3], normal[3], w[RAD_EMITTERS_LOCAL_MAX];
    receiver_floats(x, at, normal);
    const int any = any_direction(x);
    for (size_t g = 0; g < n; ++g) w[g] = weight_of(f, n, g, at, normal, any);
    for (size_t g = 0; g < n; ++g) total += w[g];
    if (total > 0) {
        double scale = (1 - LOCAL_GLOBAL_SHARE) / total;
        for (size_t g = 0; g < n; ++g)
            p[g] = scale * w[g] + LOCAL_GLOBAL_SHARE * table->groups[g].probability;
    } else
        for (size_t g = 0; g < n; ++g) p[g] = table->groups[g].probability;
}

/* Entry k's group: the last whose first entry is at most k. */
static size_t group_of(const rad_emitter_table *table, size_t k) {
    size_t lo = 0, hi = table->group_count - 1;
    while (lo < hi) {
        size_t mid = (lo + hi + 1) / 2;
        if (table->group_first[mid] <= k) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

/* The entry of group g for v in [0, 1) by the global distribution within the group's span; *u
 * gets v rescaled inside the entry's share. */
static size_t pick_in_group(const rad_emitter_table *table, size_t g, double v, double *u) {
    uint32_t first = table->group_first[g], last = table->group_first[g + 1] - 1;
    double low = first ? table->cdf[first - 1] : 0;
    double w = low + v * table->groups[g].probability;
    size_t k = pick(table, &w);
    if (k < first || k > last) { /* rounding at the span's ends */
        k = k < first ? first : last;
        w = v;
    }
    *u = w;
    return k;
}

/* An entry for receiver x: the group holding u under P_g(x), then the entry in it by the global
 * distribution, u rescaled and reused at each step. Its probability P_k(x) in *probability.
 * With a light tree, P_g(x) mixes two choices: u below LOCAL_GLOBAL_SHARE picks an entry by the
 * global distribution, above it a group down the tree; without one, p holds every P_g(x)
 * (group_probabilities). */
static size_t pick_local(const rad_emitter_table *table, const receiver *x, const double *p,
                         double *u, double *probability) {
    size_t g, k;
    double pg;
    if (table->nodes) {
        double tree;
        if (*u < LOCAL_GLOBAL_SHARE) {
            double w = *u / LOCAL_GLOBAL_SHARE;
            k = pick(table, &w);
            g = group_of(table, k);
            *u = w;
            tree = tree_probability(table, g, x);
        } else {
            double v = fmin((*u - LOCAL_GLOBAL_SHARE) / (1 - LOCAL_GLOBAL_SHARE), 0x1.fffffffffffffp-1);
            g = tree_pick(table, x, &v, &tree);
            k = pick_in_group(table, g, v, u);
        }
        pg = (1 - LOCAL_GLOBAL_SHARE) * tree + LOCAL_GLOBAL_SHARE * table->groups[g].probability;
    } else {
        double before = 0;
        g = 0;
        while (g + 1 < table->group_count && *u >= before + p[g]) before += p[g++];
        double v = p[g] > 0 ? fmin(fmax(*u - before, 0) / p[g], 0x1.fffffffffffffp-1) : 0;
        k = pick_in_group(table, g, v, u);
        pg = p[g];
    }
    *probability = pg * rad_emitter_table_probability(table, k) / table->groups[g].probability;
    return k;
}

/* The point of entry k for the numbers left (u0 rescaled, u1) as seen from x, with the entry's
 * probability (rad_emitter_table_sample's tail). */
static int place(const rad_emitter_table *table, size_t k, double probability, double u0,
                 double u1, rad_vec3 x, rad_emitter_point *out) {
    const rad_emitter *light = &table->emitters[k];
    out->position = emitter_point(light, u0, u1);
    rad_vec3 to_light = v3_sub(out->position, x);
    double distance2 = v3_dot(to_light, to_light);
    if (!(distance2 > 0)) return 0;
    out->direction = v3_scale(to_light, 1 / sqrt(distance2));
    double cos_y = -v3_dot(light->normal, out->direction);
    if (cos_y <= 0) return 0;
    out->distance2 = distance2;
    out->pdf = probability / light->area * distance2 / cos_y;
    out->radiance = light->radiance;
    out->index = k;
    return 1;
}

void rad_emitter_choice_init(rad_emitter_choice *choice, const rad_emitter_table *table,
                             rad_vec3 x, rad_vec3 normal) {
    choice->table = table;
    choice->x = x;
    choice->normal = normal;
    if (table->count && local_choice(table) && !table->nodes) {
        receiver r = {x, normal};
        group_probabilities(table, &r, choice->probability);
    }
}

int rad_emitter_choice_sample(const rad_emitter_choice *choice, double u0, double u1,
                              rad_emitter_point *out) {
    const rad_emitter_table *table = choice->table;
    if (table->count == 0) return 0;
    size_t k;
    double probability;
    if (local_choice(table)) {
        receiver r = {choice->x, choice->normal};
        k = pick_local(table, &r, choice->probability, &u0, &probability);
    } else {
        k = pick(table, &u0);
        probability = rad_emitter_table_probability(table, k);
    }
    return place(table, k, probability, u0, u1, choice->x, out);
}

double rad_emitter_choice_pdf(const rad_emitter_choice *choice, size_t k, rad_vec3 direction,
                              double distance) {
    const rad_emitter_table *table = choice->table;
    if (k >= table->count) return 0;
    const rad_emitter *light = &table->emitters[k];
    double cos_y = -v3_dot(light->normal, direction);
    if (cos_y <= 0) return 0;
    double probability = rad_emitter_table_probability(table, k);
    if (local_choice(table)) {
        size_t g = group_of(table, k);
        receiver r = {choice->x, choice->normal};
        double pg = table->nodes ? (1 - LOCAL_GLOBAL_SHARE) * tree_probability(table, g, &r) +
                                       LOCAL_GLOBAL_SHARE * table->groups[g].probability
                                 : choice->probability[g];
        probability *= pg / table->groups[g].probability;
    }
    return probability / light->area * distance * distance / cos_y;
}

int rad_emitter_table_sample(const rad_emitter_table *table, double u0, double u1, rad_vec3 x,
                             rad_vec3 normal, rad_emitter_point *out) {
    rad_emitter_choice choice;
    rad_emitter_choice_init(&choice, table, x, normal);
    return rad_emitter_choice_sample(&choice, u0, u1, out);
}

double rad_emitter_table_pdf(const rad_emitter_table *table, size_t k, rad_vec3 x,
                             rad_vec3 normal, rad_vec3 direction, double distance) {
    rad_emitter_choice choice;
    rad_emitter_choice_init(&choice, table, x, normal);
    return rad_emitter_choice_pdf(&choice, k, direction, distance);
}

size_t rad_emitter_table_sample_point(const rad_emitter_table *table, double u0, double u1,
                                      rad_vec3 *position) {
    size_t k = pick(table, &u0);
    *position = emitter_point(&table->emitters[k], u0, u1);
    return k;
}
