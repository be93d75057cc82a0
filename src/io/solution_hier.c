/* solution_hier.c - solution files of the hierarchical solver (version 3 of the solution format;
 * docs/formats.md, "Hierarchy solution files"): everything needed to go on exactly where a
 * hierarchical solve stopped, or to draw it again.
 *
 * Layout, little-endian throughout (a header of 160 bytes, then the sections in this order):
 *   0   8  magic "RADSOLN\n"            8   4  version (3)
 *   12  4  solver that wrote it (rad_solver_kind's file code: hierarchical)
 *   16  8  steps done (summed over resumed runs)
 *   24  8  scene fingerprint (as version 1's: surface names and materials)
 *   32  8  element fingerprint (the system's elements, when the nodes read light from them:
 *          scenes with mirrors or glass; else 0)
 *   40  8  hierarchy fingerprint (rad_hier_fingerprint: roots, clusters, their light, threshold)
 *   48  8  link error, float64 (as the solve used it)
 *   56  4  flags: 1 importance, 2 node light, 4 second specular pass's light per element,
 *          8 refinement stopped at the memory budget, 16 the last solve was interrupted (the
 *          next step finishes it before refining), 32 the last solve stopped at the loose
 *          tolerance (it refined much; the step that refines nothing asks the oracle again),
 *          64 the refinement was interrupted between two passes (the links are in the order
 *          it kept them, not grouped by increasing receiver; the next step goes on with it),
 *          128 the last solve's importance rounds were interrupted after the light's converged
 *   60  4  gathering rounds of the last solve
 *   64  8  node count          72  8  root count        80  8  split count
 *   88  8  link count          96  8  receiver runs     104 8  importance view hits
 *   112 8  element count       120 8  links refined by the last step
 *   128 8  largest remaining error over the threshold, float64
 *   136 8  importance mean     144 8  a hit's share of the image    152 8  seen share (float64)
 *   160    splits, in the order they were made: node, first child (uint32 each)
 *          nodes: radiosity[3] float64; with flag 2 light[3] float64 and spread float32; with
 *          flag 1 importance float64
 *          roots: per signed axis (+x, -x, +y, -y, +z, -z) exposure rays, rays seen (uint32
 *          each)
 *          links, grouped by receiver in their order: receiver, count (uint32), then per link
 *          source (uint32), form factor and error bound (float32)
 *          with flag 1, hits: polygon (uint32), point[3] float64
 *          with flag 4, per element: the second specular pass's light[3] float64
 *          with flag 64: how many of the links, first, the refinement had passed (uint64)
 *   end 8  FNV-1a 64 of every byte before it
 * Written through a temporary renamed into place (core/atomic_file.h), checksummed on the way.
 * A load checks the whole file, rebuilds the hierarchy aside (rad_hier_create, the splits
 * replayed in order so the nodes get their numbers, then the values) and only then gives it to
 * the system: a refused file changes nothing. */
#include "io/solution.h"

#include "core/atomic_file.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "scene/scene.h"
#include "solve/hierarchical_view.h"
#include "solve/solver.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HEADER 160u
#define SPLIT_BYTES 8u
#define NODE_BYTES 24u
#define NODE_LIGHT_BYTES 28u
#define NODE_IMPORTANCE_BYTES 8u
#define ROOT_BYTES 48u
#define RUN_BYTES 8u
#define LINK_BYTES 12u
#define HIT_BYTES 28u
#define ELEMENT_BYTES 24u

enum { FLAG_IMPORTANCE = 1, FLAG_LIGHT = 2, FLAG_REFLECTION = 4, FLAG_BUDGET = 8, FLAG_UNFINISHED = 16,
       FLAG_LOOSE = 32, FLAG_REFINING = 64, FLAG_IMPORTANCE_UNFINISHED = 128, FLAGS_KNOWN = 255 };

static uint64_t hash_f64(uint64_t h, double v) {
    unsigned char b[8];
    rad_le_put_f64(b, v == 0 ? 0.0 : v); /* -0 and +0 alike */
    return rad_fnv1a(h, b, 8);
}

