/* scene.h - what was loaded: a patch system with given form factors, or geometry (named
 * surfaces made of convex polygons, materials, an optional camera). */
#ifndef RAD_SCENE_SCENE_H
#define RAD_SCENE_SCENE_H

#include "core/context.h"
#include "core/vec3.h"
#include "light/lights.h"

#include <stdint.h>

/* How a material scatters light beyond the diffuse part (the ray-traced second pass). */
typedef enum rad_material_kind {
    RAD_MATERIAL_DIFFUSE = 0,
    RAD_MATERIAL_MIRROR,  /* perfect or glossy specular reflection */
    RAD_MATERIAL_GLASS    /* smooth dielectric: Fresnel reflection and refraction */
} rad_material_kind;

typedef struct rad_material {
    char *name;
    double reflectance[3]; /* diffuse albedo, in [0, 1] */
    double emission[3];    /* emitted radiance L (W / m^2 / sr); radiosity B = pi L */
    rad_material_kind kind;
    double specular[3];    /* mirror / glass tint */
    double roughness;      /* 0: perfect mirror */
    double ior;            /* glass index of refraction */
    /* A colour texture that multiplies `reflectance` (scene/texture.h), or NULL; the scene
     * holds a reference (textures below). */
    const struct rad_texture *texture;
    int two_sided; /* both faces receive and reflect (glTF doubleSided): two_sided.c */
} rad_material;

/* A named input object: results are reported per surface. */
typedef struct rad_surface_def {
    char *name;
    uint32_t material;
} rad_surface_def;

/* A convex polygon, counter-clockwise seen from its front (the lit side). */
typedef struct rad_polygon {
    uint32_t first; /* index into scene->polygon_vertices */
    uint32_t count; /* 3 or more */
    uint32_t surface;
} rad_polygon;

typedef struct rad_camera {
    rad_vec3 eye, look, up;
    double fov_degrees; /* vertical */
} rad_camera;

typedef struct rad_ffm_patch {
    char *name;
    double area;
    double reflectance[3];
    double emission[3]; /* radiosity units (B), as the .ffm file gives it */
} rad_ffm_patch;

/* Paths of files, each once (as they were opened: relative to the working directory). */
typedef struct rad_file_list {
    char **paths;
    size_t count, capacity;
} rad_file_list;

/* Adds a copy of path unless it is there already. */
rad_status rad_file_list_add(rad_context *ctx, rad_file_list *list, const char *path);
void rad_file_list_free(rad_context *ctx, rad_file_list *list);

struct rad_scene {
    rad_context *ctx;
    int geometric;
    char *source; /* file path or built-in name */
    rad_file_list files; /* every file read for the scene (rad_scene_file_count) */

    /* A patch system: patches and a dense row-major form-factor matrix. */
    size_t patch_count;
    rad_ffm_patch *patches;
    double *form_factors;

    /* Geometry. */
    size_t vertex_count, vertex_capacity;
    rad_vec3 *vertices;
    size_t polygon_vertex_count, polygon_vertex_capacity;
    uint32_t *polygon_vertices;
    size_t polygon_count, polygon_capacity;
    rad_polygon *polygons;
    size_t surface_count, surface_capacity;
    rad_surface_def *surfaces;
    size_t material_count, material_capacity;
    rad_material *materials;
    int has_camera;
    rad_camera camera;

    /* Textures (scene/texture.h): the scene holds one reference to each; materials point at
     * them. Texture coordinates per polygon corner, parallel to polygon_vertices: corners past
     * polygon_uv_count, or NaN, have none. */
    size_t texture_count, texture_capacity;
    struct rad_texture **textures;
    size_t polygon_uv_count, polygon_uv_capacity;
    float (*polygon_uvs)[2];

    /* No camera in the file: `camera` is the automatic one (camera.c, rad_scene_auto_camera). */
    int camera_automatic;
    /* Sources that are not surfaces (light/lights.h, scene_lights.c): point, spot and
     * directional lights from the file or the caller (the sun), and the sky. */
    size_t light_count, light_capacity;
    rad_light *lights;
    rad_sky sky;

    /* The specular-first pass of the solution (system/specular_first.c): 0 when the scene has
     * mirror or glass materials, 1 always, -1 never; its photon count (0: the default). */
    int specular_first;
    uint64_t specular_photons;

    /* The Embree scene of these polygons (scene/rays.h), made by the first rad_rays_create on
     * the scene's context and handed out, shared, to every later one (the automatic camera,
     * the contacts, the form factors, the hierarchy, the renderers: one build of a 10^6
     * triangle scene instead of three or four); dropped when the geometry changes
     * (rad_scene_geometry_changed), released with the scene. */
    struct rad_rays *rays;
};

