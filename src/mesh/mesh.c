/* mesh.c - cutting surfaces into patches and elements (see mesh.h).
 *
 * 0. Cut the polygons at contacts with other surfaces, dropping hidden pieces (contact.c); the
 *    steps below work on the pieces.
 * 1. Weld polygon corners by position within each surface, then split every welded corner
 *    where the faces around it bend by more than the crease angle, so that a box's faces or a
 *    wall and the floor never share a vertex (and never smooth across the corner).
 * 2. Cut polygons of more than four corners into triangles, peeled in rings (ngon.c): every
 *    cell is a triangle or a quad.
 * 3. Decide how many pieces each edge is cut into. A quad's opposite edges must agree, and an
 *    edge shared by two cells is one edge: union-find over edges ties them into classes, and a
 *    class takes the largest count any member asks for. A triangle ties nothing: each of its
 *    sides keeps its own count.
 * 4. Cut each quad into a grid and each triangle to its three side counts (triangle.c), reusing
 *    the vertices along shared edges; patches are blocks of up to k x k elements. */
#include "mesh/mesh.h"

#include "mesh/contact.h"
#include "mesh/ngon.h"
#include "mesh/triangle.h"

#include "scene/scene.h"

#include <math.h>
#include <string.h>

/* ------------------------------------------------------------------------------------------- */
/* An open-addressing hash map from a 64-bit key pair to a 32-bit value.                        */

typedef struct key_map {
    uint64_t *keys_a, *keys_b;
    uint32_t *values;
    size_t capacity; /* power of two */
    size_t count;
} key_map;

static uint64_t mix64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    return x ^ (x >> 33);
}

static rad_status key_map_init(rad_context *ctx, key_map *map, size_t expected) {
    size_t capacity = 64;
    while (capacity < 2 * expected + 1) capacity *= 2;
    map->capacity = capacity;
    map->count = 0;
    map->keys_a = rad_alloc(ctx, capacity, sizeof *map->keys_a);
    map->keys_b = rad_alloc(ctx, capacity, sizeof *map->keys_b);
    map->values = rad_alloc(ctx, capacity, sizeof *map->values);
    if (!map->keys_a || !map->keys_b || !map->values) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < capacity; ++i) map->values[i] = UINT32_MAX;
    return RAD_OK;
}

static void key_map_free(rad_context *ctx, key_map *map) {
    rad_free(ctx, map->keys_a);
    rad_free(ctx, map->keys_b);
    rad_free(ctx, map->values);
}

/* Returns the value for (a, b), inserting `fresh` when absent. */
static uint32_t key_map_get(key_map *map, uint64_t a, uint64_t b, uint32_t fresh, int *inserted) {
    size_t mask = map->capacity - 1;
    size_t slot = (size_t)(mix64(a * 0x9e3779b97f4a7c15ull ^ b)) & mask;
    while (map->values[slot] != UINT32_MAX) {
        if (map->keys_a[slot] == a && map->keys_b[slot] == b) {
            *inserted = 0;
            return map->values[slot];
        }
        slot = (slot + 1) & mask;
    }
    map->keys_a[slot] = a;
    map->keys_b[slot] = b;
    map->values[slot] = fresh;
    map->count++;
    *inserted = 1;
    return fresh;
}

/* ------------------------------------------------------------------------------------------- */

typedef struct cell {
    uint32_t corner[4]; /* welded corner ids; corner[3] == RAD_NO_VERTEX for triangles */
    uint32_t edge[4];
    uint32_t polygon, surface;
    rad_vec3 normal;
} cell;

/* Faces meeting at less than this angle share vertices (smooth); more, and they split. */
#define CREASE_COSINE 0.866 /* 30 degrees */

typedef struct mesher {
    rad_context *ctx;
    const rad_scene *scene;
    /* Welded corners. */
    size_t corner_count;
    rad_vec3 *corner_position;
    uint32_t *corner_surface;
    uint32_t *corner_vertex; /* mesh vertex, once made */
    /* Cells. */
    size_t cell_count;
    cell *cells;
    /* Edges. */
    size_t edge_count;
    uint32_t *edge_a, *edge_b; /* welded corners, a < b */
    uint32_t *edge_parent;     /* union-find */
    uint32_t *edge_cuts;
    uint32_t *edge_first_vertex; /* interior vertices along a -> b */
    size_t skipped;
    rad_contact_cut *contacts; /* the polygons cut at contacts (contact.h) */
} mesher;

