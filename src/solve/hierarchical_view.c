/* hierarchical_view.c - the hierarchy's own solution view (system/solution_view.h): render,
 * bake and --json read the quadtree leaves directly instead of a uniform element mesh.
 *
 * The leaves are drawn as a rad_mesh built when the hierarchy's nodes change (nodes only grow,
 * so the node count is the generation). Vertices are welded inside a surface and a plane (by
 * position rounded to 1e-7 of the scene's diagonal, and the polygon's normal), so neighbouring
 * leaves of different input polygons share their corners.
 *
 * Smooth leaves without cracks: a leaf next to finer leaves has their corners on its edges
 * (T-junctions). Gouraud shading of such a leaf would interpolate its own corners along that
 * edge while the finer side shows the value at the T-vertex, a visible seam. Each leaf with
 * T-vertices is therefore drawn as a fan of triangles about its centre through every vertex on
 * its boundary ("anchoring", as in Baum et al. 1991, "Improving radiosity solutions through the
 * use of analytically determined form-factors", section 6): the drawn mesh is conforming, the
 * vertex radiosities (area-weighted means of the leaves around each vertex) are shared by both
 * sides of every edge, and the picture is continuous. The fan's triangles all carry their
 * leaf's radiosity. */
#include "solve/hierarchical_view.h"

#include "mesh/mesh.h"
#include "scene/scene.h"
#include "system/solution_view.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define MAX_EDGE_POINTS 64 /* T-vertices looked for along one leaf edge, at most */

typedef struct hier_view {
    rad_system *system;
    rad_hier *hier;
    rad_mesh *mesh;      /* the drawn leaves, built for `built` */
    uint32_t *leaf_node; /* the hierarchy node each drawn polygon shows */
    uint64_t built;      /* the generation the mesh was built for; 0: none */
    rad_hier_setup *setup; /* what the hierarchy was built with (hierarchical.c), owned */
    int restored;          /* loaded from a solution file and not yet taken by a solve */
} hier_view;

/* ---- Welding vertices -------------------------------------------------------------------- */

typedef struct vertex_key {
    int64_t x, y, z;
    uint32_t surface;
    int32_t normal; /* the polygon's normal rounded to 1/64 per component, packed */
} vertex_key;

typedef struct vertex_map {
    vertex_key *keys;
    uint32_t *ids; /* RAD_NO_VERTEX: empty */
    size_t capacity; /* a power of two */
    double step;     /* the rounding of positions */
} vertex_map;

static uint64_t key_hash(const vertex_key *k) {
    uint64_t h = 1469598103934665603ull;
    const int64_t parts[5] = {k->x, k->y, k->z, k->surface, k->normal};
    for (int i = 0; i < 5; ++i) h = (h ^ (uint64_t)parts[i]) * 1099511628211ull, h ^= h >> 29;
    return h;
}

static vertex_key make_key(const vertex_map *map, rad_vec3 p, uint32_t surface, rad_vec3 normal) {
    vertex_key k;
    k.x = llround(p.x / map->step);
    k.y = llround(p.y / map->step);
    k.z = llround(p.z / map->step);
    k.surface = surface;
    int32_t nx = (int32_t)lround(normal.x * 64) + 64, ny = (int32_t)lround(normal.y * 64) + 64;
    int32_t nz = (int32_t)lround(normal.z * 64) + 64;
    k.normal = nx | ny << 8 | nz << 16;
    return k;
}

static int key_equal(const vertex_key *a, const vertex_key *b) {
    return a->x == b->x && a->y == b->y && a->z == b->z && a->surface == b->surface &&
           a->normal == b->normal;
}

/* The slot of `key`: where it is, or the empty slot where it would go. */
static size_t map_slot(const vertex_map *map, const vertex_key *key) {
    size_t mask = map->capacity - 1, i = (size_t)key_hash(key) & mask;
    while (map->ids[i] != RAD_NO_VERTEX && !key_equal(&map->keys[i], key)) i = (i + 1) & mask;
    return i;
}

