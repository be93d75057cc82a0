/* triangle.h - cutting one triangle into elements and patches, given how many pieces each of
 * its sides is cut into (docs/meshing.md, "Triangles"). Internal to src/mesh.
 *
 * The side counts come from the edges the triangle shares with its neighbours, so they may
 * differ; the cut respects them exactly (the side's cut points are the only element vertices
 * on it), which keeps the surface conforming without tying the three counts together. */
#ifndef RAD_MESH_TRIANGLE_H
#define RAD_MESH_TRIANGLE_H

#include "mesh/mesh.h"

/* One side of a triangle: count pieces, its count + 1 vertex ids from the side's first corner
 * to its last (`reverse`: read ids[count - i]); ids is NULL while only counting. */
typedef struct tri_side {
    const uint32_t *ids;
    uint32_t count;
    int reverse;
} tri_side;

/* Where the elements go. With mesh NULL nothing is written and only the counts advance, so the
 * mesher can size its arrays with the very code that fills them. */
typedef struct tri_out {
    rad_mesh *mesh;
    uint32_t polygon, surface;
    uint32_t k;          /* patches of up to k x k elements */
    double element_size; /* for the counts of the cuts made inside the triangle */
    size_t vertices, elements, patches;
    uint32_t *scratch; /* vertex ids; tri_scratch_size(largest side count) entries */
    size_t scratch_used, scratch_size;
    size_t grids;      /* quad grids cut (counted with or without a mesh) */
    size_t grid_room;  /* more of them mesh->grids has room for (mesh.h, rad_mesh_grid) */
} tri_out;

/* Appends an element (corners counter-clockwise, d == RAD_NO_VERTEX for a triangle) to the
 * current patch, with its area, normal and centroid (mesh.c). */
void rad_mesh_put_element(rad_mesh *mesh, uint32_t polygon, uint32_t surface, uint32_t a,
                          uint32_t b, uint32_t c, uint32_t d);

/* Scratch ids needed for a triangle whose sides have at most `largest` pieces. */
size_t tri_scratch_size(uint32_t largest);

/* Cuts the counter-clockwise triangle p[0] p[1] p[2]; side s runs from p[s] to p[(s + 1) % 3]. */
void tri_cut(tri_out *out, const rad_vec3 p[3], const tri_side side[3]);

#endif
