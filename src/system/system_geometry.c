/* system_geometry.c - a geometric scene becomes a system: mesh it, take each element's material
 * (emission as radiosity B = pi L), and set up the form-factor provider. */
#include "system/system.h"

#include "formfactor/geometric.h"
#include "scene/scene.h"
#include "scene/texture.h"

#include <string.h>

rad_status rad_system_from_geometry(rad_context *ctx, const rad_scene *scene,
                                    const rad_mesh_options *mesh_options,
                                    const rad_ff_options *ff_options, rad_system **out) {
    *out = NULL;
    for (size_t i = 0; i < scene->material_count; ++i) {
        const rad_material *m = &scene->materials[i];
        for (int c = 0; c < 3; ++c) {
            if (!isfinite(m->reflectance[c]) || m->reflectance[c] < 0 || m->reflectance[c] > 1)
                return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                                "%s: material '%s' has reflectance %g, outside [0, 1]",
                                scene->source, m->name, m->reflectance[c]);
            if (!isfinite(m->emission[c]))
                return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                                "%s: material '%s' has emission %g; it must be a finite number",
                                scene->source, m->name, m->emission[c]);
            if (m->emission[c] < 0)
                return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                                "%s: material '%s' has emission %g; it must be >= 0",
                                scene->source, m->name, m->emission[c]);
        }
    }
    /* One element per polygon for a solver that draws its own leaves (with lights or a sky too:
     * the hierarchy computes their light on its own nodes, src/solve/hierarchical.c), unless
     * light through mirrors and glass asks for the uniform mesh: the specular-first deposit is
     * resolved on its elements (specular_first.c) and the hierarchy reads it from them. */
    int polygons_only = mesh_options->polygons_only && !rad_scene_wants_specular_first(scene);
    rad_mesh *mesh = NULL;
    rad_status status = polygons_only ? rad_system_polygon_mesh(ctx, scene, &mesh)
                                      : rad_mesh_create(ctx, scene, mesh_options, &mesh);
    if (status) return status;
    rad_system *s = NULL;
    status = rad_system_alloc(ctx, mesh->element_count, mesh->patch_count, scene->surface_count, &s);
    if (status) {
        rad_mesh_destroy(mesh);
        return status;
    }
    s->mesh = mesh;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        const rad_material *m = &scene->materials[scene->surfaces[mesh->element_surface[e]].material];
        s->area[e] = mesh->element_area[e];
        s->element_patch[e] = mesh->element_patch[e];
        s->element_surface[e] = mesh->element_surface[e];
        for (int c = 0; c < 3; ++c) {
            s->reflectance[e][c] = m->reflectance[c];
            s->emission[e][c] = RAD_PI * m->emission[c];
        }
        /* A textured element reflects the texture's mean over it times the factor. */
        if (m->texture) {
            rad_vec3 corners[4];
            int count = rad_mesh_corner_count(mesh, e);
            for (int k = 0; k < count; ++k) corners[k] = mesh->vertices[mesh->element_vertices[e][k]];
            rad_texture_element_mean(scene, mesh->element_polygon[e], corners, count, s->reflectance[e]);
        }
    }
    memcpy(s->patch_first, mesh->patch_first, (mesh->patch_count + 1) * sizeof *s->patch_first);
    for (size_t i = 0; i < scene->surface_count && !status; ++i)
        if (!(s->surface_name[i] = rad_strdup(ctx, scene->surfaces[i].name))) status = RAD_ERROR_NO_MEMORY;
    rad_system_finish_areas(s);
    if (!status) status = rad_system_check_finite(s, scene->source);
    /* A solver that draws its own leaves computes its own form factors. */
    if (!status && !polygons_only)
        status = rad_ff_create(ctx, scene, mesh, ff_options, &s->ff);
    if (!status) status = rad_scene_copy_geometry(ctx, scene, &s->geometry);
    if (!status && (scene->light_count || scene->sky.kind != RAD_SKY_OFF)) {
        status = rad_system_add_light_emission(s, scene);
    }
    if (!status) status = rad_system_add_specular_emission(s, scene);
    if (status) {
        rad_system_destroy(s);
        return status;
    }
    if (!rad_scene_is_lit(scene))
        rad_warn(ctx, "%s: nothing emits light; the result will be black", scene->source);
    rad_system_reset(s);
    *out = s;
    return RAD_OK;
}