/* The scene: its surfaces' names and materials (the geometry is the hierarchy's fingerprint).
 * Read from the scene, not the system's elements, whose emission holds the second specular
 * pass's light once it is added. */
static uint64_t scene_fingerprint(const rad_scene *scene) {
    uint64_t h = hash_f64(RAD_FNV1A_START, (double)scene->surface_count);
    for (size_t i = 0; i < scene->surface_count; ++i) {
        const rad_surface_def *surface = &scene->surfaces[i];
        const rad_material *m = &scene->materials[surface->material];
        const char *name = surface->name ? surface->name : "";
        h = rad_fnv1a(h, name, strlen(name) + 1);
        for (int c = 0; c < 3; ++c)
            h = hash_f64(hash_f64(hash_f64(h, m->reflectance[c]), m->emission[c]), m->specular[c]);
        h = hash_f64(hash_f64(hash_f64(h, (double)m->kind), m->roughness), m->ior);
        h = hash_f64(hash_f64(h, m->texture != NULL), m->two_sided);
    }
    return h;
}

/* The system's elements as the nodes' light reads them (only with mirrors or glass, whose
 * deposits live on the elements). */
static uint64_t element_fingerprint(const rad_system *s) {
    if (!s->specular_emission) return 0;
    uint64_t h = RAD_FNV1A_START;
    unsigned char b[8];
    rad_le_put_u64(b, s->element_count);
    h = rad_fnv1a(h, b, 8);
    for (size_t e = 0; e < s->element_count; ++e) {
        double values[7] = {s->area[e], s->specular_emission[e][0], s->specular_emission[e][1],
                            s->specular_emission[e][2], s->mesh->element_centroid[e].x,
                            s->mesh->element_centroid[e].y, s->mesh->element_centroid[e].z};
        rad_le_put_u64(b, s->mesh->element_polygon[e]);
        h = rad_fnv1a(h, b, 8);
        for (int k = 0; k < 7; ++k) {
            rad_le_put_f64(b, values[k] == 0 ? 0.0 : values[k]);
            h = rad_fnv1a(h, b, 8);
        }
    }
    return h ? h : 1;
}

/* ---- Writing ----------------------------------------------------------------------------- */

/* Bytes to the file through a buffer, summed into the checksum on the way. */
typedef struct writer {
    FILE *file;
    uint64_t checksum;
    size_t used;
    int failed;
    unsigned char buffer[1 << 16];
} writer;

static void flush(writer *w) {
    if (w->used && fwrite(w->buffer, 1, w->used, w->file) != w->used) w->failed = 1;
    w->checksum = rad_fnv1a(w->checksum, w->buffer, w->used);
    w->used = 0;
}

static void put(writer *w, const unsigned char *bytes, size_t count) {
    if (w->used + count > sizeof w->buffer) flush(w);
    memcpy(w->buffer + w->used, bytes, count);
    w->used += count;
}

static void put_u32(writer *w, uint32_t v) {
    unsigned char b[4];
    rad_le_put_u32(b, v);
    put(w, b, 4);
}

static void put_f64(writer *w, double v) {
    unsigned char b[8];
    rad_le_put_f64(b, v);
    put(w, b, 8);
}

static void put_f32(writer *w, float v) {
    uint32_t bits;
    memcpy(&bits, &v, sizeof bits);
    put_u32(w, bits);
}

/* The splits in the order they were made: every node past the roots and clusters is one of
 * four children made together, so block k's parent is the k-th split. */
static rad_status split_order(rad_context *ctx, const rad_hier_node *nodes, size_t node_count,
                              size_t base, uint32_t **out, size_t *count) {
    size_t blocks = node_count > base ? (node_count - base) / 4 : 0;
    uint32_t *parent = rad_alloc(ctx, blocks ? blocks : 1, sizeof *parent);
    if (!parent) return RAD_ERROR_NO_MEMORY;
    for (size_t k = 0; k < blocks; ++k) parent[k] = RAD_HIER_NO_NODE;
    for (size_t i = 0; i < node_count; ++i) {
        const rad_hier_node *n = &nodes[i];
        if (n->corner_count == 0 || n->first_child == RAD_HIER_NO_NODE) continue;
        size_t k = (n->first_child - base) / 4;
        if (n->first_child < base || k >= blocks) continue; /* cannot be: children follow */
        parent[k] = (uint32_t)i;
    }
    *out = parent;
    *count = blocks;
    return RAD_OK;
}

