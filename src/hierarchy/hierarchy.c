/* hierarchy.c - quadtrees over the input polygons, links between their nodes, the refinement
 * oracle and the gather/push-pull solve of hierarchical radiosity (Hanrahan, Salzman &
 * Aupperle 1991). See hierarchy.h for the method and docs/hierarchical.md for the parameters. */
#include "hierarchy/hierarchy.h"
#include "hierarchy/source_kernel.h"

#include "formfactor/geometric.h"
#include "core/sampler.h"
#include "formfactor/pair.h"
#include "mesh/roots.h"
#include "scene/camera.h"
#include "scene/rays.h"
#include "scene/scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEFAULT_LINK_ERROR RAD_HIER_DEFAULT_LINK_ERROR
#define DEFAULT_MIN_AREA 1e-6
#define MAX_DEPTH 24
/* Polygon links test visibility with shaft culling first (make_link) on scenes of at most this
 * many occluders (polygons gathered by plane, formfactor/shaft.c): each test visits every
 * occluder. */
#define SHAFT_OCCLUDERS 64
#define PARALLEL_MIN 256 /* loops shorter than this run on one thread */
#define LEAF_CLUSTER 4   /* roots in a leaf cluster, at most */
#define UNKNOWN_ERROR FLT_MAX /* the bound of a link that must be refined before it is trusted */
#define NOT_ESTIMATED -1.0f /* the factor of a link made without its estimate */
#define PARTIAL_BATCHES 6 /* sets of 16 visibility rays for a partly hidden polygon link (the first decides;
                            * 4 before: Sponza's mean swung by 2 points between seeds, see jackknife()) */
#define SEEN_BATCHES 3      /* ... whose deciding set saw most of the source (MOSTLY_SEEN): two fresh */
#define MOSTLY_SEEN 0.9     /* the kernel-weighed share of the deciding set's rays that were seen */
#define EMITTER_BATCHES 24  /* ... whose source polygon emits, however much of it the deciding set saw:
                             * with PARTIAL_BATCHES Sponza's walls under the sky took 1301-1381
                             * units of power over seeds 0-3 and its image mean swung 1.2 points
                             * (docs/hierarchical.md, "sponza3: the sky's partly hidden links") */

typedef double rgb[3];

/* fmax and fmin as glibc's x86-64 libm gives them (the second argument when the two compare
 * equal, the other one when one is NaN), inline: the compiler calls libm for fmax and fmin
 * (their NaN rule), and those calls through the PLT were 2% of the office's solve, most of
 * them in the oracle, the links' bounds and the walks. */
static inline double larger(double a, double b) { return a > b || b != b ? a : b; }
static inline double smaller(double a, double b) { return a < b || b != b ? a : b; }

/* What one cluster link's own rays saw of its source (issue #16): the members its counted set of
 * sampled pairs ended on, each weighed by what its visible pairs added to the link's form
 * factor (V P_r P_s / r^2), normalised to sum 1. The link sends sum weight B_member, re-read
 * every gathering round, so what it carries is what its factor was estimated over; the
 * exposure-weighted mean (source_radiosity) gave exposed members more weight than a given
 * link's rays saw them with, and the closed office 20000 absorbed 5.5% more than it emitted
 * (docs/hierarchical.md, "The closed office's energy"). */
typedef rad_hier_link_sample link_sample; /* weights in SAMPLE_UNIT */
#define SAMPLE_UNIT (1.0 / 65534)
#define NO_SAMPLE RAD_HIER_NO_SAMPLE

/* What the oracle and the form factors need of a cluster (node cluster_first + i). */
typedef struct cluster_info {
    /* What every link with the cluster at one end reads first, together (two cache lines). */
    rad_vec3 centre;
    double radius;         /* of the bounding sphere about the box's centre */
    double axis_area[6];   /* sum over members of A max(0, +n_x), A max(0, -n_x), ... y, z */
    rad_vec3 normal_sum;   /* sum over members of A n */
    double reflectance;    /* the largest member reflectance (any channel) */
    rad_vec3 lo, hi;       /* the box */
    uint32_t parent;       /* the parent cluster's node, or RAD_HIER_NO_NODE for the top */
    float reflected;       /* the largest reflected radiosity (radiosity minus its own emission,
                              any channel) of a member root, as of the last refinement
                              (brightest_members); in the padding after parent */
    double brightest;      /* the largest radiosity (any channel) of a member root, as of the
                              last refinement (brightest_members) */
} cluster_info;

/* The cluster tree as the sampling walks read it, compact (two clusters to a cache line): a
 * cluster's signed-axis areas as floats and where its children are. An internal cluster's two
 * children are clusters `first` and `first + 1` (numbered from cluster_first); a leaf cluster's
 * `count` children are the roots `first` .. (their area and normal in a root_walk each). */
typedef struct walk_cluster {
    float axis_area[6];
    uint32_t first;
    uint16_t count;
    uint16_t leaf;
} walk_cluster;

typedef struct walk_root {
    float area, normal[3];
} walk_root;

/* A node's bounding sphere (node_centre). */
typedef struct node_shape {
    rad_vec3 centre;
    double radius;
} node_shape;

struct rad_hier {
    rad_context *ctx;
    uint32_t salt; /* from the context's seed, added to every link's stream (link_hash); 0 for seed 0 */
    const rad_scene *scene;
    rad_rays *rays;
    rad_ff_shaft *shaft; /* shaft culling for polygon links (make_link); NULL on large scenes */
    rad_hier_node *nodes;
    size_t node_count, node_capacity, root_count;
    uint32_t *polygon_root_first, *polygon_root_count; /* into polygon_roots */
    uint32_t *polygon_roots;      /* root nodes, grouped by polygon */
    uint32_t *root_parent;        /* each root's leaf cluster */
    cluster_info *clusters;
    size_t cluster_first, cluster_count; /* cluster nodes are cluster_first .. + cluster_count */
    rgb *cluster_down;            /* irradiance pushed down to each cluster's members */
    walk_cluster *walk;           /* per cluster, aligned to 64 bytes within walk_memory */
    walk_root *root_walk;         /* per root */
    void *walk_memory;
    int no_clusters;
    rgb *reflectance, *emission; /* per polygon */
    rad_vec3 *normal;            /* per polygon */
    rad_hier_link *links;
    size_t link_count;
    link_sample *samples; /* rad_hier_link.sample indexes it */
    size_t sample_count, sample_capacity;
    uint32_t *free_samples; /* slots of samples whose links were refined, to be used again
                               (sample_capacity of them) */
    size_t free_count;
    size_t samples_new;   /* samples kept since order_samples last put them in link order */
    rgb *root_radiosity;  /* per root, as pull_clusters last read it: what link samples send */
    double *sends; /* per node (node_capacity of them), what the cluster oracle charges a link
                      from it at: its largest radiosity (any channel), a cluster's brightest
                      member's when larger; set by brightest_members, a split node's children
                      take its own. NULL before the first refinement. */
    node_shape *shape; /* per node (node_capacity of them), its bounding sphere (node_centre),
                          filled for every node at the first refinement and for each split's
                          children by split_into; NULL before. */
    /* Links are sorted by receiver: group g's links are receivers' group_first[g] .. [g+1]. */
    size_t group_count;
    size_t *group_first;
    double threshold; /* absolute power: link_error times the power emitted */
    double emission_max, emitted_power;
    double radiosity_cap; /* no radiosity exceeds it: emission_max / (1 - the largest
                             reflectance); 0 when no such bound is known (cheap_link) */
    double min_area;  /* absolute */
    int source_depth; /* rad_hier_options.source_depth */
    rad_hier_kernel_cache kernel; /* its weights, kept for the rounds of one rad_hier_solve */
    rad_hier_stats stats;
    /* Light besides the materials' emission (rad_hier_options.light): per node, NULL without. */
    void (*light_fn)(void *user, uint32_t polygon, const rad_vec3 *corners, int count,
                     uint64_t stream, double out[3], double *spread);
    void *light_user;
    rgb *light;
    float *light_spread; /* per node: rad_hier_options.light's spread */
    /* Importance (Smits, Arvo & Salesin 1992), NULL without a view (rad_hier_set_view): where
     * the camera's pixels meet the surfaces, and per node A Y (Y the importance of unit
     * radiosity there, summed over the node's leaves), the emitted part A R of a leaf, and Y
     * gathered over the transposed links. Per cluster: what its sending links gathered per
     * signed axis, and Z = sum rho A Y of its members. */
    uint32_t *hit_polygon;
    rad_vec3 *hit_point;
    size_t hit_count;
    double hit_share;       /* of the image, per hit */
    double *importance, *importance_emitted, *importance_gathered;
    double (*cluster_axis_importance)[6], (*cluster_down_importance)[6], *cluster_z;
    double importance_mean; /* sum A Y over the roots over their area: the oracle's unit */
    /* A refinement stopped by Ctrl-C between two of its passes (rad_hier_refining): the links
     * are the ones it had passed (refine_kept of them, in the order it kept them) followed by
     * the new ones it had made and not yet asked the oracle about; the next rad_hier_refine
     * goes on from there. The receiver groups are not built meanwhile. */
    int refining;
    size_t refine_kept;
    /* The importance rounds of the last solve were stopped (Ctrl-C) after the light's had
     * converged: the next solve goes on with importance only. */
    int importance_unfinished;
};

static int threads(const rad_hier *h) { return rad_thread_count(h->ctx); }
static rad_status solve_importance(rad_hier *h, double tolerance, int max_rounds);
static uint32_t leaf_at(const rad_hier *h, uint32_t polygon, rad_vec3 x);

/* ---- Nodes ------------------------------------------------------------------------------- */

static double corners_area(const rad_vec3 *c, int count) {
    if (count == 3) return 0.5 * v3_length(v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0])));
    return 0.5 * v3_length(v3_cross(v3_sub(c[2], c[0]), v3_sub(c[3], c[1])));
}

static rad_status reserve_nodes(rad_hier *h, size_t extra) {
    if (h->node_count + extra <= h->node_capacity) return RAD_OK;
    size_t wanted = h->node_capacity ? h->node_capacity : 64;
    while (wanted < h->node_count + extra) wanted *= 2;
    rad_hier_node *grown = rad_realloc(h->ctx, h->nodes, wanted, sizeof *grown);
    if (!grown) return RAD_ERROR_NO_MEMORY;
    h->nodes = grown;
    /* The per-node arrays the hierarchy keeps (only those it has) grow with the nodes. */
#define GROW_PER_NODE(array)                                                   \
    if (h->array) {                                                            \
        void *more = rad_realloc(h->ctx, h->array, wanted, sizeof *h->array);  \
        if (!more) return RAD_ERROR_NO_MEMORY;                                 \
        h->array = more;                                                       \
    }
    GROW_PER_NODE(light)
    GROW_PER_NODE(light_spread)
    GROW_PER_NODE(sends)
    GROW_PER_NODE(shape)
    GROW_PER_NODE(importance)
    GROW_PER_NODE(importance_emitted)
    GROW_PER_NODE(importance_gathered)
#undef GROW_PER_NODE
    h->node_capacity = wanted;
    return RAD_OK;
}

static rad_vec3 surface_centre(const rad_hier_node *n) {
    rad_vec3 sum = v3(0, 0, 0);
    for (int k = 0; k < n->corner_count; ++k) sum = v3_add(sum, n->corner[k]);
    return v3_scale(sum, 1.0 / n->corner_count);
}

/* A polygon node's bounding sphere: its corners' about their centroid. */
static node_shape surface_shape(const rad_hier_node *n) {
    node_shape shape = {surface_centre(n), 0};
    for (int k = 0; k < n->corner_count; ++k)
        shape.radius = larger(shape.radius, v3_length(v3_sub(n->corner[k], shape.centre)));
    return shape;
}

static void init_node(rad_hier *h, rad_hier_node *n, const rad_vec3 *c, int count,
                      uint32_t polygon, uint32_t root, int depth) {
    memset(n, 0, sizeof *n);
    for (int k = 0; k < count; ++k) n->corner[k] = c[k];
    n->corner_count = (uint8_t)count;
    n->area = corners_area(c, count);
    n->polygon = polygon;
    n->root = root;
    n->first_child = RAD_HIER_NO_NODE;
    n->child_count = 0;
    n->depth = (uint8_t)depth;
    memcpy(n->radiosity, h->emission[polygon], sizeof n->radiosity);
}

/* Splits leaf `index` into four made at nodes first .. first + 3 (reserved): a quad at its edge
 * midpoints and centre, a triangle at its edge midpoints (the fourth child is the middle
 * triangle). Children keep the winding. Touches only the leaf and those four, so leaves may
 * be split in parallel. */
static void split_into(rad_hier *h, uint32_t index, uint32_t first) {
    rad_hier_node parent = h->nodes[index];
    const rad_vec3 *c = parent.corner;
    rad_vec3 child[4][4];
    int count = parent.corner_count;
    if (count == 4) {
        rad_vec3 m01 = v3_lerp(c[0], c[1], 0.5), m12 = v3_lerp(c[1], c[2], 0.5);
        rad_vec3 m23 = v3_lerp(c[2], c[3], 0.5), m30 = v3_lerp(c[3], c[0], 0.5);
        rad_vec3 m = v3_scale(v3_add(v3_add(c[0], c[1]), v3_add(c[2], c[3])), 0.25);
        const rad_vec3 q[4][4] = {{c[0], m01, m, m30}, {m01, c[1], m12, m},
                                  {m, m12, c[2], m23}, {m30, m, m23, c[3]}};
        memcpy(child, q, sizeof child);
    } else {
        rad_vec3 m01 = v3_lerp(c[0], c[1], 0.5), m12 = v3_lerp(c[1], c[2], 0.5);
        rad_vec3 m20 = v3_lerp(c[2], c[0], 0.5);
        const rad_vec3 t[4][4] = {{c[0], m01, m20, m20}, {m01, c[1], m12, m12},
                                  {m20, m12, c[2], c[2]}, {m12, m20, m01, m01}};
        memcpy(child, t, sizeof child);
    }
    for (int k = 0; k < 4; ++k) {
        init_node(h, &h->nodes[first + k], child[k], count, parent.polygon, parent.root,
                  parent.depth + 1);
        if (h->light) { /* light_nodes() computes the children's own */
            memcpy(h->light[first + k], h->light[index], sizeof(rgb));
            h->light_spread[first + k] = 0;
        }
        memcpy(h->nodes[first + k].radiosity, parent.radiosity, sizeof parent.radiosity);
        if (h->sends) h->sends[first + k] = h->sends[index]; /* the same radiosity */
        if (h->shape) h->shape[first + k] = surface_shape(&h->nodes[first + k]);
        if (h->importance) /* the parent's importance per unit area, until the next solve */
            h->importance[first + k] =
                parent.area > 0 ? h->importance[index] * h->nodes[first + k].area / parent.area : 0;
    }
    h->nodes[index].first_child = first;
    h->nodes[index].child_count = 4;
}

/* Splits a leaf into four new nodes (split_into); a node already split is left alone. */
static rad_status subdivide(rad_hier *h, uint32_t index) {
    if (h->nodes[index].first_child != RAD_HIER_NO_NODE) return RAD_OK;
    rad_status status = reserve_nodes(h, 4);
    if (status) return status;
    split_into(h, index, (uint32_t)h->node_count);
    h->node_count += 4;
    h->stats.leaves += 3;
    return RAD_OK;
}

/* The light (rad_hier_options.light) of nodes first .. node_count - 1, in parallel (each node
 * its own slot and its own index as the sampling stream). */
static void light_nodes(rad_hier *h, size_t first) {
    if (!h->light) return;
    long last = (long)h->node_count;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (last - (long)first >= 64)
    for (long i = (long)first; i < last; ++i) {
        rad_hier_node *n = &h->nodes[i];
        if (n->corner_count == 0) continue; /* a cluster */
        double spread = 0;
        h->light_fn(h->light_user, n->polygon, n->corner, n->corner_count, (uint64_t)i,
                    h->light[i], &spread);
        h->light_spread[i] = (float)spread;
    }
}

/* A node's quadrature points: the pair kernel's rule (2 x 2 Gauss in a quad's bilinear
 * parameters, the three-point rule (2/3, 1/6, 1/6) of a triangle). */
static int quadrature_points(const rad_hier_node *n, rad_vec3 *out) {
    const rad_ff_piece piece = {n->corner, n->corner_count, v3(0, 0, 0)}; /* the rule needs no normal */
    return rad_ff_piece_quadrature(&piece, out);
}

/* A hash of a link's two ends and a counter, for its visibility points: deterministic (the same
 * for any thread count) but different for every pair. */
static uint32_t pair_hash(uint32_t receiver, uint32_t source, uint32_t k) {
    return (uint32_t)(rad_mix64(((uint64_t)receiver << 32 | source) ^ rad_mix64(k + 1)) >> 32);
}

/* The stream of a link's pseudo-random choices (visibility points, member walks): seeded by the
 * pair and by the context's seed, as every random choice (radiosity.h), so a run's result can be
 * judged over seeds. Seed 0 gives the bits it gave before the seed counted. */
static uint32_t link_hash(const rad_hier *h, uint32_t receiver, uint32_t source, uint32_t k) {
    return pair_hash(receiver, source, k + h->salt);
}

static double unit(uint32_t bits) { return (bits >> 8) * (1.0 / 16777216.0); }

/* Four points spread over a source node for visibility rays, one in each quarter (a quad's 2 x 2
 * cells in its bilinear parameters, a triangle's four midpoint triangles), jittered by `seed`.
 * Fixed points (the quadrature's) see a large source through a small opening all or nothing,
 * the same way for every receiver: the sky quad over Sponza's open roof was hidden from most of
 * the atrium by its four Gauss points. Jittered per pair, the visible fraction is unbiased.
 * Receivers keep their quadrature points (jittered there too, neighbouring tiles under a box
 * differed by 10% from run-to-run noise). */
static rad_vec3 visibility_point(const rad_hier_node *n, uint32_t seed, int k) {
    const rad_vec3 *c = n->corner;
    uint32_t bits = pair_hash(seed, (uint32_t)k, 0x5bd1e995u);
    double a = unit(bits), b = unit(pair_hash(bits, (uint32_t)k, 0x27d4eb2fu));
    if (n->corner_count == 4) {
        double u = 0.5 * ((k & 1) + a), v = 0.5 * ((k >> 1) + b);
        return v3_lerp(v3_lerp(c[0], c[1], u), v3_lerp(c[3], c[2], u), v);
    }
    /* A uniform point in midpoint triangle k (the corners' three, then the middle one). */
    rad_vec3 m01 = v3_lerp(c[0], c[1], 0.5), m12 = v3_lerp(c[1], c[2], 0.5);
    rad_vec3 m20 = v3_lerp(c[2], c[0], 0.5);
    const rad_vec3 t[4][3] = {{c[0], m01, m20}, {m01, c[1], m12}, {m20, m12, c[2]},
                              {m12, m20, m01}};
    if (a + b > 1) a = 1 - a, b = 1 - b;
    return v3_add(t[k][0], v3_add(v3_scale(v3_sub(t[k][1], t[k][0]), a),
                                  v3_scale(v3_sub(t[k][2], t[k][0]), b)));
}

static int visibility_points(const rad_hier_node *n, uint32_t seed, rad_vec3 *out) {
    for (int k = 0; k < 4; ++k) out[k] = visibility_point(n, seed, k);
    return 4;
}

/* ---- Links ------------------------------------------------------------------------------- */

/* Nonzero when some corner of `n` lies strictly in front of the plane through `p` with normal
 * `normal`. */
