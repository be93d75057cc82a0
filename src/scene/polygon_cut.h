/* polygon_cut.h - a simple polygon in its plane cut into a few convex pieces: ear clipping
 * that resumes where it was and tests only reflex corners, through a grid, then Hertel and
 * Mehlhorn's removal of the diagonals convexity does not need (docs/meshing.md, "concave").
 * Used by the importers for non-convex faces (scene/import.c, scene/mgf.c). */
#ifndef RAD_SCENE_POLYGON_CUT_H
#define RAD_SCENE_POLYGON_CUT_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

/* The pieces of a polygon: piece k has the corners corners[first[k] .. first[k + 1]), indices
 * into the polygon, counter-clockwise like it. Valid when zeroed; free with
 * rad_polygon_pieces_free. */
typedef struct rad_polygon_pieces {
    uint32_t *corners;
    size_t *first; /* count + 1 entries */
    size_t count;
    /* 0 when the polygon is not simple (it crosses or touches itself so that no ear was left
     * at some step): the pieces are then the triangles as they were clipped, some of them
     * overlapping or turned over, as a fan would cut it. */
    int simple;
} rad_polygon_pieces;

/* Cuts the polygon of n corners (`xy[2k]`, `xy[2k + 1]` for corner k: 2-D, counter-clockwise,
 * n >= 3 and below 2^30) into convex pieces. A corner counts as convex when it turns left, or
 * right by less than `dent` (a distance, off the line through its neighbours), so a piece may
 * keep dents that small; dent 0 means convex up to rounding. Every piece is convex in that
 * sense, the pieces cover the polygon without overlap when it is simple, and there are at most
 * four times the fewest possible (Hertel and Mehlhorn 1983) and at most 2r + 1 for r reflex
 * corners. Time about linear in n on real faces (gears, combs, letters, floor plans): at most
 * 3n ear tests, each looking at the reflex corners in the grid cells its triangle meets; a
 * budget of work bounds the worst case (the polygon is then cut as if it were not simple). */
rad_status rad_polygon_cut(rad_context *ctx, const double *xy, size_t n, double dent,
                           rad_polygon_pieces *out);

/* The same for a polygon in 3-D: its corners p[0 .. n) projected on the plane through the
 * origin with unit `normal`, counter-clockwise seen from its front. */
rad_status rad_polygon_cut_in_plane(rad_context *ctx, const rad_vec3 *p, size_t n,
                                    rad_vec3 normal, double dent, rad_polygon_pieces *out);

void rad_polygon_pieces_free(rad_context *ctx, rad_polygon_pieces *pieces);

#endif
