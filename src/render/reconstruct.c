/* reconstruct.c - the radiosity solution as radiance at any point of the mesh.
 *
 * The solution is constant per element. Shown as it is ("flat") the element grid is visible;
 * Cohen et al. 1986 ("An efficient radiosity approach for realistic image synthesis") average
 * the radiosity of the elements around each vertex, weighted by area, and interpolate it across
 * each element ("smooth", Gouraud shading): bilinearly on quads, barycentrically on triangles.
 * Vertices are split at creases and never shared between surfaces (mesh/mesh.h), so a corner
 * between a wall and the floor keeps one value per side instead of blending the two.
 *
 * Radiance = B / pi for a Lambertian surface; on an emitter B = E + reflected, so B / pi is the
 * emitted radiance plus the reflected one. */
#include "render/render.h"

#include "solve/vertex_radiosity.h"

rad_status rad_reconstruct_prepare(rad_renderer *r) {
    const rad_system *s = r->system;
    const rad_mesh *mesh = r->mesh;
    rad_context *ctx = r->ctx;
    rad_rgb *vertex = rad_alloc(ctx, mesh->vertex_count ? mesh->vertex_count : 1, sizeof *vertex);
    if (!vertex) return RAD_ERROR_NO_MEMORY;
    rad_status status = rad_system_vertex_radiosity(s, r->settings.ambient, vertex);
    if (status) {
        rad_free(ctx, vertex);
        return status;
    }
    const float to_radiance = (float)(1 / RAD_PI);
    for (size_t v = 0; v < mesh->vertex_count; ++v)
        for (int c = 0; c < 3; ++c) r->vertex_radiance[v][c] = (float)vertex[v][c] * to_radiance;
    rad_free(ctx, vertex);
    for (size_t e = 0; e < mesh->element_count; ++e) {
        double b[3];
        rad_system_display_radiosity(s, e, r->settings.ambient, b);
        for (int c = 0; c < 3; ++c) {
            r->element_radiance[e][c] = (float)b[c] * to_radiance;
            r->element_emission[e][c] = (float)s->emission[e][c] * to_radiance;
            r->element_reflectance[e][c] = (float)s->reflectance[e][c];
        }
    }
    return RAD_OK;
}

void rad_reconstruct_radiance(const rad_renderer *r, uint32_t element, double u, double v,
                              double out[3]) {
    if (r->settings.shading == RAD_SHADING_FLAT) {
        for (int c = 0; c < 3; ++c) out[c] = r->element_radiance[element][c];
        return;
    }
    double weight[4];
    int corners = rad_element_weights(r->mesh, element, u, v, weight);
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < corners; ++k) {
        const float *radiance = r->vertex_radiance[r->mesh->element_vertices[element][k]];
        for (int c = 0; c < 3; ++c) out[c] += weight[k] * radiance[c];
    }
}
