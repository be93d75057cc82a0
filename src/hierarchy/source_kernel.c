/* source_kernel.c - the radiosity a link reads from its source, weighed by where its receiver
 * looks.
 *
 * A link r <- s carries F_rs times s's radiosity, and the push-pull makes that the area mean of
 * s's leaves (Hanrahan, Salzman & Aupperle 1991). The exact transfer is the integral of B_s over
 * s weighed by the kernel from r: a large source of uneven light read by a small receiver that
 * sees mostly one side of it (a wall's strip beside the floor, the ceiling's over the walls'
 * tops) takes the mean of the far side too. The oracle cannot see it while the link's
 * BF error passes, and at a fine link error there are many such links, all off the same way:
 * on the Cornell box every surface but the floor came out 0.26-0.29 % dark (the ceiling 0.9 %)
 * and 0.17 % of the lamp's power more escaped than with shooting at 10,000 elements
 * (docs/hierarchical.md, "hcornell2").
 *
 * Here the source's descendants a few levels down, which the refinement made for other links
 * and whose radiosity the push-pull keeps, are weighed by their area times cos cos / r^2 from
 * the receiver's centre to theirs (from its four quadrature points instead: the same surface
 * means to 0.01 %, for four times the work): the link's factor F_rs (visibility
 * included) stays, only the mean it multiplies follows the kernel. The children's own factors
 * from r sum to F_rs when r sees all of s, so this is the transfer of the links one level
 * further down the source, without making them; partly hidden links keep the plain mean (the
 * kernel does not know which descendants are hidden). */
#include "hierarchy/source_kernel.h"

#include <math.h>
#include <string.h>

static rad_vec3 centre(const rad_hier_node *n) {
    if (n->corner_count == 3)
        return v3_scale(v3_add(v3_add(n->corner[0], n->corner[1]), n->corner[2]), 1.0 / 3);
    return v3_scale(v3_add(v3_add(n->corner[0], n->corner[1]), v3_add(n->corner[2], n->corner[3])),
                    0.25);
}

/* fmax(0, cosine) inline (a call through the PLT otherwise); the same value, NaN included. */
static inline double facing(double cosine) { return cosine > 0 ? cosine : 0; }

/* Node n's area times the point kernel cos cos / r^2 from x (normal nr; ns: n's normal). */
static double kernel_weight(const rad_hier_node *n, rad_vec3 x, rad_vec3 nr, rad_vec3 ns) {
    rad_vec3 ray = v3_sub(centre(n), x);
    double r2 = v3_dot(ray, ray);
    return facing(v3_dot(nr, ray)) * facing(-v3_dot(ns, ray)) / (r2 * r2) * n->area;
}

/* Adds node `index`'s descendants `depth` levels down (or its leaves above that) to the
 * weighed sums, x the receiver's centre. */
static void add_descendants(const rad_hier_node *nodes, uint32_t index, int depth, rad_vec3 x,
                            rad_vec3 nr, rad_vec3 ns, double *weights, double sum[3]) {
    const rad_hier_node *n = &nodes[index];
    if (depth > 0 && n->first_child != RAD_HIER_NO_NODE) {
        for (uint32_t k = 0; k < n->child_count; ++k)
            add_descendants(nodes, n->first_child + k, depth - 1, x, nr, ns, weights, sum);
        return;
    }
    double weight = kernel_weight(n, x, nr, ns);
    *weights += weight;
    for (int c = 0; c < 3; ++c) sum[c] += weight * n->radiosity[c];
}

int rad_hier_source_kernel_mean(const rad_hier_node *nodes, const rad_hier_node *receiver,
                                rad_vec3 nr, uint32_t source, rad_vec3 ns, int depth,
                                double out[3]) {
    const rad_hier_node *s = &nodes[source];
    if (depth <= 0 || s->first_child == RAD_HIER_NO_NODE || s->corner_count == 0 ||
        receiver->corner_count == 0)
        return 0;
    double weights = 0, sum[3] = {0, 0, 0};
    add_descendants(nodes, source, depth, centre(receiver), nr, ns, &weights, sum);
    if (!(weights > 0)) return 0;
    for (int c = 0; c < 3; ++c) out[c] = sum[c] / weights;
    return 1;
}

/* ---- The weights kept for a solve --------------------------------------------------------- */

/* A link reads its source's kernel-weighed mean when it is a fully visible link between two
 * polygon nodes whose source has children (hierarchy.c, source_radiosity); links of factor 0
 * are not read at all. */
static int kernel_link(const rad_hier_node *nodes, const rad_hier_link *link, int depth) {
    const rad_hier_node *r = &nodes[link->receiver], *s = &nodes[link->source];
    return depth > 0 && link->form_factor != 0 && link->sample == RAD_HIER_NO_NODE &&
           link->error >= 0 && r->corner_count && s->corner_count &&
           s->first_child != RAD_HIER_NO_NODE;
}

