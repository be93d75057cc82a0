/* polygon_cut.c - a simple polygon cut into a few convex pieces (polygon_cut.h).
 *
 * 1. Triangulate by ear clipping over a doubly linked list of the corners. Corners wait in a
 *    queue to be tried as ears; clipping an ear changes whether its two neighbours are ears
 *    and no other corner's (Eberly, "Triangulation by ear clipping", 2002), so only they are
 *    queued again: at most 3n tries, where a search that walks the ring from the last ear (as
 *    mapbox's earcut does) walks a comb's whole bar of collinear corners for every ear. The
 *    corner after an ear is tried after the others (its entry goes to the back), so a convex
 *    run is clipped every other corner rather than as a fan. A corner is an ear when it turns
 *    left and no other corner lies in its triangle; only reflex corners can (the others lie on
 *    the convex side of both of their edges: O'Rourke, "Computational Geometry in C", 1998,
 *    ch. 1), and a reflex corner only turns convex as ears are clipped, never the reverse, so
 *    the reflex corners sit in a uniform grid over their own bounds (about one a cell, the
 *    cells shaped to the bounds), from which they are taken out as they turn convex; an ear
 *    looks at the cells its triangle meets, row by row. On gears, combs, letters and floor
 *    plans that is about linear (bench/bench_polygon_cut.c). Every clip records, for the new
 *    edge (a, c), the half-edge on its other side, so the triangles come out with their
 *    neighbours (the diagonals' twins) at no cost.
 * 2. When the queue runs dry with more than three corners left, the polygon is not simple as
 *    seen in its plane (or rounding made it so): corners that lie on the line through their
 *    neighbours (no area) are dropped; failing that, the first corner that turns left is
 *    clipped without the test, as the old clipper did ("cut anyway, as a fan would"), and
 *    after a few such rounds what is left is fanned; past a budget of work the tests stop.
 *    The pieces are then the triangles as they were clipped (`simple` = 0).
 * 3. Hertel and Mehlhorn ("Fast triangulation of simple polygons", FCT 1983): visit the
 *    diagonals in the order they were made and remove each one whose removal leaves both of
 *    its ends convex. The pieces stay convex, and there are at most four times as many as in
 *    the fewest convex pieces without new corners (every diagonal left is essential at one of
 *    its ends, a reflex corner having at most two essential diagonals).
 * 4. A piece of more corners than the caller's limit (and a convex polygon given to
 *    rad_polygon_split) is split into a core and caps: the core goes through `max_corners`
 *    corners spread by length along the boundary, from one end of the longest edge round to
 *    the other, so that edge (a cap's chord, one level down) is the core's too; each run of
 *    corners between two consecutive core corners, closed by its chord, is a cap, split the
 *    same way while it has too many. Chords between roughly opposite corners (halving the
 *    polygon at each level) make rounder pieces, but the mesher peels only round polygons of
 *    even edges into rings and fans the rest from its centroid: half-disks and circular
 *    segments of many short edges became fans of needles (docs/meshing.md, "ngon"). */
#include "scene/polygon_cut.h"

#include <math.h>
#include <string.h>

#define NONE UINT32_MAX
/* Failed rounds (no ear in a whole round) before the rest is clipped without tests. */
#define CARELESS_ROUNDS 8
/* Rows and cells looked at reach this fraction of a cell beyond the triangle, so that a corner
 * on a cell's border is found whichever side rounding put it. */
#define SLACK 0.01
/* The grid's cells, at most. */
#define GRID_CELLS_MAX (1 << 22)