rad_status rad_solution_hier_save(rad_system *s, const char *path, const rad_solution_info *info) {
    rad_context *ctx = s->ctx;
    rad_hier *hier = rad_hier_view_hierarchy(s);
    rad_hier_setup *setup = rad_hier_view_setup(s);
    if (!hier || !setup) return RAD_ERROR_INVALID_ARGUMENT;
    rad_status status = RAD_OK;
    size_t node_count, link_count;
    const rad_hier_node *nodes = rad_hier_nodes(hier, &node_count);
    const rad_hier_link *links = rad_hier_links(hier, &link_count);
    rad_hier_stats stats = rad_hier_get_stats(hier);
    size_t base = stats.roots + stats.clusters;
    uint32_t *parent = NULL;
    size_t splits = 0;
    if ((status = split_order(ctx, nodes, node_count, base, &parent, &splits))) return status;
    size_t runs = 0;
    for (size_t l = 0; l < link_count; ++l) runs += l == 0 || links[l].receiver != links[l - 1].receiver;
    const uint32_t *hit_polygon;
    const rad_vec3 *hit_point;
    double hit_share;
    size_t hits = rad_hier_view_hits(hier, &hit_polygon, &hit_point, &hit_share);
    uint32_t flags = (setup && rad_hier_setup_importance(setup) ? FLAG_IMPORTANCE : 0) |
                     (rad_hier_has_light(hier) ? FLAG_LIGHT : 0) |
                     (s->specular_reflection ? FLAG_REFLECTION : 0) |
                     (stats.budget_reached ? FLAG_BUDGET : 0) |
                     (rad_hier_setup_unfinished(setup) ? FLAG_UNFINISHED : 0) |
                     (setup && rad_hier_setup_loose(setup) ? FLAG_LOOSE : 0);
    size_t refine_kept = 0;
    if (rad_hier_refining(hier, &refine_kept)) flags |= FLAG_REFINING;
    if (rad_hier_importance_unfinished(hier)) flags |= FLAG_IMPORTANCE_UNFINISHED;
    if (!(flags & FLAG_IMPORTANCE)) hits = 0;

    unsigned char header[HEADER];
    memset(header, 0, sizeof header);
    memcpy(header, RAD_SOLUTION_MAGIC, 8);
    rad_le_put_u32(header + 8, RAD_SOLUTION_HIER_VERSION);
    rad_le_put_u32(header + 12, rad_solver_file_code(RAD_SOLVER_HIERARCHICAL));
    rad_le_put_u64(header + 16, info && info->steps > 0 ? (uint64_t)info->steps : 0u);
    rad_le_put_u64(header + 24, scene_fingerprint(s->geometry));
    rad_le_put_u64(header + 32, element_fingerprint(s));
    rad_le_put_u64(header + 40, rad_hier_fingerprint(hier));
    rad_le_put_f64(header + 48, rad_hier_setup_link_error(setup));
    rad_le_put_u32(header + 56, flags);
    rad_le_put_u32(header + 60, (uint32_t)stats.solve_rounds);
    const uint64_t counts[8] = {node_count, stats.roots, splits, link_count, runs, hits,
                                s->element_count, stats.refined};
    for (int k = 0; k < 8; ++k) rad_le_put_u64(header + 64 + 8 * k, counts[k]);
    const double scalars[4] = {stats.largest_error, rad_hier_importance_mean(hier), hit_share,
                               stats.seen_share};
    for (int k = 0; k < 4; ++k) rad_le_put_f64(header + 128 + 8 * k, scalars[k]);

    writer *w = rad_alloc_zero(ctx, 1, sizeof *w);
    rad_atomic_file file;
    if (!w) status = RAD_ERROR_NO_MEMORY;
    if (!status) status = rad_atomic_open(ctx, path, &file);
    if (status) {
        rad_free(ctx, w);
        rad_free(ctx, parent);
        return status;
    }
    w->file = file.file;
    w->checksum = RAD_FNV1A_START;
    put(w, header, HEADER);
    for (size_t k = 0; k < splits; ++k) {
        put_u32(w, parent[k]);
        put_u32(w, (uint32_t)(base + 4 * k));
    }
    for (size_t i = 0; i < node_count; ++i) {
        for (int c = 0; c < 3; ++c) put_f64(w, nodes[i].radiosity[c]);
        rad_hier_node_state state;
        rad_hier_node_state_get(hier, (uint32_t)i, &state);
        if (flags & FLAG_LIGHT) {
            for (int c = 0; c < 3; ++c) put_f64(w, state.light[c]);
            put_f32(w, state.spread);
        }
        if (flags & FLAG_IMPORTANCE) put_f64(w, state.importance);
    }
    for (size_t r = 0; r < stats.roots; ++r) {
        uint32_t rays[6], seen[6];
        rad_hier_exposure_get(hier, (uint32_t)r, rays, seen);
        for (int a = 0; a < 6; ++a) {
            put_u32(w, rays[a]);
            put_u32(w, seen[a]);
        }
    }
    for (size_t l = 0; l < link_count;) {
        size_t last = l + 1;
        while (last < link_count && links[last].receiver == links[l].receiver) ++last;
        put_u32(w, links[l].receiver);
        put_u32(w, (uint32_t)(last - l));
        for (; l < last; ++l) {
            put_u32(w, links[l].source);
            put_f32(w, links[l].form_factor);
            put_f32(w, links[l].error);
        }
    }
    for (size_t i = 0; i < hits; ++i) {
        put_u32(w, hit_polygon[i]);
        put_f64(w, hit_point[i].x);
        put_f64(w, hit_point[i].y);
        put_f64(w, hit_point[i].z);
    }
    for (size_t e = 0; (flags & FLAG_REFLECTION) && e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c) put_f64(w, s->specular_reflection[e][c]);
    if (flags & FLAG_REFINING) {
        unsigned char kept[8];
        rad_le_put_u64(kept, refine_kept);
        put(w, kept, 8);
    }
    flush(w);
    unsigned char sum[8];
    rad_le_put_u64(sum, w->checksum);
    if (!w->failed && fwrite(sum, 1, 8, file.file) != 8) w->failed = 1;
    if (w->failed) {
        status = rad_fail(ctx, RAD_ERROR_IO, "%s: write failed: %s", path, strerror(errno));
        rad_atomic_abandon(&file);
    } else {
        status = rad_atomic_commit(&file);
    }
    rad_free(ctx, w);
    rad_free(ctx, parent);
    return status;
}

