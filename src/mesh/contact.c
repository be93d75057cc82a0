/* contact.c - discontinuity meshing at contacts (D0; see contact.h).
 *
 * 1. Planes and bounds of every polygon; candidate pairs from a tree of the bounds (each
 *    polygon asks it for the bounds near its own), taken in the order of a sweep along x.
 * 2. For a polygon A and a polygon B of another surface whose bounds meet: B's intersection
 *    with A's plane (the edge of B lying in it, or the segment where B passes through it). If
 *    that segment runs through A's interior, A is to be cut along its line.
 * 3. Each polygon is cut by its lines in turn (a convex polygon and a line give two convex
 *    pieces), so no piece straddles a contact.
 * 4. A piece is hidden when, just in front of it, a ray along its normal first meets the back of
 *    a surface S that touches the polygon and the piece lies behind every polygon of S that
 *    touches it: the floor under a block (behind its four sides, below its top), a slab inside a
 *    wall. Hidden pieces are dropped: they can neither receive nor send light.
 * With shadows (rad_contact_options): after its contact lines, each polygon is cut along the
 *    shadow boundaries found on it (shadow.c; largest first, at most MAX_SHADOW_LINES, none
 *    within SEPARATION element sizes of a parallel one taken, none leaving a sliver), each
 *    only through the pieces the segment crosses.
 * 5. Where a cut ends on another piece's edge (a shadow segment inside a face; a line reaching
 *    an edge the polygon shares with another polygon of its surface), that piece gets the end
 *    as a corner: the pieces then meet corner to corner and the mesh has no T-junctions.
 * Steps 2 to 4 run on the context's threads over fixed chunks of polygons, joined in order: the
 * same cut, to the bit, for any thread count. */
#include "mesh/contact.h"

#include "core/team.h"
#include "mesh/shadow.h"
#include "scene/rays.h"
#include "scene/scene.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* A polygon receives at most this many contact lines (more are ignored): a bound on the cost of
 * step 3 for polygons touched by very many others. */
#define MAX_LINES 64
/* Shadow boundaries (shadow.c) cut along per polygon, the most important first. */
#define MAX_SHADOW_LINES 24
/* A shadow segment parallel to one already taken and nearer to it than this many element
 * sizes is not cut along; nor is a piece cut where one half would be narrower than SLIVER. */
#define SEPARATION 0.2
#define SLIVER 0.15

typedef struct plane_info {
    rad_vec3 normal, lo, hi;
    double offset; /* normal . x on the plane */
} plane_info;

/* A polygon's bounds in sweep order (step 2), with its reach: NEAR_GAP times the bounds'
 * diagonal (step 2b), 0 without near-parallel lines. */
typedef struct box {
    rad_vec3 lo, hi;
    double reach;
} box;

typedef struct line {
    rad_vec3 point, direction; /* in the receiver's plane; direction unit */
} line;

typedef struct contact {
    uint32_t receiver, other;
    line cut;
    int covered; /* `other` lies on the receiver in its plane, facing the same way (step 2c) */
} contact;

typedef struct piece_list {
    rad_vec3 *points;
    uint32_t *first, *count;
    size_t pieces, piece_capacity, used, capacity;
} piece_list;

static int grow(rad_context *ctx, void **array, size_t *capacity, size_t needed, size_t size) {
    if (needed <= *capacity) return 0;
    size_t next = *capacity ? *capacity : 64;
    while (next < needed) next *= 2;
    void *grown = rad_realloc(ctx, *array, next, size);
    if (!grown) return 1;
    *array = grown;
    *capacity = next;
    return 0;
}

static void piece_list_free(rad_context *ctx, piece_list *list) {
    rad_free(ctx, list->points);
    rad_free(ctx, list->first);
    rad_free(ctx, list->count);
}

static rad_status add_piece(rad_context *ctx, piece_list *list, const rad_vec3 *p, size_t n) {
    size_t capacity = list->piece_capacity;
    if (grow(ctx, (void **)&list->first, &capacity, list->pieces + 1, sizeof *list->first))
        return RAD_ERROR_NO_MEMORY;
    capacity = list->piece_capacity;
    if (grow(ctx, (void **)&list->count, &capacity, list->pieces + 1, sizeof *list->count))
        return RAD_ERROR_NO_MEMORY;
    list->piece_capacity = capacity;
    if (grow(ctx, (void **)&list->points, &list->capacity, list->used + n, sizeof *list->points))
        return RAD_ERROR_NO_MEMORY;
    if (n) memcpy(list->points + list->used, p, n * sizeof *p);
    list->first[list->pieces] = (uint32_t)list->used;
    list->count[list->pieces] = (uint32_t)n;
    list->used += n;
    list->pieces++;
    return RAD_OK;
}

/* The point where the line (side values sa at a, sb at b) crosses segment ab, computed from the
 * endpoints in a fixed order so that both pieces sharing the edge get the same point. */
static rad_vec3 crossing(rad_vec3 a, double sa, rad_vec3 b, double sb) {
    int swap = a.x > b.x || (a.x == b.x && (a.y > b.y || (a.y == b.y && a.z > b.z)));
    if (swap) {
        rad_vec3 t = a;
        a = b, b = t;
        double s = sa;
        sa = sb, sb = s;
    }
    return v3_lerp(a, b, sa / (sa - sb));
}

static double polygon_area(const rad_vec3 *p, size_t n) {
    rad_vec3 sum = v3(0, 0, 0);
    for (size_t k = 0; k < n; ++k) sum = v3_add(sum, v3_cross(p[k], p[(k + 1) % n]));
    return 0.5 * v3_length(sum);
}

/* Splits the convex polygon p by the line (side(x) = side_normal . (x - point)) into the parts
 * on each side; points within eps of the line go to both. Returns 0 when the line misses the
 * interior (the polygon is left whole). */
static int split(const rad_vec3 *p, size_t n, rad_vec3 point, rad_vec3 side_normal, double eps,
                 rad_vec3 *left, size_t *nl, rad_vec3 *right, size_t *nr) {
    int positive = 0, negative = 0;
    for (size_t k = 0; k < n; ++k) {
        double s = v3_dot(side_normal, v3_sub(p[k], point));
        positive |= s > eps;
        negative |= s < -eps;
    }
    if (!positive || !negative) return 0;
    *nl = *nr = 0;
    for (size_t k = 0; k < n; ++k) {
        rad_vec3 a = p[k], b = p[(k + 1) % n];
        double sa = v3_dot(side_normal, v3_sub(a, point)), sb = v3_dot(side_normal, v3_sub(b, point));
        if (fabs(sa) <= eps) sa = 0;
        if (fabs(sb) <= eps) sb = 0;
        if (sa >= 0) left[(*nl)++] = a;
        if (sa <= 0) right[(*nr)++] = a;
        if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) {
            rad_vec3 x = crossing(a, sa, b, sb);
            left[(*nl)++] = x;
            right[(*nr)++] = x;
        }
    }
    return *nl >= 3 && *nr >= 3;
}

int rad_clip_line_convex(const rad_vec3 *p, size_t n, rad_vec3 normal, rad_vec3 point,
                         rad_vec3 direction, double eps, double *t0, double *t1) {
    for (size_t k = 0; k < n && *t0 < *t1; ++k) {
        rad_vec3 u = p[k], w = p[(k + 1) % n];
        rad_vec3 inward = v3_normalize(v3_cross(normal, v3_sub(w, u)));
        double at = v3_dot(inward, v3_sub(point, u)) - eps, slope = v3_dot(inward, direction);
        if (fabs(slope) < 1e-12) {
            if (at < 0) return 0;
            continue;
        }
        double t = -at / slope;
        if (slope > 0) *t0 = fmax(*t0, t);
        else *t1 = fmin(*t1, t);
    }
    return *t1 > *t0;
}

/* Step 2: B's intersection with A's plane, clipped to A's interior (eps inside its edges).
 * Returns 1 with the line when it runs through A; 2 when B lies in A's plane. */
