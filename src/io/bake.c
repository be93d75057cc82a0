/* bake.c - the solution as vertex colours (see bake.h): the public entry points, the choice of
 * format, and the baked mesh every writer reads. */
#include "io/bake.h"

#include "core/atomic_file.h"
#include "mesh/mesh.h"
#include "render/render.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "system/system.h"
#include "system/solution_view.h"

#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------------------------------------- */
/* Text                                                                                         */

static int text_reserve(rad_bake_text *t, size_t more) {
    if (t->status) return 0;
    if (t->length + more + 1 <= t->capacity) return 1;
    size_t capacity = t->capacity ? t->capacity : 4096;
    while (capacity < t->length + more + 1) {
        if (capacity > SIZE_MAX / 2) {
            t->status = rad_fail(t->ctx, RAD_ERROR_NO_MEMORY, "text too large");
            return 0;
        }
        capacity *= 2;
    }
    char *data = rad_realloc(t->ctx, t->data, capacity, 1);
    if (!data) {
        t->status = RAD_ERROR_NO_MEMORY;
        return 0;
    }
    t->data = data;
    t->capacity = capacity;
    return 1;
}

void rad_bake_text_printf(rad_bake_text *t, const char *format, ...) {
    va_list args;
    va_start(args, format);
    int needed = vsnprintf(NULL, 0, format, args);
    va_end(args);
    if (needed < 0 || !text_reserve(t, (size_t)needed)) return;
    va_start(args, format);
    vsnprintf(t->data + t->length, (size_t)needed + 1, format, args);
    va_end(args);
    t->length += (size_t)needed;
}

void rad_bake_text_json_string(rad_bake_text *t, const char *value) {
    rad_bake_text_printf(t, "\"");
    for (const char *s = value ? value : ""; *s;) {
        unsigned char c = (unsigned char)*s;
        int length = rad_utf8_char_length(s);
        if (c == '"' || c == '\\') rad_bake_text_printf(t, "\\%c", c);
        else if (c < 0x20) rad_bake_text_printf(t, "\\u%04x", c);
        else if (!length) rad_bake_text_printf(t, "\\ufffd"); /* not UTF-8 */
        else rad_bake_text_printf(t, "%.*s", length, s);
        s += length ? length : 1;
    }
    rad_bake_text_printf(t, "\"");
}

void rad_bake_text_free(rad_bake_text *t) {
    rad_free(t->ctx, t->data);
    t->data = NULL;
    t->length = t->capacity = 0;
}

/* ------------------------------------------------------------------------------------------- */
/* Formats and checks                                                                           */

static int ends_with(const char *path, const char *suffix) {
    size_t n = strlen(path), m = strlen(suffix);
    if (n <= m) return 0;
    for (size_t i = 0; i < m; ++i)
        if (tolower((unsigned char)path[n - m + i]) != suffix[i]) return 0;
    return path[n - m - 1] != '/'; /* a name before the extension */
}

rad_bake_format rad_bake_format_of(const char *path) {
    if (!path) return RAD_BAKE_AUTO;
    if (ends_with(path, ".glb")) return RAD_BAKE_GLB;
    if (ends_with(path, ".gltf")) return RAD_BAKE_GLTF;
    if (ends_with(path, ".ply")) return RAD_BAKE_PLY;
    if (ends_with(path, ".obj")) return RAD_BAKE_OBJ;
    return RAD_BAKE_AUTO;
}

static const rad_bake_options no_options;

static rad_status check_options(rad_context *ctx, const char *path, const rad_bake_options *o,
                                rad_bake_format *format, int *tonemap) {
    *format = RAD_BAKE_AUTO;
    *tonemap = RAD_TONEMAP_CLAMP;
    if (!path || !*path) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bake: no output path");
    *format = o->format ? o->format : rad_bake_format_of(path);
    if (*format < RAD_BAKE_GLB || *format > RAD_BAKE_OBJ)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: unknown bake format (the name must end in .glb, .gltf, .ply or .obj)",
                        path);
    *tonemap = o->tonemap ? rad_tonemap_parse(o->tonemap) : RAD_TONEMAP_CLAMP;
    if (*tonemap < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "unknown tone curve '%s' (none, clamp, reinhard, aces)", o->tonemap);
    if (!isfinite(o->exposure) || !isfinite(o->scale) || o->scale < 0 || !isfinite(o->aspect) ||
        o->aspect < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "bake: exposure must be finite, scale and aspect positive");
    if (*format == RAD_BAKE_GLTF && strlen(path) > 4096)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bake: output path too long");
    if (o->final_gather < 0 || o->final_gather > RAD_RENDER_MAX_GATHER)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "bake: final gather rays must be 0 to %d, not %d", RAD_RENDER_MAX_GATHER,
                        o->final_gather);
    return RAD_OK;
}

