/* builtin_mirror.c - cornell-mirror: the Cornell box with the tall block a mirror and a glass
 * sphere on the floor, for the ray-traced second pass and the path tracer.
 *
 * The box has no front wall: a mirror facing the camera would show the empty space behind it.
 * So the tall block turns 23 degrees further about its vertical axis; its two visible faces then
 * reflect the green wall with the short block and the red wall.
 *
 * Both new materials reflect nothing diffusely (reflectance 0): the radiosity solution sees them
 * as black occluders, and only the ray-traced passes show what they reflect and refract
 * (docs/pathtracing.md). The sphere stands on the floor in front of the mirror, clear of both
 * blocks (short block footprint x 82..290, z 65..272; tall block x 265..472, z 247..456). */
#include "scene/scene.h"

#include <string.h>

#define SPHERE_RADIUS 80.0
#define SPHERE_SLICES 48 /* around the vertical axis */
#define SPHERE_STACKS 24 /* pole to pole */

static const rad_vec3 sphere_center = {400.0, SPHERE_RADIUS + 0.5, 140.0};

/* Extra turn of the tall block about its vertical axis, in degrees (x towards z positive). */
#define MIRROR_TURN_DEGREES (-23.0)

/* A UV sphere of convex faces (planar trapezoids between rings, triangles at the poles),
 * counter-clockwise seen from outside. */
static rad_status add_sphere(rad_scene *scene, uint32_t surface, rad_vec3 center, double radius) {
    rad_vec3 ring[SPHERE_STACKS + 1][SPHERE_SLICES];
    for (int i = 0; i <= SPHERE_STACKS; ++i) {
        double theta = RAD_PI * i / SPHERE_STACKS; /* from the top */
        for (int j = 0; j < SPHERE_SLICES; ++j) {
            double phi = 2 * RAD_PI * j / SPHERE_SLICES;
            ring[i][j] = v3_add(center, v3(radius * sin(theta) * cos(phi), radius * cos(theta),
                                           radius * sin(theta) * sin(phi)));
        }
    }
    rad_status status = RAD_OK;
    for (int i = 0; i < SPHERE_STACKS && !status; ++i)
        for (int j = 0; j < SPHERE_SLICES && !status; ++j) {
            int k = (j + 1) % SPHERE_SLICES;
            /* Counter-clockwise seen from outside: along the upper ring towards larger phi,
             * down the meridian, back along the lower ring, up. */
            rad_vec3 a = ring[i][j], b = ring[i][k], c = ring[i + 1][k], d = ring[i + 1][j];
            if (i == 0) status = rad_scene_add_polygon_points(scene, surface, (rad_vec3[]){a, c, d}, 3);
            else if (i == SPHERE_STACKS - 1)
                status = rad_scene_add_polygon_points(scene, surface, (rad_vec3[]){a, b, c}, 3);
            else status = rad_scene_add_polygon_points(scene, surface, (rad_vec3[]){a, b, c, d}, 4);
        }
    return status;
}

/* Turns a surface about the vertical axis through the centre of its vertices. */
static rad_status turn_surface(rad_scene *scene, uint32_t surface, double angle) {
    uint8_t *mine = rad_alloc_zero(scene->ctx, scene->vertex_count, 1);
    if (!mine) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        if (p->surface != surface) continue;
        for (uint32_t k = 0; k < p->count; ++k) mine[scene->polygon_vertices[p->first + k]] = 1;
    }
    rad_vec3 center = v3(0, 0, 0);
    size_t count = 0;
    for (size_t v = 0; v < scene->vertex_count; ++v)
        if (mine[v]) {
            center = v3_add(center, scene->vertices[v]);
            ++count;
        }
    if (count) center = v3_scale(center, 1.0 / (double)count);
    double c = cos(angle), s = sin(angle);
    for (size_t v = 0; v < scene->vertex_count; ++v) {
        if (!mine[v]) continue;
        rad_vec3 d = v3_sub(scene->vertices[v], center);
        scene->vertices[v] = v3(center.x + c * d.x - s * d.z, scene->vertices[v].y,
                                center.z + s * d.x + c * d.z);
    }
    rad_free(scene->ctx, mine);
    rad_scene_geometry_changed(scene);
    return RAD_OK;
}

rad_status rad_builtin_cornell_mirror(rad_scene *scene) {
    rad_material mirror = {0};
    mirror.name = "mirror";
    mirror.kind = RAD_MATERIAL_MIRROR;
    mirror.specular[0] = mirror.specular[1] = mirror.specular[2] = 0.9;
    mirror.ior = 1.5;
    rad_material glass = {0};
    glass.name = "glass";
    glass.kind = RAD_MATERIAL_GLASS;
    glass.specular[0] = glass.specular[1] = glass.specular[2] = 1;
    glass.ior = 1.5;
    uint32_t mirror_index, glass_index, sphere;
    rad_status status = rad_scene_add_material(scene, &mirror, &mirror_index);
    if (!status) status = rad_scene_add_material(scene, &glass, &glass_index);
    if (status) return status;
    long tall = -1;
    for (size_t i = 0; i < scene->surface_count; ++i)
        if (strcmp(scene->surfaces[i].name, "tall-block") == 0) tall = (long)i;
    if (tall < 0)
        return rad_fail(scene->ctx, RAD_ERROR_INTERNAL, "cornell-mirror: no tall block to silver");
    scene->surfaces[tall].material = mirror_index;
    status = turn_surface(scene, (uint32_t)tall, MIRROR_TURN_DEGREES * RAD_PI / 180);
    if (status) return status;
    status = rad_scene_add_surface(scene, "glass-sphere", glass_index, &sphere);
    if (!status) status = add_sphere(scene, sphere, sphere_center, SPHERE_RADIUS);
    return status;
}
