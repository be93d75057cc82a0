/* scene_copy.c - a copy of a geometric scene's geometry and materials (scene.h), kept by the
 * system so that the hierarchical solver can build its quadtrees and rays from the input
 * polygons (and light its nodes from the lights and the sky) after the caller has destroyed the
 * scene. */
#include "scene/rays.h"
#include "scene/scene.h"
#include "scene/texture.h"

#include <string.h>

/* A copy of `count` items of `size` bytes, or NULL (also for count 0, when *ok stays set). */
static void *copy_array(rad_context *ctx, const void *items, size_t count, size_t size, int *ok) {
    if (!count) return NULL;
    void *copy = rad_alloc(ctx, count, size);
    if (!copy) {
        *ok = 0;
        return NULL;
    }
    memcpy(copy, items, count * size);
    return copy;
}

rad_status rad_scene_copy_geometry(rad_context *ctx, const rad_scene *scene, rad_scene **out) {
    *out = NULL;
    rad_scene *copy = NULL;
    rad_status status = rad_scene_new(ctx, 1, scene->source, &copy);
    if (status) return status;
    int ok = 1;
    copy->vertices = copy_array(ctx, scene->vertices, scene->vertex_count, sizeof *scene->vertices, &ok);
    copy->vertex_count = copy->vertex_capacity = ok ? scene->vertex_count : 0;
    copy->polygon_vertices = copy_array(ctx, scene->polygon_vertices, scene->polygon_vertex_count,
                                        sizeof *scene->polygon_vertices, &ok);
    copy->polygon_vertex_count = copy->polygon_vertex_capacity = ok ? scene->polygon_vertex_count : 0;
    copy->polygons = copy_array(ctx, scene->polygons, scene->polygon_count, sizeof *scene->polygons, &ok);
    copy->polygon_count = copy->polygon_capacity = ok ? scene->polygon_count : 0;
    for (size_t i = 0; i < scene->material_count && ok; ++i)
        ok = rad_scene_add_material(copy, &scene->materials[i], NULL) == RAD_OK;
    for (size_t i = 0; i < scene->surface_count && ok; ++i)
        ok = rad_scene_add_surface(copy, scene->surfaces[i].name, scene->surfaces[i].material,
                                   NULL) == RAD_OK;
    /* Textures are shared (one more reference each), texture coordinates copied. */
    for (size_t i = 0; i < scene->texture_count && ok; ++i)
        ok = rad_scene_add_texture(copy, scene->textures[i], NULL) == RAD_OK;
    copy->polygon_uvs = copy_array(ctx, scene->polygon_uvs, scene->polygon_uv_count,
                                   sizeof *scene->polygon_uvs, &ok);
    copy->polygon_uv_count = copy->polygon_uv_capacity = ok ? scene->polygon_uv_count : 0;
    /* The lights and the sky, which the hierarchy evaluates on its own nodes. */
    if (ok && scene->light_count) {
        ok = rad_lights_copy(ctx, scene->lights, scene->light_count, &copy->lights) == RAD_OK;
        copy->light_count = copy->light_capacity = ok ? scene->light_count : 0;
    }
    copy->sky = scene->sky;
    copy->has_camera = scene->has_camera;
    copy->camera = scene->camera;
    copy->camera_automatic = scene->camera_automatic;
    /* The same polygons: the same rays, shared. */
    if (scene->rays && scene->rays->ctx == ctx) copy->rays = rad_rays_share(scene->rays);
    if (!ok) {
        rad_scene_destroy(copy);
        return RAD_ERROR_NO_MEMORY;
    }
    *out = copy;
    return RAD_OK;
}
