/* builtin_geometry.c - the built-in geometric scenes.
 *
 * cornell: the Cornell box as published by the Cornell University Program of Computer Graphics
 * (geometry in mm, reflectances as given in the issue), camera at (278, 273, -800) looking along
 * +z. Walls face into the box, blocks face out; every polygon is counter-clockwise seen from its
 * front. */
#include "scene/scene.h"

#include <string.h>

typedef struct quad_def {
    const char *surface;
    double p[4][3];
} quad_def;

static const quad_def cornell_quads[] = {
    {"floor", {{552.8, 0, 0}, {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}}},
    {"ceiling", {{556, 548.8, 0}, {556, 548.8, 559.2}, {0, 548.8, 559.2}, {0, 548.8, 0}}},
    {"back-wall", {{549.6, 0, 559.2}, {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}},
    {"green-wall", {{0, 0, 559.2}, {0, 0, 0}, {0, 548.8, 0}, {0, 548.8, 559.2}}},
    {"red-wall", {{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}},
    {"light", {{343, 548.7, 227}, {343, 548.7, 332}, {213, 548.7, 332}, {213, 548.7, 227}}},
    {"short-block", {{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}}},
    {"short-block", {{290, 0, 114}, {290, 165, 114}, {240, 165, 272}, {240, 0, 272}}},
    {"short-block", {{130, 0, 65}, {130, 165, 65}, {290, 165, 114}, {290, 0, 114}}},
    {"short-block", {{82, 0, 225}, {82, 165, 225}, {130, 165, 65}, {130, 0, 65}}},
    {"short-block", {{240, 0, 272}, {240, 165, 272}, {82, 165, 225}, {82, 0, 225}}},
    {"tall-block", {{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}}},
    {"tall-block", {{423, 0, 247}, {423, 330, 247}, {472, 330, 406}, {472, 0, 406}}},
    {"tall-block", {{472, 0, 406}, {472, 330, 406}, {314, 330, 456}, {314, 0, 456}}},
    {"tall-block", {{314, 0, 456}, {314, 330, 456}, {265, 330, 296}, {265, 0, 296}}},
    {"tall-block", {{265, 0, 296}, {265, 330, 296}, {423, 330, 247}, {423, 0, 247}}},
};

static rad_material diffuse(const char *name, double r, double g, double b) {
    rad_material m = {0};
    m.name = (char *)name;
    m.reflectance[0] = r;
    m.reflectance[1] = g;
    m.reflectance[2] = b;
    m.ior = 1.5;
    return m;
}

/* Finds or adds the surface `name` with material `material`. */
static rad_status surface_named(rad_scene *scene, const char *name, uint32_t material,
                                uint32_t *index) {
    for (size_t i = 0; i < scene->surface_count; ++i)
        if (strcmp(scene->surfaces[i].name, name) == 0) {
            *index = (uint32_t)i;
            return RAD_OK;
        }
    return rad_scene_add_surface(scene, name, material, index);
}

static rad_status add_quads(rad_scene *scene, const quad_def *quads, size_t count,
                            uint32_t (*material_of)(const char *surface)) {
    for (size_t i = 0; i < count; ++i) {
        uint32_t surface;
        rad_status status = surface_named(scene, quads[i].surface, material_of(quads[i].surface),
                                          &surface);
        if (status) return status;
        rad_vec3 points[4];
        for (int k = 0; k < 4; ++k)
            points[k] = v3(quads[i].p[k][0], quads[i].p[k][1], quads[i].p[k][2]);
        status = rad_scene_add_polygon_points(scene, surface, points, 4);
        if (status) return status;
    }
    return RAD_OK;
}

enum { CORNELL_WHITE, CORNELL_RED, CORNELL_GREEN, CORNELL_LIGHT };

static uint32_t cornell_material(const char *surface) {
    if (strcmp(surface, "red-wall") == 0) return CORNELL_RED;
    if (strcmp(surface, "green-wall") == 0) return CORNELL_GREEN;
    if (strcmp(surface, "light") == 0) return CORNELL_LIGHT;
    return CORNELL_WHITE;
}

static rad_status build_cornell(rad_scene *scene) {
    rad_material light = diffuse("light", 0.78, 0.78, 0.78);
    light.emission[0] = 17;
    light.emission[1] = 12;
    light.emission[2] = 4;
    rad_material materials[] = {
        diffuse("white", 0.725, 0.71, 0.68),
        diffuse("red", 0.63, 0.065, 0.05),
        diffuse("green", 0.14, 0.45, 0.091),
        light,
    };
    for (size_t i = 0; i < sizeof materials / sizeof materials[0]; ++i) {
        rad_status status = rad_scene_add_material(scene, &materials[i], NULL);
        if (status) return status;
    }
    scene->has_camera = 1;
    scene->camera = (rad_camera){v3(278, 273, -800), v3(278, 273, 0), v3(0, 1, 0), 39.3077};
    return add_quads(scene, cornell_quads, sizeof cornell_quads / sizeof cornell_quads[0],
                     cornell_material);
}

static uint32_t first_material(const char *surface) {
    return strcmp(surface, "emitter") == 0 || strcmp(surface, "top") == 0 ? 1 : 0;
}

/* Two opposed unit squares one unit apart; the lower one emits radiosity 1 (radiance 1/pi). */
static rad_status build_two_squares(rad_scene *scene) {
    static const quad_def quads[] = {
        {"emitter", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
        {"receiver", {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}},
    };
    rad_material grey = diffuse("grey", 0.5, 0.5, 0.5);
    rad_material glowing = grey;
    glowing.name = "emitting grey";
    for (int c = 0; c < 3; ++c) glowing.emission[c] = 1.0 / RAD_PI;
    rad_status status = rad_scene_add_material(scene, &grey, NULL);
    if (!status) status = rad_scene_add_material(scene, &glowing, NULL);
    if (!status) status = add_quads(scene, quads, 2, first_material);
    /* From the side, half a unit above the emitter: both fronts in view. */
    scene->has_camera = 1;
    scene->camera = (rad_camera){v3(0.5, -1.2, 0.5), v3(0.5, 0.5, 0.5), v3(0, 0, 1), 60};
    return status;
}

/* A closed unit cube seen from inside; the top emits radiosity 1 (radiance 1/pi). */
static rad_status build_unit_cube(rad_scene *scene) {
    static const quad_def quads[] = {
        {"bottom", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
        {"top", {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}},
        {"front", {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}},
        {"back", {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}},
        {"left", {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}},
        {"right", {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}},
    };
    rad_material grey = diffuse("grey", 0.5, 0.5, 0.5);
    rad_material glowing = grey;
    glowing.name = "emitting grey";
    for (int c = 0; c < 3; ++c) glowing.emission[c] = 1.0 / RAD_PI;
    rad_status status = rad_scene_add_material(scene, &grey, NULL);
    if (!status) status = rad_scene_add_material(scene, &glowing, NULL);
    if (!status) status = add_quads(scene, quads, 6, first_material);
    /* Inside, just under the emitting top, looking down at the bottom. */
    scene->has_camera = 1;
    scene->camera = (rad_camera){v3(0.5, 0.5, 0.98), v3(0.5, 0.5, 0), v3(0, 1, 0), 90};
    return status;
}

rad_status rad_builtin_cornell_mirror(rad_scene *scene); /* src/scene/builtin_mirror.c */

rad_status rad_builtin_geometry(rad_context *ctx, const char *name, rad_scene **out) {
    *out = NULL;
    rad_scene *scene;
    rad_status status = rad_scene_new(ctx, 1, name, &scene);
    if (status) return status;
    if (strcmp(name, "cornell") == 0) status = build_cornell(scene);
    else if (strcmp(name, "cornell-mirror") == 0) {
        status = build_cornell(scene);
        if (!status) status = rad_builtin_cornell_mirror(scene);
    } else if (strcmp(name, "two-squares") == 0) status = build_two_squares(scene);
    else if (strcmp(name, "unit-cube") == 0) status = build_unit_cube(scene);
    else status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "no built-in scene '%s'", name);
    if (status) {
        rad_scene_destroy(scene);
        return status;
    }
    *out = scene;
    return RAD_OK;
}