rad_status rad_bake_check(rad_context *ctx, const char *path, const rad_bake_options *options) {
    if (!ctx) return RAD_ERROR_INVALID_ARGUMENT;
    const rad_bake_options *o = options ? options : &no_options;
    rad_bake_format format;
    int tonemap;
    rad_status status = check_options(ctx, path, o, &format, &tonemap);
    if (status) return status;
    /* Try the directory: make the temporary the real write would make, and drop it. */
    status = rad_atomic_check(ctx, path);
    if (status) return status;
    return RAD_OK;
}

/* ------------------------------------------------------------------------------------------- */
/* The baked mesh                                                                               */

static void baked_free(rad_baked_mesh *b) {
    rad_context *ctx = b->ctx;
    rad_free(ctx, b->surfaces);
    rad_free(ctx, b->position);
    rad_free(ctx, b->normal);
    rad_free(ctx, b->radiance);
    rad_free(ctx, b->shown);
    rad_free(ctx, b->display);
    rad_free(ctx, b->face);
}

/* Rotation matrix (columns: camera x, y, z in world) to a unit quaternion x, y, z, w. */
static void quaternion_from_basis(rad_vec3 x, rad_vec3 y, rad_vec3 z, float q[4]) {
    double m00 = x.x, m10 = x.y, m20 = x.z;
    double m01 = y.x, m11 = y.y, m21 = y.z;
    double m02 = z.x, m12 = z.y, m22 = z.z;
    double trace = m00 + m11 + m22, qx, qy, qz, qw;
    if (trace > 0) {
        double s = 2 * sqrt(trace + 1);
        qw = 0.25 * s;
        qx = (m21 - m12) / s;
        qy = (m02 - m20) / s;
        qz = (m10 - m01) / s;
    } else if (m00 > m11 && m00 > m22) {
        double s = 2 * sqrt(1 + m00 - m11 - m22);
        qw = (m21 - m12) / s;
        qx = 0.25 * s;
        qy = (m01 + m10) / s;
        qz = (m02 + m20) / s;
    } else if (m11 > m22) {
        double s = 2 * sqrt(1 + m11 - m00 - m22);
        qw = (m02 - m20) / s;
        qx = (m01 + m10) / s;
        qy = 0.25 * s;
        qz = (m12 + m21) / s;
    } else {
        double s = 2 * sqrt(1 + m22 - m00 - m11);
        qw = (m10 - m01) / s;
        qx = (m02 + m20) / s;
        qy = (m12 + m21) / s;
        qz = 0.25 * s;
    }
    double length = sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
    q[0] = (float)(qx / length);
    q[1] = (float)(qy / length);
    q[2] = (float)(qz / length);
    q[3] = (float)(qw / length);
}

/* The scene camera in glTF terms: the node's -Z looks forward, +Y is up; clip planes that hold
 * the whole mesh. */
static rad_status bake_camera(rad_context *ctx, const rad_scene *scene, const rad_mesh *mesh,
                              double scale, double aspect, rad_baked_camera *out) {
    rad_view view;
    rad_status status = rad_view_make(ctx, &scene->camera, 1, 1, &view);
    if (status) return status;
    quaternion_from_basis(view.right, view.up, v3_scale(view.forward, -1), out->rotation);
    out->eye[0] = (float)(view.eye.x * scale);
    out->eye[1] = (float)(view.eye.y * scale);
    out->eye[2] = (float)(view.eye.z * scale);
    out->yfov = scene->camera.fov_degrees * RAD_PI / 180;
    out->aspect = aspect;
    /* Far: twice the farthest vertex. Near: as far out as the nearest geometry allows (a
     * vertex's distance less an element's size bounds the distance to the elements around it),
     * since depth precision goes with near / far and surfaces lie close together (the Cornell
     * lamp is 0.1 mm below the ceiling); at least far / 10^4. */
    double farthest = 0, nearest = INFINITY;
    for (size_t v = 0; v < mesh->vertex_count; ++v) {
        double d = v3_length(v3_sub(mesh->vertices[v], view.eye));
        if (d > farthest) farthest = d;
        if (d < nearest) nearest = d;
    }
    if (!(farthest > 0)) farthest = 1;
    out->zfar = 2 * farthest * scale;
    double clear = 0.5 * (nearest - mesh->element_size) * scale;
    out->znear = fmax(out->zfar * 1e-4, isfinite(clear) ? clear : 0);
    return RAD_OK;
}

