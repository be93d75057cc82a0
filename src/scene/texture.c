/* texture.c - colour textures: decoding (stb_image), lookup, and the means the solve and the
 * renderer need (texture.h). */
#include "scene/texture.h"

#include "scene/scene.h"

#include <stb/stb_image.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Sides beyond this are refused before decoding (stb_image's own limit is 2^24). */
#define MAX_SIDE 65536
/* The element mean takes at most this many points per side of an element. */
#define MAX_GRID 64

/* sRGB 8-bit code to linear reflectance (IEC 61966-2-1). */
static float srgb_linear[256];
static int srgb_ready;

static void srgb_table(void) {
    if (srgb_ready) return;
    for (int i = 0; i < 256; ++i) {
        double c = i / 255.0;
        srgb_linear[i] = (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
    }
    srgb_ready = 1;
}

rad_status rad_texture_from_texels(rad_context *ctx, const char *name, uint32_t width,
                                   uint32_t height, const uint8_t *texels, rad_texture **out) {
    *out = NULL;
    if (width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "image of %u x %u texels", width, height);
    size_t bytes = (size_t)width * height * 3;
    rad_status status = rad_check_budget(ctx, (double)bytes, "the texture");
    if (status) return status;
    srgb_table();
    rad_texture *t = rad_alloc_zero(ctx, 1, sizeof *t);
    if (!t) return RAD_ERROR_NO_MEMORY;
    t->ctx = ctx;
    t->references = 1;
    t->width = width;
    t->height = height;
    t->name = rad_strdup(ctx, name);
    t->texels = rad_alloc(ctx, bytes, 1);
    if (!t->name || !t->texels) {
        rad_texture_release(t);
        return RAD_ERROR_NO_MEMORY;
    }
    memcpy(t->texels, texels, bytes);
    *out = t;
    return RAD_OK;
}

rad_status rad_texture_decode(rad_context *ctx, const char *name, const void *bytes, size_t size,
                              rad_texture **out) {
    *out = NULL;
    int width = 0, height = 0, channels = 0;
    if (size == 0 || size > INT32_MAX ||
        !stbi_info_from_memory(bytes, (int)size, &width, &height, &channels))
        return rad_fail(ctx, RAD_ERROR_PARSE, "not an image stb_image can read (%s)",
                        size == 0 ? "empty" : stbi_failure_reason() ? stbi_failure_reason() : "unknown");
    if (width <= 0 || height <= 0 || width > MAX_SIDE || height > MAX_SIDE)
        return rad_fail(ctx, RAD_ERROR_PARSE, "image of %d x %d texels", width, height);
    /* The decoder's copy and ours, before decoding. */
    rad_status status = rad_check_budget(ctx, 2.0 * width * height * 3, "the texture");
    if (status) return status;
    uint8_t *texels = stbi_load_from_memory(bytes, (int)size, &width, &height, &channels, 3);
    if (!texels)
        return rad_fail(ctx, RAD_ERROR_PARSE, "the image cannot be decoded (%s; truncated?)",
                        stbi_failure_reason() ? stbi_failure_reason() : "unknown");
    status = rad_texture_from_texels(ctx, name, (uint32_t)width, (uint32_t)height, texels, out);
    stbi_image_free(texels);
    return status;
}

rad_status rad_texture_read(rad_context *ctx, const char *path, rad_texture **out) {
    *out = NULL;
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s", strerror(errno));
    rad_status status = RAD_OK;
    long size = -1;
    if (fseek(file, 0, SEEK_END) == 0) size = ftell(file);
    if (size < 0 || fseek(file, 0, SEEK_SET) != 0)
        status = rad_fail(ctx, RAD_ERROR_IO, "cannot tell its size");
    /* A compressed image is smaller than its texels; a file over the budget is refused. */
    if (!status) status = rad_check_budget(ctx, (double)size, "the texture file");
    void *bytes = NULL;
    if (!status) {
        bytes = rad_alloc(ctx, size ? (size_t)size : 1, 1);
        if (!bytes) status = RAD_ERROR_NO_MEMORY;
        else if (fread(bytes, 1, (size_t)size, file) != (size_t)size)
            status = rad_fail(ctx, RAD_ERROR_IO, "read error");
    }
    fclose(file);
    if (!status) status = rad_texture_decode(ctx, path, bytes, (size_t)size, out);
    rad_free(ctx, bytes);
    return status;
}

void rad_texture_retain(rad_texture *texture) {
    if (texture) texture->references++;
}

void rad_texture_release(rad_texture *texture) {
    if (!texture || --texture->references > 0) return;
    rad_context *ctx = texture->ctx;
    rad_free(ctx, texture->name);
    rad_free(ctx, texture->texels);
    rad_free(ctx, texture);
}

static void texel(const rad_texture *t, uint32_t x, uint32_t y, double rgb[3]) {
    const uint8_t *p = t->texels + 3 * ((size_t)y * t->width + x);
    for (int c = 0; c < 3; ++c) rgb[c] = srgb_linear[p[c]];
}

void rad_texture_lookup(const rad_texture *t, double u, double v, double rgb[3]) {
    if (!isfinite(u) || !isfinite(v)) u = v = 0;
    /* Texel centres at half-integers; row 0 is the top (v = 1). */
    double fx = (u - floor(u)) * t->width - 0.5, fy = (1 - (v - floor(v))) * t->height - 0.5;
    double x0f = floor(fx), y0f = floor(fy), ax = fx - x0f, ay = fy - y0f;
    long x0 = (long)x0f, y0 = (long)y0f;
    uint32_t xa = (uint32_t)((x0 % (long)t->width + (long)t->width) % (long)t->width);
    uint32_t ya = (uint32_t)((y0 % (long)t->height + (long)t->height) % (long)t->height);
    uint32_t xb = (xa + 1) % t->width, yb = (ya + 1) % t->height;
    double c00[3], c10[3], c01[3], c11[3];
    texel(t, xa, ya, c00);
    texel(t, xb, ya, c10);
    texel(t, xa, yb, c01);
    texel(t, xb, yb, c11);
    for (int c = 0; c < 3; ++c)
        rgb[c] = (1 - ay) * ((1 - ax) * c00[c] + ax * c10[c]) + ay * ((1 - ax) * c01[c] + ax * c11[c]);
}

void rad_texture_mean(const rad_texture *t, double rgb[3]) {
    double sum[3] = {0, 0, 0};
    for (uint32_t y = 0; y < t->height; ++y)
        for (uint32_t x = 0; x < t->width; ++x) {
            double c[3];
            texel(t, x, y, c);
            for (int k = 0; k < 3; ++k) sum[k] += c[k];
        }
    for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / ((double)t->width * t->height);
}

/* ------------------------------------------------------------------------------------------- */
/* Texture coordinates on polygons                                                              */

static int polygon_has_uv(const rad_scene *scene, const rad_polygon *p) {
    if (!scene->polygon_uvs || (size_t)p->first + p->count > scene->polygon_uv_count) return 0;
    for (uint32_t k = 0; k < p->count; ++k)
        if (!isfinite(scene->polygon_uvs[p->first + k][0]) ||
            !isfinite(scene->polygon_uvs[p->first + k][1]))
            return 0;
    return 1;
}

int rad_polygon_uv(const rad_scene *scene, uint32_t polygon, rad_vec3 x, double uv[2]) {
    if (polygon >= scene->polygon_count) return 0;
    const rad_polygon *p = &scene->polygons[polygon];
    if (!polygon_has_uv(scene, p)) return 0;
    /* Barycentric coordinates in each fan triangle (0, k, k + 1); the one x is most inside. */
    rad_vec3 a = rad_polygon_vertex(scene, p, 0);
    double best = -INFINITY, weights[3] = {1, 0, 0};
    uint32_t best_k = 1;
    for (uint32_t k = 1; k + 1 < p->count; ++k) {
        rad_vec3 b = rad_polygon_vertex(scene, p, k), c = rad_polygon_vertex(scene, p, k + 1);
        rad_vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), ax = v3_sub(x, a);
        rad_vec3 n = v3_cross(ab, ac);
        double nn = v3_dot(n, n);
        if (!(nn > 0)) continue;
        double wb = v3_dot(v3_cross(ax, ac), n) / nn, wc = v3_dot(v3_cross(ab, ax), n) / nn;
        double wa = 1 - wb - wc, inside = fmin(wa, fmin(wb, wc));
        if (inside > best) {
            best = inside;
            best_k = k;
            weights[0] = wa;
            weights[1] = wb;
            weights[2] = wc;
        }
    }
    float(*t)[2] = scene->polygon_uvs + p->first;
    for (int i = 0; i < 2; ++i)
        uv[i] = weights[0] * t[0][i] + weights[1] * t[best_k][i] + weights[2] * t[best_k + 1][i];
    return 1;
}