static int any_in_front(const rad_hier_node *n, rad_vec3 p, rad_vec3 normal) {
    for (int k = 0; k < n->corner_count; ++k)
        if (v3_dot(normal, v3_sub(n->corner[k], p)) > 0) return 1;
    return 0;
}

/* The visible fraction of the rays from every point x (rn of them) to every point y (sn; at
 * most 16 rays); *partial is set when some ray is blocked. With `seen` (16 slots), which
 * pairs were visible, x-major. */
static double visible_pairs(const rad_hier *h, const rad_vec3 *x, int rn, const rad_vec3 *y,
                            int sn, int *partial, uint8_t *seen) {
    rad_vec3 a[16] = {{0, 0, 0}}, b[16] = {{0, 0, 0}};
    uint8_t occluded[16];
    int count = 0;
    for (int i = 0; i < rn; ++i)
        for (int j = 0; j < sn; ++j) {
            a[count] = x[i];
            b[count] = y[j];
            ++count;
        }
    rad_rays_occluded_batch(h->rays, a, b, (size_t)count, occluded);
    int visible = 0;
    for (int i = 0; i < count; ++i) {
        visible += !occluded[i];
        if (seen) seen[i] = !occluded[i];
    }
    *partial = visible < count;
    return (double)visible / count;
}


static int decide(const rad_hier *h, const rad_hier_link *link, double *relative);

/* The point-to-point kernel cos cos / r^2 (without pi and the areas) of every pair x[i] -> y[j]
 * (receiver normal nr, source normal ns), added to *all, and of the pairs seen[i * sn + j] to
 * *visible: one set of a partly hidden link's rays, weighed. */
static void kernel_weighed(const rad_vec3 *x, int rn, const rad_vec3 *y, int sn, rad_vec3 nr,
                           rad_vec3 ns, const uint8_t *seen, double *all, double *visible) {
    for (int i = 0; i < rn; ++i)
        for (int j = 0; j < sn; ++j) {
            rad_vec3 ray = v3_sub(y[j], x[i]);
            double r2 = v3_dot(ray, ray);
            double k = larger(0, v3_dot(nr, ray)) * larger(0, -v3_dot(ns, ray)) / (r2 * r2);
            *all += k;
            *visible += seen[i * sn + j] ? k : 0;
        }
}

/* The kernel-weighted visible fraction `ratio` = visible / all over `m` independent sets of
 * rays (set j's sums set_all[j], set_visible[j]), with the ratio's bias taken out by the
 * jackknife (Quenouille 1956): m R - (m - 1) times the mean of the ratios leaving one set out,
 * which removes the bias's 1/m term. The ratio is biased low when a few rays see a small part
 * of the source where the kernel is large: Sponza's image was 1.4% darker with 3 fresh sets
 * than with 7 (docs/hierarchical.md, "Sponza at three seeds"). The jackknife adds variance
 * (with 3 sets Sponza's seed 0 came out +1.1% and its worst block +12%), which 5 sets keep
 * small: Sponza's mean within 0.6% at seeds 0, 1, 2. Clamped to [0, 1]; a ratio of 0 or 1
 * (every ray blocked or none) is kept as it is. */
static double jackknife(double ratio, double all, double visible, const double *set_all,
                        const double *set_visible, int m) {
    if (m < 2 || !(visible > 0) || !(visible < all)) return ratio;
    double left_out = 0;
    for (int j = 0; j < m; ++j) {
        double rest = all - set_all[j];
        if (!(rest > 0)) return ratio;
        left_out += (visible - set_visible[j]) / rest;
    }
    return smaller(1, larger(0, m * ratio - (m - 1) * left_out / m));
}

/* The link receiver <- source: its form factor and error bound. Returns 0 when no light can
 * pass (the two face away from each other). With `may_skip`, a partly hidden link that the
 * oracle refines in this pass whatever its visible fraction (its error is at least its whole
 * unoccluded factor) does not cast the further PARTIAL_BATCHES - 1 sets: its factor is then
 * NOT_ESTIMATED, as for cluster links (make_cluster_link). The decision is the one the full
 * link gets (the fraction only adds to the error, and which end is split depends on partial
 * visibility, not on the error's size), so the results are the same. */
static int make_link(const rad_hier *h, uint32_t receiver, uint32_t source, rad_hier_link *out,
                     int may_skip) {
    const rad_hier_node *r = &h->nodes[receiver], *s = &h->nodes[source];
    if (r->polygon == s->polygon) return 0;
    rad_vec3 nr = h->normal[r->polygon], ns = h->normal[s->polygon];
    if (!any_in_front(s, r->corner[0], nr) || !any_in_front(r, s->corner[0], ns)) return 0;
    rad_vec3 x[8], y[4];
    int rn = quadrature_points(r, x), sn = quadrature_points(s, y);
    /* The spread also looks at the corners (pulled in a little, off neighbouring planes): the
     * kernel peaks at edges shared with the source, where the quadrature points see least. */
    rad_vec3 centre = v3_scale(v3_add(v3_add(r->corner[0], r->corner[1]),
                                      v3_add(r->corner[2], r->corner[r->corner_count - 1])), 0.25);
    if (r->corner_count == 3)
        centre = v3_scale(v3_add(v3_add(r->corner[0], r->corner[1]), r->corner[2]), 1.0 / 3);
    for (int k = 0; k < r->corner_count; ++k) x[rn + k] = v3_lerp(r->corner[k], centre, 0.01);
    /* Lambert's contour integral from each of those points to the source polygon, all in one
     * call (its front from the corners' order, as rad_ff_point_polygon takes it). */
    double f[8];
    rad_ff_point_polygon_front_many(x, rn + r->corner_count, nr, s->corner, s->corner_count,
                                    rad_ff_polygon_front(s->corner, s->corner_count), f);
    double sum = 0, lo = INFINITY, hi = 0;
    for (int i = 0; i < rn; ++i) {
        sum += f[i];
        lo = smaller(lo, f[i]);
        hi = larger(hi, f[i]);
    }
    double form_factor = sum / rn;
    if (!(form_factor > 0)) return 0;
    for (int k = 0; k < r->corner_count; ++k) {
        lo = smaller(lo, f[rn + k]);
        hi = larger(hi, f[rn + k]);
    }
    /* Rays that all hit something do not prove the pair hidden (a sliver of the receiver may
     * see past the occluder): such a link carries nothing but keeps its whole factor as its
     * error, so the oracle refines it where it matters. The rays leave from jittered points of
     * the receiver too, one in each quarter, not from its quadrature points: fixed points sit
     * where the scene puts them for every link alike. The generated office's floor tiles have
     * theirs in the shadow of their own desk, which covers a small part of the tile, and the
     * floor took 0.88 of the lamps' light (test_desk_shadows: -13%). */
    int partial = 0;
    rad_vec3 xv[4];
    uint8_t seen[16];
    double fraction = 1;
    /* A link that shaft culling proves clear (no polygon can block a segment between its two
     * nodes; small scenes, h->shaft) casts no rays and carries its whole factor: its rays
     * would all arrive, and their kernel-weighed fraction would be 1 (on the Cornell box it
     * was for every clear link: none had its fresh set's kernel all 0). Not quite all arrive:
     * a ray that meets its source's plane at a grazing angle can hit that polygon short of its
     * end point, which made 62 of the 56,939 clear links of the Cornell box (link error 5e-6)
     * partly hidden. Its solve takes a fifth less processor time (0.74 -> 0.57 s); the
     * render's block errors moved by 0.0005 points at most. */
    const int clear = h->shaft && rad_ff_shaft_pair_clear(h->shaft, r->corner, r->corner_count,
                                                          s->corner, s->corner_count);
    if (!clear) {
        rn = visibility_points(r, link_hash(h, receiver, source, 3), xv);
        sn = visibility_points(s, link_hash(h, receiver, source, 2), y);
        fraction = visible_pairs(h, xv, rn, y, sn, &partial, seen);
    }
    out->receiver = receiver;
    out->source = source;
    out->sample = RAD_HIER_NO_NODE;
    if (partial && may_skip) {
        double relative;
        out->error = (float)-form_factor; /* the least error a partly hidden link can have */
        /* The source's variation counts the visible factor, between 0 and the unoccluded one:
         * skipped only when both ends of that range give the same decision (the decision is
         * monotone in the factor), so it is the one the estimated link would get. */
        out->form_factor = 0;
        int least = decide(h, out, &relative);
        out->form_factor = (float)form_factor;
        if (least && decide(h, out, &relative) == least) {
            out->form_factor = NOT_ESTIMATED;
            return 1;
        }
    }
    if (!clear) {
        /* Weigh the rays by the point-to-point kernel cos cos / r^2: the part of a large source
         * seen through an opening is the part overhead, where the kernel is largest (the sky
         * over Sponza's atrium: the area fraction halved the floor's direct light). The
         * weighted fraction is a ratio of two sums over the same rays, biased low when few rays
         * see a small part of the source with a large kernel (a visible ray's kernel is in both
         * sums), and zero when none does: partly hidden links take PARTIAL_BATCHES - 1 fresh
         * sets (test_opening: a floor under a sky seen through a hole, -11.3% with one set,
         * -2.9% with four; Sponza's links carried 0.88 of the light a Monte Carlo gather of the
         * same leaves finds, docs/hierarchical.md). The first set only decides (as it did for
         * cluster links before hspeed10): given that its 16 rays all arrived, the pair is likelier seen than it is, and
         * taking the whole unoccluded factor then made the office's floor links that saw the
         * lamps unoccluded carry 1.19-1.30 of their light, the closed office 20000 absorb 4.6%
         * more than it emits at link error 2.5e-4, and test_desk_shadows +2.2%. So every link
         * is estimated on fresh sets: one when the first saw everything (which may find it
         * partly hidden after all), PARTIAL_BATCHES - 1 when it did not, SEEN_BATCHES - 1 when
         * it saw at least MOSTLY_SEEN of the source by kernel weight (the ratio's bias is a
         * small-visible-share bias; on main, without the jackknife, two sets instead of four
         * saved 5% of the office's solve, docs/hierarchical.md "seventh session"). */
        double first_all = 0, first_seen = 0;
        if (partial) kernel_weighed(xv, rn, y, sn, nr, ns, seen, &first_all, &first_seen);
        /* A link from an emitter carries the scene's brightest light, and every bounce after
         * it repeats its visibility's noise: its partly hidden links take EMITTER_BATCHES.
         * Not on a small scene's fine leaves (source_depth): there a lamp's light arrives over
         * many small links whose noise averages out, and the hierarchical Cornell render was
         * the same to 0.01 % in every block size (seeds 0, 1) for 8 % more processor time. */
        const double *emission = h->emission[s->polygon];
        int emits = !h->source_depth && (emission[0] > 0 || emission[1] > 0 || emission[2] > 0);
        /* On a small scene's fine leaves (source_depth) a partly hidden link takes SEEN_BATCHES
         * whatever its deciding set saw, for the reason emitters do not take more there: the
         * light arrives over many small links whose noise averages out. The hierarchical
         * Cornell render's mean and block errors came out the same to 0.001 points at seeds 0-3
         * (8x8 0.4268% against 0.4269%) for 4% less processor time (docs/hierarchical.md,
         * "Twenty-second session"). */
        int sets = !partial ? 2
                   : emits ? EMITTER_BATCHES
                   : h->source_depth || first_seen >= MOSTLY_SEEN * first_all ? SEEN_BATCHES
                                                                             : PARTIAL_BATCHES;
        double all = 0, visible = 0, set_all[EMITTER_BATCHES] = {0}, set_visible[EMITTER_BATCHES] = {0};
        for (int batch = 1; batch < sets; ++batch) {
            int blocked;
            rn = visibility_points(r, link_hash(h, receiver, source, 3 + 0x100u * (uint32_t)batch), xv);
            sn = visibility_points(s, link_hash(h, receiver, source, 2 + 0x100u * (uint32_t)batch), y);
            visible_pairs(h, xv, rn, y, sn, &blocked, seen);
            partial |= blocked;
            kernel_weighed(xv, rn, y, sn, nr, ns, seen, &set_all[batch], &set_visible[batch]);
            all += set_all[batch];
            visible += set_visible[batch];
        }
        fraction = all > 0 ? visible / all : 0;
        fraction = jackknife(fraction, all, visible, set_all + 1, set_visible + 1, sets - 1);
    }
    double error = 0.25 * (hi - lo) * fraction + (partial ? form_factor : 0);
    out->form_factor = (float)(form_factor * fraction);
    /* The sign keeps whether the visibility was partial. */
    out->error = (float)(partial ? -error : error);
    return 1;
}

static int can_split(const rad_hier *h, const rad_hier_node *n) {
    return n->area > h->min_area && n->depth < MAX_DEPTH;
}

/* How much the view needs a receiver's light (Smits, Arvo & Salesin 1992): its importance per
 * unit area over the mean of the whole scene's, so that a link's error rho B dF A becomes the
 * error it makes in the image, on the scale of the plain oracle (a view that sees everything
 * alike weighs every link by 1). 1 without a view. */
static double importance_weight(const rad_hier *h, uint32_t receiver) {
    if (!h->importance) return 1;
    double area = h->nodes[receiver].area;
    return area > 0 && h->importance_mean > 0
               ? h->importance[receiver] / area / h->importance_mean
               : 0;
}

/* The oracle: 0 keeps the link, 1 splits its receiver, 2 its source. *relative is its error
 * over the threshold. */
static int decide(const rad_hier *h, const rad_hier_link *link, double *relative) {
    const rad_hier_node *r = &h->nodes[link->receiver], *s = &h->nodes[link->source];
    const double *rho = h->reflectance[r->polygon];
    double carried = 0;
    for (int c = 0; c < 3; ++c) carried = larger(carried, rho[c] * s->radiosity[c]);
    double weight = r->area * importance_weight(h, link->receiver);
    double spread_error = carried * fabs((double)link->error) * weight;
    /* The source's own variation: the link carries its mean, but the receiver may see mostly
     * one side of it (a block's face at the foot of a floor piece that is lit far off and in
     * the block's shadow next to it). For a source larger than its receiver, half the range
     * of its children's radiosity (reflected by the receiver) times the factor. */
    double variation = 0;
    if (s->first_child != RAD_HIER_NO_NODE && s->area > r->area)
        for (int c = 0; c < 3; ++c) {
            double lo = INFINITY, hi = -INFINITY;
            for (uint32_t k = 0; k < s->child_count; ++k) {
                double b = h->nodes[s->first_child + k].radiosity[c];
                lo = smaller(lo, b);
                hi = larger(hi, b);
            }
            variation = larger(variation, 0.5 * rho[c] * (hi - lo));
        }
    /* A link made without its estimate (NOT_ESTIMATED) was skipped because its decision is
     * the same for any factor (make_link): 0 stands for it. */
    double variation_error = variation * larger(0.0, (double)link->form_factor) * weight;
    double error = spread_error + variation_error;
    *relative = error / h->threshold;
    if (!(error > h->threshold)) return 0;
    int partial = link->error < 0;
    int split_r = can_split(h, r), split_s = can_split(h, s);
    /* A link wrong mostly for its source's variation takes the source's children. */
    if (variation_error > spread_error && s->first_child != RAD_HIER_NO_NODE) return 2;
    /* The receiver is split first: that is what puts leaves at shadow edges and contacts.
     * A receiver already much smaller than its source passes a partly hidden link to the
     * source's children instead (the penumbra is the source's to resolve). */
    if (split_r && !(partial && split_s && s->area > r->area)) return 1;
    if (partial && split_s) return 2;
    return 0;
}

/* ---- Cluster links (Smits, Arvo & Greenberg 1994; Sillion 1995) -------------------------- */

static int is_cluster(const rad_hier_node *n) { return n->corner_count == 0; }

/* Whether node `index` is a cluster, from its number alone (the clusters are numbered
 * cluster_first .. + cluster_count, after the roots and before every split node). */
static int cluster_index(const rad_hier *h, uint32_t index) {
    return (size_t)index - h->cluster_first < h->cluster_count;
}

static const cluster_info *info(const rad_hier *h, uint32_t index) {
    return &h->clusters[index - h->cluster_first];
}

/* A node's bounding sphere: the box's for a cluster, the corners' about the centroid for a
 * polygon node (surface_shape). */
static node_shape shape_of(const rad_hier *h, uint32_t index) {
    if (is_cluster(&h->nodes[index])) return (node_shape){info(h, index)->centre, info(h, index)->radius};
    return surface_shape(&h->nodes[index]);
}

/* shape_of, read from h->shape once the first refinement filled it. */
static rad_vec3 node_centre(const rad_hier *h, uint32_t index, double *radius) {
    node_shape shape = h->shape ? h->shape[index] : shape_of(h, index);
    *radius = shape.radius;
    return shape.centre;
}

/* The projected area of a node toward unit direction w, and bounds on it over every direction
 * within `spread` radians of w (a cosine moves by at most the angle). A cluster's estimate sums
 * its members' areas per signed axis weighted by |w_a|: an upper bound on sum A max(0, n.w),
 * exact when every member's normal lies in w's octant; its lower bound is (sum A n).w. */
typedef struct projection {
    double estimate, lower, upper;
} projection;

static projection project(const rad_hier *h, uint32_t index, rad_vec3 w, double spread) {
    const rad_hier_node *n = &h->nodes[index];
    projection p;
    if (!is_cluster(n)) {
        double c = v3_dot(h->normal[n->polygon], w);
        p.estimate = n->area * larger(0, c);
        p.lower = n->area * larger(0, c - spread);
        p.upper = n->area * smaller(1, larger(0, c + spread));
        return p;
    }
    const cluster_info *ci = info(h, index);
    const double *a = ci->axis_area;
    p.estimate = fabs(w.x) * a[w.x < 0] + fabs(w.y) * a[2 + (w.y < 0)] + fabs(w.z) * a[4 + (w.z < 0)];
    p.upper = smaller(n->area, p.estimate + n->area * spread);
    p.lower = larger(0, v3_dot(ci->normal_sum, w) - n->area * spread);
    if (p.lower > p.estimate) p.lower = p.estimate;
    return p;
}

/* Points on a node's surfaces for visibility rays toward unit direction w, from `seed`, one in
 * each of the strata first, first + stride, ... (`walks` of them, at most WALKS; stratum k is
 * quarter k of the node or member drawn, and its point is the same whichever others are asked
 * for): a polygon node's jittered points; for a cluster,
 * points on members reached by a fixed pseudo-random walk (seeded by the pair) down it that
 * picks each child in proportion to its projected area toward w (members facing away, whose own
 * bodies would block the rays, are not sampled), with the member (members[k]) and the
 * probability the walk drew it with (probability[k]).
 *
 * A `slack` (s) above 0 widens "toward w": a member with f = n.w is drawn
 * in proportion to A f when f >= s, A (f + s)^2 / (4 s) when -s < f < s (the mean of max(0,
 * n.u) over directions u spread about w, roughly; it meets A f at f = s with the same slope),
 * 0 below; a cluster in proportion to the same weight of each signed axis's component of w
 * times its area along that axis (axis_area), which is not 0 when a member's is (a unit normal
 * with n.w > -s has some axis a with sign(n_a) w_a > -s), and is the projected area when s is
 * 0. The rays between the link's
 * two bounding spheres leave w by up to the angle the spheres subtend, so a member with f <= 0
 * faces some of them. Drawn toward w alone, such a member had probability 0 while the link's
 * factor counts what each drawn member adds (member_weight, unbiased only over members that
 * can be drawn): on Sponza the links from clusters carried 0.99 of a Monte Carlo gather of the
 * same leaves and the image was 0.45-1.07% dark at seeds 0-2, the closed office 20000's 0.975
 * (docs/hierarchical.md, "sponza3"). A cluster receiver's points keep the plain draw (its
 * links are opened, hspeed10). The walk reads the compact tables
 * (walk_cluster, walk_root): one cache line a level, where the nodes and cluster_info cost three
 * (the walk was two fifths of the solve at 10^6). The walks go down together, a level each in
 * turn: each level's read waits for the level above, so walks taken one after the other wait
 * for every miss in a row, while walks taken in turn wait for theirs side by side (the walks
 * were a quarter of the 10^6 office's samples). */
