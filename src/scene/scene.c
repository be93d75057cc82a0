/* scene.c - scene storage and builders shared by the .ffm parser, the built-in scenes and the
 * importer. */
#include "scene/scene.h"

#include "scene/rays.h"
#include "scene/texture.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

rad_status rad_scene_new(rad_context *ctx, int geometric, const char *source, rad_scene **out) {
    *out = NULL;
    rad_scene *scene = rad_alloc_zero(ctx, 1, sizeof *scene);
    if (!scene) return RAD_ERROR_NO_MEMORY;
    scene->ctx = ctx;
    scene->geometric = geometric;
    scene->source = rad_strdup(ctx, source ? source : "");
    if (!scene->source) {
        rad_free(ctx, scene);
        return RAD_ERROR_NO_MEMORY;
    }
    *out = scene;
    return RAD_OK;
}

void rad_scene_destroy(rad_scene *scene) {
    if (!scene) return;
    rad_context *ctx = scene->ctx;
    for (size_t i = 0; i < scene->patch_count; ++i) rad_free(ctx, scene->patches[i].name);
    rad_free(ctx, scene->patches);
    rad_free(ctx, scene->form_factors);
    for (size_t i = 0; i < scene->surface_count; ++i) rad_free(ctx, scene->surfaces[i].name);
    for (size_t i = 0; i < scene->material_count; ++i) rad_free(ctx, scene->materials[i].name);
    rad_free(ctx, scene->surfaces);
    rad_free(ctx, scene->materials);
    rad_free(ctx, scene->vertices);
    rad_free(ctx, scene->polygon_vertices);
    rad_free(ctx, scene->polygons);
    rad_lights_free(ctx, scene->lights, scene->light_count);
    rad_free(ctx, scene->source);
    rad_file_list_free(ctx, &scene->files);
    for (size_t i = 0; i < scene->texture_count; ++i) rad_texture_release(scene->textures[i]);
    rad_free(ctx, scene->textures);
    rad_free(ctx, scene->polygon_uvs);
    rad_rays_destroy(scene->rays);
    rad_free(ctx, scene);
}

void rad_scene_geometry_changed(rad_scene *scene) {
    rad_rays_destroy(scene->rays);
    scene->rays = NULL;
}

int rad_scene_is_geometric(const rad_scene *scene) { return scene && scene->geometric; }

/* Makes room for one more item in a growing array. */
static rad_status grow(rad_context *ctx, void **items, size_t *capacity, size_t count,
                       size_t item_size) {
    if (count < *capacity) return RAD_OK;
    size_t wanted = *capacity ? *capacity * 2 : 16;
    void *grown = rad_realloc(ctx, *items, wanted, item_size);
    if (!grown) return RAD_ERROR_NO_MEMORY;
    *items = grown;
    *capacity = wanted;
    return RAD_OK;
}

#define GROW(scene, array, count, capacity)                                                     \
    grow((scene)->ctx, (void **)&(scene)->array, &(scene)->capacity, (scene)->count,             \
         sizeof *(scene)->array)

rad_status rad_scene_add_material(rad_scene *scene, const rad_material *material, uint32_t *index) {
    if (GROW(scene, materials, material_count, material_capacity)) return RAD_ERROR_NO_MEMORY;
    rad_material copy = *material;
    copy.name = rad_strdup(scene->ctx, material->name ? material->name : "");
    if (!copy.name) return RAD_ERROR_NO_MEMORY;
    if (index) *index = (uint32_t)scene->material_count;
    scene->materials[scene->material_count++] = copy;
    return RAD_OK;
}

rad_status rad_scene_add_surface(rad_scene *scene, const char *name, uint32_t material,
                                 uint32_t *index) {
    if (material >= scene->material_count)
        return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT, "surface %s: no material %u",
                        name, material);
    if (GROW(scene, surfaces, surface_count, surface_capacity)) return RAD_ERROR_NO_MEMORY;
    char *copy = rad_strdup(scene->ctx, name);
    if (!copy) return RAD_ERROR_NO_MEMORY;
    if (index) *index = (uint32_t)scene->surface_count;
    scene->surfaces[scene->surface_count++] = (rad_surface_def){copy, material};
    return RAD_OK;
}