typedef struct cutter {
    const double (*p)[2];
    uint32_t *prev, *next;
    uint32_t *outside; /* half-edge beyond the edge (v, next[v]), NONE on the polygon's border */
    /* The reflex corners' grid: cell k holds entries[start[k] .. start[k] + count[k]). */
    uint32_t *start, *count, *entries, *slot; /* slot[v]: v's place in entries, or NONE */
    size_t side[2]; /* cells along x and along y */
    double lo[2], hi[2], cell[2];
    /* The triangles: half-edge 3t + k runs from corner[3t + k] to corner[3t + (k + 1) % 3]. */
    uint32_t *corner, *twin;
    size_t triangles;
    /* Corners to try as ears, in turn; queued[v] counts v's entries, removed[v] once clipped. */
    uint32_t *queue, *queued;
    size_t queue_end;
    unsigned char *removed;
    double work; /* points and cells looked at */
} cutter;

/* Twice the signed area of the triangle (a, b, c): positive when b turns left. */
static double turn(const double *a, const double *b, const double *c) {
    return (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
}

/* Turns left, beyond rounding: an ear's tip (the old clipper's test). */
static int turns_left(const double *a, const double *b, const double *c) {
    double scale = hypot(b[0] - a[0], b[1] - a[1]) * hypot(c[0] - b[0], c[1] - b[1]);
    return turn(a, b, c) > 1e-12 * scale;
}

/* Convex enough to stay a corner of a piece: turns left, or goes on forward and turns right by
 * rounding only or by less than `dent` off the line through its neighbours (the importer's
 * convex_within, corner by corner). */
static int convex_corner(const double *a, const double *b, const double *c, double dent) {
    double ax = b[0] - a[0], ay = b[1] - a[1], bx = c[0] - b[0], by = c[1] - b[1];
    double sine = ax * by - ay * bx, cosine = ax * bx + ay * by;
    if (sine > 0) return 1;
    if (cosine <= 0) return 0;
    return -sine <= 1e-12 * (fabs(ax) + fabs(ay)) * (fabs(bx) + fabs(by)) ||
           -sine <= dent * hypot(ax + bx, ay + by);
}

static size_t cell_index(const cutter *c, double x, size_t axis) {
    double k = (x - c->lo[axis]) / c->cell[axis];
    if (!(k > 0)) return 0;
    return k >= (double)(c->side[axis] - 1) ? c->side[axis] - 1 : (size_t)k;
}

static size_t cell_of(const cutter *c, uint32_t v) {
    return cell_index(c, c->p[v][1], 1) * c->side[0] + cell_index(c, c->p[v][0], 0);
}

/* Widens [*x0, *x1] by the part of segment (a, b) within y0 <= y <= y1. */
static void slab_span(const double *a, const double *b, double y0, double y1, double *x0,
                      double *x1) {
    double lo = fmax(fmin(a[1], b[1]), y0), hi = fmin(fmax(a[1], b[1]), y1);
    if (lo > hi) return;
    double dy = b[1] - a[1];
    for (int end = 0; end < 2; ++end) {
        double y = end ? hi : lo;
        double x = dy != 0 ? a[0] + (b[0] - a[0]) * ((y - a[1]) / dy) : (end ? b[0] : a[0]);
        if (dy != 0) x = fmin(fmax(x, fmin(a[0], b[0])), fmax(a[0], b[0]));
        *x0 = fmin(*x0, x);
        *x1 = fmax(*x1, x);
    }
}

/* Takes corner v out of the reflex grid, if it is there. */
static void grid_remove(cutter *c, uint32_t v) {
    if (c->slot[v] == NONE) return;
    size_t k = cell_of(c, v);
    uint32_t last = c->entries[c->start[k] + --c->count[k]];
    c->entries[c->slot[v]] = last;
    c->slot[last] = c->slot[v];
    c->slot[v] = NONE;
}

/* Is some reflex corner other than a, b, c in the closed triangle (a, b, c)? Corners at a's or
 * c's place (a polygon touching itself there) do not count. */
static int blocked(cutter *c, uint32_t ia, uint32_t ib, uint32_t ic) {
    const double *a = c->p[ia], *b = c->p[ib], *d = c->p[ic];
    size_t y0 = cell_index(c, fmin(a[1], fmin(b[1], d[1])), 1);
    size_t y1 = cell_index(c, fmax(a[1], fmax(b[1], d[1])), 1);
    for (size_t y = y0; y <= y1; ++y) {
        /* The cells of this row the triangle meets: its span within the row's slab (no reflex
         * corner lies outside the grid's bounds, which are theirs). */
        double below = fmax(c->lo[1] + ((double)y - SLACK) * c->cell[1], c->lo[1]);
        double above = fmin(c->lo[1] + ((double)y + 1 + SLACK) * c->cell[1], c->hi[1]);
        double left = INFINITY, right = -INFINITY;
        slab_span(a, b, below, above, &left, &right);
        slab_span(b, d, below, above, &left, &right);
        slab_span(d, a, below, above, &left, &right);
        if (left > right) continue;
        size_t x0 = cell_index(c, left - SLACK * c->cell[0], 0);
        size_t x1 = cell_index(c, right + SLACK * c->cell[0], 0);
        for (size_t x = x0; x <= x1; ++x) {
            size_t k = y * c->side[0] + x;
            c->work += 1 + c->count[k];
            for (uint32_t i = 0; i < c->count[k]; ++i) {
                uint32_t v = c->entries[c->start[k] + i];
                if (v == ia || v == ib || v == ic) continue;
                const double *q = c->p[v];
                if ((q[0] == a[0] && q[1] == a[1]) || (q[0] == d[0] && q[1] == d[1])) continue;
                if (turn(a, b, q) >= 0 && turn(b, d, q) >= 0 && turn(d, a, q) >= 0) return 1;
            }
        }
    }
    return 0;
}

/* Clips corner b: records the triangle (a, b, c) with its neighbours and unlinks b. With
 * `triangle` 0 (a corner with no area) no triangle is made, and the edges around b lose their
 * twins (no piece grows across them). */
static void clip(cutter *c, uint32_t b, int triangle) {
    uint32_t a = c->prev[b], d = c->next[b];
    grid_remove(c, b);
    uint32_t made = NONE;
    if (triangle) {
        uint32_t h = (uint32_t)(3 * c->triangles++);
        c->corner[h] = a;
        c->corner[h + 1] = b;
        c->corner[h + 2] = d;
        c->twin[h] = c->outside[a];
        c->twin[h + 1] = c->outside[b];
        c->twin[h + 2] = NONE;
        if (c->outside[a] != NONE) c->twin[c->outside[a]] = h;
        if (c->outside[b] != NONE) c->twin[c->outside[b]] = h + 1;
        made = h + 2;
    } else {
        if (c->outside[a] != NONE) c->twin[c->outside[a]] = NONE;
        if (c->outside[b] != NONE) c->twin[c->outside[b]] = NONE;
    }
    c->outside[a] = made;
    c->next[a] = d;
    c->prev[d] = a;
    /* a and d lost a piece of their angle: reflex ones may have turned convex. */
    if (c->slot[a] != NONE && turns_left(c->p[c->prev[a]], c->p[a], c->p[d])) grid_remove(c, a);
    if (c->slot[d] != NONE && turns_left(c->p[a], c->p[d], c->p[c->next[d]])) grid_remove(c, d);
}

static int grid_build(rad_context *ctx, cutter *c, size_t n) {
    size_t reflex = 0;
    c->lo[0] = c->lo[1] = INFINITY;
    double *hi = c->hi;
    hi[0] = hi[1] = -INFINITY;
    for (size_t v = 0; v < n; ++v) {
        c->slot[v] = turns_left(c->p[c->prev[v]], c->p[v], c->p[c->next[v]]) ? NONE : 0;
        if (c->slot[v] == NONE) continue;
        ++reflex;
        for (int axis = 0; axis < 2; ++axis) {
            c->lo[axis] = fmin(c->lo[axis], c->p[v][axis]);
            hi[axis] = fmax(hi[axis], c->p[v][axis]);
        }
    }
    /* About one reflex corner a cell, over the reflex corners' bounds, the cells as square as
     * the bounds let them be (a row of them along a comb's bar). */
    double width = reflex ? hi[0] - c->lo[0] : 0, height = reflex ? hi[1] - c->lo[1] : 0;
    double cells_wanted = fmin((double)reflex, (double)GRID_CELLS_MAX);
    for (int axis = 0; axis < 2; ++axis) {
        double extent = axis ? height : width, other = axis ? width : height, side = 1;
        if (extent > 0 && other > 0) side = sqrt(cells_wanted * extent / other);
        else if (extent > 0) side = cells_wanted;
        side = fmin(fmax(side, 1), cells_wanted > 1 ? cells_wanted : 1);
        c->side[axis] = (size_t)ceil(side);
        c->cell[axis] = extent / (double)c->side[axis];
        if (!(c->cell[axis] > 0)) c->cell[axis] = 1;
        if (!reflex) c->lo[axis] = hi[axis] = 0;
    }
    size_t cells = c->side[0] * c->side[1];
    c->start = rad_alloc_zero(ctx, cells + 1, sizeof *c->start);
    c->count = rad_alloc_zero(ctx, cells, sizeof *c->count);
    c->entries = rad_alloc(ctx, reflex ? reflex : 1, sizeof *c->entries);
    if (!c->start || !c->count || !c->entries) return 0;
    /* Counting sort of the reflex corners by cell. */
    for (size_t v = 0; v < n; ++v)
        if (c->slot[v] == 0) c->start[cell_of(c, (uint32_t)v) + 1]++;
    for (size_t k = 0; k < cells; ++k) c->start[k + 1] += c->start[k];
    for (size_t v = 0; v < n; ++v)
        if (c->slot[v] == 0) {
            size_t k = cell_of(c, (uint32_t)v);
            c->slot[v] = c->start[k] + c->count[k]++;
            c->entries[c->slot[v]] = (uint32_t)v;
        }
    return 1;
}

/* Queues corner v to be tried as an ear (again). */
static void try_later(cutter *c, uint32_t v) {
    c->queue[c->queue_end++] = v;
    c->queued[v]++;
}

/* Clips corner b (or drops it, with `triangle` 0) and queues its two neighbours, the only
 * corners whose being an ear this changes (Eberly, "Triangulation by ear clipping", 2002). */
static void clip_and_queue(cutter *c, uint32_t b, int triangle) {
    uint32_t a = c->prev[b], d = c->next[b];
    clip(c, b, triangle);
    c->removed[b] = 1;
    try_later(c, a);
    try_later(c, d);
}

static int turns_left_at(const cutter *c, uint32_t b) {
    return turns_left(c->p[c->prev[b]], c->p[b], c->p[c->next[b]]);
}

/* Step 1 and 2: the triangles. Returns 1 when every clip was an ear. */
static int triangulate(cutter *c, size_t n) {
    size_t left = n, rounds = 0, head = 0;
    int simple = 1, careless = 0;
    double budget = 256.0 * (double)n + 2e8;
    for (uint32_t v = 0; v < n; ++v) try_later(c, v);
    uint32_t last = 0; /* a corner still in the polygon */
    while (left > 3) {
        if (head < c->queue_end) {
            uint32_t b = c->queue[head++];
            /* An entry made stale by a later one waits for that one: the corner after an ear
             * is tried after the others, not at once (which would cut a fan). */
            if (--c->queued[b] > 0 || c->removed[b]) continue;
            last = b;
            uint32_t a = c->prev[b], d = c->next[b];
            if (turns_left(c->p[a], c->p[b], c->p[d]) && (careless || !blocked(c, a, b, d))) {
                clip_and_queue(c, b, 1);
                --left;
                last = d;
            }
            if (!careless && c->work > budget) careless = 1, simple = 0;
            continue;
        }
        /* No ear left. First drop corners that make no area. */
        head = c->queue_end = 0;
        size_t dropped = 0;
        uint32_t b = last;
        for (size_t k = 0, round = left; k < round && left > 3; ++k) {
            uint32_t after = c->next[b];
            const double *pa = c->p[c->prev[b]], *pb = c->p[b], *pc = c->p[after];
            double scale = hypot(pb[0] - pa[0], pb[1] - pa[1]) * hypot(pc[0] - pb[0], pc[1] - pb[1]);
            if (fabs(turn(pa, pb, pc)) <= 1e-12 * scale) {
                clip_and_queue(c, b, 0);
                --left;
                ++dropped;
            }
            b = after;
        }
        last = b;
        if (dropped || left <= 3) continue;
        /* Then clip the first corner that turns left without the test (the corner itself if
         * none does); after CARELESS_ROUNDS of these, fan what is left. */
        simple = 0;
        if (++rounds > CARELESS_ROUNDS) {
            while (left > 3) {
                clip(c, c->next[b], 1);
                --left;
            }
            last = b;
            break;
        }
        for (size_t k = 0; k < left && !turns_left_at(c, b); ++k) b = c->next[b];
        if (!turns_left_at(c, b)) b = last;
        last = c->next[b];
        clip_and_queue(c, b, 1);
        --left;
    }
    /* The last triangle: its third edge is on the border or beyond an earlier diagonal too. */
    uint32_t ear = last;
    uint32_t beyond = c->outside[c->next[ear]];
    clip(c, ear, 1);
    uint32_t h = (uint32_t)(3 * c->triangles - 1);
    c->twin[h] = beyond;
    if (beyond != NONE) c->twin[beyond] = h;
    return simple;
}

/* Step 3: Hertel and Mehlhorn, then the pieces. */
static rad_status merge_pieces(rad_context *ctx, cutter *c, double dent, int simple,
                               rad_polygon_pieces *out) {
    size_t edges = 3 * c->triangles;
    uint32_t *hnext = rad_alloc(ctx, edges, sizeof *hnext);
    uint32_t *hprev = rad_alloc(ctx, edges, sizeof *hprev);
    unsigned char *gone = rad_alloc_zero(ctx, edges, 1);
    rad_status status = RAD_OK;
    if (!hnext || !hprev || !gone) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    for (size_t h = 0; h < edges; ++h) {
        size_t t = h - h % 3;
        hnext[h] = (uint32_t)(t + (h + 1) % 3);
        hprev[h] = (uint32_t)(t + (h + 2) % 3);
    }
    size_t pieces = c->triangles;
    if (simple)
        for (uint32_t e = 0; e < edges; ++e) {
            uint32_t t = c->twin[e];
            if (t == NONE || t < e) continue;
            /* Remove the diagonal (u, v) when the corners at u and at v stay convex. */
            uint32_t u = c->corner[e], v = c->corner[t];
            uint32_t x = c->corner[hprev[e]], y = c->corner[hnext[hnext[t]]];
            uint32_t w = c->corner[hprev[t]], z = c->corner[hnext[hnext[e]]];
            if (!convex_corner(c->p[x], c->p[u], c->p[y], dent) ||
                !convex_corner(c->p[w], c->p[v], c->p[z], dent))
                continue;
            hnext[hprev[e]] = hnext[t];
            hprev[hnext[t]] = hprev[e];
            hnext[hprev[t]] = hnext[e];
            hprev[hnext[e]] = hprev[t];
            gone[e] = gone[t] = 1;
            --pieces;
        }
    size_t corners = 0;
    for (size_t h = 0; h < edges; ++h) corners += !gone[h];
    out->corners = rad_alloc(ctx, corners, sizeof *out->corners);
    out->first = rad_alloc(ctx, pieces + 1, sizeof *out->first);
    if (!out->corners || !out->first) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    /* Each piece once, from its first half-edge left; `gone` marks those taken. */
    size_t at = 0;
    for (size_t h = 0; h < edges; ++h) {
        if (gone[h]) continue;
        out->first[out->count++] = at;
        for (uint32_t g = (uint32_t)h; !gone[g]; g = hnext[g]) {
            out->corners[at++] = c->corner[g];
            gone[g] = 1;
        }
    }
    out->first[out->count] = at;
    out->simple = simple;
done:
    rad_free(ctx, hnext);
    rad_free(ctx, hprev);
    rad_free(ctx, gone);
    return status;
}

/* Step 4: pieces of at most `max` corners, appended to out (which has room for `piece_room`
 * pieces and `corner_room` corners). */
typedef struct splitter {
    rad_context *ctx;
    const double (*p)[2];
    size_t max;
    double dent;
    rad_polygon_pieces *out;
    size_t piece_room, corner_room;
} splitter;

static rad_status put_piece(splitter *s, const uint32_t *run, size_t m) {
    rad_polygon_pieces *out = s->out;
    size_t used = out->count ? out->first[out->count] : 0;
    if (out->count + 2 > s->piece_room) {
        size_t room = 2 * s->piece_room + 16;
        size_t *first = rad_realloc(s->ctx, out->first, room, sizeof *first);
        if (!first) return RAD_ERROR_NO_MEMORY;
        out->first = first;
        s->piece_room = room;
    }
    if (used + m > s->corner_room) {
        size_t room = 2 * s->corner_room + m + 64;
        uint32_t *corners = rad_realloc(s->ctx, out->corners, room, sizeof *corners);
        if (!corners) return RAD_ERROR_NO_MEMORY;
        out->corners = corners;
        s->corner_room = room;
    }
    memcpy(out->corners + used, run, m * sizeof *run);
    out->first[out->count] = used;
    out->first[++out->count] = used + m;
    return RAD_OK;
}

/* Do the corners run[1 .. m-2] all lie within `dent` of the chord run[m-1] -> run[0] (with
 * dent 0: on it)? */
static int flat_cap(const splitter *s, const uint32_t *run, size_t m) {
    const double *a = s->p[run[0]], *b = s->p[run[m - 1]];
    double length = hypot(b[0] - a[0], b[1] - a[1]);
    for (size_t k = 1; k + 1 < m; ++k) {
        double off = fabs(turn(a, b, s->p[run[k]]));
        if (length > 0 ? off > s->dent * length : hypot(s->p[run[k]][0] - a[0],
                                                        s->p[run[k]][1] - a[1]) > s->dent)
            return 0;
    }
    return 1;
}

static rad_status split_run(splitter *s, const uint32_t *run, size_t m) {
    if (m <= s->max) return put_piece(s, run, m);
    size_t K = s->max;
    uint32_t *path = rad_alloc(s->ctx, m + 1 + K, sizeof *path);
    double *along = rad_alloc(s->ctx, m + 1, sizeof *along);
    size_t *at = rad_alloc(s->ctx, K + 1, sizeof *at);
    rad_status status = RAD_ERROR_NO_MEMORY;
    if (!path || !along || !at) goto done;
    size_t longest = 0;
    double most = -1, perimeter = 0;
    for (size_t k = 0; k < m; ++k) {
        const double *a = s->p[run[k]], *b = s->p[run[(k + 1) % m]];
        double length = hypot(b[0] - a[0], b[1] - a[1]);
        perimeter += length;
        if (length > most) most = length, longest = k;
    }
    /* An edge longer than the core's share of the boundary (a cap's chord) is one of the
     * core's edges: the boundary is walked from its far end round to its near end, and the
     * other K - 1 core edges share the rest. Else (a round polygon) the K core edges share the
     * whole boundary from corner 0, and each is about as long as the others: the mesher peels
     * round polygons of even edges into rings, where one short edge among long ones makes it
     * fan the polygon from its centroid. */
    int chord = most * (double)K >= perimeter;
    size_t start = chord ? longest + 1 : 0;
    for (size_t j = 0; j <= m; ++j) path[j] = run[(start + j) % m];
    along[0] = 0;
    for (size_t j = 1; j <= m; ++j) {
        const double *a = s->p[path[j - 1]], *b = s->p[path[j]];
        along[j] = along[j - 1] + hypot(b[0] - a[0], b[1] - a[1]);
    }
    /* The core's corners: path[0], then each the nearest to its share of the length along
     * path[0 .. end], kept in order with room for those after it; by count when the length is
     * none (corners all in one place) or not a number. No cap takes more than 8 times its
     * share of the corners, so each level divides them by about K / 8 at least (corners
     * bunched in one place cannot make the recursion deep). */
    size_t end = chord ? m - 1 : m, gaps = chord ? K - 1 : K, j = 0;
    size_t widest = 8 * ((end + gaps - 1) / gaps);
    int by_length = along[end] > 0 && along[end] < INFINITY;
    at[0] = 0;
    for (size_t k = 1; k < gaps; ++k) {
        double target = along[end] * (double)k / (double)gaps;
        while (j + 1 < end && along[j + 1] <= target) ++j;
        size_t pick = j + 1 < end && along[j + 1] - target < target - along[j] ? j + 1 : j;
        if (!by_length) pick = k * end / gaps;
        if (pick > at[k - 1] + widest) pick = at[k - 1] + widest;
        if (pick + (gaps - k) * widest < end) pick = end - (gaps - k) * widest;
        if (pick <= at[k - 1]) pick = at[k - 1] + 1;
        if (pick > end - gaps + k) pick = end - gaps + k;
        at[k] = pick;
    }
    at[gaps] = end;
    at[K] = m;
    uint32_t *core = path + m + 1;
    for (size_t k = 0; k < K; ++k) core[k] = path[at[k]];
    status = put_piece(s, core, K);
    /* The caps, each the run between two consecutive core corners, closed by its chord. */
    for (size_t k = 0; k < K && !status; ++k) {
        size_t count = at[k + 1] - at[k] + 1;
        if (count >= 3 && !flat_cap(s, path + at[k], count))
            status = split_run(s, path + at[k], count);
    }
done:
    rad_free(s->ctx, path);
    rad_free(s->ctx, along);
    rad_free(s->ctx, at);
    return status;
}

/* Replaces every piece of more than `max` corners in *pieces by its split. */
static rad_status split_large(rad_context *ctx, const double (*p)[2], size_t max, double dent,
                              rad_polygon_pieces *pieces) {
    size_t k = 0;
    while (k < pieces->count && pieces->first[k + 1] - pieces->first[k] <= max) ++k;
    if (k == pieces->count) return RAD_OK;
    rad_polygon_pieces split = {0};
    splitter s = {ctx, p, max, dent, &split, 0, 0};
    rad_status status = RAD_OK;
    for (k = 0; k < pieces->count && !status; ++k)
        status = split_run(&s, pieces->corners + pieces->first[k],
                           pieces->first[k + 1] - pieces->first[k]);
    split.simple = pieces->simple;
    rad_polygon_pieces_free(ctx, pieces);
    if (status) rad_polygon_pieces_free(ctx, &split);
    else *pieces = split;
    return status;
}

rad_status rad_polygon_split(rad_context *ctx, const double *xy, size_t n, size_t max_corners,
                             double dent, rad_polygon_pieces *out) {
    memset(out, 0, sizeof *out);
    if (n < 3 || n >= (size_t)1 << 30 || max_corners < 3)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "polygon_split: %zu corners, at most %zu",
                        n, max_corners);
    uint32_t *all = rad_alloc(ctx, n, sizeof *all);
    if (!all) return RAD_ERROR_NO_MEMORY;
    for (size_t k = 0; k < n; ++k) all[k] = (uint32_t)k;
    splitter s = {ctx, (const double(*)[2])xy, max_corners, dent, out, 0, 0};
    rad_status status = split_run(&s, all, n);
    rad_free(ctx, all);
    out->simple = 1;
    if (status) rad_polygon_pieces_free(ctx, out);
    return status;
}