#define WALKS 4
/* A member's weight per unit area at facing f = n.w, widened by s (above): f from s up, the
 * quadratic (f + s)^2 / (4 s) between -s and s, 0 below; max(0, f) when s is 0. */
static inline float facing_weight(float f, float s) {
    if (f >= s) return f > 0 ? f : 0;
    return f > -s ? (f + s) * (f + s) / (4 * s) : 0;
}

static void sample_points(const rad_hier *h, uint32_t index, rad_vec3 w, uint32_t seed,
                          rad_vec3 *out, uint32_t *members, double *probability, float slack,
                          int walks, int first, int stride) {
    if (!is_cluster(&h->nodes[index])) {
        for (int k = 0; k < walks; ++k)
            out[k] = visibility_point(&h->nodes[index], seed, first + stride * k);
        return;
    }
    const float wx = (float)fabs(w.x), wy = (float)fabs(w.y), wz = (float)fabs(w.z);
    const int sx = w.x < 0, sy = 2 + (w.y < 0), sz = 4 + (w.z < 0);
    /* A cluster's weight with slack is linear in its signed-axis areas: each axis's factor,
     * the same at every level, once. */
    const float widened[6] = {facing_weight((float)w.x, slack), facing_weight(-(float)w.x, slack),
                              facing_weight((float)w.y, slack), facing_weight(-(float)w.y, slack),
                              facing_weight((float)w.z, slack), facing_weight(-(float)w.z, slack)};
    const walk_cluster *at[WALKS];
    uint32_t state[WALKS], root[WALKS];
    float chance[WALKS];
    for (int k = 0; k < walks; ++k) {
        chance[k] = 1;
        state[k] = pair_hash(seed, index, (uint32_t)(first + stride * k));
        at[k] = &h->walk[index - h->cluster_first];
        root[k] = RAD_HIER_NO_NODE;
    }
    for (int left = walks; left > 0;)
        for (int k = 0; k < walks; ++k) {
            if (root[k] != RAD_HIER_NO_NODE) continue;
            const walk_cluster *c = at[k];
            state[k] = state[k] * 1664525u + 1013904223u;
            float weight[LEAF_CLUSTER > 2 ? LEAF_CLUSTER : 2], total = 0;
            uint32_t count = c->count <= LEAF_CLUSTER ? c->count : LEAF_CLUSTER;
            for (uint32_t i = 0; i < count; ++i) {
                if (c->leaf) {
                    const walk_root *r = &h->root_walk[c->first + i];
                    float facing = r->normal[0] * (float)w.x + r->normal[1] * (float)w.y +
                                   r->normal[2] * (float)w.z;
                    weight[i] = r->area * facing_weight(facing, slack);
                } else {
                    const float *a = h->walk[c->first + i].axis_area;
                    if (slack > 0)
                        weight[i] = a[0] * widened[0] + a[1] * widened[1] + a[2] * widened[2] +
                                    a[3] * widened[3] + a[4] * widened[4] + a[5] * widened[5];
                    else
                        weight[i] = wx * a[sx] + wy * a[sy] + wz * a[sz];
                }
                total += weight[i];
            }
            uint32_t pick = 0;
            if (total > 0 && c->count <= LEAF_CLUSTER) {
                float u = (float)((state[k] >> 8) * (1.0 / 16777216.0)) * total;
                for (; pick + 1 < count && u >= weight[pick]; ++pick) u -= weight[pick];
                chance[k] *= weight[pick] / total;
            } else {
                pick = (state[k] >> 16) % c->count;
                chance[k] /= (float)c->count;
            }
            if (c->leaf) {
                root[k] = c->first + pick;
                __builtin_prefetch(&h->nodes[root[k]]);
                --left;
            } else {
                /* What this walk reads next is known now: ask for it while the others go on. */
                const walk_cluster *next = &h->walk[c->first + pick];
                at[k] = next;
                if (next->leaf) __builtin_prefetch(&h->root_walk[next->first]);
                else __builtin_prefetch(&h->walk[next->first]);
            }
        }
    for (int k = 0; k < walks; ++k) {
        out[k] = visibility_point(&h->nodes[root[k]], state[k], first + stride * k);
        members[k] = root[k];
        probability[k] = chance[k];
    }
}

/* A sampled member's projected area along `ray` (from the other end toward the member, length
 * `length`) over the probability the walk drew it with: its mean over the draws is the
 * cluster's projected area along that ray, so the mean over the pairs of V P_r P_s / (pi r^2
 * A_r) is the form factor itself. The walk draws members by their projected area toward the
 * centres' direction; weighing every ray by the cluster's projected area toward that direction
 * instead (its far-field limit) made an icosahedron over a floor 7.5% too bright at the default
 * link error and 21% at 1e-2 (test_hierarchy, test_cluster_form_factors). */
static double member_weight(const rad_hier *h, uint32_t member, double probability,
                            rad_vec3 ray, double length) {
    const rad_hier_node *m = &h->nodes[member];
    double c = -v3_dot(h->normal[m->polygon], ray) / length;
    return c > 0 && probability > 0 ? m->area * c / probability : 0;
}

/* The oracle for a link with a cluster at one end or both (below); with pick_end 0 it only
 * says whether the link is refined (nonzero), not which end. */
static int cluster_oracle(const rad_hier *h, const rad_hier_link *link, double *relative,
                          int pick_end);

/* Whether the oracle refines a cluster link whose bound is `error` (sets link->error to it):
 * its bound fails, or its receiver is a cluster (which only sends) and the source is lit.
 * Partial visibility only adds to the bound, so a link refined with a smaller bound is
 * refined with any larger one. */
static int refined_anyway(const rad_hier *h, rad_hier_link *link, double error) {
    double relative;
    link->error = (float)smaller(error, UNKNOWN_ERROR);
    return cluster_oracle(h, link, &relative, 0) != 0;
}

/* The corner of a cluster's box farthest along `normal`. */
static rad_vec3 farthest_along(const cluster_info *ci, rad_vec3 normal) {
    return v3(normal.x > 0 ? ci->hi.x : ci->lo.x, normal.y > 0 ? ci->hi.y : ci->lo.y,
              normal.z > 0 ? ci->hi.z : ci->lo.z);
}

/* Nonzero when `surface` is a polygon node, `cluster` a cluster, and no corner of the
 * cluster's box lies strictly in front of the surface's plane (the test any_in_front makes for
 * two polygons): no member can reach the surface's front, nor be reached from it. */
static int cluster_behind(const rad_hier *h, uint32_t surface, uint32_t cluster) {
    const rad_hier_node *n = &h->nodes[surface];
    if (is_cluster(n) || !cluster_index(h, cluster)) return 0;
    const cluster_info *ci = info(h, cluster);
    rad_vec3 normal = h->normal[n->polygon];
    return !(v3_dot(normal, v3_sub(farthest_along(ci, normal), n->corner[0])) > 0);
}

/* Nonzero when no member of cluster `cluster` faces any point of node `other`'s box: for every
 * signed axis along which some member's normal has a part (its axis area is not zero), the
 * other box lies wholly on the back side of the cluster's box along that axis, so every term of
 * n . (x - y) is at most zero (x in the other box, y a member point). A row of walls facing +x
 * seen from their west, a floor's tiles from under the floor. */
static int cluster_faces_away(const rad_hier *h, uint32_t cluster, uint32_t other) {
    if (!cluster_index(h, cluster)) return 0;
    const cluster_info *ci = info(h, cluster);
    rad_vec3 lo, hi;
    const rad_hier_node *n = &h->nodes[other];
    if (is_cluster(n)) {
        lo = info(h, other)->lo;
        hi = info(h, other)->hi;
    } else {
        lo = hi = n->corner[0];
        for (int k = 1; k < n->corner_count; ++k) {
            lo = v3_min(lo, n->corner[k]);
            hi = v3_max(hi, n->corner[k]);
        }
    }
    const double other_lo[3] = {lo.x, lo.y, lo.z}, other_hi[3] = {hi.x, hi.y, hi.z};
    const double box_lo[3] = {ci->lo.x, ci->lo.y, ci->lo.z}, box_hi[3] = {ci->hi.x, ci->hi.y, ci->hi.z};
    for (int a = 0; a < 3; ++a) {
        if (ci->axis_area[2 * a] > 0 && other_hi[a] > box_lo[a]) return 0;
        if (ci->axis_area[2 * a + 1] > 0 && other_lo[a] < box_hi[a]) return 0;
    }
    return 1;
}

/* Nonzero when `receiver` (bounding radius `radius`, node_centre) is a polygon node and the box
 * of source cluster `source` lies behind its plane (behind every corner, by a millionth of the
 * two radii): every sampled point is then behind the receiver, so every ray of the link leaves the receiver's back and the link's
 * factor is exactly 0 (each ray's receiver weight A max(0, n.ray) is 0), its centre estimate
 * too (n.w < 0), and its bound upper - lower whatever the rays find blocked. Such links are
 * still made (no_light_between explains why), but without rays or member walks: in the 10^5
 * office 0.55 M of the 4.4 M links kept (hspeed9), each with 16 to 32 rays. The margin keeps
 * a flat cluster lying in the receiver's own plane (floor tiles beside a tile), whose rays'
 * weights are rounding errors, on the path with rays, so the factors are the same bits. */
static int receiver_behind(const rad_hier *h, uint32_t receiver, double radius, uint32_t source) {
    const rad_hier_node *n = &h->nodes[receiver];
    if (is_cluster(n) || !cluster_index(h, source)) return 0;
    const cluster_info *ci = info(h, source);
    rad_vec3 normal = h->normal[n->polygon];
    double front = -INFINITY; /* the receiver's points lie behind its farthest corner */
    for (int k = 0; k < n->corner_count; ++k) front = larger(front, v3_dot(normal, n->corner[k]));
    return v3_dot(normal, farthest_along(ci, normal)) - front < -1e-6 * (radius + ci->radius);
}

/* Nonzero when no light can pass between the two ends of a link with a cluster at one end or
 * both, whatever it is refined into: a cluster receiver behind a polygon source's plane
 * (cluster_behind), or a cluster none of whose members faces the other end
 * (cluster_faces_away). Without these tests such a link was refined down to every member (a
 * cluster receiver is opened as soon as its source is lit) or estimated with rays: in the 10^4
 * office the links kept fell from 358,818 to 334,890, the same image on Sponza.
 *
 * A polygon receiver with a source cluster behind its plane carries nothing either, but it is
 * linked (and its rays cast) as before: leaving it out (hspeed4) cut the 10^4 office's links
 * by another 14% and made Sponza darker (mean -2.30% against -1.61%, 16x16 RMSE 3.36% against
 * 2.60%; docs/hierarchical.md, "Speed at scale, fifth session"). Its rays, 88% of them blocked,
 * count toward the source members' exposure, and its bound refines the receiver as the source
 * brightens; neither counting those rays as blocked without casting them (-1.84%) nor casting
 * them for the exposure alone (-1.99%) kept the image. */
static int no_light_between(const rad_hier *h, uint32_t receiver, uint32_t source) {
    return cluster_behind(h, source, receiver) || cluster_faces_away(h, receiver, source) ||
           cluster_faces_away(h, source, receiver);
}

/* The largest reflectance (any channel) of a link's receiver: a cluster's is its members'
 * largest (cluster_info.reflectance), what the oracles charge a link's error with. */
static double receiver_reflectance(const rad_hier *h, uint32_t receiver) {
    const rad_hier_node *r = &h->nodes[receiver];
    if (is_cluster(r)) return info(h, receiver)->reflectance;
    const double *rho = h->reflectance[r->polygon];
    return larger(rho[0], larger(rho[1], rho[2]));
}

/* Whether a cluster link with form-factor bound `bound` (its spread plus its estimate, the
 * most it has with partial visibility) passes the oracle whatever its rays say and whatever the
 * radiosities become: charged at the radiosity cap (no radiosity E + rho H exceeds
 * emission_max / (1 - rho_max), H being a mean of radiosities), its error stays under the
 * threshold, so the oracle keeps it in every refinement and its estimate only has to be
 * unbiased, not decisive. Not with importance (its weight may exceed 1) nor with lights (a
 * split node's light may exceed the roots' that emission_max counts). In the office of 10^5
 * triangles 57% of the cluster links estimated with rays are such; at 10^6 (roots a tenth the
 * area) more. */
static int cheap_link(const rad_hier *h, uint32_t receiver, double bound) {
    if (!(h->radiosity_cap > 0) || h->importance || h->light) return 0;
    return receiver_reflectance(h, receiver) * h->radiosity_cap * bound * h->nodes[receiver].area <
           h->threshold;
}

/* A link's sample (link_sample) from the source members its counted pairs ended on and what
 * each pair added to its factor; none (NO_SAMPLE) when nothing was seen. */
static void keep_seen_members(link_sample *out, const uint32_t *member, const double *added, int count) {
    if (!out) return;
    double total = 0;
    for (int k = 0; k < count; ++k) total += added[k];
    for (int k = 0; k < 4; ++k) {
        out->member[k] = k < count ? member[k] : 0;
        out->weight[k] = k < count && total > 0 ? (uint16_t)lrint(added[k] / total / SAMPLE_UNIT) : 0;
    }
    if (!(total > 0)) out->weight[0] = NO_SAMPLE;
}

/* A cluster link's factor from its rays: one ray per receiver point (a polygon receiver's
 * quadrature points, a cluster receiver's four sampled points), each to its own sampled source
 * point (the points drawn from the link's stream `stream`, link_hash); with `two`, two of those
 * pairs (a cheap link's, make_cluster_link). The mean over the pairs of V P_r P_s / (pi r^2 A_r)
 * is unbiased; clamped to the upper bound. The bound is the spread, plus the whole estimate when
 * a ray was blocked or when `partial` says the link counts as partly hidden whatever its rays
 * find (make_cluster_link). 1-4 rays; a link not cheap (cheap_link) cast 16 until hspeed11,
 * between every receiver point and every source point. */
static int estimate_cluster_link(const rad_hier *h, rad_vec3 w, double upper, double spread,
                                 double estimate, double slack, uint32_t stream, int partial,
                                 int two, rad_hier_link *out, link_sample *seen_members) {
    const uint32_t receiver = out->receiver, source = out->source;
    const rad_hier_node *nr = &h->nodes[receiver], *ns = &h->nodes[source];
    rad_vec3 x[4], y[4];
    uint32_t receiver_member[4], source_member[4];
    double receiver_chance[4], source_chance[4];
    const uint32_t receiver_seed = link_hash(h, receiver, source, 1 + stream);
    const uint32_t source_seed = link_hash(h, receiver, source, 2 + stream);
    const rad_vec3 back = v3_scale(w, -1);
    /* With `two`, strata j and j + 2 of both ends (j drawn per link), a triangle receiver's two
     * quadrature points drawn among its three pairs of them: each of the four pairs (or three
     * points) is in the estimate with the same chance, so the mean is unbiased. */
    const uint32_t bits = two ? link_hash(h, receiver, source, 5 + stream) >> 8 : 0;
    const int first = (int)(bits & 1), stride = two ? 2 : 1, walks = two ? 2 : WALKS;
    int pairs = walks;
    if (is_cluster(nr))
        sample_points(h, receiver, w, receiver_seed, x, receiver_member, receiver_chance, 0, walks,
                      first, stride);
    else if (!two)
        pairs = quadrature_points(nr, x);
    else {
        rad_vec3 q[4];
        int n = quadrature_points(nr, q);
        if (n == 4) x[0] = q[first], x[1] = q[first + 2];
        else if (n == 3) x[0] = q[bits % 3], x[1] = q[(bits + 1) % 3];
        else x[0] = q[0], pairs = 1;
    }
    /* Without `two` the source always takes its four points (a partly hidden link turns them). */
    sample_points(h, source, back, source_seed, y, source_member, source_chance, (float)slack,
                  two ? pairs : WALKS, first, stride);
    if (partial) {
        /* Receiver point k is in quarter k of its node or member (the quadrature's order,
         * visibility_point's strata), and so is source point k: paired k with k, the rays join
         * like quarters, which on aligned surfaces (the office's) lie nearer each other than
         * two points drawn apart (+0.1..+0.4% on every surface of the 10^5 office at three
         * seeds). A turn drawn per link pairs each receiver quarter with every source quarter
         * alike over the links. */
        const uint32_t turn = link_hash(h, receiver, source, 3 + stream) >> 30;
        rad_vec3 y0[4];
        uint32_t m0[4];
        double c0[4];
        memcpy(y0, y, sizeof y0);
        memcpy(m0, source_member, sizeof m0);
        memcpy(c0, source_chance, sizeof c0);
        for (int k = 0; k < 4; ++k) {
            y[k] = y0[(k + turn) & 3];
            source_member[k] = m0[(k + turn) & 3];
            source_chance[k] = c0[(k + turn) & 3];
        }
    }
    /* One ray at a time (rtcOccluded1): these four rays, to members drawn apart, are not a
     * coherent packet, and in a packet of sixteen lanes they cost what sixteen would (the 10^5
     * office's solve took 5-10% more processor time with the packet, three pairs; 10^6: 2-4%). */
    uint8_t occluded[4];
    for (int k = 0; k < pairs; ++k) occluded[k] = (uint8_t)rad_rays_occluded(h->rays, x[k], y[k]);
    double sum = 0, added[4] = {0, 0, 0, 0};
    int blocked = 0;
    for (int k = 0; k < pairs; ++k) {
        const int seen = !occluded[k];
        blocked |= !seen;
        if (!seen) continue;
        rad_vec3 ray = v3_sub(y[k], x[k]);
        double r2 = v3_dot(ray, ray), length = sqrt(r2);
        double wr = is_cluster(nr)
                        ? member_weight(h, receiver_member[k], receiver_chance[k], v3_scale(ray, -1), length)
                        : nr->area * larger(0, v3_dot(h->normal[nr->polygon], ray) / length);
        double ws = is_cluster(ns)
                        ? member_weight(h, source_member[k], source_chance[k], ray, length)
                        : ns->area * larger(0, -v3_dot(h->normal[ns->polygon], ray) / length);
        added[k] = wr * ws / r2;
        sum += added[k];
    }
    if (is_cluster(ns)) keep_seen_members(seen_members, source_member, added, pairs);
    out->form_factor = (float)smaller(upper, sum / pairs / (RAD_PI * nr->area));
    blocked |= partial;
    double error = spread + (blocked ? estimate : 0);
    out->error = (float)smaller(error, UNKNOWN_ERROR);
    if (blocked) out->error = -out->error;
    return 1;
}