static uint32_t find(uint32_t *parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void unite(uint32_t *parent, uint32_t a, uint32_t b) {
    a = find(parent, a);
    b = find(parent, b);
    if (a != b) parent[a < b ? b : a] = a < b ? a : b;
}

static int cell_corners(const cell *c) { return c->corner[3] == RAD_NO_VERTEX ? 3 : 4; }

/* Pieces cut along a shadow boundary that ends inside a face get the cut's end as a corner on
 * the straight edge of their neighbour (contact.c, step 5). Such a piece is cut by chords from
 * each straight-on corner to another corner (the chord most across the edge it lies on, into
 * parts of as few corners as possible) until no part has one, rather than fanned from its
 * centroid: a quad with a T-point becomes a quad and a triangle. `at` indexes ids/points. */
#define FLAT_SPLIT_CORNERS 16

static int flat_at(const rad_vec3 *points, const uint8_t *at, int n, rad_vec3 normal, int k) {
    rad_vec3 a = points[at[(k + n - 1) % n]], b = points[at[k]], c = points[at[(k + 1) % n]];
    rad_vec3 u = v3_sub(b, a), v = v3_sub(c, b);
    return v3_dot(v3_cross(u, v), normal) <= 1e-9 * v3_length(u) * v3_length(v);
}


static void put_cell(mesher *m, const uint32_t *ids, const uint8_t *at, int n, uint32_t polygon,
                     uint32_t surface, rad_vec3 normal) {
    cell c = {{ids[at[0]], ids[at[1]], ids[at[2]], n == 4 ? ids[at[3]] : RAD_NO_VERTEX}, {0}, polygon, surface, normal};
    m->cells[m->cell_count++] = c;
}

/* Do a quad part's opposite sides agree in length within a factor of 2 (its grid ties each
 * side's count to the opposite one's)? */
static int even_quad(const rad_vec3 *points, const uint8_t *at) {
    double side[4];
    for (int k = 0; k < 4; ++k) side[k] = v3_length(v3_sub(points[at[(k + 1) % 4]], points[at[k]]));
    return fmax(side[0], side[2]) <= 2 * fmin(side[0], side[2]) && fmax(side[1], side[3]) <= 2 * fmin(side[1], side[3]);
}

/* A part of split_flat: a quad whose opposite sides differ much in length (a chord across a
 * long strip from a T-point to a far corner) would have its grid give the short sides the long
 * ones' counts, and every cell tied to them too (a 0.2 x 8.8 m wall top took 572 elements):
 * it is put as two triangles, each cut to its own sides' counts, along the shorter diagonal. */
static void put_part(mesher *m, const rad_vec3 *points, const uint32_t *ids, const uint8_t *at, int n,
                     uint32_t polygon, uint32_t surface, rad_vec3 normal) {
    if (n != 4 || even_quad(points, at)) {
        put_cell(m, ids, at, n, polygon, surface, normal);
        return;
    }
    int d = v3_length(v3_sub(points[at[2]], points[at[0]])) <= v3_length(v3_sub(points[at[3]], points[at[1]])) ? 0 : 1;
    uint8_t first[3] = {at[d], at[d + 1], at[d + 2]}, second[3] = {at[d + 2], at[(d + 3) % 4], at[d]};
    put_cell(m, ids, first, 3, polygon, surface, normal);
    put_cell(m, ids, second, 3, polygon, surface, normal);
}

/* A convex part of more than four corners and none straight on, inside split_flat: cut into
 * quads and a triangle from its first corner (few such parts: a straight-on corner's chord
 * leaves at most n - 1 corners). */
static void put_fan(mesher *m, const rad_vec3 *points, const uint32_t *ids, const uint8_t *at, int n,
                    uint32_t polygon, uint32_t surface, rad_vec3 normal) {
    (void)points;
    int k = 1;
    for (; k + 2 < n; k += 2) {
        uint8_t q[4] = {at[0], at[k], at[k + 1], at[k + 2]};
        put_part(m, points, ids, q, 4, polygon, surface, normal);
    }
    if (k + 1 < n) {
        uint8_t t[3] = {at[0], at[k], at[k + 1]};
        put_cell(m, ids, t, 3, polygon, surface, normal);
    }
}

/* Returns 0 when the part has no straight-on corner and more than four (left to ngon_cut). */
static int split_flat(mesher *m, const rad_vec3 *points, const uint32_t *ids, const uint8_t *at, int n,
                      uint32_t polygon, uint32_t surface, rad_vec3 normal, int top) {
    int flat = -1;
    for (int k = 0; k < n && flat < 0; ++k)
        if (flat_at(points, at, n, normal, k)) flat = k;
    if (flat < 0) {
        if (n > 4) return top ? 0 : (put_fan(m, points, ids, at, n, polygon, surface, normal), 1);
        if (top) put_cell(m, ids, at, n, polygon, surface, normal);
        else put_part(m, points, ids, at, n, polygon, surface, normal);
        return 1;
    }
    if (n == 3) return 1; /* no area */
    rad_vec3 edge = v3_normalize(v3_sub(points[at[(flat + 1) % n]], points[at[(flat + n - 1) % n]]));
    int best = -1;
    double best_score = INFINITY;
    for (int d = 2; d <= n - 2; ++d) {
        int j = (flat + d) % n, larger = d + 1 > n - d + 1 ? d + 1 : n - d + 1;
        rad_vec3 chord = v3_normalize(v3_sub(points[at[j]], points[at[flat]]));
        /* Not along the straight edge itself (to another corner on it): that chord would cut
         * nothing off and skip the corners between, the T-junctions this split is for. */
        if (v3_length(v3_cross(chord, edge)) <= 1e-9) continue;
        double across = fabs(v3_dot(chord, edge));
        double score = 10.0 * (larger > 4 ? larger : 4) + across;
        if (score < best_score) best_score = score, best = d;
    }
    if (best < 0) return 1; /* every corner on one line: no area */
    uint8_t a[FLAT_SPLIT_CORNERS], b[FLAT_SPLIT_CORNERS];
    int na = 0, nb = 0;
    for (int k = 0; k <= best; ++k) a[na++] = at[(flat + k) % n];
    for (int k = best; k <= n; ++k) b[nb++] = at[(flat + k) % n];
    split_flat(m, points, ids, a, na, polygon, surface, normal, 0);
    split_flat(m, points, ids, b, nb, polygon, surface, normal, 0);
    return 1;
}

/* Steps 1 and 2: welded corners and cells. */
static rad_status build_cells(mesher *m) {
    const rad_scene *scene = m->scene;
    rad_context *ctx = m->ctx;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double diagonal = v3_length(v3_sub(hi, lo));
    double quantum = diagonal > 0 ? diagonal * 1e-7 : 1e-9;
    double min_area = diagonal * diagonal * 1e-14;

    const rad_contact_cut *cut = m->contacts;
    size_t max_cells = 0, max_corners = cut->point_count + 1, largest = 4;
    for (size_t i = 0; i < cut->piece_count; ++i) {
        size_t n = cut->pieces[i].count;
        max_cells += n <= 4 ? 2 : ngon_max_triangles(n);
        if (n > 4) max_corners += ngon_max_points(n);
        if (n > largest) largest = n;
    }
    m->cells = rad_alloc(ctx, max_cells ? max_cells : 1, sizeof *m->cells);
    m->corner_position = rad_alloc(ctx, max_corners, sizeof(rad_vec3));
    m->corner_surface = rad_alloc(ctx, max_corners, sizeof(uint32_t));
    /* Scratch for one polygon: its corner ids, and its cut (ngon.h). */
    uint32_t *ids = rad_alloc(ctx, largest + ngon_max_points(largest), sizeof *ids);
    rad_vec3 *extra = rad_alloc(ctx, ngon_max_points(largest), sizeof *extra);
    uint32_t (*triangles)[3] = rad_alloc(ctx, ngon_max_triangles(largest), sizeof *triangles);
    uint32_t *ring = rad_alloc(ctx, largest, sizeof *ring);
    rad_status status = RAD_OK;
    key_map weld = {0};
    if (!m->cells || !m->corner_position || !m->corner_surface || !ids || !extra || !triangles ||
        !ring) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }

    status = key_map_init(ctx, &weld, cut->point_count);
    if (status) goto done;
    /* The pieces of the polygons after the contact cuts (contact.c), in polygon order. */
    uint32_t last_polygon = UINT32_MAX;
    int bad = 0;
    for (size_t piece = 0; piece < cut->piece_count; ++piece) {
        uint32_t i = cut->pieces[piece].polygon;
        const rad_polygon *polygon = &scene->polygons[i];
        const rad_vec3 *points = cut->points + cut->pieces[piece].first;
        uint32_t count = cut->pieces[piece].count;
        if (i != last_polygon) {
            last_polygon = i;
            bad = rad_polygon_area(scene, polygon) <= min_area;
            for (uint32_t k = 0; k < polygon->count && !bad; ++k) {
                rad_vec3 p = rad_polygon_vertex(scene, polygon, k);
                if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) bad = 1;
            }
            if (bad) m->skipped++;
        }
        if (bad) continue;
        for (uint32_t k = 0; k < count; ++k) {
            rad_vec3 p = points[k];
            /* Quantised relative to the bounds, so each coordinate fits 32 bits. */
            uint64_t qx = (uint64_t)llround((p.x - lo.x) / quantum);
            uint64_t qy = (uint64_t)llround((p.y - lo.y) / quantum);
            uint64_t qz = (uint64_t)llround((p.z - lo.z) / quantum);
            uint64_t key_a = ((uint64_t)polygon->surface << 32) | (qx & 0xffffffffu);
            uint64_t key_b = (qy << 32) | (qz & 0xffffffffu);
            int inserted;
            ids[k] = key_map_get(&weld, key_a, key_b, (uint32_t)m->corner_count, &inserted);
            if (inserted) {
                m->corner_position[m->corner_count] = p;
                m->corner_surface[m->corner_count] = polygon->surface;
                m->corner_count++;
            }
        }
        /* Anything larger than a quad is cut into triangles, peeled in rings (ngon.c). */
        rad_vec3 normal = rad_polygon_normal(scene, polygon);
        if (count <= FLAT_SPLIT_CORNERS) {
            uint8_t at[FLAT_SPLIT_CORNERS];
            for (uint32_t k = 0; k < count; ++k) at[k] = (uint8_t)k;
            if (count > 3 && split_flat(m, points, ids, at, (int)count, i, polygon->surface, normal, 1)) continue;
        }
        if (count <= 4) {
            cell c = {{ids[0], ids[1], ids[2], count == 4 ? ids[3] : RAD_NO_VERTEX},
                      {0}, (uint32_t)i, polygon->surface, normal};
            m->cells[m->cell_count++] = c;
            continue;
        }
        size_t added = 0;
        size_t made = ngon_cut(points, count, normal, extra, &added, triangles, ring);
        for (size_t k = 0; k < added; ++k) {
            ids[count + k] = (uint32_t)m->corner_count;
            m->corner_position[m->corner_count] = extra[k];
            m->corner_surface[m->corner_count] = polygon->surface;
            m->corner_count++;
        }
        for (size_t t = 0; t < made; ++t) {
            cell c = {{ids[triangles[t][0]], ids[triangles[t][1]], ids[triangles[t][2]], RAD_NO_VERTEX},
                      {0}, (uint32_t)i, polygon->surface, normal};
            m->cells[m->cell_count++] = c;
        }
    }