rad_status rad_polygon_cut(rad_context *ctx, const double *xy, size_t n, double dent,
                           size_t max_corners, rad_polygon_pieces *out) {
    memset(out, 0, sizeof *out);
    if (n < 3 || n >= (size_t)1 << 30 || (max_corners && max_corners < 3)) /* half-edges: 32 bits */
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "polygon_cut: %zu corners, at most %zu",
                        n, max_corners);
    cutter c = {.p = (const double(*)[2])xy};
    /* The per-corner and per-triangle arrays, one block: prev, next, outside, slot, queued (n
     * each), queue (3n), corner and twin (3 (n - 2) each); removed after them. */
    size_t words = 8 * n + 6 * (n - 2);
    uint32_t *block = rad_alloc_zero(ctx, words * sizeof(uint32_t) + n, 1);
    rad_status status = RAD_ERROR_NO_MEMORY;
    if (block) {
        uint32_t *at = block;
        c.prev = at, at += n;
        c.next = at, at += n;
        c.outside = at, at += n;
        c.slot = at, at += n;
        c.queued = at, at += n;
        c.queue = at, at += 3 * n;
        c.corner = at, at += 3 * (n - 2);
        c.twin = at, at += 3 * (n - 2);
        c.removed = (unsigned char *)at;
        for (size_t v = 0; v < n; ++v) {
            c.prev[v] = (uint32_t)(v ? v - 1 : n - 1);
            c.next[v] = (uint32_t)(v + 1 < n ? v + 1 : 0);
            c.outside[v] = NONE;
        }
        if (grid_build(ctx, &c, n)) {
            int simple = triangulate(&c, n);
            status = merge_pieces(ctx, &c, dent, simple, out);
        }
    }
    rad_free(ctx, block);
    rad_free(ctx, c.start);
    rad_free(ctx, c.count);
    rad_free(ctx, c.entries);
    if (!status && max_corners) status = split_large(ctx, c.p, max_corners, dent, out);
    if (status) rad_polygon_pieces_free(ctx, out);
    return status;
}

