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
 *          128 the last solve's importance rounds were interrupted after the light's converged,
 *          256 every link carries its sample (written by every version since 2026-12-04)
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
 *          each; written as zeros and skipped on reading since the hierarchy stopped counting
 *          them)
 *          links, grouped by receiver in their order: receiver, count (uint32), then per link
 *          source (uint32), form factor and error bound (float32); with flag 256 then whether
 *          it keeps a sample (uint8, 0 or 1) and if so the sample (rad_hier_link_sample: what a
 *          cluster link's rays saw of its source): members[4] (uint32, roots), weights[4]
 *          (uint16, in 1/65534); the file's length follows from the marks. Without flag
 *          256 a load casts every cluster link's rays again to draw the samples, which took
 *          as long as making the links (the 10^5 office: 5.5 s of wall to load and draw a
 *          small picture, 2.9 s with the samples kept; 38% of its links keep one)
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
#include <sys/types.h>

#define HEADER 160u
#define SPLIT_BYTES 8u
#define NODE_BYTES 24u
#define NODE_LIGHT_BYTES 28u
#define NODE_IMPORTANCE_BYTES 8u
#define ROOT_BYTES 48u
#define RUN_BYTES 8u
#define LINK_BYTES 12u
#define SAMPLE_BYTES 24u /* a kept sample, after its link's 1-byte mark (flag 256) */
#define HIT_BYTES 28u
#define ELEMENT_BYTES 24u
#define NOT_ESTIMATED -1.0f /* a link's factor made without its estimate (hierarchy.c) */

enum { FLAG_IMPORTANCE = 1, FLAG_LIGHT = 2, FLAG_REFLECTION = 4, FLAG_BUDGET = 8, FLAG_UNFINISHED = 16,
       FLAG_LOOSE = 32, FLAG_REFINING = 64, FLAG_IMPORTANCE_UNFINISHED = 128, FLAG_SAMPLES = 256,
       FLAGS_KNOWN = 511 };

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
                     (setup && rad_hier_setup_loose(setup) ? FLAG_LOOSE : 0) | FLAG_SAMPLES;
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
    /* The roots' exposure counts: no longer kept (hspeed9), written as zeros so that the format
     * stays version 3. */
    for (size_t r = 0; r < stats.roots; ++r)
        for (int a = 0; a < 12; ++a) put_u32(w, 0);
    for (size_t l = 0; l < link_count;) {
        size_t last = l + 1;
        while (last < link_count && links[last].receiver == links[l].receiver) ++last;
        put_u32(w, links[l].receiver);
        put_u32(w, (uint32_t)(last - l));
        for (; l < last; ++l) {
            put_u32(w, links[l].source);
            put_f32(w, links[l].form_factor);
            put_f32(w, links[l].error);
            const rad_hier_link_sample *sample = rad_hier_link_sample_of(hier, &links[l]);
            unsigned char bytes[1 + SAMPLE_BYTES] = {sample != NULL};
            for (int k = 0; sample && k < 4; ++k) {
                rad_le_put_u32(bytes + 1 + 4 * k, sample->member[k]);
                rad_le_put_u16(bytes + 17 + 2 * k, sample->weight[k]);
            }
            put(w, bytes, sample ? 1 + SAMPLE_BYTES : 1);
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

/* The file is read as a stream, twice, never whole: the first pass checks every value and the
 * checksum and keeps the small sections the rebuild needs first (the importance hits, the
 * second specular pass's light, the links a refinement had passed); the second builds the
 * hierarchy from the splits, nodes and links, checking the checksum again. Beside the rebuilt
 * hierarchy it needs one buffer of READ_BUFFER bytes. */
#define READ_BUFFER (1u << 16)

typedef struct reader {
    FILE *file;
    uint64_t checksum;   /* FNV-1a of the bytes before `hashed` */
    size_t hashed, next, have; /* in the buffer: hashed <= next <= have */
    uint64_t offset;     /* of the buffer's first byte in the file */
    unsigned char buffer[READ_BUFFER];
} reader;

static void reader_start(reader *r, FILE *file) {
    r->file = file;
    r->checksum = RAD_FNV1A_START;
    r->hashed = r->next = r->have = 0;
    r->offset = 0;
}

/* The next `count` bytes (at most READ_BUFFER), hashed into the checksum; NULL when the file
 * ends first or cannot be read. */
static const unsigned char *take(reader *r, size_t count) {
    if (r->have - r->next < count) {
        r->checksum = rad_fnv1a(r->checksum, r->buffer + r->hashed, r->next - r->hashed);
        size_t left = r->have - r->next;
        memmove(r->buffer, r->buffer + r->next, left);
        r->offset += r->next;
        r->hashed = r->next = 0;
        r->have = left;
        while (r->have < count) {
            size_t got = fread(r->buffer + r->have, 1, READ_BUFFER - r->have, r->file);
            if (got == 0) return NULL;
            r->have += got;
        }
    }
    const unsigned char *p = r->buffer + r->next;
    r->next += count;
    return p;
}

/* The checksum of every byte taken so far. */
static uint64_t reader_checksum(reader *r) {
    r->checksum = rad_fnv1a(r->checksum, r->buffer + r->hashed, r->next - r->hashed);
    r->hashed = r->next;
    return r->checksum;
}

/* Passes over `count` records of `size` bytes (checksummed). */
static int skip(reader *r, uint64_t count, size_t size) {
    for (uint64_t i = 0; i < count; ++i)
        if (!take(r, size)) return 1;
    return 0;
}

/* The file's layout from its header: where each section starts. */
typedef struct layout {
    uint32_t flags;
    uint64_t nodes, roots, splits, links, runs, hits, elements;
    uint64_t size;
    size_t node_bytes, link_bytes, end; /* with flag 256, end counts the samples once the first
                                           pass has (check_values) */
    unsigned char header[HEADER];
} layout;

/* What the first pass keeps for the rebuild. */
typedef struct tail {
    uint32_t *hit_polygon;
    rad_vec3 *hit_point;
    rad_rgb *reflection;
    uint64_t kept;
} tail;

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

static rad_status truncated(rad_context *ctx, const char *path, uint64_t size, size_t expected) {
    return rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated solution file (%llu of %zu bytes)", path,
                    (unsigned long long)size, expected);
}

/* The header, and the file's length against the one it gives. */
static rad_status read_layout(rad_context *ctx, const char *path, reader *r, uint64_t size,
                              layout *out) {
    const unsigned char *bytes = size >= HEADER + 8 ? take(r, HEADER) : NULL;
    if (!bytes)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated solution file (%llu bytes)", path,
                        (unsigned long long)size);
    layout l = {0};
    memcpy(l.header, bytes, HEADER);
    l.flags = rad_le_get_u32(bytes + 56);
    uint64_t *counts[7] = {&l.nodes, &l.roots, &l.splits, &l.links, &l.runs, &l.hits, &l.elements};
    for (int k = 0; k < 7; ++k) *counts[k] = rad_le_get_u64(bytes + 64 + 8 * k);
    if (l.flags & ~(uint32_t)FLAGS_KNOWN) return corrupted(ctx, path, "unknown flags");
    /* Unfinished importance rounds need the importance they go on from. */
    if ((l.flags & FLAG_IMPORTANCE_UNFINISHED) && !(l.flags & FLAG_IMPORTANCE))
        return corrupted(ctx, path, "unfinished importance without importance");
    l.node_bytes = NODE_BYTES + (l.flags & FLAG_LIGHT ? NODE_LIGHT_BYTES : 0) +
                   (l.flags & FLAG_IMPORTANCE ? NODE_IMPORTANCE_BYTES : 0);
    l.link_bytes = LINK_BYTES + (l.flags & FLAG_SAMPLES ? 1 : 0);
    size_t at = HEADER;
    int overflow = add_product(&at, l.splits, SPLIT_BYTES);
    overflow |= add_product(&at, l.nodes, l.node_bytes);
    overflow |= add_product(&at, l.roots, ROOT_BYTES);
    overflow |= add_product(&at, l.runs, RUN_BYTES) || add_product(&at, l.links, l.link_bytes);
    overflow |= add_product(&at, l.flags & FLAG_IMPORTANCE ? l.hits : 0, HIT_BYTES);
    overflow |= add_product(&at, l.flags & FLAG_REFLECTION ? l.elements : 0, ELEMENT_BYTES);
    overflow |= add_product(&at, l.flags & FLAG_REFINING ? 1 : 0, 8);
    l.end = at;
    l.size = size;
    if (overflow || at > SIZE_MAX - 8) return corrupted(ctx, path, "section sizes");
    if (size < at + 8) return truncated(ctx, path, size, at + 8);
    /* The samples' length is known once their marks are read (check_values). */
    if (size > at + 8 && !(l.flags & FLAG_SAMPLES))
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

static void tail_free(rad_context *ctx, tail *t) {
    rad_free(ctx, t->hit_polygon);
    rad_free(ctx, t->hit_point);
    rad_free(ctx, t->reflection);
    *t = (tail){0};
}

/* A link's sample as saved: four members below the root count with weights of at most 65534
 * (the hierarchy checks that the link's source is a cluster). */
static int sample_ok(const unsigned char *p, uint64_t roots) {
    for (int k = 0; k < 4; ++k)
        if (rad_le_get_u32(p + 4 * k) >= roots ||
            rad_le_get_u16(p + 16 + 2 * k) == RAD_HIER_NO_SAMPLE)
            return 0;
    return 1;
}

/* The first pass, after the header: every value that needs no hierarchy to check (finite,
 * radiosity and light not below zero beyond rounding, counts and indices within the file's own
 * counts) and the checksum; keeps the tail sections. A short read is a truncated file. */
static rad_status check_values(rad_context *ctx, const char *path, reader *r, layout *l,
                               tail *t) {
    const unsigned char *bytes = l->header;
    const size_t scalars[5] = {48, 128, 136, 144, 152};
    for (int k = 0; k < 5; ++k)
        if (!isfinite(rad_le_get_f64(bytes + scalars[k])))
            return corrupted(ctx, path, "a value is not finite");
    if (!(rad_le_get_f64(bytes + 48) > 0)) return corrupted(ctx, path, "link error");
    if (l->roots == 0 || l->roots > l->nodes || l->nodes > UINT32_MAX || l->splits > l->nodes / 4)
        return corrupted(ctx, path, "node counts");
    if (skip(r, l->splits, SPLIT_BYTES)) return truncated(ctx, path, r->offset + r->have, l->end + 8);
    /* Radiosity and light are never negative: a solve may leave rounding below zero (a
     * millionth of the largest radiosity), no more. */
    double largest = 0, lowest = 0;
    for (uint64_t i = 0; i < l->nodes; ++i) {
        const unsigned char *p = take(r, l->node_bytes);
        if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
        for (int k = 0; k < 3; ++k) {
            double b = rad_le_get_f64(p + 8 * k);
            if (!isfinite(b)) return corrupted(ctx, path, "a value is not finite");
            largest = fmax(largest, fabs(b));
            lowest = fmin(lowest, b);
        }
        if (l->flags & FLAG_LIGHT) {
            for (int k = 0; k < 3; ++k) {
                double light = rad_le_get_f64(p + 24 + 8 * k);
                if (!isfinite(light)) return corrupted(ctx, path, "a value is not finite");
                lowest = fmin(lowest, light);
            }
            float spread = get_f32(p + 48);
            if (!(spread >= 0) || !isfinite(spread)) return corrupted(ctx, path, "a light's spread");
        }
        if (l->flags & FLAG_IMPORTANCE) {
            double y = rad_le_get_f64(p + l->node_bytes - 8);
            if (!(y >= 0) || !isfinite(y)) return corrupted(ctx, path, "a node's importance");
        }
    }
    if (lowest < -1e-6 * largest) return corrupted(ctx, path, "a negative radiosity");
    for (uint64_t root = 0; root < l->roots; ++root) {
        const unsigned char *p = take(r, ROOT_BYTES);
        if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
        for (int a = 0; a < 6; ++a)
            if (rad_le_get_u32(p + 8 * a + 4) > rad_le_get_u32(p + 8 * a))
                return corrupted(ctx, path, "a root's exposure");
    }
    /* Receiver runs: increasing receivers, counts summing to the link count, ends in range.
     * While a refinement waits to go on (flag 64), the links it has not passed yet may carry
     * the factor NOT_ESTIMATED (-1: made without an estimate, as the oracle splits them
     * whatever it would be; hierarchy.c), never one it kept. */
    uint64_t seen = 0, first_unestimated = UINT64_MAX, samples = 0;
    int64_t previous = -1;
    for (uint64_t run = 0; run < l->runs; ++run) {
        const unsigned char *p = take(r, RUN_BYTES);
        if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
        uint32_t receiver = rad_le_get_u32(p), count = rad_le_get_u32(p + 4);
        /* Grouped by receiver, except while a refinement waits to go on (flag 64). */
        int out_of_order = (l->flags & FLAG_REFINING) ? (int64_t)receiver == previous
                                                      : (int64_t)receiver <= previous;
        if (out_of_order || receiver >= l->nodes || count == 0 || count > l->links - seen)
            return corrupted(ctx, path, "a link's receiver");
        previous = receiver;
        for (uint32_t k = 0; k < count; ++k) {
            if (!(p = take(r, l->link_bytes)))
                return truncated(ctx, path, r->offset + r->have, l->end + 8);
            uint32_t source = rad_le_get_u32(p);
            float ff = get_f32(p + 4), error = get_f32(p + 8);
            unsigned mark = (l->flags & FLAG_SAMPLES) ? p[LINK_BYTES] : 0;
            if ((l->flags & FLAG_REFINING) && ff == NOT_ESTIMATED && first_unestimated == UINT64_MAX)
                first_unestimated = seen + k;
            int factor_ok = (ff >= 0 && isfinite(ff)) || ((l->flags & FLAG_REFINING) && ff == NOT_ESTIMATED);
            if (source >= l->nodes || !factor_ok || !isfinite(error) || mark > 1)
                return corrupted(ctx, path, "a link");
            if (!mark) continue;
            /* The link's sample (p is not read past here: take() may move the buffer). */
            samples++;
            if (!(p = take(r, SAMPLE_BYTES)))
                return truncated(ctx, path, r->offset + r->have,
                                 l->end + 8 + SAMPLE_BYTES * samples);
            if (!sample_ok(p, l->roots)) return corrupted(ctx, path, "a link's sample");
        }
        seen += count;
    }
    if (seen != l->links) return corrupted(ctx, path, "the link count");
    if (l->flags & FLAG_SAMPLES) {
        /* Now the file's length is known: as for the fixed sections (read_layout). */
        l->end += (size_t)samples * SAMPLE_BYTES; /* no overflow: the bytes were read */
        if (l->size > l->end + 8)
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (checksum mismatch)",
                            path);
    }
    /* The tail: kept for the rebuild, which needs it before the nodes and links. */
    size_t hits = (l->flags & FLAG_IMPORTANCE) ? (size_t)l->hits : 0;
    size_t elements = (l->flags & FLAG_REFLECTION) ? (size_t)l->elements : 0;
    if (l->flags & FLAG_IMPORTANCE) {
        t->hit_polygon = rad_alloc(ctx, hits ? hits : 1, sizeof *t->hit_polygon);
        t->hit_point = rad_alloc(ctx, hits ? hits : 1, sizeof *t->hit_point);
        if (!t->hit_polygon || !t->hit_point) return RAD_ERROR_NO_MEMORY;
    }
    for (size_t i = 0; i < hits; ++i) {
        const unsigned char *p = take(r, HIT_BYTES);
        if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
        t->hit_polygon[i] = rad_le_get_u32(p);
        t->hit_point[i] = v3(rad_le_get_f64(p + 4), rad_le_get_f64(p + 12), rad_le_get_f64(p + 20));
        if (!isfinite(t->hit_point[i].x) || !isfinite(t->hit_point[i].y) ||
            !isfinite(t->hit_point[i].z))
            return corrupted(ctx, path, "an importance hit");
    }
    if (l->flags & FLAG_REFLECTION) {
        t->reflection = rad_alloc(ctx, elements ? elements : 1, sizeof *t->reflection);
        if (!t->reflection) return RAD_ERROR_NO_MEMORY;
    }
    for (size_t e = 0; e < elements; ++e) {
        const unsigned char *p = take(r, ELEMENT_BYTES);
        if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
        for (int c = 0; c < 3; ++c) {
            t->reflection[e][c] = rad_le_get_f64(p + 8 * c);
            if (!isfinite(t->reflection[e][c])) return corrupted(ctx, path, "a specular light");
        }
    }
    if (l->flags & FLAG_REFINING) {
        const unsigned char *p = take(r, 8);
        if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
        t->kept = rad_le_get_u64(p);
        if (t->kept > l->links || first_unestimated < t->kept)
            return corrupted(ctx, path, "the links a refinement had passed");
    }
    uint64_t sum = reader_checksum(r);
    const unsigned char *p = take(r, 8);
    if (!p) return truncated(ctx, path, r->offset + r->have, l->end + 8);
    if (rad_le_get_u64(p) != sum)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (checksum mismatch)", path);
    return RAD_OK;
}

/* The second pass, after the header: builds the saved hierarchy aside, on one fresh from the
 * same scene and options. `t`'s hits go to the hierarchy (whatever the outcome). */
static rad_status rebuild(rad_system *s, const char *path, reader *r, const layout *l, tail *t,
                          rad_hier_setup **setup_out, rad_hier **hier_out) {
    rad_context *ctx = s->ctx;
    const unsigned char *bytes = l->header;
    double link_error = rad_le_get_f64(bytes + 48);
    rad_hier_setup *setup = NULL;
    rad_hier *hier = NULL;
    rad_status status = rad_hier_setup_create(s, link_error, (l->flags & FLAG_IMPORTANCE) != 0,
                                              t->reflection, &setup, &hier);
    if (status) return status;
    rad_hier_stats stats = rad_hier_get_stats(hier);
    if (rad_hier_fingerprint(hier) != rad_le_get_u64(bytes + 40) || stats.roots != l->roots ||
        (rad_hier_has_light(hier) != 0) != ((l->flags & FLAG_LIGHT) != 0))
        status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                          "%s: saved for a different scene or lights (the hierarchy's polygons, "
                          "light or link error differ)", path);
    if (!status && (l->flags & FLAG_IMPORTANCE)) {
        size_t hits = (size_t)l->hits;
        for (size_t i = 0; i < hits && !status; ++i) {
            uint32_t count;
            if (!rad_hier_polygon_roots(hier, t->hit_polygon[i], &count))
                status = corrupted(ctx, path, "an importance hit's polygon");
        }
        if (!status) {
            status = rad_hier_restore_view(hier, t->hit_polygon, t->hit_point, hits,
                                           rad_le_get_f64(bytes + 144));
            t->hit_polygon = NULL; /* the hierarchy's now */
            t->hit_point = NULL;
        }
    }
    /* The splits, in the order they were made: the nodes get their numbers back. */
    for (uint64_t k = 0; k < l->splits && !status; ++k) {
        const unsigned char *p = take(r, SPLIT_BYTES);
        if (!p) status = truncated(ctx, path, r->offset + r->have, l->end + 8);
        else if (rad_hier_restore_split(hier, rad_le_get_u32(p), rad_le_get_u32(p + 4)))
            status = corrupted(ctx, path, "the refinement tree");
    }
    size_t node_count = 0;
    if (!status) rad_hier_nodes(hier, &node_count);
    if (!status && node_count != l->nodes) status = corrupted(ctx, path, "the node count");
    for (uint64_t i = 0; i < l->nodes && !status; ++i) {
        const unsigned char *p = take(r, l->node_bytes);
        if (!p) {
            status = truncated(ctx, path, r->offset + r->have, l->end + 8);
            break;
        }
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
    /* The roots' exposure counts: checked above, no longer used (hspeed9). */
    for (uint64_t root = 0; root < l->roots && !status; ++root)
        if (!take(r, ROOT_BYTES)) status = truncated(ctx, path, r->offset + r->have, l->end + 8);
    rad_hier_link *links = NULL;
    rad_hier_link_sample *samples = NULL;
    size_t at = 0;
    if (!status) {
        links = rad_alloc(ctx, l->links ? (size_t)l->links : 1, sizeof *links);
        if (l->flags & FLAG_SAMPLES)
            samples = rad_alloc(ctx, l->links ? (size_t)l->links : 1, sizeof *samples);
        if (!links || ((l->flags & FLAG_SAMPLES) && !samples)) status = RAD_ERROR_NO_MEMORY;
    }
    for (uint64_t run = 0; run < l->runs && !status; ++run) {
        const unsigned char *p = take(r, RUN_BYTES);
        uint32_t receiver = p ? rad_le_get_u32(p) : 0, count = p ? rad_le_get_u32(p + 4) : 0;
        if (!p || count > l->links - at) status = corrupted(ctx, path, "the links changed while read");
        for (uint32_t k = 0; k < count && !status; ++k, ++at) {
            if (!(p = take(r, l->link_bytes))) {
                status = corrupted(ctx, path, "the links changed while read");
                break;
            }
            links[at].receiver = receiver;
            links[at].source = rad_le_get_u32(p);
            links[at].form_factor = get_f32(p + 4);
            links[at].error = get_f32(p + 8);
            if (samples) samples[at].weight[0] = RAD_HIER_NO_SAMPLE;
            if (samples && p[LINK_BYTES]) {
                if (!(p = take(r, SAMPLE_BYTES))) {
                    status = corrupted(ctx, path, "the links changed while read");
                    break;
                }
                for (int k = 0; k < 4; ++k) {
                    samples[at].member[k] = rad_le_get_u32(p + 4 * k);
                    samples[at].weight[k] = rad_le_get_u16(p + 16 + 2 * k);
                }
            }
        }
    }
    /* The rest was kept by the first pass; its bytes are read again for the checksum, which
     * must be the first pass's (the file did not change in between). */
    size_t rest = l->end - (size_t)(r->offset + r->next);
    for (; !status && rest > 0;) {
        size_t n = rest < READ_BUFFER ? rest : READ_BUFFER;
        if (!take(r, n)) status = corrupted(ctx, path, "the file changed while read");
        rest -= n;
    }
    if (!status) {
        uint64_t sum = reader_checksum(r);
        const unsigned char *p = take(r, 8);
        if (!p || rad_le_get_u64(p) != sum) status = corrupted(ctx, path, "the file changed while read");
    }
    if (!status) {
        if (l->flags & FLAG_REFINING)
            status = rad_hier_restore_refining(hier, links, samples, at, (size_t)t->kept);
        else
            status = rad_hier_restore_links(hier, links, samples, at);
        links = NULL; /* the hierarchy's now, with the samples */
        samples = NULL;
        if (status == RAD_ERROR_PARSE)
            status = corrupted(ctx, path, (l->flags & FLAG_REFINING)
                                              ? "the links a refinement had passed, or a sample"
                                              : "a link's sample");
        rad_hier_restore_importance_unfinished(hier, (l->flags & FLAG_IMPORTANCE_UNFINISHED) != 0);
    }
    rad_free(ctx, links);
    rad_free(ctx, samples);
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

/* Both passes over the open file (its magic and version checked by the caller). */
static rad_status load(rad_system *s, const char *path, FILE *file, reader *r, layout *l,
                       tail *t, rad_hier_setup **setup, rad_hier **hier) {
    rad_context *ctx = s->ctx;
    uint64_t size = 0;
    off_t end = fseeko(file, 0, SEEK_END) == 0 ? ftello(file) : -1;
    if (end < 0 || fseeko(file, 0, SEEK_SET) != 0)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read a hierarchy solution from a pipe or "
                        "device (it is read twice): %s", path, strerror(errno));
    size = (uint64_t)end;
    reader_start(r, file);
    rad_status status = read_layout(ctx, path, r, size, l);
    if (status) return status;
    const unsigned char *bytes = l->header;
    if (rad_solver_from_file_code(rad_le_get_u32(bytes + 12)) != (int)RAD_SOLVER_HIERARCHICAL)
        return corrupted(ctx, path, "not made by the hierarchical solver");
    if (!s->geometry || !s->mesh)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: a hierarchy's solution needs the scene's geometry; this is a patch "
                        "system (.ffm)", path);
    if ((status = check_values(ctx, path, r, l, t))) return status;
    if (rad_le_get_u64(bytes + 24) != scene_fingerprint(s->geometry))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved for a different scene (surfaces or materials differ)", path);
    if (rad_le_get_u64(bytes + 32) != element_fingerprint(s) ||
        ((l->flags & FLAG_REFLECTION) && l->elements != s->element_count))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved for a different mesh or specular light (the elements the "
                        "hierarchy reads light through mirrors and glass from differ): use the "
                        "same scene and meshing options", path);
    /* What the rebuilt hierarchy will hold, against the memory budget. */
    double bytes_needed = (double)l->nodes * 160.0 + 2.0 * (double)l->links * sizeof(rad_hier_link);
    if ((status = rad_check_budget(ctx, bytes_needed, path))) return status;
    if (fseeko(file, 0, SEEK_SET) != 0)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    reader_start(r, file);
    if (!take(r, HEADER) || memcmp(r->buffer, bytes, HEADER) != 0)
        return corrupted(ctx, path, "the file changed while read");
    return rebuild(s, path, r, l, t, setup, hier);
}

