/* scene_lights.c - the scene's lights and sky (scene.h, light/lights.h): the public setters,
 * with the photometric conversions of docs/units.md, and IES profiles by light name. */
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

rad_status rad_scene_append_light(rad_scene *scene, const rad_light *light) {
    rad_context *ctx = scene->ctx;
    if (scene->light_count == scene->light_capacity) {
        size_t wanted = scene->light_capacity ? 2 * scene->light_capacity : 4;
        rad_light *grown = rad_realloc(ctx, scene->lights, wanted, sizeof *grown);
        if (!grown) return RAD_ERROR_NO_MEMORY;
        scene->lights = grown;
        scene->light_capacity = wanted;
    }
    rad_light copy = *light;
    copy.name = rad_strdup(ctx, light->name ? light->name : "");
    if (!copy.name) return RAD_ERROR_NO_MEMORY;
    scene->lights[scene->light_count++] = copy;
    return RAD_OK;
}

static int finite3(const double v[3]) {
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

rad_status rad_scene_add_light(rad_scene *scene, const rad_light_desc *d) {
    if (!scene || !d) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = scene->ctx;
    const char *name = d->name ? d->name : "light";
    if (!scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: light '%s': a patch system has no "
                        "geometry to light", scene->source, name);
    if (d->type > RAD_LIGHT_TYPE_DIRECTIONAL || d->units > RAD_LIGHT_LUMENS)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': unknown type or units", name);
    double white[3] = {1, 1, 1};
    const double *color = d->color[0] || d->color[1] || d->color[2] ? d->color : white;
    if (!finite3(color) || color[0] < 0 || color[1] < 0 || color[2] < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': colour (%g, %g, %g) must be "
                        "finite and >= 0", name, color[0], color[1], color[2]);
    if (!(isfinite(d->strength) && d->strength >= 0))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': strength %g must be a finite "
                        "number >= 0", name, d->strength);
    rad_vec3 direction = v3(d->direction[0], d->direction[1], d->direction[2]);
    if (d->type != RAD_LIGHT_TYPE_POINT &&
        !(finite3(d->direction) && v3_length(direction) > 0 && isfinite(v3_length(direction))))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': direction (%g, %g, %g) must "
                        "be finite and not zero", name, direction.x, direction.y, direction.z);
    if (d->type != RAD_LIGHT_TYPE_DIRECTIONAL && !finite3(d->position))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': position must be finite",
                        name);
    rad_light light;
    memset(&light, 0, sizeof light);
    light.name = (char *)name;
    light.kind = (rad_light_kind)d->type;
    light.position = v3(d->position[0], d->position[1], d->position[2]);
    /* A point light's axis orients an IES profile: down (-Y) unless given. */
    light.direction = v3_length(direction) > 0 && finite3(d->direction) ? v3_normalize(direction)
                                                                         : v3(0, -1, 0);
    double scale = d->strength;
    if (d->type == RAD_LIGHT_TYPE_SPOT) {
        if (!(d->outer_degrees > 0 && d->outer_degrees <= 90 && d->inner_degrees >= 0 &&
              d->inner_degrees <= d->outer_degrees))
            return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': spot cone inner %g, "
                            "outer %g degrees: need 0 <= inner <= outer, 0 < outer <= 90", name,
                            d->inner_degrees, d->outer_degrees);
        light.inner_angle = d->inner_degrees * RAD_PI / 180;
        light.outer_angle = d->outer_degrees * RAD_PI / 180;
    }
    /* Photometric to radiometric (docs/units.md): candela and lux over 179 lm/W; lumens spread
     * over the solid angle the light fills (the sphere; a spot's cone with its falloff counted
     * half, as pbrt-v4 does). */
    if (d->units != RAD_LIGHT_WATTS) scale /= RAD_LUMINOUS_EFFICACY;
    if (d->units == RAD_LIGHT_LUMENS && d->type == RAD_LIGHT_TYPE_POINT) scale /= 4 * RAD_PI;
    if (d->units == RAD_LIGHT_LUMENS && d->type == RAD_LIGHT_TYPE_SPOT) {
        double cos_inner = cos(light.inner_angle), cos_outer = cos(light.outer_angle);
        scale /= 2 * RAD_PI * ((1 - cos_inner) + (cos_inner - cos_outer) / 2);
    }
    for (int c = 0; c < 3; ++c) light.intensity[c] = color[c] * scale;
    if (!finite3(light.intensity))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "light '%s': strength %g overflows",
                        name, d->strength);
    return rad_scene_append_light(scene, &light);
}

size_t rad_scene_light_count(const rad_scene *scene) { return scene ? scene->light_count : 0; }

