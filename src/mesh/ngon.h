/* ngon.h - cutting a convex polygon of many corners into well-shaped triangles (docs/meshing.md,
 * "Polygons of many corners"). Internal to src/mesh.
 *
 * A fan from one corner gives a disk of n corners n - 2 needles; a fan from the centroid n
 * triangles of apex 360/n degrees. Instead the polygon is peeled in rings: every other corner
 * is kept and moved inward by about one edge length, and the band between the old and the new
 * boundary is cut into triangles of corners near 45, 45 and 90 degrees; the corner count halves
 * per ring until at most NGON_FAN_CORNERS are left, which are fanned from their centroid. The
 * cells are triangles, which tie no edge counts together (mesh.c, step 3), so each edge is cut
 * to its own length and the mesher's three-quad cut (triangle.c) makes quads of them. */
#ifndef RAD_MESH_NGON_H
#define RAD_MESH_NGON_H

#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

/* Polygons of more corners than this are peeled in rings; up to this many are fanned. */
#define NGON_FAN_CORNERS 8

/* Room needed for a polygon of n corners: extra points and triangles. */
size_t ngon_max_points(size_t n);
size_t ngon_max_triangles(size_t n);

/* Cuts the convex, counter-clockwise (seen along `normal`) polygon p[0 .. n-1], n > 4, into
 * triangles. Corners 0 .. n-1 keep their indices; new inner points get n, n + 1, ... and are
 * written to extra[]. `ring` is scratch for n indices. Writes triangles (indices into the
 * corners and then the extra points, counter-clockwise) and returns how many; *extra_count
 * says how many points were added. */
size_t ngon_cut(const rad_vec3 *p, size_t n, rad_vec3 normal, rad_vec3 *extra, size_t *extra_count,
                uint32_t (*triangles)[3], uint32_t *ring);

#endif
