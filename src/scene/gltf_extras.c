/* gltf_extras.c - reads the few glTF 2.0 values assimp 5.2.5 drops (see gltf_extras.h) with a
 * small JSON walker: it understands all of JSON's syntax but keeps only
 *   materials[i].extensions.KHR_materials_emissive_strength.emissiveStrength
 *   cameras[i].perspective.yfov
 *   nodes[i].rotation (checked to be a unit quaternion) and nodes[i].name
 * A .glb file is a 12-byte header followed by chunks; the first chunk is the JSON. */
#include "scene/gltf_extras.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define JSON_MAX_DEPTH 512

typedef struct json {
    const char *p, *end;
    int depth;
    int failed;
} json;

static void skip_space(json *j) {
    while (j->p < j->end && (*j->p == ' ' || *j->p == '\t' || *j->p == '\n' || *j->p == '\r'))
        ++j->p;
}

static int peek(json *j) {
    skip_space(j);
    return j->p < j->end ? (unsigned char)*j->p : -1;
}

static int accept(json *j, char c) {
    if (peek(j) != c) return 0;
    ++j->p;
    return 1;
}

/* Reads a string token; copies up to size-1 bytes (escapes kept as written) into text. */
static void read_string(json *j, char *text, size_t size) {
    size_t used = 0;
    if (!accept(j, '"')) {
        j->failed = 1;
        return;
    }
    while (j->p < j->end && *j->p != '"') {
        if (*j->p == '\\' && j->p + 1 < j->end) {
            if (text && used + 1 < size) text[used++] = *j->p;
            ++j->p;
        }
        if (text && used + 1 < size) text[used++] = *j->p;
        ++j->p;
    }
    if (j->p >= j->end) j->failed = 1;
    else ++j->p;
    if (text && size) text[used] = '\0';
}

static double read_number(json *j) {
    skip_space(j);
    char buffer[64];
    size_t n = 0;
    while (j->p + n < j->end && n + 1 < sizeof buffer && strchr("+-0123456789.eE", j->p[n])) {
        buffer[n] = j->p[n];
        ++n;
    }
    buffer[n] = '\0';
    char *stop;
    double value = strtod(buffer, &stop);
    if (n == 0 || *stop) {
        j->failed = 1;
        return 0;
    }
    j->p += n;
    return value;
}

static void skip_value(json *j);

/* Steps through an object: returns 1 with the next key read (and its ':'), 0 at the end. */
static int next_key(json *j, int *first, char *key, size_t size) {
    if (j->failed) return 0;
    if (accept(j, '}')) return 0;
    if (!*first && !accept(j, ',')) {
        j->failed = 1;
        return 0;
    }
    *first = 0;
    read_string(j, key, size);
    if (!accept(j, ':')) j->failed = 1;
    return !j->failed;
}

/* Steps through an array: returns 1 before each item, 0 at the end. */
static int next_item(json *j, int *first) {
    if (j->failed) return 0;
    if (accept(j, ']')) return 0;
    if (!*first && !accept(j, ',')) {
        j->failed = 1;
        return 0;
    }
    *first = 0;
    return 1;
}

static int enter(json *j, char open) {
    if (j->failed || !accept(j, open)) return 0;
    if (++j->depth > JSON_MAX_DEPTH) {
        j->failed = 1;
        return 0;
    }
    return 1;
}

static void leave(json *j) { --j->depth; }

static void skip_value(json *j) {
    int c = peek(j);
    int first = 1;
    if (c == '{') {
        enter(j, '{');
        while (next_key(j, &first, NULL, 0)) skip_value(j);
        leave(j);
    } else if (c == '[') {
        enter(j, '[');
        while (next_item(j, &first)) skip_value(j);
        leave(j);
    } else if (c == '"') {
        read_string(j, NULL, 0);
    } else if (c == 't' || c == 'f' || c == 'n') {
        const char *word = c == 't' ? "true" : c == 'f' ? "false" : "null";
        size_t n = strlen(word);
        if ((size_t)(j->end - j->p) < n || strncmp(j->p, word, n) != 0) j->failed = 1;
        else j->p += n;
    } else {
        read_number(j);
    }
}

/* Calls visit(j, key, user) for each member of the object at j; visit must consume the value.
 * A value that is not an object is skipped. */
typedef void (*member_fn)(json *j, const char *key, void *user);

static void each_member(json *j, member_fn visit, void *user) {
    if (peek(j) != '{') {
        skip_value(j);
        return;
    }
    enter(j, '{');
    int first = 1;
    char key[128];
    while (next_key(j, &first, key, sizeof key)) visit(j, key, user);
    leave(j);
}

static void strength_member(json *j, const char *key, void *user) {
    if (strcmp(key, "emissiveStrength") == 0) *(double *)user = read_number(j);
    else skip_value(j);
}

static void extension_member(json *j, const char *key, void *user) {
    if (strcmp(key, "KHR_materials_emissive_strength") == 0) each_member(j, strength_member, user);
    else skip_value(j);
}

static void material_member(json *j, const char *key, void *user) {
    if (strcmp(key, "extensions") == 0) each_member(j, extension_member, user);
    else skip_value(j);
}

static void yfov_member(json *j, const char *key, void *user) {
    if (strcmp(key, "yfov") == 0) *(double *)user = read_number(j);
    else skip_value(j);
}

static void camera_member(json *j, const char *key, void *user) {
    if (strcmp(key, "perspective") == 0) each_member(j, yfov_member, user);
    else skip_value(j);
}

typedef struct walker {
    rad_context *ctx;
    rad_gltf_extras *extras;
    int no_memory;
} walker;

