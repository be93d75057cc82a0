/* scene_info.c - what a scene holds, for listing (`radiosity scenes --info`): counts, bounds,
 * materials with their textures, surfaces with their polygons and areas, lights and sky. */
#include "scene/scene.h"
#include "scene/texture.h"

#include <string.h>

void rad_scene_get_info(const rad_scene *scene, rad_scene_info *out) {
    memset(out, 0, sizeof *out);
    if (!scene) return;
    out->geometric = scene->geometric;
    out->patch_count = scene->patch_count;
    if (!scene->geometric) return;
    out->surface_count = scene->surface_count;
    out->material_count = scene->material_count;
    out->texture_count = scene->texture_count;
    out->vertex_count = scene->vertex_count;
    out->polygon_count = scene->polygon_count;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        out->triangle_count += scene->polygons[i].count - 2;
    for (size_t i = 0; i < scene->surface_count; ++i) {
        const double *e = scene->materials[scene->surfaces[i].material].emission;
        if (e[0] > 0 || e[1] > 0 || e[2] > 0) out->emitting_surface_count++;
    }
    out->has_camera = scene->has_camera;
    out->camera_automatic = scene->camera_automatic;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    out->bounds_min[0] = lo.x, out->bounds_min[1] = lo.y, out->bounds_min[2] = lo.z;
    out->bounds_max[0] = hi.x, out->bounds_max[1] = hi.y, out->bounds_max[2] = hi.z;
}

rad_status rad_scene_get_material(const rad_scene *scene, size_t index, rad_material_info *out) {
    memset(out, 0, sizeof *out);
    if (!scene || !scene->geometric || index >= scene->material_count)
        return RAD_ERROR_INVALID_ARGUMENT;
    const rad_material *m = &scene->materials[index];
    static const char *const kinds[] = {"diffuse", "mirror", "glass"};
    out->name = m->name;
    out->kind = (unsigned)m->kind < 3 ? kinds[m->kind] : "diffuse";
    memcpy(out->reflectance, m->reflectance, sizeof out->reflectance);
    memcpy(out->emission, m->emission, sizeof out->emission);
    if (m->texture) {
        out->texture = m->texture->name;
        out->texture_width = m->texture->width;
        out->texture_height = m->texture->height;
    }
    for (size_t i = 0; i < scene->surface_count; ++i)
        if (scene->surfaces[i].material == index) out->surface_count++;
    return RAD_OK;
}

rad_status rad_scene_get_surface(const rad_scene *scene, size_t index, rad_surface_listing *out) {
    memset(out, 0, sizeof *out);
    if (!scene || !scene->geometric || index >= scene->surface_count)
        return RAD_ERROR_INVALID_ARGUMENT;
    out->name = scene->surfaces[index].name;
    out->material = scene->surfaces[index].material;
    int textured = scene->materials[out->material].texture != NULL, with_uv = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        if (p->surface != index) continue;
        out->polygon_count++;
        out->triangle_count += p->count - 2;
        out->area += rad_polygon_area(scene, p);
        double uv[2];
        if (textured && !with_uv) with_uv = rad_polygon_uv(scene, (uint32_t)i, rad_polygon_vertex(scene, p, 0), uv);
    }
    out->textured = textured && with_uv;
    return RAD_OK;
}

rad_status rad_scene_get_light(const rad_scene *scene, size_t index, rad_light_info *out) {
    memset(out, 0, sizeof *out);
    if (!scene || index >= scene->light_count) return RAD_ERROR_INVALID_ARGUMENT;
    const rad_light *l = &scene->lights[index];
    out->name = l->name;
    out->type = l->kind == RAD_LIGHT_SPOT          ? RAD_LIGHT_TYPE_SPOT
                : l->kind == RAD_LIGHT_DIRECTIONAL ? RAD_LIGHT_TYPE_DIRECTIONAL
                                                   : RAD_LIGHT_TYPE_POINT;
    const rad_vec3 p = l->position, d = l->direction;
    out->position[0] = p.x, out->position[1] = p.y, out->position[2] = p.z;
    out->direction[0] = d.x, out->direction[1] = d.y, out->direction[2] = d.z;
    memcpy(out->intensity, l->intensity, sizeof out->intensity);
    out->inner_degrees = l->inner_angle * 180 / RAD_PI;
    out->outer_degrees = l->outer_angle * 180 / RAD_PI;
    out->ies = l->ies ? l->ies->file : NULL;
    return RAD_OK;
}

void rad_scene_get_sky(const rad_scene *scene, rad_sky_desc *out) {
    memset(out, 0, sizeof *out);
    if (!scene || scene->sky.kind == RAD_SKY_OFF) return;
    out->model = scene->sky.kind == RAD_SKY_CIE_OVERCAST ? RAD_SKY_MODEL_CIE_OVERCAST
                                                         : RAD_SKY_MODEL_UNIFORM;
    memcpy(out->radiance, scene->sky.radiance, sizeof out->radiance);
    out->up[0] = scene->sky.up.x, out->up[1] = scene->sky.up.y, out->up[2] = scene->sky.up.z;
    out->samples = scene->sky.samples;
}