/* Drops the scene's shared rays (scene/rays.h): call it after changing its vertices or
 * polygons in place; rad_scene_add_vertex and rad_scene_add_polygon call it. */
void rad_scene_geometry_changed(rad_scene *scene);

/* Nonzero when some material has a perfect mirror or glass lobe (caustics are possible). */
int rad_scene_has_specular(const rad_scene *scene);

/* Nonzero when the specular-first pass runs for this scene: asked for (1), or by default (0)
 * when it has a mirror or glass (rad_scene_has_specular); never when turned off (-1). */
int rad_scene_wants_specular_first(const rad_scene *scene);

/* Nonzero when something lights the scene: a polygon whose material emits, a point, spot or
 * directional light, or a sky. The one answer to "is the image black?" that the path tracer,
 * photon mapping and the solvers' systems share. */
int rad_scene_is_lit(const rad_scene *scene);

/* An empty scene of either kind. */
rad_status rad_scene_new(rad_context *ctx, int geometric, const char *source, rad_scene **out);

/* A copy of a geometric scene's geometry and materials (names included), for what needs the
 * input polygons after the scene itself is gone (the system keeps one; scene_copy.c). */
rad_status rad_scene_copy_geometry(rad_context *ctx, const rad_scene *scene, rad_scene **out);

/* Builders for geometric scenes. Indices of the new item go to *index (may be NULL). */
rad_status rad_scene_add_material(rad_scene *scene, const rad_material *material, uint32_t *index);
rad_status rad_scene_add_surface(rad_scene *scene, const char *name, uint32_t material,
                                 uint32_t *index);
rad_status rad_scene_add_vertex(rad_scene *scene, rad_vec3 position, uint32_t *index);
/* A convex polygon from vertex indices, counter-clockwise seen from the front. */
rad_status rad_scene_add_polygon(rad_scene *scene, uint32_t surface, const uint32_t *vertices,
                                 uint32_t count);
/* A convex polygon from positions (adds the vertices). */
rad_status rad_scene_add_polygon_points(rad_scene *scene, uint32_t surface,
                                        const rad_vec3 *points, uint32_t count);

/* Keeps a reference to `texture` (scene/texture.h); its index to *index (may be NULL). */
rad_status rad_scene_add_texture(rad_scene *scene, struct rad_texture *texture, uint32_t *index);
/* Texture coordinates for the corners of the last polygon added (`count` pairs). */
rad_status rad_scene_set_last_uvs(rad_scene *scene, const float (*uv)[2], uint32_t count);

/* Surfaces of two-sided materials get a back: a surface "NAME (back)" of the same polygons
 * turned over, moved behind by a hair (2e-5 of the scene's diagonal, twice the rays' offset),
 * so both faces receive and reflect as two one-sided surfaces back to back (two_sided.c). */
rad_status rad_scene_add_back_faces(rad_scene *scene);
/* Appends a copy of `light` (its name copied; its IES profile, if any, now owned by the scene). */
rad_status rad_scene_append_light(rad_scene *scene, const rad_light *light);

/* Warns, naming up to four of their surfaces, about each material whose largest diffuse
 * reflectance (times its texture's mean) is 0.95 to 1: it converges slowly and brightens the
 * scene (docs/formats.md, "Materials"). `texture_lost[i]` (may be NULL) marks material i as
 * white because its texture could not be used. Every reader calls it once its scene is whole. */
void rad_scene_warn_bright_materials(rad_context *ctx, const rad_scene *scene, const char *path,
                                     const uint8_t *texture_lost, size_t lost_count);

/* Geometry of a polygon: unit normal (Newell's method), area, centroid. */
rad_vec3 rad_polygon_normal(const rad_scene *scene, const rad_polygon *polygon);
double rad_polygon_area(const rad_scene *scene, const rad_polygon *polygon);
rad_vec3 rad_polygon_vertex(const rad_scene *scene, const rad_polygon *polygon, uint32_t k);
/* Nonzero when the polygon's material emits (any channel above 0). */
int rad_polygon_emits(const rad_scene *scene, const rad_polygon *polygon);

/* Bounds of all vertices. */
void rad_scene_bounds(const rad_scene *scene, rad_vec3 *lo, rad_vec3 *hi);

/* Built-in geometric scenes (src/scene/builtin_*.c). */
rad_status rad_builtin_geometry(rad_context *ctx, const char *name, rad_scene **out);

/* Import through assimp in a child process (src/scene/import_child.c): a crash, a hang or a
 * memory overrun inside assimp becomes an error. */
rad_status rad_scene_import(rad_context *ctx, const char *path, rad_scene **out);
/* The same import in this process (src/scene/import.c); what the child runs. */
rad_status rad_scene_import_here(rad_context *ctx, const char *path, rad_scene **out);

#endif
