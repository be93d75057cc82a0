/* geometric.h - what every geometric form-factor method shares: the mesh, the input geometry's
 * ray queries, the shooting patches' outlines, stratified points on patches and elements, shaft
 * culling, and the options. One file per method: analytic.c, hemicube.c, raycast.c,
 * montecarlo.c; the table in factory.c lists them; patch.c, shaft.c and cache.c are the shared
 * pieces. docs/formfactors.md explains each method with its paper. */
#ifndef RAD_FORMFACTOR_GEOMETRIC_H
#define RAD_FORMFACTOR_GEOMETRIC_H

#include "core/rng.h"
#include "formfactor/pair.h"
#include "formfactor/provider.h"
#include "mesh/mesh.h"
#include "scene/rays.h"

#define RAD_FF_MAX_OUTLINE 12

/* A shooting patch: the convex outline of its elements (counter-clockwise seen from the front),
 * its area-weighted centre, its unit normal and area. */
typedef struct rad_ff_patch {
    /* What rad_ff_patch_facing reads for every receiver of every row comes first. */
    rad_vec3 centre, normal;
    double radius;   /* largest distance from the centre to a corner */
    double warp;     /* largest distance of an element corner from the plane (centre, normal) */
    double tilt;     /* largest |element normal - normal| */
    double area;
    rad_vec3 lo, hi; /* bounds of the outline */
    int corner_count;
    rad_vec3 corners[RAD_FF_MAX_OUTLINE];
} rad_ff_patch;

typedef struct rad_ff_shaft rad_ff_shaft;
typedef struct rad_ff_shaft_view rad_ff_shaft_view;

/* Rows computed block by block in one parallel loop at most, and scratch slots (one per row in
 * flight, or per thread: rad_ff_rows_run). */
#define RAD_FF_ROWS_AHEAD rad_ff_rows_ahead

/* Everything a method needs; built by rad_ff_create and released with rad_ff_context_release
 * by the provider that holds it. */
typedef struct rad_ff_context {
    rad_context *ctx;
    const rad_mesh *mesh;   /* owned by the system */
    rad_rays *rays;         /* owned here */
    rad_ff_patch *patches;  /* owned here, mesh->patch_count entries */
    rad_ff_shaft *shaft;    /* owned here; NULL when the scene is too large to cull this way */
    double *element_radius; /* owned here: largest distance from an element's centroid to a
                               corner */
    int max_members;        /* most elements in one patch */
    rad_ff_options options; /* samples and resolution already defaulted */
} rad_ff_context;

void rad_ff_context_release(rad_ff_context *context);

/* Builds a context: rays of the input geometry, patch outlines and (when `cull` is nonzero and
 * the scene is small enough) the shaft-culling tables. Release with rad_ff_context_release. */
rad_status rad_ff_context_build(rad_context *ctx, const struct rad_scene *scene,
                                const rad_mesh *mesh, const rad_ff_options *options, int cull,
                                rad_ff_context *out);

/* What a provider did, for benchmarks: rows computed, form factors (receivers) evaluated,
 * visibility rays cast. */
typedef struct rad_ff_stats {
    uint64_t rows, receivers, rays;
} rad_ff_stats;

/* The first members of every geometric provider. */
typedef struct rad_ff_common {
    rad_ff_provider base;
    rad_ff_context c;
    /* Scratch of each row in flight (or of each thread, for many rows): max_members entries
     * for rad_ff_source_begin, and the shaft's candidates (NULL without a shaft). Slot 0 is made
     * with the provider, the others when rad_ff_rows_run first needs them. */
    struct rad_ff_element_map *maps[RAD_FF_ROWS_AHEAD];
    rad_ff_shaft_view *views[RAD_FF_ROWS_AHEAD];
    rad_ff_stats stats;
} rad_ff_common;

/* Allocates a provider of `size` bytes starting with rad_ff_common, taking over the context
 * (its rays, outlines and shaft) on success. */
rad_status rad_ff_common_create(const rad_ff_context *context, size_t size, const char *method,
                                rad_status (*row)(rad_ff_provider *, size_t, float *),
                                void (*destroy)(rad_ff_provider *), rad_ff_common **out);