rad_status rad_scene_add_vertex(rad_scene *scene, rad_vec3 position, uint32_t *index) {
    if (GROW(scene, vertices, vertex_count, vertex_capacity)) return RAD_ERROR_NO_MEMORY;
    if (scene->rays) rad_scene_geometry_changed(scene);
    if (index) *index = (uint32_t)scene->vertex_count;
    scene->vertices[scene->vertex_count++] = position;
    return RAD_OK;
}

rad_status rad_scene_add_polygon(rad_scene *scene, uint32_t surface, const uint32_t *vertices,
                                 uint32_t count) {
    if (count < 3 || surface >= scene->surface_count)
        return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT, "bad polygon");
    for (uint32_t k = 0; k < count; ++k) {
        if (vertices[k] >= scene->vertex_count)
            return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT, "polygon vertex out of range");
        if (GROW(scene, polygon_vertices, polygon_vertex_count, polygon_vertex_capacity))
            return RAD_ERROR_NO_MEMORY;
        scene->polygon_vertices[scene->polygon_vertex_count++] = vertices[k];
    }
    if (GROW(scene, polygons, polygon_count, polygon_capacity)) return RAD_ERROR_NO_MEMORY;
    if (scene->rays) rad_scene_geometry_changed(scene);
    scene->polygons[scene->polygon_count++] =
        (rad_polygon){(uint32_t)(scene->polygon_vertex_count - count), count, surface};
    return RAD_OK;
}

rad_status rad_scene_add_polygon_points(rad_scene *scene, uint32_t surface,
                                        const rad_vec3 *points, uint32_t count) {
    uint32_t indices[64];
    if (count > 64) return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT, "polygon too large");
    for (uint32_t k = 0; k < count; ++k) {
        rad_status status = rad_scene_add_vertex(scene, points[k], &indices[k]);
        if (status) return status;
    }
    return rad_scene_add_polygon(scene, surface, indices, count);
}

rad_vec3 rad_polygon_vertex(const rad_scene *scene, const rad_polygon *polygon, uint32_t k) {
    return scene->vertices[scene->polygon_vertices[polygon->first + k]];
}