static int contact_line(const rad_scene *scene, const plane_info *info, uint32_t a, uint32_t b,
                        double eps, line *out) {
    const rad_polygon *pa = &scene->polygons[a], *pb = &scene->polygons[b];
    const plane_info *A = &info[a], *B = &info[b];
    rad_vec3 points[2 * 64 + 2];
    size_t count = 0;
    int above = 0, below = 0;
    uint32_t n = pb->count;
    if (n > 64) return 0;
    double dist[64];
    for (uint32_t k = 0; k < n; ++k) {
        dist[k] = v3_dot(A->normal, rad_polygon_vertex(scene, pb, k)) - A->offset;
        if (dist[k] > eps) above = 1;
        else if (dist[k] < -eps) below = 1;
        else dist[k] = 0;
    }
    if (!above && !below) return 2;
    if (above && below) {
        for (uint32_t k = 0; k < n; ++k) {
            double s = dist[k], t = dist[(k + 1) % n];
            if (s == 0) points[count++] = rad_polygon_vertex(scene, pb, k);
            if ((s > 0 && t < 0) || (s < 0 && t > 0))
                points[count++] = crossing(rad_polygon_vertex(scene, pb, k), s,
                                           rad_polygon_vertex(scene, pb, (k + 1) % n), t);
        }
    } else {
        for (uint32_t k = 0; k < n; ++k)
            if (dist[k] == 0) points[count++] = rad_polygon_vertex(scene, pb, k);
    }
    if (count < 2) return 0;
    rad_vec3 direction = v3_cross(A->normal, B->normal);
    if (v3_length(direction) < 1e-6) return 0;
    direction = v3_normalize(direction);
    double t0 = INFINITY, t1 = -INFINITY;
    rad_vec3 origin = points[0];
    for (size_t k = 0; k < count; ++k) {
        double t = v3_dot(v3_sub(points[k], origin), direction);
        t0 = fmin(t0, t), t1 = fmax(t1, t);
    }
    /* Onto A's plane, then clipped against each edge of A moved eps inward. */
    origin = v3_sub(origin, v3_scale(A->normal, v3_dot(A->normal, origin) - A->offset));
    rad_vec3 corners[64];
    for (uint32_t k = 0; k < pa->count; ++k) corners[k] = rad_polygon_vertex(scene, pa, k);
    if (pa->count > 64 || !rad_clip_line_convex(corners, pa->count, A->normal, origin, direction, eps, &t0, &t1))
        return 0;
    if (!(t1 - t0 > eps)) return 0;
    out->point = v3_add(origin, v3_scale(direction, 0.5 * (t0 + t1)));
    out->direction = direction;
    return 1;
}

/* A polygon's width: twice its area over its perimeter (a w x h rectangle: w h / (w + h)). */
static double polygon_width(const rad_scene *scene, const rad_polygon *p) {
    double perimeter = 0;
    for (uint32_t k = 0; k < p->count; ++k)
        perimeter += v3_length(v3_sub(rad_polygon_vertex(scene, p, (k + 1) % p->count), rad_polygon_vertex(scene, p, k)));
    return perimeter > 0 ? 2 * rad_polygon_area(scene, p) / perimeter : 0;
}

/* Step 2b: B parallel to A, a little in front of it (nearer than NEAR_GAP times B's extent,
 * farther than eps): a lamp panel just under a ceiling, a rug on a floor. A is cut along the
 * lines of B's edges projected onto its plane, so that no element straddles B's outline, half
 * seen and half hidden behind B (it was black or dark in view, beside the lamp). Adds up to
 * B's corner count of lines to `out`; returns how many. */
#define NEAR_GAP 0.05
static size_t near_parallel_lines(const rad_scene *scene, const plane_info *info, uint32_t a,
                                  uint32_t b, double eps, int coplanar, int sealed, line *out) {
    const plane_info *A = &info[a], *B = &info[b];
    const rad_polygon *pb = &scene->polygons[b];
    if (fabs(v3_dot(A->normal, B->normal)) < 1 - 1e-9 || pb->count > 64) return 0;
    double gap = v3_dot(A->normal, rad_polygon_vertex(scene, pb, 0)) - A->offset;
    double extent = v3_length(v3_sub(B->hi, B->lo));
    if (!coplanar && (!(gap > eps) || gap > NEAR_GAP * extent)) return 0;
    /* Sealed only: B facing the same way, its gap a small share of its width. */
    if (sealed && !coplanar &&
        (v3_dot(A->normal, B->normal) < 0 || gap > RAD_CONTACT_SEALED_GAP * polygon_width(scene, pb)))
        return 0;
    size_t count = 0;
    for (uint32_t k = 0; k < pb->count; ++k) {
        rad_vec3 p = rad_polygon_vertex(scene, pb, k), q = rad_polygon_vertex(scene, pb, (k + 1) % pb->count);
        rad_vec3 d = v3_sub(q, p);
        if (v3_length(d) <= eps) continue;
        p = v3_sub(p, v3_scale(A->normal, v3_dot(A->normal, p) - A->offset));
        out[count++] = (line){p, v3_normalize(d)};
    }
    return count;
}

/* Is the point inside polygon a (eps within its edges, seen along a's normal)? */
static int point_inside(const rad_scene *scene, const plane_info *info, uint32_t a, rad_vec3 centre,
                        double eps) {
    const rad_polygon *pa = &scene->polygons[a];
    for (uint32_t k = 0; k < pa->count; ++k) {
        rad_vec3 p = rad_polygon_vertex(scene, pa, k), q = rad_polygon_vertex(scene, pa, (k + 1) % pa->count);
        rad_vec3 inward = v3_normalize(v3_cross(info[a].normal, v3_sub(q, p)));
        if (v3_dot(inward, v3_sub(centre, p)) < eps) return 0;
    }
    return 1;
}

static rad_vec3 corner_mean(const rad_vec3 *p, size_t n) {
    rad_vec3 centre = v3(0, 0, 0);
    for (size_t k = 0; k < n; ++k) centre = v3_add(centre, p[k]);
    return v3_scale(centre, 1.0 / (double)n);
}

/* Is the corner mean of polygon b inside polygon a? */
static int inside(const rad_scene *scene, const plane_info *info, uint32_t a, uint32_t b, double eps) {
    const rad_polygon *pb = &scene->polygons[b];
    rad_vec3 corners[64];
    uint32_t n = pb->count < 64 ? pb->count : 64;
    for (uint32_t k = 0; k < n; ++k) corners[k] = rad_polygon_vertex(scene, pb, k);
    return point_inside(scene, info, a, corner_mean(corners, n), eps);
}

/* Step 4 for coplanar overlaps: is the piece under a polygon lying on it (step 2c)? */
static int covered(const rad_scene *scene, const plane_info *info, const contact *list,
                   size_t count, const rad_vec3 *p, size_t n, double eps) {
    rad_vec3 centre = corner_mean(p, n);
    for (size_t i = 0; i < count; ++i)
        if (list[i].covered && point_inside(scene, info, list[i].other, centre, eps)) return 1;
    return 0;
}

/* Step 2's pair search: a bounding-volume tree over the polygons' bounds, each grown by its
 * margin (slack plus its reach), built top down, split at the median of the centres along
 * their longest spread (Ericson, "Real-Time Collision Detection", 2005, 6.2.1). A polygon's
 * candidates are the grown bounds its own grown bounds meet: about O(log n + candidates) each,
 * where a sweep along x tested every pair overlapping along x (10^5 triangles stacked along z,
 * all overlapping in x and y: 5 * 10^9 tests, 16 s). The grown bounds meet whenever the bounds
 * are within slack plus the larger reach (the test step 2 makes): the tree misses no pair. */
#define TREE_LEAF 4
typedef struct tree_node {
    rad_vec3 lo, hi;
    uint32_t first, count; /* a leaf: items first .. first + count - 1; else count 0 and the
                              children are nodes first and first + 1 */
} tree_node;

typedef struct box_tree {
    tree_node *nodes;
    size_t node_count;
    uint32_t *items; /* sweep positions */
    const box *boxes;
    double slack;
} box_tree;

static rad_vec3 grown_lo(const box_tree *tree, uint32_t t) {
    double g = tree->slack + tree->boxes[t].reach;
    return v3(tree->boxes[t].lo.x - g, tree->boxes[t].lo.y - g, tree->boxes[t].lo.z - g);
}

static rad_vec3 grown_hi(const box_tree *tree, uint32_t t) {
    double g = tree->slack + tree->boxes[t].reach;
    return v3(tree->boxes[t].hi.x + g, tree->boxes[t].hi.y + g, tree->boxes[t].hi.z + g);
}

static double centre_along(const box_tree *tree, uint32_t t, int axis) {
    const box *b = &tree->boxes[t];
    return axis == 0 ? b->lo.x + b->hi.x : axis == 1 ? b->lo.y + b->hi.y : b->lo.z + b->hi.z;
}

/* Puts the k-th smallest centre along `axis` of items[0 .. n-1] at k, smaller ones before it,
 * larger ones after (Hoare's selection; deterministic). */
static void select_median(const box_tree *tree, uint32_t *items, size_t n, size_t k, int axis) {
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, target = (ptrdiff_t)k;
    while (lo < hi) {
        double pivot = centre_along(tree, items[lo + (hi - lo) / 2], axis);
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (centre_along(tree, items[i], axis) < pivot) ++i;
            while (centre_along(tree, items[j], axis) > pivot) --j;
            if (i <= j) {
                uint32_t swap = items[i];
                items[i++] = items[j], items[j--] = swap;
            }
        }
        /* items[lo .. j] <= pivot <= items[i .. hi]; between them, the pivot's equals. */
        if (target <= j) hi = j;
        else if (target >= i) lo = i;
        else break;
    }
}

/* Nodes a build makes under a node of n items (the numbers its subtree takes). */
static size_t nodes_below(uint32_t n) {
    return n <= TREE_LEAF ? 0 : 2 + nodes_below(n / 2) + nodes_below(n - n / 2);
}

/* The subtrees at depth TREE_SPLIT_DEPTH are built on the context's threads; each knows the
 * node numbers a depth-first build gives it, so the tree is the same for any thread count. */
#define TREE_SPLIT_DEPTH 3

typedef struct tree_task {
    size_t index, next;
    uint32_t first, n;
} tree_task;

typedef struct tree_job {
    box_tree *tree;
    size_t count;
    tree_task tasks[1 << TREE_SPLIT_DEPTH];
} tree_job;