done:
    key_map_free(ctx, &weld);
    rad_free(ctx, ids);
    rad_free(ctx, extra);
    rad_free(ctx, triangles);
    rad_free(ctx, ring);
    return status;
}

/* Step 1, second half: give each welded corner one id per group of faces around it whose
 * normals agree within the crease angle. */
static rad_status split_creases(mesher *m) {
    rad_context *ctx = m->ctx;
    size_t corners = m->corner_count, uses = 0;
    size_t *start = rad_alloc_zero(ctx, corners + 1, sizeof *start);
    if (!start) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < m->cell_count; ++i)
        for (int k = 0; k < cell_corners(&m->cells[i]); ++k) start[m->cells[i].corner[k] + 1]++, uses++;
    for (size_t c = 0; c < corners; ++c) start[c + 1] += start[c];
    /* use = (cell, corner slot), grouped by corner. */
    uint32_t *use_cell = rad_alloc(ctx, uses + 1, sizeof *use_cell);
    uint8_t *use_slot = rad_alloc(ctx, uses + 1, sizeof *use_slot);
    size_t *fill = rad_alloc(ctx, corners + 1, sizeof *fill);
    rad_vec3 *position = rad_alloc(ctx, uses + 1, sizeof *position);
    uint32_t *surface = rad_alloc(ctx, uses + 1, sizeof *surface);
    uint32_t *label = rad_alloc(ctx, uses + 1, sizeof *label);
    rad_status status = RAD_OK;
    if (!use_cell || !use_slot || !fill || !position || !surface || !label) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    memcpy(fill, start, corners * sizeof *fill);
    for (size_t i = 0; i < m->cell_count; ++i)
        for (int k = 0; k < cell_corners(&m->cells[i]); ++k) {
            size_t at = fill[m->cells[i].corner[k]]++;
            use_cell[at] = (uint32_t)i;
            use_slot[at] = (uint8_t)k;
        }
    /* Around each corner, faces that share an edge through it and bend by less than the crease
     * angle join one group (connected components, so a finely faceted cone stays one smooth
     * vertex however many facets go round it). */
    size_t fresh = 0;
    for (size_t c = 0; c < corners; ++c) {
        size_t first = start[c], count = start[c + 1] - start[c];
        uint32_t *group = label;
        for (size_t i = 0; i < count; ++i) group[first + i] = (uint32_t)i;
        for (size_t i = 0; i < count; ++i) {
            const cell *a = &m->cells[use_cell[first + i]];
            int na = cell_corners(a), ka = use_slot[first + i];
            uint32_t a_prev = a->corner[(ka + na - 1) % na], a_next = a->corner[(ka + 1) % na];
            for (size_t j = i + 1; j < count; ++j) {
                const cell *b = &m->cells[use_cell[first + j]];
                int nb = cell_corners(b), kb = use_slot[first + j];
                uint32_t b_prev = b->corner[(kb + nb - 1) % nb], b_next = b->corner[(kb + 1) % nb];
                int share = a_prev == b_next || a_next == b_prev || a_prev == b_prev ||
                            a_next == b_next;
                if (!share || v3_dot(a->normal, b->normal) < CREASE_COSINE) continue;
                /* Union by relabelling to the smaller label (corners have few faces), so a
                 * group's label is always the index of its first use. */
                uint32_t x = group[first + i], y = group[first + j];
                if (x == y) continue;
                uint32_t from = x > y ? x : y, to = x > y ? y : x;
                for (size_t k = 0; k < count; ++k)
                    if (group[first + k] == from) group[first + k] = to;
            }
        }
        for (size_t i = 0; i < count; ++i) {
            uint32_t label = group[first + i];
            if (label == (uint32_t)i) { /* the first use of its group names a new corner */
                position[fresh] = m->corner_position[c];
                surface[fresh] = m->corner_surface[c];
                group[first + i] = (uint32_t)(fresh++) | 0x80000000u;
            } else {
                /* label < i: that use was already given its corner id */
                group[first + i] = group[first + label];
            }
        }
        for (size_t i = 0; i < count; ++i) {
            cell *owner = &m->cells[use_cell[first + i]];
            owner->corner[use_slot[first + i]] = group[first + i] & 0x7fffffffu;
        }
    }
    rad_free(ctx, m->corner_position);
    rad_free(ctx, m->corner_surface);
    m->corner_position = position;
    m->corner_surface = surface;
    m->corner_count = fresh;
    position = NULL;
    surface = NULL;
