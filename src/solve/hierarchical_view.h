/* hierarchical_view.h - the hierarchy's own solution view: the outputs (render, bake, --json)
 * draw the quadtree leaves directly (hierarchical_view.c). */
#ifndef RAD_SOLVE_HIERARCHICAL_VIEW_H
#define RAD_SOLVE_HIERARCHICAL_VIEW_H

#include "hierarchy/hierarchy.h"
#include "system/system.h"

/* What the hierarchical solver builds a hierarchy with (hierarchical.c): the link error and
 * importance it was asked for, and what the nodes read their light from (the lights, the sky,
 * the specular-first deposits on the system's elements). */
typedef struct rad_hier_setup rad_hier_setup;

/* A hierarchy as the hierarchical solver begins one on `system`: the roots, the clusters and
 * their light (rad_hier_create), not yet linked. `reflection`, when not NULL, is the second
 * specular pass's per-element light to read instead of system->specular_reflection (a saved
 * solution's). */
rad_status rad_hier_setup_create(rad_system *system, double link_error, int importance,
                                 rad_rgb *reflection, rad_hier_setup **setup, rad_hier **hier);
void rad_hier_setup_destroy(rad_system *system, rad_hier_setup *setup);
double rad_hier_setup_link_error(const rad_hier_setup *setup);
int rad_hier_setup_importance(const rad_hier_setup *setup);
/* Whether the last solve of the links was cancelled (Ctrl-C) and is to be finished by the next
 * step, and setting it (a saved solution's). */
int rad_hier_setup_unfinished(const rad_hier_setup *setup);
void rad_hier_setup_set_unfinished(rad_hier_setup *setup, int unfinished);
/* Whether the last solve of the links stopped at the loose tolerance (after a step that refined
 * much; the step that refines nothing then solves tight and asks the oracle once more), and
 * setting it (a saved solution's). */
int rad_hier_setup_loose(const rad_hier_setup *setup);
void rad_hier_setup_set_loose(rad_hier_setup *setup, int loose);

/* Sets the system's elements' radiosity from the hierarchy behind its view (as every
 * hierarchical step does), so that what reads elements reads the hierarchy. */
void rad_hier_view_evaluate(rad_system *system);

/* The link error at or below which the hierarchy's leaves are fine enough for the final gather
 * to read them where its rays land, re-gathering only short rays (RAD_LEAVES_FINE), rather than
 * as coarse leaves (every first gather ray re-gathered, RAD_LEAVES_COARSE). Cornell 256 x 256 at
 * 1e-5, seeds 0-4: 4x4 RMSE 1.06-1.11 % -> 0.92-0.94 %, 8x8 0.71-0.75 % -> 0.74-0.78 %, gather
 * rays 8.57 -> 6.31 M, shadow rays 3.25 -> 1.22 M, processor time 38 % less; at 1e-4 and 3e-5
 * the fine reading was ahead per processor second in 4x4 and 8x8 blocks but not in 16x16, at
 * 3e-4 even, at the default 1e-3 behind (docs/hierarchical.md, "The Cornell render from fine
 * leaves"). */
#define RAD_HIER_FINE_LINK_ERROR 1e-5

/* The link error a hierarchy solved for a final-gathered image (the solver's "final-gather"
 * option, which render sets) takes when none is given (no --link-error, no --tolerance, no
 * --importance), on a one-element-per-root system of at most RAD_HIER_GATHERED_ROOTS roots:
 * fine leaves read where the gather rays land. Cornell 256 x 256, seeds 0-2: 4x4 RMSE
 * 0.74-0.75 %, 8x8 0.53-0.56 %, 16x16 0.39-0.44 % in 2.7-2.9 processor-s, against 1.15-1.19 %,
 * 0.81-0.84 %, 0.55-0.59 % in 3.6-3.7 s at the default 1e-3, back to back: 23x the path
 * tracer at equal 4x4 error (docs/hierarchical.md, "The roots cut where a polygon seals
 * another"). The threshold keeps the scenes where the hierarchy
 * is the default solver (RAD_HIERARCHY_DEFAULT_POLYGONS, 8,000 polygons and more; Sponza's
 * 43,502 roots, the offices' 1,028 and more) at RAD_HIER_DEFAULT_LINK_ERROR: at 5e-6 the
 * smallest office's solve took 2.07 processor-s against 0.27 s. */
#define RAD_HIER_GATHERED_LINK_ERROR 5e-6
#define RAD_HIER_GATHERED_ROOTS 256

/* A hierarchy refined to fine leaves (RAD_HIER_FINE_LINK_ERROR or less) of a scene of at most
 * RAD_HIER_GATHERED_ROOTS roots reads each fully visible link's source this many levels down,
 * weighed by the kernel from the receiver (rad_hier_options.source_depth, source_kernel.c),
 * not as the source's mean. Cornell at 5e-6, `solve --json`: every surface but the floor was
 * 0.26-0.29 % darker than shooting's at 10,000 elements (the ceiling 0.90 %) and 0.308 of the
 * lamp's power escaped against 0.306; with 2 levels within 0.12 % (the floor +0.31 %) and
 * 0.306. The final-gathered render, seeds 0-3: 8x8 bias 0.39 -> 0.24 %, 16x16 0.36 -> 0.20 %
 * (1 level: 0.26 / 0.22 %, 3 levels: 0.24 / 0.20 % for more solve time; docs/hierarchical.md,
 * "hcornell2"). Larger scenes keep the mean: Sponza's and the offices' links are millions. */
#define RAD_HIER_FINE_SOURCE_DEPTH 2

/* Installs a view over the leaves of `hier` as the system's solution view; the system owns the
 * hierarchy and `setup` from now on (they go with the system or the next rad_system_set_view).
 * `restored`: loaded from a solution file, for the next resumed solve to go on from. */
rad_status rad_hier_view_install(rad_system *system, rad_hier *hier, rad_hier_setup *setup,
                                 int restored);

/* The hierarchy behind the system's view and its setup, or NULL when the view is not a
 * hierarchy's. */
rad_hier *rad_hier_view_hierarchy(const rad_system *system);
rad_hier_setup *rad_hier_view_setup(const rad_system *system);

/* 1, once, when the view's hierarchy was restored from a solution file (a resumed solve goes on
 * from it); 0 otherwise. */
int rad_hier_view_take_restored(rad_system *system);

/* The area-weighted mean of `values` (per system element) over the elements order[first ..
 * last) (order NULL: first .. last themselves) whose centroids lie inside the polygon
 * `corners` (count corners, counter-clockwise); the nearest element's value when none does,
 * zero when the range is empty. How the hierarchy reads per-element light (the lights'
 * pre-pass, the specular-first deposits) onto its nodes and leaves. */
void rad_hier_elements_mean(const rad_system *system, rad_rgb *values, const uint32_t *order,
                            size_t first, size_t last, const rad_vec3 *corners, int count,
                            double out[3]);

#endif