/* One node: its name and its rotation quaternion (x, y, z, w), if it has one. */
typedef struct gltf_node {
    char name[64];
    double rotation[4];
    int rotation_values; /* how many numbers "rotation" held; -1 when it has none */
} gltf_node;

static void node_member(json *j, const char *key, void *user) {
    gltf_node *node = user;
    int first = 1;
    if (strcmp(key, "name") == 0 && peek(j) == '"') {
        read_string(j, node->name, sizeof node->name);
    } else if (strcmp(key, "rotation") == 0 && enter(j, '[')) {
        node->rotation_values = 0;
        while (next_item(j, &first)) {
            double value = read_number(j);
            if (node->rotation_values < 4) node->rotation[node->rotation_values] = value;
            node->rotation_values++;
        }
        leave(j);
    } else
        skip_value(j);
}

/* Each node's rotation must be a unit quaternion (glTF 2.0, 5.25); the first that is not is
 * kept for the importer's error. */
static void read_nodes(json *j, rad_gltf_extras *extras) {
    int first = 1;
    if (!enter(j, '[')) {
        skip_value(j);
        return;
    }
    for (long index = 0; next_item(j, &first); ++index) {
        gltf_node node = {.rotation_values = -1};
        each_member(j, node_member, &node);
        if (node.rotation_values < 0 || extras->bad_rotation_node >= 0) continue;
        double length = 0;
        for (int i = 0; i < 4 && i < node.rotation_values; ++i)
            length += node.rotation[i] * node.rotation[i];
        length = sqrt(length);
        if (node.rotation_values != 4 || !(fabs(length - 1) <= RAD_GLTF_UNIT_TOLERANCE)) {
            extras->bad_rotation_node = index;
            extras->bad_rotation_length = length;
            memcpy(extras->bad_rotation_name, node.name, sizeof node.name);
        }
    }
    leave(j);
}

/* Reads an array of objects, one double per item, each starting at `initial`. */
static void read_array(json *j, walker *w, member_fn visit, double initial, double **values,
                       size_t *count) {
    /* A key given twice: the first one counts (as in assimp's reader); growing the first
     * array again would write past its end. */
    if (*values || !enter(j, '[')) {
        skip_value(j);
        return;
    }
    size_t capacity = 0;
    int first = 1;
    while (next_item(j, &first)) {
        if (*count == capacity) {
            size_t wanted = capacity ? capacity * 2 : 8;
            double *grown = rad_realloc(w->ctx, *values, wanted, sizeof **values);
            if (!grown) {
                w->no_memory = 1;
                j->failed = 1;
                break;
            }
            *values = grown;
            capacity = wanted;
        }
        double value = initial;
        each_member(j, visit, &value);
        (*values)[(*count)++] = value;
    }
    leave(j);
}

static void root_member(json *j, const char *key, void *user) {
    walker *w = user;
    if (strcmp(key, "materials") == 0)
        read_array(j, w, material_member, 1.0, &w->extras->emissive_strength,
                   &w->extras->material_count);
    else if (strcmp(key, "cameras") == 0)
        read_array(j, w, camera_member, 0.0, &w->extras->camera_yfov, &w->extras->camera_count);
    else if (strcmp(key, "nodes") == 0)
        read_nodes(j, w->extras);
    else skip_value(j);
}

static uint32_t little_endian_u32(const unsigned char *b) {
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

void rad_gltf_extras_free(rad_context *ctx, rad_gltf_extras *extras) {
    if (!extras) return;
    rad_free(ctx, extras->emissive_strength);
    rad_free(ctx, extras->camera_yfov);
    memset(extras, 0, sizeof *extras);
    extras->bad_rotation_node = -1;
}

rad_status rad_gltf_extras_read(rad_context *ctx, const char *path, rad_gltf_extras *out) {
    memset(out, 0, sizeof *out);
    out->bad_rotation_node = -1;
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
    size_t capacity = 1 << 16, length = 0;
    unsigned char *bytes = rad_alloc(ctx, capacity, 1);
    while (bytes) {
        if (length == capacity) {
            unsigned char *grown = rad_realloc(ctx, bytes, capacity * 2, 1);
            if (!grown) {
                rad_free(ctx, bytes);
                bytes = NULL;
                break;
            }
            bytes = grown;
            capacity *= 2;
        }
        size_t got = fread(bytes + length, 1, capacity - length, file);
        if (got == 0) break;
        length += got;
    }
    fclose(file);
    if (!bytes) return RAD_ERROR_NO_MEMORY;

    /* Find the JSON: the whole file, or the first chunk of a binary glTF. */
    const char *text = (const char *)bytes;
    size_t text_length = length;
    if (length >= 4 && memcmp(bytes, "glTF", 4) == 0) {
        uint32_t chunk_length = length >= 20 ? little_endian_u32(bytes + 12) : 0;
        if (length < 20 || memcmp(bytes + 16, "JSON", 4) != 0 || chunk_length > length - 20) {
            rad_free(ctx, bytes);
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s: not a binary glTF file", path);
        }
        text = (const char *)bytes + 20;
        text_length = chunk_length;
    }
    json j = {text, text + text_length, 0, 0};
    walker w = {ctx, out, 0};
    if (peek(&j) != '{') j.failed = 1;
    else each_member(&j, root_member, &w);
    rad_free(ctx, bytes);
    if (w.no_memory) {
        rad_gltf_extras_free(ctx, out);
        return RAD_ERROR_NO_MEMORY;
    }
    if (j.failed) {
        rad_gltf_extras_free(ctx, out);
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: cannot read the glTF JSON", path);
    }
    return RAD_OK;
}