done:
    rad_free(ctx, start);
    rad_free(ctx, use_cell);
    rad_free(ctx, use_slot);
    rad_free(ctx, fill);
    rad_free(ctx, position);
    rad_free(ctx, surface);
    rad_free(ctx, label);
    return status;
}

/* Step 3: edges and their classes (they do not depend on the element size). */
static rad_status build_edges(mesher *m) {
    rad_context *ctx = m->ctx;
    size_t max_edges = 4 * m->cell_count + 1;
    m->edge_a = rad_alloc(ctx, max_edges, sizeof(uint32_t));
    m->edge_b = rad_alloc(ctx, max_edges, sizeof(uint32_t));
    m->edge_parent = rad_alloc(ctx, max_edges, sizeof(uint32_t));
    m->edge_cuts = rad_alloc(ctx, max_edges, sizeof(uint32_t));
    m->edge_first_vertex = rad_alloc(ctx, max_edges, sizeof(uint32_t));
    if (!m->edge_a || !m->edge_b || !m->edge_parent || !m->edge_cuts || !m->edge_first_vertex)
        return RAD_ERROR_NO_MEMORY;
    key_map edges;
    rad_status status = key_map_init(ctx, &edges, max_edges);
    if (status) {
        key_map_free(ctx, &edges);
        return status;
    }
    for (size_t i = 0; i < m->cell_count; ++i) {
        cell *c = &m->cells[i];
        int n = cell_corners(c);
        for (int k = 0; k < n; ++k) {
            uint32_t a = c->corner[k], b = c->corner[(k + 1) % n];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            int inserted;
            uint32_t e = key_map_get(&edges, lo, hi, (uint32_t)m->edge_count, &inserted);
            if (inserted) {
                m->edge_a[e] = lo;
                m->edge_b[e] = hi;
                m->edge_parent[e] = e;
                m->edge_count++;
            }
            c->edge[k] = e;
        }
        if (n == 4) {
            unite(m->edge_parent, c->edge[0], c->edge[2]);
            unite(m->edge_parent, c->edge[1], c->edge[3]);
        }
    }
    key_map_free(ctx, &edges);
    for (size_t e = 0; e < m->edge_count; ++e) m->edge_parent[e] = find(m->edge_parent, (uint32_t)e);
    return RAD_OK;
}

static rad_status pair_odd_triangles(mesher *m);

/* Step 3, cut counts for an element size: each edge asks for ceil(length / size) pieces and a
 * class takes the largest count any of its edges asks for; then triangle parities. */
static rad_status cut_edges(mesher *m, double element_size) {
    for (size_t e = 0; e < m->edge_count; ++e) {
        double length = v3_length(v3_sub(m->corner_position[m->edge_a[e]], m->corner_position[m->edge_b[e]]));
        double cuts = ceil(length / element_size - 1e-9);
        m->edge_cuts[e] = (uint32_t)fmax(1.0, fmin(cuts, 1e6));
    }
    for (size_t e = 0; e < m->edge_count; ++e) {
        uint32_t root = m->edge_parent[e];
        if (m->edge_cuts[e] > m->edge_cuts[root]) m->edge_cuts[root] = m->edge_cuts[e];
    }
    for (size_t e = 0; e < m->edge_count; ++e) m->edge_cuts[e] = m->edge_cuts[m->edge_parent[e]];
    return pair_odd_triangles(m);
}

/* Step 3, second half: even side sums for triangles. A triangle whose three counts add up to
 * an even number is cut into three quads (triangle.c); an odd sum needs a triangle element
 * somewhere and a less regular cut. Adding one piece to an edge flips the parity of the
 * triangles on both sides, so adding one along a path of edges between two odd triangles (or
 * from one to the free border of the surface) fixes both ends and leaves the triangles in
 * between as they were: a T-join in the graph of triangles, found here by breadth-first search
 * from each odd triangle to the nearest partner. Only edges no quad uses change (a quad's
 * counts stay as they are), and single-element triangles (1, 1, 1) are left alone. */