/* Frees what rad_ff_common_create made (call from the method's destroy, last). */
void rad_ff_common_destroy(rad_ff_common *common);

/* The statistics of a provider made by rad_ff_create (looking through the row cache); zeros
 * for providers that keep none. */
rad_ff_stats rad_ff_provider_stats(const rad_ff_provider *provider);

/* A method's registration: what the public registry shows (rad_ff_method_info), its defaults
 * and its constructor. Each method file defines one, `rad_ff_method_<name>`, and factory.c
 * lists it in RAD_FF_METHODS: a new method is one file plus that one line. */
typedef struct rad_ff_method_entry {
    rad_ff_method_info info;
    int default_resolution;
    rad_status (*create)(const rad_ff_context *context, rad_ff_provider **out);
} rad_ff_method_entry;

/* Creates the provider for options->method over a mesh (RAD_FF_DEFAULT picks the default).
 * Rows are cached within a share of the memory budget (cache.c). */
rad_status rad_ff_create(rad_context *ctx, const struct rad_scene *scene, const rad_mesh *mesh,
                         const rad_ff_options *options, rad_ff_provider **out);

/* The method table (factory.c). */
const rad_ff_method_entry *rad_ff_method_find(rad_ff_method method);
const rad_ff_method_entry *rad_ff_method_by_name(const char *name);

/* A row cache in front of a provider (cache.c): rows are deterministic, so progressive
 * refinement, which shoots the same bright patches again and again, computes each once.
 * Holds at most `bytes`; evicts the least recently used row. Takes ownership of `inner`. */
rad_status rad_ff_cache_create(rad_context *ctx, rad_ff_provider *inner, size_t patch_count,
                               size_t element_count, double bytes, rad_ff_provider **out);

/* ------------------------------------------------------------------------------------------- */
/* Points on elements and patches (patch.c)                                                     */

/* An element ready for sampling: p(u, v) = origin + u e1 + v e2 + u v e3 for quads (bilinear,
 * uniform by area for parallelograms), and with u -> sqrt(u) (1 - v), v -> sqrt(u) v for
 * triangles. */
typedef struct rad_ff_element_map {
    rad_vec3 origin, e1, e2, e3;
    double area;
    int triangle;
} rad_ff_element_map;

rad_ff_element_map rad_ff_element_map_make(const rad_mesh *mesh, size_t element);

static inline rad_vec3 rad_ff_element_map_point(const rad_ff_element_map *m, double u, double v) {
    if (m->triangle) {
        double s = sqrt(u);
        double a = s * (1 - v), b = s * v;
        return v3(m->origin.x + a * m->e1.x + b * m->e2.x, m->origin.y + a * m->e1.y + b * m->e2.y,
                  m->origin.z + a * m->e1.z + b * m->e2.z);
    }
    double w = u * v;
    return v3(m->origin.x + u * m->e1.x + v * m->e2.x + w * m->e3.x,
              m->origin.y + u * m->e1.y + v * m->e2.y + w * m->e3.y,
              m->origin.z + u * m->e1.z + v * m->e2.z + w * m->e3.z);
}

/* A point on element e from two uniform numbers (uniform by area for parallelograms). */
rad_vec3 rad_element_sample(const rad_mesh *mesh, size_t element, double u1, double u2);

/* Corner k of element e. */
static inline rad_vec3 rad_element_corner(const rad_mesh *mesh, size_t element, int k) {
    return mesh->vertices[mesh->element_vertices[element][k]];
}

/* The R2 sequence (Roberts 2018): the 2-D low-discrepancy lattice i * (1/g, 1/g^2) mod 1 with
 * g the plastic number, rotated by a random offset (Cranley & Patterson 1976). */
#define RAD_R2_A1 0.75487766624669276
#define RAD_R2_A2 0.56984029099805327
static inline void rad_r2_point(int i, double r1, double r2, double *u, double *v) {
    double a = r1 + i * RAD_R2_A1, b = r2 + i * RAD_R2_A2;
    *u = a - floor(a);
    *v = b - floor(b);
}