/* The link receiver <- source when either is a cluster: the point estimate between the
 * centres, its bound, and the visible fraction of the rays between sampled member points.
 * A self-link, or one whose bounding spheres overlap, carries nothing and must be refined.
 * With `may_skip`, a link the oracle will refine in this pass (the radiosities it reads do not
 * change within rad_hier_refine) is not estimated: no rays when its bound fails, with the
 * whole estimate counted unless the link is cheap (cheap_link) or carries nothing
 * (receiver_behind). Its factor is then NOT_ESTIMATED, and a link kept after all (the memory
 * budget stopped refinement) is made again without `may_skip`. Returns 0 when no light can
 * pass. */
static int make_cluster_link(const rad_hier *h, uint32_t receiver, uint32_t source,
                             rad_hier_link *out, int may_skip, link_sample *seen_members) {
    out->receiver = receiver;
    out->source = source;
    out->sample = RAD_HIER_NO_NODE;
    out->form_factor = 0;
    out->error = UNKNOWN_ERROR;
    if (receiver == source) return 1;
    if (no_light_between(h, receiver, source)) return 0;
    double rr, rs;
    rad_vec3 cr = node_centre(h, receiver, &rr), cs = node_centre(h, source, &rs);
    rad_vec3 between = v3_sub(cs, cr);
    double d = v3_length(between), reach = rr + rs;
    if (!(d > reach)) return 1;
    rad_vec3 w = v3_scale(between, 1 / d);
    double spread = asin(smaller(1, reach / d));
    /* How far behind w a source member may face and still be drawn (sample_points): the sine of
     * the angle the two spheres subtend. The tangent is the exact bound (members with n.w
     * between minus the tangent and minus the sine still face a few rays and are not drawn);
     * the sine is what was measured on Sponza, and the tangent drew no better tiles in
     * test_bright_member or test_cluster_form_factors. */
    double slack = smaller(1, reach / d);
    projection pr = project(h, receiver, w, spread), ps = project(h, source, v3_scale(w, -1), spread);
    if (!(pr.upper > 0) || !(ps.upper > 0)) return 0;
    double area = h->nodes[receiver].area;
    double estimate = pr.estimate * ps.estimate / (RAD_PI * d * d * area);
    double upper = pr.upper * ps.upper / (RAD_PI * (d - reach) * (d - reach) * area);
    double lower = pr.lower * ps.lower / (RAD_PI * (d + reach) * (d + reach) * area);
    if (may_skip && refined_anyway(h, out, upper - lower)) {
        out->form_factor = NOT_ESTIMATED;
        return 1;
    }
    if (receiver_behind(h, receiver, rr, source)) {
        /* No ray can carry light (receiver_behind): what they would give is known. */
        out->form_factor = 0;
        out->error = -(float)smaller(upper - lower, UNKNOWN_ERROR);
        return 1;
    }
    /* A cheap link is kept by the oracle whatever its rays find, and carries little: its estimate
     * need only be unbiased, and two pairs of points (half of the four, drawn per link) are.
     * They halve its member walks and rays; at 10^6 triangles most cluster links are cheap, and
     * the solve took 52.6-54.1 s against 60.2-61.1 s (three alternating pairs), the surfaces'
     * means within 0.15% (0.3% at 10^5, where one seed to the next moves them up to 1%),
     * Sponza's render the same in the mean and in 8x8 and 16x16 blocks at seeds 0-2
     * (docs/hierarchical.md, "Twenty-third session"). */
    if (cheap_link(h, receiver, upper - lower + estimate))
        return estimate_cluster_link(h, w, upper, upper - lower, estimate, slack, 0, 0, 1, out,
                                     seen_members);
    /* The factor itself from the rays between sampled member points (chosen in proportion to
     * projected area): the mean over the pairs of V P_r P_s / (pi r^2 A_r), with a polygon
     * end's A cos taken along each ray (estimate_cluster_link). The centres' distance alone underestimates it (the
     * mean of 1 / r^2 over an extended pair exceeds 1 / d^2, and near pairs are the visible
     * ones): Sponza's arcades, lit through large clusters, came out half as bright. Clamped to
     * the upper bound.
     *
     * The link counts as partly hidden whatever its rays find: its bound is the spread plus
     * the whole estimate, and the oracle decides on it before any ray. Its rays then only
     * estimate, and nothing they find decides whether the link is kept, so the estimate is
     * unbiased. (Until hspeed10 a first set of 16 pairs decided partial visibility and a fresh
     * set estimated, because an estimate from the rays that chose the link was biased: low
     * given blocked rays, high given none, Sponza -4.8% against the path tracer. 83-87% of
     * these links were partly hidden anyway and 0.1% were refined on it when made; the
     * deciding set was 16 rays and 4 member walks of every such link, a fifth of the rays at
     * 10^6: docs/hierarchical.md, "Speed at scale, tenth session".) The points and members are
     * the ones the fresh set drew (its seeds). Since hspeed11 the four pairs (receiver point k,
     * source point k) of those points, not all 16: the same walks, a quarter of the rays
     * (7.7 M such links at 10^6); unbiased as before, Sponza at seeds 0-2 within the seeds'
     * spread ("Speed at scale, eleventh session"). */
    if (may_skip && refined_anyway(h, out, upper - lower + estimate)) {
        out->form_factor = NOT_ESTIMATED;
        out->error = -out->error;
        return 1;
    }
    /* A cluster source whose brightest member reflects at least a quarter of the brightest
     * emission (the surfaces a sky lights) takes BRIGHT_CLUSTER_SETS sets: its link's
     * visibility noise is repeated by every bounce after it (sponza4, sponza5,
     * docs/hierarchical.md). Reflected, not sent: an emitter's own light (the office's lamps,
     * the sky) does not count, so their clusters keep one set. */
    enum { BRIGHT_CLUSTER_SETS = 3 };
    int sets = is_cluster(&h->nodes[source]) && h->emission_max > 0 &&
                       info(h, source)->reflected >= 0.25 * h->emission_max
                   ? BRIGHT_CLUSTER_SETS
                   : 1;
    if (sets <= 1 || !seen_members)
        return estimate_cluster_link(h, w, upper, upper - lower, estimate, slack, 0x100u, 1, 0, out,
                                     seen_members);
    /* Several sets of four pairs: the factor is their mean; the members each set saw are
     * weighed by the set's factor, and four of them are drawn in proportion (systematic
     * resampling), which keeps the sent radiosity unbiased. */
    double factor = 0, weight[4 * BRIGHT_CLUSTER_SETS];
    uint32_t member[4 * BRIGHT_CLUSTER_SETS];
    int count = 0;
    rad_hier_link one = *out;
    for (int j = 0; j < sets; ++j) {
        link_sample seen;
        seen.weight[0] = NO_SAMPLE;
        estimate_cluster_link(h, w, upper, upper - lower, estimate, slack,
                              0x100u + 4u * (uint32_t)j, 1, 0, &one, &seen);
        if (j == 0) out->error = one.error;
        factor += one.form_factor;
        if (seen.weight[0] == NO_SAMPLE) continue;
        for (int k = 0; k < 4; ++k) {
            member[count] = seen.member[k];
            weight[count++] = one.form_factor * SAMPLE_UNIT * seen.weight[k];
        }
    }
    out->form_factor = (float)(factor / sets);
    double total = 0;
    for (int k = 0; k < count; ++k) total += weight[k];
    if (!(total > 0)) {
        seen_members->weight[0] = NO_SAMPLE;
        out->form_factor = 0;
        return 1;
    }
    uint32_t picked[4];
    double added[4] = {1, 1, 1, 1}, step = total / 4, at = step * unit(link_hash(h, receiver, source, 0x1ffu)), run = 0;
    for (int k = 0, i = 0; k < 4; ++k, at += step) {
        while (i < count - 1 && run + weight[i] <= at) run += weight[i++];
        picked[k] = member[i];
    }
    keep_seen_members(seen_members, picked, added, 4);
    return 1;
}

/* Any link: the contour integral between two polygon nodes, the point estimate otherwise. */
static int make_any_link(const rad_hier *h, uint32_t receiver, uint32_t source, rad_hier_link *out,
                         int may_skip, link_sample *seen_members) {
    if (seen_members) seen_members->weight[0] = NO_SAMPLE;
    if (cluster_index(h, receiver) || cluster_index(h, source))
        return make_cluster_link(h, receiver, source, out, may_skip, seen_members);
    return make_link(h, receiver, source, out, may_skip);
}

/* The radiosity a link's source sends toward its receiver: what the link's own rays saw of a
 * cluster's members (link_sample, weighed by what each visible pair added to the factor), or,
 * without a sample, the node's own radiosity. Only links from clusters keep samples
 * (keep_seen_members), so a polygon source sends its own; a cluster link without one saw
 * nothing of its source, has factor 0 and is not asked by the gather. (The members' plain mean
 * would mix the sky quad over Sponza with the roof beside it, which faces away; before energy2
 * a cluster sent a directional, exposure-weighted mean, Sillion 1995.) */
static void source_radiosity(const rad_hier *h, const rad_hier_link *link, double out[3]) {
    if (link->sample == RAD_HIER_NO_NODE) {
        const rad_hier_node *r = &h->nodes[link->receiver], *s = &h->nodes[link->source];
        if (h->kernel.count) {
            if (rad_hier_kernel_cache_mean(&h->kernel, h->nodes, (size_t)(link - h->links), out))
                return;
        } else if (h->source_depth && link->error >= 0 && r->corner_count && s->corner_count &&
                   rad_hier_source_kernel_mean(h->nodes, r, h->normal[r->polygon], link->source,
                                               h->normal[s->polygon], h->source_depth, out))
            return;
        memcpy(out, s->radiosity, sizeof(double[3]));
        return;
    }
    const link_sample *seen = &h->samples[link->sample];
    for (int i = 0; i < 3; ++i) out[i] = 0;
    for (int k = 0; k < 4; ++k) {
        const double *b = h->root_radiosity[seen->member[k]];
        for (int i = 0; i < 3; ++i) out[i] += SAMPLE_UNIT * seen->weight[k] * b[i];
    }
}

/* The oracle for a link with a cluster at one end or both: 0 keeps it, 1 opens (or splits) the
 * receiver, 2 the source, 3 a self-link into every pair of children. The end with the larger
 * bounding sphere is opened (Smits et al. 1994). */
static int cluster_oracle(const rad_hier *h, const rad_hier_link *link, double *relative,
                          int pick_end) {
    const rad_hier_node *r = &h->nodes[link->receiver];
    double rho = receiver_reflectance(h, link->receiver);
    /* A cluster source sends its members' light: charge the error at its brightest member's
     * radiosity (Smits, Arvo & Greenberg 1994 bound a cluster's transfer by its members' largest
     * radiosity), not at their mean. A cluster that mixes a bright member with dark ones is then
     * opened until the bright one is sent on its own, where the directional, exposure-weighted
     * mean (source_radiosity) would spread its light over members the receiver does not see.
     * Read from the compact per-node `sends` (brightest_members): the sources are read at
     * random, and the node and its cluster record cost three cache lines where this costs one. */
    double brightest = h->sends[link->source];
    /* A link that carries nothing yet (overlapping ends) is refined whatever its importance:
     * until it is, no importance crosses it either. */
    double weight = fabs(link->error) >= UNKNOWN_ERROR ? 1 : importance_weight(h, link->receiver);
    double error = rho * brightest * fabs((double)link->error) * r->area * weight;
    *relative = error / h->threshold;
    /* A cluster only sends. Gathered into a cluster, light would reach every member alike,
     * whatever its orientation and whatever hides it (it leaked under boxes standing on a
     * tiled floor: 0.10 against 0.009); so a cluster receiver is opened as soon as its source
     * carries light, and every surface gathers with its own orientation and visibility. */
    if (is_cluster(r) && brightest > 0) return link->receiver == link->source ? 3 : 1;
    if (!(error > h->threshold)) return 0;
    if (link->receiver == link->source) return 3;
    const rad_hier_node *s = &h->nodes[link->source];
    int split_r = is_cluster(r) || can_split(h, r), split_s = is_cluster(s) || can_split(h, s);
    if (!pick_end) return split_r || split_s;
    double radius_r, radius_s;
    node_centre(h, link->receiver, &radius_r);
    node_centre(h, link->source, &radius_s);
    if (split_r && (!split_s || radius_r >= radius_s)) return 1;
    if (split_s) return 2;
    return 0;
}

static int decide_cluster(const rad_hier *h, const rad_hier_link *link, double *relative) {
    return cluster_oracle(h, link, relative, 1);
}

static int decide_any(const rad_hier *h, const rad_hier_link *link, double *relative) {
    if (cluster_index(h, link->receiver) || cluster_index(h, link->source))
        return decide_cluster(h, link, relative);
    return decide(h, link, relative);
}

/* Long loops over links are cut into BLOCKS blocks: each block's count (of what the loop keeps
 * or makes) is taken in parallel, the counts are summed in block order into each block's first
 * slot, then every block writes its own slots, so the output is in the one serial order for any
 * thread count. */
enum { BLOCKS = 256 };
static void block_range(size_t count, long k, size_t *first, size_t *last) {
    size_t block = (count + BLOCKS - 1) / BLOCKS;
    *first = (size_t)k * block < count ? (size_t)k * block : count;
    *last = *first + block < count ? *first + block : count;
}

/* Turns the block counts at[1 .. BLOCKS] into each block's first slot (at[0] the first of all);
 * returns the total. */
static size_t block_starts(size_t *at) {
    for (int k = 0; k < BLOCKS; ++k) at[k + 1] += at[k];
    return at[BLOCKS];
}

/* Keeps links[i] where (flag[i] != 0) == keep_set, in order, in place; returns how many. Each
 * block is squeezed in parallel, then the blocks are moved down one after the other. */
static size_t compact_links(const rad_hier *h, rad_hier_link *links, size_t count,
                            const uint8_t *flag, int keep_set) {
    size_t at[BLOCKS + 1];
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last;
        block_range(count, k, &first, &last);
        size_t here = first;
        for (size_t i = first; i < last; ++i)
            if ((flag[i] != 0) == keep_set) links[here++] = links[i];
        at[k + 1] = here - first;
    }
    at[0] = 0;
    size_t kept = block_starts(at);
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last;
        block_range(count, k, &first, &last);
        if (at[k] != first && at[k + 1] > at[k])
            memmove(links + at[k], links + first, (at[k + 1] - at[k]) * sizeof *links);
    }
    return kept;
}

/* Sorts links[0 .. count) by receiver (stable) into out. A counting sort in `parts` contiguous
 * parts, one per thread: each part counts its receivers, part p's links of receiver n go after
 * those of every part before p, so the result is the one stable order whatever the number of
 * parts. */
static rad_status sort_by_receiver(rad_hier *h, const rad_hier_link *links, size_t count,
                                   rad_hier_link *out) {
    const size_t nodes = h->node_count;
    const int parts = count >= 4096 ? threads(h) : 1;
    const size_t part = (count + (size_t)parts - 1) / (size_t)parts;
    size_t *start = rad_alloc_zero(h->ctx, (size_t)parts * nodes + 1, sizeof *start);
    if (!start) return RAD_ERROR_NO_MEMORY;
#pragma omp parallel for schedule(static, 1) num_threads(parts)
    for (int p = 0; p < parts; ++p) {
        size_t *mine = start + (size_t)p * nodes;
        size_t last = (size_t)(p + 1) * part < count ? (size_t)(p + 1) * part : count;
        for (size_t i = (size_t)p * part; i < last; ++i) mine[links[i].receiver]++;
    }
    /* Each (receiver, part)'s first slot, receivers in order, parts in order within each. */
    size_t at = 0;
    for (size_t n = 0; n < nodes; ++n)
        for (int p = 0; p < parts; ++p) {
            size_t c = start[(size_t)p * nodes + n];
            start[(size_t)p * nodes + n] = at;
            at += c;
        }
#pragma omp parallel for schedule(static, 1) num_threads(parts)
    for (int p = 0; p < parts; ++p) {
        size_t *mine = start + (size_t)p * nodes;
        size_t last = (size_t)(p + 1) * part < count ? (size_t)(p + 1) * part : count;
        for (size_t i = (size_t)p * part; i < last; ++i) out[mine[links[i].receiver]++] = links[i];
    }
    rad_free(h->ctx, start);
    return RAD_OK;
}

/* Makes `links` (sorted by receiver, count of them) the hierarchy's links: frees the old ones,
 * rebuilds the receiver groups and counts the links with a cluster end. Takes ownership. */
static rad_status take_sorted_links(rad_hier *h, rad_hier_link *links, size_t count) {
    size_t at[BLOCKS + 1], cluster_links = 0;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096) \
    reduction(+ : cluster_links)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last, starts = 0;
        block_range(count, k, &first, &last);
        for (size_t i = first; i < last; ++i) {
            starts += i == 0 || links[i].receiver != links[i - 1].receiver;
            cluster_links += cluster_index(h, links[i].receiver) || cluster_index(h, links[i].source);
        }
        at[k + 1] = starts;
    }
    at[0] = 0;
    size_t group_count = block_starts(at);
    size_t *groups = rad_alloc(h->ctx, group_count + 1, sizeof *groups);
    if (!groups) {
        rad_free(h->ctx, links);
        return RAD_ERROR_NO_MEMORY;
    }
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last, group = at[k];
        block_range(count, k, &first, &last);
        for (size_t i = first; i < last; ++i)
            if (i == 0 || links[i].receiver != links[i - 1].receiver) groups[group++] = i;
    }
    groups[group_count] = count;
    if (h->links != links) rad_free(h->ctx, h->links);
    rad_free(h->ctx, h->group_first);
    h->links = links;
    h->link_count = count;
    h->group_first = groups;
    h->group_count = group_count;
    h->stats.links = count;
    h->stats.cluster_links = cluster_links;
    return RAD_OK;
}

/* Sorts `links` by receiver (stable) into h->links and rebuilds the receiver groups. Takes
 * ownership of `links`. */
static rad_status adopt_links(rad_hier *h, rad_hier_link *links, size_t count) {
    rad_hier_link *sorted = rad_alloc(h->ctx, count ? count : 1, sizeof *sorted);
    rad_status status = sorted ? sort_by_receiver(h, links, count, sorted) : RAD_ERROR_NO_MEMORY;
    rad_free(h->ctx, links);
    if (status) {
        rad_free(h->ctx, sorted);
        return status;
    }
    return take_sorted_links(h, sorted, count);
}

/* How many of the first `k` links of the merge of a[0 .. na) and b[0 .. nb) (both sorted by
 * receiver, a's links before b's of the same receiver) come from a: the merge path's split. */
static size_t merge_split(const rad_hier_link *a, size_t na, const rad_hier_link *b, size_t nb,
                          size_t k) {
    size_t lo = k > nb ? k - nb : 0, hi = k < na ? k : na;
    while (lo < hi) {
        size_t i = lo + (hi - lo) / 2;
        if (a[i].receiver <= b[k - i - 1].receiver) lo = i + 1;
        else hi = i;
    }
    return lo;
}

/* Merges apart[0 .. tail) into links[0 .. sorted) (both sorted by receiver), in place in
 * links[0 .. sorted + tail), links' own before apart's of the same receiver. The output is cut
 * into one part per thread at merge-path points (Odeh et al. 2012, "Merge Path"); each part
 * merges from its back, as the serial loop did. A part's links below its first output slot may
 * be overwritten by the parts before it, so they are copied aside first. The merge has one
 * result, so the bits do not depend on the number of parts. */
