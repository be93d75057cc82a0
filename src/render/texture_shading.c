/* texture_shading.c - textures in the rendered image: the light-map split (docs/rendering.md,
 * "Textures").
 *
 * The solve gives each element of a textured surface the texture's mean reflectance rho_e over
 * it (system_geometry.c), so its radiosity is B_e = E_e + rho_e H_e, with H_e the irradiance
 * (as radiosity, pi times radiance) it receives. The image shows the texture's detail by
 * taking the irradiance from the solution and the reflectance from the texture at the pixel:
 *   - final gather: rho at the pixel replaces rho_e (rad_renderer_albedo);
 *   - smooth or flat reconstruction: L = E / pi + rho(x) h(x), E / pi as reconstruct.c draws it
 *     (a specular-first deposit smoothed at the vertices), where h is the irradiance
 *     (B - E) / (pi rho_e) of the elements, averaged at the vertices by area and interpolated as
 *     the radiosity is (reconstruct.c), so neighbouring elements of different mean
 *     reflectance (a checker's edge) meet without a step.
 * Gather rays and the bake see the element means: the solution itself. */
#include "render/render.h"

#include "scene/texture.h"

#include <string.h>

int rad_renderer_albedo(const rad_renderer *r, uint32_t element, rad_vec3 x, float rho[3]) {
    const rad_material *m = rad_renderer_material(r, element);
    double at[3];
    if (!m->texture || !r->system->geometry ||
        !rad_scene_albedo_at(r->system->geometry, r->mesh->element_polygon[element], x, at)) {
        memcpy(rho, r->element_reflectance[element], 3 * sizeof *rho);
        return 0;
    }
    for (int c = 0; c < 3; ++c) rho[c] = (float)at[c];
    return 1;
}

/* The element's irradiance as radiance, (B - E) / (pi rho_e), per channel. */
static void element_irradiance(const rad_renderer *r, size_t e, double out[3]) {
    for (int c = 0; c < 3; ++c) {
        double rho = r->element_reflectance[e][c];
        double reflected = fmax(0.0, (double)r->element_radiance[e][c] - r->element_emission[e][c]);
        out[c] = rho > 0 ? reflected / rho : 0;
    }
}

rad_status rad_texture_shading_prepare(rad_renderer *r) {
    const rad_mesh *mesh = r->mesh;
    int textured = 0;
    for (size_t s = 0; s < r->surface_count && !textured; ++s)
        textured = r->surface_material[s].texture != NULL;
    if (!textured) return RAD_OK;
    if (!r->vertex_irradiance) {
        r->vertex_irradiance = rad_alloc(r->ctx, mesh->vertex_count + 1, sizeof *r->vertex_irradiance);
        if (!r->vertex_irradiance) return RAD_ERROR_NO_MEMORY;
    }
    double *weight = rad_alloc_zero(r->ctx, mesh->vertex_count + 1, sizeof *weight);
    double(*sum)[3] = rad_alloc_zero(r->ctx, mesh->vertex_count + 1, sizeof *sum);
    if (!weight || !sum) {
        rad_free(r->ctx, weight);
        rad_free(r->ctx, sum);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t e = 0; e < mesh->element_count; ++e) {
        if (!rad_renderer_material(r, (uint32_t)e)->texture) continue;
        double h[3];
        element_irradiance(r, e, h);
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            uint32_t v = mesh->element_vertices[e][k];
            weight[v] += mesh->element_area[e];
            for (int c = 0; c < 3; ++c) sum[v][c] += mesh->element_area[e] * h[c];
        }
    }
    for (size_t v = 0; v < mesh->vertex_count; ++v)
        for (int c = 0; c < 3; ++c)
            r->vertex_irradiance[v][c] = weight[v] > 0 ? (float)(sum[v][c] / weight[v]) : 0;
    rad_free(r->ctx, weight);
    rad_free(r->ctx, sum);
    return RAD_OK;
}

int rad_texture_shading_radiance(const rad_renderer *r, const rad_element_hit *hit, rad_vec3 x,
                                 double out[3]) {
    uint32_t e = hit->element;
    float rho[3];
    if (!r->vertex_irradiance || !rad_renderer_albedo(r, e, x, rho)) return 0;
    double h[3] = {0, 0, 0};
    if (r->settings.shading == RAD_SHADING_FLAT) {
        element_irradiance(r, e, h);
    } else {
        double weight[4];
        int corners = rad_element_weights(r->mesh, e, hit->u, hit->v, weight);
        for (int k = 0; k < corners; ++k)
            for (int c = 0; c < 3; ++c)
                h[c] += weight[k] * r->vertex_irradiance[r->mesh->element_vertices[e][k]][c];
    }
    /* The emission as reconstruct.c draws it: a specular-first deposit smoothed (smooth
     * shading), not flat per element. */
    double emission[3];
    rad_reconstruct_emission(r, e, hit->u, hit->v, emission);
    for (int c = 0; c < 3; ++c) out[c] = emission[c] + rho[c] * h[c];
    return 1;
}
