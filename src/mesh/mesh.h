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

/* A quad cell of the mesher cut into a grid (rad_mesh_create, step 4): elements first .. first +
 * nu nv - 1, element (i, j) (i < nu along corner 0 -> 1, j < nv along corner 0 -> 3) spanning
 * [i / nu, (i + 1) / nu] x [j / nv, (j + 1) / nv] of the bilinear map of its corners, numbered in
 * blocks of k x k (its patches): rows of blocks, blocks along a row, then rows within a block. */
typedef struct rad_mesh_grid {
    uint32_t corner[4]; /* mesh vertices at (0, 0), (nu, 0), (nu, nv), (0, nv) */
    uint32_t first, nu, nv, k;
} rad_mesh_grid;

/* A quadtree of drawn elements (a hierarchy's, solve/hierarchical_view.c): node i of
 * rad_mesh.tree_nodes is split (count 0) into the four nodes first .. first + 3, made as
 * rad_hier's split makes them (a quad at its edge midpoints and centre: children at (s, t) in
 * [0, 1/2]^2, then s, then both, then t in the upper half of its bilinear map; a triangle at
 * its edge midpoints: the corners 0, 1 and 2's children, then the middle one, whose corners
 * are the midpoints of edges 1-2, 2-0 and 0-1), or a leaf drawn as the elements first .. first
 * + count - 1 (one: the leaf itself, corners in its own order; more: a fan of triangles about
 * its centre, each (centre, a, b) with a, b along its outline). */
typedef struct rad_mesh_tree_node {
    uint32_t first, count;
} rad_mesh_tree_node;
/* A tree's root: its corners (counter-clockwise) and its node. */
typedef struct rad_mesh_tree {
    rad_vec3 corner[4];
    uint32_t corner_count, node;
} rad_mesh_tree;

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

    /* The quad cells' grids (rad_mesh_create only; other meshes have none): what lets ray
     * queries trace a cell as one quad and find the element inside (element_rays.h). */
    size_t grid_count;
    rad_mesh_grid *grids;
    /* Quadtrees over the elements (a hierarchy's drawn leaves; other meshes have none), for the
     * same use. */
    size_t tree_count;
    rad_mesh_tree *trees;
    rad_mesh_tree_node *tree_nodes;
} rad_mesh;

/* The element of grid g at cell (i, j), i < nu, j < nv. */
static inline uint32_t rad_mesh_grid_element(const rad_mesh_grid *g, uint32_t i, uint32_t j) {
    uint32_t row = j / g->k, column = i / g->k;
    uint32_t height = g->nv - row * g->k < g->k ? g->nv - row * g->k : g->k;
    uint32_t width = g->nu - column * g->k < g->k ? g->nu - column * g->k : g->k;
    return g->first + row * g->k * g->nu + column * g->k * height + (j - row * g->k) * width +
           (i - column * g->k);
}

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
