/* solution_view.c - the solution view (solution_view.h): its first implementation, the uniform
 * mesh, where each element is a leaf with one radiosity, and what every view gets on top of its
 * operations (display radiosity, radiosity at the leaf vertices). */
#include "system/solution_view.h"

#include <string.h>

/* ------------------------------------------------------------------------------------------- */
/* The uniform mesh: the system's own arrays                                                   */

static const rad_system *uniform_system(const rad_solution_view *view) { return view->state; }

static const rad_mesh *uniform_leaves(const rad_solution_view *view) {
    return uniform_system(view)->mesh;
}

/* The elements never change once the system is built. */
static uint64_t uniform_generation(const rad_solution_view *view) {
    (void)view;
    return 1;
}

static void uniform_radiosity(const rad_solution_view *view, size_t leaf, double u, double v,
                              double out[3]) {
    (void)u;
    (void)v;
    memcpy(out, uniform_system(view)->radiosity[leaf], sizeof(rad_rgb));
}

static int uniform_unshot(const rad_solution_view *view, size_t leaf, double out[3]) {
    memcpy(out, uniform_system(view)->unshot[leaf], sizeof(rad_rgb));
    return 1;
}

/* What the element emits itself: without the light of the lights' pre-pass (light_emission,
 * docs/lights.md), which the renderer samples from the lights, not from the element. */
static void uniform_emission(const rad_solution_view *view, size_t leaf, double out[3]) {
    const rad_system *s = uniform_system(view);
    for (int c = 0; c < 3; ++c) out[c] = rad_system_own_emission(s, leaf, c);
}

static void uniform_reflectance(const rad_solution_view *view, size_t leaf, double out[3]) {
    memcpy(out, uniform_system(view)->reflectance[leaf], sizeof(rad_rgb));
}

static void uniform_ambient(const rad_solution_view *view, double out[3]) {
    memcpy(out, uniform_system(view)->ambient, sizeof(rad_rgb));
}

static void uniform_store(rad_solution_view *view, size_t leaf, const double radiosity[3],
                          const double unshot[3]) {
    rad_system *s = view->state;
    memcpy(s->radiosity[leaf], radiosity, sizeof(rad_rgb));
    memcpy(s->unshot[leaf], unshot, sizeof(rad_rgb));
}

const rad_solution_view_ops rad_uniform_view_ops = {
    "uniform mesh",      uniform_leaves,   uniform_generation, uniform_radiosity,
    uniform_unshot,      uniform_emission, uniform_reflectance, uniform_ambient,
    uniform_store,       NULL,               NULL,                0,
};

/* ------------------------------------------------------------------------------------------- */
/* The system's view                                                                           */

const rad_solution_view *rad_system_view(const rad_system *system) { return &system->view; }

rad_solution_view *rad_system_view_mutable(rad_system *system) { return &system->view; }

size_t rad_system_leaf_count(const rad_system *system, size_t *polygons) {
    const rad_mesh *mesh = system ? rad_solution_leaves(&system->view) : NULL;
    size_t drawn = mesh ? mesh->element_count : 0;
    if (polygons) *polygons = drawn;
    if (!mesh) return 0;
    return system->view.ops->leaf_count ? system->view.ops->leaf_count(&system->view) : drawn;
}

void rad_system_set_view(rad_system *system, const rad_solution_view_ops *ops, void *state) {
    if (system->view.ops && system->view.ops->destroy) system->view.ops->destroy(system->view.state);
    system->view.ops = ops;
    system->view.state = state;
}

/* ------------------------------------------------------------------------------------------- */
/* On top of any view                                                                          */

void rad_solution_display_radiosity(const rad_solution_view *view, size_t leaf, double u, double v,
                                int with_ambient, double out[3]) {
    double b[3], rho[3] = {0, 0, 0}, ambient[3] = {0, 0, 0};
    view->ops->radiosity(view, leaf, u, v, b);
    if (with_ambient) {
        view->ops->reflectance(view, leaf, rho);
        view->ops->ambient(view, ambient);
    }
    for (int c = 0; c < 3; ++c) out[c] = b[c] + (with_ambient ? rho[c] * ambient[c] : 0);
}

rad_status rad_solution_vertex_radiosity(const rad_solution_view *view, rad_context *ctx,
                                     int with_ambient, rad_rgb *out) {
    const rad_mesh *mesh = rad_solution_leaves(view);
    if (!mesh) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "a patch system has no vertices");
    double *weight = rad_alloc_zero(ctx, mesh->vertex_count, sizeof *weight);
    if (!weight) return RAD_ERROR_NO_MEMORY;
    memset(out, 0, mesh->vertex_count * sizeof *out);
    for (size_t e = 0; e < mesh->element_count; ++e) {
        double b[3];
        int corners = rad_mesh_corner_count(mesh, e);
        double centre = rad_solution_leaf_centre(mesh, e);
        rad_solution_display_radiosity(view, e, centre, centre, with_ambient, b);
        for (int k = 0; k < corners; ++k) {
            uint32_t v = mesh->element_vertices[e][k];
            weight[v] += mesh->element_area[e];
            for (int c = 0; c < 3; ++c) out[v][c] += mesh->element_area[e] * b[c];
        }
    }
    for (size_t v = 0; v < mesh->vertex_count; ++v)
        if (weight[v] > 0)
            for (int c = 0; c < 3; ++c) out[v][c] /= weight[v];
    rad_free(ctx, weight);
    return RAD_OK;
}
