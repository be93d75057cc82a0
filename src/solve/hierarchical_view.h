/* hierarchical_view.h - the hierarchy's own solution view: the outputs (render, bake, --json)
 * draw the quadtree leaves directly (hierarchical_view.c). */
#ifndef RAD_SOLVE_HIERARCHICAL_VIEW_H
#define RAD_SOLVE_HIERARCHICAL_VIEW_H

#include "hierarchy/hierarchy.h"
#include "system/system.h"

/* Installs a view over the leaves of `hier` as the system's solution view; the system owns the
 * hierarchy from now on (it goes with the system or the next rad_system_set_view). */
rad_status rad_hier_view_install(rad_system *system, rad_hier *hier);

/* The hierarchy behind the system's view, or NULL when the view is not a hierarchy's. */
rad_hier *rad_hier_view_hierarchy(const rad_system *system);

/* The area-weighted mean of `values` (per system element) over the elements order[first ..
 * last) (order NULL: first .. last themselves) whose centroids lie inside the polygon
 * `corners` (count corners, counter-clockwise); the nearest element's value when none does,
 * zero when the range is empty. How the hierarchy reads per-element light (the lights'
 * pre-pass, the specular-first deposits) onto its nodes and leaves. */
void rad_hier_elements_mean(const rad_system *system, rad_rgb *values, const uint32_t *order,
                            size_t first, size_t last, const rad_vec3 *corners, int count,
                            double out[3]);

#endif