static rad_status pair_odd_triangles(mesher *m) {
    rad_context *ctx = m->ctx;
    size_t cells = m->cell_count, edges = m->edge_count;
    /* Per edge: up to two triangle cells (UINT32_MAX: none) and whether it may change. */
    uint32_t (*users)[2] = rad_alloc(ctx, edges + 1, sizeof *users);
    uint8_t *free_edge = rad_alloc_zero(ctx, edges + 1, 1);
    uint32_t *queue = rad_alloc(ctx, cells + 1, sizeof *queue);
    uint32_t *via = rad_alloc(ctx, cells + 1, sizeof *via); /* the edge a cell was reached by */
    uint32_t *seen = rad_alloc_zero(ctx, cells + 1, sizeof *seen);
    rad_status status = RAD_OK;
    if (!users || !free_edge || !queue || !via || !seen) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    for (size_t e = 0; e < edges; ++e) users[e][0] = users[e][1] = UINT32_MAX, free_edge[e] = 1;
    for (size_t i = 0; i < cells; ++i) {
        const cell *c = &m->cells[i];
        int n = cell_corners(c);
        for (int k = 0; k < n; ++k) {
            uint32_t e = c->edge[k];
            if (n == 4) free_edge[e] = 0;
            else if (users[e][0] == UINT32_MAX) users[e][0] = (uint32_t)i;
            else if (users[e][1] == UINT32_MAX) users[e][1] = (uint32_t)i;
            else free_edge[e] = 0; /* three or more faces on one edge */
        }
    }
#define SUM(c) (m->edge_cuts[(c)->edge[0]] + m->edge_cuts[(c)->edge[1]] + m->edge_cuts[(c)->edge[2]])
#define SINGLE(c) (SUM(c) == 3)
#define ODD(c) (cell_corners(c) == 3 && SUM(c) % 2 == 1 && !SINGLE(c))
    uint32_t stamp = 0;
    for (size_t start = 0; start < cells; ++start) {
        if (!ODD(&m->cells[start])) continue;
        /* Breadth-first over triangles through changeable edges, to the nearest odd triangle
         * or changeable border edge. */
        size_t head = 0, tail = 0;
        uint32_t end = UINT32_MAX, border = UINT32_MAX;
        queue[tail++] = (uint32_t)start;
        seen[start] = ++stamp;
        via[start] = UINT32_MAX;
        while (head < tail && end == UINT32_MAX) {
            uint32_t t = queue[head++];
            const cell *c = &m->cells[t];
            /* At the surface's border (an edge with one side only), the triangle's shortest
             * border edge gets the piece: it keeps the counts' triangle inequality. */
            for (int k = 0; k < 3; ++k) {
                uint32_t e = c->edge[k];
                if (free_edge[e] && users[e][1] == UINT32_MAX &&
                    (border == UINT32_MAX || m->edge_cuts[e] < m->edge_cuts[border]))
                    border = e;
            }
            if (border != UINT32_MAX) {
                end = t;
                break;
            }
            for (int k = 0; k < 3 && end == UINT32_MAX; ++k) {
                uint32_t e = c->edge[k];
                if (!free_edge[e]) continue;
                uint32_t other = users[e][0] == t ? users[e][1] : users[e][0];
                if (seen[other] == stamp || SINGLE(&m->cells[other])) continue;
                seen[other] = stamp;
                via[other] = e;
                if (ODD(&m->cells[other])) end = other;
                else queue[tail++] = other;
            }
        }
        if (end == UINT32_MAX) continue; /* stays odd: triangle.c copes */
        if (border != UINT32_MAX) m->edge_cuts[border]++;
        for (uint32_t t = end; via[t] != UINT32_MAX;) {
            uint32_t e = via[t];
            m->edge_cuts[e]++;
            t = users[e][0] == t ? users[e][1] : users[e][0];
        }
    }
#undef SUM
#undef SINGLE
#undef ODD
done:
    rad_free(ctx, users);
    rad_free(ctx, free_edge);
    rad_free(ctx, queue);
    rad_free(ctx, via);
    rad_free(ctx, seen);
    return status;
}

/* The mesh vertex at position `index` (0 .. cuts) along a cell edge walked from corner `from`. */
static uint32_t edge_vertex(const mesher *m, uint32_t edge, uint32_t from, uint32_t index) {
    uint32_t cuts = m->edge_cuts[edge];
    uint32_t along = m->edge_a[edge] == from ? index : cuts - index;
    if (along == 0) return m->corner_vertex[m->edge_a[edge]];
    if (along == cuts) return m->corner_vertex[m->edge_b[edge]];
    return m->edge_first_vertex[edge] + along - 1;
}

static uint32_t add_vertex(rad_mesh *mesh, rad_vec3 p, uint32_t surface) {
    mesh->vertices[mesh->vertex_count] = p;
    mesh->vertex_surface[mesh->vertex_count] = surface;
    return (uint32_t)mesh->vertex_count++;
}

void rad_mesh_put_element(rad_mesh *mesh, uint32_t polygon, uint32_t surface, uint32_t a,
                          uint32_t b, uint32_t d, uint32_t e) {
    size_t i = mesh->element_count++;
    mesh->element_vertices[i][0] = a;
    mesh->element_vertices[i][1] = b;
    mesh->element_vertices[i][2] = d;
    mesh->element_vertices[i][3] = e;
    int n = e == RAD_NO_VERTEX ? 3 : 4;
    rad_vec3 normal = v3(0, 0, 0), centroid = v3(0, 0, 0);
    for (int k = 0; k < n; ++k) {
        rad_vec3 p = mesh->vertices[mesh->element_vertices[i][k]];
        rad_vec3 q = mesh->vertices[mesh->element_vertices[i][(k + 1) % n]];
        normal = v3_add(normal, v3_cross(p, q));
        centroid = v3_add(centroid, p);
    }
    mesh->element_area[i] = 0.5 * v3_length(normal);
    mesh->element_normal[i] = v3_normalize(normal);
    mesh->element_centroid[i] = v3_scale(centroid, 1.0 / n);
    mesh->element_polygon[i] = polygon;
    mesh->element_surface[i] = surface;
    mesh->element_patch[i] = (uint32_t)mesh->patch_count;
}

static void add_element(rad_mesh *mesh, const cell *c, uint32_t a, uint32_t b, uint32_t d,
                        uint32_t e) {
    rad_mesh_put_element(mesh, c->polygon, c->surface, a, b, d, e);
}

