/* hierarchy.h - hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991).
 *
 * Every input polygon, cut at its contacts (mesh/roots.h: the pieces hidden inside solids
 * dropped, pieces of more than four corners fanned into quads), gives the roots of quadtrees:
 * a quad splits into four quads at its edge midpoints and centre, a triangle into
 * four at its edge midpoints. Nodes are made lazily, when a link asks for them. A link carries
 * light from a source node to a receiver node at any level of either tree; its form factor is
 * the point-to-polygon factor (Lambert's contour integral) averaged over the receiver's quadrature
 * points, times the visible fraction of rays between the two nodes (Embree).
 *
 * The oracle: a link's error is rho_r B_s (dF + partial F), the radiosity it carries times its
 * form-factor error bound, where dF is the spread of the point factor over the receiver's
 * quadrature points and partial visibility counts its whole factor, plus, for a split source
 * larger than its receiver, rho_r dB_s F (dB_s half the range of its children's radiosity). A link whose error exceeds
 * the threshold is replaced by links to the four children of its receiver (or, when the
 * visibility is partial and the source is larger, of its source).
 *
 * Clustering (Smits, Arvo & Greenberg 1994; Sillion 1995): the roots are the leaves of a
 * bounding-volume hierarchy of volume clusters (splits at the midpoint of the roots'
 * centroids, at most four roots a leaf cluster). The solve starts from one self-link on the top
 * cluster; links with a cluster at either end carry the point estimate
 * P_r P_s / (pi d^2 A_r) between the two centres, where P is the projected area toward the
 * other end (a surface: A cos; a cluster: its members' areas summed per axis direction, exact
 * for axis-aligned members), and their error bound is the spread of that estimate over the two
 * bounding spheres and all member orientations, plus the whole factor (partial visibility is
 * assumed; cheap links, whose bound passes at any radiosity, count it when some of their rays
 * are blocked). Irradiance gathered by a cluster is pushed to its
 * members; a cluster's radiosity is its members' area-weighted mean.
 *
 * Solving: Jacobi gathering over the links into each node's irradiance, then push-pull through
 * the trees (Hanrahan et al. 1991, section 4): irradiance is pushed down to the leaves, the
 * leaves' radiosity is pulled up as area-weighted means. Receivers are processed in parallel,
 * each summing its links in a fixed order, so results do not depend on the thread count. */
#ifndef RAD_HIERARCHY_HIERARCHY_H
#define RAD_HIERARCHY_HIERARCHY_H

#include "core/context.h"
#include "core/vec3.h"

#include <stdint.h>

struct rad_scene;
struct rad_view;

#define RAD_HIER_NO_NODE UINT32_MAX
#define RAD_HIER_DEFAULT_LINK_ERROR 1e-3 /* rad_hier_options.link_error when zero */

typedef struct rad_hier_node {
    rad_vec3 corner[4]; /* counter-clockwise seen from the front */
    double area;
    double radiosity[3];
    double irradiance[3]; /* gathered over the node's own links in the last round */
    uint32_t polygon;     /* the input polygon */
    uint32_t root;        /* the root of its tree */
    uint32_t first_child; /* child_count contiguous children, or RAD_HIER_NO_NODE for a leaf */
    uint32_t child_count; /* 4 for a split polygon node; a cluster's members */
    uint8_t corner_count; /* 3 or 4; 0 for a cluster (polygon is then RAD_HIER_NO_NODE) */
    uint8_t depth;
} rad_hier_node;

typedef struct rad_hier_link {
    uint32_t receiver, source;
    float form_factor; /* F(receiver -> source), visibility included */
    float error;       /* the form-factor error bound: spread plus partial visibility */
    uint32_t sample;   /* a cluster source: which of its members the link's own rays saw (an
                          index the hierarchy keeps); RAD_HIER_NO_NODE without */
} rad_hier_link;

/* What a cluster link's own rays saw of its source cluster: the members (roots) its visible pairs
 * ended on, each weighed by what it added to the link's factor, in units of 1/65534 (summing to
 * about 65534; 0 for an unused slot); weight[0] RAD_HIER_NO_SAMPLE when the rays saw nothing.
 * The link sends the weighed mean of those members' radiosities. */
typedef struct rad_hier_link_sample {
    uint32_t member[4];
    uint16_t weight[4];
} rad_hier_link_sample;
#define RAD_HIER_NO_SAMPLE UINT16_MAX