rad_status rad_scene_set_light_ies(rad_scene *scene, const char *light_name, const char *path) {
    if (!scene || !path) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = scene->ctx;
    int every = !light_name || strcmp(light_name, "*") == 0;
    size_t matched = 0;
    for (size_t i = 0; i < scene->light_count; ++i) {
        const rad_light *l = &scene->lights[i];
        if (l->kind == RAD_LIGHT_DIRECTIONAL) continue;
        if (every || strcmp(l->name, light_name) == 0) ++matched;
    }
    if (!matched)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: no point or spot light named '%s' "
                        "for %s (the scene has %zu lights)", scene->source,
                        every ? "*" : light_name, path, scene->light_count);
    for (size_t i = 0; i < scene->light_count; ++i) {
        rad_light *l = &scene->lights[i];
        if (l->kind == RAD_LIGHT_DIRECTIONAL || !(every || strcmp(l->name, light_name) == 0))
            continue;
        rad_ies_profile *profile = NULL;
        rad_status status = rad_ies_load(ctx, path, &profile);
        if (!status) status = rad_file_list_add(ctx, &scene->files, path); /* a scene's file */
        if (status) {
            rad_ies_free(ctx, profile);
            return status;
        }
        snprintf(profile->file, sizeof profile->file, "%s", path);
        rad_ies_free(ctx, l->ies);
        l->ies = profile;
    }
    return RAD_OK;
}

rad_status rad_scene_set_sky(rad_scene *scene, const rad_sky_desc *d) {
    if (!scene || !d) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = scene->ctx;
    if (d->model == RAD_SKY_NONE) {
        memset(&scene->sky, 0, sizeof scene->sky);
        return RAD_OK;
    }
    if (!scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: a patch system has no openings for "
                        "a sky", scene->source);
    if (d->model > RAD_SKY_MODEL_CIE_OVERCAST)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "unknown sky model %d", (int)d->model);
    if (!finite3(d->radiance) || d->radiance[0] < 0 || d->radiance[1] < 0 || d->radiance[2] < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "sky radiance (%g, %g, %g) must be "
                        "finite and >= 0", d->radiance[0], d->radiance[1], d->radiance[2]);
    rad_vec3 up = v3(d->up[0], d->up[1], d->up[2]);
    if (!finite3(d->up)) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "sky up must be finite");
    if (!(v3_length(up) > 0)) up = v3(0, 1, 0);
    if (d->samples < 0 || d->samples > 1 << 20)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "sky samples %d: need 0..%d", d->samples,
                        1 << 20);
    scene->sky.kind = d->model == RAD_SKY_MODEL_UNIFORM ? RAD_SKY_UNIFORM : RAD_SKY_CIE_OVERCAST;
    memcpy(scene->sky.radiance, d->radiance, sizeof scene->sky.radiance);
    scene->sky.up = v3_normalize(up);
    scene->sky.samples = d->samples ? d->samples : 64;
    return RAD_OK;
}

rad_status rad_scene_set_specular_first(rad_scene *scene, int on, uint64_t photons) {
    if (!scene) return RAD_ERROR_INVALID_ARGUMENT;
    if (on < -1 || on > 1)
        return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "specular-first must be 1, 0 or -1 (when the scene has mirrors or glass), "
                        "not %d", on);
    if (photons > 1000000000u)
        return rad_fail(scene->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "specular-first photons %llu: need 1 .. 10^9", (unsigned long long)photons);
    scene->specular_first = on == 1 ? 1 : on == 0 ? -1 : 0;
    scene->specular_photons = photons;
    return RAD_OK;
}

int rad_scene_has_specular(const rad_scene *scene) {
    for (size_t i = 0; i < scene->material_count; ++i) {
        const rad_material *m = &scene->materials[i];
        if (m->kind == RAD_MATERIAL_GLASS ||
            (m->kind == RAD_MATERIAL_MIRROR && m->roughness <= 0 &&
             (m->specular[0] > 0 || m->specular[1] > 0 || m->specular[2] > 0)))
            return 1;
    }
    return 0;
}

int rad_scene_wants_specular_first(const rad_scene *scene) {
    return scene->specular_first > 0 ||
           (scene->specular_first == 0 && rad_scene_has_specular(scene));
}

int rad_scene_is_lit(const rad_scene *scene) {
    if (scene->light_count || scene->sky.kind != RAD_SKY_OFF) return 1;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        if (rad_polygon_emits(scene, &scene->polygons[i])) return 1;
    return 0;
}

int rad_polygon_emits(const rad_scene *scene, const rad_polygon *polygon) {
    const double *e = scene->materials[scene->surfaces[polygon->surface].material].emission;
    return e[0] > 0 || e[1] > 0 || e[2] > 0;
}