/* Step 4 for a quad: an nu x nv grid, k x k blocks as patches. */
static void cut_quad(mesher *m, rad_mesh *mesh, const cell *c, uint32_t k, uint32_t *grid) {
    uint32_t nu = m->edge_cuts[c->edge[0]], nv = m->edge_cuts[c->edge[1]];
    const uint32_t *q = c->corner;
    rad_vec3 p0 = m->corner_position[q[0]], p1 = m->corner_position[q[1]],
             p2 = m->corner_position[q[2]], p3 = m->corner_position[q[3]];
#define GRID(i, j) grid[(size_t)(j) * (nu + 1) + (i)]
    for (uint32_t j = 0; j <= nv; ++j)
        for (uint32_t i = 0; i <= nu; ++i) {
            uint32_t v;
            if (j == 0) v = edge_vertex(m, c->edge[0], q[0], i);
            else if (i == nu) v = edge_vertex(m, c->edge[1], q[1], j);
            else if (j == nv) v = edge_vertex(m, c->edge[2], q[2], nu - i);
            else if (i == 0) v = edge_vertex(m, c->edge[3], q[3], nv - j);
            else {
                double u = (double)i / nu, t = (double)j / nv;
                rad_vec3 p = v3_add(v3_add(v3_scale(p0, (1 - u) * (1 - t)), v3_scale(p1, u * (1 - t))),
                                    v3_add(v3_scale(p2, u * t), v3_scale(p3, (1 - u) * t)));
                v = add_vertex(mesh, p, c->surface);
            }
            GRID(i, j) = v;
        }
    if (mesh->grids)
        mesh->grids[mesh->grid_count++] =
            (rad_mesh_grid){{GRID(0, 0), GRID(nu, 0), GRID(nu, nv), GRID(0, nv)},
                            (uint32_t)mesh->element_count, nu, nv, k};
    for (uint32_t pj = 0; pj < nv; pj += k)
        for (uint32_t pi = 0; pi < nu; pi += k) {
            for (uint32_t j = pj; j < pj + k && j < nv; ++j)
                for (uint32_t i = pi; i < pi + k && i < nu; ++i)
                    add_element(mesh, c, GRID(i, j), GRID(i + 1, j), GRID(i + 1, j + 1),
                                GRID(i, j + 1));
            mesh->patch_first[++mesh->patch_count] = mesh->element_count;
        }
#undef GRID
}

/* Step 4 for a triangle: cut to its three side counts (triangle.c). With out->mesh NULL, only
 * counts what it would make. `ids` holds room for the three sides' vertex ids. */
static void cut_triangle(mesher *m, tri_out *out, const cell *c, uint32_t *ids) {
    rad_vec3 p[3];
    tri_side sides[3];
    for (int s = 0; s < 3; ++s) {
        uint32_t edge = c->edge[s], count = m->edge_cuts[edge];
        p[s] = m->corner_position[c->corner[s]];
        sides[s] = (tri_side){NULL, count, 0};
        if (out->mesh) {
            for (uint32_t i = 0; i <= count; ++i) ids[i] = edge_vertex(m, edge, c->corner[s], i);
            sides[s].ids = ids;
            ids += count + 1;
        }
    }
    out->polygon = c->polygon;
    out->surface = c->surface;
    tri_cut(out, p, sides);
}

static void mesher_free(mesher *m) {
    rad_context *ctx = m->ctx;
    rad_free(ctx, m->corner_position);
    rad_free(ctx, m->corner_surface);
    rad_free(ctx, m->corner_vertex);
    rad_free(ctx, m->cells);
    rad_free(ctx, m->edge_a);
    rad_free(ctx, m->edge_b);
    rad_free(ctx, m->edge_parent);
    rad_free(ctx, m->edge_cuts);
    rad_free(ctx, m->edge_first_vertex);
    rad_contact_cut_destroy(ctx, m->contacts);
}

rad_mesh *rad_mesh_alloc(rad_context *ctx, size_t vertices, size_t elements) {
    rad_mesh *mesh = rad_alloc_zero(ctx, 1, sizeof *mesh);
    if (!mesh) return NULL;
    size_t nv = vertices ? vertices : 1, ne = elements ? elements : 1;
    mesh->ctx = ctx;
    mesh->vertices = rad_alloc(ctx, nv, sizeof *mesh->vertices);
    mesh->vertex_surface = rad_alloc_zero(ctx, nv, sizeof *mesh->vertex_surface);
    mesh->element_vertices = rad_alloc(ctx, ne, sizeof *mesh->element_vertices);
    mesh->element_normal = rad_alloc(ctx, ne, sizeof *mesh->element_normal);
    mesh->element_centroid = rad_alloc(ctx, ne, sizeof *mesh->element_centroid);
    mesh->element_area = rad_alloc(ctx, ne, sizeof *mesh->element_area);
    mesh->element_polygon = rad_alloc(ctx, ne, sizeof *mesh->element_polygon);
    mesh->element_surface = rad_alloc(ctx, ne, sizeof *mesh->element_surface);
    mesh->element_patch = rad_alloc(ctx, ne, sizeof *mesh->element_patch);
    mesh->patch_first = rad_alloc(ctx, ne + 1, sizeof *mesh->patch_first);
    if (!mesh->vertices || !mesh->vertex_surface || !mesh->element_vertices ||
        !mesh->element_normal || !mesh->element_centroid || !mesh->element_area ||
        !mesh->element_polygon || !mesh->element_surface || !mesh->element_patch ||
        !mesh->patch_first) {
        rad_mesh_destroy(mesh);
        return NULL;
    }
    return mesh;
}

void rad_mesh_destroy(rad_mesh *mesh) {
    if (!mesh) return;
    rad_context *ctx = mesh->ctx;
    rad_free(ctx, mesh->vertices);
    rad_free(ctx, mesh->vertex_surface);
    rad_free(ctx, mesh->element_vertices);
    rad_free(ctx, mesh->element_normal);
    rad_free(ctx, mesh->element_centroid);
    rad_free(ctx, mesh->element_area);
    rad_free(ctx, mesh->element_polygon);
    rad_free(ctx, mesh->element_surface);
    rad_free(ctx, mesh->element_patch);
    rad_free(ctx, mesh->patch_first);
    rad_free(ctx, mesh->grids);
    rad_free(ctx, mesh->trees);
    rad_free(ctx, mesh->tree_nodes);
    rad_free(ctx, mesh);
}

static double scene_area(const rad_scene *scene) {
    double area = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        double a = rad_polygon_area(scene, &scene->polygons[i]);
        if (isfinite(a)) area += a;
    }
    return area;
}

