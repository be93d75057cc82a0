/* contact.h - discontinuity meshing at contacts (D0): the scene's polygons cut along the lines
 * where other surfaces touch or pass through them, and the pieces hidden inside solids dropped
 * (docs/meshing.md, "Contacts"; Baum, Mann, Smith and Winget 1991; Heckbert 1992; Lischinski,
 * Tampieri and Greenberg 1992).
 *
 * The mesher cuts these pieces instead of the input polygons, so no element straddles a
 * contact; any other method that wants the same roots (the hierarchical solver's quadtrees)
 * calls rad_contact_cut_create on the scene and takes its pieces. */
#ifndef RAD_MESH_CONTACT_H
#define RAD_MESH_CONTACT_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

struct rad_scene;

/* A convex piece of input polygon `polygon` (same surface, same orientation): points
 * first .. first + count - 1 of the cut, counter-clockwise seen from its front. */
typedef struct rad_contact_piece {
    uint32_t polygon;
    uint32_t first, count;
} rad_contact_piece;

typedef struct rad_contact_cut {
    size_t piece_count;
    rad_contact_piece *pieces; /* in polygon order; an uncut polygon is one piece */
    size_t point_count;
    rad_vec3 *points;
    size_t cut_polygons;  /* input polygons cut by at least one contact line */
    size_t contact_lines; /* lines cut along, over all polygons */
    size_t hidden_pieces; /* pieces dropped: inside a solid standing on or passing through */
    double hidden_area;
    size_t coplanar_pairs; /* polygons of two surfaces overlapping back to back in one plane
                              (not cut) */
    size_t covered_pairs;  /* a polygon lying on a larger one in its plane, facing the same way:
                              the larger is cut along its outline ... */
    size_t covered_pieces; /* ... and these pieces of it, under the smaller, are dropped */
    size_t shadow_segments; /* shadow boundaries found (shadow.h) ... */
    size_t shadow_cuts;     /* ... and those cut along (after dedupe and the cap per polygon) */
    size_t t_points;        /* corners added where a cut ended on another piece's edge */
    size_t left_whole;      /* with sparing: polygons cut and then left whole (nothing hidden,
                               or too many pieces) */
    size_t bound_tests;     /* step 2's cost: bounds compared (the tree's nodes and the
                               polygons' bounds), near n log n plus the pairs that meet */
} rad_contact_cut;

typedef struct rad_contact_options {
    int shadows;         /* nonzero: cut at shadow boundaries of area emitters too (shadow.h) */
    double element_size; /* with shadows: segments shorter than a quarter of it are not cut
                            along, and no cut leaves a piece narrower than SLIVER times it */
    int t_points;        /* nonzero: where a contact cut ends on an edge shared with another
                            polygon of the surface (bending less than 30 degrees), that polygon
                            gets the end as a corner (the mesher asks for it; with shadows they
                            are always added) */
    int no_near;         /* nonzero: no step 2b (B parallel and a little in front of A): what
                            lies behind B may still be seen past its edges (a sky quad above a
                            roof with an opening), so only touching contacts are cut */
    int sealed;          /* nonzero, with no_near: step 2b is kept where B seals A: B faces the
                            same way as A, and its gap is under RAD_CONTACT_SEALED_GAP of B's
                            width (2 area / perimeter): a lamp panel 0.1 mm under its ceiling,
                            not a ceiling 1 m under a sky (the part of the sky behind it is seen
                            through an opening). What lies behind B is then hidden (step 4) */
    int quiet;           /* nonzero: no warnings (a second cut of the same scene) */
    int sparing;         /* nonzero (the hierarchy's roots, mesh/roots.h): a polygon cut by its
                            contacts is left whole when none of its pieces is hidden or covered,
                            or when it would be cut into more than RAD_CONTACT_SPARING_PIECES
                            pieces (a wall crossed by many others): cuts only where they pay */
} rad_contact_options;

/* With sparing, a polygon cut into more pieces than this is left whole (the Cornell box's
 * floor, cut along both blocks' bases, has 22; Sponza's 41,274 polygons give 42,595 pieces at
 * 24, 43,672 at 64; docs/hierarchical.md, "Contacts and the source's variation"). */
#define RAD_CONTACT_SPARING_PIECES 24

/* The gap, as a share of B's width (2 area / perimeter), under which a polygon B just in
 * front of A and facing the same way seals the part of A behind it (options.sealed). A point
 * of A at depth d behind B's outline sees past it only within about gap / d of grazing (a
 * cosine-weighted share of about (gap / d)^2 / 4 beside a straight edge, gap / 2 per unit of
 * outline summed over d), so the light the dropped part would get is about this share of what
 * it would get in the open (the Cornell lamp: 0.1 mm under the ceiling, 58 mm wide, 0.0017). */
#define RAD_CONTACT_SEALED_GAP 0.01

/* Finds the contacts of every polygon with the polygons of other surfaces and cuts. Polygons
 * the mesher would skip (zero area, not finite) are passed on uncut. Where two polygons overlap
 * in one plane facing the same way, the larger loses the part under the smaller; back to back
 * they are left as they are. Warns once for each, naming the first two surfaces. */
rad_status rad_contact_cut_create(rad_context *ctx, const struct rad_scene *scene,
                                  rad_contact_cut **out);
/* The same with options (NULL: contacts only, no T-points). With shadows or t_points, where a
 * cut ends on the edge of another piece of the same surface (a shadow segment inside a face, a
 * contact line at an edge shared with a neighbouring polygon), that piece gets the end as a
 * corner, so the pieces meet without T-junctions: a piece then has corners where it runs
 * straight on. */
rad_status rad_contact_cut_create_with(rad_context *ctx, const struct rad_scene *scene,
                                       const rad_contact_options *options, rad_contact_cut **out);
/* Narrows [*t0, *t1] to where the line point + t direction (unit) lies inside the convex
 * polygon p[0 .. n-1] (counter-clockwise about normal), eps inside its edges; 0 when nothing
 * is left. */
int rad_clip_line_convex(const rad_vec3 *p, size_t n, rad_vec3 normal, rad_vec3 point,
                         rad_vec3 direction, double eps, double *t0, double *t1);
void rad_contact_cut_destroy(rad_context *ctx, rad_contact_cut *cut);

#endif
