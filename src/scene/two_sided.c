/* two_sided.c - two-sided surfaces as two one-sided surfaces back to back (scene.h,
 * rad_scene_add_back_faces). Radiosity surfaces receive and reflect on their front only; a
 * material marked two-sided (glTF doubleSided) gets a second surface behind the first, turned
 * over, so light on either side is received, reflected and shown. */
#include "scene/scene.h"

#include <stdio.h>
#include <string.h>

/* How far behind the front the back lies, as a fraction of the scene's diagonal: twice the
 * offset rays start at (scene/rays.c, system/element_rays.c), so a ray that meets the front
 * meets it first, and one leaving it never meets its own back. */
#define BACK_OFFSET 2e-5

rad_status rad_scene_add_back_faces(rad_scene *scene) {
    if (!scene->geometric) return RAD_OK;
    size_t surfaces = scene->surface_count, polygons = scene->polygon_count, added = 0;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double offset = BACK_OFFSET * v3_length(v3_sub(hi, lo));
    for (size_t s = 0; s < surfaces; ++s) {
        if (!scene->materials[scene->surfaces[s].material].two_sided) continue;
        char name[1100];
        snprintf(name, sizeof name, "%s (back)", scene->surfaces[s].name);
        uint32_t back;
        rad_status status = rad_scene_add_surface(scene, name, scene->surfaces[s].material, &back);
        if (status) return status;
        for (size_t i = 0; i < polygons; ++i) {
            rad_polygon p = scene->polygons[i];
            if (p.surface != s) continue;
            rad_vec3 shift = v3_scale(rad_polygon_normal(scene, &p), -offset), points[64];
            float uv[64][2];
            int has_uv = scene->polygon_uvs && (size_t)p.first + p.count <= scene->polygon_uv_count;
            if (p.count > 64) continue; /* the importer makes at most 64 corners */
            for (uint32_t k = 0; k < p.count; ++k) {
                /* Reversed: counter-clockwise seen from behind. */
                uint32_t from = p.count - 1 - k;
                points[k] = v3_add(rad_polygon_vertex(scene, &p, from), shift);
                if (has_uv) memcpy(uv[k], scene->polygon_uvs[p.first + from], sizeof uv[k]);
            }
            status = rad_scene_add_polygon_points(scene, back, points, p.count);
            if (!status && has_uv) status = rad_scene_set_last_uvs(scene, (const float(*)[2])uv, p.count);
            if (status) return status;
            ++added;
        }
    }
    if (added)
        rad_info(scene->ctx, "%s: %zu polygons of two-sided materials got a back face (surfaces "
                 "'NAME (back)')", scene->source, added);
    return RAD_OK;
}
