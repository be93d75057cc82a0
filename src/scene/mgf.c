/* mgf.c - Ward's Materials and Geometry Format (MGF 2.0, the scene format of RenderPark and of
 * Radiance's mgf2rad), read by the project's own parser (docs/formats.md, "MGF").
 *
 * Entities read: v/p/n (named vertices), f (faces, convex or not), m with rd, rs, ed and sides
 * (materials), c with cxy and cspec (colours), o (objects: surface names), xf (transforms:
 * -t -rx -ry -rz -s -mx -my -mz, and -a arrays: the body read once per copy), i (includes,
 * relative to the including file, with an optional transform, arrays too), and the primitives
 * sph, cyl, cone, ring, prism and torus, tessellated. Entities that carry nothing a diffuse
 * radiosity solver uses (td, ts, ir, cct, cmix, fh, ies) are skipped with one note each; any
 * other word is skipped with one warning for the file set, as mgflib and RenderPark do.
 *
 * Colours: a chromaticity (cxy, or the CIE 1931 xy of a cspec spectrum, integrated with the
 * analytic colour-matching functions of Wyman, Sloan & Shirley 2013) with the reflectance or
 * emission as luminance Y, to linear RGB with sRGB (Rec. 709) primaries and MGF's equal-energy
 * white (x = y = 1/3 gives R = G = B, as in Radiance's mgf2rad).
 * Emission: ed is luminous exitance in lm/m^2; radiance L = ed / (pi * 179 lm/W), 179 lm/W
 * being Radiance's white efficacy (docs/units.md). Coordinates are in metres.
 * Faces: counter-clockwise seen from the front, as here; non-convex ones are cut into a few
 * convex pieces and convex ones of more than 64 corners split into a core and caps
 * (scene/polygon_cut.h), as the OBJ importer does. Transforms apply to the geometry an entity
 * makes, when it is made. */
#include "scene/mgf.h"
#include "scene/polygon_cut.h"

#include "core/hash_index.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MGF_MAX_WORDS 512
#define MGF_MAX_NAME 128
#define MGF_MAX_INCLUDE_DEPTH 16
#define MGF_MAX_DEPTH 64        /* nested o and xf contexts */
#define MGF_SEGMENTS 24         /* around a sphere, cylinder, cone, ring or torus */
#define MGF_EFFICACY 179.0      /* lm/W, white light: Radiance's WHTEFFICACY */
#define MGF_PI 3.14159265358979323846
#define MGF_MAX_ARRAY_DIMS 8      /* xf -a dimensions, as RenderPark's reader */
#define MGF_MAX_ARRAY_COPIES 100000 /* copies made by xf -a arrays in one file, all told */

typedef struct mgf_vertex {
    char name[MGF_MAX_NAME];
    rad_vec3 point, normal;
} mgf_vertex;

typedef struct mgf_color {
    char name[MGF_MAX_NAME];
    double x, y; /* CIE 1931 chromaticity */
} mgf_color;

typedef struct mgf_material {
    char name[MGF_MAX_NAME];
    double rd, ed, rs;
    double rd_x, rd_y, ed_x, ed_y; /* chromaticities current when rd and ed were given */
    uint32_t index;                /* in the scene, once made; UINT32_MAX before */
} mgf_material;

typedef struct mgf_transform { double m[3][4]; } mgf_transform;

/* An xf's arguments: the transform before the first -a, then per array dimension (-a N) the
 * transform that follows it, applied 0, 1, ..., N-1 times (MGF 2.0; RenderPark's and mgflib's
 * reading: copy (i1, i2, ...) is prefix, then step1 i1 times, then step2 i2 times, ...). */
typedef struct mgf_xf_spec {
    mgf_transform prefix, step[MGF_MAX_ARRAY_DIMS];
    int dims;
    int count[MGF_MAX_ARRAY_DIMS];
} mgf_xf_spec;

/* An open xf: its spec, the copy being read, and where its body starts in the file. */
typedef struct mgf_array {
    mgf_xf_spec spec;
    int index[MGF_MAX_ARRAY_DIMS];
    long body;     /* file offset of the line after the xf */
    int body_line; /* its line number, less one */
} mgf_array;

/* A scene surface: one per object and scene material. Its name is the object's, then
 * "object/material", then "object/material.N" (suffix 1, 2, N) for the first that is free. */
typedef struct mgf_surface_key {
    char object[MGF_MAX_NAME];
    char material_name[MGF_MAX_NAME];
    uint32_t material; /* in the scene */
    uint32_t surface;
    unsigned suffix;
} mgf_surface_key;

typedef struct mgf_reader {
    rad_context *ctx;
    rad_scene *scene;
    const char *file;
    int line;
    mgf_vertex *vertices;
    size_t vertex_count, vertex_capacity;
    size_t current_vertex; /* SIZE_MAX: none */
    mgf_color *colors;
    size_t color_count, color_capacity;
    mgf_color color; /* the current colour */
    mgf_material *materials;
    size_t material_count, material_capacity;
    size_t current_material; /* index into materials */
    mgf_surface_key *keys;
    size_t key_count, key_capacity;
    /* Names to items in O(1) (a file of 10^5 names, or an array making 10^5 copies, would scan
     * quadratically): the newest vertex, colour and material (from 1) of each name; the key of
     * each (object, scene material) and the newest key of each (object, material name); the
     * scene surfaces' names. */
    rad_hash_index vertex_names, color_names, material_names, key_index, stem_index, surface_names;
    char objects[MGF_MAX_DEPTH][MGF_MAX_NAME];
    int object_depth;
    mgf_transform transforms[MGF_MAX_DEPTH + 1];
    mgf_array arrays[MGF_MAX_DEPTH + 1]; /* per transform depth; spec.dims 0: no array */
    int transform_depth;
    int file_transform_base; /* the depth the current file started at: its xf cannot end below */
    FILE *stream;            /* the file being read (an array's body is read again from it) */
    int rewound_line;        /* -1, or the line to go on from after an array went back */
    int line_end;            /* the last line of the entity being read */
    long array_copies;       /* copies made by xf -a so far, all told */
    int include_depth;
    unsigned skipped_notes; /* one note per skipped entity kind */
    size_t unknown_count;   /* unknown entities skipped */
    char unknown_first[4200]; /* where the first was, and its name */
} mgf_reader;

#define MGF_FAIL(r, ...) rad_fail((r)->ctx, RAD_ERROR_PARSE, __VA_ARGS__)

static rad_status fail_at(mgf_reader *r, const char *what, const char *detail) {
    return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: %s%s%s", r->file, r->line, what,
                    detail ? ": " : "", detail ? detail : "");
}

/* Grows *items (of `size` bytes each) to hold one more. */
static rad_status grow(mgf_reader *r, void **items, size_t *capacity, size_t count, size_t size) {
    if (count < *capacity) return RAD_OK;
    size_t wanted = *capacity ? 2 * *capacity : 16;
    rad_status status = rad_check_budget(r->ctx, (double)wanted * (double)size, "the MGF scene");
    if (status) return status;
    void *grown = rad_realloc(r->ctx, *items, wanted, size);
    if (!grown) return RAD_ERROR_NO_MEMORY;
    *items = grown;
    *capacity = wanted;
    return RAD_OK;
}

static int parse_number(const char *word, double *out) {
    char *end;
    errno = 0;
    double value = strtod(word, &end);
    if (end == word || *end != '\0' || errno == ERANGE || !isfinite(value)) return 0;
    *out = value;
    return 1;
}