/* Node `index` over items first .. first + n - 1 and everything under it, its descendants
 * numbered from `next` on in depth-first order; returns the next free number. With `defer`,
 * the subtrees at depth TREE_SPLIT_DEPTH become defer's tasks instead. */
static size_t tree_build(box_tree *tree, size_t index, uint32_t first, uint32_t n, size_t next,
                         tree_job *defer, int depth) {
    tree_node *node = &tree->nodes[index];
    rad_vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    rad_vec3 centre_lo = lo, centre_hi = hi;
    for (uint32_t k = first; k < first + n; ++k) {
        uint32_t t = tree->items[k];
        rad_vec3 a = grown_lo(tree, t), b = grown_hi(tree, t);
        lo = v3(fmin(lo.x, a.x), fmin(lo.y, a.y), fmin(lo.z, a.z));
        hi = v3(fmax(hi.x, b.x), fmax(hi.y, b.y), fmax(hi.z, b.z));
        rad_vec3 c = v3(centre_along(tree, t, 0), centre_along(tree, t, 1), centre_along(tree, t, 2));
        centre_lo = v3(fmin(centre_lo.x, c.x), fmin(centre_lo.y, c.y), fmin(centre_lo.z, c.z));
        centre_hi = v3(fmax(centre_hi.x, c.x), fmax(centre_hi.y, c.y), fmax(centre_hi.z, c.z));
    }
    node->lo = lo, node->hi = hi;
    if (n <= TREE_LEAF) {
        node->first = first, node->count = n;
        return next;
    }
    rad_vec3 spread = v3_sub(centre_hi, centre_lo);
    int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
    uint32_t half = n / 2;
    select_median(tree, tree->items + first, n, half, axis);
    size_t child = next;
    node->first = (uint32_t)child, node->count = 0;
    next += 2;
    if (defer && depth + 1 >= TREE_SPLIT_DEPTH) {
        defer->tasks[defer->count++] = (tree_task){child, next, first, half};
        next += nodes_below(half);
        defer->tasks[defer->count++] = (tree_task){child + 1, next, first + half, n - half};
        return next + nodes_below(n - half);
    }
    next = tree_build(tree, child, first, half, next, defer, depth + 1);
    return tree_build(tree, child + 1, first + half, n - half, next, defer, depth + 1);
}

static void tree_task_run(void *user, long index, int worker) {
    (void)worker;
    tree_job *job = user;
    const tree_task *task = &job->tasks[index];
    tree_build(job->tree, task->index, task->first, task->n, task->next, NULL, 0);
}

/* The tree over the sweep positions whose polygons take part (`usable`). */
static rad_status tree_create(rad_context *ctx, const box *boxes, const uint8_t *usable, size_t np,
                              double slack, box_tree *tree) {
    memset(tree, 0, sizeof *tree);
    tree->boxes = boxes;
    tree->slack = slack;
    uint32_t n = 0;
    for (size_t t = 0; t < np; ++t) n += usable[t];
    tree->items = rad_alloc(ctx, (size_t)n + 1, sizeof *tree->items);
    /* A node of more than TREE_LEAF items splits into halves of at least 2, so there are at
     * most n / 2 leaves and n - 1 nodes. */
    tree->nodes = rad_alloc(ctx, (size_t)n + 1, sizeof *tree->nodes);
    if (!tree->items || !tree->nodes) return RAD_ERROR_NO_MEMORY;
    n = 0;
    for (size_t t = 0; t < np; ++t)
        if (usable[t]) tree->items[n++] = (uint32_t)t;
    if (n) {
        tree_job job = {.tree = tree};
        tree->node_count = tree_build(tree, 0, 0, n, 1, &job, 0);
        rad_team_for(ctx, (long)job.count, tree_task_run, &job);
    }
    return RAD_OK;
}

static void tree_free(rad_context *ctx, box_tree *tree) {
    rad_free(ctx, tree->nodes);
    rad_free(ctx, tree->items);
}

static int by_position(const void *x, const void *y) {
    uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return a < b ? -1 : a > b;
}

/* The sweep positions after s whose grown bounds meet s's, in increasing order, into
 * (*found)[0 .. *count - 1]. */
static rad_status tree_candidates(rad_context *ctx, const box_tree *tree, uint32_t s,
                                  uint32_t **found, size_t *count, size_t *capacity,
                                  uint32_t **stack, size_t *stack_capacity, size_t *tests) {
    *count = 0;
    if (!tree->node_count) return RAD_OK;
    rad_vec3 lo = grown_lo(tree, s), hi = grown_hi(tree, s);
    size_t depth = 0;
    (*stack)[depth++] = 0;
    while (depth) {
        const tree_node *node = &tree->nodes[(*stack)[--depth]];
        ++*tests;
        if (node->lo.x > hi.x || lo.x > node->hi.x || node->lo.y > hi.y || lo.y > node->hi.y ||
            node->lo.z > hi.z || lo.z > node->hi.z)
            continue;
        if (node->count == 0) {
            if (grow(ctx, (void **)stack, stack_capacity, depth + 2, sizeof **stack)) return RAD_ERROR_NO_MEMORY;
            (*stack)[depth++] = node->first + 1;
            (*stack)[depth++] = node->first;
            continue;
        }
        for (uint32_t k = node->first; k < node->first + node->count; ++k) {
            uint32_t t = tree->items[k];
            if (t <= s) continue;
            ++*tests;
            rad_vec3 b_lo = grown_lo(tree, t), b_hi = grown_hi(tree, t);
            if (b_lo.x > hi.x || lo.x > b_hi.x || b_lo.y > hi.y || lo.y > b_hi.y || b_lo.z > hi.z ||
                lo.z > b_hi.z)
                continue;
            if (grow(ctx, (void **)found, capacity, *count + 1, sizeof **found)) return RAD_ERROR_NO_MEMORY;
            (*found)[(*count)++] = t;
        }
    }
    if (*count > 1) qsort(*found, *count, sizeof **found, by_position);
    return RAD_OK;
}

static int by_receiver(const void *x, const void *y) {
    const contact *a = x, *b = y;
    if (a->receiver != b->receiver) return a->receiver < b->receiver ? -1 : 1;
    return a->other < b->other ? -1 : a->other > b->other;
}

static const plane_info *sort_info;
static int by_low_x(const void *x, const void *y) {
    double a = sort_info[*(const uint32_t *)x].lo.x, b = sort_info[*(const uint32_t *)y].lo.x;
    return a < b ? -1 : a > b;
}

void rad_contact_cut_destroy(rad_context *ctx, rad_contact_cut *cut) {
    if (!cut) return;
    rad_free(ctx, cut->pieces);
    rad_free(ctx, cut->points);
    rad_free(ctx, cut);
}

/* Step 4 for one piece of polygon `receiver`, whose contacts are list[0 .. count-1]. */
static int hidden(const rad_scene *scene, const rad_rays *rays, const plane_info *info,
                  const contact *list, size_t count, const rad_vec3 *p, size_t n, double eps) {
    rad_vec3 centre = v3(0, 0, 0);
    for (size_t k = 0; k < n; ++k) centre = v3_add(centre, p[k]);
    centre = v3_scale(centre, 1.0 / (double)n);
    rad_vec3 normal = info[list[0].receiver].normal;
    rad_hit hit;
    if (!rad_rays_intersect(rays, v3_add(centre, v3_scale(normal, 4 * rays->epsilon)), normal,
                            rays->epsilon, INFINITY, &hit) || hit.front)
        return 0;
    uint32_t solid = scene->polygons[hit.polygon].surface;
    if (solid == scene->polygons[list[0].receiver].surface) return 0; /* step 4b's, if any */
    int touching = 0;
    for (size_t i = 0; i < count; ++i) {
        const plane_info *B = &info[list[i].other];
        if (scene->polygons[list[i].other].surface != solid) continue;
        touching++;
        if (v3_dot(B->normal, centre) - B->offset > -eps) return 0;
    }
    return touching > 0;
}

/* Step 4b: the surface whose backs the rays from x both ways along `axis`, tilted by 30 degrees
 * towards `up`, meet first (x lies between two faces of one solid, facing away from it), or
 * UINT32_MAX. The tilt keeps the rays off surfaces lying flush with the piece. */
static uint32_t between_backs(const rad_scene *scene, const rad_rays *rays, rad_vec3 x, rad_vec3 axis,
                              rad_vec3 up) {
    rad_hit ahead, behind;
    rad_vec3 lift = v3_scale(up, 0.5), along = v3_scale(axis, 0.8660254037844386);
    if (!rad_rays_intersect(rays, x, v3_add(along, lift), rays->epsilon, INFINITY, &ahead) || ahead.front ||
        !rad_rays_intersect(rays, x, v3_sub(lift, along), rays->epsilon, INFINITY, &behind) || behind.front)
        return UINT32_MAX;
    uint32_t surface = scene->polygons[ahead.polygon].surface;
    return scene->polygons[behind.polygon].surface == surface ? surface : UINT32_MAX;
}

/* Step 4b: the share of 16 directions over the hemisphere above x (cosine-weighted: 4 rings
 * of 4, turned from ring to ring) whose first hit is a back face. */