/* The shooting patch of a row, ready for stratified sampling: `count` points spread over its
 * elements (each element gets count / members of them, or, with fewer points than elements, a
 * stratified choice of elements), weights summing to the patch area in expectation. */
typedef struct rad_ff_source {
    const rad_ff_patch *patch;
    int members, count;
    rad_ff_element_map *maps; /* members entries, scratch owned by the provider */
} rad_ff_source;

void rad_ff_source_begin(rad_ff_source *source, const rad_ff_context *context, size_t patch,
                         int count, rad_ff_element_map *scratch);

/* The random offsets of one receiver's set of source points. */
typedef struct rad_ff_jitter {
    double choice, r1, r2;
} rad_ff_jitter;

static inline rad_ff_jitter rad_ff_jitter_make(rad_rng *rng) {
    rad_ff_jitter j;
    j.choice = rad_rng_uniform(rng);
    j.r1 = rad_rng_uniform(rng);
    j.r2 = rad_rng_uniform(rng);
    return j;
}

/* Walks one receiver's set of n source points (n is usually source->count) in order, without
 * a division per point. */
typedef struct rad_ff_cursor {
    const rad_ff_source *source;
    double r1, r2, choice, spread; /* spread = members / n, for fewer points than elements */
    double share[2];               /* 1 / (points per element), for elements with more, fewer */
    int n, s, q, index, extra;
} rad_ff_cursor;

static inline rad_ff_cursor rad_ff_cursor_make(const rad_ff_source *source,
                                               const rad_ff_jitter *jitter, int n) {
    rad_ff_cursor c;
    int m = source->members;
    c.source = source;
    c.r1 = jitter->r1;
    c.r2 = jitter->r2;
    c.choice = jitter->choice;
    c.spread = (double)m / n;
    c.n = n;
    c.s = c.q = c.index = 0;
    c.extra = n >= m ? n % m : 0;
    c.share[0] = n >= m ? 1.0 / (n / m + 1) : 0; /* elements q < extra get one more point */
    c.share[1] = n >= m ? 1.0 / (n / m) : 0;
    return c;
}

/* The next point and its area weight: with at least as many points as elements, point s lies
 * on element s mod members (each element gets n / members of them); with fewer, on a
 * stratified random choice of elements. Within an element, the R2 lattice, rotated at random
 * per receiver and per element. */
static inline rad_vec3 rad_ff_cursor_next(rad_ff_cursor *c, double *weight) {
    const rad_ff_source *source = c->source;
    int m = source->members, q, index;
    if (c->n >= m) {
        q = c->q;
        index = c->index;
        *weight = source->maps[q].area * c->share[q < c->extra ? 0 : 1];
        if (++c->q == m) {
            c->q = 0;
            ++c->index;
        }
    } else {
        q = (int)(((double)c->s + c->choice) * c->spread);
        if (q >= m) q = m - 1;
        index = c->s;
        *weight = source->maps[q].area * c->spread;
    }
    ++c->s;
    double u, v;
    rad_r2_point(index, c->r1 + q * RAD_R2_A2, c->r2 + q * RAD_R2_A1, &u, &v);
    return rad_ff_element_map_point(&source->maps[q], u, v);
}

/* Seed of the random numbers of one row: rows never depend on the thread count or the order in
 * which they are asked for. Receiver e then draws from stream e. */
static inline uint64_t rad_ff_row_seed(const rad_ff_context *context, size_t patch) {
    uint64_t x = context->ctx->seed ^ (0x9e3779b97f4a7c15ull * (uint64_t)(patch + 1));
    x ^= x >> 31;
    x *= 0xbf58476d1ce4e5b9ull;
    return x ^ (x >> 29);
}

/* Builds the outlines of every patch (patch.c). */
rad_status rad_ff_patches_create(rad_context *ctx, const rad_mesh *mesh, rad_ff_patch **out,
                                 int *max_members);

/* Nonzero when element e is so close to the patch that the form factor varies much across
 * either: their centres are less than `factor` times the sum of their radii apart. Methods that
 * work from a point of the element (or of the patch) spread their points over it there. */