/* ---- Reading ----------------------------------------------------------------------------- */

/* The file's layout from its header: where each section starts. */
typedef struct layout {
    uint32_t flags;
    uint64_t nodes, roots, splits, links, runs, hits, elements;
    size_t node_bytes, split_at, node_at, root_at, link_at, hit_at, element_at, kept_at, end;
} layout;

/* a += b * c, with overflow reported. */
static int add_product(size_t *a, uint64_t b, size_t c) {
    size_t product;
    if (b > SIZE_MAX || rad_size_mul((size_t)b, c, &product) || product > SIZE_MAX - *a) return 1;
    *a += product;
    return 0;
}

static rad_status corrupted(rad_context *ctx, const char *path, const char *what) {
    return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted hierarchy solution file (%s)", path, what);
}

static rad_status read_layout(rad_context *ctx, const char *path, const unsigned char *bytes,
                              size_t size, layout *out) {
    if (size < HEADER + 8)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated solution file (%zu bytes)", path, size);
    layout l = {0};
    l.flags = rad_le_get_u32(bytes + 56);
    uint64_t *counts[7] = {&l.nodes, &l.roots, &l.splits, &l.links, &l.runs, &l.hits, &l.elements};
    for (int k = 0; k < 7; ++k) *counts[k] = rad_le_get_u64(bytes + 64 + 8 * k);
    if (l.flags & ~(uint32_t)FLAGS_KNOWN) return corrupted(ctx, path, "unknown flags");
    l.node_bytes = NODE_BYTES + (l.flags & FLAG_LIGHT ? NODE_LIGHT_BYTES : 0) +
                   (l.flags & FLAG_IMPORTANCE ? NODE_IMPORTANCE_BYTES : 0);
    size_t at = HEADER;
    l.split_at = at;
    int overflow = add_product(&at, l.splits, SPLIT_BYTES);
    l.node_at = at;
    overflow |= add_product(&at, l.nodes, l.node_bytes);
    l.root_at = at;
    overflow |= add_product(&at, l.roots, ROOT_BYTES);
    l.link_at = at;
    overflow |= add_product(&at, l.runs, RUN_BYTES) || add_product(&at, l.links, LINK_BYTES);
    l.hit_at = at;
    overflow |= add_product(&at, l.flags & FLAG_IMPORTANCE ? l.hits : 0, HIT_BYTES);
    l.element_at = at;
    overflow |= add_product(&at, l.flags & FLAG_REFLECTION ? l.elements : 0, ELEMENT_BYTES);
    l.kept_at = at;
    overflow |= add_product(&at, l.flags & FLAG_REFINING ? 1 : 0, 8);
    l.end = at;
    if (overflow || at > SIZE_MAX - 8) return corrupted(ctx, path, "section sizes");
    if (size < at + 8)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated solution file (%zu of %zu bytes)",
                        path, size, at + 8);
    if (size > at + 8 || rad_le_get_u64(bytes + at) != rad_fnv1a(RAD_FNV1A_START, bytes, at))
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (checksum mismatch)", path);
    *out = l;
    return RAD_OK;
}

