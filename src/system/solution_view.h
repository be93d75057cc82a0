/* solution_view.h - the solution as the outputs see it (issue 11, item 4).
 *
 * Render (smooth, flat, final gather, second pass), bake and the solution file ask a solution
 * view, not the system's per-element arrays: the radiosity at a point of a leaf, its unshot
 * radiosity where the method keeps one, its emission and reflectance, and the list of leaves to
 * draw with their polygons. The model is RenderPark's RadianceMethod::getRadiance(patch, u, v):
 * the renderer does not care whether the solution is stored per element, per hierarchy leaf or
 * in some other basis.
 *
 * Leaves are given as a rad_mesh whose elements are the leaves (corners counter-clockwise, shared
 * vertices inside a surface, normals, areas, centroids, surfaces). A method whose leaves appear
 * and vanish while it runs (a hierarchy refining its links) hands out a new mesh and a new
 * generation number each time the set changes; whoever keeps something built from the leaves
 * (the renderer's rays, its emitter table, its reconstruction weights) rebuilds it when the
 * generation it built from is no longer the view's. Leaf numbers are valid only within one
 * generation.
 *
 * The first implementation is the uniform mesh (rad_system_alloc installs it): the leaves are the
 * system's elements, the radiosity is constant over each one. Another method installs its own
 * with rad_system_set_view. */
#ifndef RAD_SYSTEM_SOLUTION_VIEW_H
#define RAD_SYSTEM_SOLUTION_VIEW_H

#include "mesh/mesh.h"
#include "system/system.h"

typedef struct rad_solution_view_ops {
    const char *name; /* "uniform mesh", ... */
    /* The leaves to draw now; NULL when the system has no geometry (a patch system, .ffm).
     * Valid until the generation changes. */
    const rad_mesh *(*leaves)(const rad_solution_view *view);
    /* Changes whenever leaves appear or vanish; the same number means the same leaves. */
    uint64_t (*generation)(const rad_solution_view *view);
    /* The method's radiosity at (u, v) of a leaf (the parametrisation of element_rays.h), W/m^2,
     * without the ambient term. */
    void (*radiosity)(const rad_solution_view *view, size_t leaf, double u, double v,
                      double out[3]);
    /* The leaf's unshot radiosity; returns 0 (and zeros) when the method keeps none. */
    int (*unshot)(const rad_solution_view *view, size_t leaf, double out[3]);
    /* What the leaf emits itself (its material), without the light the lights' pre-pass put
     * into the system's emission (docs/lights.md): what makes it a light source to render. */
    void (*emission)(const rad_solution_view *view, size_t leaf, double out[3]);
    void (*reflectance)(const rad_solution_view *view, size_t leaf, double out[3]);
    /* The ambient radiosity (Cohen et al. 1988) display adds as reflectance * ambient. */
    void (*ambient)(const rad_solution_view *view, double out[3]);
    /* Restores a leaf's radiosity and unshot radiosity (solution files); NULL when the method
     * cannot be restored from per-leaf values. */
    void (*store)(rad_solution_view *view, size_t leaf, const double radiosity[3],
                  const double unshot[3]);
    /* Frees the state when the system goes; NULL when the state is not the view's. */
    void (*destroy)(void *state);
    /* How many leaves the method holds, when a leaf may be drawn as several polygons; NULL:
     * one polygon each (rad_system_leaf_count). */
    size_t (*leaf_count)(const rad_solution_view *view);
    /* What the leaves are like, for the final gather (final_gather.c, rad_regather_choose):
     * RAD_LEAVES_UNIFORM (0) a uniform mesh's elements; RAD_LEAVES_COARSE a leaf may straddle
     * a shadow line and hold its mean (the hierarchy's large leaves at its default link
     * error): the gather reads the solution one bounce later at any distance
     * (docs/hierarchical.md, "The arcades' back walls"); RAD_LEAVES_FINE a hierarchy refined
     * finely (docs/hierarchical.md, "The Cornell render from fine leaves"): read where gather
     * rays land, as a uniform mesh is, but its leaves at dark contacts are larger than a
     * uniform mesh's elements. */
    int leaf_kind;
} rad_solution_view_ops;

enum { RAD_LEAVES_UNIFORM = 0, RAD_LEAVES_COARSE = 1, RAD_LEAVES_FINE = 2 };

/* The system's current view (the uniform mesh unless a solver installed another); lives as long
 * as the system or until rad_system_set_view. */
const rad_solution_view *rad_system_view(const rad_system *system);
rad_solution_view *rad_system_view_mutable(rad_system *system);

/* Replaces the system's view (the old one's destroy is called); the system owns `state` from
 * now on when ops->destroy is set. */
void rad_system_set_view(rad_system *system, const rad_solution_view_ops *ops, void *state);

/* The uniform mesh's view of a system: leaves = elements, constant radiosity per element. */
extern const rad_solution_view_ops rad_uniform_view_ops;

/* Shorthands. */
static inline const rad_mesh *rad_solution_leaves(const rad_solution_view *view) {
    return view->ops->leaves(view);
}
static inline uint64_t rad_solution_generation(const rad_solution_view *view) {
    return view->ops->generation(view);
}

/* The u = v of a leaf's centre: (1/3, 1/3) on a triangle, (1/2, 1/2) on a quad or when there
 * are no leaf polygons (a patch system). */
static inline double rad_solution_leaf_centre(const rad_mesh *leaves, size_t leaf) {
    return leaves && rad_mesh_corner_count(leaves, leaf) == 3 ? 1.0 / 3 : 0.5;
}

/* What is shown at (u, v) of a leaf: B, plus rho * ambient when with_ambient. */
void rad_solution_display_radiosity(const rad_solution_view *view, size_t leaf, double u, double v,
                                int with_ambient, double out[3]);

/* The area-weighted mean of the display radiosity at the centres of the leaves around each leaf
 * vertex; out has leaves->vertex_count entries (smooth shading and baking, Cohen et al. 1986).
 * Vertices are shared only inside a surface and across gentle bends (src/mesh/mesh.c), so
 * corners keep one value per side. Fails when the view has no leaves. */
rad_status rad_solution_vertex_radiosity(const rad_solution_view *view, rad_context *ctx,
                                     int with_ambient, rad_rgb *out);

#endif