static uint32_t map_find(const vertex_map *map, const vertex_key *key) {
    return map->ids[map_slot(map, key)];
}

/* ---- Building the drawn mesh ------------------------------------------------------------- */

typedef struct builder {
    rad_context *ctx;
    rad_mesh *mesh;
    uint32_t *leaf_node;
    size_t vertex_capacity, element_capacity;
} builder;

static rad_status add_vertex(builder *b, rad_vec3 p, uint32_t surface, uint32_t *id) {
    rad_mesh *m = b->mesh;
    if (m->vertex_count == b->vertex_capacity) {
        size_t wanted = b->vertex_capacity ? 2 * b->vertex_capacity : 1024;
        rad_vec3 *v = rad_realloc(b->ctx, m->vertices, wanted, sizeof *v);
        if (v) m->vertices = v;
        uint32_t *s = v ? rad_realloc(b->ctx, m->vertex_surface, wanted, sizeof *s) : NULL;
        if (s) m->vertex_surface = s;
        if (!v || !s) return RAD_ERROR_NO_MEMORY;
        b->vertex_capacity = wanted;
    }
    m->vertices[m->vertex_count] = p;
    m->vertex_surface[m->vertex_count] = surface;
    *id = (uint32_t)m->vertex_count++;
    return RAD_OK;
}

static rad_status reserve_elements(builder *b, size_t extra) {
    rad_mesh *m = b->mesh;
    if (m->element_count + extra <= b->element_capacity) return RAD_OK;
    size_t wanted = b->element_capacity ? 2 * b->element_capacity : 1024;
    while (wanted < m->element_count + extra) wanted *= 2;
#define GROW(field)                                                                                \
    do {                                                                                           \
        void *grown = rad_realloc(b->ctx, m->field, wanted, sizeof *m->field);                     \
        if (!grown) return RAD_ERROR_NO_MEMORY;                                                    \
        m->field = grown;                                                                          \
    } while (0)
    GROW(element_vertices);
    GROW(element_normal);
    GROW(element_centroid);
    GROW(element_area);
    GROW(element_polygon);
    GROW(element_surface);
    GROW(element_patch);
#undef GROW
    uint32_t *nodes = rad_realloc(b->ctx, b->leaf_node, wanted, sizeof *nodes);
    if (!nodes) return RAD_ERROR_NO_MEMORY;
    b->leaf_node = nodes;
    b->element_capacity = wanted;
    return RAD_OK;
}

/* Appends a drawn polygon (3 or 4 vertex ids, counter-clockwise) showing `node`. */
static void add_element(builder *b, const uint32_t *ids, int count, uint32_t node,
                        uint32_t polygon, uint32_t surface, rad_vec3 normal) {
    rad_mesh *m = b->mesh;
    size_t e = m->element_count++;
    rad_vec3 c[4] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    rad_vec3 centroid = v3(0, 0, 0);
    for (int k = 0; k < 4; ++k) {
        m->element_vertices[e][k] = k < count ? ids[k] : RAD_NO_VERTEX;
        if (k < count) centroid = v3_add(centroid, c[k] = m->vertices[ids[k]]);
    }
    double area = count == 3
        ? 0.5 * v3_length(v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0])))
        : 0.5 * v3_length(v3_cross(v3_sub(c[2], c[0]), v3_sub(c[3], c[1])));
    m->element_normal[e] = normal;
    m->element_centroid[e] = v3_scale(centroid, 1.0 / count);
    m->element_area[e] = area;
    m->element_polygon[e] = polygon;
    m->element_surface[e] = surface;
    m->element_patch[e] = (uint32_t)e;
    b->leaf_node[e] = node;
}

/* The welded vertices strictly inside the edge a -> b, in order from a: midpoints looked up
 * recursively (a finer neighbour's corners on this edge are its dyadic points). */
