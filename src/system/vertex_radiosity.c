/* vertex_radiosity.c - radiosity at mesh vertices, for smooth shading and baking: each vertex
 * takes the area-weighted mean of the elements around it. Vertices are shared only inside a
 * surface and across gentle bends (src/mesh/mesh.c), so corners keep one value per side. */
#include "system/vertex_radiosity.h"

#include "mesh/mesh.h"

#include <string.h>

void rad_system_display_radiosity(const rad_system *s, size_t e, int with_ambient, double out[3]) {
    for (int c = 0; c < 3; ++c)
        out[c] = s->radiosity[e][c] + (with_ambient ? s->reflectance[e][c] * s->ambient[c] : 0);
}

rad_status rad_system_vertex_radiosity(const rad_system *s, int with_ambient, rad_rgb *out) {
    const rad_mesh *mesh = s->mesh;
    if (!mesh) return rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT, "a patch system has no vertices");
    double *weight = rad_alloc_zero(s->ctx, mesh->vertex_count, sizeof *weight);
    if (!weight) return RAD_ERROR_NO_MEMORY;
    memset(out, 0, mesh->vertex_count * sizeof *out);
    for (size_t e = 0; e < mesh->element_count; ++e) {
        double b[3];
        rad_system_display_radiosity(s, e, with_ambient, b);
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            uint32_t v = mesh->element_vertices[e][k];
            weight[v] += s->area[e];
            for (int c = 0; c < 3; ++c) out[v][c] += s->area[e] * b[c];
        }
    }
    for (size_t v = 0; v < mesh->vertex_count; ++v)
        if (weight[v] > 0)
            for (int c = 0; c < 3; ++c) out[v][c] /= weight[v];
    rad_free(s->ctx, weight);
    return RAD_OK;
}
