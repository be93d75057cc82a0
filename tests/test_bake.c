/* test_bake.c - baked vertex colours read back: glTF by its own JSON and buffer (parsed here) and
 * by assimp, PLY by its binary records and by assimp, OBJ by assimp. Counts, the unlit material,
 * the camera, and every vertex's value against the solution: the radiance B / pi averaged over
 * the elements around the vertex on its own surface and face, recomputed here by brute force, so
 * a bake that blended across a corner would fail. Bad paths leave no file behind. */
#include "radiosity.h"
#include "test.h"

#include "io/bake.h"
#include "mesh/mesh.h"
#include "image/tonemap.h"
#include "system/system.h"
#include "system/solution_view.h"

#include <assimp/cimport.h>
#include <assimp/scene.h>

#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static rad_context *ctx;
static char directory[64];

/* ------------------------------------------------------------------------------------------- */
/* Files                                                                                        */

static char *path_in(const char *name) {
    static char paths[8][256];
    static int next;
    char *path = paths[next++ % 8];
    snprintf(path, 256, "%s/%s", directory, name);
    return path;
}

static uint8_t *read_all(const char *path, size_t *size) {
    FILE *file = fopen(path, "rb");
    if (!file) return NULL;
    fseek(file, 0, SEEK_END);
    long length = ftell(file);
    fseek(file, 0, SEEK_SET);
    uint8_t *data = malloc((size_t)length + 1);
    *size = fread(data, 1, (size_t)length, file);
    data[*size] = 0;
    fclose(file);
    return data;
}

static int entries_in(const char *path) {
    DIR *dir = opendir(path);
    if (!dir) return -1;
    int count = 0;
    for (struct dirent *e; (e = readdir(dir));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++count;
    closedir(dir);
    return count;
}

static void remove_all(const char *path) {
    DIR *dir = opendir(path);
    if (!dir) return;
    for (struct dirent *e; (e = readdir(dir));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        char child[512];
        snprintf(child, sizeof child, "%s/%s", path, e->d_name);
        struct stat st;
        if (stat(child, &st) == 0 && S_ISDIR(st.st_mode)) remove_all(child);
        else unlink(child);
    }
    closedir(dir);
    rmdir(path);
}

static uint32_t get_u32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float get_f32(const uint8_t *p) {
    union {
        uint32_t u;
        float f;
    } bits = {get_u32(p)};
    return bits.f;
}

/* ------------------------------------------------------------------------------------------- */
/* A minimal JSON reader: enough for glTF.                                                      */

typedef struct json {
    char type; /* 'o' object, 'a' array, 's' string, 'n' number, 'b' true/false/null */
    double number;
    char *string;
    size_t count;
    char **keys;
    struct json *items;
} json;

static const char *skip(const char *p) {
    while (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t') ++p;
    return p;
}

static const char *parse_value(const char *p, json *out);

static const char *parse_string(const char *p, char **out) {
    if (*p != '"') return NULL;
    ++p;
    size_t capacity = 16, length = 0;
    char *s = malloc(capacity);
    while (*p && *p != '"') {
        char c = *p++;
        if (c == '\\') {
            c = *p++;
            if (c == 'n') c = '\n';
            else if (c == 't') c = '\t';
            else if (c == 'u') {
                c = (char)strtol((char[5]){p[0], p[1], p[2], p[3], 0}, NULL, 16);
                p += 4;
            }
        }
        if (length + 2 > capacity) s = realloc(s, capacity *= 2);
        s[length++] = c;
    }
    s[length] = 0;
    *out = s;
    return *p == '"' ? p + 1 : NULL;
}

static const char *parse_value(const char *p, json *out) {
    memset(out, 0, sizeof *out);
    p = skip(p);
    if (*p == '{' || *p == '[') {
        int object = *p == '{';
        out->type = object ? 'o' : 'a';
        p = skip(p + 1);
        if (*p == (object ? '}' : ']')) return p + 1;
        for (;;) {
            out->items = realloc(out->items, (out->count + 1) * sizeof *out->items);
            out->keys = realloc(out->keys, (out->count + 1) * sizeof *out->keys);
            out->keys[out->count] = NULL;
            if (object) {
                p = parse_string(skip(p), &out->keys[out->count]);
                if (!p || *(p = skip(p)) != ':') return NULL;
                ++p;
            }
            p = parse_value(p, &out->items[out->count++]);
            if (!p) return NULL;
            p = skip(p);
            if (*p == ',') {
                ++p;
                continue;
            }
            if (*p == (object ? '}' : ']')) return p + 1;
            return NULL;
        }
    }
    if (*p == '"') {
        out->type = 's';
        return parse_string(p, &out->string);
    }
    if (!strncmp(p, "true", 4) || !strncmp(p, "null", 4)) {
        out->type = 'b';
        out->number = *p == 't';
        return p + 4;
    }
    if (!strncmp(p, "false", 5)) {
        out->type = 'b';
        return p + 5;
    }
    char *end;
    out->type = 'n';
    out->number = strtod(p, &end);
    return end == p ? NULL : end;
}

static void json_free(json *j) {
    for (size_t i = 0; i < j->count; ++i) {
        json_free(&j->items[i]);
        free(j->keys[i]);
    }
    free(j->items);
    free(j->keys);
    free(j->string);
}

static const json *get(const json *j, const char *key) {
    if (!j || j->type != 'o') return NULL;
    for (size_t i = 0; i < j->count; ++i)
        if (!strcmp(j->keys[i], key)) return &j->items[i];
    return NULL;
}

static const json *at(const json *j, size_t index) {
    if (!j || j->type != 'a' || index >= j->count) return NULL;
    return &j->items[index];
}

static double num(const json *j) { return j && j->type == 'n' ? j->number : NAN; }
static size_t count_of(const json *j) { return j ? j->count : 0; }

/* ------------------------------------------------------------------------------------------- */
/* Scenes and the expected values                                                               */

typedef struct solved {
    rad_scene *scene;
    rad_system *system;
    rad_rgb *vertex_radiance; /* per mesh vertex, B / pi */
} solved;

static solved solve(const char *name, size_t elements) {
    solved s = {0};
    CHECK(rad_scene_builtin(ctx, name, &s.scene) == RAD_OK);
    rad_mesh_options mesh = {0, 0, elements, 0, 0};
    CHECK(rad_system_create(ctx, s.scene, &mesh, NULL, &s.system) == RAD_OK);
    rad_solve_options options = {0};
    options.solver = RAD_SOLVER_SHOOTING;
    options.tolerance = 1e-4;
    rad_solve_report report;
    CHECK(rad_solve(s.system, &options, &report) == RAD_OK);
    const rad_mesh *m = rad_solution_leaves(rad_system_view(s.system));
    s.vertex_radiance = malloc(m->vertex_count * sizeof *s.vertex_radiance);
    CHECK(rad_solution_vertex_radiosity(rad_system_view(s.system), ctx, 0, s.vertex_radiance) ==
          RAD_OK);
    for (size_t v = 0; v < m->vertex_count; ++v)
        for (int c = 0; c < 3; ++c) s.vertex_radiance[v][c] /= RAD_PI;
    return s;
}

static void solved_free(solved *s) {
    free(s->vertex_radiance);
    rad_system_destroy(s->system);
    rad_scene_destroy(s->scene);
}

static size_t surface_index(const rad_system *system, const char *name) {
    for (size_t i = 0; i < system->surface_count; ++i)
        if (!strcmp(system->surface_name[i], name)) return i;
    return SIZE_MAX;
}

/* The k-th vertex of a surface, in mesh order (the bake keeps that order within a surface). */
static size_t nth_vertex(const rad_mesh *mesh, size_t surface, size_t k) {
    for (size_t v = 0; v < mesh->vertex_count; ++v)
        if (mesh->vertex_surface[v] == surface && k-- == 0) return v;
    return SIZE_MAX;
}

static size_t vertices_of(const rad_mesh *mesh, size_t surface) {
    size_t n = 0;
    for (size_t v = 0; v < mesh->vertex_count; ++v) n += mesh->vertex_surface[v] == surface;
    return n;
}

static size_t triangles_of(const rad_mesh *mesh, size_t surface) {
    size_t n = 0;
    for (size_t e = 0; e < mesh->element_count; ++e)
        if (mesh->element_surface[e] == surface) n += rad_mesh_corner_count(mesh, e) == 4 ? 2 : 1;
    return n;
}

/* Brute force, independent of the mesh's vertex sharing: the area-weighted mean of B / pi over
 * the elements of `surface` that have a corner at `position` and face the way `normal` does. */
static void expected_at(const rad_system *system, size_t surface, const float position[3],
                        const float normal[3], double out[3]) {
    const rad_mesh *mesh = system->mesh;
    double sum[3] = {0, 0, 0}, weight = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        if (mesh->element_surface[e] != surface) continue;
        rad_vec3 n = mesh->element_normal[e];
        if (n.x * normal[0] + n.y * normal[1] + n.z * normal[2] < 0.99) continue;
        int touches = 0;
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            rad_vec3 p = mesh->vertices[mesh->element_vertices[e][k]];
            if ((float)p.x == position[0] && (float)p.y == position[1] && (float)p.z == position[2])
                touches = 1;
        }
        if (!touches) continue;
        weight += system->area[e];
        for (int c = 0; c < 3; ++c) sum[c] += system->area[e] * system->radiosity[e][c] / RAD_PI;
    }
    for (int c = 0; c < 3; ++c) out[c] = weight > 0 ? sum[c] / weight : NAN;
}