static const rad_material *polygon_material(const rad_scene *scene, uint32_t polygon) {
    return &scene->materials[scene->surfaces[scene->polygons[polygon].surface].material];
}

int rad_scene_albedo_at(const rad_scene *scene, uint32_t polygon, rad_vec3 x, double rho[3]) {
    const rad_material *m = polygon_material(scene, polygon);
    double uv[2], texture[3];
    for (int c = 0; c < 3; ++c) rho[c] = m->reflectance[c];
    if (!m->texture || !rad_polygon_uv(scene, polygon, x, uv)) return 0;
    rad_texture_lookup(m->texture, uv[0], uv[1], texture);
    for (int c = 0; c < 3; ++c) rho[c] *= texture[c];
    return 1;
}

const rad_material *rad_scene_material_at(const rad_scene *scene, const rad_material *m,
                                          uint32_t polygon, rad_vec3 x, rad_material *textured) {
    if (!m->texture || !scene) return m;
    *textured = *m;
    rad_scene_albedo_at(scene, polygon, x, textured->reflectance);
    return textured;
}

/* The point at (s, t) of the bilinear patch c0 c1 c2 c3 (a triangle when c3 = c2), and the
 * length of its cross derivative there: the area it stands for. */
static rad_vec3 patch_point(const rad_vec3 *c, double s, double t, double *jacobian) {
    rad_vec3 ds = v3_add(v3_scale(v3_sub(c[1], c[0]), 1 - t), v3_scale(v3_sub(c[2], c[3]), t));
    rad_vec3 dt = v3_add(v3_scale(v3_sub(c[3], c[0]), 1 - s), v3_scale(v3_sub(c[2], c[1]), s));
    *jacobian = v3_length(v3_cross(ds, dt));
    return v3_add(v3_add(v3_scale(c[0], (1 - s) * (1 - t)), v3_scale(c[1], s * (1 - t))),
                  v3_add(v3_scale(c[2], s * t), v3_scale(c[3], (1 - s) * t)));
}