static float get_f32(const unsigned char *p) {
    uint32_t bits = rad_le_get_u32(p);
    float v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

/* Every value that needs no hierarchy to check: finite, radiosity and light not below zero
 * (beyond rounding), counts and indices within the file's own counts. */
static rad_status check_values(rad_context *ctx, const char *path, const unsigned char *bytes,
                               const layout *l) {
    const size_t scalars[5] = {48, 128, 136, 144, 152};
    for (int k = 0; k < 5; ++k)
        if (!isfinite(rad_le_get_f64(bytes + scalars[k])))
            return corrupted(ctx, path, "a value is not finite");
    if (!(rad_le_get_f64(bytes + 48) > 0)) return corrupted(ctx, path, "link error");
    if (l->roots == 0 || l->roots > l->nodes || l->nodes > UINT32_MAX || l->splits > l->nodes / 4)
        return corrupted(ctx, path, "node counts");
    /* Radiosity and light are never negative: a solve may leave rounding below zero (a
     * millionth of the largest), no more. */
    double largest = 0;
    for (uint64_t i = 0; i < l->nodes; ++i) {
        const unsigned char *p = bytes + l->node_at + i * l->node_bytes;
        for (int k = 0; k < 3; ++k) {
            double b = rad_le_get_f64(p + 8 * k);
            if (!isfinite(b)) return corrupted(ctx, path, "a value is not finite");
            largest = fmax(largest, fabs(b));
        }
        if (l->flags & FLAG_LIGHT) {
            for (int k = 0; k < 3; ++k)
                if (!isfinite(rad_le_get_f64(p + 24 + 8 * k)))
                    return corrupted(ctx, path, "a value is not finite");
            float spread = get_f32(p + 48);
            if (!(spread >= 0) || !isfinite(spread)) return corrupted(ctx, path, "a light's spread");
        }
        if (l->flags & FLAG_IMPORTANCE) {
            double y = rad_le_get_f64(p + l->node_bytes - 8);
            if (!(y >= 0) || !isfinite(y)) return corrupted(ctx, path, "a node's importance");
        }
    }
    for (uint64_t i = 0; i < l->nodes; ++i) {
        const unsigned char *p = bytes + l->node_at + i * l->node_bytes;
        for (int k = 0; k < 3; ++k)
            if (rad_le_get_f64(p + 8 * k) < -1e-6 * largest ||
                ((l->flags & FLAG_LIGHT) && rad_le_get_f64(p + 24 + 8 * k) < -1e-6 * largest))
                return corrupted(ctx, path, "a negative radiosity");
    }
    for (uint64_t r = 0; r < 6 * l->roots; ++r)
        if (rad_le_get_u32(bytes + l->root_at + 8 * r + 4) > rad_le_get_u32(bytes + l->root_at + 8 * r))
            return corrupted(ctx, path, "a root's exposure");
    /* Receiver runs: increasing receivers, counts summing to the link count, ends in range. */
    const unsigned char *p = bytes + l->link_at;
    uint64_t seen = 0;
    int64_t previous = -1;
    for (uint64_t run = 0; run < l->runs; ++run) {
        uint32_t receiver = rad_le_get_u32(p), count = rad_le_get_u32(p + 4);
        p += RUN_BYTES;
        /* Grouped by receiver, except while a refinement waits to go on (flag 64). */
        int out_of_order = (l->flags & FLAG_REFINING) ? (int64_t)receiver == previous
                                                      : (int64_t)receiver <= previous;
        if (out_of_order || receiver >= l->nodes || count == 0 || count > l->links - seen)
            return corrupted(ctx, path, "a link's receiver");
        previous = receiver;
        for (uint32_t k = 0; k < count; ++k, p += LINK_BYTES) {
            float ff = get_f32(p + 4), error = get_f32(p + 8);
            if (rad_le_get_u32(p) >= l->nodes || !(ff >= 0) || !isfinite(ff) || !isfinite(error))
                return corrupted(ctx, path, "a link");
        }
        seen += count;
    }
    if (seen != l->links) return corrupted(ctx, path, "the link count");
    if ((l->flags & FLAG_REFINING) && rad_le_get_u64(bytes + l->kept_at) > l->links)
        return corrupted(ctx, path, "the links a refinement had passed");
    for (uint64_t i = 0; (l->flags & FLAG_IMPORTANCE) && i < l->hits; ++i)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(rad_le_get_f64(bytes + l->hit_at + HIT_BYTES * i + 4 + 8 * k)))
                return corrupted(ctx, path, "an importance hit");
    for (uint64_t i = 0; (l->flags & FLAG_REFLECTION) && i < 3 * l->elements; ++i)
        if (!isfinite(rad_le_get_f64(bytes + l->element_at + 8 * i)))
            return corrupted(ctx, path, "a specular light");
    return RAD_OK;
}