static rad_status merge_in_place(rad_hier *h, rad_hier_link *links, size_t sorted,
                                 const rad_hier_link *apart, size_t tail) {
    enum { MAX_PARTS = 64 };
    const size_t count = sorted + tail;
    int parts = count >= (1u << 16) ? threads(h) : 1;
    if (parts > MAX_PARTS) parts = MAX_PARTS;
    if (parts < 1) parts = 1;
    size_t out_at[MAX_PARTS + 1], from_links[MAX_PARTS + 1], aside_at[MAX_PARTS + 1];
    aside_at[0] = 0;
    for (int p = 0; p <= parts; ++p) {
        out_at[p] = (size_t)((double)count * p / parts);
        if (p == parts) out_at[p] = count;
        from_links[p] = merge_split(links, sorted, apart, tail, out_at[p]);
    }
    for (int p = 0; p < parts; ++p) {
        size_t low = from_links[p + 1] < out_at[p] ? from_links[p + 1] : out_at[p];
        aside_at[p + 1] = aside_at[p] + (low - from_links[p]);
    }
    rad_hier_link *aside = NULL;
    if (aside_at[parts]) {
        aside = rad_alloc(h->ctx, aside_at[parts], sizeof *aside);
        if (!aside) return RAD_ERROR_NO_MEMORY;
#pragma omp parallel for schedule(static, 1) num_threads(parts)
        for (int p = 0; p < parts; ++p)
            memcpy(aside + aside_at[p], links + from_links[p],
                   (aside_at[p + 1] - aside_at[p]) * sizeof *aside);
    }
#pragma omp parallel for schedule(static, 1) num_threads(parts)
    for (int p = 0; p < parts; ++p) {
        const size_t i0 = from_links[p], j0 = out_at[p] - i0, k0 = out_at[p];
        const size_t saved_end = i0 + (aside_at[p + 1] - aside_at[p]);
        size_t i = from_links[p + 1], j = out_at[p + 1] - i, k = out_at[p + 1];
        while (k > k0) {
            if (j == j0 && k == i) break; /* the rest of links' part is in place already */
            const rad_hier_link *a =
                i == i0 ? NULL : i - 1 < saved_end ? &aside[aside_at[p] + (i - 1 - i0)] : &links[i - 1];
            if (a && (j == j0 || a->receiver > apart[j - 1].receiver)) {
                links[--k] = *a;
                --i;
            } else
                links[--k] = apart[--j];
        }
    }
    rad_free(h->ctx, aside);
    return RAD_OK;
}

/* The same when links[0 .. sorted) are sorted by receiver already (the links a refinement kept
 * in place, in their order) and the rest are not: the rest are sorted apart and merged in from
 * the back, the sorted part's links before the others' of the same receiver, which is the
 * order adopt_links gives. Only the unsorted part is copied: a step that refines a handful of
 * 37.8 M links (the 10^6 office's) no longer copies all of them twice. Takes ownership. */
static rad_status merge_links(rad_hier *h, rad_hier_link *links, size_t sorted, size_t count) {
    const size_t tail = count - sorted;
    if (tail) {
        rad_hier_link *apart = rad_alloc(h->ctx, tail, sizeof *apart);
        rad_status status = apart ? sort_by_receiver(h, links + sorted, tail, apart) : RAD_ERROR_NO_MEMORY;
        if (status) {
            rad_free(h->ctx, apart);
            rad_free(h->ctx, links);
            return status;
        }
        status = merge_in_place(h, links, sorted, apart, tail);
        rad_free(h->ctx, apart);
        if (status) {
            rad_free(h->ctx, links);
            return status;
        }
    }
    return take_sorted_links(h, links, count);
}

/* The bytes the memory budget counts for `links` links (two arrays of them while a refinement
 * merges) and `nodes` nodes with their own arrays: direct light and spread, importance terms. */
static double held_bytes(const rad_hier *h, size_t links, size_t nodes) {
    double node_bytes = (double)sizeof(rad_hier_node) +
                        (h->light ? (double)(sizeof *h->light + sizeof *h->light_spread) : 0) +
                        (h->importance ? 3.0 * sizeof(double) : 0);
    return 2.0 * (double)links * sizeof(rad_hier_link) + (double)nodes * node_bytes;
}

static rad_status check_memory(rad_hier *h, size_t links, size_t nodes) {
    char what[160];
    snprintf(what, sizeof what, "hierarchical radiosity with %zu links and %zu nodes", links, nodes);
    return rad_check_budget(h->ctx, held_bytes(h, links, nodes), what);
}

rad_status rad_hier_link_roots(rad_hier *h) {
    if (!h->no_clusters) {
        /* One self-link on the top cluster: the oracle opens it where the light asks. */
        rad_hier_link *top = rad_alloc(h->ctx, 1, sizeof *top);
        if (!top) return RAD_ERROR_NO_MEMORY;
        make_cluster_link(h, rad_hier_top(h), rad_hier_top(h), top, 0, NULL);
        return adopt_links(h, top, 1);
    }
    size_t n = h->root_count;
    rad_status status = check_memory(h, n * n, h->node_count);
    if (status) return status;
    size_t pairs = n * n > 0 ? n * n : 1;
    rad_hier_link *all = rad_alloc(h->ctx, pairs, sizeof *all);
    uint8_t *made = rad_alloc_zero(h->ctx, pairs, 1);
    if (!all || !made) {
        rad_free(h->ctx, all);
        rad_free(h->ctx, made);
        return RAD_ERROR_NO_MEMORY;
    }
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads(h)) if (n >= 16)
    for (long i = 0; i < (long)n; ++i)
        for (size_t j = 0; j < n; ++j)
            if ((size_t)i != j)
                made[(size_t)i * n + j] = (uint8_t)make_link(h, (uint32_t)i, (uint32_t)j,
                                                             &all[(size_t)i * n + j], 0);
    size_t kept = 0;
    for (size_t i = 0; i < n * n; ++i)
        if (made[i]) all[kept++] = all[i];
    rad_free(h->ctx, made);
    return adopt_links(h, all, kept);
}

/* How many links a decision makes of one link. */
static size_t children_made(const rad_hier *h, const rad_hier_link *link, int decision) {
    const rad_hier_node *r = &h->nodes[link->receiver], *s = &h->nodes[link->source];
    size_t cr = is_cluster(r) ? r->child_count : 4, cs = is_cluster(s) ? s->child_count : 4;
    return decision == 1 ? cr : decision == 2 ? cs : decision == 3 ? cr * cs : 0;
}

/* Splits the leaves whose light (rad_hier_options.light) changes across them by more than the
 * threshold allows (a quarter of the spread times the area, as a link's error), and their new
 * children likewise, until every leaf passes or cannot be split. Links stay where they are
 * (push-pull hands their irradiance down). Returns the number of leaves split; *largest is
 * the largest relative error of the leaves left. */
static rad_status refine_light(rad_hier *h, size_t *splits, double *largest) {
    *splits = 0;
    if (!h->light) return RAD_OK;
    for (size_t first = 0, last = h->node_count; first < last; first = last, last = h->node_count) {
        size_t nodes_before = h->node_count;
        for (size_t i = first; i < last; ++i) {
            const rad_hier_node *n = &h->nodes[i];
            if (n->corner_count == 0 || n->first_child != RAD_HIER_NO_NODE) continue;
            double relative = 0.25 * h->light_spread[i] * n->area / h->threshold;
            if (!(relative > 1) || !can_split(h, n)) {
                *largest = larger(*largest, relative);
                continue;
            }
            rad_status status = check_memory(h, h->link_count, h->node_count + 4);
            if (status == RAD_ERROR_MEMORY_BUDGET) {
                rad_warn(h->ctx, "%s; the lights' shadow edges are not refined further",
                         rad_context_error(h->ctx));
                light_nodes(h, nodes_before);
                return RAD_OK;
            }
            if (!status) status = subdivide(h, (uint32_t)i);
            if (status) return status;
            ++*splits;
        }
        light_nodes(h, nodes_before);
    }
    return RAD_OK;
}

/* Sets every cluster's `brightest` from its members' radiosities, children first (leaf
 * clusters in parallel, then the others from the last to the first), and every node's `sends`:
 * what the oracle charges a source's links at (cluster_oracle). Taken at the start of every refinement from the
 * radiosities it refines with, so a loaded hierarchy gets the same. */
static rad_status brightest_members(rad_hier *h) {
    const long count = (long)h->cluster_count;
    if (!h->sends) {
        h->sends = rad_alloc(h->ctx, h->node_capacity ? h->node_capacity : 1, sizeof *h->sends);
        if (!h->sends) return RAD_ERROR_NO_MEMORY;
    }
    if (!h->shape) { /* split_into keeps it from here on */
        node_shape *shape = rad_alloc(h->ctx, h->node_capacity ? h->node_capacity : 1, sizeof *shape);
        if (!shape) return RAD_ERROR_NO_MEMORY;
        const long nodes = (long)h->node_count;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (nodes >= 4096)
        for (long i = 0; i < nodes; ++i) shape[i] = shape_of(h, (uint32_t)i);
        h->shape = shape;
    }
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 64)
    for (long c = 0; c < count; ++c) {
        if (!h->walk[c].leaf) continue;
        const rad_hier_node *n = &h->nodes[h->cluster_first + (size_t)c];
        double brightest = 0, reflected = 0;
        for (uint32_t k = 0; k < n->child_count; ++k) {
            const rad_hier_node *m = &h->nodes[n->first_child + k];
            const double *b = m->radiosity, *e = h->emission[m->polygon];
            brightest = larger(brightest, larger(b[0], larger(b[1], b[2])));
            reflected = larger(reflected, larger(b[0] - e[0], larger(b[1] - e[1], b[2] - e[2])));
        }
        h->clusters[c].brightest = brightest;
        h->clusters[c].reflected = (float)reflected;
    }
    for (size_t c = h->cluster_count; c-- > 0;) {
        if (h->walk[c].leaf) continue;
        const rad_hier_node *n = &h->nodes[h->cluster_first + c];
        double brightest = 0, reflected = 0;
        for (uint32_t k = 0; k < n->child_count; ++k) {
            brightest = larger(brightest, info(h, n->first_child + k)->brightest);
            reflected = larger(reflected, info(h, n->first_child + k)->reflected);
        }
        h->clusters[c].brightest = brightest;
        h->clusters[c].reflected = (float)reflected;
    }
    /* Every node's, clusters' with their brightest member. */
    const long nodes = (long)h->node_count;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (nodes >= 4096)
    for (long i = 0; i < nodes; ++i) {
        const double *b = h->nodes[i].radiosity;
        double brightest = larger(b[0], larger(b[1], b[2]));
        if (cluster_index(h, (uint32_t)i)) brightest = larger(brightest, info(h, (uint32_t)i)->brightest);
        h->sends[i] = brightest;
    }
    return RAD_OK;
}

/* Gives each of links[0 .. count) that was made (made[i], or every one when made is NULL) and
 * saw some of its source its sample seen[i], in h->samples: in the slots of refined links'
 * samples first (in the order they were freed, so the same for any thread count), then
 * appended. */
static rad_status keep_samples(rad_hier *h, rad_hier_link *links, const link_sample *seen,
                               const uint8_t *made, size_t count) {
    /* Each block counts its wanted samples in parallel; the k-th wanted of all takes the k-th
     * free slot from the top of the free list, past those the next new slot, as the serial
     * loop gave them. */
    size_t at[BLOCKS + 1];
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last, here = 0;
        block_range(count, k, &first, &last);
        for (size_t i = first; i < last; ++i) here += (!made || made[i]) && seen[i].weight[0] != NO_SAMPLE;
        at[k + 1] = here;
    }
    at[0] = 0;
    const size_t wanted = block_starts(at);
    size_t needed = h->sample_count + (wanted > h->free_count ? wanted - h->free_count : 0);
    if (needed > UINT32_MAX - 1)
        return rad_fail(h->ctx, RAD_ERROR_MEMORY_BUDGET, "more than 2^32 cluster links");
    if (needed > h->sample_capacity) {
        size_t capacity = needed + needed / 4;
        link_sample *grown = rad_realloc(h->ctx, h->samples, capacity, sizeof *grown);
        uint32_t *slots = rad_realloc(h->ctx, h->free_samples, capacity, sizeof *slots);
        if (grown) h->samples = grown;
        if (slots) h->free_samples = slots;
        if (!grown || !slots) return RAD_ERROR_NO_MEMORY;
        h->sample_capacity = capacity;
    }
    const size_t free_count = h->free_count, sample_count = h->sample_count;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last, nth = at[k];
        block_range(count, k, &first, &last);
        for (size_t i = first; i < last; ++i) {
            if ((made && !made[i]) || seen[i].weight[0] == NO_SAMPLE) continue;
            uint32_t slot = nth < free_count ? h->free_samples[free_count - 1 - nth]
                                             : (uint32_t)(sample_count + (nth - free_count));
            ++nth;
            links[i].sample = slot;
            h->samples[slot] = seen[i];
        }
    }
    h->free_count = wanted < free_count ? free_count - wanted : 0;
    h->sample_count = sample_count + (wanted > free_count ? wanted - free_count : 0);
    h->samples_new += wanted;
    return RAD_OK;
}

/* Puts the samples in link order, which the gather reads them in (in the order they were made
 * its reads missed the cache: the 10^5 office's gather took 1.7 times as long), and drops the
 * free slots: copied into a new array in link order, the links cut into blocks whose samples
 * are counted, then copied, in parallel. (It used to permute them in place, following the
 * cycles one slot at a time: 13 s of one thread at 10^6, every step a cache miss.) Not when
 * fewer than 1 in ORDER_NEW of the samples came since the last time: the copy, most of a late
 * refinement pass at 10^6 triangles, then costs more than the few cache misses it saves (the
 * links are as before; the gather's sums read the same values in the same order). */
#define ORDER_NEW 16
static rad_status order_samples(rad_hier *h) {
    if (!h->sample_count) return RAD_OK;
    if (h->samples_new * ORDER_NEW < h->sample_count - h->free_count) return RAD_OK;
    h->samples_new = 0;
    size_t at[BLOCKS + 1];
    const size_t count = h->link_count;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last, here = 0;
        block_range(count, k, &first, &last);
        for (size_t l = first; l < last; ++l) here += h->links[l].sample != RAD_HIER_NO_NODE;
        at[k + 1] = here;
    }
    at[0] = 0;
    const size_t used = block_starts(at);
    link_sample *ordered = rad_alloc(h->ctx, used ? used : 1, sizeof *ordered);
    if (!ordered) return RAD_ERROR_NO_MEMORY;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 4096)
    for (long k = 0; k < BLOCKS; ++k) {
        size_t first, last, slot = at[k];
        block_range(count, k, &first, &last);
        for (size_t l = first; l < last; ++l) {
            rad_hier_link *link = &h->links[l];
            if (link->sample == RAD_HIER_NO_NODE) continue;
            ordered[slot] = h->samples[link->sample];
            link->sample = (uint32_t)slot++;
        }
    }
    rad_free(h->ctx, h->samples);
    h->samples = ordered;
    h->sample_count = used;
    h->free_count = 0;
    h->sample_capacity = used; /* the free list holds at least as many slots (keep_samples) */
    uint32_t *free_fit = used ? rad_realloc(h->ctx, h->free_samples, used, sizeof *free_fit) : NULL;
    if (free_fit) h->free_samples = free_fit;
    return RAD_OK;
}