/* ---- transforms --------------------------------------------------------------------------- */

static void transform_identity(mgf_transform *t) {
    memset(t, 0, sizeof *t);
    for (int i = 0; i < 3; ++i) t->m[i][i] = 1;
}

/* a then b: the result applies a first. */
static mgf_transform transform_then(const mgf_transform *a, const mgf_transform *b) {
    mgf_transform out;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            double sum = j == 3 ? b->m[i][3] : 0;
            for (int k = 0; k < 3; ++k) sum += b->m[i][k] * a->m[k][j];
            out.m[i][j] = sum;
        }
    }
    return out;
}

static rad_vec3 transform_point(const mgf_transform *t, rad_vec3 p) {
    return v3(t->m[0][0] * p.x + t->m[0][1] * p.y + t->m[0][2] * p.z + t->m[0][3],
              t->m[1][0] * p.x + t->m[1][1] * p.y + t->m[1][2] * p.z + t->m[1][3],
              t->m[2][0] * p.x + t->m[2][1] * p.y + t->m[2][2] * p.z + t->m[2][3]);
}

static double transform_determinant(const mgf_transform *t) {
    const double(*m)[4] = t->m;
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Parses xf arguments (words[0..count-1]) into a transform spec, applied left to right. */
static rad_status parse_transform(mgf_reader *r, char **words, int count, mgf_xf_spec *out) {
    transform_identity(&out->prefix);
    out->dims = 0;
    mgf_transform *current = &out->prefix;
    for (int i = 0; i < count; ++i) {
        const char *flag = words[i];
        if (strcmp(flag, "-a") == 0) {
            char *end;
            long copies = i + 1 < count ? strtol(words[i + 1], &end, 10) : 0;
            if (i + 1 >= count || *end != '\0' || end == words[i + 1] || copies < 1 ||
                copies > MGF_MAX_ARRAY_COPIES)
                return fail_at(r, "xf -a: the count must be a whole number from 1 to 100000",
                               i + 1 < count ? words[i + 1] : NULL);
            if (out->dims == MGF_MAX_ARRAY_DIMS)
                return fail_at(r, "xf: more than 8 array dimensions (-a)", NULL);
            out->count[out->dims] = (int)copies;
            current = &out->step[out->dims++];
            transform_identity(current);
            ++i;
            continue;
        }
        mgf_transform step;
        transform_identity(&step);
        int needs = strcmp(flag, "-t") == 0 ? 3
                    : (strcmp(flag, "-rx") == 0 || strcmp(flag, "-ry") == 0 ||
                       strcmp(flag, "-rz") == 0 || strcmp(flag, "-s") == 0) ? 1
                    : (strcmp(flag, "-mx") == 0 || strcmp(flag, "-my") == 0 ||
                       strcmp(flag, "-mz") == 0) ? 0 : -1;
        if (needs < 0) return fail_at(r, "unknown transform", flag);
        double value[3];
        if (i + needs >= count + (needs == 0)) return fail_at(r, "xf: missing value after", flag);
        for (int k = 0; k < needs; ++k)
            if (!parse_number(words[i + 1 + k], &value[k]))
                return fail_at(r, "xf: not a number", words[i + 1 + k]);
        i += needs;
        if (flag[1] == 't') {
            for (int k = 0; k < 3; ++k) step.m[k][3] = value[k];
        } else if (flag[1] == 's') {
            if (!(value[0] != 0)) return fail_at(r, "xf -s: scale must not be zero", NULL);
            for (int k = 0; k < 3; ++k) step.m[k][k] = value[0];
        } else if (flag[1] == 'm') {
            int axis = flag[2] - 'x';
            step.m[axis][axis] = -1;
        } else {
            int axis = flag[2] - 'x';
            double angle = value[0] * MGF_PI / 180, c = cos(angle), s = sin(angle);
            int a = (axis + 1) % 3, b = (axis + 2) % 3;
            step.m[a][a] = c;
            step.m[a][b] = -s;
            step.m[b][a] = s;
            step.m[b][b] = c;
        }
        *current = transform_then(current, &step);
    }
    return RAD_OK;
}

/* The transform of copy `index` (one index per array dimension) of a spec. */
static mgf_transform xf_spec_copy(const mgf_xf_spec *spec, const int *index) {
    mgf_transform out = spec->prefix;
    for (int d = 0; d < spec->dims; ++d) {
        /* step^index by squaring: copies of a long array cost log(index) products each. */
        mgf_transform power = spec->step[d];
        for (int k = index[d]; k > 0; k >>= 1) {
            if (k & 1) out = transform_then(&out, &power);
            power = transform_then(&power, &power);
        }
    }
    return out;
}

/* The next copy of an array, the last dimension counting fastest; 0 after the last copy. */
static int xf_spec_next(const mgf_xf_spec *spec, int *index) {
    for (int d = spec->dims; d-- > 0;) {
        if (++index[d] < spec->count[d]) return 1;
        index[d] = 0;
    }
    return 0;
}

/* ---- colours ------------------------------------------------------------------------------ */

/* CIE 1931 colour-matching functions, the multi-lobe fit of Wyman, Sloan & Shirley, "Simple
 * Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2), 2013. */
static double lobe(double x, double mu, double s1, double s2) {
    double t = (x - mu) / (x < mu ? s1 : s2);
    return exp(-0.5 * t * t);
}
static void cie_xyz(double nm, double *xyz) {
    xyz[0] = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
             0.065 * lobe(nm, 501.1, 20.4, 26.2);
    xyz[1] = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    xyz[2] = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
}

/* Linear RGB of luminance Y at chromaticity (x, y): sRGB primaries, equal-energy white. */
static void xy_to_rgb(double x, double y, double luminance, double *rgb) {
    static const double primaries[3][2] = {{0.640, 0.330}, {0.300, 0.600}, {0.150, 0.060}};
    /* Columns: XYZ of each primary, scaled so that R = G = B = 1 is X = Y = Z = 1. */
    double p[3][3];
    for (int k = 0; k < 3; ++k) {
        double px = primaries[k][0], py = primaries[k][1];
        p[0][k] = px / py;
        p[1][k] = 1;
        p[2][k] = (1 - px - py) / py;
    }
    double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                 p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                 p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    double inv[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
            inv[i][j] = (p[a][c] * p[b][d] - p[a][d] * p[b][c]) / det;
        }
    double scale[3];
    for (int i = 0; i < 3; ++i) scale[i] = inv[i][0] + inv[i][1] + inv[i][2]; /* inv * (1,1,1) */
    double xyz[3] = {x / y * luminance, luminance, (1 - x - y) / y * luminance};
    for (int i = 0; i < 3; ++i) {
        double value = (inv[i][0] * xyz[0] + inv[i][1] * xyz[1] + inv[i][2] * xyz[2]) / scale[i];
        rgb[i] = value > 0 ? value : 0; /* outside the gamut: clipped */
    }
}

/* The newest of `items` (`stride` bytes apart, each starting with its name) named `name` in
 * `index`, or SIZE_MAX; *slot_out (if given) is its slot. */
static size_t find_named(const rad_hash_index *index, const void *items, size_t stride,
                         const char *name, size_t *slot_out) {
    size_t slot = SIZE_MAX;
    uint64_t hash = rad_hash_string(RAD_HASH_START, name);
    for (size_t i; (i = rad_hash_index_next(index, hash, &slot)) != SIZE_MAX;)
        if (strcmp((const char *)items + i * stride, name) == 0) {
            if (slot_out) *slot_out = slot;
            return i;
        }
    return SIZE_MAX;
}

/* Records items[item] as the newest of its name (a redefinition hides the older one). */
static rad_status name_item(mgf_reader *r, rad_hash_index *index, const void *items, size_t stride,
                            size_t item) {
    const char *name = (const char *)items + item * stride;
    size_t slot;
    if (find_named(index, items, stride, name, &slot) != SIZE_MAX) {
        rad_hash_index_replace(index, slot, item);
        return RAD_OK;
    }
    return rad_hash_index_insert(r->ctx, index, rad_hash_string(RAD_HASH_START, name), item);
}

static mgf_color *find_color(mgf_reader *r, const char *name) {
    size_t i = find_named(&r->color_names, r->colors, sizeof *r->colors, name, NULL);
    return i == SIZE_MAX ? NULL : &r->colors[i];
}

/* The newest material named `name` (from 1: the default material has no name), or SIZE_MAX. */
static size_t find_material(mgf_reader *r, const char *name) {
    return find_named(&r->material_names, r->materials, sizeof *r->materials, name, NULL);
}

/* ---- geometry ----------------------------------------------------------------------------- */

static mgf_vertex *find_vertex(mgf_reader *r, const char *name) {
    size_t i = find_named(&r->vertex_names, r->vertices, sizeof *r->vertices, name, NULL);
    return i == SIZE_MAX ? NULL : &r->vertices[i];
}

static const mgf_transform *current_transform(const mgf_reader *r) {
    return &r->transforms[r->transform_depth];
}

/* The scene surface of the current object and material, made on first use. */
static rad_status current_surface(mgf_reader *r, uint32_t *out) {
    mgf_material *m = &r->materials[r->current_material];
    const char *object = r->object_depth > 0 ? r->objects[r->object_depth - 1] : m->name;
    rad_status status = RAD_OK;
    if (m->index == UINT32_MAX) {
        rad_material material = {0};
        material.name = m->name;
        double rd = m->rd;
        /* More light reflected than arrives (rd + rs over 1): both scaled down to a total of 1
         * when the material is first used, with one warning naming it, as RenderPark reads
         * such files (its own cube.mgf has rd 0.9 with rs 0.2; RenderPark scales the RGB sum's
         * largest channel, this reader the luminances MGF gives). */
        if (m->rd + m->rs > 1) {
            double total = m->rd + m->rs;
            rd = m->rd / total;
            rad_warn(r->ctx, "%s:%d: material '%s' has rd + rs = %.3g, more than 1: both scaled "
                     "by %.3g (rd %.3g, rs %.3g) so that it reflects no more light than it "
                     "receives", r->file, r->line, m->name, total, 1 / total, rd, m->rs / total);
        }
        if (rd > 0.999) rd = 0.999;
        xy_to_rgb(m->rd_x, m->rd_y, rd, material.reflectance);
        for (int c = 0; c < 3; ++c)
            if (material.reflectance[c] > 0.999) material.reflectance[c] = 0.999;
        xy_to_rgb(m->ed_x, m->ed_y, m->ed / (MGF_PI * MGF_EFFICACY), material.emission);
        material.kind = RAD_MATERIAL_DIFFUSE;
        status = rad_scene_add_material(r->scene, &material, &m->index);
        if (status) return status;
    }
    uint64_t key_hash = rad_hash_string(rad_hash_pair(RAD_HASH_START, m->index), object);
    size_t slot = SIZE_MAX;
    for (size_t i; (i = rad_hash_index_next(&r->key_index, key_hash, &slot)) != SIZE_MAX;)
        if (r->keys[i].material == m->index && strcmp(r->keys[i].object, object) == 0) {
            *out = r->keys[i].surface;
            return RAD_OK;
        }
    /* Unique names: the object, or "object/material" when the object has several, then
     * numbered; a redefined material goes on from the newest suffix of its object and name. */
    uint64_t stem_hash = rad_hash_string(rad_hash_string(RAD_HASH_START, object), m->name);
    size_t stem_slot = SIZE_MAX, stem = SIZE_MAX;
    for (size_t i; (i = rad_hash_index_next(&r->stem_index, stem_hash, &stem_slot)) != SIZE_MAX;)
        if (strcmp(r->keys[i].object, object) == 0 && strcmp(r->keys[i].material_name, m->name) == 0) {
            stem = i;
            break;
        }
    unsigned suffix = stem == SIZE_MAX ? 1 : r->keys[stem].suffix + 1;
    char name[2 * MGF_MAX_NAME + 16];
    for (;; ++suffix) {
        if (suffix == 1) snprintf(name, sizeof name, "%s", object);
        else if (suffix == 2) snprintf(name, sizeof name, "%s/%s", object, m->name);
        else snprintf(name, sizeof name, "%s/%s.%u", object, m->name, suffix);
        size_t name_slot = SIZE_MAX, i;
        uint64_t name_hash = rad_hash_string(RAD_HASH_START, name);
        while ((i = rad_hash_index_next(&r->surface_names, name_hash, &name_slot)) != SIZE_MAX &&
               strcmp(r->scene->surfaces[i].name, name) != 0) {
        }
        if (i == SIZE_MAX) break; /* free */
    }
    if ((status = grow(r, (void **)&r->keys, &r->key_capacity, r->key_count, sizeof *r->keys)))
        return status;
    mgf_surface_key *key = &r->keys[r->key_count];
    snprintf(key->object, sizeof key->object, "%s", object);
    snprintf(key->material_name, sizeof key->material_name, "%s", m->name);
    key->material = m->index;
    key->suffix = suffix;
    status = rad_scene_add_surface(r->scene, name, m->index, &key->surface);
    if (status) return status;
    size_t k = r->key_count++;
    if (stem != SIZE_MAX) rad_hash_index_replace(&r->stem_index, stem_slot, k);
    else status = rad_hash_index_insert(r->ctx, &r->stem_index, stem_hash, k);
    if (!status) status = rad_hash_index_insert(r->ctx, &r->key_index, key_hash, k);
    if (!status)
        status = rad_hash_index_insert(r->ctx, &r->surface_names, rad_hash_string(RAD_HASH_START, name),
                                       key->surface);
    *out = key->surface;
    return status;
}

/* Adds a convex piece of n corners (at most RAD_POLYGON_CORNERS_MAX), p[index[0 .. n-1]],
 * unless it has no area. */
static rad_status add_piece(mgf_reader *r, uint32_t surface, const rad_vec3 *p,
                            const uint32_t *index, size_t n, double extent) {
    rad_vec3 piece[RAD_POLYGON_CORNERS_MAX];
    if (n > RAD_POLYGON_CORNERS_MAX) return RAD_ERROR_INTERNAL;
    for (size_t k = 0; k < n; ++k) piece[k] = p[index[k]];
    if (!(v3_length(v3_newell_normal(piece, n)) > 1e-12 * extent * extent)) return RAD_OK;
    return rad_scene_add_polygon_points(r->scene, surface, piece, (uint32_t)n);
}

/* Adds a polygon in world space (already transformed): whole when convex and of at most
 * RAD_POLYGON_CORNERS_MAX corners; a larger convex one split into a core and caps, a
 * non-convex one cut into a few convex pieces (scene/polygon_cut.h, as the OBJ importer does).
 * Degenerate polygons and pieces (no area) are dropped. */
static rad_status add_points(mgf_reader *r, rad_vec3 *p, size_t n) {
    if (n < 3) return RAD_OK;
    /* A mirroring transform turns the winding: turn it back so the front stays the front. */
    if (transform_determinant(current_transform(r)) < 0)
        for (size_t i = 0; i < n / 2; ++i) {
            rad_vec3 t = p[i];
            p[i] = p[n - 1 - i];
            p[n - 1 - i] = t;
        }
    rad_vec3 normal = v3_newell_normal(p, n);
    double length = v3_length(normal);
    double extent = 0;
    for (size_t i = 1; i < n; ++i) {
        double d = v3_length(v3_sub(p[i], p[0]));
        if (d > extent) extent = d;
    }
    if (!(length > 1e-12 * extent * extent)) return RAD_OK;
    normal = v3_scale(normal, 1 / length);
    /* The scene's arrays against the memory budget (they grow by doubling, and a short file
     * of arrays, xf -a, can ask for millions of polygons). */
    const rad_scene *scene = r->scene;
    double bytes = (double)scene->vertex_capacity * sizeof *scene->vertices +
                   (double)scene->polygon_vertex_capacity * sizeof *scene->polygon_vertices +
                   (double)scene->polygon_capacity * sizeof *scene->polygons;
    rad_status status = rad_check_budget(r->ctx, bytes, "the MGF scene's geometry");
    if (status) return status;
    uint32_t surface;
    status = current_surface(r, &surface);
    if (status) return status;
    int convex = 1;
    for (size_t i = 0; i < n && convex; ++i) {
        rad_vec3 a = p[i], b = p[(i + 1) % n], c = p[(i + 2) % n];
        convex = v3_dot(v3_cross(v3_sub(b, a), v3_sub(c, b)), normal) >= -1e-12 * extent * extent;
    }
    if (convex && n <= RAD_POLYGON_CORNERS_MAX)
        return rad_scene_add_polygon_points(r->scene, surface, p, (uint32_t)n);
    rad_polygon_pieces pieces = {0};
    status = rad_polygon_cut_in_plane(r->ctx, p, n, normal, 0, RAD_POLYGON_CORNERS_MAX, convex,
                                      &pieces);
    for (size_t k = 0; k < pieces.count && !status; ++k)
        status = add_piece(r, surface, p, pieces.corners + pieces.first[k],
                           pieces.first[k + 1] - pieces.first[k], extent);
    rad_polygon_pieces_free(r->ctx, &pieces);
    return status;
}

/* A polygon given in the current object's coordinates. */
static rad_status add_local(mgf_reader *r, const rad_vec3 *local, size_t n) {
    rad_vec3 world[4];
    if (n > 4) return RAD_ERROR_INTERNAL;
    for (size_t i = 0; i < n; ++i) world[i] = transform_point(current_transform(r), local[i]);
    return add_points(r, world, n);
}

/* The vertex named by words[k], with a point. */
static rad_status vertex_arg(mgf_reader *r, const char *name, mgf_vertex **out) {
    *out = find_vertex(r, name);
    if (!*out) return fail_at(r, "undefined vertex", name);
    return RAD_OK;
}

/* A ring of MGF_SEGMENTS points of radius `radius` around `center`, in the plane normal to
 * `axis`, counter-clockwise seen from the tip of the axis. */
static void circle(rad_vec3 center, rad_vec3 axis, double radius, rad_vec3 *out) {
    rad_vec3 t, b;
    v3_basis(v3_normalize(axis), &t, &b);
    for (int i = 0; i < MGF_SEGMENTS; ++i) {
        double angle = 2 * MGF_PI * i / MGF_SEGMENTS;
        out[i] = v3_add(center, v3_add(v3_scale(t, radius * cos(angle)), v3_scale(b, radius * sin(angle))));
    }
}

/* The band between two circles (each MGF_SEGMENTS points, same orientation), quads from a to b;
 * outward when `outward`, else turned. */
static rad_status band(mgf_reader *r, const rad_vec3 *a, const rad_vec3 *b, int outward) {
    rad_status status = RAD_OK;
    for (int i = 0; i < MGF_SEGMENTS && !status; ++i) {
        int j = (i + 1) % MGF_SEGMENTS;
        rad_vec3 quad[4] = {a[i], a[j], b[j], b[i]};
        if (!outward) {
            rad_vec3 t = quad[1];
            quad[1] = quad[3];
            quad[3] = t;
        }
        /* A cone's apex makes a triangle. */
        if (a[i].x == a[j].x && a[i].y == a[j].y && a[i].z == a[j].z) {
            rad_vec3 tri[3] = {quad[0], quad[2], quad[3]};
            if (!outward) tri[1] = quad[1], tri[2] = quad[2];
            status = add_local(r, tri, 3);
        } else if (b[i].x == b[j].x && b[i].y == b[j].y && b[i].z == b[j].z) {
            rad_vec3 tri[3] = {quad[0], quad[1], quad[2]};
            if (!outward) tri[1] = quad[1], tri[2] = quad[3];
            status = add_local(r, tri, 3);
        } else {
            status = add_local(r, quad, 4);
        }
    }
    return status;
}

/* cone v1 r1 v2 r2 (cyl: r1 = r2): the open side from v1 to v2; negative radii face inward. */
static rad_status cone(mgf_reader *r, rad_vec3 p1, double r1, rad_vec3 p2, double r2) {
    int outward = r1 >= 0 && r2 >= 0;
    if ((r1 < 0) != (r2 < 0) && r1 != 0 && r2 != 0)
        return fail_at(r, "cone: both radii must have the same sign", NULL);
    rad_vec3 axis = v3_sub(p2, p1);
    if (!(v3_length(axis) > 0)) return fail_at(r, "cone or cylinder of zero length", NULL);
    rad_vec3 a[MGF_SEGMENTS], b[MGF_SEGMENTS];
    circle(p1, axis, fabs(r1), a);
    circle(p2, axis, fabs(r2), b);
    return band(r, a, b, outward);
}

/* ring vc rmin rmax: the annulus (a disc when rmin = 0) facing along vc's normal. */
static rad_status ring(mgf_reader *r, const mgf_vertex *center, double inner, double outer) {
    if (!(v3_length(center->normal) > 0)) return fail_at(r, "ring: the centre vertex has no normal", center->name);
    if (!(inner >= 0 && outer > inner)) return fail_at(r, "ring: radii must satisfy 0 <= rmin < rmax", NULL);
    rad_vec3 a[MGF_SEGMENTS], b[MGF_SEGMENTS];
    circle(center->point, center->normal, outer, a);
    circle(center->point, center->normal, inner, b);
    /* Outer circle to inner: seen from the normal's tip, a[i], a[i+1], b[i+1], b[i] turns
     * counter-clockwise. */
    return band(r, a, b, 1);
}

/* sph vc radius: latitude bands, outward for a positive radius. */
static rad_status sphere(mgf_reader *r, rad_vec3 center, double radius) {
    int outward = radius > 0;
    double rr = fabs(radius);
    if (!(rr > 0)) return fail_at(r, "sph: radius must not be zero", NULL);
    int stacks = MGF_SEGMENTS / 2;
    rad_status status = RAD_OK;
    for (int s = 0; s < stacks && !status; ++s) {
        double t0 = MGF_PI * s / stacks, t1 = MGF_PI * (s + 1) / stacks;
        rad_vec3 a[MGF_SEGMENTS], b[MGF_SEGMENTS];
        /* Circles of latitude from the north pole (+z) down; band a (upper) to b (lower). */
        circle(v3_add(center, v3(0, 0, rr * cos(t0))), v3(0, 0, 1), rr * sin(t0), a);
        circle(v3_add(center, v3(0, 0, rr * cos(t1))), v3(0, 0, 1), rr * sin(t1), b);
        if (s == 0)
            for (int i = 0; i < MGF_SEGMENTS; ++i) a[i] = v3_add(center, v3(0, 0, rr));
        if (s == stacks - 1)
            for (int i = 0; i < MGF_SEGMENTS; ++i) b[i] = v3_add(center, v3(0, 0, -rr));
        status = band(r, b, a, outward);
    }
    return status;
}

/* torus vc rmin rmax: tube radius (rmax - rmin) / 2 around the circle of radius
 * (rmin + rmax) / 2 in the plane normal to vc's normal. */
static rad_status torus(mgf_reader *r, const mgf_vertex *center, double inner, double outer) {
    if (!(v3_length(center->normal) > 0)) return fail_at(r, "torus: the centre vertex has no normal", center->name);
    int outward = outer > 0;
    double ri = fabs(inner), ro = fabs(outer);
    if (!(ro > ri)) return fail_at(r, "torus: |rmax| must exceed |rmin|", NULL);
    double tube = (ro - ri) / 2, mid = (ro + ri) / 2;
    rad_vec3 n = v3_normalize(center->normal), t, b;
    v3_basis(n, &t, &b);
    rad_status status = RAD_OK;
    for (int i = 0; i < MGF_SEGMENTS && !status; ++i) {
        /* Circle of the tube at angle i around the axis, and the next one. */
        rad_vec3 a[MGF_SEGMENTS], c[MGF_SEGMENTS];
        for (int side = 0; side < 2; ++side) {
            double phi = 2 * MGF_PI * (i + side) / MGF_SEGMENTS;
            rad_vec3 radial = v3_add(v3_scale(t, cos(phi)), v3_scale(b, sin(phi)));
            rad_vec3 *ring_points = side ? c : a;
            for (int k = 0; k < MGF_SEGMENTS; ++k) {
                double theta = 2 * MGF_PI * k / MGF_SEGMENTS;
                ring_points[k] = v3_add(center->point,
                                        v3_add(v3_scale(radial, mid + tube * cos(theta)),
                                               v3_scale(n, tube * sin(theta))));
            }
        }
        status = band(r, c, a, outward);
    }
    return status;
}

/* prism v1 ... vn length: the face and its copy moved by length along the face's normal,
 * joined by sides; outward for a positive length. */
static rad_status prism(mgf_reader *r, char **names, int n, double length) {
    if (n < 3) return fail_at(r, "prism: needs at least 3 vertices and a length", NULL);
    rad_vec3 *p = rad_alloc(r->ctx, 2 * (size_t)n, sizeof *p);
    if (!p) return RAD_ERROR_NO_MEMORY;
    rad_status status = RAD_OK;
    for (int i = 0; i < n && !status; ++i) {
        mgf_vertex *v;
        status = vertex_arg(r, names[i], &v);
        if (!status) p[i] = v->point;
    }
    if (!status) {
        rad_vec3 normal = v3_normalize(v3_newell_normal(p, (size_t)n));
        if (!(v3_length(normal) > 0)) status = fail_at(r, "prism: the base face has no area", NULL);
        rad_vec3 shift = v3_scale(normal, length);
        for (int i = 0; i < n; ++i) p[n + i] = v3_add(p[i], shift);
    }
    /* The far face keeps the winding (it faces +normal), the base face turned (faces -normal),
     * for a positive length; all turned for a negative one. */
    int outward = length > 0;
    rad_vec3 *face = rad_alloc(r->ctx, (size_t)n, sizeof *face);
    if (!face && !status) status = RAD_ERROR_NO_MEMORY;
    for (int pass = 0; pass < 2 && !status; ++pass) {
        for (int i = 0; i < n; ++i) {
            int far = pass == 1;
            int k = far == outward ? i : n - 1 - i;
            face[i] = transform_point(current_transform(r), p[(far ? n : 0) + k]);
        }
        status = add_points(r, face, (size_t)n);
    }
    for (int i = 0; i < n && !status; ++i) {
        int j = (i + 1) % n;
        /* A base wound counter-clockwise around +normal: i, j, j+n, i+n faces outward. */
        rad_vec3 quad[4] = {p[i], p[j], p[n + j], p[n + i]};
        if (!outward) {
            rad_vec3 t = quad[1];
            quad[1] = quad[3];
            quad[3] = t;
        }
        status = add_local(r, quad, 4);
    }
    rad_free(r->ctx, face);
    rad_free(r->ctx, p);
    return status;
}

/* ---- the entity reader -------------------------------------------------------------------- */

static rad_status read_file(mgf_reader *r, const char *path, const mgf_transform *include_xf);

static int arg_count_is(int count, int low, int high) { return count >= low && count <= high; }

static rad_status entity(mgf_reader *r, char **w, int count) {
    const char *e = w[0];
    double value[4];
    rad_status status = RAD_OK;
    if (strcmp(e, "v") == 0) {
        if (!arg_count_is(count, 2, 4) || (count >= 3 && strcmp(w[2], "=") != 0))
            return fail_at(r, "usage: v NAME [= [TEMPLATE]]", NULL);
        if (strlen(w[1]) >= MGF_MAX_NAME) return fail_at(r, "vertex name too long", NULL);
        mgf_vertex *v = count >= 3 ? NULL : find_vertex(r, w[1]);
        if (!v) {
            /* The template by index: growing the array below may move it. */
            size_t template_index = SIZE_MAX;
            if (count == 4) {
                const mgf_vertex *template_vertex = find_vertex(r, w[3]);
                if (!template_vertex) return fail_at(r, "undefined vertex", w[3]);
                template_index = (size_t)(template_vertex - r->vertices);
            }
            if ((status = grow(r, (void **)&r->vertices, &r->vertex_capacity, r->vertex_count,
                               sizeof *r->vertices)))
                return status;
            v = &r->vertices[r->vertex_count++];
            if (template_index != SIZE_MAX) *v = r->vertices[template_index];
            else memset(v, 0, sizeof *v);
            snprintf(v->name, sizeof v->name, "%s", w[1]);
            if ((status = name_item(r, &r->vertex_names, r->vertices, sizeof *r->vertices,
                                    r->vertex_count - 1)))
                return status;
        }
        r->current_vertex = (size_t)(v - r->vertices);
        return RAD_OK;
    }
    if (strcmp(e, "p") == 0 || strcmp(e, "n") == 0) {
        if (count != 4) return fail_at(r, e[0] == 'p' ? "usage: p X Y Z" : "usage: n DX DY DZ", NULL);
        if (r->current_vertex == SIZE_MAX) return fail_at(r, "p or n outside a vertex (v NAME =)", NULL);
        for (int k = 0; k < 3; ++k)
            if (!parse_number(w[1 + k], &value[k])) return fail_at(r, "not a number", w[1 + k]);
        rad_vec3 vector = v3(value[0], value[1], value[2]);
        if (e[0] == 'p') r->vertices[r->current_vertex].point = vector;
        else r->vertices[r->current_vertex].normal = vector;
        return RAD_OK;
    }
    if (strcmp(e, "f") == 0) {
        if (count < 4) return fail_at(r, "a face needs at least 3 vertices", NULL);
        rad_vec3 *p = rad_alloc(r->ctx, (size_t)count - 1, sizeof *p);
        if (!p) return RAD_ERROR_NO_MEMORY;
        for (int i = 1; i < count && !status; ++i) {
            mgf_vertex *v;
            status = vertex_arg(r, w[i], &v);
            if (!status) p[i - 1] = transform_point(current_transform(r), v->point);
        }
        if (!status) status = add_points(r, p, (size_t)count - 1);
        rad_free(r->ctx, p);
        return status;
    }
    if (strcmp(e, "m") == 0) {
        if (count == 1) { /* back to the default material */
            r->current_material = 0;
            return RAD_OK;
        }
        if (!arg_count_is(count, 2, 4) || (count >= 3 && strcmp(w[2], "=") != 0))
            return fail_at(r, "usage: m NAME [= [TEMPLATE]]", NULL);
        if (strlen(w[1]) >= MGF_MAX_NAME) return fail_at(r, "material name too long", NULL);
        size_t found = find_material(r, w[1]);
        if (count == 2) {
            if (found == SIZE_MAX) return fail_at(r, "undefined material", w[1]);
            r->current_material = found;
            return RAD_OK;
        }
        size_t template_index = 0;
        if (count == 4) {
            template_index = find_material(r, w[3]);
            if (template_index == SIZE_MAX) return fail_at(r, "undefined material", w[3]);
        }
        if ((status = grow(r, (void **)&r->materials, &r->material_capacity, r->material_count,
                           sizeof *r->materials)))
            return status;
        mgf_material *m = &r->materials[r->material_count];
        *m = r->materials[template_index];
        if (count == 3) { /* "m NAME =": a fresh material */
            m->rd = m->ed = m->rs = 0;
            m->rd_x = m->rd_y = m->ed_x = m->ed_y = 1.0 / 3;
        }
        snprintf(m->name, sizeof m->name, "%s", w[1]);
        m->index = UINT32_MAX;
        r->current_material = r->material_count++;
        return name_item(r, &r->material_names, r->materials, sizeof *r->materials,
                         r->current_material);
    }
    if (strcmp(e, "rd") == 0 || strcmp(e, "ed") == 0 || strcmp(e, "rs") == 0) {
        int specular = e[0] == 'r' && e[1] == 's';
        if (count != (specular ? 3 : 2))
            return fail_at(r, specular ? "usage: rs REFLECTANCE ROUGHNESS" : "usage: rd|ed VALUE", NULL);
        if (!parse_number(w[1], &value[0])) return fail_at(r, "not a number", w[1]);
        if (specular && !parse_number(w[2], &value[1])) return fail_at(r, "not a number", w[2]);
        if (r->current_material == 0) return fail_at(r, "rd, rs or ed outside a material (m NAME =)", NULL);
        if (value[0] < 0 || (e[0] == 'r' && value[0] > 1))
            return fail_at(r, e[0] == 'r' ? "reflectance must be in [0, 1]" : "emission must not be negative", w[1]);
        mgf_material *m = &r->materials[r->current_material];
        mgf_color color = r->color;
        if (e[1] == 'd' && !(color.y > 0)) {
            /* A colour without luminance (cxy with y = 0, or a spectrum with no visible
             * light): black, with a warning, as RenderPark reads it. */
            rad_warn(r->ctx, "%s:%d: colour '%s' has no luminance: the %s of material '%s' is "
                     "read as black", r->file, r->line, color.name[0] ? color.name : "(unnamed)",
                     e[0] == 'r' ? "reflectance" : "emission", m->name);
            value[0] = 0;
            color.x = color.y = 1.0 / 3;
        }
        m->index = UINT32_MAX; /* changed: a new scene material on next use */
        if (e[0] == 'e') {
            m->ed = value[0];
            m->ed_x = color.x;
            m->ed_y = color.y;
        } else if (specular) {
            m->rs = value[0];
        } else {
            m->rd = value[0];
            m->rd_x = color.x;
            m->rd_y = color.y;
        }
        return RAD_OK;
    }
    if (strcmp(e, "c") == 0) {
        if (count == 1) {
            r->color.x = r->color.y = 1.0 / 3;
            return RAD_OK;
        }
        if (!arg_count_is(count, 2, 4) || (count >= 3 && strcmp(w[2], "=") != 0))
            return fail_at(r, "usage: c [NAME [= [TEMPLATE]]]", NULL);
        if (strlen(w[1]) >= MGF_MAX_NAME) return fail_at(r, "colour name too long", NULL);
        mgf_color *c = count == 2 ? find_color(r, w[1]) : NULL;
        if (count == 2 && !c) return fail_at(r, "undefined colour", w[1]);
        if (!c) {
            mgf_color base = {"", 1.0 / 3, 1.0 / 3};
            if (count == 4) {
                const mgf_color *t = find_color(r, w[3]);
                if (!t) return fail_at(r, "undefined colour", w[3]);
                base = *t;
            }
            if ((status = grow(r, (void **)&r->colors, &r->color_capacity, r->color_count,
                               sizeof *r->colors)))
                return status;
            c = &r->colors[r->color_count++];
            *c = base;
            snprintf(c->name, sizeof c->name, "%s", w[1]);
            if ((status = name_item(r, &r->color_names, r->colors, sizeof *r->colors,
                                    r->color_count - 1)))
                return status;
        }
        r->color = *c;
        return RAD_OK;
    }
    if (strcmp(e, "cxy") == 0 || strcmp(e, "cspec") == 0) {
        double x, y;
        if (e[1] == 'x') {
            if (count != 3 || !parse_number(w[1], &x) || !parse_number(w[2], &y))
                return fail_at(r, "usage: cxy X Y", NULL);
        } else {
            double low, high;
            if (count < 4 || !parse_number(w[1], &low) || !parse_number(w[2], &high) ||
                !(low > 0 && high > low))
                return fail_at(r, "usage: cspec MIN_NM MAX_NM VALUE...", NULL);
            double xyz[3] = {0, 0, 0};
            int samples = count - 3;
            for (int i = 0; i < samples; ++i) {
                double v;
                /* Negative samples are allowed (the CIE daylight components S1 and S2, in
                 * RenderPark's Materials/illums.mgf, have them): only the sum is checked. */
                if (!parse_number(w[3 + i], &v)) return fail_at(r, "cspec: bad value", w[3 + i]);
                double nm = samples > 1 ? low + (high - low) * i / (samples - 1) : (low + high) / 2, f[3];
                cie_xyz(nm, f);
                for (int k = 0; k < 3; ++k) xyz[k] += v * f[k];
            }
            double sum = xyz[0] + xyz[1] + xyz[2];
            x = xyz[0] / sum;
            y = xyz[1] / sum;
            /* No colour (a spectrum with no visible light, or one whose chromaticity falls
             * outside the diagram, as a basis spectrum for cmix can): kept, and refused only
             * if a material takes it (rd, ed). */
            if (!(sum > 0 && xyz[1] > 0 && x >= 0 && x + y <= 1)) x = y = NAN;
        }
        if (e[1] == 'x' && !(x >= 0 && y >= 0 && x + y <= 1))
            return fail_at(r, "chromaticity outside 0 <= x, 0 <= y, x + y <= 1", NULL);
        if (!(y > 0)) x = y = NAN; /* no luminance: black where a material uses it */
        r->color.x = x;
        r->color.y = y;
        mgf_color *named = r->color.name[0] ? find_color(r, r->color.name) : NULL;
        if (named) { /* the named current colour too */
            named->x = x;
            named->y = y;
        }
        return RAD_OK;
    }
    if (strcmp(e, "o") == 0) {
        if (count == 1) {
            if (r->object_depth == 0) return fail_at(r, "o: no object to end", NULL);
            --r->object_depth;
            return RAD_OK;
        }
        if (count != 2) return fail_at(r, "usage: o NAME ... o", NULL);
        if (r->object_depth >= MGF_MAX_DEPTH) return fail_at(r, "objects nested too deep", NULL);
        char name[MGF_MAX_NAME]; /* nested objects: "outer.inner" */
        if (r->object_depth > 0)
            snprintf(name, sizeof name, "%.*s.%s", MGF_MAX_NAME / 2, r->objects[r->object_depth - 1], w[1]);
        else snprintf(name, sizeof name, "%s", w[1]);
        memcpy(r->objects[r->object_depth], name, sizeof name);
        ++r->object_depth;
        return RAD_OK;
    }
    if (strcmp(e, "xf") == 0) {
        if (count == 1) {
            if (r->transform_depth <= r->file_transform_base)
                return fail_at(r, "xf: no transform to end", NULL);
            /* An array reads its body again for each copy, from the line after its xf. */
            mgf_array *array = &r->arrays[r->transform_depth];
            if (array->spec.dims > 0 && xf_spec_next(&array->spec, array->index)) {
                if (++r->array_copies > MGF_MAX_ARRAY_COPIES)
                    return fail_at(r, "xf -a: more than 100000 copies in all", NULL);
                mgf_transform copy = xf_spec_copy(&array->spec, array->index);
                r->transforms[r->transform_depth] =
                    transform_then(&copy, &r->transforms[r->transform_depth - 1]);
                if (fseek(r->stream, array->body, SEEK_SET) != 0)
                    return fail_at(r, "xf -a: cannot go back in the file", strerror(errno));
                r->rewound_line = array->body_line;
                return RAD_OK;
            }
            array->spec.dims = 0;
            --r->transform_depth;
            return RAD_OK;
        }
        if (r->transform_depth >= MGF_MAX_DEPTH) return fail_at(r, "transforms nested too deep", NULL);
        mgf_array *array = &r->arrays[r->transform_depth + 1];
        if ((status = parse_transform(r, w + 1, count - 1, &array->spec))) return status;
        memset(array->index, 0, sizeof array->index);
        if (array->spec.dims > 0) {
            array->body = ftell(r->stream);
            if (array->body < 0) return fail_at(r, "xf -a: cannot tell where the array starts", NULL);
            array->body_line = r->line_end;
        }
        mgf_transform local = xf_spec_copy(&array->spec, array->index);
        r->transforms[r->transform_depth + 1] = transform_then(&local, current_transform(r));
        ++r->transform_depth;
        return RAD_OK;
    }
    if (strcmp(e, "i") == 0) {
        if (count < 2) return fail_at(r, "usage: i FILE [transform]", NULL);
        if (r->include_depth >= MGF_MAX_INCLUDE_DEPTH) return fail_at(r, "includes nested too deep", w[1]);
        mgf_xf_spec spec;
        if ((status = parse_transform(r, w + 2, count - 2, &spec))) return status;
        /* Relative to the including file's directory. */
        char path[4096];
        const char *slash = strrchr(r->file, '/');
        if (w[1][0] == '/' || !slash) snprintf(path, sizeof path, "%s", w[1]);
        else snprintf(path, sizeof path, "%.*s/%s", (int)(slash - r->file), r->file, w[1]);
        const char *file = r->file;
        int line = r->line;
        /* Once, or once per copy of an array (i FILE -a N ...). */
        int index[MGF_MAX_ARRAY_DIMS] = {0}, first = 1;
        do {
            if (!first && ++r->array_copies > MGF_MAX_ARRAY_COPIES)
                return fail_at(r, "i -a: more than 100000 copies in all", NULL);
            first = 0;
            mgf_transform local = xf_spec_copy(&spec, index);
            mgf_transform combined = transform_then(&local, current_transform(r));
            status = read_file(r, path, &combined);
            r->file = file;
            r->line = line;
        } while (!status && xf_spec_next(&spec, index));
        return status;
    }
    if (strcmp(e, "sph") == 0 || strcmp(e, "cyl") == 0 || strcmp(e, "cone") == 0 ||
        strcmp(e, "ring") == 0 || strcmp(e, "torus") == 0) {
        int is_cone = strcmp(e, "cone") == 0, is_cyl = strcmp(e, "cyl") == 0;
        int needed = is_cone ? 5 : is_cyl ? 4 : strcmp(e, "sph") == 0 ? 3 : 4;
        if (count != needed) {
            static const char *const usage[] = {"usage: sph CENTER RADIUS",
                                                "usage: cyl V1 RADIUS V2",
                                                "usage: cone V1 R1 V2 R2",
                                                "usage: ring CENTER RMIN RMAX",
                                                "usage: torus CENTER RMIN RMAX"};
            int which = e[0] == 's' ? 0 : is_cyl ? 1 : is_cone ? 2 : e[0] == 'r' ? 3 : 4;
            return fail_at(r, usage[which], NULL);
        }
        mgf_vertex *a, *b = NULL;
        if ((status = vertex_arg(r, w[1], &a))) return status;
        if (!parse_number(w[2], &value[0])) return fail_at(r, "not a number", w[2]);
        if (is_cone || is_cyl) {
            if ((status = vertex_arg(r, w[3], &b))) return status;
            value[1] = value[0];
            if (is_cone && !parse_number(w[4], &value[1])) return fail_at(r, "not a number", w[4]);
            return cone(r, a->point, value[0], b->point, value[1]);
        }
        if (e[0] == 's') return sphere(r, a->point, value[0]);
        if (!parse_number(w[3], &value[1])) return fail_at(r, "not a number", w[3]);
        return e[0] == 'r' ? ring(r, a, value[0], value[1]) : torus(r, a, value[0], value[1]);
    }
    if (strcmp(e, "prism") == 0) {
        if (count < 5 || !parse_number(w[count - 1], &value[0]))
            return fail_at(r, "usage: prism V1 V2 V3 ... LENGTH", NULL);
        return prism(r, w + 1, count - 2, value[0]);
    }
    static const char *const skipped[] = {"td", "ts", "ir", "cct", "cmix", "fh", "ies", "sides"};
    for (unsigned k = 0; k < sizeof skipped / sizeof skipped[0]; ++k)
        if (strcmp(e, skipped[k]) == 0) {
            if (!(r->skipped_notes & (1u << k))) {
                r->skipped_notes |= 1u << k;
                rad_info(r->ctx, "%s:%d: MGF '%s' is skipped (not used by a diffuse radiosity "
                         "solve)", r->file, r->line, e);
            }
            return RAD_OK;
        }
    /* Any other word: skipped with one warning for the file set, as MGF's own parser (mgflib,
     * and RenderPark after it) ignores unknown entities; RenderPark's office1/graz.mgf has a
     * stray path name at line 53320. */
    if (r->unknown_count++ == 0) { /* warned about once the file is read (an error first: none) */
        char name[65];
        size_t n = 0;
        for (; e[n] && n < sizeof name - 1; ++n) name[n] = isprint((unsigned char)e[n]) ? e[n] : '?';
        name[n] = '\0';
        snprintf(r->unknown_first, sizeof r->unknown_first, "%s:%d: unknown MGF entity '%s'",
                 r->file, r->line, name);
    }
    return RAD_OK;
}

/* Reads one file: lines (a backslash at the end continues), '#' comments, words. */
static rad_status read_file(mgf_reader *r, const char *path, const mgf_transform *include_xf) {
    /* Only regular files: an include of a FIFO or a device (/dev/stdin) would never end. */
    struct stat info;
    if (stat(path, &info) == 0 && !S_ISREG(info.st_mode))
        return r->include_depth == 0
                   ? rad_fail(r->ctx, RAD_ERROR_IO, "%s: not a regular file", path)
                   : rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: cannot include %s: not a regular file",
                              r->file, r->line, path);
    FILE *file = fopen(path, "rb");
    if (!file) {
        if (r->include_depth == 0) return rad_fail(r->ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
        return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: cannot include %s: %s", r->file, r->line,
                        path, strerror(errno));
    }
    char *copy = rad_alloc(r->ctx, strlen(path) + 1, 1);
    if (!copy || rad_file_list_add(r->ctx, &r->scene->files, path)) { /* a scene's file */
        rad_free(r->ctx, copy);
        fclose(file);
        return RAD_ERROR_NO_MEMORY;
    }
    strcpy(copy, path);
    r->file = copy;
    r->line = 0;
    ++r->include_depth;
    int transform_base = r->transform_depth;
    if (include_xf) {
        if (r->transform_depth >= MGF_MAX_DEPTH) {
            fclose(file);
            rad_free(r->ctx, copy);
            --r->include_depth;
            return MGF_FAIL(r, "%s: transforms nested too deep", path);
        }
        r->transforms[++r->transform_depth] = *include_xf;
        r->arrays[r->transform_depth].spec.dims = 0;
        transform_base = r->transform_depth;
    }
    FILE *includer_stream = r->stream;
    int includer_transform_base = r->file_transform_base;
    r->stream = file;
    r->file_transform_base = transform_base;
    int object_base = r->object_depth;
    size_t capacity = 256, length = 0;
    char *text = rad_alloc(r->ctx, capacity, 1);
    rad_status status = text ? RAD_OK : RAD_ERROR_NO_MEMORY;
    int c = 0, first_line = 0;
    while (!status && c != EOF) {
        length = 0;
        first_line = r->line + 1;
        /* One logical line. */
        for (;;) {
            c = fgetc(file);
            if (c == EOF) break;
            if (c == '\n') {
                ++r->line;
                if (length > 0 && text[length - 1] == '\\') {
                    text[length - 1] = ' ';
                    continue;
                }
                break;
            }
            if (c == '\0') {
                status = MGF_FAIL(r, "%s:%d: not a text file (NUL byte)", r->file, r->line + 1);
                break;
            }
            if (length + 2 > capacity) {
                if (capacity >= (1u << 20)) {
                    status = MGF_FAIL(r, "%s:%d: line longer than 1 MiB", r->file, r->line + 1);
                    break;
                }
                char *grown = rad_realloc(r->ctx, text, capacity * 2, 1);
                if (!grown) {
                    status = RAD_ERROR_NO_MEMORY;
                    break;
                }
                text = grown;
                capacity *= 2;
            }
            text[length++] = (char)c;
        }
        if (status) break;
        if (c == EOF && length > 0) ++r->line;
        text[length] = '\0';
        char *hash = strchr(text, '#');
        if (hash) *hash = '\0';
        char *words[MGF_MAX_WORDS];
        int count = 0;
        for (char *s = text; *s;) {
            while (*s && isspace((unsigned char)*s)) ++s;
            if (!*s) break;
            if (count == MGF_MAX_WORDS) {
                r->line = first_line;
                status = fail_at(r, "more than 512 words in one entity", NULL);
                break;
            }
            words[count++] = s;
            while (*s && !isspace((unsigned char)*s)) ++s;
            if (*s) *s++ = '\0';
        }
        if (status || count == 0) continue;
        int line = r->line;
        r->line = first_line;
        r->line_end = line;
        status = entity(r, words, count);
        r->line = line;
        if (r->rewound_line >= 0) { /* an array's next copy: its body again */
            r->line = r->rewound_line;
            r->rewound_line = -1;
            c = 0;
        }
    }
    if (!status && r->object_depth != object_base)
        status = MGF_FAIL(r, "%s: %d object%s (o NAME) not ended at the end of the file", r->file,
                          r->object_depth - object_base, r->object_depth - object_base > 1 ? "s" : "");
    if (!status && r->transform_depth != transform_base)
        status = MGF_FAIL(r, "%s: a transform (xf) not ended at the end of the file", r->file);
    if (!status && ferror(file)) status = rad_fail(r->ctx, RAD_ERROR_IO, "%s: read error", r->file);
    r->object_depth = object_base;
    r->transform_depth = include_xf ? transform_base - 1 : transform_base;
    r->stream = includer_stream;
    r->file_transform_base = includer_transform_base;
    --r->include_depth;
    rad_free(r->ctx, text);
    fclose(file);
    /* The message keeps the name; the reader's pointer goes back to the includer's. */
    if (r->include_depth > 0) rad_free(r->ctx, copy);
    else r->file = NULL, rad_free(r->ctx, copy);
    return status;
}