static int near_rgb(const float value[3], const double expected[3], double relative) {
    for (int c = 0; c < 3; ++c)
        if (!(fabs(value[c] - expected[c]) <= relative * fmax(fabs(expected[c]), 1e-6))) return 0;
    return 1;
}

/* ------------------------------------------------------------------------------------------- */
/* glTF                                                                                         */

/* The bytes a glTF accessor covers, checked against its bufferView and the buffer. */
static const uint8_t *accessor_data(const json *root, const uint8_t *buffer, size_t buffer_size,
                                    size_t accessor, size_t element_size, size_t *count) {
    const json *a = at(get(root, "accessors"), accessor);
    const json *view = at(get(root, "bufferViews"), (size_t)num(get(a, "bufferView")));
    *count = (size_t)num(get(a, "count"));
    size_t offset = (size_t)num(get(view, "byteOffset")), length = (size_t)num(get(view, "byteLength"));
    CHECK(offset % 4 == 0);
    CHECK(offset + length <= buffer_size);
    CHECK(*count * element_size <= length);
    return offset + length <= buffer_size ? buffer + offset : NULL;
}

/* Checks a glTF (its JSON and buffer) against the solution: counts, names, the unlit material,
 * POSITION bounds, and every vertex colour. Returns the number of vertices checked. */
