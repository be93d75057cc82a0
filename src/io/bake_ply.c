/* bake_ply.c - the baked mesh as binary little-endian PLY, written by the project.
 *
 * Why not assimp's exporter: assimp 5.2.5 writes colours as `uchar red green blue alpha` from
 * the float colour times 255 without clamping (2.5 comes out as 637, which no reader takes), and
 * cannot add the float radiance properties (docs/bake.md).
 *
 * Per vertex: x y z, nx ny nz (float), red green blue (uchar: 8-bit sRGB after exposure and tone
 * curve, what the PNG of `radiosity render` shows with the same settings), radiance_r radiance_g
 * radiance_b (float: linear radiance B / pi). Faces are the elements, quads and triangles, as
 * `vertex_indices` lists, counter-clockwise seen from the lit side. Comments say which vertices
 * and faces belong to which surface. */
#include "io/bake.h"

#include "core/atomic_file.h"

#include <string.h>

/* A surface name for a one-line header comment: control characters become '_'. */
static void comment_name(rad_bake_text *t, const char *name) {
    for (const unsigned char *c = (const unsigned char *)name; *c; ++c)
        rad_bake_text_printf(t, "%c", *c < 0x20 || *c == 0x7f ? '_' : *c);
}

rad_status rad_bake_write_ply(const rad_baked_mesh *b, const char *path) {
    rad_context *ctx = b->ctx;
    rad_bake_text header = {ctx, NULL, 0, 0, RAD_OK};
    rad_bake_text_printf(&header, "ply\nformat binary_little_endian 1.0\n");
    rad_bake_text_printf(&header, "comment generator %s\n", b->generator);
    rad_bake_text_printf(&header,
                         "comment red green blue: 8-bit sRGB of the radiance after exposure %g "
                         "stops and tone curve %s\n",
                         b->exposure, b->tonemap);
    rad_bake_text_printf(&header, "comment radiance_r radiance_g radiance_b: linear radiance "
                                  "B / pi (W m^-2 sr^-1 for emission in W m^-2 sr^-1)\n");
    for (size_t i = 0; i < b->surface_count; ++i) {
        const rad_baked_surface *s = &b->surfaces[i];
        rad_bake_text_printf(&header, "comment surface vertices %zu-%zu faces %zu-%zu: ",
                             s->first_vertex, s->first_vertex + s->vertex_count - 1, s->first_face,
                             s->first_face + s->face_count - 1);
        comment_name(&header, s->name);
        rad_bake_text_printf(&header, "\n");
    }
    rad_bake_text_printf(&header,
                         "element vertex %zu\n"
                         "property float x\nproperty float y\nproperty float z\n"
                         "property float nx\nproperty float ny\nproperty float nz\n"
                         "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                         "property float radiance_r\nproperty float radiance_g\n"
                         "property float radiance_b\n"
                         "element face %zu\n"
                         "property list uchar uint vertex_indices\n"
                         "end_header\n",
                         b->vertex_count, b->face_count);
    if (header.status) {
        rad_bake_text_free(&header);
        return header.status;
    }

    rad_atomic_file file;
    rad_status status = rad_atomic_open(ctx, path, &file);
    if (status) {
        rad_bake_text_free(&header);
        return status;
    }
    fwrite(header.data, 1, header.length, file.file);
    rad_bake_text_free(&header);

    /* Vertices are grouped by surface, so a face's file index is its surface's first vertex
     * plus the local index. */
    enum { VERTEX_BYTES = 12 + 12 + 3 + 12 };
    uint8_t record[VERTEX_BYTES];
    for (size_t v = 0; v < b->vertex_count; ++v) {
        uint8_t *at = record;
        for (int c = 0; c < 3; ++c, at += 4) rad_bake_put_f32(at, b->position[v][c]);
        for (int c = 0; c < 3; ++c, at += 4) rad_bake_put_f32(at, b->normal[v][c]);
        for (int c = 0; c < 3; ++c) *at++ = b->display[v][c];
        for (int c = 0; c < 3; ++c, at += 4) rad_bake_put_f32(at, b->radiance[v][c]);
        fwrite(record, 1, VERTEX_BYTES, file.file);
    }
    for (size_t i = 0; i < b->surface_count; ++i) {
        const rad_baked_surface *s = &b->surfaces[i];
        for (size_t f = s->first_face; f < s->first_face + s->face_count; ++f) {
            int corners = rad_baked_corner_count(b, f);
            uint8_t face[1 + 16];
            face[0] = (uint8_t)corners;
            for (int k = 0; k < corners; ++k)
                rad_bake_put_u32(face + 1 + 4 * k, (uint32_t)(s->first_vertex + b->face[f][k]));
            fwrite(face, 1, 1 + 4 * (size_t)corners, file.file);
        }
    }
    return rad_atomic_commit(&file);
}