/* What the current cuts will make, counted before anything is allocated. */
typedef struct mesh_count {
    double vertices, elements;
    double grid; /* scratch vertex ids for the largest cell */
    uint32_t largest_side; /* the largest count on a triangle's side */
    double triangle_grids; /* quad grids inside triangles (triangle.c) */
    double quad_elements;
    double quad_area; /* the quads' area over the element size squared */
    double triangle_floor; /* the sum of max(1, area / element size^2) over triangles */
    double triangle_area; /* the triangles' area over the element size squared */
} mesh_count;

static rad_status check_budget(rad_context *ctx, double vertices, double elements) {
    rad_status status = rad_check_budget(ctx, vertices * 40 + elements * 120, "the mesh");
    if (!status && elements > 2e9)
        status = rad_fail(ctx, RAD_ERROR_MEMORY_BUDGET, "%.0f elements are too many", elements);
    return status;
}

/* Counts what the grids and the triangle cuts will make; triangles by running their cut
 * without output. First what the quads make and a floor for the triangles (no element is
 * larger than a square of the element size), so that a mesh far too large is refused before
 * the triangles are counted. */
static rad_status count_mesh(mesher *m, double element_size, uint32_t k, mesh_count *out) {
    mesh_count c = {0};
    c.vertices = (double)m->corner_count;
    for (size_t e = 0; e < m->edge_count; ++e) c.vertices += m->edge_cuts[e] - 1.0;
    for (size_t i = 0; i < m->cell_count; ++i) {
        const cell *q = &m->cells[i];
        double nu = m->edge_cuts[q->edge[0]], nv = m->edge_cuts[q->edge[1]];
        if (cell_corners(q) == 4) {
            c.vertices += (nu - 1) * (nv - 1);
            c.quad_elements += nu * nv;
            rad_vec3 p0 = m->corner_position[q->corner[0]], p1 = m->corner_position[q->corner[1]],
                     p2 = m->corner_position[q->corner[2]], p3 = m->corner_position[q->corner[3]];
            c.quad_area += 0.5 * v3_length(v3_cross(v3_sub(p2, p0), v3_sub(p3, p1))) /
                           (element_size * element_size);
            c.grid = fmax(c.grid, (nu + 1) * (nv + 1));
        } else {
            rad_vec3 a = m->corner_position[q->corner[0]], b = m->corner_position[q->corner[1]],
                     d = m->corner_position[q->corner[2]];
            double area = 0.5 * v3_length(v3_cross(v3_sub(b, a), v3_sub(d, a)));
            c.triangle_area += area / (element_size * element_size);
            c.triangle_floor += fmax(1.0, area / (element_size * element_size));
            for (int s = 0; s < 3; ++s)
                if (m->edge_cuts[q->edge[s]] > c.largest_side) c.largest_side = m->edge_cuts[q->edge[s]];
        }
    }
    rad_status status = check_budget(m->ctx, c.vertices, c.quad_elements + c.triangle_floor);
    if (status) return status;
    tri_out counting = {0};
    counting.k = k;
    counting.element_size = element_size;
    for (size_t i = 0; i < m->cell_count; ++i)
        if (cell_corners(&m->cells[i]) == 3) cut_triangle(m, &counting, &m->cells[i], NULL);
    c.vertices += (double)counting.vertices;
    c.elements = c.quad_elements + (double)counting.elements;
    c.triangle_grids = (double)counting.grids;
    if (c.largest_side)
        c.grid = fmax(c.grid, 3.0 * (c.largest_side + 1) + (double)tri_scratch_size(c.largest_side));
    *out = c;
    return RAD_OK;
}

/* The patch size follows the element size unless given; an element is no larger than a
 * patch. Returns k, the patch edge in elements. */
static uint32_t set_sizes(rad_mesh_options *o, double element_size, double patch_option) {
    o->element_size = element_size;
    o->patch_size = patch_option > 0 ? patch_option : 2 * element_size;
    if (o->patch_size < o->element_size) o->element_size = o->patch_size;
    return (uint32_t)fmax(1.0, floor(o->patch_size / o->element_size + 0.5));
}

/* Re-aiming --elements N (docs/meshing.md, "What --elements N gives"). The first element size
 * is that of a square of 1/N of the area. Quads then make about N (more by rounding their edges
 * up, which stays as it is unless it exceeds QUAD_ROUNDING times their area); a triangle makes more and smaller elements than its area asks for
 * (its three quads' grids). The target is what the quads make at the first size plus the
 * triangles' area over that size squared (N itself for a scene of triangles only), and at
 * least one element per cell: a scene of more polygons than N is aimed at that floor. A scene
 * without triangles whose quads round within QUAD_ROUNDING is not re-aimed. The size is scaled until the count is within
 * AIM_TOLERANCE of the target, by a secant step on log count against log size (slope -2 to
 * start: a count that follows the area), kept between the sizes known to be too fine and too
 * coarse; it stops after AIM_STEPS recounts, when those two are within AIM_GAP of each other
 * (the count jumps over the target there: triangles of one size change their cut together),
 * or when an explicit patch size caps the element size. The closest count found wins. */
#define AIM_TOLERANCE 0.05
#define AIM_STEPS 6
#define AIM_GAP 1.02
#define QUAD_ROUNDING 1.1

