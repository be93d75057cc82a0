/* bake.h - the radiosity solution as a mesh with vertex colours, for other tools (docs/bake.md).
 *
 * bake.c turns a solved geometric system into a rad_baked_mesh: the mesh vertices grouped by
 * surface, each with its position, normal, linear radiance (B / pi) and display colour (radiance
 * after exposure and tone curve, linear in [0, 1] and as 8-bit sRGB), the elements as faces
 * with surface-local indices, and the scene camera. One writer per format reads it:
 *   bake_gltf.c  glTF 2.0, .glb and .gltf + .bin (written by the project: see docs/bake.md)
 *   bake_ply.c   binary little-endian PLY (written by the project)
 *   bake_obj.c   Wavefront OBJ with "v x y z r g b" colours (assimp's exporter)
 *
 * Vertices belong to one surface and are shared only across gentle bends (src/mesh/mesh.c), so a
 * vertex's value is the area-weighted mean of the elements around it on its own side of a corner:
 * seams are right by construction. */
#ifndef RAD_IO_BAKE_H
#define RAD_IO_BAKE_H

#include "core/context.h"
#include "image/tonemap.h"

#include <stdint.h>

#define RAD_BAKED_NO_VERTEX UINT32_MAX

typedef struct rad_baked_surface {
    const char *name;         /* lives as long as the system */
    size_t first_vertex;      /* its vertices: first_vertex .. first_vertex + vertex_count */
    size_t vertex_count;
    size_t first_face;        /* its faces: first_face .. first_face + face_count */
    size_t face_count;
    size_t triangle_count;    /* a quad counts two */
} rad_baked_surface;

typedef struct rad_baked_camera {
    float eye[3];
    float rotation[4];        /* glTF x, y, z, w: camera -Z looks forward, +Y is up */
    double yfov;              /* radians */
    double aspect;            /* width / height */
    double znear, zfar;       /* scaled scene units */
} rad_baked_camera;

typedef struct rad_baked_mesh {
    rad_context *ctx;
    size_t surface_count;     /* surfaces with at least one face, in system order */
    rad_baked_surface *surfaces;

    size_t vertex_count;      /* grouped by surface */
    float (*position)[3];     /* scene units times the scale */
    float (*normal)[3];       /* unit, area-weighted over the elements around the vertex */
    float (*radiance)[3];     /* linear radiance B / pi, W m^-2 sr^-1 when B is W m^-2 */
    float (*shown)[3];        /* radiance after exposure and tone curve: linear, in [0, 1] */
    uint8_t (*display)[3];    /* shown, as 8-bit sRGB */

    size_t face_count;        /* grouped by surface */
    uint32_t (*face)[4];      /* surface-local indices, counter-clockwise seen from the front;
                                 [3] == RAD_BAKED_NO_VERTEX for triangles */

    int has_camera;
    rad_baked_camera camera;

    /* What the display colours are (for comments in the files). */
    double exposure;
    const char *tonemap;
    const char *generator;    /* "radiosity X.Y.Z" */
} rad_baked_mesh;

static inline int rad_baked_corner_count(const rad_baked_mesh *mesh, size_t face) {
    return mesh->face[face][3] == RAD_BAKED_NO_VERTEX ? 3 : 4;
}

/* The writers. Each writes the whole file through rad_atomic_file, or nothing. */
rad_status rad_bake_write_gltf(const rad_baked_mesh *mesh, const char *path, int binary);
rad_status rad_bake_write_ply(const rad_baked_mesh *mesh, const char *path);
rad_status rad_bake_write_obj(const rad_baked_mesh *mesh, const char *path);

/* A growing text for JSON and headers. An allocation failure is sticky: later appends do
 * nothing and `status` says RAD_ERROR_NO_MEMORY. */
typedef struct rad_bake_text {
    rad_context *ctx;
    char *data;
    size_t length, capacity;
    rad_status status;
} rad_bake_text;

void rad_bake_text_printf(rad_bake_text *text, const char *format, ...) RAD_PRINTF(2, 3);
/* Appends a JSON string literal (quotes and escapes). */
void rad_bake_text_json_string(rad_bake_text *text, const char *value);
void rad_bake_text_free(rad_bake_text *text);

/* Writes little-endian values into a byte buffer. */
static inline void rad_bake_put_u32(uint8_t *at, uint32_t value) {
    at[0] = (uint8_t)value;
    at[1] = (uint8_t)(value >> 8);
    at[2] = (uint8_t)(value >> 16);
    at[3] = (uint8_t)(value >> 24);
}
static inline void rad_bake_put_u16(uint8_t *at, uint16_t value) {
    at[0] = (uint8_t)value;
    at[1] = (uint8_t)(value >> 8);
}
static inline void rad_bake_put_f32(uint8_t *at, float value) {
    union {
        float f;
        uint32_t u;
    } bits;
    bits.f = value;
    rad_bake_put_u32(at, bits.u);
}

#endif