static int edge_points(const vertex_map *map, rad_vec3 a, rad_vec3 b, uint32_t surface,
                       rad_vec3 normal, int depth, uint32_t *out, int room) {
    if (depth > 24 || room <= 0) return 0;
    rad_vec3 mid = v3_scale(v3_add(a, b), 0.5);
    vertex_key key = make_key(map, mid, surface, normal);
    uint32_t id = map_find(map, &key);
    if (id == RAD_NO_VERTEX) return 0;
    int n = edge_points(map, a, mid, surface, normal, depth + 1, out, room - 1);
    out[n++] = id;
    return n + edge_points(map, mid, b, surface, normal, depth + 1, out + n, room - n);
}

static int is_leaf(const rad_hier_node *n) {
    return n->corner_count > 0 && n->first_child == RAD_HIER_NO_NODE;
}

static rad_status build_mesh(hier_view *v) {
    rad_context *ctx = v->system->ctx;
    const rad_scene *scene = v->system->geometry;
    size_t node_count;
    const rad_hier_node *nodes = rad_hier_nodes(v->hier, &node_count);
    size_t leaves = 0;
    double total_area = 0;
    for (size_t i = 0; i < node_count; ++i)
        if (is_leaf(&nodes[i])) ++leaves, total_area += nodes[i].area;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double diagonal = v3_length(v3_sub(hi, lo));
    vertex_map map = {0};
    map.step = (diagonal > 0 ? diagonal : 1) * 1e-7;
    map.capacity = 1024;
    while (map.capacity < 8 * leaves) map.capacity *= 2; /* at most 4 corners a leaf: <= 1/2 full */
    map.keys = rad_alloc(ctx, map.capacity, sizeof *map.keys);
    map.ids = rad_alloc(ctx, map.capacity, sizeof *map.ids);
    builder b = {ctx, rad_alloc_zero(ctx, 1, sizeof *b.mesh), NULL, 0, 0};
    uint32_t (*corner_id)[4] = rad_alloc(ctx, leaves ? leaves : 1, sizeof *corner_id);
    rad_status status = RAD_OK;
    if (b.mesh) b.mesh->ctx = ctx; /* before anything can fail: rad_mesh_destroy needs it */
    if (!map.keys || !map.ids || !b.mesh || !corner_id) status = RAD_ERROR_NO_MEMORY;
    if (!status) {
        memset(map.ids, 0xff, map.capacity * sizeof *map.ids);
        status = reserve_elements(&b, leaves);
    }
    /* Every leaf corner, welded. */
    size_t leaf = 0;
    for (size_t i = 0; i < node_count && !status; ++i) {
        const rad_hier_node *n = &nodes[i];
        if (!is_leaf(n)) continue;
        uint32_t surface = scene->polygons[n->polygon].surface;
        rad_vec3 normal = rad_polygon_normal(scene, &scene->polygons[n->polygon]);
        for (int k = 0; k < n->corner_count && !status; ++k) {
            vertex_key key = make_key(&map, n->corner[k], surface, normal);
            size_t slot = map_slot(&map, &key);
            if (map.ids[slot] == RAD_NO_VERTEX) {
                status = add_vertex(&b, n->corner[k], surface, &map.ids[slot]);
                map.keys[slot] = key;
            }
            corner_id[leaf][k] = map.ids[slot];
        }
        ++leaf;
    }
    /* The drawn polygons: a leaf as it is, or a fan about its centre through its T-vertices;
     * and the trees over them (mesh.h), which let ray queries trace a root as one polygon. */
    rad_mesh_tree_node *tree = rad_alloc_zero(ctx, node_count ? node_count : 1, sizeof *tree);
    if (!tree) status = RAD_ERROR_NO_MEMORY;
    leaf = 0;
    for (size_t i = 0; i < node_count && !status; ++i) {
        const rad_hier_node *n = &nodes[i];
        if (n->corner_count > 0 && n->first_child != RAD_HIER_NO_NODE)
            tree[i] = (rad_mesh_tree_node){n->first_child, 0};
        if (!is_leaf(n)) continue;
        tree[i] = (rad_mesh_tree_node){(uint32_t)b.mesh->element_count, 0};
        const rad_polygon *polygon = &scene->polygons[n->polygon];
        rad_vec3 normal = rad_polygon_normal(scene, polygon);
        uint32_t ring[4 * (MAX_EDGE_POINTS + 1)];
        int count = 0, extra = 0;
        for (int k = 0; k < n->corner_count; ++k) {
            ring[count++] = corner_id[leaf][k];
            int found = edge_points(&map, n->corner[k], n->corner[(k + 1) % n->corner_count],
                                    polygon->surface, normal, 0, ring + count, MAX_EDGE_POINTS);
            count += found;
            extra += found;
        }
        if (!extra) {
            status = reserve_elements(&b, 1);
            if (!status)
                add_element(&b, corner_id[leaf], n->corner_count, (uint32_t)i, n->polygon,
                            polygon->surface, normal);
        } else {
            rad_vec3 centre = v3(0, 0, 0);
            for (int k = 0; k < n->corner_count; ++k) centre = v3_add(centre, n->corner[k]);
            uint32_t middle;
            status = add_vertex(&b, v3_scale(centre, 1.0 / n->corner_count), polygon->surface,
                                &middle);
            if (!status) status = reserve_elements(&b, (size_t)count);
            for (int k = 0; k < count && !status; ++k) {
                uint32_t triangle[3] = {middle, ring[k], ring[(k + 1) % count]};
                add_element(&b, triangle, 3, (uint32_t)i, n->polygon, polygon->surface, normal);
            }
        }
        tree[i].count = (uint32_t)(b.mesh->element_count - tree[i].first);
        ++leaf;
    }
    size_t roots = 0;
    for (size_t i = 0; i < node_count; ++i)
        roots += nodes[i].corner_count > 0 && nodes[i].depth == 0;
    rad_mesh_tree *trees = status ? NULL : rad_alloc(ctx, roots ? roots : 1, sizeof *trees);
    if (!status && !trees) status = RAD_ERROR_NO_MEMORY;
    if (!status) {
        b.mesh->trees = trees;
        b.mesh->tree_nodes = tree;
        tree = NULL;
        for (size_t i = 0; i < node_count; ++i) {
            const rad_hier_node *n = &nodes[i];
            if (n->corner_count == 0 || n->depth != 0) continue;
            rad_mesh_tree *t = &trees[b.mesh->tree_count++];
            memcpy(t->corner, n->corner, sizeof t->corner);
            t->corner_count = n->corner_count;
            t->node = (uint32_t)i;
        }
    }
    rad_free(ctx, tree);
    rad_free(ctx, map.keys);
    rad_free(ctx, map.ids);
    rad_free(ctx, corner_id);
    if (!status) {
        rad_mesh *m = b.mesh;
        /* One patch per drawn polygon (nothing shoots from them). */
        m->patch_count = m->element_count;
        m->patch_first = rad_alloc(ctx, m->element_count + 1, sizeof *m->patch_first);
        if (!m->patch_first) status = RAD_ERROR_NO_MEMORY;
        else
            for (size_t e = 0; e <= m->element_count; ++e) m->patch_first[e] = e;
        m->element_size = leaves ? sqrt(total_area / (double)leaves) : 0;
        m->patch_size = m->element_size;
    }
    if (status) {
        rad_mesh_destroy(b.mesh);
        rad_free(ctx, b.leaf_node);
        return status;
    }
    rad_mesh_destroy(v->mesh);
    rad_free(ctx, v->leaf_node);
    v->mesh = b.mesh;
    v->leaf_node = b.leaf_node;
    size_t count;
    rad_hier_nodes(v->hier, &count);
    v->built = (uint64_t)count;
    return RAD_OK;
}