rad_status rad_hier_refine(rad_hier *h) {
    rad_context *ctx = h->ctx;
    /* The links the oracle has yet to pass (at first all of them), those it passed, and the
     * new ones made by splitting. */
    rad_hier_link *pending = h->links, *kept = NULL, *fresh = NULL;
    size_t pending_count = h->link_count, kept_count = 0;
    size_t sorted_count = 0; /* the links kept in place at the front of `kept`, still sorted */
    uint8_t *decision = NULL, *made = NULL;
    uint8_t *leaf_end = NULL; /* per pending link: 1 + the end its decision splits when that end
                                 is a polygon leaf (new nodes), else 0 */
    uint32_t *to_split = NULL; /* those leaves, each once, in link order */
    size_t refined = 0, unrefined = 0, unknown_error = 0;
    double largest = 0, found = 0;
    int budget = 0, first_pass = 1, cancelled = 0;
    rad_status status = brightest_members(h);
    if (status) return status;
    if (h->refining) {
        /* Going on with a refinement stopped between two passes, from its next pass. */
        pending_count = h->link_count - h->refine_kept;
        pending = rad_alloc(ctx, pending_count ? pending_count : 1, sizeof *pending);
        if (!pending) return RAD_ERROR_NO_MEMORY;
        memcpy(pending, h->links + h->refine_kept, pending_count * sizeof *pending);
        kept = h->links;
        kept_count = h->refine_kept;
        refined = h->stats.refined;
        largest = h->stats.largest_error;
        found = h->stats.found_error;
        budget = h->stats.budget_reached;
        first_pass = 0;
        h->refining = 0;
        h->refine_kept = 0;
    } else {
        status = refine_light(h, &refined, &largest);
    }
    h->links = NULL;
    h->link_count = 0;
    for (; pending_count && !status; first_pass = 0) {
        /* Ctrl-C between two passes: the state (the links passed and the ones to ask about,
         * every node made so far) is kept as it is, for the next call to go on from. */
        if (!first_pass && rad_progress(ctx, "hierarchical refinement", (double)refined, 0)) {
            cancelled = 1;
            break;
        }
        rad_free(ctx, decision);
        rad_free(ctx, leaf_end);
        decision = rad_alloc(ctx, pending_count, 1);
        leaf_end = rad_alloc(ctx, pending_count, 1);
        if (!decision || !leaf_end) {
            status = RAD_ERROR_NO_MEMORY;
            break;
        }
        size_t splits = 0, candidates = 0;
        double pass_largest = 0, pass_found = 0;
        /* The oracle over the pending links, with the current radiosities. */
#pragma omp parallel for schedule(static) num_threads(threads(h)) \
    if (pending_count >= PARALLEL_MIN) reduction(max : pass_largest, pass_found) \
    reduction(+ : splits, candidates)
        for (long i = 0; i < (long)pending_count; ++i) {
            double relative;
            decision[i] = (uint8_t)decide_any(h, &pending[i], &relative);
            int known = fabsf(pending[i].error) < UNKNOWN_ERROR;
            /* A link between overlapping ends has no known error: refined, it makes the
             * largest error found unknown (infinite). */
            if (known || decision[i]) pass_found = larger(pass_found, known ? relative : INFINITY);
            leaf_end[i] = 0;
            if (decision[i]) {
                splits++;
                candidates += children_made(h, &pending[i], decision[i]);
                /* A self-link (3) joins clusters, which are opened, never split. */
                uint32_t end = decision[i] == 1 ? pending[i].receiver : pending[i].source;
                if (decision[i] != 3 && !cluster_index(h, end) &&
                    h->nodes[end].first_child == RAD_HIER_NO_NODE)
                    leaf_end[i] = decision[i];
            } else if (known)
                pass_largest = larger(pass_largest, relative);
        }
        largest = larger(largest, pass_largest);
        if (first_pass) found = larger(found, pass_found);
        if (!splits && first_pass) {
            /* The oracle passed every link: they stay as they are, sorted, with their groups. */
            h->links = pending;
            h->link_count = pending_count;
            pending = NULL;
            break;
        }
        /* The nodes this pass makes: four for each distinct polygon leaf it splits (opening a
         * cluster or an already split node makes none), listed in link order so that they are
         * numbered the same for any thread count. */
        size_t split_count = 0;
        if (splits) {
            uint8_t *marked = rad_alloc_zero(ctx, h->node_count, 1);
            rad_free(ctx, to_split);
            to_split = rad_alloc(ctx, splits, sizeof *to_split);
            if (!marked || !to_split) {
                rad_free(ctx, marked);
                status = RAD_ERROR_NO_MEMORY;
                break;
            }
            for (size_t i = 0; i < pending_count; ++i) {
                if (!leaf_end[i]) continue;
                uint32_t leaf = leaf_end[i] == 1 ? pending[i].receiver : pending[i].source;
                if (!marked[leaf]) {
                    marked[leaf] = 1;
                    to_split[split_count++] = leaf;
                }
            }
            rad_free(ctx, marked);
        }
        size_t new_nodes = 4 * split_count;
        if (splits &&
            check_memory(h, kept_count + pending_count + candidates,
                         h->node_count + new_nodes) == RAD_ERROR_MEMORY_BUDGET) {
            /* Keep the solution so far: say why refinement stops, then stop refining (not
             * when not even the first links fit: the solver fails with the budget's message). */
            if (kept_count + pending_count > 1)
                rad_warn(ctx, "%s; refinement stops at %zu links, keeping the solution so far",
                         rad_context_error(ctx), kept_count + pending_count);
            budget = 1;
            memset(decision, 0, pending_count);
            splits = 0;
        }
        /* Links made without their estimate that the oracle keeps after all (the budget
         * stopped refinement): estimated now. */
        link_sample *estimated = budget ? rad_alloc(ctx, pending_count, sizeof *estimated) : NULL;
        if (budget && !estimated) {
            status = RAD_ERROR_NO_MEMORY;
            break;
        }
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (pending_count >= 4096)
        for (long i = 0; i < (long)pending_count; ++i) {
            if (estimated) estimated[i].weight[0] = NO_SAMPLE;
            if (!decision[i] && pending[i].form_factor == NOT_ESTIMATED)
                make_any_link(h, pending[i].receiver, pending[i].source, &pending[i], 0,
                              estimated ? &estimated[i] : NULL);
        }
        if (estimated) status = keep_samples(h, pending, estimated, NULL, pending_count);
        rad_free(ctx, estimated);
        if (status) break;
        /* What the budget leaves over the threshold; the largest error is the largest known
         * (a link between overlapping ends carries UNKNOWN_ERROR until it is refined). */
        for (size_t i = 0; budget && i < pending_count; ++i) {
            double relative;
            int over = decide_any(h, &pending[i], &relative) != 0;
            int unknown = fabsf(pending[i].error) >= UNKNOWN_ERROR;
            unrefined += over;
            unknown_error += over && unknown;
            if (!unknown) largest = larger(largest, relative);
        }
        refined += splits;
        /* The samples of the links refined away make room for their children's. */
        for (size_t i = 0; i < pending_count && splits; ++i)
            if (decision[i] && pending[i].sample != RAD_HIER_NO_NODE)
                h->free_samples[h->free_count++] = pending[i].sample;
        /* Split the leaves the decisions ask for, in parallel, each into the four nodes its
         * place in the list gives it. */
        size_t nodes_before = h->node_count;
        if (splits && split_count) {
            status = reserve_nodes(h, new_nodes);
            if (status) break;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (split_count >= PARALLEL_MIN)
            for (long j = 0; j < (long)split_count; ++j)
                split_into(h, to_split[j], (uint32_t)(nodes_before + 4 * (size_t)j));
            h->node_count += new_nodes;
            h->stats.leaves += 3 * split_count;
        }
        light_nodes(h, nodes_before);
        /* Links the oracle passed are kept; the others are replaced by their children's. The
         * pending links are cut into blocks whose kept and new links are counted in parallel;
         * each block then writes its own slots, in link order. The first pass keeps its links
         * where they are (sorted by receiver, merge_links), moved down over the refined ones
         * after the children are written. */
        size_t count = 0, keep = pending_count - splits;
        const int in_place = first_pass && !kept;
        fresh = splits ? rad_alloc(ctx, candidates, sizeof *fresh) : NULL;
        made = splits ? rad_alloc(ctx, candidates, 1) : NULL;
        if (splits && (!fresh || !made)) status = RAD_ERROR_NO_MEMORY;
        if (!status && keep && !in_place) {
            rad_hier_link *grown = rad_realloc(ctx, kept, kept_count + keep, sizeof *grown);
            if (grown) kept = grown;
            else status = RAD_ERROR_NO_MEMORY;
        }
        if (!status) {
            size_t keep_at[BLOCKS + 1], fresh_at[BLOCKS + 1];
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (pending_count >= 4096)
            for (long k = 0; k < BLOCKS; ++k) {
                size_t kept_here = 0, fresh_here = 0, first, last;
                block_range(pending_count, k, &first, &last);
                for (size_t i = first; i < last; ++i)
                    if (!decision[i]) kept_here++;
                    else fresh_here += children_made(h, &pending[i], decision[i]);
                keep_at[k + 1] = kept_here;
                fresh_at[k + 1] = fresh_here;
            }
            keep_at[0] = kept_count;
            fresh_at[0] = 0;
            block_starts(keep_at);
            block_starts(fresh_at);
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (pending_count >= 4096)
            for (long k = 0; k < BLOCKS; ++k) {
                size_t at_kept = keep_at[k], at_fresh = fresh_at[k], first, last;
                block_range(pending_count, k, &first, &last);
                for (size_t i = first; i < last; ++i) {
                    if (!decision[i]) {
                        if (!in_place) kept[at_kept++] = pending[i];
                        continue;
                    }
                    const rad_hier_link link = pending[i];
                    const rad_hier_node *r = &h->nodes[link.receiver], *s = &h->nodes[link.source];
                    uint32_t r_first = link.receiver, r_count = 1, s_first = link.source, s_count = 1;
                    if (decision[i] != 2) r_first = r->first_child, r_count = r->child_count;
                    if (decision[i] != 1) s_first = s->first_child, s_count = s->child_count;
                    for (uint32_t a = 0; a < r_count; ++a)
                        for (uint32_t b = 0; b < s_count; ++b) {
                            fresh[at_fresh].receiver = r_first + a;
                            fresh[at_fresh].source = s_first + b;
                            ++at_fresh;
                        }
                }
            }
            kept_count = keep_at[BLOCKS];
            count = fresh_at[BLOCKS];
            if (in_place) {
                sorted_count = compact_links(h, pending, pending_count, decision, 0);
                kept = pending;
            }
        }
        if (pending != kept) rad_free(ctx, pending);
        pending = NULL;
        pending_count = 0;
        if (status || !splits) break;
        /* The new links' form factors, in parallel (each writes its own slot). */
        link_sample *seen = rad_alloc(ctx, count ? count : 1, sizeof *seen);
        if (!seen) {
            status = RAD_ERROR_NO_MEMORY;
            break;
        }
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (count >= 64)
        for (long i = 0; i < (long)count; ++i)
            made[i] = (uint8_t)make_any_link(h, fresh[i].receiver, fresh[i].source, &fresh[i], 1,
                                             &seen[i]);
        status = keep_samples(h, fresh, seen, made, count);
        rad_free(ctx, seen);
        if (status) break;
        pending_count = compact_links(h, fresh, count, made, 1);
        rad_free(ctx, made);
        made = NULL;
        pending = fresh;
        fresh = NULL;
    }
    rad_free(ctx, decision);
    rad_free(ctx, leaf_end);
    rad_free(ctx, to_split);
    rad_free(ctx, made);
    rad_free(ctx, fresh);
    h->stats.largest_error = largest;
    h->stats.found_error = larger(found, largest);
    h->stats.refined = refined;
    h->stats.budget_reached = budget;
    h->stats.unrefined = unrefined;
    h->stats.unknown_error = unknown_error;
    if (cancelled && !status) {
        /* The links passed, then the ones still to ask about, in one array. */
        rad_hier_link *all = rad_realloc(ctx, kept, kept_count + pending_count, sizeof *all);
        if (!all) status = RAD_ERROR_NO_MEMORY;
        else {
            memcpy(all + kept_count, pending, pending_count * sizeof *all);
            kept = NULL;
            rad_free(ctx, h->group_first);
            h->group_first = NULL;
            h->group_count = 0;
            h->links = all;
            h->link_count = kept_count + pending_count;
            h->stats.links = h->link_count;
            h->refine_kept = kept_count;
            h->refining = 1;
            rad_free(ctx, pending);
            return rad_fail(ctx, RAD_ERROR_CANCELLED,
                            "refinement cancelled after %zu links refined", refined);
        }
    }
    rad_free(ctx, pending);
    if (status) {
        rad_free(ctx, kept);
        return status;
    }
    if (h->links) return RAD_OK; /* nothing refined: the links were not touched */
    if (!kept) {
        kept = rad_alloc(ctx, 1, sizeof *kept);
        if (!kept) return RAD_ERROR_NO_MEMORY;
    }
    status = merge_links(h, kept, sorted_count, kept_count);
    return status ? status : order_samples(h);
}

/* ---- Solving ----------------------------------------------------------------------------- */

/* Pushes irradiance down to the leaves (adding what each level gathered), sets the leaves'
 * radiosity E + rho H, and pulls area-weighted means back up. Returns the largest change of a
 * leaf's radiosity. */
static double push_pull(rad_hier *h, uint32_t index, const double down[3]) {
    rad_hier_node *n = &h->nodes[index];
    double total[3];
    for (int c = 0; c < 3; ++c) total[c] = down[c] + n->irradiance[c];
    double change = 0;
    if (n->first_child == RAD_HIER_NO_NODE) {
        const double *rho = h->reflectance[n->polygon], *e = h->emission[n->polygon];
        const double zero[3] = {0, 0, 0}, *light = h->light ? h->light[index] : zero;
        for (int c = 0; c < 3; ++c) {
            double b = e[c] + light[c] + rho[c] * total[c];
            change = larger(change, fabs(b - n->radiosity[c]));
            n->radiosity[c] = b;
        }
        return change;
    }
    double sum[3] = {0, 0, 0}, area = 0;
    for (uint32_t k = 0; k < n->child_count; ++k) {
        uint32_t child = n->first_child + k;
        change = larger(change, push_pull(h, child, total));
        const rad_hier_node *m = &h->nodes[child];
        for (int c = 0; c < 3; ++c) sum[c] += m->radiosity[c] * m->area;
        area += m->area;
    }
    n = &h->nodes[index];
    for (int c = 0; c < 3; ++c) n->radiosity[c] = area > 0 ? sum[c] / area : 0;
    return change;
}

/* Pulls up cluster c from its children: its radiosity is the area-weighted mean of its
 * members'; a leaf cluster copies its member roots' radiosity where link samples read it
 * (root_radiosity). */
static void pull_cluster(rad_hier *h, size_t c) {
    rad_hier_node *n = &h->nodes[h->cluster_first + c];
    double sum[3] = {0, 0, 0};
    for (uint32_t k = 0; k < n->child_count; ++k) {
        uint32_t child = n->first_child + k;
        const rad_hier_node *m = &h->nodes[child];
        for (int i = 0; i < 3; ++i) sum[i] += m->radiosity[i] * m->area;
        if (!is_cluster(m)) memcpy(h->root_radiosity[child], m->radiosity, sizeof(rgb));
    }
    for (int i = 0; i < 3; ++i) n->radiosity[i] = n->area > 0 ? sum[i] / n->area : 0;
}

/* Pulls up every cluster, children first: the leaf clusters (whose members are roots) in
 * parallel, then the others from the last to the first (children are numbered after their
 * parents). */
static void pull_clusters(rad_hier *h) {
    const long count = (long)h->cluster_count;
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (count >= 64)
    for (long c = 0; c < count; ++c)
        if (h->walk[c].leaf) pull_cluster(h, (size_t)c);
    for (size_t c = h->cluster_count; c-- > 0;)
        if (!h->walk[c].leaf) pull_cluster(h, c);
}

/* The gather reads each link's source at a random place: a node's radiosity, or a sampled
 * cluster link's four members' radiosities (link_sample, root_radiosity; source_radiosity). Asked for
 * GATHER_AHEAD links before they are read, the misses of several links wait side by side
 * instead of one after another. No value changes. */
#define GATHER_AHEAD 8
static void prefetch_source(const rad_hier *h, const rad_hier_link *link) {
    if (link->sample == RAD_HIER_NO_NODE) {
        __builtin_prefetch(h->nodes[link->source].radiosity);
        return;
    }
    const link_sample *seen = &h->samples[link->sample];
    for (int k = 0; k < 4; ++k) __builtin_prefetch(h->root_radiosity[seen->member[k]]);
}

rad_status rad_hier_solve(rad_hier *h, double tolerance, int max_rounds) {
    const long groups = (long)h->group_count, roots = (long)h->root_count;
    const long nodes = (long)h->node_count;
    double limit = tolerance * (h->emission_max > 0 ? h->emission_max : 1);
    int round = 0;
    if (h->refining)
        return rad_fail(h->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the hierarchy's refinement was stopped: refine before solving");
    if (h->importance_unfinished) {
        /* The light's rounds converged before the importance rounds were stopped. */
        rad_status status = solve_importance(h, tolerance, max_rounds);
        h->importance_unfinished = status == RAD_ERROR_CANCELLED;
        return status;
    }
    pull_clusters(h); /* the clusters start from their members as they are now */
    /* The kernel's weights, once for this solve's rounds (source_kernel.h), in what the memory
     * budget leaves beside the links and nodes (check_memory's count). */
    double held = held_bytes(h, h->link_count, h->node_count);
    rad_status kept = rad_hier_kernel_cache_build(h->ctx, &h->kernel, h->nodes, h->normal, h->links,
                                                  h->source_depth ? h->link_count : 0,
                                                  h->source_depth,
                                                  (double)h->ctx->max_memory - held, threads(h));
    if (kept) return kept;
    /* A node that receives no link gathers nothing: zeroed once for the solve (the rounds write
     * only the receivers', whose links stay the same until the next refinement). Zeroing every
     * node at every round wrote a cache line per node (1.6 M at 10^6 triangles) for nothing. */
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (nodes >= PARALLEL_MIN)
    for (long i = 0; i < nodes; ++i) memset(h->nodes[i].irradiance, 0, sizeof(double[3]));
    for (round = 1; round <= max_rounds; ++round) {
        /* Gather: every receiver sums its links in their fixed order. */
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads(h)) if (nodes >= PARALLEL_MIN)
        for (long g = 0; g < groups; ++g) {
            double sum[3] = {0, 0, 0};
            size_t first = h->group_first[g], last = h->group_first[g + 1];
            for (size_t l = first; l < last; ++l) {
                const rad_hier_link *link = &h->links[l];
                double b[3];
                if (l + GATHER_AHEAD < h->link_count && h->links[l + GATHER_AHEAD].form_factor != 0)
                    prefetch_source(h, &h->links[l + GATHER_AHEAD]);
                /* A link of factor 0 (its rays saw nothing of the source: 46% of
                 * them in the 10^5 office) adds exactly 0 to the sum: its source is not read. */
                if (link->form_factor == 0) continue;
                source_radiosity(h, link, b);
                for (int c = 0; c < 3; ++c) sum[c] += (double)link->form_factor * b[c];
            }
            memcpy(h->nodes[h->links[first].receiver].irradiance, sum, sizeof sum);
        }
        /* Push down the clusters (parents come before their children): each passes what it
         * and its ancestors gathered to its members, per unit area. */
        for (size_t c = 0; c < h->cluster_count; ++c) {
            uint32_t parent = h->clusters[c].parent;
            const double *gathered = h->nodes[h->cluster_first + c].irradiance;
            for (int k = 0; k < 3; ++k)
                h->cluster_down[c][k] = gathered[k] +
                    (parent == RAD_HIER_NO_NODE ? 0 : h->cluster_down[parent - h->cluster_first][k]);
        }
        /* Push-pull through the polygon trees, one tree per task. */
        double change = 0;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (roots >= 64) \
    reduction(max : change)
        for (long r = 0; r < roots; ++r) {
            const double *down = h->cluster_down[h->root_parent[r] - h->cluster_first];
            change = larger(change, push_pull(h, (uint32_t)r, down));
        }
        pull_clusters(h);
        if (change <= limit) break;
        if (rad_progress(h->ctx, "hierarchical gathering", round, max_rounds)) {
            rad_hier_kernel_cache_free(h->ctx, &h->kernel);
            return rad_fail(h->ctx, RAD_ERROR_CANCELLED, "cancelled after %d gathering rounds",
                            round);
        }
    }
    rad_hier_kernel_cache_free(h->ctx, &h->kernel); /* the next refinement changes the links */
    h->stats.solve_rounds = round > max_rounds ? max_rounds : round;
    if (!h->hit_point) return RAD_OK;
    rad_status status = solve_importance(h, tolerance, max_rounds);
    h->importance_unfinished = status == RAD_ERROR_CANCELLED;
    return status;
}

/* ---- Importance (Smits, Arvo & Salesin 1992) --------------------------------------------- */

/* Importance is the adjoint of light. A pixel's ray that meets leaf l emits A R = (the share of
 * the image it is) there; Y, the importance of unit radiosity, is what a leaf emits per unit
 * area plus what reaches it over the transposed links: a link r <- s of factor F (light from s
 * to r) carries Z_r F to s, where Z_r = sum rho A Y over the leaves under r (the image's change
 * per unit of r's irradiance), so that the image changes by F B_s Z_r through it. A polygon
 * source takes Z_r F / A_s per unit area (pushed down to its leaves like irradiance); a
 * cluster source sends sum_a |w_a| power(a) / sum_a |w_a| area(a) (source_radiosity), so it
 * takes Z_r F |w_a| / sum_a |w_a| area(a) per signed axis a, and a member with normal n gets
 * sum_a of that times max(0, +-n_a) per unit area: the exact adjoint of the light's transport
 * over the same links. Jacobi rounds, as for light. */

/* The largest reflectance of a polygon: importance is one channel, and the largest carries the
 * most of it on (conservative: more refinement, never less). */
static double polygon_reflectance(const rad_hier *h, uint32_t polygon) {
    const double *rho = h->reflectance[polygon];
    return larger(rho[0], larger(rho[1], rho[2]));
}

/* Z of a node: sum rho A Y over its leaves. */
static double node_z(const rad_hier *h, uint32_t index) {
    const rad_hier_node *n = &h->nodes[index];
    if (is_cluster(n)) return h->cluster_z[index - h->cluster_first];
    return polygon_reflectance(h, n->polygon) * h->importance[index];
}

/* Pushes importance down one polygon tree (`down` per unit area, from clusters and ancestors),
 * sets every leaf's A Y = A R + A (down + gathered) and pulls the sums up. Returns the largest
 * change of a leaf's Y. */
static double importance_push_pull(rad_hier *h, uint32_t index, double down) {
    rad_hier_node *n = &h->nodes[index];
    double total = down + h->importance_gathered[index];
    if (n->first_child == RAD_HIER_NO_NODE) {
        double y = (n->area > 0 ? h->importance_emitted[index] / n->area : 0) + total;
        double change = fabs(y - (n->area > 0 ? h->importance[index] / n->area : 0));
        h->importance[index] = y * n->area;
        return change;
    }
    double change = 0, sum = 0;
    for (uint32_t k = 0; k < n->child_count; ++k) {
        uint32_t child = n->first_child + k;
        change = larger(change, importance_push_pull(h, child, total));
        sum += h->importance[child];
    }
    h->importance[index] = sum;
    return change;
}