/* Newell's method: robust for slightly non-planar polygons. The length is twice the area. */
static rad_vec3 newell(const rad_scene *scene, const rad_polygon *polygon) {
    rad_vec3 n = v3(0, 0, 0);
    for (uint32_t k = 0; k < polygon->count; ++k) {
        rad_vec3 a = rad_polygon_vertex(scene, polygon, k);
        rad_vec3 b = rad_polygon_vertex(scene, polygon, (k + 1) % polygon->count);
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

rad_vec3 rad_polygon_normal(const rad_scene *scene, const rad_polygon *polygon) {
    return v3_normalize(newell(scene, polygon));
}

double rad_polygon_area(const rad_scene *scene, const rad_polygon *polygon) {
    return 0.5 * v3_length(newell(scene, polygon));
}

void rad_scene_bounds(const rad_scene *scene, rad_vec3 *lo, rad_vec3 *hi) {
    *lo = v3(INFINITY, INFINITY, INFINITY);
    *hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < scene->vertex_count; ++i) {
        rad_vec3 p = scene->vertices[i];
        *lo = v3(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
        *hi = v3(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
    }
}

rad_status rad_scene_add_texture(rad_scene *scene, struct rad_texture *texture, uint32_t *index) {
    if (GROW(scene, textures, texture_count, texture_capacity)) return RAD_ERROR_NO_MEMORY;
    rad_texture_retain(texture);
    if (index) *index = (uint32_t)scene->texture_count;
    scene->textures[scene->texture_count++] = texture;
    return RAD_OK;
}

rad_status rad_scene_set_last_uvs(rad_scene *scene, const float (*uv)[2], uint32_t count) {
    if (scene->polygon_count == 0 || scene->polygons[scene->polygon_count - 1].count != count)
        return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT, "texture coordinates: bad count");
    size_t first = scene->polygons[scene->polygon_count - 1].first, needed = first + count;
    if (needed > scene->polygon_uv_capacity) {
        size_t wanted = scene->polygon_uv_capacity ? scene->polygon_uv_capacity : 64;
        while (wanted < needed) wanted *= 2;
        float(*grown)[2] = rad_realloc(scene->ctx, scene->polygon_uvs, wanted, sizeof *grown);
        if (!grown) return RAD_ERROR_NO_MEMORY;
        scene->polygon_uvs = grown;
        scene->polygon_uv_capacity = wanted;
    }
    /* Corners of earlier polygons without coordinates: none (NaN). */
    for (size_t i = scene->polygon_uv_count; i < first; ++i)
        scene->polygon_uvs[i][0] = scene->polygon_uvs[i][1] = NAN;
    memcpy(scene->polygon_uvs + first, uv, count * sizeof *uv);
    if (needed > scene->polygon_uv_count) scene->polygon_uv_count = needed;
    return RAD_OK;
}

rad_status rad_file_list_add(rad_context *ctx, rad_file_list *list, const char *path) {
    for (size_t i = 0; i < list->count; ++i)
        if (strcmp(list->paths[i], path) == 0) return RAD_OK;
    rad_status status = grow(ctx, (void **)&list->paths, &list->capacity, list->count,
                             sizeof *list->paths);
    if (status) return status;
    size_t length = strlen(path) + 1;
    char *copy = rad_alloc(ctx, length, 1);
    if (!copy) return RAD_ERROR_NO_MEMORY;
    memcpy(copy, path, length);
    list->paths[list->count++] = copy;
    return RAD_OK;
}

void rad_file_list_free(rad_context *ctx, rad_file_list *list) {
    for (size_t i = 0; i < list->count; ++i) rad_free(ctx, list->paths[i]);
    rad_free(ctx, list->paths);
    list->paths = NULL;
    list->count = list->capacity = 0;
}

size_t rad_scene_file_count(const rad_scene *scene) { return scene ? scene->files.count : 0; }

const char *rad_scene_file(const rad_scene *scene, size_t index) {
    return scene && index < scene->files.count ? scene->files.paths[index] : NULL;
}

/* Reflectance this close to 1 barely loses energy: iterative solvers converge slowly and the
 * room comes out too bright. Textured materials' factors are usually white (1), so a texture
 * that could not be read leaves them so. */
#define BRIGHT_REFLECTANCE 0.95
/* A warning names at most this many surfaces. */
#define NAMED_SURFACES 4

void rad_scene_warn_bright_materials(rad_context *ctx, const rad_scene *scene, const char *path,
                                     const uint8_t *texture_lost, size_t lost_count) {
    for (size_t i = 0; i < scene->material_count; ++i) {
        const rad_material *m = &scene->materials[i];
        double rho[3] = {m->reflectance[0], m->reflectance[1], m->reflectance[2]};
        if (m->texture) {
            double mean[3];
            rad_texture_mean(m->texture, mean);
            for (int c = 0; c < 3; ++c) rho[c] *= mean[c];
        }
        double largest = fmax(rho[0], fmax(rho[1], rho[2]));
        if (!(largest >= BRIGHT_REFLECTANCE) || largest > 1) continue; /* > 1 is refused later */
        char names[512] = "";
        size_t used = 0, count = 0;
        for (size_t s = 0; s < scene->surface_count; ++s) {
            if (scene->surfaces[s].material != i) continue;
            if (count++ < NAMED_SURFACES && used < sizeof names)
                used += (size_t)snprintf(names + used, sizeof names - used, "%s'%s'",
                                         count > 1 ? ", " : "", scene->surfaces[s].name);
        }
        if (count == 0) continue;
        if (used >= sizeof names) used = sizeof names - 1;
        if (count > NAMED_SURFACES)
            snprintf(names + used, sizeof names - used, " and %zu more", count - NAMED_SURFACES);
        int lost = texture_lost && i < lost_count && texture_lost[i];
        rad_warn(ctx, "%s: material '%s' reflects %.3g of the light%s (surfaces %s); "
                 "reflectances near 1 converge slowly and brighten the scene", path, m->name,
                 largest, lost ? ", white because its texture could not be used" : "", names);
    }
}
