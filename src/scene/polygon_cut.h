/* polygon_cut.h - a simple polygon in its plane cut into a few convex pieces: ear clipping
 * that resumes where it was and tests only reflex corners, through a grid, then Hertel and
 * Mehlhorn's removal of the diagonals convexity does not need (docs/meshing.md, "concave");
 * and a convex polygon of more corners than the scene takes split into pieces of at most that
 * many (rad_polygon_split: a core through corners spread along it, plus the caps between;
 * docs/meshing.md, "ngon"). Used by both readers (scene/import.c, scene/mgf.c). */
#ifndef RAD_SCENE_POLYGON_CUT_H
#define RAD_SCENE_POLYGON_CUT_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

/* The most corners a polygon of the scene may have (rad_scene_add_polygon_points, the contact
 * cuts of mesh/contact.c): larger faces reach the scene as pieces of at most this many. */
#define RAD_POLYGON_CORNERS_MAX 64

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
 * budget of work bounds the worst case (the polygon is then cut as if it were not simple).
 * A piece of more than `max_corners` corners (0: no limit; else at least 3) is then split as
 * rad_polygon_split does, with the same `dent`. */
rad_status rad_polygon_cut(rad_context *ctx, const double *xy, size_t n, double dent,
                           size_t max_corners, rad_polygon_pieces *out);

/* Splits a convex polygon of n corners (as above) into convex pieces of at most `max_corners`
 * corners (at least 3): one piece when n is at most that; else the core polygon through
 * max_corners corners spread evenly (by length) along the boundary from one end of its longest
 * edge round to the other, and each cap between two consecutive core corners (the run of
 * corners between them, closed by the chord) split the same way. Every corner is in a few
 * pieces (no fan around one corner), and a piece is thin only as far as it is short: a cap
 * over a chord of length c is as thick as the boundary between the chord's ends, and the core
 * as round as the polygon. A cap whose corners all lie within `dent` of its chord is dropped
 * (with dent 0, only a cap with no area): they are rounding's dents, not a piece of the face,
 * and may be turned inside out. `simple` is 1. */
rad_status rad_polygon_split(rad_context *ctx, const double *xy, size_t n, size_t max_corners,
                             double dent, rad_polygon_pieces *out);

/* The same for a polygon in 3-D: its corners p[0 .. n) projected on the plane through the
 * origin with unit `normal`, counter-clockwise seen from its front; rad_polygon_split when the
 * caller knows it is `convex`, else rad_polygon_cut. */
rad_status rad_polygon_cut_in_plane(rad_context *ctx, const rad_vec3 *p, size_t n,
                                    rad_vec3 normal, double dent, size_t max_corners, int convex,
                                    rad_polygon_pieces *out);

void rad_polygon_pieces_free(rad_context *ctx, rad_polygon_pieces *pieces);

#endif