/* ---- The operations ---------------------------------------------------------------------- */

static hier_view *state(const rad_solution_view *view) { return view->state; }

static uint64_t leaf_generation(const rad_solution_view *view) {
    size_t count;
    rad_hier_nodes(state(view)->hier, &count);
    return (uint64_t)count;
}

static const rad_mesh *leaf_leaves(const rad_solution_view *view) {
    hier_view *v = state(view);
    if (v->built != leaf_generation(view)) {
        rad_status status = build_mesh(v);
        if (status) {
            /* Say what failed: the caller only sees NULL (render.c reports this message). */
            char why[RAD_ERROR_MESSAGE_SIZE];
            snprintf(why, sizeof why, "%s", rad_context_error(v->system->ctx));
            rad_fail(v->system->ctx, status, "drawing the hierarchy's leaves (%llu nodes) failed: %s",
                     (unsigned long long)leaf_generation(view), why[0] ? why : rad_status_name(status));
            return NULL;
        }
    }
    return v->mesh;
}

static const rad_hier_node *leaf_node(const rad_solution_view *view, size_t leaf) {
    size_t count;
    const rad_hier_node *nodes = rad_hier_nodes(state(view)->hier, &count);
    return &nodes[state(view)->leaf_node[leaf]];
}

static const rad_material *leaf_material(const rad_solution_view *view, size_t leaf) {
    const rad_scene *scene = state(view)->system->geometry;
    const rad_polygon *polygon = &scene->polygons[leaf_node(view, leaf)->polygon];
    return &scene->materials[scene->surfaces[polygon->surface].material];
}