typedef struct rad_hier_options {
    double link_error; /* threshold on rho B dF, relative to the brightest emitter; zero: 1e-3 */
    double min_area;   /* nodes this small (relative to the scene's area) are not split; zero: 1e-6 */
    int no_clusters;   /* nonzero: rad_hier_link_roots links all pairs of roots (n^2), as
                          before clustering; for comparisons */
    /* Optional: the radiosity a node of `polygon` with these corners emits besides its
     * material's emission, e.g. the reflected direct light of point, spot and directional lights
     * and the sky (src/system/lights_direct.c); asked once per node when it is made, from
     * several threads at once, `stream` the node's index (for deterministic sampling).
     * *spread is how much that radiosity changes across the node (largest channel): a leaf
     * whose spread times a quarter of its area exceeds the oracle's threshold is split, so the
     * leaves follow shadow edges of the lights as they follow those of the links. */
    void (*light)(void *user, uint32_t polygon, const rad_vec3 *corners, int count,
                  uint64_t stream, double out[3], double *spread);
    void *light_user;
    /* Nonzero: before any link, split nodes whose four children's light differs by more than
     * the oracle allows (half the range times the area, against the threshold), so that light
     * with sharp edges of its own (a caustic through glass) is held by leaves that resolve it. */
    int light_split;
    /* Nonzero: a fully visible link between two polygon nodes reads its source's descendants
     * this many levels down, weighed by the kernel from its receiver (source_kernel.h), not
     * the source's mean. */
    int source_depth;
} rad_hier_options;

typedef struct rad_hier_stats {
    size_t nodes, leaves, links, roots, clusters;
    size_t refined;        /* links refined by the last call of rad_hier_refine */
    double largest_error;  /* the oracle's largest error over the links, relative to threshold;
                              at the budget, over the links whose error is known */
    double found_error;    /* the largest error over the threshold that the last refinement's
                              first pass found, the links it refined included: over 1, it
                              refined; at most 1, the oracle was met; infinite when it refined
                              a link between overlapping ends (whose error is not known) */
    int solve_rounds;      /* gathering rounds of the last rad_hier_solve */
    int budget_reached;    /* refinement stopped at the memory budget (a warning said so) */
    size_t unrefined;      /* at the budget: links the oracle would still refine */
    size_t unknown_error;  /* of those, links whose error is not known yet (overlapping ends) */
    size_t cluster_links;  /* links with a cluster at one end or both */
    double seen_share;     /* with a view: the share of its pixels that meet a surface's front */
} rad_hier_stats;

typedef struct rad_hier rad_hier;

/* Builds the roots (rad_roots_create's: the polygons cut at contacts) and Embree's rays for
 * `scene`, which must outlive the hierarchy. Degenerate polygons get no root. */
rad_status rad_hier_create(rad_context *ctx, const struct rad_scene *scene,
                           const rad_hier_options *options, rad_hier **out);
/* The same from roots already cut (rad_roots_create's for this scene, e.g. rebuilt from a
 * one-element-per-root system's elements, so the scene is not cut twice); NULL: cut here. */
struct rad_roots;
rad_status rad_hier_create_from(rad_context *ctx, const struct rad_scene *scene,
                                const rad_hier_options *options, const struct rad_roots *roots,
                                rad_hier **out);
void rad_hier_destroy(rad_hier *hier);

/* The initial links: one self-link on the top cluster (or, with options.no_clusters, between
 * every pair of roots that can see each other, refused through the context's memory budget
 * when the pairs would not fit). */
rad_status rad_hier_link_roots(rad_hier *hier);

/* The oracle over every link, recursively: refines those over the threshold (subdividing nodes
 * and opening clusters as needed), computes the new links' form factors and asks the oracle
 * again about them, until every link passes or cannot be split. stats.refined says how many
 * links were refined. When the
 * new links would pass the memory budget nothing is refined, a warning names the link count
 * and stats.budget_reached is set: the solution so far stands.
 * The progress callback is asked between passes (phase "hierarchical refinement"); when it asks
 * to stop, RAD_ERROR_CANCELLED, and the hierarchy keeps the refinement as far as it got
 * (rad_hier_refining): the next call goes on from there exactly as this one would have, and
 * rad_hier_solve refuses until then. */
rad_status rad_hier_refine(rad_hier *hier);

/* Nonzero while a refinement stopped by the progress callback waits to go on; *kept (when not
 * NULL) is how many of the links, first in rad_hier_links, it had passed (the rest it had made
 * and not yet asked about; not grouped by receiver). */
int rad_hier_refining(const rad_hier *hier, size_t *kept);

/* Nonzero when the last solve's importance rounds were stopped after the light's converged: the
 * next rad_hier_solve goes on with importance alone. */
int rad_hier_importance_unfinished(const rad_hier *hier);

/* Gathers over the links and push-pulls until the largest change of a leaf's radiosity falls
 * under `tolerance` times the brightest emitter (or `max_rounds`). */
rad_status rad_hier_solve(rad_hier *hier, double tolerance, int max_rounds);

rad_hier_stats rad_hier_get_stats(const rad_hier *hier);

/* The nodes and links, for tests and outputs; valid until the next refine. */
const rad_hier_node *rad_hier_nodes(const rad_hier *hier, size_t *count);
const rad_hier_link *rad_hier_links(const rad_hier *hier, size_t *count);

/* The root nodes of polygon `polygon` (one, or one per fan triangle) and how many. */
const uint32_t *rad_hier_polygon_roots(const rad_hier *hier, uint32_t polygon, uint32_t *count);