/* How many descendants add_descendants visits: the nodes `depth` levels down, or leaves above. */
static uint32_t descendant_count(const rad_hier_node *nodes, uint32_t index, int depth) {
    const rad_hier_node *n = &nodes[index];
    if (depth <= 0 || n->first_child == RAD_HIER_NO_NODE) return 1;
    uint32_t count = 0;
    for (uint32_t k = 0; k < n->child_count; ++k)
        count += descendant_count(nodes, n->first_child + k, depth - 1);
    return count;
}

/* add_descendants' walk, keeping each descendant and its weight (in the same order, so that the
 * sums read back are the same bits). */
static void keep_descendants(const rad_hier_node *nodes, uint32_t index, int depth, rad_vec3 x,
                             rad_vec3 nr, rad_vec3 ns, uint32_t **node, double **weight) {
    const rad_hier_node *n = &nodes[index];
    if (depth > 0 && n->first_child != RAD_HIER_NO_NODE) {
        for (uint32_t k = 0; k < n->child_count; ++k)
            keep_descendants(nodes, n->first_child + k, depth - 1, x, nr, ns, node, weight);
        return;
    }
    *(*node)++ = index;
    *(*weight)++ = kernel_weight(n, x, nr, ns);
}

rad_status rad_hier_kernel_cache_build(rad_context *ctx, rad_hier_kernel_cache *cache,
                                       const rad_hier_node *nodes, const rad_vec3 *normal,
                                       const rad_hier_link *links, size_t count, int depth,
                                       double budget, int threads) {
    rad_hier_kernel_cache_free(ctx, cache);
    if (depth <= 0 || count == 0) return RAD_OK;
    /* The weights are recomputed every round instead past 2^32 links or entries, or the budget. */
    if (count >= UINT32_MAX || (double)(count + 1) * sizeof *cache->first > budget) return RAD_OK;
    cache->first = rad_alloc(ctx, count + 1, sizeof *cache->first);
    if (!cache->first) return RAD_ERROR_NO_MEMORY;
    /* Each link's count, then where its entries begin. */
    const long links_count = (long)count;
#pragma omp parallel for schedule(static) num_threads(threads) if (links_count >= 4096)
    for (long l = 0; l < links_count; ++l)
        cache->first[l + 1] = kernel_link(nodes, &links[l], depth)
                                  ? descendant_count(nodes, links[l].source, depth)
                                  : 0;
    size_t total = 0;
    cache->first[0] = 0;
    for (size_t l = 1; l <= count; ++l) {
        total += cache->first[l];
        if (total >= UINT32_MAX) {
            rad_hier_kernel_cache_free(ctx, cache);
            return RAD_OK;
        }
        cache->first[l] = (uint32_t)total;
    }
    if ((double)(count + 1) * sizeof *cache->first +
            (double)total * (sizeof *cache->node + sizeof *cache->weight) > budget) {
        rad_hier_kernel_cache_free(ctx, cache);
        return RAD_OK;
    }
    if (total) {
        cache->node = rad_alloc(ctx, total, sizeof *cache->node);
        cache->weight = rad_alloc(ctx, total, sizeof *cache->weight);
        if (!cache->node || !cache->weight) {
            rad_hier_kernel_cache_free(ctx, cache);
            return RAD_ERROR_NO_MEMORY;
        }
    }
#pragma omp parallel for schedule(static) num_threads(threads) if (links_count >= 4096)
    for (long l = 0; l < links_count; ++l) {
        if (cache->first[l] == cache->first[l + 1]) continue;
        const rad_hier_node *r = &nodes[links[l].receiver], *s = &nodes[links[l].source];
        uint32_t *node = cache->node + cache->first[l];
        double *weight = cache->weight + cache->first[l];
        keep_descendants(nodes, links[l].source, depth, centre(r), normal[r->polygon],
                         normal[s->polygon], &node, &weight);
    }
    cache->count = count;
    return RAD_OK;
}

int rad_hier_kernel_cache_mean(const rad_hier_kernel_cache *cache, const rad_hier_node *nodes,
                               size_t link, double out[3]) {
    if (link >= cache->count) return 0;
    uint32_t first = cache->first[link], last = cache->first[link + 1];
    if (first == last) return 0;
    double weights = 0, sum[3] = {0, 0, 0};
    for (uint32_t i = first; i < last; ++i) {
        double weight = cache->weight[i];
        const double *b = nodes[cache->node[i]].radiosity;
        weights += weight;
        for (int c = 0; c < 3; ++c) sum[c] += weight * b[c];
    }
    if (!(weights > 0)) return 0;
    for (int c = 0; c < 3; ++c) out[c] = sum[c] / weights;
    return 1;
}

void rad_hier_kernel_cache_free(rad_context *ctx, rad_hier_kernel_cache *cache) {
    rad_free(ctx, cache->first);
    rad_free(ctx, cache->node);
    rad_free(ctx, cache->weight);
    memset(cache, 0, sizeof *cache);
}