/* Clusters' A Y and Z from their members, children first. */
static void importance_pull_clusters(rad_hier *h) {
    for (size_t c = h->cluster_count; c-- > 0;) {
        uint32_t index = (uint32_t)(h->cluster_first + c);
        const rad_hier_node *n = &h->nodes[index];
        double y = 0, z = 0;
        for (uint32_t k = 0; k < n->child_count; ++k) {
            y += h->importance[n->first_child + k];
            z += node_z(h, n->first_child + k);
        }
        h->importance[index] = y;
        h->cluster_z[c] = z;
    }
}

static rad_status solve_importance(rad_hier *h, double tolerance, int max_rounds) {
    const long roots = (long)h->root_count;
    /* What the pixels emit, on the leaves as they are now. */
    memset(h->importance_emitted, 0, h->node_count * sizeof *h->importance_emitted);
    double emitted_max = 0;
    for (size_t i = 0; i < h->hit_count; ++i) {
        uint32_t leaf = leaf_at(h, h->hit_polygon[i], h->hit_point[i]);
        if (leaf != RAD_HIER_NO_NODE) h->importance_emitted[leaf] += h->hit_share;
    }
    for (size_t i = 0; i < h->node_count; ++i)
        if (h->importance_emitted[i] > 0 && h->nodes[i].area > 0)
            emitted_max = larger(emitted_max, h->importance_emitted[i] / h->nodes[i].area);
    double limit = tolerance * (emitted_max > 0 ? emitted_max : 1);
    importance_pull_clusters(h);
    for (int round = 1; round <= max_rounds; ++round) {
        /* Gather over the transposed links, in link order (one thread: sources are shared). */
        memset(h->importance_gathered, 0, h->node_count * sizeof *h->importance_gathered);
        memset(h->cluster_axis_importance, 0, h->cluster_count * sizeof *h->cluster_axis_importance);
        for (size_t l = 0; l < h->link_count; ++l) {
            const rad_hier_link *link = &h->links[l];
            double carried = node_z(h, link->receiver) * (double)link->form_factor;
            if (!(carried > 0)) continue;
            const rad_hier_node *s = &h->nodes[link->source];
            if (!is_cluster(s)) {
                if (s->area > 0) h->importance_gathered[link->source] += carried / s->area;
                continue;
            }
            /* The adjoint of source_radiosity: per signed axis toward the receiver. */
            const cluster_info *ci = info(h, link->source);
            const rad_hier_node *r = &h->nodes[link->receiver];
            rad_vec3 w = v3_sub(is_cluster(r) ? info(h, link->receiver)->centre : surface_centre(r),
                                ci->centre);
            const double d[3] = {fabs(w.x), fabs(w.y), fabs(w.z)};
            const int side[3] = {w.x < 0, w.y < 0, w.z < 0};
            double area = 0;
            for (int a = 0; a < 3; ++a) area += d[a] * ci->axis_area[2 * a + side[a]];
            if (area > 0)
                for (int a = 0; a < 3; ++a)
                    h->cluster_axis_importance[link->source - h->cluster_first][2 * a + side[a]] +=
                        carried * d[a] / area;
        }
        /* Down the clusters (parents first), then down every polygon tree. */
        for (size_t c = 0; c < h->cluster_count; ++c) {
            uint32_t parent = h->clusters[c].parent;
            for (int a = 0; a < 6; ++a)
                h->cluster_down_importance[c][a] =
                    h->cluster_axis_importance[c][a] +
                    (parent == RAD_HIER_NO_NODE
                         ? 0
                         : h->cluster_down_importance[parent - h->cluster_first][a]);
        }
        double change = 0;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (roots >= 64) \
    reduction(max : change)
        for (long r = 0; r < roots; ++r) {
            const double *q = h->cluster_down_importance[h->root_parent[r] - h->cluster_first];
            rad_vec3 normal = h->normal[h->nodes[r].polygon];
            const double n[3] = {normal.x, normal.y, normal.z};
            double down = 0;
            for (int a = 0; a < 3; ++a)
                down += q[2 * a] * larger(0, n[a]) + q[2 * a + 1] * larger(0, -n[a]);
            change = larger(change, importance_push_pull(h, (uint32_t)r, down));
        }
        importance_pull_clusters(h);
        if (change <= limit) break;
        if (rad_progress(h->ctx, "hierarchical importance", round, max_rounds))
            return rad_fail(h->ctx, RAD_ERROR_CANCELLED, "cancelled after %d importance rounds",
                            round);
    }
    double total = 0, area = 0;
    for (size_t r = 0; r < h->root_count; ++r) {
        total += h->importance[r];
        area += h->nodes[r].area;
    }
    h->importance_mean = area > 0 ? total / area : 0;
    return RAD_OK;
}

rad_status rad_hier_set_view(rad_hier *h, const rad_view *view) {
    rad_context *ctx = h->ctx;
    size_t pixels = (size_t)view->width * (size_t)view->height;
    uint32_t *polygon = rad_alloc(ctx, pixels ? pixels : 1, sizeof *polygon);
    rad_vec3 *point = rad_alloc(ctx, pixels ? pixels : 1, sizeof *point);
    if (!polygon || !point) {
        rad_free(ctx, polygon);
        rad_free(ctx, point);
        return RAD_ERROR_NO_MEMORY;
    }
    /* One ray through every pixel's centre; only fronts count (the light lives there). Each
     * pixel writes its own slot, so the hits do not depend on the thread count. */
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads(h))
    for (int y = 0; y < view->height; ++y)
        for (int x = 0; x < view->width; ++x) {
            size_t i = (size_t)y * (size_t)view->width + (size_t)x;
            rad_vec3 direction = rad_view_direction(view, x + 0.5, y + 0.5);
            rad_hit hit;
            polygon[i] = RAD_HIER_NO_NODE;
            if (rad_rays_intersect(h->rays, view->eye, direction, 0, INFINITY, &hit) && hit.front) {
                polygon[i] = hit.polygon;
                point[i] = v3_add(view->eye, v3_scale(direction, hit.t));
            }
        }
    size_t count = 0;
    for (size_t i = 0; i < pixels; ++i)
        if (polygon[i] != RAD_HIER_NO_NODE && polygon[i] < h->scene->polygon_count &&
            h->polygon_root_count[polygon[i]] > 0) {
            polygon[count] = polygon[i];
            point[count] = point[i];
            ++count;
        }
    rad_status status =
        rad_hier_restore_view(h, polygon, point, count, pixels ? 1.0 / (double)pixels : 0);
    if (status) return status;
    h->stats.seen_share = (double)count * h->hit_share;
    return solve_importance(h, 1e-5, 1000);
}

double rad_hier_importance(const rad_hier *h, uint32_t node) {
    if (!h->importance || node >= h->node_count || !(h->nodes[node].area > 0)) return 0;
    return h->importance[node] / h->nodes[node].area;
}

/* ---- Clusters ---------------------------------------------------------------------------- */

typedef struct cluster_range {
    size_t first, count;     /* roots order[first .. first + count) */
    size_t first_child;      /* the first child cluster (an internal cluster's two) */
    size_t parent;           /* the parent cluster, or SIZE_MAX */
} cluster_range;

/* Takes rad_vec3 component `axis`. */
static double component(rad_vec3 v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }


/* The bounding-volume hierarchy of the roots: a cluster of more than LEAF_CLUSTER roots splits
 * at the midpoint of its centroids' bounds along their longest axis (in half by count when
 * they coincide), breadth first, so parents precede children and an internal cluster's two
 * children are adjacent. The roots are then renumbered so that every leaf cluster's roots are
 * contiguous; the clusters are appended after them as nodes, and their bounds, axis areas,
 * reflectance and radiosity are gathered bottom-up. */
static rad_status build_clusters(rad_hier *h) {
    rad_context *ctx = h->ctx;
    size_t n = h->root_count;
    uint32_t *order = rad_alloc(ctx, n, sizeof *order);
    rad_vec3 *centroid = rad_alloc(ctx, n, sizeof *centroid);
    cluster_range *ranges = rad_alloc(ctx, 2 * n, sizeof *ranges);
    rad_hier_node *roots = rad_alloc(ctx, n, sizeof *roots);
    h->polygon_roots = rad_alloc(ctx, n, sizeof *h->polygon_roots);
    h->root_parent = rad_alloc(ctx, n, sizeof *h->root_parent);
    rad_status status = RAD_OK;
    if (!order || !centroid || !ranges || !roots || !h->polygon_roots || !h->root_parent)
        status = RAD_ERROR_NO_MEMORY;
    size_t count = 1;
    if (!status) {
        for (size_t i = 0; i < n; ++i) {
            order[i] = (uint32_t)i;
            centroid[i] = surface_centre(&h->nodes[i]);
        }
        ranges[0] = (cluster_range){0, n, 0, SIZE_MAX};
    }
    for (size_t c = 0; c < count && !status; ++c) {
        cluster_range *r = &ranges[c];
        if (r->count <= LEAF_CLUSTER) continue;
        rad_vec3 lo = centroid[order[r->first]], hi = lo;
        for (size_t i = r->first; i < r->first + r->count; ++i) {
            lo = v3_min(lo, centroid[order[i]]);
            hi = v3_max(hi, centroid[order[i]]);
        }
        rad_vec3 extent = v3_sub(hi, lo);
        int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        double split = 0.5 * (component(lo, axis) + component(hi, axis));
        size_t i = r->first, j = r->first + r->count;
        while (i < j) {
            if (component(centroid[order[i]], axis) < split) ++i;
            else {
                uint32_t t = order[--j];
                order[j] = order[i];
                order[i] = t;
            }
        }
        if (i == r->first || i == r->first + r->count) i = r->first + r->count / 2;
        ranges[count] = (cluster_range){r->first, i - r->first, 0, c};
        ranges[count + 1] = (cluster_range){i, r->first + r->count - i, 0, c};
        r->first_child = count;
        count += 2;
    }
    if (!status) status = reserve_nodes(h, count);
    if (!status) {
        /* Renumber the roots in cluster order. */
        memcpy(roots, h->nodes, n * sizeof *roots);
        for (size_t k = 0; k < n; ++k) {
            h->nodes[k] = roots[order[k]];
            h->nodes[k].root = (uint32_t)k;
            h->polygon_roots[order[k]] = (uint32_t)k;
        }
        h->walk_memory = rad_alloc(ctx, count + 4, sizeof *h->walk);
        h->root_walk = rad_alloc(ctx, n, sizeof *h->root_walk);
        h->clusters = rad_alloc_zero(ctx, count, sizeof *h->clusters);
        h->cluster_down = rad_alloc_zero(ctx, count, sizeof *h->cluster_down);
        if (!h->clusters || !h->cluster_down || !h->walk_memory || !h->root_walk)
            status = RAD_ERROR_NO_MEMORY;
    }
    if (!status) {
        h->cluster_first = n;
        h->cluster_count = count;
        for (size_t c = 0; c < count; ++c) {
            const cluster_range *r = &ranges[c];
            rad_hier_node *node = &h->nodes[n + c];
            memset(node, 0, sizeof *node);
            node->polygon = RAD_HIER_NO_NODE;
            node->root = (uint32_t)(n + c);
            int leaf = r->count <= LEAF_CLUSTER;
            node->first_child = (uint32_t)(leaf ? r->first : n + r->first_child);
            node->child_count = (uint32_t)(leaf ? r->count : 2);
            h->clusters[c].parent = r->parent == SIZE_MAX ? RAD_HIER_NO_NODE : (uint32_t)(n + r->parent);
            if (leaf)
                for (size_t k = r->first; k < r->first + r->count; ++k)
                    h->root_parent[k] = (uint32_t)(n + c);
        }
        h->node_count = n + count;
        /* Bounds, areas, orientations and radiosity, children first. */
        for (size_t c = count; c-- > 0;) {
            rad_hier_node *node = &h->nodes[n + c];
            cluster_info *ci = &h->clusters[c];
            ci->lo = v3(INFINITY, INFINITY, INFINITY);
            ci->hi = v3(-INFINITY, -INFINITY, -INFINITY);
            double power[3] = {0, 0, 0};
            for (uint32_t k = 0; k < node->child_count; ++k) {
                uint32_t child = node->first_child + k;
                const rad_hier_node *m = &h->nodes[child];
                if (is_cluster(m)) {
                    const cluster_info *mi = info(h, child);
                    ci->lo = v3_min(ci->lo, mi->lo);
                    ci->hi = v3_max(ci->hi, mi->hi);
                    for (int a = 0; a < 6; ++a) ci->axis_area[a] += mi->axis_area[a];
                    ci->normal_sum = v3_add(ci->normal_sum, mi->normal_sum);
                    ci->reflectance = larger(ci->reflectance, mi->reflectance);
                } else {
                    for (int k2 = 0; k2 < m->corner_count; ++k2) {
                        ci->lo = v3_min(ci->lo, m->corner[k2]);
                        ci->hi = v3_max(ci->hi, m->corner[k2]);
                    }
                    rad_vec3 normal = h->normal[m->polygon];
                    double d[3] = {normal.x, normal.y, normal.z};
                    for (int a = 0; a < 3; ++a) {
                        ci->axis_area[2 * a] += m->area * larger(0, d[a]);
                        ci->axis_area[2 * a + 1] += m->area * larger(0, -d[a]);
                    }
                    ci->normal_sum = v3_add(ci->normal_sum, v3_scale(normal, m->area));
                    for (int i = 0; i < 3; ++i)
                        ci->reflectance = larger(ci->reflectance, h->reflectance[m->polygon][i]);
                }
                node->area += m->area;
                for (int i = 0; i < 3; ++i) power[i] += m->radiosity[i] * m->area;
            }
            ci->centre = v3_scale(v3_add(ci->lo, ci->hi), 0.5);
            ci->radius = 0.5 * v3_length(v3_sub(ci->hi, ci->lo));
            for (int i = 0; i < 3; ++i) node->radiosity[i] = node->area > 0 ? power[i] / node->area : 0;
        }
        /* The walks' compact tables. An internal cluster's children are numbered 2j + 1 and
         * 2j + 2, so the table starts 32 bytes into a cache line and each pair shares one. */
        uintptr_t line = ((uintptr_t)h->walk_memory + 63) & ~(uintptr_t)63;
        h->walk = (walk_cluster *)line + 1;
        for (size_t c = 0; c < count; ++c) {
            const rad_hier_node *node = &h->nodes[n + c];
            walk_cluster *wc = &h->walk[c];
            for (int a = 0; a < 6; ++a) wc->axis_area[a] = (float)h->clusters[c].axis_area[a];
            wc->leaf = ranges[c].count <= LEAF_CLUSTER;
            wc->first = (uint32_t)(wc->leaf ? node->first_child : node->first_child - n);
            wc->count = (uint16_t)node->child_count;
        }
        for (size_t k = 0; k < n; ++k) {
            rad_vec3 normal = h->normal[h->nodes[k].polygon];
            h->root_walk[k] = (walk_root){(float)h->nodes[k].area,
                                          {(float)normal.x, (float)normal.y, (float)normal.z}};
        }
    }
    rad_free(ctx, order);
    rad_free(ctx, centroid);
    rad_free(ctx, ranges);
    rad_free(ctx, roots);
    return status;
}

/* Splits every root whose light (rad_hier_options.light) its children would hold differently
 * by more than the oracle allows: half the range of the children's light (the largest channel)
 * times the node's area, against the threshold; then the same for the children, depth first.
 * Light with edges of its own (the specular-first caustic under a glass sphere) is otherwise
 * spread over whatever leaves the links made. */
static rad_status split_by_light(rad_hier *h) {
    size_t count = h->root_count, capacity = count + 64;
    uint32_t *stack = rad_alloc(h->ctx, capacity, sizeof *stack);
    if (!stack) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < count; ++i) stack[i] = (uint32_t)(count - 1 - i);
    rad_status status = RAD_OK;
    while (count && !status) {
        uint32_t index = stack[--count];
        const rad_hier_node *n = &h->nodes[index];
        if (is_cluster(n) || !can_split(h, n)) continue;
        if (n->first_child == RAD_HIER_NO_NODE) {
            /* Its children's light, before making them. */
            rad_hier_node probe = *n;
            double lo = INFINITY, hi = -INFINITY;
            if ((status = subdivide(h, index))) break;
            light_nodes(h, h->nodes[index].first_child);
            for (uint32_t k = 0; k < 4; ++k)
                for (int c = 0; c < 3; ++c) {
                    lo = smaller(lo, h->light[h->nodes[index].first_child + k][c]);
                    hi = larger(hi, h->light[h->nodes[index].first_child + k][c]);
                }
            if (!(0.5 * (hi - lo) * probe.area > h->threshold)) {
                /* Resolved: take the children back (they are the last four nodes made). */
                h->node_count -= 4;
                h->nodes[index].first_child = RAD_HIER_NO_NODE;
                h->nodes[index].child_count = 0;
                continue;
            }
        }
        if (count + 4 > capacity) {
            capacity *= 2;
            uint32_t *grown = rad_realloc(h->ctx, stack, capacity, sizeof *stack);
            if (!grown) {
                status = RAD_ERROR_NO_MEMORY;
                break;
            }
            stack = grown;
        }
        for (uint32_t k = 0; k < 4; ++k) stack[count++] = h->nodes[index].first_child + 3 - k;
    }
    rad_free(h->ctx, stack);
    return status;
}

/* ---- Set-up and queries ------------------------------------------------------------------ */

rad_status rad_hier_create(rad_context *ctx, const rad_scene *scene,
                           const rad_hier_options *options, rad_hier **out) {
    return rad_hier_create_from(ctx, scene, options, NULL, out);
}