static inline int rad_ff_near(const rad_ff_context *context, const rad_ff_patch *patch,
                              size_t element, double factor) {
    rad_vec3 d = v3_sub(context->mesh->element_centroid[element], patch->centre);
    double reach = factor * (patch->radius + context->element_radius[element]);
    return v3_dot(d, d) < reach * reach;
}

/* The 2 x 2 Gauss-Legendre points of the unit square: receivers near the source are sampled
 * there instead of at their centroid. */
#define RAD_FF_GAUSS_LOW 0.21132486540518713
#define RAD_FF_GAUSS_HIGH 0.78867513459481287

/* Nonzero when nothing can pass energy from the patch to element e: e lies on or behind the
 * patch's plane, or the whole patch lies on or behind e's plane. */
int rad_ff_facing_away(const rad_mesh *mesh, const rad_ff_patch *patch, size_t element);

/* The same question for all elements of a receiving patch at once (its elements lie in one
 * plane, inside its outline): RAD_FF_AWAY when every one faces away, RAD_FF_FACING when none
 * does, RAD_FF_MIXED when each must be asked. The first two answers keep a margin of the
 * tolerance, so they never differ from rad_ff_facing_away. */
enum { RAD_FF_AWAY, RAD_FF_FACING, RAD_FF_MIXED };
int rad_ff_patch_facing(const rad_ff_patch *shooter, const rad_ff_patch *receiver);

/* ------------------------------------------------------------------------------------------- */
/* Visibility rays in full packets                                                              */

/* Receivers are handled in blocks of this many (one parallel task); their rays share packets,
 * so a packet of 16 is full even when each receiver casts only a few. */
#define RAD_FF_BLOCK 64

/* Source points are made and weighed this many at a time (vectorised arithmetic). */
#define RAD_FF_BATCH 32

/* Segments waiting for a packet; each carries the contribution it makes to receiver `slot` of
 * the block when nothing blocks it. */
typedef struct rad_ff_ray_queue {
    rad_ray_packet packet;
    double contribution[16];
    int slot[16];
    uint64_t cast; /* rays queued so far (the provider's statistics) */
} rad_ff_ray_queue;

/* Traces what is queued and adds the contributions of the unblocked segments to sums[slot]. */
static inline void rad_ff_queue_flush(rad_ff_ray_queue *queue, const rad_rays *rays,
                                      double *sums) {
    if (!queue->packet.count) return;
    rad_rays_trace_packet(rays, &queue->packet);
    for (int i = 0; i < queue->packet.count; ++i) /* branch-free: blocking is unpredictable */
        sums[queue->slot[i]] += rad_ray_packet_occluded(&queue->packet, i) ? 0.0 : queue->contribution[i];
    queue->packet.count = 0;
}

/* Queues the segment from -> to (both already offset from their surfaces), flushing when the
 * packet is full. The ends are excluded by the rays' epsilon; a segment shorter than that casts
 * no ray and adds its contribution at once. */
static inline void rad_ff_queue_segment(rad_ff_ray_queue *queue, const rad_rays *rays,
                                       double *sums, rad_vec3 from, rad_vec3 to,
                                       double contribution, int slot) {
    rad_vec3 d = v3_sub(to, from);
    double length = sqrt(v3_dot(d, d));
    if (length <= 2 * rays->epsilon) {
        sums[slot] += contribution;
        return;
    }
    double margin = rays->epsilon / length;
    int lane = rad_ray_packet_add(&queue->packet, from, d, margin, 1 - margin);
    queue->contribution[lane] = contribution;
    queue->slot[lane] = slot;
    queue->cast++;
    if (queue->packet.count == 16) rad_ff_queue_flush(queue, rays, sums);
}

/* The same with the direction (to - from) and the margin epsilon / |to - from| known to the
 * caller, who often has the length already. */
static inline void rad_ff_queue_ray(rad_ff_ray_queue *queue, const rad_rays *rays, double *sums,
                                   rad_vec3 from, rad_vec3 direction, double margin,
                                   double contribution, int slot) {
    if (margin >= 0.5) {
        sums[slot] += contribution;
        return;
    }
    int lane = rad_ray_packet_add(&queue->packet, from, direction, margin, 1 - margin);
    queue->contribution[lane] = contribution;
    queue->slot[lane] = slot;
    queue->cast++;
    if (queue->packet.count == 16) rad_ff_queue_flush(queue, rays, sums);
}

