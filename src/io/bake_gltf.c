/* bake_gltf.c - the baked mesh as glTF 2.0 (.glb, or .gltf + .bin), written by the project.
 *
 * Why not assimp's exporter: assimp 5.2.5 writes no KHR_materials_unlit (it drops
 * aiShadingMode_Unlit), no cameras (the camera node comes out empty), and lists extensions it did
 * not use (KHR_materials_volume, FB_ngon_encoding); docs/bake.md has the details.
 *
 * What is written, after the glTF 2.0 specification (Khronos, 2021):
 *   - one mesh and one node per surface, named after it; one triangle primitive (quads split
 *     along their first diagonal) with POSITION (min/max given), NORMAL, COLOR_0, _RADIANCE and
 *     indices (unsigned short when the surface has fewer than 65535 vertices, else unsigned int);
 *   - COLOR_0 (float VEC3) is the linear radiance after exposure and tone curve, which with the
 *     defaults is the radiance itself, clipped at 1: the specification and the Khronos validator
 *     (ACCESSOR_NON_CLAMPED, an error) want colours in [0, 1]. _RADIANCE (float VEC3, an
 *     application-specific attribute, so the leading underscore) is the radiance B / pi
 *     unclipped, for tools that want the high dynamic range;
 *   - one material, KHR_materials_unlit with base colour 1, so viewers show COLOR_0 as it is;
 *     its lit fallback (metallic 0, roughness 1) is what a viewer without the extension shows;
 *   - the scene camera, if any: a perspective camera on a node whose -Z looks forward and +Y is
 *     up (translation + rotation), yfov in radians, aspect ratio, clip planes around the mesh;
 *   - one buffer; every bufferView starts on a 4-byte boundary; GLB chunks padded to 4 bytes
 *     (JSON with spaces, BIN with zeros). */
#include "io/bake.h"

#include "core/atomic_file.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define GLTF_FLOAT 5126
#define GLTF_UNSIGNED_SHORT 5123
#define GLTF_UNSIGNED_INT 5125
#define GLTF_ARRAY_BUFFER 34962
#define GLTF_ELEMENT_ARRAY_BUFFER 34963

static size_t align4(size_t n) { return (n + 3) & ~(size_t)3; }

/* Where one surface's data sits in the buffer. */
typedef struct surface_layout {
    size_t positions, normals, colours, radiances, indices; /* byte offsets */
    size_t attribute_bytes, index_bytes;         /* per attribute array; indices unpadded */
    int short_indices;
} surface_layout;

static rad_status plan(const rad_baked_mesh *b, surface_layout *layout, size_t *total) {
    size_t at = 0;
    for (size_t i = 0; i < b->surface_count; ++i) {
        const rad_baked_surface *s = &b->surfaces[i];
        surface_layout *l = &layout[i];
        l->short_indices = s->vertex_count < 65535; /* 65535 is the primitive restart value */
        l->attribute_bytes = 12 * s->vertex_count;
        l->index_bytes = 3 * s->triangle_count * (l->short_indices ? 2 : 4);
        l->positions = at;
        l->normals = l->positions + l->attribute_bytes;
        l->colours = l->normals + l->attribute_bytes;
        l->radiances = l->colours + l->attribute_bytes;
        l->indices = l->radiances + l->attribute_bytes;
        at = l->indices + align4(l->index_bytes);
    }
    *total = at;
    /* GLB and glTF lengths are 32-bit in practice (the GLB header is); stay well inside. */
    if (at > 0xFFFFFFFFu - 4096)
        return rad_fail(b->ctx, RAD_ERROR_UNSUPPORTED,
                        "bake: %zu bytes of mesh data; glTF buffers stop at 4 GiB", at);
    return RAD_OK;
}