static size_t check_gltf(const solved *s, const json *root, const uint8_t *buffer, size_t size) {
    const rad_system *system = s->system;
    const rad_mesh *mesh = system->mesh;
    CHECK(!strcmp(get(get(root, "asset"), "version")->string, "2.0"));
    const json *used = get(root, "extensionsUsed");
    int unlit_used = 0;
    for (size_t i = 0; i < count_of(used); ++i) unlit_used |= !strcmp(at(used, i)->string, "KHR_materials_unlit");
    CHECK(unlit_used);
    const json *material = at(get(root, "materials"), 0);
    CHECK(get(get(material, "extensions"), "KHR_materials_unlit") != NULL);
    const json *base = get(get(material, "pbrMetallicRoughness"), "baseColorFactor");
    for (size_t c = 0; c < 4; ++c) CHECK(num(at(base, c)) == 1);
    CHECK(num(get(at(get(root, "buffers"), 0), "byteLength")) <= size);

    const json *meshes = get(root, "meshes");
    CHECK(count_of(meshes) == system->surface_count);
    size_t checked = 0, total_vertices = 0;
    for (size_t i = 0; i < count_of(meshes); ++i) {
        const json *m = at(meshes, i);
        size_t surface = surface_index(system, get(m, "name")->string);
        CHECK(surface != SIZE_MAX);
        if (surface == SIZE_MAX) continue;
        const json *node = at(get(root, "nodes"), i);
        CHECK(num(get(node, "mesh")) == i && !strcmp(get(node, "name")->string, system->surface_name[surface]));
        const json *primitive = at(get(m, "primitives"), 0);
        CHECK(num(get(primitive, "mode")) == 4 && num(get(primitive, "material")) == 0);
        const json *attributes = get(primitive, "attributes");
        size_t position_accessor = (size_t)num(get(attributes, "POSITION"));
        size_t colour_accessor = (size_t)num(get(attributes, "COLOR_0"));
        size_t radiance_accessor = (size_t)num(get(attributes, "_RADIANCE"));
        size_t normal_accessor = (size_t)num(get(attributes, "NORMAL"));
        const json *colour_info = at(get(root, "accessors"), colour_accessor);
        CHECK(num(get(colour_info, "componentType")) == 5126);
        CHECK(!strcmp(get(colour_info, "type")->string, "VEC3"));
        size_t n, n_colour, n_normal, n_index, n_radiance;
        const uint8_t *positions = accessor_data(root, buffer, size, position_accessor, 12, &n);
        const uint8_t *colours = accessor_data(root, buffer, size, colour_accessor, 12, &n_colour);
        const uint8_t *normals = accessor_data(root, buffer, size, normal_accessor, 12, &n_normal);
        const uint8_t *radiances = accessor_data(root, buffer, size, radiance_accessor, 12, &n_radiance);
        const json *index_info = at(get(root, "accessors"), (size_t)num(get(primitive, "indices")));
        size_t index_size = num(get(index_info, "componentType")) == 5123 ? 2 : 4;
        const uint8_t *indices = accessor_data(root, buffer, size, (size_t)num(get(primitive, "indices")),
                                               index_size, &n_index);
        CHECK(n == vertices_of(mesh, surface) && n_colour == n && n_normal == n && n_radiance == n);
        CHECK(n_index == 3 * triangles_of(mesh, surface));
        if (!positions || !colours || !normals || !radiances || !indices) continue;
        total_vertices += n;
        /* Indices in range and counter-clockwise like the elements: the triangle's normal
         * agrees with the vertex normals. */
        int in_range = 1, facing = 1;
        for (size_t t = 0; t + 2 < n_index; t += 3) {
            uint32_t k[3];
            for (int j = 0; j < 3; ++j) {
                const uint8_t *p = indices + (t + j) * index_size;
                k[j] = index_size == 2 ? (uint32_t)(p[0] | p[1] << 8) : get_u32(p);
                if (k[j] >= n) in_range = 0;
            }
            if (!in_range) break;
            float a[3], b[3], c[3], nn[3];
            for (int d = 0; d < 3; ++d) {
                a[d] = get_f32(positions + 12 * k[0] + 4 * d);
                b[d] = get_f32(positions + 12 * k[1] + 4 * d);
                c[d] = get_f32(positions + 12 * k[2] + 4 * d);
                nn[d] = get_f32(normals + 12 * k[0] + 4 * d);
            }
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double cross[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            if (cross[0] * nn[0] + cross[1] * nn[1] + cross[2] * nn[2] <= 0) facing = 0;
        }
        CHECK(in_range);
        CHECK(facing);
        /* POSITION min/max: what the data holds. */
        const json *info = at(get(root, "accessors"), position_accessor);
        for (int c = 0; c < 3; ++c) {
            float lo = INFINITY, hi = -INFINITY;
            for (size_t v = 0; v < n; ++v) {
                float x = get_f32(positions + 12 * v + 4 * c);
                lo = fminf(lo, x);
                hi = fmaxf(hi, x);
            }
            CHECK((float)num(at(get(info, "min"), (size_t)c)) == lo);
            CHECK((float)num(at(get(info, "max"), (size_t)c)) == hi);
        }
        /* Every vertex: _RADIANCE is the solution's vertex radiance and the brute-force mean on
         * its side of every corner; COLOR_0 is the same, clipped to [0, 1] (the defaults:
         * exposure 0, tone curve clamp). */
        int same_as_solution = 1, same_as_brute_force = 1, colour_clipped = 1;
        for (size_t v = 0; v < n; ++v) {
            float p[3], colour[3], normal[3], radiance[3];
            for (int c = 0; c < 3; ++c) {
                p[c] = get_f32(positions + 12 * v + 4 * c);
                colour[c] = get_f32(colours + 12 * v + 4 * c);
                normal[c] = get_f32(normals + 12 * v + 4 * c);
                radiance[c] = get_f32(radiances + 12 * v + 4 * c);
            }
            size_t mv = nth_vertex(mesh, surface, v);
            double expected[3];
            expected_at(system, surface, p, normal, expected);
            for (int c = 0; c < 3; ++c) {
                if (radiance[c] != (float)s->vertex_radiance[mv][c]) same_as_solution = 0;
                if (colour[c] != fminf(radiance[c], 1.0f)) colour_clipped = 0;
            }
            if (!near_rgb(radiance, expected, 1e-5)) same_as_brute_force = 0;
            ++checked;
        }
        CHECK(same_as_solution);
        CHECK(same_as_brute_force);
        CHECK(colour_clipped);
    }
    CHECK(total_vertices == mesh->vertex_count);
    return checked;
}

/* A GLB: header, chunks and padding, then the glTF checks. */
static void test_glb(void) {
    solved s = solve("unit-cube", 150);
    const char *path = path_in("cube.glb");
    CHECK(rad_bake(s.system, path, &(rad_bake_options){.scene = s.scene}) == RAD_OK);
    size_t size;
    uint8_t *file = read_all(path, &size);
    CHECK(file && size > 28);
    if (!file) return;
    CHECK(!memcmp(file, "glTF", 4) && get_u32(file + 4) == 2 && get_u32(file + 8) == size);
    uint32_t json_length = get_u32(file + 12), bin_length = get_u32(file + 20 + json_length);
    CHECK(!memcmp(file + 16, "JSON", 4) && json_length % 4 == 0);
    CHECK(!memcmp(file + 24 + json_length, "BIN\0", 4) && bin_length % 4 == 0);
    CHECK(28 + json_length + bin_length == size);
    char *text = malloc(json_length + 1);
    memcpy(text, file + 20, json_length);
    text[json_length] = 0;
    json root;
    const char *parsed = parse_value(text, &root);
    CHECK(parsed != NULL && *skip(parsed) == 0); /* only spaces pad the chunk */
    CHECK(get(&root, "cameras") != NULL);             /* the unit cube's own camera */
    size_t checked = check_gltf(&s, &root, file + 28 + json_length, bin_length);
    CHECK(checked == s.system->mesh->vertex_count);

    /* Seams: at a corner of the cube, three surfaces each keep their own value. */
    const float corner[3] = {0, 0, 1};
    int found = 0;
    double values[3] = {0};
    for (size_t i = 0; i < s.system->surface_count && found < 3; ++i)
        for (size_t k = 0; k < vertices_of(s.system->mesh, i); ++k) {
            rad_vec3 p = s.system->mesh->vertices[nth_vertex(s.system->mesh, i, k)];
            if ((float)p.x == corner[0] && (float)p.y == corner[1] && (float)p.z == corner[2])
                values[found++] = s.vertex_radiance[nth_vertex(s.system->mesh, i, k)][0];
        }
    CHECK(found == 3);
    CHECK(values[0] != values[1] || values[1] != values[2]);
    json_free(&root);
    free(text);
    free(file);
    solved_free(&s);
}

/* .gltf + .bin, with the Cornell box's camera. */
static void test_gltf_camera(void) {
    solved s = solve("cornell", 300);
    const char *path = path_in("cornell box.gltf");
    CHECK(rad_bake(s.system, path, &(rad_bake_options){.scene = s.scene, .aspect = 1.5}) == RAD_OK);
    size_t size, bin_size;
    char *text = (char *)read_all(path, &size);
    uint8_t *bin = read_all(path_in("cornell_box.bin"), &bin_size); /* no space: see bake_gltf.c */
    CHECK(text && bin);
    if (!text || !bin) return;
    json root;
    CHECK(parse_value(text, &root) != NULL);
    const json *buffer = at(get(&root, "buffers"), 0);
    CHECK(!strcmp(get(buffer, "uri")->string, "cornell_box.bin"));
    CHECK(num(get(buffer, "byteLength")) == bin_size);
    size_t checked = check_gltf(&s, &root, bin, bin_size);
    CHECK(checked == s.system->mesh->vertex_count);

    /* The short block is one surface of five faces: its vertical edges are creases, so their
     * positions carry one vertex per face. */
    size_t block = surface_index(s.system, "short-block");
    CHECK(block != SIZE_MAX && vertices_of(s.system->mesh, block) > 0);

    /* The camera: eye (278, 273, -800) looking along +z, up +y, 39.3077 degrees. */
    const json *camera = at(get(&root, "cameras"), 0);
    const json *perspective = get(camera, "perspective");
    CHECK(!strcmp(get(camera, "type")->string, "perspective"));
    CHECK_NEAR(num(get(perspective, "yfov")), 39.3077 * RAD_PI / 180, 1e-12);
    CHECK_NEAR(num(get(perspective, "aspectRatio")), 1.5, 1e-12);
    double znear = num(get(perspective, "znear")), zfar = num(get(perspective, "zfar"));
    /* The box is 800 to 1359.2 mm in front of the eye: all of it between the clip planes, with
     * near far enough out for the depth buffer to separate the lamp from the ceiling (0.1 mm). */
    CHECK(zfar > 800 + 559.2 && znear < 800 && znear > 100);
    const json *node = at(get(&root, "nodes"), s.system->surface_count);
    CHECK(num(get(node, "camera")) == 0);
    const json *t = get(node, "translation"), *r = get(node, "rotation");
    CHECK_NEAR(num(at(t, 0)), 278, 1e-4);
    CHECK_NEAR(num(at(t, 1)), 273, 1e-4);
    CHECK_NEAR(num(at(t, 2)), -800, 1e-4);
    /* Rotate the camera's -Z and +Y by the quaternion: forward (0, 0, 1), up (0, 1, 0). */
    double qx = num(at(r, 0)), qy = num(at(r, 1)), qz = num(at(r, 2)), qw = num(at(r, 3));
    double forward[3] = {-(2 * (qx * qz + qw * qy)), -(2 * (qy * qz - qw * qx)), -(1 - 2 * (qx * qx + qy * qy))};
    double up[3] = {2 * (qx * qy - qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qw * qx)};
    CHECK_NEAR(forward[0], 0, 1e-6);
    CHECK_NEAR(forward[1], 0, 1e-6);
    CHECK_NEAR(forward[2], 1, 1e-6);
    CHECK_NEAR(up[0], 0, 1e-6);
    CHECK_NEAR(up[1], 1, 1e-6);
    CHECK_NEAR(up[2], 0, 1e-6);
    CHECK(get(get(&root, "scenes")->items, "nodes")->count == s.system->surface_count + 1);

    /* assimp reads it back: one mesh per surface, triangles, the colours. */
    const struct aiScene *scene = aiImportFile(path, 0);
    CHECK(scene != NULL);
    if (scene) {
        CHECK(scene->mNumMeshes == s.system->surface_count);
        CHECK(scene->mNumCameras == 1);
        size_t vertices = 0;
        int colours_match = 1;
        for (unsigned int i = 0; i < scene->mNumMeshes; ++i) {
            const struct aiMesh *m = scene->mMeshes[i];
            size_t surface = surface_index(s.system, m->mName.data);
            CHECK(surface != SIZE_MAX);
            if (surface == SIZE_MAX) continue;
            CHECK(m->mNumFaces == triangles_of(s.system->mesh, surface));
            CHECK(m->mColors[0] != NULL);
            vertices += m->mNumVertices;
            for (unsigned int v = 0; v < m->mNumVertices && m->mColors[0]; ++v) {
                float colour[3] = {m->mColors[0][v].r, m->mColors[0][v].g, m->mColors[0][v].b};
                float p[3] = {m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z};
                float normal[3] = {m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z};
                double expected[3];
                expected_at(s.system, surface, p, normal, expected);
                for (int c = 0; c < 3; ++c) expected[c] = fmin(expected[c], 1);
                if (!near_rgb(colour, expected, 1e-5)) colours_match = 0;
            }
        }
        CHECK(vertices == s.system->mesh->vertex_count);
        CHECK(colours_match);
        aiReleaseImport(scene);
    }
    json_free(&root);
    free(text);
    free(bin);
    solved_free(&s);
}

/* ------------------------------------------------------------------------------------------- */
/* PLY and OBJ                                                                                  */

static void test_ply(void) {
    solved s = solve("unit-cube", 150);
    const char *path = path_in("cube.ply");
    rad_bake_options options = {.exposure = 1.5, .tonemap = "reinhard"};
    CHECK(rad_bake(s.system, path, &options) == RAD_OK);
    size_t size;
    uint8_t *file = read_all(path, &size);
    CHECK(file != NULL);
    if (!file) return;
    const char *end = strstr((char *)file, "end_header\n");
    CHECK(end != NULL);
    CHECK(strstr((char *)file, "format binary_little_endian 1.0\n") != NULL);
    CHECK(strstr((char *)file, "property uchar red\nproperty uchar green\nproperty uchar blue\n"));
    CHECK(strstr((char *)file, "property float radiance_r\n") != NULL);
    const rad_mesh *mesh = s.system->mesh;
    size_t vertices = 0, faces = 0;
    const char *v = strstr((char *)file, "element vertex "), *f = strstr((char *)file, "element face ");
    if (v) vertices = strtoul(v + 15, NULL, 10);
    if (f) faces = strtoul(f + 13, NULL, 10);
    CHECK(vertices == mesh->vertex_count && faces == mesh->element_count);
    if (!end || vertices != mesh->vertex_count) return;
    /* Records: x y z nx ny nz (float) red green blue (uchar) radiance_r g b (float). Surfaces in
     * order, each surface's vertices in mesh order. */
    const uint8_t *record = (const uint8_t *)end + strlen("end_header\n");
    int radiance_ok = 1, display_ok = 1, brute_ok = 1;
    size_t k = 0;
    for (size_t surface = 0; surface < s.system->surface_count; ++surface)
        for (size_t j = 0; j < vertices_of(mesh, surface); ++j, ++k, record += 39) {
            size_t mv = nth_vertex(mesh, surface, j);
            float p[3], n[3], radiance[3], shown[3];
            for (int c = 0; c < 3; ++c) {
                p[c] = get_f32(record + 4 * c);
                n[c] = get_f32(record + 12 + 4 * c);
                radiance[c] = get_f32(record + 27 + 4 * c);
            }
            float linear[3] = {(float)s.vertex_radiance[mv][0], (float)s.vertex_radiance[mv][1],
                               (float)s.vertex_radiance[mv][2]};
            rad_tonemap_apply(RAD_TONEMAP_REINHARD, 1.5, linear, shown);
            for (int c = 0; c < 3; ++c) {
                if (radiance[c] != linear[c]) radiance_ok = 0;
                if (record[24 + c] != rad_srgb_encode(shown[c])) display_ok = 0;
            }
            double expected[3];
            expected_at(s.system, surface, p, n, expected);
            if (!near_rgb(radiance, expected, 1e-5)) brute_ok = 0;
        }
    CHECK(radiance_ok);
    CHECK(display_ok);
    CHECK(brute_ok);
    CHECK(record <= file + size);
    /* Faces: a count byte and uint indices; the file ends with the last face. */
    size_t face_bytes = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) face_bytes += 1 + 4 * (size_t)rad_mesh_corner_count(mesh, e);
    CHECK(record + face_bytes == file + size);
    free(file);

    /* assimp reads it: the vertices and their 8-bit colours. */
    const struct aiScene *scene = aiImportFile(path, 0);
    CHECK(scene != NULL && scene->mNumMeshes >= 1);
    if (scene) {
        size_t faces_read = 0;
        int coloured = 1;
        for (unsigned int i = 0; i < scene->mNumMeshes; ++i) {
            faces_read += scene->mMeshes[i]->mNumFaces;
            if (!scene->mMeshes[i]->mColors[0]) coloured = 0;
        }
        CHECK(faces_read == mesh->element_count);
        CHECK(coloured);
        aiReleaseImport(scene);
    }
    solved_free(&s);
}