/* ------------------------------------------------------------------------------------------- */
/* Shaft culling (Haines & Wallace 1991), shaft.c                                               */

/* Built once per provider (and per hierarchy); NULL (and RAD_OK) when the scene's polygons make
 * more than `most` occluders (polygons gathered by plane): the pairwise tables grow as its
 * square. The row methods take RAD_FF_SHAFT_OCCLUDERS. `mesh` is needed only by
 * rad_ff_shaft_clear. */
#define RAD_FF_SHAFT_OCCLUDERS 512
rad_status rad_ff_shaft_create(rad_context *ctx, const struct rad_scene *scene,
                               const rad_mesh *mesh, size_t most, rad_ff_shaft **out);
void rad_ff_shaft_destroy(rad_ff_shaft *shaft);

/* What culling keeps for one shooting patch, one view for each row in flight. NULL without a
 * shaft or memory (a NULL view clears nothing). */
rad_ff_shaft_view *rad_ff_shaft_view_create(const rad_ff_shaft *shaft);
void rad_ff_shaft_view_destroy(rad_ff_shaft_view *view);

/* Prepares the occluder candidates of one shooting patch in `view`. Call before the parallel
 * loop over receivers; rows with views of their own may begin at the same time. */
void rad_ff_shaft_begin(const rad_ff_shaft *shaft, rad_ff_shaft_view *view,
                        const rad_ff_patch *patch);

/* Nonzero when no input polygon can block any segment between the patch of the view's last
 * rad_ff_shaft_begin and element e, so no ray is needed. Thread safe. A NULL shaft clears
 * nothing. */
int rad_ff_shaft_clear(const rad_ff_shaft *shaft, const rad_ff_shaft_view *view, size_t element);

/* The same for a whole receiving patch (in input polygon `polygon`): when it is clear, so is
 * each of its elements. Thread safe. */
int rad_ff_shaft_clear_patch(const rad_ff_shaft *shaft, const rad_ff_shaft_view *view,
                             const rad_ff_patch *receiver, uint32_t polygon);

/* Nonzero when no input polygon can block any segment between a point of the convex hull of
 * a[0 .. na) and one of b[0 .. nb) (na, nb at most 4), with no view: every occluder is tested
 * (the plane, box and shaft tests above), so the cost grows with the occluder count. For a
 * hierarchy's links, whose ends are its nodes. Thread safe; a NULL shaft clears nothing. */
int rad_ff_shaft_pair_clear(const rad_ff_shaft *shaft, const rad_vec3 *a, int na,
                            const rad_vec3 *b, int nb);

/* ------------------------------------------------------------------------------------------- */
/* The frame of a row (factory.c): what analytic.c, raycast.c and montecarlo.c share around their
 * arithmetic per receiver. A row is cut into blocks of RAD_FF_BLOCK elements, one parallel task
 * each; a block walks its elements, skips those that receive nothing, asks the shaft whether
 * rays are needed, and queues its rays in shared packets. */

typedef struct rad_ff_row {
    const rad_ff_context *c;
    const rad_mesh *mesh;
    const rad_rays *rays;
    rad_ff_source source;
    const rad_ff_shaft_view *shaft; /* the patch's culling candidates */
    const rad_ff_patch *p; /* the shooting patch's outline */
    size_t patch;
    rad_vec3 np;           /* its normal */
    double epsilon, inverse_area;
    int samples;
    uint64_t seed;
    long n, blocks;
} rad_ff_row;

/* Prepares the row of `patch` in scratch slot `slot` (< RAD_FF_ROWS_AHEAD): its source points
 * and shaft candidates. Rows in different slots may begin at the same time. */
void rad_ff_row_begin(rad_ff_common *common, size_t patch, int slot, rad_ff_row *row);

/* Adds a finished row to the provider's statistics. */
void rad_ff_row_end(rad_ff_common *common, uint64_t receivers, uint64_t rays);

struct rad_ff_block;
/* One block of a row, begun by rad_ff_row_run: writes F for the block's elements into `out`;
 * the block counts its receivers and its queue the rays cast. */