/* Builds the saved hierarchy aside, on one fresh from the same scene and options. */
static rad_status rebuild(rad_system *s, const char *path, const unsigned char *bytes,
                          const layout *l, rad_rgb *reflection, rad_hier_setup **setup_out,
                          rad_hier **hier_out) {
    rad_context *ctx = s->ctx;
    double link_error = rad_le_get_f64(bytes + 48);
    rad_hier_setup *setup = NULL;
    rad_hier *hier = NULL;
    rad_status status = rad_hier_setup_create(s, link_error, (l->flags & FLAG_IMPORTANCE) != 0,
                                              reflection, &setup, &hier);
    if (status) return status;
    rad_hier_stats stats = rad_hier_get_stats(hier);
    if (rad_hier_fingerprint(hier) != rad_le_get_u64(bytes + 40) || stats.roots != l->roots ||
        (rad_hier_has_light(hier) != 0) != ((l->flags & FLAG_LIGHT) != 0))
        status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                          "%s: saved for a different scene or lights (the hierarchy's polygons, "
                          "light or link error differ)", path);
    if (!status && (l->flags & FLAG_IMPORTANCE)) {
        size_t hits = (size_t)l->hits;
        uint32_t *polygon = rad_alloc(ctx, hits ? hits : 1, sizeof *polygon);
        rad_vec3 *point = rad_alloc(ctx, hits ? hits : 1, sizeof *point);
        for (size_t i = 0; polygon && point && i < hits; ++i) {
            const unsigned char *p = bytes + l->hit_at + HIT_BYTES * i;
            polygon[i] = rad_le_get_u32(p);
            point[i] = v3(rad_le_get_f64(p + 4), rad_le_get_f64(p + 12), rad_le_get_f64(p + 20));
            uint32_t count;
            if (!rad_hier_polygon_roots(hier, polygon[i], &count)) {
                status = corrupted(ctx, path, "an importance hit's polygon");
                break;
            }
        }
        if (!polygon || !point) status = RAD_ERROR_NO_MEMORY;
        if (!status) status = rad_hier_restore_view(hier, polygon, point, hits, rad_le_get_f64(bytes + 144));
        else {
            rad_free(ctx, polygon);
            rad_free(ctx, point);
        }
    }
    /* The splits, in the order they were made: the nodes get their numbers back. */
    for (uint64_t k = 0; k < l->splits && !status; ++k) {
        const unsigned char *p = bytes + l->split_at + SPLIT_BYTES * k;
        if (rad_hier_restore_split(hier, rad_le_get_u32(p), rad_le_get_u32(p + 4)))
            status = corrupted(ctx, path, "the refinement tree");
    }
    size_t node_count = 0;
    if (!status) rad_hier_nodes(hier, &node_count);
    if (!status && node_count != l->nodes) status = corrupted(ctx, path, "the node count");
    for (uint64_t i = 0; i < l->nodes && !status; ++i) {
        const unsigned char *p = bytes + l->node_at + i * l->node_bytes;
        double radiosity[3];
        rad_hier_node_state state = {{0, 0, 0}, 0, 0};
        for (int c = 0; c < 3; ++c) radiosity[c] = rad_le_get_f64(p + 8 * c);
        if (l->flags & FLAG_LIGHT) {
            for (int c = 0; c < 3; ++c) state.light[c] = rad_le_get_f64(p + 24 + 8 * c);
            state.spread = get_f32(p + 48);
        }
        if (l->flags & FLAG_IMPORTANCE) state.importance = rad_le_get_f64(p + l->node_bytes - 8);
        rad_hier_restore_node(hier, (uint32_t)i, radiosity, &state);
    }
    for (uint64_t r = 0; r < l->roots && !status; ++r) {
        uint32_t rays[6], seen[6];
        for (int a = 0; a < 6; ++a) {
            rays[a] = rad_le_get_u32(bytes + l->root_at + ROOT_BYTES * r + 8 * a);
            seen[a] = rad_le_get_u32(bytes + l->root_at + ROOT_BYTES * r + 8 * a + 4);
        }
        rad_hier_restore_exposure(hier, (uint32_t)r, rays, seen);
    }
    if (!status) {
        rad_hier_link *links = rad_alloc(ctx, l->links ? (size_t)l->links : 1, sizeof *links);
        if (!links) status = RAD_ERROR_NO_MEMORY;
        const unsigned char *p = bytes + l->link_at;
        size_t at = 0;
        for (uint64_t run = 0; run < l->runs && !status; ++run) {
            uint32_t receiver = rad_le_get_u32(p), count = rad_le_get_u32(p + 4);
            p += RUN_BYTES;
            for (uint32_t k = 0; k < count; ++k, p += LINK_BYTES, ++at) {
                links[at].receiver = receiver;
                links[at].source = rad_le_get_u32(p);
                links[at].form_factor = get_f32(p + 4);
                links[at].error = get_f32(p + 8);
            }
        }
        if (!status && (l->flags & FLAG_REFINING))
            status = rad_hier_restore_refining(hier, links, at,
                                               (size_t)rad_le_get_u64(bytes + l->kept_at));
        else if (!status)
            status = rad_hier_restore_links(hier, links, at);
        if (status == RAD_ERROR_PARSE) status = corrupted(ctx, path, "the links a refinement had passed");
        rad_hier_restore_importance_unfinished(hier, (l->flags & FLAG_IMPORTANCE_UNFINISHED) != 0);
    }
    if (!status) {
        rad_hier_stats saved = {0};
        saved.largest_error = rad_le_get_f64(bytes + 128);
        saved.refined = (size_t)rad_le_get_u64(bytes + 120);
        saved.solve_rounds = (int)rad_le_get_u32(bytes + 60);
        saved.budget_reached = (l->flags & FLAG_BUDGET) != 0;
        saved.seen_share = rad_le_get_f64(bytes + 152);
        rad_hier_restore_stats(hier, &saved, rad_le_get_f64(bytes + 136));
    }
    if (status) {
        rad_hier_destroy(hier);
        rad_hier_setup_destroy(s, setup);
        return status;
    }
    *setup_out = setup;
    *hier_out = hier;
    return RAD_OK;
}