static void test_obj(void) {
    solved s = solve("unit-cube", 150);
    const char *path = path_in("cube.obj");
    CHECK(rad_bake(s.system, path, &(rad_bake_options){.exposure = 2}) == RAD_OK);
    const struct aiScene *scene = aiImportFile(path, 0);
    CHECK(scene != NULL);
    if (scene) {
        CHECK(scene->mNumMeshes == s.system->surface_count);
        int colours_match = 1, named = 1;
        size_t faces = 0;
        for (unsigned int i = 0; i < scene->mNumMeshes; ++i) {
            const struct aiMesh *m = scene->mMeshes[i];
            size_t surface = surface_index(s.system, m->mName.data);
            if (surface == SIZE_MAX) {
                named = 0;
                continue;
            }
            faces += m->mNumFaces;
            CHECK(m->mColors[0] != NULL);
            for (unsigned int v = 0; v < m->mNumVertices && m->mColors[0]; ++v) {
                float p[3] = {m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z};
                /* The cube's faces are flat: the face normal of the surface's first element. */
                rad_vec3 n = s.system->mesh->element_normal[0];
                for (size_t e = 0; e < s.system->mesh->element_count; ++e)
                    if (s.system->mesh->element_surface[e] == surface) {
                        n = s.system->mesh->element_normal[e];
                        break;
                    }
                float normal[3] = {(float)n.x, (float)n.y, (float)n.z};
                double expected[3];
                float linear[3], shown[3];
                expected_at(s.system, surface, p, normal, expected);
                for (int c = 0; c < 3; ++c) linear[c] = (float)expected[c];
                rad_tonemap_apply(RAD_TONEMAP_CLAMP, 2, linear, shown);
                for (int c = 0; c < 3; ++c) {
                    float colour = c == 0 ? m->mColors[0][v].r : c == 1 ? m->mColors[0][v].g : m->mColors[0][v].b;
                    /* The value written is one of the 256 display levels; allow one level for
                     * the float rounding of the brute-force mean. */
                    if (fabsf(colour * 255 - rad_srgb_encode(shown[c])) > 1.0001f) colours_match = 0;
                }
            }
        }
        CHECK(named);
        CHECK(colours_match);
        CHECK(faces == s.system->mesh->element_count);
        aiReleaseImport(scene);
    }
    /* The text: the vertex-colour extension and a group per surface. */
    size_t size;
    char *text = (char *)read_all(path, &size);
    CHECK(text && strstr(text, "\no top\ng top\n") && strstr(text, "\no bottom\ng bottom\n"));
    int six = 0;
    for (char *line = text ? strstr(text, "\nv ") : NULL; line && six == 0; line = NULL) {
        double x[6];
        six = sscanf(line, "\nv %lf %lf %lf %lf %lf %lf", &x[0], &x[1], &x[2], &x[3], &x[4], &x[5]) == 6;
    }
    CHECK(six);
    free(text);
    solved_free(&s);
}