static void leaf_radiosity(const rad_solution_view *view, size_t leaf, double u, double v,
                           double out[3]) {
    (void)u;
    (void)v;
    memcpy(out, leaf_node(view, leaf)->radiosity, sizeof(double[3]));
}

/* The hierarchy gathers: it keeps no unshot radiosity. */
static int leaf_unshot(const rad_solution_view *view, size_t leaf, double out[3]) {
    (void)view;
    (void)leaf;
    memset(out, 0, sizeof(double[3]));
    return 0;
}

void rad_hier_elements_mean(const rad_system *s, rad_rgb *values, const uint32_t *order,
                            size_t first, size_t last, const rad_vec3 *corners, int count,
                            double out[3]) {
    const rad_vec3 *centroids = s->mesh->element_centroid;
    rad_vec3 normal = v3_cross(v3_sub(corners[1], corners[0]), v3_sub(corners[count - 1], corners[0]));
    rad_vec3 centre = v3(0, 0, 0);
    for (int k = 0; k < count; ++k) centre = v3_add(centre, v3_scale(corners[k], 1.0 / count));
    double sum[3] = {0, 0, 0}, area = 0, nearest = INFINITY;
    size_t best = SIZE_MAX;
    for (size_t i = first; i < last; ++i) {
        size_t e = order ? order[i] : i;
        rad_vec3 x = centroids[e];
        int in = 1;
        for (int k = 0; k < count && in; ++k) {
            rad_vec3 a = corners[k], b = corners[(k + 1) % count];
            in = v3_dot(v3_cross(v3_sub(b, a), v3_sub(x, a)), normal) >= 0;
        }
        double d = v3_length(v3_sub(x, centre));
        if (d < nearest) nearest = d, best = e;
        if (!in) continue;
        for (int c = 0; c < 3; ++c) sum[c] += values[e][c] * s->area[e];
        area += s->area[e];
    }
    for (int c = 0; c < 3; ++c)
        out[c] = area > 0 ? sum[c] / area : best != SIZE_MAX ? values[best][c] : 0;
}

/* The material's emission, plus the specular-first deposit (light through mirrors and glass,
 * src/system/specular_first.c), which the renderer shows as the surface's own emission: the
 * mean of the system's elements under the leaf (the system is the uniform mesh then). */