static double back_share(const rad_rays *rays, rad_vec3 x, rad_vec3 normal) {
    rad_vec3 t, b;
    v3_basis(normal, &t, &b);
    int backs = 0;
    for (int ring = 0; ring < 4; ++ring)
        for (int k = 0; k < 4; ++k) {
            double r = sqrt((ring + 0.5) / 4), phi = 2 * RAD_PI * (k + 0.25 * ring + 0.125) / 4;
            rad_vec3 d = v3_add(v3_add(v3_scale(t, r * cos(phi)), v3_scale(b, r * sin(phi))),
                                v3_scale(normal, sqrt(1 - r * r)));
            rad_hit hit;
            backs += rad_rays_intersect(rays, x, d, rays->epsilon, INFINITY, &hit) && !hit.front;
        }
    return backs / 16.0;
}

/* Step 4b for one piece of polygon `receiver` (contacts list[0 .. count-1]): inside a wall or a
 * slab whose faces are not closed around it (a floor slab running under a wall that has no
 * bottom face, a wall's face running on into the wall it meets at a corner). Just in front of
 * the piece, the rays both ways across one of its edges first meet the backs of one surface S
 * that touches the polygon; the ray along its normal meets a back, or a front that lies between
 * the same faces of S (the roof slab's underside inside the same wall: the two pieces face each
 * other inside it, so step 4's single ray sees a front); and most of the hemisphere above it
 * sees backs. An open box standing on a floor leaves the floor inside it in view: its normal
 * ray goes out through the top. */
static int enclosed(const rad_scene *scene, const rad_rays *rays, const contact *list, size_t count,
                    rad_vec3 normal, const rad_vec3 *p, size_t n) {
    rad_vec3 centre = corner_mean(p, n);
    rad_vec3 x = v3_add(centre, v3_scale(normal, 4 * rays->epsilon));
    for (size_t k = 0; k < n; ++k) {
        rad_vec3 edge = v3_sub(p[(k + 1) % n], p[k]);
        if (!(v3_length(edge) > 0)) continue;
        rad_vec3 axis = v3_normalize(v3_cross(normal, edge));
        int seen = 0; /* an axis already tried (the opposite edge of a quad) */
        for (size_t j = 0; j < k && !seen; ++j) {
            rad_vec3 other = v3_sub(p[(j + 1) % n], p[j]);
            seen = v3_length(other) > 0 && v3_length(v3_cross(v3_normalize(other), v3_normalize(edge))) < 1e-6;
        }
        if (seen) continue;
        uint32_t solid = between_backs(scene, rays, x, axis, normal);
        int touching = 0;
        for (size_t i = 0; i < count && !touching && solid != UINT32_MAX; ++i)
            touching = scene->polygons[list[i].other].surface == solid;
        if (!touching) continue;
        rad_hit hit;
        if (!rad_rays_intersect(rays, x, normal, rays->epsilon, INFINITY, &hit)) return 0;
        rad_vec3 there = v3_add(x, v3_scale(normal, hit.t - 4 * rays->epsilon));
        if (!hit.front || (hit.t > 8 * rays->epsilon &&
                           between_backs(scene, rays, there, axis, v3_scale(normal, -1)) == solid))
            return back_share(rays, x, normal) >= 0.5;
    }
    return 0;
}

/* Step 4's verdict on one piece of polygon `receiver`: 0 kept, 1 under a coplanar polygon
 * (covered), 2 hidden behind a contact or enclosed in a wall or slab. */
static int piece_fate(const rad_scene *scene, const rad_rays *rays, const plane_info *info,
                      const contact *list, size_t count, const rad_vec3 *p, size_t n, double eps) {
    if (covered(scene, info, list, count, p, n, eps)) return 1;
    if (hidden(scene, rays, info, list, count, p, n, eps) ||
        enclosed(scene, rays, list, count, info[list[0].receiver].normal, p, n))
        return 2;
    return 0;
}

/* The part [t0, t1] of the line point + t direction (unit) inside the convex piece p, eps
 * inside its edges; 0 when the line misses it. */
static int chord(const rad_vec3 *p, size_t n, rad_vec3 normal, rad_vec3 point, rad_vec3 direction,
                 double eps, double *t0, double *t1) {
    *t0 = -INFINITY, *t1 = INFINITY;
    return rad_clip_line_convex(p, n, normal, point, direction, eps, t0, t1);
}

/* Is segment c (a, unit direction, length) parallel to segment d and nearer to it than
 * `gap`, where their extents along it overlap? */
static int beside(const rad_shadow_segment *c, const rad_shadow_segment *d, double gap) {
    rad_vec3 dc = v3_normalize(v3_sub(c->b, c->a)), dd = v3_sub(d->b, d->a);
    double length = v3_length(dd);
    if (!(length > 0)) return 0;
    dd = v3_scale(dd, 1 / length);
    if (v3_length(v3_cross(dc, dd)) > 0.035) return 0; /* 2 degrees */
    rad_vec3 middle = v3_scale(v3_add(c->a, c->b), 0.5), off = v3_sub(middle, d->a);
    if (v3_length(v3_sub(off, v3_scale(dd, v3_dot(off, dd)))) > gap) return 0;
    double s0 = v3_dot(v3_sub(c->a, d->a), dd), s1 = v3_dot(v3_sub(c->b, d->a), dd);
    return fmax(s0, s1) > 0 && fmin(s0, s1) < length;
}

/* Step 3 with shadows: cuts the pieces of `work` that the segment crosses along its line.
 * Returns 1 when something was cut. */
static int cut_segment(rad_context *ctx, piece_list *work, const rad_shadow_segment *segment,
                       rad_vec3 normal, double eps, double sliver, rad_vec3 *left, rad_vec3 *right,
                       size_t room, rad_status *status) {
    rad_vec3 direction = v3_sub(segment->b, segment->a);
    double length = v3_length(direction);
    if (!(length > eps)) return 0;
    direction = v3_scale(direction, 1 / length);
    rad_vec3 side = v3_cross(normal, direction);
    size_t pieces = work->pieces;
    int made = 0;
    for (size_t w = 0; w < pieces && !*status; ++w) {
        size_t n = work->count[w], nl, nr;
        if (n == 0 || n + 2 > room) continue;
        const rad_vec3 *p = work->points + work->first[w];
        double t0, t1;
        if (!chord(p, n, normal, segment->a, direction, eps, &t0, &t1)) continue;
        if (!(fmin(t1, length) - fmax(t0, 0) > eps)) continue; /* the segment misses this piece */
        if (!split(p, n, segment->a, side, eps, left, &nl, right, &nr)) continue;
        double smaller = fmin(polygon_area(left, nl), polygon_area(right, nr));
        if (smaller < sliver * (t1 - t0)) continue; /* one half would be a sliver */
        work->count[w] = 0;
        *status = add_piece(ctx, work, left, nl);
        if (!*status) *status = add_piece(ctx, work, right, nr);
        made = 1;
    }
    return made;
}

/* Step 5: T-junctions. A point strictly inside segment a-b (eps from the line and its ends);
 * its distance along it goes to *along. */
static int inside_edge(rad_vec3 x, rad_vec3 a, rad_vec3 b, double eps, double *along) {
    rad_vec3 d = v3_sub(b, a);
    double length = v3_length(d);
    if (!(length > 2 * eps)) return 0;
    double t = v3_dot(v3_sub(x, a), d) / length;
    if (t <= eps || t >= length - eps) return 0;
    if (v3_length(v3_sub(v3_sub(x, a), v3_scale(d, t / length))) > eps) return 0;
    *along = t;
    return 1;
}

/* A point on an edge of an input polygon, keyed by the edge (its surface and welded ends), so
 * the polygon on the other side of the edge finds it. */
typedef struct edge_point {
    int64_t key[7];
    rad_vec3 point;
    rad_vec3 normal; /* of the polygon whose piece has the point */
} edge_point;

/* Polygons bending by more than this across an edge do not share the mesh's vertices there
 * (mesh.c's crease angle, 30 degrees): a T-junction across such an edge makes no crack, and
 * its point is not added (a cut up a wall's face would otherwise put corners on the wall's
 * thin top, cut into needles). */
#define T_POINT_COSINE 0.866

