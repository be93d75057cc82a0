/* source_kernel.h - the radiosity a link reads from its source, weighed by where its receiver
 * looks (source_kernel.c). */
#ifndef RAD_HIERARCHY_SOURCE_KERNEL_H
#define RAD_HIERARCHY_SOURCE_KERNEL_H

#include "hierarchy/hierarchy.h"

/* The mean radiosity of node `source`'s descendants `depth` levels down (or the leaves above
 * that depth), each weighed by its area times the point kernel cos cos / r^2 from the
 * receiver's centre to its own (nr, ns: the receiver's and the source's normals),
 * into out. Returns 0 (out untouched) when the source has no children or no descendant faces
 * the receiver. */
int rad_hier_source_kernel_mean(const rad_hier_node *nodes, const rad_hier_node *receiver,
                                rad_vec3 nr, uint32_t source, rad_vec3 ns, int depth,
                                double out[3]);

/* The weights of every link's descendants, kept for the rounds of one solve (the links and the
 * nodes' shapes do not change between refinements; only the radiosities do), so that a round
 * reads them instead of walking the source's tree and computing the kernel again: Cornell at
 * link error 5e-6 ran 21 rounds over 5 refinements (docs/hierarchical.md, "hcornell3"). */
typedef struct rad_hier_kernel_cache {
    uint32_t *first; /* link l's entries are first[l] .. first[l + 1]; none: the plain mean */
    uint32_t *node;  /* the descendant each entry reads */
    double *weight;  /* its area times the point kernel from the receiver's centre */
    size_t count;    /* links covered; 0: none kept */
} rad_hier_kernel_cache;

/* Keeps the weights of links[0 .. count) (rad_hier_source_kernel_mean's, the same bits) for the
 * links that read their source through the kernel, 12 bytes a descendant read (Cornell at link
 * error 5e-6: 13 MB for 161,845 links, four times the links' own). When they would take more
 * than `budget` bytes, or past 2^32 entries, nothing is kept (RAD_OK, count 0) and the caller
 * computes them every round as before; RAD_ERROR_NO_MEMORY when an allocation fails. */
rad_status rad_hier_kernel_cache_build(rad_context *ctx, rad_hier_kernel_cache *cache,
                                       const rad_hier_node *nodes, const rad_vec3 *normal,
                                       const rad_hier_link *links, size_t count, int depth,
                                       double budget, int threads);
/* Link `link`'s kernel-weighed mean from the kept weights and the nodes' radiosities now, as
 * rad_hier_source_kernel_mean; 0 (out untouched) when none is kept for it. */
int rad_hier_kernel_cache_mean(const rad_hier_kernel_cache *cache, const rad_hier_node *nodes,
                               size_t link, double out[3]);
void rad_hier_kernel_cache_free(rad_context *ctx, rad_hier_kernel_cache *cache);

#endif
