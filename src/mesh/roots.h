/* roots.h - the coarsest cut of a scene into quads and triangles, for methods that refine their
 * own leaves (the hierarchical solver's quadtree roots, and its one-element-per-root system).
 *
 * Each input polygon is first cut at its contacts (contact.h: D0, the pieces hidden inside
 * solids dropped), so no root straddles a contact line, but only where that pays
 * (rad_contact_options.sparing: a piece dropped, at most RAD_CONTACT_SPARING_PIECES left;
 * otherwise the polygon stays whole); each piece then loses the corners where
 * it runs straight on (the T-points a cut left on a neighbour's edge), and is a root as it is
 * when it has three or four corners, or fanned from its first corner into triangles. */
#ifndef RAD_MESH_ROOTS_H
#define RAD_MESH_ROOTS_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

struct rad_scene;

typedef struct rad_root {
    rad_vec3 corner[4]; /* counter-clockwise seen from the front; corner[3] unused for a triangle */
    double area;
    uint32_t polygon; /* the input polygon */
    uint32_t count;   /* 3 or 4 */
} rad_root;

typedef struct rad_roots {
    size_t count;
    rad_root *roots;          /* in polygon order, the same for every call on the same scene */
    size_t hidden_pieces;     /* contact pieces dropped (contact.h) */
    double hidden_area;
} rad_roots;

/* The roots of every polygon of nonzero area. Deterministic. Touching contacts are cut, and a
 * polygon is cut where another just in front of it, facing the same way, seals it (the
 * ceiling behind a lamp panel 0.1 mm under it: that part is dropped; rad_contact_options.
 * sealed); not at near-parallel polygons at large (no_near): a surface a little behind another
 * may still be seen past its edges (a sky quad above a roof's opening). quiet: no warnings
 * about coplanar overlaps (the second cut of the same scene). */
rad_status rad_roots_create(rad_context *ctx, const struct rad_scene *scene, int quiet,
                            rad_roots **out);
void rad_roots_destroy(rad_context *ctx, rad_roots *roots);

#endif