rad_status rad_hier_create_from(rad_context *ctx, const rad_scene *scene,
                                const rad_hier_options *options, const rad_roots *given,
                                rad_hier **out) {
    *out = NULL;
    rad_hier_options o = options ? *options : (rad_hier_options){0};
    if (o.link_error < 0 || !isfinite(o.link_error))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the link error must be a positive number, not %g", o.link_error);
    if (o.link_error == 0) o.link_error = DEFAULT_LINK_ERROR;
    if (!(o.min_area >= 0) || !isfinite(o.min_area))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bad minimum node area %g", o.min_area);
    if (o.min_area == 0) o.min_area = DEFAULT_MIN_AREA;
    rad_hier *h = rad_alloc_zero(ctx, 1, sizeof *h);
    if (!h) return RAD_ERROR_NO_MEMORY;
    h->ctx = ctx;
    h->salt = ctx->seed ? (uint32_t)(rad_mix64(ctx->seed) >> 32) : 0;
    h->scene = scene;
    h->no_clusters = o.no_clusters;
    h->light_fn = o.light;
    h->light_user = o.light_user;
    size_t np = scene->polygon_count;
    h->polygon_root_first = rad_alloc_zero(ctx, np + 1, sizeof *h->polygon_root_first);
    h->polygon_root_count = rad_alloc_zero(ctx, np + 1, sizeof *h->polygon_root_count);
    h->reflectance = rad_alloc_zero(ctx, np + 1, sizeof *h->reflectance);
    h->emission = rad_alloc_zero(ctx, np + 1, sizeof *h->emission);
    h->normal = rad_alloc_zero(ctx, np + 1, sizeof *h->normal);
    rad_status status = RAD_OK;
    if (!h->polygon_root_first || !h->polygon_root_count || !h->reflectance || !h->emission ||
        !h->normal)
        status = RAD_ERROR_NO_MEMORY;
    /* The roots: every polygon's contact-cut pieces as quads and triangles (mesh/roots.h), so
     * no root straddles a contact and the pieces hidden inside solids are left out. */
    rad_roots *made = NULL;
    if (!status && !given) status = rad_roots_create(ctx, scene, 1, &made);
    const rad_roots *roots = given ? given : made;
    double total_area = 0;
    size_t next_root = 0;
    for (size_t p = 0; p < np && !status; ++p) {
        const rad_polygon *polygon = &scene->polygons[p];
        const rad_material *m = &scene->materials[scene->surfaces[polygon->surface].material];
        for (int c = 0; c < 3; ++c) {
            h->reflectance[p][c] = m->reflectance[c];
            h->emission[p][c] = RAD_PI * m->emission[c];
            h->emission_max = larger(h->emission_max, h->emission[p][c]);
        }
        double emitted = larger(h->emission[p][0], larger(h->emission[p][1], h->emission[p][2]));
        h->normal[p] = rad_polygon_normal(scene, polygon);
        h->polygon_root_first[p] = (uint32_t)h->node_count; /* before renumbering: identity */
        for (; next_root < roots->count && roots->roots[next_root].polygon == p; ++next_root) {
            const rad_root *root = &roots->roots[next_root];
            if ((status = reserve_nodes(h, 1))) break;
            rad_hier_node *n = &h->nodes[h->node_count];
            init_node(h, n, root->corner, (int)root->count, (uint32_t)p,
                      (uint32_t)h->node_count, 0);
            if (!(n->area > 0)) continue;
            total_area += n->area;
            h->emitted_power += emitted * n->area;
            h->node_count++;
            h->polygon_root_count[p]++;
        }
    }
    rad_roots_destroy(ctx, made);
    h->root_count = h->node_count;
    h->min_area = o.min_area * total_area;
    h->source_depth = o.source_depth;
    double rho_max = 0;
    for (size_t p = 0; p < np && !status; ++p)
        for (int c = 0; c < 3; ++c) rho_max = larger(rho_max, h->reflectance[p][c]);
    h->radiosity_cap = rho_max < 1 ? h->emission_max / (1 - rho_max) : 0;
    h->threshold = o.link_error * (h->emitted_power > 0 ? h->emitted_power : 1);
    if (!status && h->root_count == 0)
        status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                          "%s: no polygon with a nonzero area", scene->source);
    if (!status) status = build_clusters(h);
    if (!status) {
        h->root_radiosity = rad_alloc_zero(ctx, h->root_count, sizeof *h->root_radiosity);
        if (!h->root_radiosity) status = RAD_ERROR_NO_MEMORY;
    }
    if (!status && h->light_fn) {
        /* The roots' light (after build_clusters renumbered them), counted as emitted. */
        h->light = rad_alloc_zero(h->ctx, h->node_capacity, sizeof *h->light);
        h->light_spread = rad_alloc_zero(h->ctx, h->node_capacity, sizeof *h->light_spread);
        if (!h->light || !h->light_spread) status = RAD_ERROR_NO_MEMORY;
        if (!status) light_nodes(h, 0);
        for (size_t i = 0; i < h->root_count && !status; ++i) {
            rad_hier_node *n = &h->nodes[i];
            double most = larger(h->light[i][0], larger(h->light[i][1], h->light[i][2]));
            h->emission_max = larger(h->emission_max, most);
            h->emitted_power += most * n->area;
            for (int c = 0; c < 3; ++c) n->radiosity[c] += h->light[i][c];
        }
        h->threshold = o.link_error * (h->emitted_power > 0 ? h->emitted_power : 1);
    }
    if (!status && h->light && o.light_split) status = split_by_light(h);
    if (!status) status = rad_rays_create(ctx, scene, &h->rays);
    if (!status) status = rad_ff_shaft_create(ctx, scene, NULL, SHAFT_OCCLUDERS, &h->shaft);
    if (status) {
        rad_hier_destroy(h);
        return status;
    }
    h->stats.roots = h->root_count;
    h->stats.clusters = h->cluster_count;
    h->stats.leaves = h->root_count;
    *out = h;
    return RAD_OK;
}

void rad_hier_destroy(rad_hier *h) {
    if (!h) return;
    rad_context *ctx = h->ctx;
    rad_rays_destroy(h->rays);
    rad_ff_shaft_destroy(h->shaft);
    rad_free(ctx, h->nodes);
    rad_free(ctx, h->polygon_root_first);
    rad_free(ctx, h->polygon_root_count);
    rad_free(ctx, h->polygon_roots);
    rad_free(ctx, h->root_parent);
    rad_free(ctx, h->clusters);
    rad_free(ctx, h->cluster_down);
    rad_free(ctx, h->walk_memory);
    rad_free(ctx, h->root_walk);
    rad_free(ctx, h->reflectance);
    rad_free(ctx, h->emission);
    rad_free(ctx, h->normal);
    rad_free(ctx, h->light);
    rad_free(ctx, h->light_spread);
    rad_free(ctx, h->root_radiosity);
    rad_free(ctx, h->sends);
    rad_free(ctx, h->shape);
    rad_free(ctx, h->hit_polygon);
    rad_free(ctx, h->hit_point);
    rad_free(ctx, h->importance);
    rad_free(ctx, h->importance_emitted);
    rad_free(ctx, h->importance_gathered);
    rad_free(ctx, h->cluster_axis_importance);
    rad_free(ctx, h->cluster_down_importance);
    rad_free(ctx, h->cluster_z);
    rad_free(ctx, h->links);
    rad_free(ctx, h->samples);
    rad_free(ctx, h->free_samples);
    rad_free(ctx, h->group_first);
    rad_free(ctx, h);
}

rad_hier_stats rad_hier_get_stats(const rad_hier *h) {
    rad_hier_stats s = h->stats; /* leaves and cluster_links are counted as they change */
    s.nodes = h->node_count;
    s.links = h->link_count;
    s.roots = h->root_count;
    s.clusters = h->cluster_count;
    return s;
}

const rad_hier_node *rad_hier_nodes(const rad_hier *h, size_t *count) {
    *count = h->node_count;
    return h->nodes;
}

const rad_hier_link *rad_hier_links(const rad_hier *h, size_t *count) {
    *count = h->link_count;
    return h->links;
}

const uint32_t *rad_hier_polygon_roots(const rad_hier *h, uint32_t polygon, uint32_t *count) {
    *count = polygon < h->scene->polygon_count ? h->polygon_root_count[polygon] : 0;
    return *count ? h->polygon_roots + h->polygon_root_first[polygon] : NULL;
}

uint32_t rad_hier_top(const rad_hier *h) { return (uint32_t)h->cluster_first; }

uint32_t rad_hier_root_of(const rad_hier *h, uint32_t node) { return h->nodes[node].root; }

/* How far x is inside node n (the smallest distance to an edge, negative outside). */
static double inside(const rad_hier *h, const rad_hier_node *n, rad_vec3 x) {
    rad_vec3 normal = h->normal[n->polygon];
    double worst = INFINITY;
    for (int k = 0; k < n->corner_count; ++k) {
        rad_vec3 a = n->corner[k], b = n->corner[(k + 1) % n->corner_count];
        rad_vec3 edge = v3_sub(b, a);
        double length = v3_length(edge);
        if (!(length > 0)) continue;
        worst = smaller(worst, v3_dot(v3_cross(edge, v3_sub(x, a)), normal) / length);
    }
    return worst;
}

/* The leaf of polygon `polygon` under x, or RAD_HIER_NO_NODE when the polygon has no root. */
static uint32_t leaf_at(const rad_hier *h, uint32_t polygon, rad_vec3 x) {
    uint32_t count;
    const uint32_t *roots = rad_hier_polygon_roots(h, polygon, &count);
    if (!roots) return RAD_HIER_NO_NODE;
    double best = -INFINITY;
    uint32_t index = roots[0];
    for (uint32_t k = 0; k < count; ++k) {
        double d = inside(h, &h->nodes[roots[k]], x);
        if (d > best) best = d, index = roots[k];
    }
    while (h->nodes[index].first_child != RAD_HIER_NO_NODE) {
        uint32_t child = h->nodes[index].first_child, pick = child;
        best = -INFINITY;
        for (uint32_t k = 0; k < 4; ++k) {
            double d = inside(h, &h->nodes[child + k], x);
            if (d > best) best = d, pick = child + k;
        }
        index = pick;
    }
    return index;
}

void rad_hier_radiosity_at(const rad_hier *h, uint32_t polygon, rad_vec3 x, double out[3]) {
    uint32_t leaf = leaf_at(h, polygon, x);
    if (leaf == RAD_HIER_NO_NODE) memset(out, 0, sizeof(double[3]));
    else memcpy(out, h->nodes[leaf].radiosity, sizeof(double[3]));
}

void rad_hier_light_at(const rad_hier *h, uint32_t polygon, rad_vec3 x, double out[3]) {
    uint32_t leaf = h->light ? leaf_at(h, polygon, x) : RAD_HIER_NO_NODE;
    if (leaf == RAD_HIER_NO_NODE) memset(out, 0, sizeof(double[3]));
    else memcpy(out, h->light[leaf], sizeof(double[3]));
}

/* ---- Saving and restoring (src/io/solution_hier.c) --------------------------------------- */

static uint64_t mix_u64(uint64_t hash, uint64_t v) { return rad_mix64(hash ^ rad_mix64(v + 1)); }

static uint64_t mix_f64(uint64_t hash, double v) {
    uint64_t bits;
    if (v == 0) v = 0; /* -0 and +0 alike */
    memcpy(&bits, &v, sizeof bits);
    return mix_u64(hash, bits);
}

uint64_t rad_hier_fingerprint(const rad_hier *h) {
    uint64_t hash = mix_u64(mix_u64(mix_u64(0x68696572u, h->root_count), h->cluster_count),
                            (uint64_t)h->no_clusters);
    const double scalars[4] = {h->threshold, h->min_area, h->emission_max, h->emitted_power};
    for (int k = 0; k < 4; ++k) hash = mix_f64(hash, scalars[k]);
    hash = mix_u64(hash, h->light != NULL);
    for (size_t i = 0; i < h->root_count + h->cluster_count; ++i) {
        const rad_hier_node *n = &h->nodes[i];
        hash = mix_u64(mix_u64(hash, n->polygon), n->corner_count);
        if (i >= h->root_count) hash = mix_u64(hash, n->child_count); /* a cluster's members */
        hash = mix_f64(hash, n->area);
        for (int k = 0; k < n->corner_count; ++k)
            hash = mix_f64(mix_f64(mix_f64(hash, n->corner[k].x), n->corner[k].y), n->corner[k].z);
        for (int c = 0; c < 3 && h->light && i < h->root_count; ++c) hash = mix_f64(hash, h->light[i][c]);
    }
    return hash;
}

int rad_hier_has_light(const rad_hier *h) { return h->light != NULL; }

void rad_hier_node_state_get(const rad_hier *h, uint32_t node, rad_hier_node_state *out) {
    memset(out, 0, sizeof *out);
    if (h->light) {
        memcpy(out->light, h->light[node], sizeof out->light);
        out->spread = h->light_spread[node];
    }
    if (h->importance) out->importance = h->importance[node];
}

size_t rad_hier_view_hits(const rad_hier *h, const uint32_t **polygon, const rad_vec3 **point,
                          double *share) {
    *polygon = h->hit_polygon;
    *point = h->hit_point;
    *share = h->hit_share;
    return h->hit_point ? h->hit_count : 0;
}

double rad_hier_importance_mean(const rad_hier *h) { return h->importance_mean; }

void rad_hier_set_light(rad_hier *h,
                        void (*light)(void *user, uint32_t polygon, const rad_vec3 *corners,
                                      int count, uint64_t stream, double out[3], double *spread),
                        void *user) {
    h->light_fn = light;
    h->light_user = user;
}

rad_status rad_hier_restore_split(rad_hier *h, uint32_t node, uint32_t first_child) {
    if (node >= h->node_count || cluster_index(h, node) || h->nodes[node].corner_count == 0)
        return RAD_ERROR_PARSE;
    const rad_hier_node *n = &h->nodes[node];
    if (n->first_child != RAD_HIER_NO_NODE) return n->first_child == first_child ? RAD_OK : RAD_ERROR_PARSE;
    if (first_child != h->node_count || n->depth >= MAX_DEPTH) return RAD_ERROR_PARSE;
    return subdivide(h, node);
}

rad_status rad_hier_restore_view(rad_hier *h, uint32_t *polygon, rad_vec3 *point, size_t count,
                                 double share) {
    rad_context *ctx = h->ctx;
    rad_free(ctx, h->hit_polygon);
    rad_free(ctx, h->hit_point);
    h->hit_polygon = polygon;
    h->hit_point = point;
    h->hit_count = count;
    h->hit_share = share;
    if (!h->importance) {
        h->importance = rad_alloc_zero(ctx, h->node_capacity, sizeof *h->importance);
        h->importance_emitted = rad_alloc_zero(ctx, h->node_capacity, sizeof *h->importance_emitted);
        h->importance_gathered = rad_alloc_zero(ctx, h->node_capacity, sizeof *h->importance_gathered);
        h->cluster_axis_importance = rad_alloc_zero(ctx, h->cluster_count + 1, sizeof *h->cluster_axis_importance);
        h->cluster_down_importance = rad_alloc_zero(ctx, h->cluster_count + 1, sizeof *h->cluster_down_importance);
        h->cluster_z = rad_alloc_zero(ctx, h->cluster_count + 1, sizeof *h->cluster_z);
        if (!h->importance || !h->importance_emitted || !h->importance_gathered ||
            !h->cluster_axis_importance || !h->cluster_down_importance || !h->cluster_z)
            return RAD_ERROR_NO_MEMORY;
    }
    return RAD_OK;
}

void rad_hier_restore_node(rad_hier *h, uint32_t node, const double radiosity[3],
                           const rad_hier_node_state *state) {
    memcpy(h->nodes[node].radiosity, radiosity, sizeof(double[3]));
    if (h->light) {
        memcpy(h->light[node], state->light, sizeof(rgb));
        h->light_spread[node] = state->spread;
    }
    if (h->importance) h->importance[node] = state->importance;
}

/* Restored links' samples (link_sample) when the solution file did not keep them, made again
 * from the same rays: each link's pairs are drawn from its own stream (link_hash). As costly as
 * making the links: 3 of the 8.8 s of wall that loading the 10^5 office's solution and drawing
 * a small bare picture took. */
static rad_status resample_links(rad_hier *h) {
    const size_t count = h->link_count;
    for (size_t l = 0; l < count; ++l) h->links[l].sample = RAD_HIER_NO_NODE;
    link_sample *seen = rad_alloc(h->ctx, count ? count : 1, sizeof *seen);
    if (!seen) return RAD_ERROR_NO_MEMORY;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (count >= 64)
    for (long l = 0; l < (long)count; ++l) {
        const rad_hier_link *link = &h->links[l];
        rad_hier_link again;
        seen[l].weight[0] = NO_SAMPLE;
        if (cluster_index(h, link->source) && link->form_factor != NOT_ESTIMATED)
            make_cluster_link(h, link->receiver, link->source, &again, 0, &seen[l]);
    }
    h->sample_count = h->free_count = h->samples_new = 0;
    rad_status status = keep_samples(h, h->links, seen, NULL, count);
    rad_free(h->ctx, seen);
    return status;
}

/* The saved samples (one per link, in link order; weight[0] NO_SAMPLE for none): checked, then
 * compacted into h->samples, each link pointing at its own (before the links are sorted, which
 * carries the index along). Takes `samples` over. */
static rad_status restore_samples(rad_hier *h, rad_hier_link *links, rad_hier_link_sample *samples,
                                  size_t count) {
    size_t used = 0;
    rad_status status = RAD_OK;
    for (size_t l = 0; l < count && !status; ++l) {
        links[l].sample = RAD_HIER_NO_NODE;
        const link_sample *sample = &samples[l];
        if (sample->weight[0] == NO_SAMPLE) continue;
        if (!cluster_index(h, links[l].source) || links[l].form_factor == NOT_ESTIMATED)
            status = RAD_ERROR_PARSE;
        for (int k = 0; k < 4; ++k)
            if (sample->member[k] >= h->root_count || sample->weight[k] == NO_SAMPLE)
                status = RAD_ERROR_PARSE;
        if (status) break;
        samples[used] = *sample;
        links[l].sample = (uint32_t)used++;
    }
    uint32_t *slots = status ? NULL : rad_alloc(h->ctx, used ? used : 1, sizeof *slots);
    if (!status && !slots) status = RAD_ERROR_NO_MEMORY;
    if (status) {
        rad_free(h->ctx, samples);
        return status;
    }
    rad_free(h->ctx, h->samples);
    rad_free(h->ctx, h->free_samples);
    link_sample *fit = rad_realloc(h->ctx, samples, used ? used : 1, sizeof *fit);
    h->samples = fit ? fit : samples;
    h->free_samples = slots;
    h->sample_count = h->sample_capacity = used;
    h->free_count = h->samples_new = 0;
    return RAD_OK;
}

rad_status rad_hier_restore_links(rad_hier *h, rad_hier_link *links, rad_hier_link_sample *samples,
                                  size_t count) {
    if (samples) {
        rad_status status = restore_samples(h, links, samples, count);
        if (status) {
            rad_free(h->ctx, links);
            return status;
        }
    }
    /* A file's links come grouped by increasing receiver (its reader checks it): sorting them
     * again (a copy of 0.76 GB and its page faults at 10^6) was 7% of the processor time of
     * resuming the 10^6 office from its second step, by a profile. */
    int sorted = 1;
    for (size_t i = 1; i < count && sorted; ++i) sorted = links[i - 1].receiver <= links[i].receiver;
    rad_status status = sorted ? take_sorted_links(h, links, count) : adopt_links(h, links, count);
    return status || samples ? status : resample_links(h);
}

const rad_hier_link_sample *rad_hier_link_sample_of(const rad_hier *h, const rad_hier_link *link) {
    return link->sample == RAD_HIER_NO_NODE ? NULL : &h->samples[link->sample];
}

int rad_hier_refining(const rad_hier *h, size_t *kept) {
    if (kept) *kept = h->refining ? h->refine_kept : 0;
    return h->refining;
}

rad_status rad_hier_restore_refining(rad_hier *h, rad_hier_link *links,
                                     rad_hier_link_sample *samples, size_t count, size_t kept) {
    rad_status status = kept > count ? RAD_ERROR_PARSE : RAD_OK;
    if (status) rad_free(h->ctx, samples);
    else if (samples) status = restore_samples(h, links, samples, count);
    if (status) {
        rad_free(h->ctx, links);
        return status;
    }
    rad_free(h->ctx, h->links);
    rad_free(h->ctx, h->group_first);
    h->group_first = NULL;
    h->group_count = 0;
    h->links = links;
    h->link_count = count;
    h->stats.links = count;
    size_t cluster_links = 0;
    for (size_t i = 0; i < count; ++i)
        cluster_links += cluster_index(h, links[i].receiver) || cluster_index(h, links[i].source);
    h->stats.cluster_links = cluster_links;
    h->refine_kept = kept;
    h->refining = 1;
    return samples ? RAD_OK : resample_links(h);
}

int rad_hier_importance_unfinished(const rad_hier *h) { return h->importance_unfinished; }

void rad_hier_restore_importance_unfinished(rad_hier *h, int unfinished) {
    h->importance_unfinished = unfinished != 0;
}

void rad_hier_restore_stats(rad_hier *h, const rad_hier_stats *stats, double importance_mean) {
    h->stats.largest_error = stats->largest_error;
    h->stats.refined = stats->refined;
    h->stats.solve_rounds = stats->solve_rounds;
    h->stats.budget_reached = stats->budget_reached;
    h->stats.seen_share = stats->seen_share;
    h->importance_mean = importance_mean;
}