int rad_texture_element_mean(const rad_scene *scene, uint32_t polygon, const rad_vec3 *corners,
                             int count, double rho[3]) {
    const rad_material *m = polygon_material(scene, polygon);
    for (int c = 0; c < 3; ++c) rho[c] = m->reflectance[c];
    if (!m->texture || count < 3 || count > 4 || !polygon_has_uv(scene, &scene->polygons[polygon]))
        return 0;
    rad_vec3 c[4] = {corners[0], corners[1], corners[2], count == 4 ? corners[3] : corners[2]};
    /* How many texels the piece covers: its area in texture space, from its corners' (u, v). */
    double uv[4][2], texels = 0;
    for (int k = 0; k < count; ++k) rad_polygon_uv(scene, polygon, corners[k], uv[k]);
    for (int k = 0; k < count; ++k) {
        int next = (k + 1) % count;
        texels += 0.5 * (uv[k][0] * uv[next][1] - uv[next][0] * uv[k][1]);
    }
    texels = fabs(texels) * m->texture->width * m->texture->height;
    int grid = (int)fmin(MAX_GRID, fmax(2, ceil(2 * sqrt(texels))));
    double sum[3] = {0, 0, 0}, weight = 0;
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
            double jacobian, at[2], texture[3];
            rad_vec3 x = patch_point(c, (i + 0.5) / grid, (j + 0.5) / grid, &jacobian);
            if (!(jacobian > 0) || !rad_polygon_uv(scene, polygon, x, at)) continue;
            rad_texture_lookup(m->texture, at[0], at[1], texture);
            for (int k = 0; k < 3; ++k) sum[k] += jacobian * texture[k];
            weight += jacobian;
        }
    if (!(weight > 0)) return 0;
    for (int k = 0; k < 3; ++k) rho[k] *= sum[k] / weight;
    return 1;
}