typedef void (*rad_ff_block_fn)(const rad_ff_row *row, struct rad_ff_block *block, float *out);

/* The row of `patch`: rad_ff_row_begin, `block` over every block of the row on the context's
 * worker threads (core/team.h: they sleep between rows, where an OpenMP region per row left them
 * spinning), then rad_ff_row_end. Blocks write disjoint elements, so the row is the same for
 * any thread count. */
rad_status rad_ff_row_run(rad_ff_common *common, size_t patch, rad_ff_block_fn block, float *out);

/* The rows of patches[0 .. count) into out[0 .. count), the same values as rad_ff_row_run gives
 * each. Up to RAD_FF_ROWS_AHEAD rows: every block of every row in one parallel loop, which keeps
 * the threads busier than a loop per row (fewer wake-ups, one tail instead of `count`); more:
 * one task a row, each thread in its own scratch slot. */
rad_status rad_ff_rows_run(rad_ff_common *common, const size_t *patches, size_t count,
                           rad_ff_block_fn block, float *const *out);

typedef struct rad_ff_block {
    long first, last;      /* its elements */
    uint64_t receivers;    /* elements rad_ff_block_receives said yes to */
    rad_ff_ray_queue queue;
    size_t facing_patch;   /* the receiving patch whose facing answer is in `facing` */
    int facing;
    size_t tested_patch;   /* the receiving patch whose shaft answer is in `patch_clear` */
    int patch_clear;
} rad_ff_block;

static inline void rad_ff_block_begin(const rad_ff_row *row, long block, rad_ff_block *b) {
    b->first = block * RAD_FF_BLOCK;
    b->last = b->first + RAD_FF_BLOCK < row->n ? b->first + RAD_FF_BLOCK : row->n;
    rad_ray_packet_init(&b->queue.packet);
    b->facing_patch = b->tested_patch = SIZE_MAX;
    b->facing = RAD_FF_MIXED;
    b->patch_clear = 0;
    b->receivers = 0;
    b->queue.cast = 0;
}

/* Nonzero when element e receives from the patch: it is not one of the patch's own elements
 * and does not face away. Asked patch by patch (rad_ff_patch_facing), element by element only
 * where the patch's answer is mixed. */
static inline int rad_ff_block_receives(const rad_ff_row *row, rad_ff_block *b, long e) {
    const size_t q = row->mesh->element_patch[e];
    if (q == row->patch) return 0;
    if (q != b->facing_patch) {
        b->facing_patch = q;
        b->facing = rad_ff_patch_facing(row->p, &row->c->patches[q]);
    }
    int receives = b->facing == RAD_FF_MIXED ? !rad_ff_facing_away(row->mesh, row->p, (size_t)e)
                                             : b->facing == RAD_FF_FACING;
    b->receivers += (uint64_t)receives;
    return receives;
}

/* Nonzero when rays must decide the visibility between the patch and element e: shaft culling
 * cannot prove the receiving patch clear, nor (when `each`) the element alone. The patch's
 * answer is kept for its next elements. */
static inline int rad_ff_block_needs_rays(const rad_ff_row *row, rad_ff_block *b, long e, int each) {
    const rad_ff_context *c = row->c;
    if (!c->shaft) return 1;
    size_t q = row->mesh->element_patch[e];
    if (q != b->tested_patch) {
        b->tested_patch = q;
        b->patch_clear = rad_ff_shaft_clear_patch(c->shaft, row->shaft, &c->patches[q],
                                                  row->mesh->element_polygon[e]);
    }
    return !(b->patch_clear || (each && rad_ff_shaft_clear(c->shaft, row->shaft, (size_t)e)));
}

/* Writes the block's part of the row: F_pe = A_e / A_p * f[e - first], f the factor of each
 * element from the patch's point of view (dA_e -> p, visibility included). */
static inline void rad_ff_block_write(const rad_ff_row *row, const rad_ff_block *b,
                                      const double *f, float *out) {
    for (long e = b->first; e < b->last; ++e)
        out[e] = (float)(row->mesh->element_area[e] * row->inverse_area * f[e - b->first]);
}

/* ------------------------------------------------------------------------------------------- */


#endif