static rad_status aim_element_count(mesher *m, double patch_option, rad_mesh_options *o,
                                    uint32_t *k, mesh_count *count) {
    /* The quads' rounding is kept unless it overshoots their area by more than QUAD_ROUNDING
     * (narrow quads tied in long chains: the sides of a cylinder, the columns of a sphere). */
    double quads = fmin(count->quad_elements, QUAD_ROUNDING * count->quad_area);
    if (count->elements == count->quad_elements && quads == count->quad_elements) return RAD_OK;
    double target = fmax(quads + count->triangle_area, (double)m->cell_count);
    double best_size = o->element_size, best_off = fabs(count->elements - target);
    double too_fine = 0, too_coarse = INFINITY, last_size = 0, last_elements = 0;
    rad_status status = RAD_OK;
    for (int step = 0; step < AIM_STEPS && best_off > AIM_TOLERANCE * target; ++step) {
        double size = o->element_size, elements = count->elements;
        if (elements > target) too_fine = fmax(too_fine, size);
        else too_coarse = fmin(too_coarse, size);
        double slope = -2;
        if (last_size > 0 && last_elements != elements)
            slope = fmin(-0.25, fmax(-4.0, log(elements / last_elements) / log(size / last_size)));
        double next = size * exp(log(target / elements) / slope);
        if (!(next > too_fine && next < too_coarse)) next = sqrt(too_fine * too_coarse);
        if (too_coarse < AIM_GAP * too_fine) break; /* the target falls in a jump of the count */
        if (patch_option > 0 && next >= patch_option) {
            if (size >= patch_option) break; /* as coarse as the patches allow */
            next = patch_option;
        }
        last_size = size;
        last_elements = elements;
        *k = set_sizes(o, next, patch_option);
        status = cut_edges(m, o->element_size);
        if (!status) status = count_mesh(m, o->element_size, *k, count);
        if (status) return status;
        double off = fabs(count->elements - target);
        if (off < best_off) best_off = off, best_size = o->element_size;
    }
    if (o->element_size != best_size) {
        *k = set_sizes(o, best_size, patch_option);
        status = cut_edges(m, o->element_size);
        if (!status) status = count_mesh(m, o->element_size, *k, count);
    }
    return status;
}

rad_status rad_mesh_create(rad_context *ctx, const rad_scene *scene,
                           const rad_mesh_options *options, rad_mesh **out) {
    *out = NULL;
    rad_mesh_options o = options ? *options : (rad_mesh_options){0};
    if (o.element_size < 0 || o.patch_size < 0 || !isfinite(o.element_size) || !isfinite(o.patch_size))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "patch and element sizes must be positive");
    if (scene->polygon_count == 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: the scene has no faces", scene->source);
    double total_area = scene_area(scene);
    if (!(total_area > 0))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: the scene has no area", scene->source);

    /* Sizes: an element count gives the edge of a square of that share of the area, then
     * re-aimed below where triangles make more elements than that. */
    int aimed = o.element_size == 0 && !(o.patch_size > 0 && o.elements == 0);
    double patch_option = o.patch_size;
    if (o.element_size == 0) {
        if (!aimed) o.element_size = o.patch_size / 2;
        else {
            size_t wanted = o.elements ? o.elements : RAD_MESH_DEFAULT_ELEMENTS;
            o.element_size = sqrt(total_area / (double)wanted);
        }
    }
    uint32_t k = set_sizes(&o, o.element_size, patch_option);

    mesher m = {0};
    m.ctx = ctx;
    m.scene = scene;
    mesh_count count = {0};
    rad_contact_options cuts = {.shadows = o.shadow_boundaries, .element_size = o.element_size,
                                .t_points = 1};
    rad_status status = rad_contact_cut_create_with(ctx, scene, &cuts, &m.contacts);
    if (!status) status = build_cells(&m);
    if (!status && m.cell_count == 0)
        status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                          "%s: every face is degenerate (zero area or not finite)", scene->source);
    if (!status) status = split_creases(&m);
    if (!status) status = build_edges(&m);
    if (!status && m.skipped) rad_warn(ctx, "%s: skipped %zu degenerate faces (zero area or not finite)",
                                       scene->source, m.skipped);
    if (!status) status = cut_edges(&m, o.element_size);
    if (!status) status = count_mesh(&m, o.element_size, k, &count);
    if (!status && aimed) status = aim_element_count(&m, patch_option, &o, &k, &count);
    /* The budget, on what will be allocated. */
    double vertices = count.vertices, elements = count.elements, grid = count.grid;
    uint32_t largest_side = count.largest_side;
    if (!status) status = check_budget(ctx, vertices, elements);
    if (status) {
        mesher_free(&m);
        return status;
    }
    size_t ne = (size_t)elements;
    rad_mesh *mesh = rad_mesh_alloc(ctx, (size_t)vertices, ne);
    uint32_t *scratch = rad_alloc(ctx, (size_t)grid, sizeof *scratch);
    m.corner_vertex = rad_alloc(ctx, m.corner_count + 1, sizeof *m.corner_vertex);
    size_t quads = (size_t)count.triangle_grids;
    for (size_t i = 0; i < m.cell_count; ++i) quads += cell_corners(&m.cells[i]) == 4;
    if (mesh && quads) mesh->grids = rad_alloc(ctx, quads, sizeof *mesh->grids);
    if (!mesh || !scratch || !m.corner_vertex || (quads && !mesh->grids)) {
        rad_free(ctx, scratch);
        rad_mesh_destroy(mesh);
        mesher_free(&m);
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for a mesh of %zu elements", ne);
    }
    /* Corners, then the vertices inside each edge, then each cell's grid. */
    for (size_t i = 0; i < m.corner_count; ++i)
        m.corner_vertex[i] = add_vertex(mesh, m.corner_position[i], m.corner_surface[i]);
    for (size_t e = 0; e < m.edge_count; ++e) {
        m.edge_first_vertex[e] = (uint32_t)mesh->vertex_count;
        rad_vec3 a = m.corner_position[m.edge_a[e]], b = m.corner_position[m.edge_b[e]];
        for (uint32_t t = 1; t < m.edge_cuts[e]; ++t)
            add_vertex(mesh, v3_lerp(a, b, (double)t / m.edge_cuts[e]), m.corner_surface[m.edge_a[e]]);
    }
    mesh->patch_first[0] = 0;
    tri_out output = {0};
    output.mesh = mesh;
    output.k = k;
    output.element_size = o.element_size;
    output.grid_room = (size_t)count.triangle_grids;
    if (largest_side) {
        output.scratch = scratch + 3 * ((size_t)largest_side + 1);
        output.scratch_size = tri_scratch_size(largest_side);
    }
    for (size_t i = 0; i < m.cell_count; ++i) {
        if (cell_corners(&m.cells[i]) == 4) cut_quad(&m, mesh, &m.cells[i], k, scratch);
        else cut_triangle(&m, &output, &m.cells[i], scratch);
    }
    mesh->element_size = o.element_size;
    mesh->patch_size = o.patch_size;
    rad_free(ctx, scratch);
    mesher_free(&m);
    *out = mesh;
    return RAD_OK;
}
