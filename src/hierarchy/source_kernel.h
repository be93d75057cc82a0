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

#endif