/* The corners p[0 .. n) projected on the plane across `normal`, or NULL (no memory). */
static double *project(rad_context *ctx, const rad_vec3 *p, size_t n, rad_vec3 normal) {
    double (*xy)[2] = rad_alloc(ctx, n ? n : 1, sizeof *xy);
    if (!xy) return NULL;
    rad_vec3 u, v;
    v3_basis(normal, &u, &v);
    for (size_t k = 0; k < n; ++k) {
        xy[k][0] = v3_dot(p[k], u);
        xy[k][1] = v3_dot(p[k], v);
    }
    return &xy[0][0];
}

rad_status rad_polygon_cut_in_plane(rad_context *ctx, const rad_vec3 *p, size_t n,
                                    rad_vec3 normal, double dent, size_t max_corners, int convex,
                                    rad_polygon_pieces *out) {
    memset(out, 0, sizeof *out);
    double *xy = project(ctx, p, n, normal);
    if (!xy) return RAD_ERROR_NO_MEMORY;
    rad_status status = convex ? rad_polygon_split(ctx, xy, n, max_corners, dent, out)
                               : rad_polygon_cut(ctx, xy, n, dent, max_corners, out);
    rad_free(ctx, xy);
    return status;
}

void rad_polygon_pieces_free(rad_context *ctx, rad_polygon_pieces *pieces) {
    rad_free(ctx, pieces->corners);
    rad_free(ctx, pieces->first);
    memset(pieces, 0, sizeof *pieces);
}