static rad_status build(const rad_system *s, const rad_bake_options *o, int tonemap,
                        rad_baked_mesh *b) {
    rad_context *ctx = s->ctx;
    const rad_solution_view *solution = rad_system_view(s);
    const rad_mesh *mesh = rad_solution_leaves(solution); /* the leaves to draw */
    size_t nv = mesh->vertex_count, ne = mesh->element_count, ns = s->surface_count;
    double scale = o->scale > 0 ? o->scale : 1;
    /* Positions (and the camera's far plane, twice the farthest distance) are written as
     * floats: a scale that overflows them would write inf, which no mesh format takes. */
    double largest = 0;
    for (size_t v = 0; v < nv; ++v)
        largest = fmax(largest, fmax(fabs(mesh->vertices[v].x),
                                     fmax(fabs(mesh->vertices[v].y), fabs(mesh->vertices[v].z))));
    if (!(4 * largest * scale < FLT_MAX))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bake: a scale of %g makes the mesh's "
                        "coordinates (up to %g) overflow single precision (3.4e38)", scale,
                        largest);
    memset(b, 0, sizeof *b);
    b->ctx = ctx;
    b->exposure = o->exposure;
    b->tonemap = o->tonemap ? o->tonemap : "clamp";

    rad_rgb *vertex_radiosity = rad_alloc(ctx, nv ? nv : 1, sizeof *vertex_radiosity);
    rad_vec3 *normal_sum = rad_alloc_zero(ctx, nv ? nv : 1, sizeof *normal_sum);
    uint32_t *new_index = rad_alloc(ctx, nv ? nv : 1, sizeof *new_index);
    size_t *surface_first = rad_alloc_zero(ctx, ns + 1, sizeof *surface_first);
    size_t *surface_faces = rad_alloc_zero(ctx, ns + 1, sizeof *surface_faces);
    size_t *vertex_fill = rad_alloc(ctx, ns + 1, sizeof *vertex_fill);
    size_t *face_fill = rad_alloc(ctx, ns + 1, sizeof *face_fill);
    b->surfaces = rad_alloc_zero(ctx, ns ? ns : 1, sizeof *b->surfaces);
    b->position = rad_alloc(ctx, nv ? nv : 1, sizeof *b->position);
    b->normal = rad_alloc(ctx, nv ? nv : 1, sizeof *b->normal);
    b->radiance = rad_alloc(ctx, nv ? nv : 1, sizeof *b->radiance);
    b->shown = rad_alloc(ctx, nv ? nv : 1, sizeof *b->shown);
    b->display = rad_alloc(ctx, nv ? nv : 1, sizeof *b->display);
    b->face = rad_alloc(ctx, ne ? ne : 1, sizeof *b->face);
    rad_status status = RAD_OK;
    if (!vertex_radiosity || !normal_sum || !new_index || !surface_first || !surface_faces ||
        !vertex_fill || !face_fill || !b->surfaces || !b->position || !b->normal ||
        !b->radiance || !b->shown || !b->display || !b->face) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }

    /* The solution at the vertices: area-weighted over the elements around each one, or
     * gathered again at each (the renderer's final gather, render.c). */
    if (o->final_gather > 0) {
        rad_render_options render = {0};
        render.final_gather = o->final_gather;
        render.ambient = o->ambient;
        rad_renderer *r = NULL;
        status = rad_renderer_create_for_points(o->scene, s, &render, &r);
        if (!status) status = rad_renderer_vertex_radiosity(r, o->final_gather, vertex_radiosity);
        rad_renderer_destroy(r);
    } else
        status = rad_solution_vertex_radiosity(solution, ctx, o->ambient, vertex_radiosity);
    if (status) goto done;

    /* Vertices and faces grouped by surface, in system order. Each element uses only vertices
     * of its own surface; check it, since the seams depend on it. */
    for (size_t v = 0; v < nv; ++v) surface_first[mesh->vertex_surface[v] + 1]++;
    for (size_t e = 0; e < ne; ++e) {
        uint32_t surface = mesh->element_surface[e];
        surface_faces[surface + 1]++;
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            uint32_t v = mesh->element_vertices[e][k];
            if (mesh->vertex_surface[v] != surface) {
                status = rad_fail(ctx, RAD_ERROR_INTERNAL,
                                  "bake: element %zu uses a vertex of another surface", e);
                goto done;
            }
            rad_vec3 weighted = v3_scale(mesh->element_normal[e], mesh->element_area[e]);
            normal_sum[v] = v3_add(normal_sum[v], weighted);
        }
    }
    for (size_t i = 0; i < ns; ++i) {
        surface_first[i + 1] += surface_first[i];
        surface_faces[i + 1] += surface_faces[i];
    }
    /* Fill in surface order, remembering each vertex's index within its surface. */
    memcpy(vertex_fill, surface_first, (ns + 1) * sizeof *vertex_fill);
    memcpy(face_fill, surface_faces, (ns + 1) * sizeof *face_fill);
    for (size_t v = 0; v < nv; ++v) {
        uint32_t surface = mesh->vertex_surface[v];
        size_t at = vertex_fill[surface]++;
        new_index[v] = (uint32_t)(at - surface_first[surface]);
        rad_vec3 p = mesh->vertices[v];
        b->position[at][0] = (float)(p.x * scale);
        b->position[at][1] = (float)(p.y * scale);
        b->position[at][2] = (float)(p.z * scale);
        rad_vec3 n = v3_normalize(normal_sum[v]);
        if (!(v3_length(n) > 0.5)) n = v3(0, 0, 1); /* a vertex no element uses */
        b->normal[at][0] = (float)n.x;
        b->normal[at][1] = (float)n.y;
        b->normal[at][2] = (float)n.z;
        /* Radiance of a diffuse surface: L = B / pi. */
        for (int c = 0; c < 3; ++c) b->radiance[at][c] = (float)(vertex_radiosity[v][c] / RAD_PI);
        rad_tonemap_apply((rad_tonemap)tonemap, o->exposure, b->radiance[at], b->shown[at]);
        for (int c = 0; c < 3; ++c) b->display[at][c] = rad_srgb_encode(b->shown[at][c]);
    }
    for (size_t e = 0; e < ne; ++e) {
        uint32_t surface = mesh->element_surface[e];
        size_t at = face_fill[surface]++;
        int corners = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < 4; ++k)
            b->face[at][k] =
                k < corners ? new_index[mesh->element_vertices[e][k]] : RAD_BAKED_NO_VERTEX;
    }

    /* Surfaces with faces; an empty one (all its polygons degenerate) has nothing to show. */
    b->vertex_count = nv;
    b->face_count = ne;
    for (size_t i = 0; i < ns; ++i) {
        size_t faces = surface_faces[i + 1] - surface_faces[i];
        if (!faces) continue;
        rad_baked_surface *out = &b->surfaces[b->surface_count++];
        out->name = s->surface_name[i];
        out->first_vertex = surface_first[i];
        out->vertex_count = surface_first[i + 1] - surface_first[i];
        out->first_face = surface_faces[i];
        out->face_count = faces;
        for (size_t f = out->first_face; f < out->first_face + faces; ++f)
            out->triangle_count += rad_baked_corner_count(b, f) == 4 ? 2 : 1;
    }
    if (!b->surface_count)
        status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bake: the scene has no elements");

    if (!status && o->scene && o->scene->has_camera) {
        status = bake_camera(ctx, o->scene, mesh, scale, o->aspect > 0 ? o->aspect : 1, &b->camera);
        b->has_camera = !status;
    }

