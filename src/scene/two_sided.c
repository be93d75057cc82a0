/* two_sided.c - two-sided surfaces as two one-sided surfaces back to back (scene.h,
 * rad_scene_add_back_faces; rad_scene_set_two_sided for --two-sided). Radiosity surfaces receive and reflect on their front only; a
 * material marked two-sided (glTF doubleSided) gets a second surface behind the first, turned
 * over, so light on either side is received, reflected and shown. */
#include "scene/scene.h"

#include <stdio.h>
#include <string.h>

/* How far behind the front the back lies, as a fraction of the scene's diagonal: twice the
 * offset rays start at (scene/rays.c, system/element_rays.c), so a ray that meets the front
 * meets it first, and one leaving it never meets its own back. */
#define BACK_OFFSET 2e-5

/* Backs for the surfaces whose material has `backed[material]` set: first one back surface
 * each, then one pass over the polygons (each turned over onto its surface's back). */
static rad_status add_backs(rad_scene *scene, const unsigned char *backed) {
    rad_context *ctx = scene->ctx;
    size_t surfaces = scene->surface_count, polygons = scene->polygon_count, added = 0;
    uint32_t most = 0;
    for (size_t i = 0; i < polygons; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        if (backed[scene->surfaces[p->surface].material] && p->count > most) most = p->count;
    }
    if (!most) return RAD_OK;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double offset = BACK_OFFSET * v3_length(v3_sub(hi, lo));
    uint32_t *back = rad_alloc(ctx, surfaces, sizeof *back);
    uint32_t *corners = rad_alloc(ctx, most, sizeof *corners);
    float(*uv)[2] = rad_alloc(ctx, most, sizeof *uv);
    rad_status status = back && corners && uv ? RAD_OK : RAD_ERROR_NO_MEMORY;
    for (size_t s = 0; s < surfaces && !status; ++s) {
        back[s] = UINT32_MAX;
        if (!backed[scene->surfaces[s].material]) continue;
        char name[1100];
        snprintf(name, sizeof name, "%s (back)", scene->surfaces[s].name);
        uint32_t material = scene->surfaces[s].material;
        status = rad_scene_add_surface(scene, name, material, &back[s]);
    }
    for (size_t i = 0; i < polygons && !status; ++i) {
        rad_polygon p = scene->polygons[i];
        if (back[p.surface] == UINT32_MAX) continue;
        rad_vec3 shift = v3_scale(rad_polygon_normal(scene, &p), -offset);
        int has_uv = scene->polygon_uvs && (size_t)p.first + p.count <= scene->polygon_uv_count;
        for (uint32_t k = 0; k < p.count && !status; ++k) {
            /* Reversed: counter-clockwise seen from behind. */
            uint32_t from = p.count - 1 - k;
            status = rad_scene_add_vertex(scene, v3_add(rad_polygon_vertex(scene, &p, from), shift),
                                          &corners[k]);
            if (has_uv) memcpy(uv[k], scene->polygon_uvs[p.first + from], sizeof uv[k]);
        }
        if (!status) status = rad_scene_add_polygon(scene, back[p.surface], corners, p.count);
        if (!status && has_uv) status = rad_scene_set_last_uvs(scene, (const float(*)[2])uv, p.count);
        ++added;
    }
    rad_free(ctx, back);
    rad_free(ctx, corners);
    rad_free(ctx, uv);
    if (!status && added)
        rad_info(ctx, "%s: %zu polygons of two-sided materials got a back face (surfaces "
                 "'NAME (back)')", scene->source, added);
    return status;
}

rad_status rad_scene_add_back_faces(rad_scene *scene) {
    if (!scene->geometric || !scene->material_count) return RAD_OK;
    unsigned char *backed = rad_alloc_zero(scene->ctx, scene->material_count, 1);
    if (!backed) return RAD_ERROR_NO_MEMORY;
    for (size_t m = 0; m < scene->material_count; ++m) backed[m] = scene->materials[m].two_sided != 0;
    rad_status status = add_backs(scene, backed);
    rad_free(scene->ctx, backed);
    return status;
}

/* --two-sided: every material not yet two-sided becomes so, except emitters (a lamp's panel
 * would emit twice its power) and glass (which has two sides of its own). */
rad_status rad_scene_set_two_sided(rad_scene *scene) {
    if (!scene) return RAD_ERROR_INVALID_ARGUMENT;
    if (!scene->geometric)
        return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: two-sided surfaces need "
                        "geometry, and a patch system has none", scene->source);
    if (!scene->material_count) return RAD_OK;
    unsigned char *backed = rad_alloc_zero(scene->ctx, scene->material_count, 1);
    if (!backed) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < scene->material_count; ++i) {
        rad_material *m = &scene->materials[i];
        int emits = m->emission[0] > 0 || m->emission[1] > 0 || m->emission[2] > 0;
        if (m->two_sided || emits || m->kind == RAD_MATERIAL_GLASS) continue;
        m->two_sided = 1;
        backed[i] = 1;
    }
    rad_status status = add_backs(scene, backed);
    rad_free(scene->ctx, backed);
    return status;
}