rad_status rad_solution_hier_load(rad_system *s, const char *path, FILE *file,
                                  rad_solution_info *info) {
    rad_context *ctx = s->ctx;
    reader *r = rad_alloc(ctx, 1, sizeof *r);
    layout *l = rad_alloc_zero(ctx, 1, sizeof *l);
    tail t = {0};
    rad_hier_setup *setup = NULL;
    rad_hier *hier = NULL;
    rad_status status = r && l ? load(s, path, file, r, l, &t, &setup, &hier) : RAD_ERROR_NO_MEMORY;
    rad_free(ctx, r);
    if (status) {
        tail_free(ctx, &t);
        rad_free(ctx, l);
        return status;
    }
    /* Checked and rebuilt: now the system takes it. The second specular pass's light joins the
     * elements' emission as rad_system_add_specular_reflection would have added it. */
    rad_system_remove_specular_reflection(s);
    rad_rgb *reflection = t.reflection;
    t.reflection = NULL;
    if (reflection) {
        for (size_t e = 0; e < s->element_count; ++e)
            for (int c = 0; c < 3; ++c) s->emission[e][c] += reflection[e][c];
        s->specular_reflection = reflection;
    }
    tail_free(ctx, &t);
    rad_hier_setup_set_unfinished(setup, (l->flags & FLAG_UNFINISHED) != 0);
    rad_hier_setup_set_loose(setup, (l->flags & FLAG_LOOSE) != 0);
    status = rad_hier_view_install(s, hier, setup, 1);
    if (status) {
        rad_hier_destroy(hier);
        rad_hier_setup_destroy(s, setup);
        rad_free(ctx, l);
        return status;
    }
    rad_hier_view_evaluate(s);
    for (int c = 0; c < 3; ++c) s->ambient[c] = 0;
    if (info) {
        info->solver = RAD_SOLVER_HIERARCHICAL;
        info->steps = (long)rad_le_get_u64(l->header + 16);
    }
    rad_free(ctx, l);
    return RAD_OK;
}