rad_status rad_scene_load_mgf(rad_context *ctx, const char *path, rad_scene **out) {
    *out = NULL;
    mgf_reader r = {0};
    r.ctx = ctx;
    r.current_vertex = SIZE_MAX;
    r.rewound_line = -1;
    r.color.x = r.color.y = 1.0 / 3;
    transform_identity(&r.transforms[0]);
    rad_status status = rad_scene_new(ctx, 1, path, &r.scene);
    /* Material 0: MGF's default, black and not emitting (geometry before any m). */
    if (!status) status = grow(&r, (void **)&r.materials, &r.material_capacity, 0, sizeof *r.materials);
    if (!status) {
        mgf_material *m = &r.materials[r.material_count++];
        memset(m, 0, sizeof *m);
        snprintf(m->name, sizeof m->name, "default");
        m->rd_x = m->rd_y = m->ed_x = m->ed_y = 1.0 / 3;
        m->index = UINT32_MAX;
    }
    if (!status) status = read_file(&r, path, NULL);
    if (!status && r.scene->polygon_count == 0)
        status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: no faces or primitives in the MGF file", path);
    if (!status && r.unknown_count > 0)
        rad_warn(ctx, "%s skipped (%zu unknown entit%s skipped in all, as MGF readers do)",
                 r.unknown_first, r.unknown_count, r.unknown_count > 1 ? "ies" : "y");
    if (!status) rad_scene_warn_bright_materials(ctx, r.scene, path, NULL, 0);
    rad_free(ctx, r.vertices);
    rad_free(ctx, r.colors);
    rad_free(ctx, r.materials);
    rad_free(ctx, r.keys);
    rad_hash_index *indexes[] = {&r.vertex_names, &r.color_names, &r.material_names,
                                 &r.key_index, &r.stem_index, &r.surface_names};
    for (size_t i = 0; i < sizeof indexes / sizeof indexes[0]; ++i) rad_hash_index_free(ctx, indexes[i]);
    if (status) {
        rad_scene_destroy(r.scene);
        return status;
    }
    *out = r.scene;
    return RAD_OK;
}