done:
    rad_free(ctx, vertex_fill);
    rad_free(ctx, face_fill);
    rad_free(ctx, vertex_radiosity);
    rad_free(ctx, normal_sum);
    rad_free(ctx, new_index);
    rad_free(ctx, surface_first);
    rad_free(ctx, surface_faces);
    if (status) baked_free(b);
    return status;
}

rad_status rad_bake(const rad_system *system, const char *path, const rad_bake_options *options) {
    if (!system) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = system->ctx;
    const rad_bake_options *o = options ? options : &no_options;
    rad_bake_format format;
    int tonemap;
    rad_status status = check_options(ctx, path, o, &format, &tonemap);
    if (status) return status;
    const rad_mesh *leaves = rad_solution_leaves(rad_system_view(system));
    if (!leaves)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "bake: a patch system (.ffm) has no geometry to bake");
    if (leaves->vertex_count > UINT32_MAX - 1)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "bake: more than 2^32 - 2 vertices");
    if (o->final_gather > 0 && !o->scene)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "bake: the final gather needs the scene (rad_bake_options.scene)");

    rad_baked_mesh baked;
    status = build(system, o, tonemap, &baked);
    if (status) return status;
    char generator[64];
    snprintf(generator, sizeof generator, "radiosity %s", rad_version());
    baked.generator = generator;
    switch (format) {
    case RAD_BAKE_GLB: status = rad_bake_write_gltf(&baked, path, 1); break;
    case RAD_BAKE_GLTF: status = rad_bake_write_gltf(&baked, path, 0); break;
    case RAD_BAKE_PLY: status = rad_bake_write_ply(&baked, path); break;
    case RAD_BAKE_OBJ: status = rad_bake_write_obj(&baked, path); break;
    default: status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bake: unknown format"); break;
    }
    baked_free(&baked);
    return status;
}