/* The top cluster (the node every root descends from). */
uint32_t rad_hier_top(const rad_hier *hier);

/* The radiosity of the leaf under point x (on polygon `polygon`). */
void rad_hier_radiosity_at(const rad_hier *hier, uint32_t polygon, rad_vec3 x, double out[3]);

/* The light (rad_hier_options.light) of the leaf under point x; zero without lights. */
void rad_hier_light_at(const rad_hier *hier, uint32_t polygon, rad_vec3 x, double out[3]);

/* The root a node belongs to (a cluster: itself). */
uint32_t rad_hier_root_of(const rad_hier *hier, uint32_t node);

/* Importance (Smits, Arvo & Salesin 1992): from now on the oracle weighs every link's error
 * by the importance of its receiver (what the view sees of its light, directly or after
 * reflections) over the scene's mean, so links are refined where this view needs them and
 * left coarse where it does not (docs/hierarchical.md, "Importance"). One ray per pixel of
 * `view` finds what the camera sees; every rad_hier_solve then also solves importance over
 * the transposed links. */
rad_status rad_hier_set_view(rad_hier *hier, const struct rad_view *view);

/* A node's importance per unit area (the image's change per unit of its radiosity, per unit
 * area), after the last solve; 0 without a view. */
double rad_hier_importance(const rad_hier *hier, uint32_t node);

/* ---- Saving and restoring (src/io/solution_hier.c, docs/formats.md) ----------------------
 * A saved hierarchy is rebuilt on one fresh from rad_hier_create (and, with importance,
 * rad_hier_restore_view): the splits replayed in the order they were made, so the nodes get
 * the same numbers, then the nodes' values, the links, the exposure counts and the stats set
 * as they were, after which refine and solve go on exactly as they would have. */

/* A hash of what rad_hier_create made of the scene and options: the roots and clusters
 * (polygon, corners, area), the roots' light, the threshold. Nothing refine or solve changes. */
uint64_t rad_hier_fingerprint(const rad_hier *hier);

/* A node's state besides rad_hier_node: its light and spread (rad_hier_options.light) and its
 * importance A Y; zeros without them. */
typedef struct rad_hier_node_state {
    double light[3];
    float spread;
    double importance;
} rad_hier_node_state;

int rad_hier_has_light(const rad_hier *hier);
void rad_hier_node_state_get(const rad_hier *hier, uint32_t node, rad_hier_node_state *out);
/* The importance view's hits (rad_hier_set_view) and each one's share of the image; 0 without. */
size_t rad_hier_view_hits(const rad_hier *hier, const uint32_t **polygon, const rad_vec3 **point,
                          double *share);
double rad_hier_importance_mean(const rad_hier *hier);

/* Replaces the light function (rad_hier_options.light) for the nodes made from now on. */
void rad_hier_set_light(rad_hier *hier,
                        void (*light)(void *user, uint32_t polygon, const rad_vec3 *corners,
                                      int count, uint64_t stream, double out[3], double *spread),
                        void *user);

/* Splits leaf `node` so that its children are first_child .. + 3; a node already split with
 * those children is left alone. RAD_ERROR_PARSE (no message) when that cannot be. */
rad_status rad_hier_restore_split(rad_hier *hier, uint32_t node, uint32_t first_child);
/* The importance view's hits as rad_hier_set_view found them (the arrays are taken over, also
 * on failure), without solving importance. */
rad_status rad_hier_restore_view(rad_hier *hier, uint32_t *polygon, rad_vec3 *point, size_t count,
                                 double share);
void rad_hier_restore_node(rad_hier *hier, uint32_t node, const double radiosity[3],
                           const rad_hier_node_state *state);
/* The sample a link keeps (what its rays saw of a cluster source), NULL when it keeps none. */
const rad_hier_link_sample *rad_hier_link_sample_of(const rad_hier *hier,
                                                    const rad_hier_link *link);
/* The links (taken over, also on failure), every end below the node count, with their samples
 * (`samples[i]` link i's, taken over too; RAD_ERROR_PARSE when one names a member that is not a
 * root or belongs to a link whose source is not a cluster). Without samples (NULL: files
 * written before they were kept) each cluster link's rays are cast again to draw them. */
rad_status rad_hier_restore_links(rad_hier *hier, rad_hier_link *links,
                                  rad_hier_link_sample *samples, size_t count);
/* A stopped refinement's links as rad_hier_refining described them (taken over, also on
 * failure): the first `kept` passed, the rest to ask about; RAD_ERROR_PARSE when kept > count.
 * Samples as for rad_hier_restore_links. */
rad_status rad_hier_restore_refining(rad_hier *hier, rad_hier_link *links,
                                     rad_hier_link_sample *samples, size_t count, size_t kept);
void rad_hier_restore_importance_unfinished(rad_hier *hier, int unfinished);
/* largest_error, refined, solve_rounds, budget_reached and seen_share of `stats`. */
void rad_hier_restore_stats(rad_hier *hier, const rad_hier_stats *stats, double importance_mean);

#endif