static int by_key(const void *x, const void *y) {
    const int64_t *a = ((const edge_point *)x)->key, *b = ((const edge_point *)y)->key;
    for (int k = 0; k < 7; ++k)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

static void edge_key(const rad_scene *scene, uint32_t polygon, uint32_t k, rad_vec3 lo, double quantum,
                     int64_t key[7]) {
    const rad_polygon *p = &scene->polygons[polygon];
    rad_vec3 a = rad_polygon_vertex(scene, p, k), b = rad_polygon_vertex(scene, p, (k + 1) % p->count);
    int64_t qa[3] = {llround((a.x - lo.x) / quantum), llround((a.y - lo.y) / quantum), llround((a.z - lo.z) / quantum)};
    int64_t qb[3] = {llround((b.x - lo.x) / quantum), llround((b.y - lo.y) / quantum), llround((b.z - lo.z) / quantum)};
    int swap = qa[0] != qb[0] ? qa[0] > qb[0] : qa[1] != qb[1] ? qa[1] > qb[1] : qa[2] > qb[2];
    key[0] = p->surface;
    for (int c = 0; c < 3; ++c) key[1 + c] = swap ? qb[c] : qa[c], key[4 + c] = swap ? qa[c] : qb[c];
}

/* Step 5: every piece gets, as corners, the corners of other pieces of its polygon and the
 * points on its polygon's edges from the pieces of its neighbours that lie inside its edges. */
static rad_status add_t_points(rad_context *ctx, const rad_scene *scene, double eps, rad_contact_cut *cut,
                               piece_list *list) {
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double quantum = fmax(v3_length(v3_sub(hi, lo)) * 1e-7, 1e-300);
    edge_point *marks = NULL;
    size_t mark_count = 0, mark_capacity = 0, along_capacity = 0;
    double *along = NULL;
    rad_vec3 *corners = NULL;
    size_t corner_capacity = 0;
    piece_list fresh = {0};
    rad_status status = RAD_OK;
    /* Corners of pieces lying inside an edge of their input polygon. */
    for (size_t j = 0; j < cut->piece_count && !status; ++j) {
        const rad_contact_piece *piece = &cut->pieces[j];
        const rad_polygon *p = &scene->polygons[piece->polygon];
        for (uint32_t c = 0; c < piece->count; ++c) {
            rad_vec3 x = list->points[piece->first + c];
            for (uint32_t k = 0; k < p->count; ++k) {
                double t;
                if (!inside_edge(x, rad_polygon_vertex(scene, p, k), rad_polygon_vertex(scene, p, (k + 1) % p->count), eps, &t))
                    continue;
                if (grow(ctx, (void **)&marks, &mark_capacity, mark_count + 1, sizeof *marks)) {
                    status = RAD_ERROR_NO_MEMORY;
                    break;
                }
                edge_key(scene, piece->polygon, k, lo, quantum, marks[mark_count].key);
                marks[mark_count].normal = rad_polygon_normal(scene, p);
                marks[mark_count++].point = x;
            }
        }
    }
    if (mark_count) qsort(marks, mark_count, sizeof *marks, by_key);
    size_t first_of_polygon = 0;
    for (size_t j = 0; j < cut->piece_count && !status; ++j) {
        const rad_contact_piece *piece = &cut->pieces[j];
        if (j == 0 || piece->polygon != cut->pieces[j - 1].polygon) first_of_polygon = j;
        size_t last_of_polygon = j;
        while (last_of_polygon + 1 < cut->piece_count && cut->pieces[last_of_polygon + 1].polygon == piece->polygon)
            last_of_polygon++;
        const rad_polygon *p = &scene->polygons[piece->polygon];
        size_t made = 0;
        for (uint32_t c = 0; c < piece->count && !status; ++c) {
            rad_vec3 a = list->points[piece->first + c], b = list->points[piece->first + (c + 1) % piece->count];
            size_t found = 0;
            /* Corners of the polygon's other pieces. */
            for (size_t o = first_of_polygon; o <= last_of_polygon && !status; ++o) {
                if (o == j || cut->piece_count <= 1) continue;
                const rad_contact_piece *other = &cut->pieces[o];
                for (uint32_t q = 0; q < other->count; ++q) {
                    double t;
                    if (!inside_edge(list->points[other->first + q], a, b, eps, &t)) continue;
                    if (grow(ctx, (void **)&along, &along_capacity, found + 1, sizeof *along) ||
                        grow(ctx, (void **)&corners, &corner_capacity, found + 1, sizeof *corners)) {
                        status = RAD_ERROR_NO_MEMORY;
                        break;
                    }
                    along[found] = t;
                    corners[found++] = list->points[other->first + q];
                }
            }
            /* Points the neighbours across the polygon's edge put on it. */
            for (uint32_t k = 0; k < p->count && mark_count && !status; ++k) {
                rad_vec3 u = rad_polygon_vertex(scene, p, k), w = rad_polygon_vertex(scene, p, (k + 1) % p->count);
                double ta, tb;
                rad_vec3 d = v3_normalize(v3_sub(w, u));
                ta = v3_length(v3_cross(v3_sub(a, u), d));
                tb = v3_length(v3_cross(v3_sub(b, u), d));
                if (ta > eps || tb > eps) continue; /* this piece edge is not on edge k */
                edge_point probe;
                edge_key(scene, piece->polygon, k, lo, quantum, probe.key);
                edge_point *hit = bsearch(&probe, marks, mark_count, sizeof *marks, by_key);
                if (!hit) continue;
                while (hit > marks && by_key(hit - 1, &probe) == 0) hit--;
                rad_vec3 normal = rad_polygon_normal(scene, p);
                for (; hit < marks + mark_count && by_key(hit, &probe) == 0; ++hit) {
                    double t;
                    if (v3_dot(hit->normal, normal) < T_POINT_COSINE) continue;
                    if (!inside_edge(hit->point, a, b, eps, &t)) continue;
                    if (grow(ctx, (void **)&along, &along_capacity, found + 1, sizeof *along) ||
                        grow(ctx, (void **)&corners, &corner_capacity, found + 1, sizeof *corners)) {
                        status = RAD_ERROR_NO_MEMORY;
                        break;
                    }
                    along[found] = t;
                    corners[found++] = hit->point;
                }
            }
            if (status) break;
            /* The piece's corner, then the points along the edge in order, each once. */
            if (grow(ctx, (void **)&fresh.points, &fresh.capacity, fresh.used + made + found + 1, sizeof *fresh.points)) {
                status = RAD_ERROR_NO_MEMORY;
                break;
            }
            fresh.points[fresh.used + made++] = a;
            /* Sort the points by their distance along the edge (pairs sorted by index). */
            for (size_t x = 1; x < found; ++x)
                for (size_t y = x; y > 0 && along[y - 1] > along[y]; --y) {
                    double ts = along[y];
                    along[y] = along[y - 1], along[y - 1] = ts;
                    rad_vec3 ps = corners[y];
                    corners[y] = corners[y - 1], corners[y - 1] = ps;
                }
            double last = -INFINITY;
            for (size_t x = 0; x < found; ++x) {
                if (along[x] - last <= eps) continue;
                last = along[x];
                fresh.points[fresh.used + made++] = corners[x];
                cut->t_points++;
            }
        }
        if (status) break;
        status = add_piece(ctx, &fresh, NULL, 0); /* its points are in place already */
        if (status) break;
        fresh.count[fresh.pieces - 1] = (uint32_t)made;
        fresh.used += made;
    }
    /* The pieces point into the new list only now: the loop above reads the other pieces of a
     * polygon from the old one (it read them at their new places in the old list, garbage
     * that made NaN corners and a mesher that ran for minutes). */
    for (size_t j = 0; j < cut->piece_count && !status; ++j) {
        cut->pieces[j].first = fresh.first[j];
        cut->pieces[j].count = fresh.count[j];
    }
    if (!status) {
        rad_free(ctx, list->points);
        list->points = fresh.points;
        list->used = fresh.used;
        list->capacity = fresh.capacity;
        fresh.points = NULL;
    }
    piece_list_free(ctx, &fresh);
    rad_free(ctx, marks);
    rad_free(ctx, along);
    rad_free(ctx, corners);
    return status;
}

/* ------------------------------------------------------------------------------------------- */
/* Step 2 in parallel: the sweep positions in chunks of PAIR_CHUNK, each chunk's contacts kept */
/* apart and joined in sweep order, so the contacts come out as one sweep makes them.          */

#define PAIR_CHUNK 1024

typedef struct pair_scratch {
    uint32_t *candidates, *stack;
    size_t candidate_count, candidate_capacity, stack_capacity;
} pair_scratch;

typedef struct pair_chunk {
    contact *contacts;
    size_t contact_count, contact_capacity;
    size_t bound_tests, coplanar_pairs, covered_pairs;
    uint32_t coplanar[2], covering[2]; /* the chunk's first pair of each kind */
    rad_status status;
} pair_chunk;

typedef struct pair_job {
    rad_context *ctx;
    const rad_scene *scene;
    const plane_info *info;
    const uint32_t *order;
    const box *boxes;
    const uint8_t *usable;
    const box_tree *tree;
    double eps, slack;
    int no_near, sealed;
    size_t np;
    pair_scratch *scratch; /* per worker */
    pair_chunk *chunks;
} pair_job;

/* Step 2 for the polygon at sweep position s and those after it whose bounds meet its own. */
static rad_status pairs_of(const pair_job *job, pair_scratch *scratch, pair_chunk *chunk, size_t s) {
    rad_context *ctx = job->ctx;
    const rad_scene *scene = job->scene;
    const plane_info *info = job->info;
    const box *boxes = job->boxes;
    const double eps = job->eps, slack = job->slack;
    const int no_near = job->no_near, sealed = job->sealed;
    uint32_t a = job->order[s];
    if (!job->usable[s]) return RAD_OK;
    /* Bounds nearer than slack, or than NEAR_GAP times the larger polygon's extent (step 2b;
     * none for the roots, no_near): the tree gives the bounds within slack plus both reaches,
     * judged here on the larger reach, read in sweep order (boxes) with the reaches computed
     * once, the polygons only for pairs that meet. */
    rad_status status = tree_candidates(ctx, job->tree, (uint32_t)s, &scratch->candidates,
                                        &scratch->candidate_count, &scratch->candidate_capacity,
                                        &scratch->stack, &scratch->stack_capacity, &chunk->bound_tests);
    const double reach_a = boxes[s].reach;
    const rad_vec3 a_lo = boxes[s].lo, a_hi = boxes[s].hi;
    for (size_t k = 0; k < scratch->candidate_count && !status; ++k) {
        size_t t = scratch->candidates[k];
        const rad_vec3 b_lo = boxes[t].lo, b_hi = boxes[t].hi;
        const double m = slack + fmax(reach_a, boxes[t].reach);
        if (b_lo.x > a_hi.x + m || b_lo.y > a_hi.y + m || a_lo.y > b_hi.y + m ||
            b_lo.z > a_hi.z + m || a_lo.z > b_hi.z + m)
            continue;
        uint32_t b = job->order[t];
        /* Polygons of one surface are cut only where one passes through the other or stands
         * on it (kind 1): a building exported as one material, walls of one surface running
         * into each other at the corners. */
        const int same = scene->polygons[a].surface == scene->polygons[b].surface;
        for (int way = 0; way < 2 && !status; ++way) {
            uint32_t receiver = way ? b : a, other = way ? a : b;
            line l;
            int kind = contact_line(scene, info, receiver, other, eps, &l);
            if (same && kind != 1) {
                if (kind == 2) break;
                continue;
            }
            if (kind == 2) {
                /* Coplanar: overlapping when the centre of one lies inside the other. Step 2c:
                 * facing the same way (a rug on a floor, a decal, a face given twice), the
                 * larger is cut along the smaller's outline and loses the pieces under it, so
                 * the two never fight for the same place; facing opposite ways (back to back),
                 * only the note. */
                if (way == 1 || !(inside(scene, info, a, b, eps) || inside(scene, info, b, a, eps))) break;
                if (v3_dot(info[a].normal, info[b].normal) < 0) {
                    if (!chunk->coplanar_pairs) chunk->coplanar[0] = a, chunk->coplanar[1] = b;
                    chunk->coplanar_pairs++;
                    break;
                }
                double area_a = rad_polygon_area(scene, &scene->polygons[a]);
                double area_b = rad_polygon_area(scene, &scene->polygons[b]);
                receiver = area_a > area_b || (area_a == area_b && a > b) ? a : b;
                other = receiver == a ? b : a;
                if (!chunk->covered_pairs) chunk->covering[0] = receiver, chunk->covering[1] = other;
                chunk->covered_pairs++;
            }
            line near[64];
            size_t lines = kind == 1                         ? 1
                           : kind == 0 && no_near && !sealed ? 0
                           : near_parallel_lines(scene, info, receiver, other, eps, kind == 2, sealed, near);
            if (kind == 1) near[0] = l;
            if (grow(ctx, (void **)&chunk->contacts, &chunk->contact_capacity, chunk->contact_count + lines,
                     sizeof *chunk->contacts))
                return RAD_ERROR_NO_MEMORY;
            for (size_t k = 0; k < lines; ++k)
                chunk->contacts[chunk->contact_count++] = (contact){receiver, other, near[k], kind == 2};
            if (kind == 2) break;
        }
    }
    return status;
}

static void pair_chunk_run(void *user, long index, int worker) {
    const pair_job *job = user;
    pair_chunk *chunk = &job->chunks[index];
    pair_scratch *scratch = &job->scratch[worker];
    if (!scratch->stack) {
        scratch->stack_capacity = 64;
        if (!(scratch->stack = rad_alloc(job->ctx, 64, sizeof *scratch->stack))) {
            chunk->status = RAD_ERROR_NO_MEMORY;
            return;
        }
    }
    size_t end = ((size_t)index + 1) * PAIR_CHUNK < job->np ? ((size_t)index + 1) * PAIR_CHUNK : job->np;
    for (size_t s = (size_t)index * PAIR_CHUNK; s < end && !chunk->status; ++s)
        chunk->status = pairs_of(job, scratch, chunk, s);
}

/* Step 2 over every sweep position: the contacts, in sweep order, into *contacts; the counts
 * and the first pair of each kind into cut. */
static rad_status pairs_find(pair_job *job, rad_contact_cut *cut, contact **contacts, size_t *contact_count,
                             uint32_t coplanar[2], uint32_t covering[2]) {
    rad_context *ctx = job->ctx;
    const size_t chunk_count = (job->np + PAIR_CHUNK - 1) / PAIR_CHUNK;
    const int workers = rad_thread_count(ctx) > 0 ? rad_thread_count(ctx) : 1;
    rad_status status = RAD_OK;
    job->scratch = rad_alloc_zero(ctx, (size_t)workers, sizeof *job->scratch);
    job->chunks = rad_alloc_zero(ctx, chunk_count + 1, sizeof *job->chunks);
    if (!job->scratch || !job->chunks) status = RAD_ERROR_NO_MEMORY;
    if (!status) rad_team_for(ctx, (long)chunk_count, pair_chunk_run, job);
    size_t total = 0;
    for (size_t c = 0; c < chunk_count && !status; ++c) {
        status = job->chunks[c].status;
        total += job->chunks[c].contact_count;
    }
    if (!status && !(*contacts = rad_alloc(ctx, total + 1, sizeof **contacts))) status = RAD_ERROR_NO_MEMORY;
    for (size_t c = 0; c < chunk_count && !status; ++c) {
        const pair_chunk *chunk = &job->chunks[c];
        if (chunk->contact_count) /* an empty chunk has no array: memcpy from NULL is undefined */
            memcpy(*contacts + *contact_count, chunk->contacts, chunk->contact_count * sizeof **contacts);
        *contact_count += chunk->contact_count;
        cut->bound_tests += chunk->bound_tests;
        if (!cut->coplanar_pairs && chunk->coplanar_pairs)
            coplanar[0] = chunk->coplanar[0], coplanar[1] = chunk->coplanar[1];
        if (!cut->covered_pairs && chunk->covered_pairs)
            covering[0] = chunk->covering[0], covering[1] = chunk->covering[1];
        cut->coplanar_pairs += chunk->coplanar_pairs;
        cut->covered_pairs += chunk->covered_pairs;
    }
    for (size_t c = 0; job->chunks && c < chunk_count; ++c) rad_free(ctx, job->chunks[c].contacts);
    for (int w = 0; job->scratch && w < workers; ++w) {
        rad_free(ctx, job->scratch[w].candidates);
        rad_free(ctx, job->scratch[w].stack);
    }
    rad_free(ctx, job->chunks);
    rad_free(ctx, job->scratch);
    return status;
}

/* ------------------------------------------------------------------------------------------- */
/* Steps 3 and 4 in parallel: the polygons in chunks of CUT_CHUNK (a fixed size, so what each   */
/* chunk makes does not depend on the thread count), each chunk's pieces and counts kept apart */
/* and joined in polygon order: the same cut, to the bit, as one polygon after another.        */

#define CUT_CHUNK 1024

/* What one worker reuses from polygon to polygon. */
typedef struct cut_scratch {
    piece_list work;
    rad_vec3 *left, *right; /* split_room points each */
    uint8_t *fate;          /* with sparing: per piece of one polygon, 1 covered, 2 hidden */
    size_t fate_capacity;
} cut_scratch;

/* What one chunk of polygons made. */
typedef struct cut_chunk {
    piece_list list;          /* its pieces' points */
    uint32_t *polygon;        /* per piece of list: the input polygon */
    size_t polygon_capacity;
    double *hidden_area;      /* the hidden pieces' areas, in order (summed when joined) */
    size_t hidden_count, hidden_capacity;
    size_t cut_polygons, contact_lines, covered_pieces, left_whole, shadow_cuts;
    rad_status status;
} cut_chunk;

typedef struct cut_job {
    rad_context *ctx;
    const rad_scene *scene;
    const rad_contact_options *options;
    const plane_info *info;
    const contact *contacts; /* by receiver */
    size_t contact_count;
    const rad_shadow_segment *segments; /* by polygon */
    size_t segment_count;
    uint8_t *taken; /* per segment: cut along (each polygon writes only its own) */
    const rad_rays *rays;
    double eps;
    int sparing;
    size_t split_room;
    size_t np;
    size_t *contact_first; /* polygon i's contacts: [contact_first[2i], contact_first[2i + 1]) */
    size_t *segment_first; /* the same for its shadow segments */
    cut_scratch *scratch;  /* per worker */
    cut_chunk *chunks;
} cut_job;

/* Steps 3 and 4 for polygon i: its pieces into chunk->list. */
static rad_status cut_polygon(const cut_job *job, cut_scratch *scratch, cut_chunk *chunk, size_t i) {
    rad_context *ctx = job->ctx;
    const rad_scene *scene = job->scene;
    const rad_contact_options *options = job->options;
    const plane_info *info = job->info;
    const contact *contacts = job->contacts;
    const rad_shadow_segment *segments = job->segments;
    const rad_rays *rays = job->rays;
    const double eps = job->eps;
    const size_t split_room = job->split_room;
    piece_list *work = &scratch->work;
    rad_vec3 *left = scratch->left, *right = scratch->right;
    rad_status status = RAD_OK;
    const rad_polygon *polygon = &scene->polygons[i];
    size_t first_contact = job->contact_first[2 * i], next_contact = job->contact_first[2 * i + 1];
    size_t lines = next_contact - first_contact;
    work->pieces = work->used = 0;
    rad_vec3 corners[64];
    const rad_vec3 *whole = corners;
    rad_vec3 *big = NULL;
    if (polygon->count > 64) {
        big = rad_alloc(ctx, polygon->count, sizeof *big);
        if (!big) return RAD_ERROR_NO_MEMORY;
        whole = big;
    }
    for (uint32_t k = 0; k < polygon->count; ++k)
        (big ? big : corners)[k] = rad_polygon_vertex(scene, polygon, k);
    status = add_piece(ctx, work, whole, polygon->count);
    size_t made = 0;
    for (size_t c = first_contact; c < next_contact && made < MAX_LINES && !status; ++c) {
        line l = contacts[c].cut;
        int seen = 0; /* the same line from another polygon (a block's side and its top) */
        for (size_t d = first_contact; d < c && !seen; ++d) {
            line o = contacts[d].cut;
            seen = v3_length(v3_cross(o.direction, l.direction)) < 1e-9 &&
                   v3_length(v3_cross(v3_sub(l.point, o.point), o.direction)) < eps;
        }
        if (seen) continue;
        made++;
        rad_vec3 side = v3_cross(info[i].normal, l.direction);
        size_t pieces = work->pieces;
        for (size_t w = 0; w < pieces && !status; ++w) {
            size_t nl, nr;
            if (work->count[w] == 0) continue;
            if (work->count[w] + 2 > split_room / 2) continue;
            if (!split(work->points + work->first[w], work->count[w], l.point, side, eps, left, &nl,
                       right, &nr))
                continue;
            if (polygon_area(left, nl) <= eps * eps || polygon_area(right, nr) <= eps * eps) continue;
            work->count[w] = 0; /* replaced by its two halves */
            status = add_piece(ctx, work, left, nl);
            if (!status) status = add_piece(ctx, work, right, nr);
        }
    }
    /* Sparing: the cut is kept only when it pays (a piece hidden or covered) and stays small;
     * else the polygon is one piece again. */
    if (job->sparing && made && !status) {
        size_t live = 0, dropped = 0;
        if (grow(ctx, (void **)&scratch->fate, &scratch->fate_capacity, work->pieces, 1)) {
            rad_free(ctx, big);
            return RAD_ERROR_NO_MEMORY;
        }
        for (size_t w = 0; w < work->pieces; ++w) {
            scratch->fate[w] = 0;
            if (work->count[w] == 0) continue;
            live++;
            const rad_vec3 *p = work->points + work->first[w];
            scratch->fate[w] = (uint8_t)piece_fate(scene, rays, info, contacts + first_contact, lines,
                                                   p, work->count[w], eps);
            dropped += scratch->fate[w] != 0;
        }
        if (!dropped || live - dropped > RAD_CONTACT_SPARING_PIECES) {
            work->pieces = work->used = 0;
            status = add_piece(ctx, work, whole, polygon->count);
            made = 0;
            chunk->left_whole++;
        }
    }
    rad_free(ctx, big);
    if (made) chunk->cut_polygons++, chunk->contact_lines += made;
    /* Shadow boundaries on this polygon, the largest weight first. */
    size_t first_segment = job->segment_first[2 * i], next_segment = job->segment_first[2 * i + 1];
    size_t shadow_lines = 0;
    for (size_t c = first_segment; c < next_segment && shadow_lines < MAX_SHADOW_LINES && !status; ++c) {
        int near = 0;
        for (size_t d = first_segment; d < c && !near; ++d)
            near = job->taken[d] && beside(&segments[c], &segments[d], SEPARATION * options->element_size);
        if (near) continue;
        if (!cut_segment(ctx, work, &segments[c], info[i].normal, eps, SLIVER * options->element_size,
                         left, right, split_room / 2, &status))
            continue;
        job->taken[c] = 1;
        shadow_lines++;
    }
    chunk->shadow_cuts += shadow_lines;
    for (size_t w = 0; w < work->pieces && !status; ++w) {
        if (work->count[w] == 0) continue;
        const rad_vec3 *p = work->points + work->first[w];
        int fate_w = !made         ? 0
                     : job->sparing ? scratch->fate[w]
                                    : piece_fate(scene, rays, info, contacts + first_contact, lines, p,
                                                 work->count[w], eps);
        if (fate_w == 1) {
            chunk->covered_pieces++;
            continue;
        }
        if (fate_w == 2) {
            if (grow(ctx, (void **)&chunk->hidden_area, &chunk->hidden_capacity, chunk->hidden_count + 1,
                     sizeof *chunk->hidden_area))
                return RAD_ERROR_NO_MEMORY;
            chunk->hidden_area[chunk->hidden_count++] = polygon_area(p, work->count[w]);
            continue;
        }
        status = add_piece(ctx, &chunk->list, p, work->count[w]);
        if (status) break;
        if (grow(ctx, (void **)&chunk->polygon, &chunk->polygon_capacity, chunk->list.pieces,
                 sizeof *chunk->polygon))
            return RAD_ERROR_NO_MEMORY;
        chunk->polygon[chunk->list.pieces - 1] = (uint32_t)i;
    }
    return status;
}

static void cut_chunk_run(void *user, long index, int worker) {
    const cut_job *job = user;
    cut_chunk *chunk = &job->chunks[index];
    cut_scratch *scratch = &job->scratch[worker];
    size_t end = ((size_t)index + 1) * CUT_CHUNK < job->np ? ((size_t)index + 1) * CUT_CHUNK : job->np;
    for (size_t i = (size_t)index * CUT_CHUNK; i < end && !chunk->status; ++i)
        chunk->status = cut_polygon(job, scratch, chunk, i);
}

/* Steps 3 and 4 over every polygon: the pieces kept into *list and cut->pieces, the counts
 * into cut. */
static rad_status cut_polygons(cut_job *job, rad_contact_cut *cut, piece_list *list) {
    rad_context *ctx = job->ctx;
    const size_t np = job->np;
    const size_t chunk_count = (np + CUT_CHUNK - 1) / CUT_CHUNK;
    const int workers = rad_thread_count(ctx) > 0 ? rad_thread_count(ctx) : 1;
    rad_status status = RAD_OK;
    job->contact_first = rad_alloc(ctx, 2 * np + 1, sizeof *job->contact_first);
    job->segment_first = rad_alloc(ctx, 2 * np + 1, sizeof *job->segment_first);
    job->scratch = rad_alloc_zero(ctx, (size_t)workers, sizeof *job->scratch);
    job->chunks = rad_alloc_zero(ctx, chunk_count + 1, sizeof *job->chunks);
    if (!job->contact_first || !job->segment_first || !job->scratch || !job->chunks)
        status = RAD_ERROR_NO_MEMORY;
    for (int w = 0; w < workers && !status; ++w) {
        job->scratch[w].left = rad_alloc(ctx, job->split_room, sizeof *job->scratch[w].left);
        job->scratch[w].right = rad_alloc(ctx, job->split_room, sizeof *job->scratch[w].right);
        if (!job->scratch[w].left || !job->scratch[w].right) status = RAD_ERROR_NO_MEMORY;
    }
    /* Each polygon's contacts and segments, found as the walk in polygon order finds them. */
    size_t next_contact = 0, next_segment = 0;
    for (size_t i = 0; i < np && !status; ++i) {
        job->contact_first[2 * i] = next_contact;
        while (next_contact < job->contact_count && job->contacts[next_contact].receiver == i) next_contact++;
        job->contact_first[2 * i + 1] = next_contact;
        while (next_segment < job->segment_count && job->segments[next_segment].polygon < i) next_segment++;
        job->segment_first[2 * i] = next_segment;
        while (next_segment < job->segment_count && job->segments[next_segment].polygon == i) next_segment++;
        job->segment_first[2 * i + 1] = next_segment;
    }
    if (!status) rad_team_for(ctx, (long)chunk_count, cut_chunk_run, job);
    /* Joined in polygon order. */
    size_t pieces = 0, points = 0;
    for (size_t c = 0; c < chunk_count && !status; ++c) {
        status = job->chunks[c].status;
        pieces += job->chunks[c].list.pieces;
        points += job->chunks[c].list.used;
    }
    if (!status) {
        list->points = rad_alloc(ctx, points + 1, sizeof *list->points);
        list->first = rad_alloc(ctx, pieces + 1, sizeof *list->first);
        list->count = rad_alloc(ctx, pieces + 1, sizeof *list->count);
        cut->pieces = rad_alloc(ctx, pieces + 1, sizeof *cut->pieces);
        if (!list->points || !list->first || !list->count || !cut->pieces) status = RAD_ERROR_NO_MEMORY;
        list->capacity = points + 1;
        list->piece_capacity = pieces + 1;
    }
    for (size_t c = 0; c < chunk_count && !status; ++c) {
        const cut_chunk *chunk = &job->chunks[c];
        if (chunk->list.used) /* an empty chunk may have no array */
            memcpy(list->points + list->used, chunk->list.points, chunk->list.used * sizeof *list->points);
        for (size_t k = 0; k < chunk->list.pieces; ++k) {
            size_t at = list->pieces + k;
            list->first[at] = (uint32_t)(list->used + chunk->list.first[k]);
            list->count[at] = chunk->list.count[k];
            cut->pieces[at] = (rad_contact_piece){chunk->polygon[k], list->first[at], list->count[at]};
        }
        list->used += chunk->list.used;
        list->pieces += chunk->list.pieces;
        cut->cut_polygons += chunk->cut_polygons;
        cut->contact_lines += chunk->contact_lines;
        cut->covered_pieces += chunk->covered_pieces;
        cut->left_whole += chunk->left_whole;
        cut->shadow_cuts += chunk->shadow_cuts;
        cut->hidden_pieces += chunk->hidden_count;
        for (size_t k = 0; k < chunk->hidden_count; ++k) cut->hidden_area += chunk->hidden_area[k];
    }
    for (size_t c = 0; job->chunks && c < chunk_count; ++c) {
        piece_list_free(ctx, &job->chunks[c].list);
        rad_free(ctx, job->chunks[c].polygon);
        rad_free(ctx, job->chunks[c].hidden_area);
    }
    for (int w = 0; job->scratch && w < workers; ++w) {
        piece_list_free(ctx, &job->scratch[w].work);
        rad_free(ctx, job->scratch[w].left);
        rad_free(ctx, job->scratch[w].right);
        rad_free(ctx, job->scratch[w].fate);
    }
    rad_free(ctx, job->chunks);
    rad_free(ctx, job->scratch);
    rad_free(ctx, job->contact_first);
    rad_free(ctx, job->segment_first);
    return status;
}

rad_status rad_contact_cut_create(rad_context *ctx, const rad_scene *scene, rad_contact_cut **out) {
    return rad_contact_cut_create_with(ctx, scene, NULL, out);
}

rad_status rad_contact_cut_create_with(rad_context *ctx, const rad_scene *scene,
                                       const rad_contact_options *options, rad_contact_cut **out) {
    *out = NULL;
    size_t np = scene->polygon_count;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double diagonal = v3_length(v3_sub(hi, lo));
    double eps = diagonal > 0 ? 1e-6 * diagonal : 1e-9;
    plane_info *info = rad_alloc(ctx, np + 1, sizeof *info);
    uint32_t *order = rad_alloc(ctx, np + 1, sizeof *order);
    box *boxes = NULL; /* the bounds in sweep order */
    uint8_t *usable = NULL; /* per sweep position: the polygon takes part in step 2 */
    box_tree tree = {0};
    contact *contacts = NULL;
    size_t contact_count = 0, largest = 3;
    rad_contact_cut *cut = rad_alloc_zero(ctx, 1, sizeof *cut);
    piece_list list = {0};
    rad_rays *rays = NULL;
    rad_status status = RAD_OK;
    uint32_t coplanar[2] = {0, 0}, covering[2] = {0, 0};
    rad_shadow_segment *segments = NULL;
    size_t segment_count = 0;
    uint8_t *taken = NULL;
    int sparing = options && options->sparing;
    /* Without near-parallel lines (step 2b; the hierarchy's roots) only pairs whose bounds meet
     * can touch: no reach, a window of a few eps, not NEAR_GAP times the largest polygon (with
     * a floor slab spanning an office of 10^6 triangles, that window held thousands of polygons
     * for each). */
    const int no_near = options && options->no_near;
    const int sealed = no_near && options->sealed;
    const double slack = no_near ? 4 * eps : eps;
    if (!info || !order || !cut) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    /* Step 1. */
    for (size_t i = 0; i < np; ++i) {
        const rad_polygon *polygon = &scene->polygons[i];
        plane_info *p = &info[i];
        p->normal = rad_polygon_normal(scene, polygon);
        p->lo = v3(INFINITY, INFINITY, INFINITY);
        p->hi = v3(-INFINITY, -INFINITY, -INFINITY);
        rad_vec3 sum = v3(0, 0, 0);
        for (uint32_t k = 0; k < polygon->count; ++k) {
            rad_vec3 q = rad_polygon_vertex(scene, polygon, k);
            sum = v3_add(sum, q);
            p->lo = v3(fmin(p->lo.x, q.x), fmin(p->lo.y, q.y), fmin(p->lo.z, q.z));
            p->hi = v3(fmax(p->hi.x, q.x), fmax(p->hi.y, q.y), fmax(p->hi.z, q.z));
        }
        p->offset = v3_dot(p->normal, v3_scale(sum, 1.0 / polygon->count));
        if (polygon->count > largest) largest = polygon->count;
        order[i] = (uint32_t)i;
    }
    sort_info = info;
    if (np) qsort(order, np, sizeof *order, by_low_x);
    /* Step 2: pairs whose bounds meet, taken as a sweep along x would meet them (the earlier
     * polygon in x is `a`), from the tree of the bounds. */
    boxes = rad_alloc(ctx, np + 1, sizeof *boxes);
    usable = rad_alloc(ctx, np + 1, sizeof *usable);
    if (!boxes || !usable) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    for (size_t i = 0; i < np; ++i) {
        const plane_info *p = &info[order[i]];
        /* The reach: as far as step 2b looks in front of the polygon (sealed: only as far as
         * it can seal, a small share of its width). */
        const double reach = sealed    ? RAD_CONTACT_SEALED_GAP * polygon_width(scene, &scene->polygons[order[i]])
                             : no_near ? 0
                                       : NEAR_GAP * v3_length(v3_sub(p->hi, p->lo));
        boxes[i] = (box){p->lo, p->hi, reach};
        usable[i] = isfinite(p->offset) && scene->polygons[order[i]].count <= 64;
    }
    status = tree_create(ctx, boxes, usable, np, slack, &tree);
    if (!status) {
        pair_job job = {ctx, scene, info, order, boxes, usable, &tree, eps, slack, no_near, sealed,
                        np, NULL, NULL};
        status = pairs_find(&job, cut, &contacts, &contact_count, coplanar, covering);
    }
    if (status) goto done;
    if (contact_count) qsort(contacts, contact_count, sizeof *contacts, by_receiver);
    /* Shadow boundaries (shadow.c), cut after each polygon's contact lines. */
    if (options && options->shadows && options->element_size > 0) {
        status = rad_shadow_segments_find(ctx, scene, options->element_size, &segments, &segment_count, NULL);
        if (status) goto done;
        cut->shadow_segments = segment_count;
        taken = rad_alloc_zero(ctx, segment_count + 1, 1);
        if (!taken) {
            status = RAD_ERROR_NO_MEMORY;
            goto done;
        }
    }
    /* Rays for step 4, only when something was cut. */
    if (contact_count) status = rad_rays_create(ctx, scene, &rays);
    /* Step 3 and 4, polygon by polygon, chunk by chunk on the context's threads, then the
     * chunks' pieces joined in polygon order. */
    if (!status) {
        cut_job job = {ctx, scene, options, info, contacts, contact_count, segments, segment_count,
                       taken, rays, eps, sparing, (largest + MAX_LINES + MAX_SHADOW_LINES + 2) * 2,
                       np, NULL, NULL, NULL, NULL};
        status = cut_polygons(&job, cut, &list);
    }
    if (status) goto done;
    cut->piece_count = list.pieces;
    /* Step 5. (It was run with shadows only: on contacts it read the other pieces of a polygon
     * at their new places in the old list, NaN corners that sent the mesher into minutes.) */
    if (segment_count || (options && options->t_points)) status = add_t_points(ctx, scene, eps, cut, &list);
    if (status) goto done;
    cut->points = list.points;
    cut->point_count = list.used;
    list.points = NULL;
    if (cut->covered_pairs && !(options && options->quiet))
        rad_warn(ctx, "%s: surface '%s' lies on '%s' in one plane (%zu pairs of polygons): the "
                 "part of '%s' under it is left out of the mesh", scene->source,
                 scene->surfaces[scene->polygons[covering[1]].surface].name,
                 scene->surfaces[scene->polygons[covering[0]].surface].name, cut->covered_pairs,
                 scene->surfaces[scene->polygons[covering[0]].surface].name);
    if (cut->coplanar_pairs && !(options && options->quiet))
        rad_warn(ctx, "%s: surfaces '%s' and '%s' overlap back to back in one plane (%zu pairs of "
                 "polygons); they are meshed as they are and may flicker in renders",
                 scene->source, scene->surfaces[scene->polygons[coplanar[0]].surface].name,
                 scene->surfaces[scene->polygons[coplanar[1]].surface].name, cut->coplanar_pairs);
    *out = cut;
    cut = NULL;
done:
    if (status == RAD_ERROR_NO_MEMORY) status = rad_fail(ctx, status, "out of memory cutting contacts");
    rad_rays_destroy(rays);
    rad_free(ctx, segments);
    rad_free(ctx, taken);
    rad_free(ctx, info);
    rad_free(ctx, order);
    rad_free(ctx, boxes);
    rad_free(ctx, usable);
    tree_free(ctx, &tree);
    rad_free(ctx, contacts);
    piece_list_free(ctx, &list);
    rad_contact_cut_destroy(ctx, cut);
    return status;
}
