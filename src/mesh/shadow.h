/* shadow.h - discontinuity meshing at shadow boundaries of area emitters (D1 and D2):
 * P. Heckbert, "Discontinuity Meshing for Radiosity", Eurographics Workshop on Rendering 1992;
 * D. Lischinski, F. Tampieri and D. P. Greenberg, "Discontinuity Meshing for Accurate
 * Radiosity", IEEE CG&A 12(6), 1992 (docs/meshing.md, "Shadow boundaries").
 *
 * Where a blocker's silhouette edge and an emitter's corner (EV) or an emitter's edge and a
 * blocker's silhouette corner (VE) line up, the visible part of the emitter changes shape, and
 * the light on the receiver behind has a kink (D1: where umbra and penumbra begin and end when
 * the edges are parallel) or a kink in its slope (D2). These are found as segments on the
 * receiving polygons; contact.c cuts the polygons along them before meshing, so no element
 * straddles a shadow's edge. Internal to src/mesh. */
#ifndef RAD_MESH_SHADOW_H
#define RAD_MESH_SHADOW_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

struct rad_scene;

/* A critical line on input polygon `polygon`, from a to b (in its plane, inside it). */
typedef struct rad_shadow_segment {
    uint32_t polygon;
    rad_vec3 a, b;
    double weight; /* the emitter's share of the emitted power times the segment's length */
} rad_shadow_segment;

typedef struct rad_shadow_stats {
    size_t emitters;  /* emitter polygons whose events were traced */
    size_t events;    /* EV and VE events traced with rays */
    size_t segments;  /* found on receivers */
    int capped;       /* the budget of events ran out (the rest were not traced) */
} rad_shadow_stats;

/* Finds the shadow boundaries cast by the brightest emitter polygons (at most
 * RAD_SHADOW_EMITTERS) on the scene's polygons; segments shorter than a quarter of
 * `element_size` are left out. *out is sorted by polygon, then by weight (largest first);
 * free it with rad_free. */
rad_status rad_shadow_segments_find(rad_context *ctx, const struct rad_scene *scene,
                                    double element_size, rad_shadow_segment **out, size_t *count,
                                    rad_shadow_stats *stats);

#define RAD_SHADOW_EMITTERS 8

#endif