static void leaf_emission(const rad_solution_view *view, size_t leaf, double out[3]) {
    const rad_material *m = leaf_material(view, leaf);
    for (int c = 0; c < 3; ++c) out[c] = RAD_PI * m->emission[c];
    const rad_system *s = state(view)->system;
    const rad_hier_node *node = leaf_node(view, leaf);
    if (!s->specular_emission || !s->mesh || node->corner_count == 0) return;
    /* The polygon's elements are consecutive. */
    size_t first = 0, n = s->element_count;
    while (first < n && s->mesh->element_polygon[first] != node->polygon) ++first;
    size_t last = first;
    while (last < n && s->mesh->element_polygon[last] == node->polygon) ++last;
    double deposit[3];
    rad_hier_elements_mean(s, s->specular_emission, NULL, first, last, node->corner,
                           node->corner_count, deposit);
    for (int c = 0; c < 3; ++c) out[c] += deposit[c];
}

static void leaf_reflectance(const rad_solution_view *view, size_t leaf, double out[3]) {
    memcpy(out, leaf_material(view, leaf)->reflectance, sizeof(double[3]));
}

static void leaf_ambient(const rad_solution_view *view, double out[3]) {
    (void)view;
    memset(out, 0, sizeof(double[3]));
}

static void leaf_destroy(void *p) {
    hier_view *v = p;
    if (!v) return;
    rad_context *ctx = v->system->ctx;
    rad_mesh_destroy(v->mesh);
    rad_free(ctx, v->leaf_node);
    rad_hier_destroy(v->hier);
    rad_hier_setup_destroy(v->system, v->setup);
    rad_free(ctx, v);
}

static size_t leaf_count(const rad_solution_view *view) {
    return rad_hier_get_stats(state(view)->hier).leaves;
}

/* The leaves of a hierarchy refined at the default link error are coarse: the final gather
 * reads them one bounce later (RAD_LEAVES_COARSE, final_gather.c). Refined to a link error of
 * RAD_HIER_FINE_LINK_ERROR or less they are read where gather rays land (RAD_LEAVES_FINE). */
static const rad_solution_view_ops leaf_view_ops = {
    "hierarchy leaves", leaf_leaves,      leaf_generation, leaf_radiosity, leaf_unshot,
    leaf_emission,      leaf_reflectance, leaf_ambient,    NULL,           leaf_destroy,
    leaf_count,         RAD_LEAVES_COARSE,
};
static const rad_solution_view_ops fine_leaf_view_ops = {
    "hierarchy leaves", leaf_leaves,      leaf_generation, leaf_radiosity, leaf_unshot,
    leaf_emission,      leaf_reflectance, leaf_ambient,    NULL,           leaf_destroy,
    leaf_count,         RAD_LEAVES_FINE,
};

static int is_leaf_view(const rad_solution_view *view) {
    return view->ops == &leaf_view_ops || view->ops == &fine_leaf_view_ops;
}

rad_status rad_hier_view_install(rad_system *system, rad_hier *hier, rad_hier_setup *setup,
                                 int restored) {
    hier_view *v = rad_alloc_zero(system->ctx, 1, sizeof *v);
    if (!v) return RAD_ERROR_NO_MEMORY;
    v->system = system;
    v->hier = hier;
    v->setup = setup;
    v->restored = restored;
    int fine = setup && rad_hier_setup_link_error(setup) <= RAD_HIER_FINE_LINK_ERROR;
    rad_system_set_view(system, fine ? &fine_leaf_view_ops : &leaf_view_ops, v);
    return RAD_OK;
}

rad_hier *rad_hier_view_hierarchy(const rad_system *system) {
    const rad_solution_view *view = rad_system_view(system);
    return is_leaf_view(view) ? state(view)->hier : NULL;
}

rad_hier_setup *rad_hier_view_setup(const rad_system *system) {
    const rad_solution_view *view = rad_system_view(system);
    return is_leaf_view(view) ? state(view)->setup : NULL;
}

int rad_hier_view_take_restored(rad_system *system) {
    const rad_solution_view *view = rad_system_view(system);
    if (!is_leaf_view(view) || !state(view)->restored) return 0;
    state(view)->restored = 0;
    return 1;
}