/* The writers on a made-up mesh: a surface of more than 65534 vertices needs 32-bit indices,
 * and a name with quotes, a backslash and spaces must survive JSON (and become one OBJ word). */
static void test_large_and_odd_names(void) {
    enum { COLUMNS = 400, ROWS = 200 }; /* 401 x 201 = 80601 vertices, 80000 quads */
    size_t nv = (COLUMNS + 1) * (ROWS + 1), nf = COLUMNS * ROWS;
    rad_baked_surface surfaces[2] = {
        {"wall \"north\"\\ 1", 0, nv, 0, nf, 2 * nf},
        {"tiny", nv, 3, nf, 1, 1},
    };
    rad_baked_mesh b = {0};
    b.ctx = ctx;
    b.surface_count = 2;
    b.surfaces = surfaces;
    b.vertex_count = nv + 3;
    b.face_count = nf + 1;
    b.position = calloc(b.vertex_count, sizeof *b.position);
    b.normal = calloc(b.vertex_count, sizeof *b.normal);
    b.radiance = calloc(b.vertex_count, sizeof *b.radiance);
    b.shown = calloc(b.vertex_count, sizeof *b.shown);
    b.display = calloc(b.vertex_count, sizeof *b.display);
    b.face = calloc(b.face_count, sizeof *b.face);
    b.tonemap = "clamp";
    b.generator = "test";
    for (size_t j = 0; j <= ROWS; ++j)
        for (size_t i = 0; i <= COLUMNS; ++i) {
            size_t v = j * (COLUMNS + 1) + i;
            b.position[v][0] = (float)i;
            b.position[v][1] = (float)j;
            b.normal[v][2] = 1;
            b.radiance[v][0] = b.shown[v][0] = (float)v / (float)nv;
        }
    for (size_t j = 0; j < ROWS; ++j)
        for (size_t i = 0; i < COLUMNS; ++i) {
            uint32_t v = (uint32_t)(j * (COLUMNS + 1) + i);
            uint32_t *f = b.face[j * COLUMNS + i];
            f[0] = v;
            f[1] = v + 1;
            f[2] = v + COLUMNS + 2;
            f[3] = v + COLUMNS + 1;
        }
    for (int k = 0; k < 3; ++k) {
        b.position[nv + k][k] = 1;
        b.normal[nv + k][2] = 1;
        b.face[nf][k] = (uint32_t)k;
    }
    b.face[nf][3] = RAD_BAKED_NO_VERTEX;

    const char *path = path_in("large.glb");
    CHECK(rad_bake_write_gltf(&b, path, 1) == RAD_OK);
    size_t size;
    uint8_t *file = read_all(path, &size);
    if (file && size > 28) {
        uint32_t json_length = get_u32(file + 12);
        char *text = malloc(json_length + 1);
        memcpy(text, file + 20, json_length);
        text[json_length] = 0;
        json root;
        CHECK(parse_value(text, &root) != NULL);
        const json *m0 = at(get(&root, "meshes"), 0), *m1 = at(get(&root, "meshes"), 1);
        CHECK(m0 && !strcmp(get(m0, "name")->string, surfaces[0].name));
        const json *p0 = at(get(m0, "primitives"), 0), *p1 = at(get(m1, "primitives"), 0);
        const json *i0 = at(get(&root, "accessors"), (size_t)num(get(p0, "indices")));
        const json *i1 = at(get(&root, "accessors"), (size_t)num(get(p1, "indices")));
        CHECK(num(get(i0, "componentType")) == 5125 && num(get(i0, "count")) == 6.0 * nf);
        CHECK(num(get(i1, "componentType")) == 5123 && num(get(i1, "count")) == 3);
        /* The last triangle of the big surface: the far corner, 32-bit. */
        const uint8_t *bin = file + 28 + json_length;
        size_t n_index;
        const uint8_t *index = accessor_data(&root, bin, get_u32(file + 20 + json_length),
                                             (size_t)num(get(p0, "indices")), 4, &n_index);
        if (index) {
            uint32_t last[3] = {get_u32(index + 4 * (n_index - 3)), get_u32(index + 4 * (n_index - 2)),
                                get_u32(index + 4 * (n_index - 1))};
            CHECK(last[1] == nv - 1 && last[0] == nv - COLUMNS - 3 && last[2] == nv - 2);
        }
        /* The short indices are padded: the next bufferView starts on 4 bytes (checked by
         * accessor_data); and the file is what the header says. */
        CHECK(get_u32(file + 8) == size);
        json_free(&root);
        free(text);
    }
    free(file);

    const char *obj = path_in("large.obj");
    CHECK(rad_bake_write_obj(&b, obj) == RAD_OK);
    char *text = (char *)read_all(obj, &size);
    CHECK(text && strstr(text, "\ng wall_\"north\"\\_1\n") != NULL);
    free(text);
    free(b.position);
    free(b.normal);
    free(b.radiance);
    free(b.shown);
    free(b.display);
    free(b.face);
}