static void fill_buffer(const rad_baked_mesh *b, const surface_layout *layout, uint8_t *buffer) {
    for (size_t i = 0; i < b->surface_count; ++i) {
        const rad_baked_surface *s = &b->surfaces[i];
        const surface_layout *l = &layout[i];
        for (size_t v = 0; v < s->vertex_count; ++v)
            for (int c = 0; c < 3; ++c) {
                size_t k = s->first_vertex + v;
                rad_bake_put_f32(buffer + l->positions + 12 * v + 4 * c, b->position[k][c]);
                rad_bake_put_f32(buffer + l->normals + 12 * v + 4 * c, b->normal[k][c]);
                rad_bake_put_f32(buffer + l->colours + 12 * v + 4 * c, b->shown[k][c]);
                rad_bake_put_f32(buffer + l->radiances + 12 * v + 4 * c, b->radiance[k][c]);
            }
        uint8_t *index = buffer + l->indices;
        for (size_t f = s->first_face; f < s->first_face + s->face_count; ++f) {
            const uint32_t *q = b->face[f];
            uint32_t triangles[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
            int count = rad_baked_corner_count(b, f) == 4 ? 2 : 1;
            for (int t = 0; t < count; ++t)
                for (int k = 0; k < 3; ++k) {
                    if (l->short_indices) {
                        rad_bake_put_u16(index, (uint16_t)triangles[t][k]);
                        index += 2;
                    } else {
                        rad_bake_put_u32(index, triangles[t][k]);
                        index += 4;
                    }
                }
        }
    }
}

/* "%.9g" prints every float so that it reads back to the same float. */
static void json_float3(rad_bake_text *t, const float v[3]) {
    rad_bake_text_printf(t, "[%.9g, %.9g, %.9g]", v[0], v[1], v[2]);
}

/* The .bin's file name, the URI the .gltf gives for its buffer. */
static const char *file_name_of(const char *path) {
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static void write_json(const rad_baked_mesh *b, const surface_layout *layout, size_t total,
                       const char *bin_path, rad_bake_text *t) {
    size_t n = b->surface_count;
    rad_bake_text_printf(t, "{\n\"asset\": {\"version\": \"2.0\", \"generator\": ");
    rad_bake_text_json_string(t, b->generator);
    rad_bake_text_printf(t, ", \"extras\": {\"_RADIANCE\": \"linear radiance L = B / pi, in the "
                            "units of the scene's emission (W m^-2 sr^-1)\", \"COLOR_0\": \"the "
                            "radiance after exposure %g stops and tone curve %s, linear, in "
                            "[0, 1]\"}},\n", b->exposure, b->tonemap);
    rad_bake_text_printf(t, "\"extensionsUsed\": [\"KHR_materials_unlit\"],\n");

    /* Scene and nodes: one per surface, then the camera. */
    rad_bake_text_printf(t, "\"scene\": 0,\n\"scenes\": [{\"nodes\": [");
    for (size_t i = 0; i < n + (size_t)b->has_camera; ++i)
        rad_bake_text_printf(t, "%s%zu", i ? ", " : "", i);
    rad_bake_text_printf(t, "]}],\n\"nodes\": [");
    for (size_t i = 0; i < n; ++i) {
        rad_bake_text_printf(t, "%s\n  {\"name\": ", i ? "," : "");
        rad_bake_text_json_string(t, b->surfaces[i].name);
        rad_bake_text_printf(t, ", \"mesh\": %zu}", i);
    }
    if (b->has_camera) {
        const rad_baked_camera *c = &b->camera;
        rad_bake_text_printf(t, ",\n  {\"name\": \"camera\", \"camera\": 0, \"translation\": ");
        json_float3(t, c->eye);
        rad_bake_text_printf(t, ", \"rotation\": [%.9g, %.9g, %.9g, %.9g]}", c->rotation[0],
                             c->rotation[1], c->rotation[2], c->rotation[3]);
    }
    rad_bake_text_printf(t, "],\n");
    if (b->has_camera) {
        const rad_baked_camera *c = &b->camera;
        rad_bake_text_printf(t, "\"cameras\": [{\"name\": \"camera\", \"type\": \"perspective\", "
                                "\"perspective\": {\"yfov\": %.17g, \"aspectRatio\": %.17g, "
                                "\"znear\": %.9g, \"zfar\": %.9g}}],\n",
                             c->yfov, c->aspect, c->znear, c->zfar);
    }

    /* The material: unlit, base colour 1, so the colour shown is COLOR_0. */
    rad_bake_text_printf(t, "\"materials\": [{\"name\": \"baked radiance\", "
                            "\"pbrMetallicRoughness\": {\"baseColorFactor\": [1, 1, 1, 1], "
                            "\"metallicFactor\": 0, \"roughnessFactor\": 1}, "
                            "\"extensions\": {\"KHR_materials_unlit\": {}}}],\n");

    /* Meshes: accessors 5i .. 5i+4 (and bufferViews alike) are position, normal, colour,
     * radiance and indices of surface i. */
    rad_bake_text_printf(t, "\"meshes\": [");
    for (size_t i = 0; i < n; ++i) {
        rad_bake_text_printf(t, "%s\n  {\"name\": ", i ? "," : "");
        rad_bake_text_json_string(t, b->surfaces[i].name);
        rad_bake_text_printf(t, ", \"primitives\": [{\"attributes\": {\"POSITION\": %zu, "
                                "\"NORMAL\": %zu, \"COLOR_0\": %zu, \"_RADIANCE\": %zu}, "
                                "\"indices\": %zu, \"material\": 0, \"mode\": 4}]}",
                             5 * i, 5 * i + 1, 5 * i + 2, 5 * i + 3, 5 * i + 4);
    }
    rad_bake_text_printf(t, "],\n\"accessors\": [");
    for (size_t i = 0; i < n; ++i) {
        const rad_baked_surface *s = &b->surfaces[i];
        float lo[3], hi[3];
        for (int c = 0; c < 3; ++c) lo[c] = hi[c] = b->position[s->first_vertex][c];
        for (size_t v = s->first_vertex; v < s->first_vertex + s->vertex_count; ++v)
            for (int c = 0; c < 3; ++c) {
                if (b->position[v][c] < lo[c]) lo[c] = b->position[v][c];
                if (b->position[v][c] > hi[c]) hi[c] = b->position[v][c];
            }
        rad_bake_text_printf(t, "%s\n  {\"bufferView\": %zu, \"componentType\": %d, "
                                "\"count\": %zu, \"type\": \"VEC3\", \"min\": ",
                             i ? "," : "", 5 * i, GLTF_FLOAT, s->vertex_count);
        json_float3(t, lo);
        rad_bake_text_printf(t, ", \"max\": ");
        json_float3(t, hi);
        rad_bake_text_printf(t, "},");
        for (size_t a = 1; a <= 3; ++a)
            rad_bake_text_printf(t, "\n  {\"bufferView\": %zu, \"componentType\": %d, "
                                    "\"count\": %zu, \"type\": \"VEC3\"},",
                                 5 * i + a, GLTF_FLOAT, s->vertex_count);
        rad_bake_text_printf(t, "\n  {\"bufferView\": %zu, \"componentType\": %d, \"count\": %zu, "
                                "\"type\": \"SCALAR\"}",
                             5 * i + 4,
                             layout[i].short_indices ? GLTF_UNSIGNED_SHORT : GLTF_UNSIGNED_INT,
                             3 * s->triangle_count);
    }
    rad_bake_text_printf(t, "],\n\"bufferViews\": [");
    for (size_t i = 0; i < n; ++i) {
        const surface_layout *l = &layout[i];
        size_t offsets[4] = {l->positions, l->normals, l->colours, l->radiances};
        for (int a = 0; a < 4; ++a)
            rad_bake_text_printf(t, "%s\n  {\"buffer\": 0, \"byteOffset\": %zu, "
                                    "\"byteLength\": %zu, \"target\": %d}",
                                 i || a ? "," : "", offsets[a], l->attribute_bytes,
                                 GLTF_ARRAY_BUFFER);
        rad_bake_text_printf(t, ",\n  {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu, "
                                "\"target\": %d}",
                             l->indices, l->index_bytes, GLTF_ELEMENT_ARRAY_BUFFER);
    }
    rad_bake_text_printf(t, "],\n\"buffers\": [{\"byteLength\": %zu", total);
    if (bin_path) {
        rad_bake_text_printf(t, ", \"uri\": ");
        rad_bake_text_json_string(t, file_name_of(bin_path));
    }
    rad_bake_text_printf(t, "}]\n}\n");
}

/* GLB: a 12-byte header, then the JSON chunk (padded with spaces) and the BIN chunk (padded with
 * zeros), every chunk a multiple of 4 bytes. */
static void write_glb(FILE *file, const rad_bake_text *json, const uint8_t *buffer, size_t total) {
    size_t json_length = align4(json->length), bin_length = align4(total);
    uint8_t header[12], chunk[8];
    rad_bake_put_u32(header, 0x46546C67u); /* "glTF" */
    rad_bake_put_u32(header + 4, 2);
    rad_bake_put_u32(header + 8, (uint32_t)(12 + 8 + json_length + 8 + bin_length));
    fwrite(header, 1, sizeof header, file);
    rad_bake_put_u32(chunk, (uint32_t)json_length);
    rad_bake_put_u32(chunk + 4, 0x4E4F534Au); /* "JSON" */
    fwrite(chunk, 1, sizeof chunk, file);
    fwrite(json->data, 1, json->length, file);
    for (size_t k = json->length; k < json_length; ++k) fputc(' ', file);
    rad_bake_put_u32(chunk, (uint32_t)bin_length);
    rad_bake_put_u32(chunk + 4, 0x004E4942u); /* "BIN\0" */
    fwrite(chunk, 1, sizeof chunk, file);
    fwrite(buffer, 1, total, file);
    for (size_t k = total; k < bin_length; ++k) fputc(0, file);
}

/* FILE.gltf -> FILE.bin, where the name keeps only RFC 3986 unreserved characters (others
 * become '_'), so the relative URI needs no percent-encoding: assimp 5.2.5 does not decode it. */
static char *bin_path_of(rad_context *ctx, const char *path) {
    const char *dot = strrchr(path, '.');
    size_t stem = dot ? (size_t)(dot - path) : strlen(path);
    size_t name = (size_t)(file_name_of(path) - path);
    char *bin = rad_alloc(ctx, stem + 5, 1);
    if (!bin) return NULL;
    memcpy(bin, path, stem);
    for (size_t k = name; k < stem; ++k) {
        char c = bin[k];
        int unreserved = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                         (c >= '0' && c <= '9') || c == '-' || c == '.' || c == '_' || c == '~';
        if (!unreserved) bin[k] = '_';
    }
    memcpy(bin + stem, ".bin", 5);
    return bin;
}

rad_status rad_bake_write_gltf(const rad_baked_mesh *b, const char *path, int binary) {
    rad_context *ctx = b->ctx;
    surface_layout *layout = rad_alloc_zero(ctx, b->surface_count, sizeof *layout);
    if (!layout) return RAD_ERROR_NO_MEMORY;
    size_t total = 0;
    rad_status status = plan(b, layout, &total);
    uint8_t *buffer = NULL;
    char *bin_path = NULL;
    rad_bake_text json = {ctx, NULL, 0, 0, RAD_OK};
    rad_atomic_file main_file = {0}, bin_file = {0};
    if (status) goto done;
    buffer = rad_alloc_zero(ctx, total ? total : 1, 1);
    if (!buffer) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    fill_buffer(b, layout, buffer);
    if (!binary) {
        bin_path = bin_path_of(ctx, path);
        if (!bin_path) {
            status = RAD_ERROR_NO_MEMORY;
            goto done;
        }
    }
    write_json(b, layout, total, bin_path, &json);
    if ((status = json.status)) goto done;

    if (binary) {
        if ((status = rad_atomic_open(ctx, path, &main_file))) goto done;
        write_glb(main_file.file, &json, buffer, total);
        status = rad_atomic_commit(&main_file);
        goto done;
    }
    /* .gltf + .bin: both temporaries written before either is renamed into place; the .bin
     * first, so that a .gltf never points at a missing buffer. */
    if ((status = rad_atomic_open(ctx, bin_path, &bin_file))) goto done;
    if ((status = rad_atomic_open(ctx, path, &main_file))) goto done;
    fwrite(buffer, 1, total, bin_file.file);
    fwrite(json.data, 1, json.length, main_file.file);
    if ((status = rad_atomic_commit(&bin_file))) goto done;
    if ((status = rad_atomic_commit(&main_file))) unlink(bin_path);

done:
    rad_atomic_abandon(&bin_file);
    rad_atomic_abandon(&main_file);
    rad_bake_text_free(&json);
    rad_free(ctx, bin_path);
    rad_free(ctx, buffer);
    rad_free(ctx, layout);
    return status;
}
