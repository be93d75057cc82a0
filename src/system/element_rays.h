/* element_rays.h - ray queries against the ELEMENT mesh (Embree 3): the surfaces the radiosity
 * solution lives on. A hit names the element and where on it (Embree's u, v), so the renderer can
 * interpolate the radiosity at the hit. Every element goes into one RTC_GEOMETRY_TYPE_QUAD
 * geometry (triangles as quads with the last corner twice), except that a flat grid of elements
 * (a quad cell of the mesher, mesh.h) or a flat tree of them (a hierarchy root's leaves) goes in
 * as one quad and a hit on it finds its element and the element's u, v by inverting the shape's
 * bilinear map: Embree traverses a tree of a few cells or roots rather than of every element.
 *
 * The renderer traces every ray (camera, gather, shadow, specular) against this one geometry, so
 * a point found by one query is exactly on the surface the next query starts from; the input
 * polygons (scene/rays.h) may differ from it by a few units where a quad is not planar (the
 * Cornell box's walls are off by about 3 mm). */
#ifndef RAD_RENDER_ELEMENT_RAYS_H
#define RAD_RENDER_ELEMENT_RAYS_H

#include "mesh/mesh.h"
#include "scene/rays.h"

#include <embree3/rtcore.h>

/* A flat convex grid or tree of the mesh (mesh.h) traced as one quad (a tree's triangle as
 * Embree's quad (c0, c1, c2, c2)): its bilinear map in a frame of its plane with corner 0 at the
 * origin, h = s e + t f + s t g (e, f, c2 corners 1, 3, 2; for a triangle f is corner 2). */
typedef struct rad_grid_quad {
    double e[2], f[2], g[2], c2[2];
    double ef, gf;     /* cross(e, f), cross(g, f) */
    double half_inverse_gf;
    int affine;        /* a parallelogram: g is 0 */
    int nearly_affine; /* |gf| under 10^-4 |ef|: the quadratic for t is nearly linear */
    int triangle;      /* a tree's triangle root: Embree's u, v are its barycentric coordinates */
    rad_vec3 origin, axis_x, axis_y; /* the plane's frame: corner 0 and two axes */
    const rad_mesh_grid *grid;       /* the grid, or NULL for a tree */
    const rad_mesh_tree *tree;       /* the tree (its root node: tree->node), or NULL */
    int table_depth;                 /* its table's depth (0: none) */
    size_t table;                    /* its first cell in rad_element_rays.cells */
} rad_grid_quad;

/* A cell of a tree's table (element_rays.c, tree_locate): the node at the table's depth that
 * holds it, or the leaf above it at `depth`, and a copy of that node (a leaf's elements read
 * without another load). */
typedef struct rad_tree_cell {
    uint32_t node, depth;
    rad_mesh_tree_node leaf;
} rad_tree_cell;

typedef struct rad_element_rays {
    rad_context *ctx;
    const rad_mesh *mesh;
    RTCDevice device;
    RTCScene scene;
    double epsilon;             /* scene-scaled offset that keeps rays off their start surface */
    rad_ray_frame frame;        /* world -> Embree coordinates (scene/rays.h) */
    /* Primitives 0 .. quad_count - 1 are grids and trees (a hit finds its element inside), the
     * others the elements of no such shape: primitive quad_count + i is element loose[i]
     * (loose NULL: no shapes, primitive i is element i); loose_count elements are traced as
     * themselves. */
    size_t quad_count, loose_count;
    rad_grid_quad *quads;
    uint32_t *loose;
    rad_tree_cell *cells; /* the trees' tables */
} rad_element_rays;

/* Builds the Embree scene of the mesh's elements. The mesh must outlive the result. */
rad_status rad_element_rays_create(rad_context *ctx, const rad_mesh *mesh, rad_element_rays **out);
/* The same; robust 0 leaves Embree's robust traversal (RTC_SCENE_FLAG_ROBUST) off: a few %
 * less processor time per ray, at the risk of a ray slipping through an edge shared by two
 * elements (the renderer's, docs/rendering.md, "Where the time goes"). */
rad_status rad_element_rays_create_with(rad_context *ctx, const rad_mesh *mesh, int robust,
                                          rad_element_rays **out);
void rad_element_rays_destroy(rad_element_rays *rays);

typedef struct rad_element_hit {
    double t;
    uint32_t element;
    /* Where on the element, Embree's parametrisation: for a triangle (v0, v1, v2) the point is
     * (1-u-v) v0 + u v1 + v v2; for a quad (v0, v1, v2, v3) u runs along v0 -> v1 and v along
     * v0 -> v3, and vertex values interpolate bilinearly with weights (1-u)(1-v), u(1-v), uv,
     * (1-u)v. */
    double u, v;
    int front; /* nonzero when the ray arrived on the element's front (counter-clockwise) side */
} rad_element_hit;

/* The closest hit along origin + t * direction, t in (tnear, tfar); nonzero on a hit.
 * Thread safe. */
int rad_element_rays_intersect(const rad_element_rays *rays, rad_vec3 origin, rad_vec3 direction,
                               double tnear, double tfar, rad_element_hit *hit);

/* Nonzero when something blocks the segment from a to b, its ends excluded by epsilon.
 * Thread safe. */
int rad_element_rays_occluded(const rad_element_rays *rays, rad_vec3 a, rad_vec3 b);

/* rad_element_hit.element where a ray of rad_element_rays_intersect16 met nothing. */
#define RAD_NO_ELEMENT UINT32_MAX

/* The first hits of n <= 16 rays from origin along direction[i] (any length), t in (tnear,
 * inf), as one Embree packet: rad_element_rays_intersect's hits (the same floats go in), element
 * RAD_NO_ELEMENT where a ray meets nothing. For coherent rays (a point's gather rays). Thread
 * safe. */
void rad_element_rays_intersect16(const rad_element_rays *rays, rad_vec3 origin, const rad_vec3 *direction,
                                  int n, double tnear, rad_element_hit *hit);

/* Whether the segments from a to b[i], i < n <= 16, are blocked, as one Embree packet:
 * rad_element_rays_occluded's answers (the same floats go in). Thread safe. */
void rad_element_rays_occluded16(const rad_element_rays *rays, rad_vec3 a, const rad_vec3 *b, int n,
                                 int *occluded);

/* The interpolation weights of the element's corners at (u, v) (3 or 4 of them). */
static inline int rad_element_weights(const rad_mesh *mesh, uint32_t element, double u, double v,
                                      double weight[4]) {
    if (rad_mesh_corner_count(mesh, element) == 3) {
        weight[0] = 1 - u - v;
        weight[1] = u;
        weight[2] = v;
        return 3;
    }
    weight[0] = (1 - u) * (1 - v);
    weight[1] = u * (1 - v);
    weight[2] = u * v;
    weight[3] = (1 - u) * v;
    return 4;
}

/* The point at (u, v) on the element, on the same two triangles Embree intersects. */
rad_vec3 rad_element_point(const rad_mesh *mesh, uint32_t element, double u, double v);

#endif