rad_status rad_solution_hier_load(rad_system *s, const char *path, const unsigned char *bytes,
                                  size_t size, rad_solution_info *info) {
    rad_context *ctx = s->ctx;
    layout l = {0};
    rad_status status = read_layout(ctx, path, bytes, size, &l);
    if (status) return status;
    if (rad_solver_from_file_code(rad_le_get_u32(bytes + 12)) != (int)RAD_SOLVER_HIERARCHICAL)
        return corrupted(ctx, path, "not made by the hierarchical solver");
    if (!s->geometry || !s->mesh)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: a hierarchy's solution needs the scene's geometry; this is a patch "
                        "system (.ffm)", path);
    if ((status = check_values(ctx, path, bytes, &l))) return status;
    if (rad_le_get_u64(bytes + 24) != scene_fingerprint(s->geometry))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved for a different scene (surfaces or materials differ)", path);
    if (rad_le_get_u64(bytes + 32) != element_fingerprint(s) ||
        ((l.flags & FLAG_REFLECTION) && l.elements != s->element_count))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved for a different mesh or specular light (the elements the "
                        "hierarchy reads light through mirrors and glass from differ): use the "
                        "same scene and meshing options", path);
    /* What the rebuilt hierarchy will hold, against the memory budget. */
    double bytes_needed = (double)l.nodes * 160.0 + 2.0 * (double)l.links * sizeof(rad_hier_link);
    if ((status = rad_check_budget(ctx, bytes_needed, path))) return status;
    rad_rgb *reflection = NULL;
    if (l.flags & FLAG_REFLECTION) {
        reflection = rad_alloc(ctx, s->element_count ? s->element_count : 1, sizeof *reflection);
        if (!reflection) return RAD_ERROR_NO_MEMORY;
        for (size_t e = 0; e < s->element_count; ++e)
            for (int c = 0; c < 3; ++c)
                reflection[e][c] = rad_le_get_f64(bytes + l.element_at + 24 * e + 8 * c);
    }
    rad_hier_setup *setup = NULL;
    rad_hier *hier = NULL;
    status = rebuild(s, path, bytes, &l, reflection, &setup, &hier);
    if (status) {
        rad_free(ctx, reflection);
        return status;
    }
    /* Checked and rebuilt: now the system takes it. The second specular pass's light joins the
     * elements' emission as rad_system_add_specular_reflection would have added it. */
    rad_system_remove_specular_reflection(s);
    if (reflection) {
        for (size_t e = 0; e < s->element_count; ++e)
            for (int c = 0; c < 3; ++c) s->emission[e][c] += reflection[e][c];
        s->specular_reflection = reflection;
    }
    rad_hier_setup_set_unfinished(setup, (l.flags & FLAG_UNFINISHED) != 0);
    rad_hier_setup_set_loose(setup, (l.flags & FLAG_LOOSE) != 0);
    status = rad_hier_view_install(s, hier, setup, 1);
    if (status) {
        rad_hier_destroy(hier);
        rad_hier_setup_destroy(s, setup);
        return status;
    }
    rad_hier_view_evaluate(s);
    for (int c = 0; c < 3; ++c) s->ambient[c] = 0;
    if (info) {
        info->solver = RAD_SOLVER_HIERARCHICAL;
        info->steps = (long)rad_le_get_u64(bytes + 16);
    }
    return RAD_OK;
}
