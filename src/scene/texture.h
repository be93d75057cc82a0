/* texture.h - colour textures on surfaces (docs/rendering.md, "Textures").
 *
 * A texture multiplies its material's reflectance (the colour factor): OBJ map_Kd, glTF
 * baseColorTexture, the diffuse map of 3DS, FBX and Collada. Texels are kept as the file has
 * them, 8-bit sRGB, three per texel, top row first, and turned into linear reflectance when
 * read. Texture coordinates follow assimp's convention (v up: v = 0 is the image's bottom row)
 * and repeat outside [0, 1).
 *
 * Where each consumer reads a texture:
 *   - the solve: each element's reflectance is the texture's area-weighted mean over the
 *     element times the factor (rad_texture_element_mean), so the solution bleeds its colour;
 *   - the renderer and the path tracer: the reflectance at the point (rad_scene_albedo_at), the
 *     light-map split: radiosity carries irradiance, the image shows albedo x irradiance. */
#ifndef RAD_SCENE_TEXTURE_H
#define RAD_SCENE_TEXTURE_H

#include "core/context.h"
#include "core/vec3.h"

#include <stdint.h>

struct rad_scene;

typedef struct rad_texture {
    rad_context *ctx;
    int references;
    char *name;             /* the file, or "FILE: embedded image N" */
    uint32_t width, height;
    uint8_t *texels;        /* sRGB, 3 bytes per texel, rows from the top */
} rad_texture;

/* Decodes an image (PNG, JPEG, BMP, TGA, GIF, PSD, PNM: what stb_image reads) from memory. The
 * decoded texels must fit the context's memory budget. On failure the context's message says
 * why (not an image, truncated, over the budget) without naming the texture. */
rad_status rad_texture_decode(rad_context *ctx, const char *name, const void *bytes, size_t size,
                              rad_texture **out);
/* The same from a file. */
rad_status rad_texture_read(rad_context *ctx, const char *path, rad_texture **out);
/* A texture of given texels (8-bit sRGB, 3 per texel, copied). */
rad_status rad_texture_from_texels(rad_context *ctx, const char *name, uint32_t width,
                                   uint32_t height, const uint8_t *texels, rad_texture **out);
void rad_texture_retain(rad_texture *texture);
void rad_texture_release(rad_texture *texture);

/* Linear reflectance at (u, v), bilinearly filtered, repeating. */
void rad_texture_lookup(const rad_texture *texture, double u, double v, double rgb[3]);
/* Mean linear reflectance of the whole image. */
void rad_texture_mean(const rad_texture *texture, double rgb[3]);

/* Texture coordinates of point x on polygon `polygon` of the scene, interpolated from its
 * corners (fan triangles from corner 0, the one that holds x). 0 when the polygon has none. */
int rad_polygon_uv(const struct rad_scene *scene, uint32_t polygon, rad_vec3 x, double uv[2]);

/* The reflectance at point x of polygon `polygon`: the material's factor times its texture
 * there. Returns 1 when a texture was read, 0 when rho is the factor alone. */
int rad_scene_albedo_at(const struct rad_scene *scene, uint32_t polygon, rad_vec3 x,
                        double rho[3]);

/* The material at point x of `polygon`: `m` itself, or when it is textured (and `scene` is not
 * NULL) a copy in *textured whose reflectance is rad_scene_albedo_at's. What the path tracer,
 * the photons and photonmap's camera paths read at a hit. */
const struct rad_material *rad_scene_material_at(const struct rad_scene *scene,
                                                 const struct rad_material *m, uint32_t polygon,
                                                 rad_vec3 x, struct rad_material *textured);

/* The area-weighted mean reflectance over a convex piece (3 or 4 corners, counter-clockwise) of
 * polygon `polygon`: the factor times the texture's mean over the piece, from a grid of points
 * dense enough to see every texel it covers (at most 64 x 64). Returns 0 (rho = factor) when
 * the polygon is not textured. */
int rad_texture_element_mean(const struct rad_scene *scene, uint32_t polygon,
                             const rad_vec3 *corners, int count, double rho[3]);

#endif