/* ------------------------------------------------------------------------------------------- */
/* Bad input: one clear error, nothing left behind                                              */

/* bake --final-gather (render.c, rad_renderer_vertex_radiosity): each vertex gathered again.
 * On the unit cube lit from its top, the face "bottom" (z = 0)'s gathered radiances average
 * within 3% of the element means' (the same light found again; measured 1.8% lower, its edges
 * darker), while its four corners, which the element means place half an element inside, come
 * out darker than those (measured 13-14%: a concave corner sees less of the lamp); the same
 * bytes for 1 and 2 threads; without the scene the bake is refused and writes nothing. */
static void test_final_gather(void) {
    solved s = solve("unit-cube", 600);
    const rad_mesh *mesh = rad_solution_leaves(rad_system_view(s.system));
    size_t face = surface_index(s.system, "bottom");
    rad_bake_options options = {.tonemap = "none", .scene = s.scene, .final_gather = 256};
    const char *path = path_in("gathered.ply");
    CHECK(rad_bake(s.system, path, &options) == RAD_OK);
    size_t size = 0;
    uint8_t *file = read_all(path, &size);
    const char *end = file ? strstr((char *)file, "end_header\n") : NULL;
    CHECK(end != NULL);
    if (!end) {
        free(file);
        solved_free(&s);
        return;
    }
    const uint8_t *record = (const uint8_t *)end + strlen("end_header\n");
    double gathered = 0, averaged = 0;
    int finite = 1, corners = 0, darker = 0;
    size_t k = 0, count = 0;
    for (size_t surface = 0; surface < s.system->surface_count; ++surface)
        for (size_t j = 0; j < vertices_of(mesh, surface); ++j, ++k, record += 39) {
            size_t mv = nth_vertex(mesh, surface, j);
            float p[3], radiance[3];
            for (int c = 0; c < 3; ++c) {
                p[c] = get_f32(record + 4 * c);
                radiance[c] = get_f32(record + 27 + 4 * c);
                if (!isfinite(radiance[c]) || radiance[c] < 0) finite = 0;
            }
            if (surface != face) continue;
            gathered += radiance[1];
            averaged += s.vertex_radiance[mv][1];
            ++count;
            int corner = 1; /* a corner of the cube: every coordinate 0 or 1 */
            for (int c = 0; c < 3; ++c) corner &= fabsf(p[c]) < 1e-6f || fabsf(p[c] - 1) < 1e-6f;
            if (corner) {
                ++corners;
                darker += radiance[1] < 0.9 * s.vertex_radiance[mv][1];
            }
        }
    printf("bake --final-gather 256: a face's mean %.5f against the element means' %.5f (%zu "
           "vertices), %d of %d corners below 0.9 of theirs\n",
           gathered / (double)count, averaged / (double)count, count, darker, corners);
    CHECK(finite);
    CHECK(count > 0 && fabs(gathered / averaged - 1) < 0.03);
    CHECK(corners == 4 && darker == 4);

    /* The same file with one thread. */
    rad_context *one = NULL;
    CHECK(rad_context_create(&(rad_context_options){.threads = 1}, &one) == RAD_OK);
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_mesh_options mesh_options = {0, 0, 600, 0, 0};
    rad_solve_options solve_options = {.solver = RAD_SOLVER_SHOOTING, .tolerance = 1e-4};
    CHECK(rad_scene_builtin(one, "unit-cube", &scene) == RAD_OK);
    CHECK(rad_system_create(one, scene, &mesh_options, NULL, &system) == RAD_OK);
    CHECK(rad_solve(system, &solve_options, NULL) == RAD_OK);
    options.scene = scene;
    const char *again = path_in("gathered-1.ply");
    CHECK(rad_bake(system, again, &options) == RAD_OK);
    size_t size_one = 0;
    uint8_t *file_one = read_all(again, &size_one);
    CHECK(file_one && size_one == size && memcmp(file_one, file, size) == 0);
    free(file_one);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(one);

    /* No scene: refused, nothing written. */
    options.scene = NULL;
    const char *refused = path_in("refused.ply");
    CHECK(rad_bake(s.system, refused, &options) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(access(refused, F_OK) != 0);
    options.scene = s.scene;
    options.final_gather = -1;
    CHECK(rad_bake(s.system, refused, &options) == RAD_ERROR_INVALID_ARGUMENT);
    free(file);
    solved_free(&s);
}

static void test_errors(void) {
    solved s = solve("unit-cube", 24);
    char dir[128];
    snprintf(dir, sizeof dir, "%s/errors", directory);
    mkdir(dir, 0700);
    char path[256];

    snprintf(path, sizeof path, "%s/out.png", dir);
    CHECK(rad_bake(s.system, path, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "unknown bake format") != NULL);
    CHECK(rad_bake_check(ctx, path, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(rad_bake_format_of("a/B.GLB") == RAD_BAKE_GLB && rad_bake_format_of(".obj") == RAD_BAKE_AUTO);
    CHECK(rad_bake_format_of("x.gltf") == RAD_BAKE_GLTF && rad_bake_format_of("dir.ply/") == RAD_BAKE_AUTO);

    snprintf(path, sizeof path, "%s/out.ply", dir);
    CHECK(rad_bake(s.system, path, &(rad_bake_options){.tonemap = "filmic"}) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(rad_bake_check(ctx, path, NULL) == RAD_OK);

    /* A directory that does not exist, and a "directory" that is a file. */
    snprintf(path, sizeof path, "%s/missing/out.glb", dir);
    CHECK(rad_bake_check(ctx, path, NULL) == RAD_ERROR_IO);
    CHECK(rad_bake(s.system, path, NULL) == RAD_ERROR_IO);
    CHECK(strstr(rad_context_error(ctx), "missing/out.glb") != NULL);
    snprintf(path, sizeof path, "%s/file", dir);
    FILE *file = fopen(path, "w");
    if (file) fclose(file);
    snprintf(path, sizeof path, "%s/file/out.gltf", dir);
    CHECK(rad_bake(s.system, path, NULL) == RAD_ERROR_IO);
    CHECK(entries_in(dir) == 1);

    /* A .gltf whose rename fails (a directory is in the way) takes its .bin away again. */
    snprintf(path, sizeof path, "%s/busy.gltf", dir);
    mkdir(path, 0700);
    snprintf(path, sizeof path, "%s/busy.gltf/inside", dir);
    file = fopen(path, "w");
    if (file) fclose(file);
    snprintf(path, sizeof path, "%s/busy.gltf", dir);
    CHECK(rad_bake(s.system, path, NULL) == RAD_ERROR_IO);
    CHECK(entries_in(dir) == 2); /* file, busy.gltf: no busy.bin, no temporaries */

    /* A patch system has no geometry. */
    rad_patch_desc patches[2] = {{"a", 1, {0.5, 0.5, 0.5}, {1, 1, 1}}, {"b", 1, {0.5, 0.5, 0.5}, {0, 0, 0}}};
    float ff[4] = {0, 1, 1, 0};
    rad_system *dense = NULL;
    CHECK(rad_system_create_dense(ctx, patches, 2, ff, &dense) == RAD_OK);
    snprintf(path, sizeof path, "%s/dense.glb", dir);
    CHECK(rad_bake(dense, path, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(entries_in(dir) == 2);
    rad_system_destroy(dense);
    solved_free(&s);
}

int main(void) {
    CHECK(rad_context_create(&(rad_context_options){.threads = 2}, &ctx) == RAD_OK);
    snprintf(directory, sizeof directory, "/tmp/test_bake-XXXXXX");
    CHECK(mkdtemp(directory) != NULL);
    test_glb();
    test_gltf_camera();
    test_ply();
    test_obj();
    test_large_and_odd_names();
    test_final_gather();
    test_errors();
    remove_all(directory);
    rad_context_destroy(ctx);
    return test_finish();
}
