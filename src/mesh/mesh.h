/* mesh.h - surfaces cut into patches and patches into elements (Cohen et al. 1986).
 *
 * The input polygons are first cut where other surfaces touch or pass through them, and the
 * pieces hidden inside solids are dropped (contact.h). Each piece is cut into elements (quads
 * into a grid of quads, triangles to their own three side counts, mostly into three grids of
 * quads: triangle.h; larger convex polygons are peeled into triangles first: ngon.h). The number of cuts along an edge is shared by every polygon of
 * the surface that uses the edge, so elements of a surface share their vertices: no T-junctions
 * inside a surface. Vertices are never shared between surfaces, so a corner between two
 * surfaces keeps one value per side.
 *
 * Patches are convex groups of elements of one polygon, no larger than k x k elements;
 * elements of a patch are contiguous. */
#ifndef RAD_MESH_MESH_H
#define RAD_MESH_MESH_H

#include "core/context.h"
#include "core/vec3.h"

#include <stdint.h>

#define RAD_NO_VERTEX UINT32_MAX

struct rad_scene;

typedef struct rad_mesh {
    rad_context *ctx;
    size_t vertex_count;
    rad_vec3 *vertices;
    uint32_t *vertex_surface; /* the surface a vertex belongs to */

    size_t element_count;
    uint32_t (*element_vertices)[4]; /* counter-clockwise; [3] == RAD_NO_VERTEX for triangles */
    rad_vec3 *element_normal;
    rad_vec3 *element_centroid;
    double *element_area;
    uint32_t *element_polygon; /* the input polygon it was cut from */
    uint32_t *element_surface;
    uint32_t *element_patch;

    size_t patch_count;
    size_t *patch_first; /* patch_count + 1 */

    double element_size, patch_size; /* what was used */
} rad_mesh;

/* Meshes a geometric scene. Zero options pick defaults (docs/meshing.md). Degenerate (zero-area)
 * polygons are skipped and counted in a warning. */
rad_status rad_mesh_create(rad_context *ctx, const struct rad_scene *scene,
                           const rad_mesh_options *options, rad_mesh **out);
void rad_mesh_destroy(rad_mesh *mesh);
/* An empty mesh with room for this many vertices and elements (vertex_surface zeroed, counts 0);
 * NULL when memory runs out. rad_mesh_destroy frees it. */
rad_mesh *rad_mesh_alloc(rad_context *ctx, size_t vertices, size_t elements);

static inline int rad_mesh_corner_count(const rad_mesh *mesh, size_t element) {
    return mesh->element_vertices[element][3] == RAD_NO_VERTEX ? 3 : 4;
}

/* The default number of elements when no size is given. */
#define RAD_MESH_DEFAULT_ELEMENTS 2500

#endif
