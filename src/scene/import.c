/* import.c - geometric scenes from files, through assimp's C API (docs/formats.md).
 *
 * 1. assimp reads the file (OBJ/MTL, glTF 2.0/GLB, PLY, STL, Collada, FBX, 3DS, ...) without
 *    post-processing, so faces stay the polygons the file has.
 * 2. The node tree is walked with each node's world transform; every (node, mesh) pair becomes
 *    one named surface: the node's name (or node/material when a node holds several meshes),
 *    made unique with ".2", ".3", ... suffixes. Results are reported per surface.
 * 3. Faces: points and lines are ignored; repeated corners are removed; faces with fewer than
 *    three distinct corners or (near) zero area are dropped and counted in a warning; a corner
 *    with a NaN or infinite coordinate is an error. Faces under a mirroring transform are
 *    turned so that the front stays the front (counter-clockwise). Non-convex faces are cut
 *    into a few convex pieces (scene/polygon_cut.h); convex faces and pieces of more
 *    than 64 corners into a 64-gon through corners spread along them and the caps between its
 *    corners, split the same way (rad_polygon_split); two consecutive
 *    coplanar triangles that form a convex quad are joined again, since the mesher cuts quads
 *    into better elements than triangles.
 * 4. Materials: diffuse reflectance and emitted radiance, plus mirror/glass hints for the
 *    ray-traced pass. Values are kept as the file gives them (a reflectance above 1 is refused
 *    later, when the system is built).
 * 5. The first camera, if the file has one.
 * 6. Textures (scene/texture.h): a material's diffuse or base-colour texture (a file beside the
 *    scene, or an image embedded in it) is decoded here, in the import child, and the first
 *    texture-coordinate channel goes with each polygon's corners. A texture that cannot be used
 *    (missing, not an image, truncated, over the memory budget) is a warning naming it, and the
 *    material keeps its colour factor.
 * 7. Warnings about materials (docs/formats.md, "Materials"): a diffuse reflectance of 0.95 or
 *    more (with its texture's mean when textured), naming the surfaces that use it, and for an
 *    OBJ a note for each `usemtl` that names a material the MTL files lack. */
#include "scene/gltf_extras.h"
#include "scene/import_check.h"
#include "scene/polygon_cut.h"
#include "scene/scene.h"
#include "scene/texture.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/ObjMaterial.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <pthread.h>
#include <limits.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A face is degenerate when its area is below this fraction of its longest edge squared: a
 * height below 2e-7 of its length, which is what rounding to float leaves of collinear points. */
#define DEGENERATE_RELATIVE_AREA 1e-7
/* Two triangles are joined into a quad only when their normals agree to this (cosine). */
#define COPLANAR_COSINE (1.0 - 1e-9)
/* The reflectance of faces without a material of their own (assimp's default material). */
#define DEFAULT_REFLECTANCE 0.5

/* ------------------------------------------------------------------------------------------- */
/* Unique surface names: an open-addressing set of the names given so far.                      */

typedef struct name_set {
    const char **names; /* owned by the scene's surfaces */
    size_t capacity, count;
} name_set;

static uint64_t hash_name(const char *name) {
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (; *name; ++name) h = (h ^ (unsigned char)*name) * 1099511628211ull;
    return h;
}

static int name_set_has(const name_set *set, const char *name) {
    if (!set->capacity) return 0;
    size_t mask = set->capacity - 1;
    for (size_t slot = hash_name(name) & mask; set->names[slot]; slot = (slot + 1) & mask)
        if (strcmp(set->names[slot], name) == 0) return 1;
    return 0;
}

static rad_status name_set_add(rad_context *ctx, name_set *set, const char *name) {
    if (2 * (set->count + 1) > set->capacity) {
        size_t capacity = set->capacity ? set->capacity * 2 : 64;
        const char **names = rad_alloc_zero(ctx, capacity, sizeof *names);
        if (!names) return RAD_ERROR_NO_MEMORY;
        for (size_t i = 0; i < set->capacity; ++i) {
            if (!set->names[i]) continue;
            size_t slot = hash_name(set->names[i]) & (capacity - 1);
            while (names[slot]) slot = (slot + 1) & (capacity - 1);
            names[slot] = set->names[i];
        }
        rad_free(ctx, set->names);
        set->names = names;
        set->capacity = capacity;
    }
    size_t mask = set->capacity - 1, slot = hash_name(name) & mask;
    while (set->names[slot]) slot = (slot + 1) & mask;
    set->names[slot] = name;
    set->count++;
    return RAD_OK;
}

/* ------------------------------------------------------------------------------------------- */
/* Transforms: row-major 4x4, as assimp stores them (a1..a4 is the first row).                  */

typedef struct transform {
    double m[4][4];
} transform;

static transform transform_from(const struct aiMatrix4x4 *a) {
    transform t = {{{a->a1, a->a2, a->a3, a->a4},
                    {a->b1, a->b2, a->b3, a->b4},
                    {a->c1, a->c2, a->c3, a->c4},
                    {a->d1, a->d2, a->d3, a->d4}}};
    return t;
}

static transform transform_multiply(const transform *a, const transform *b) {
    transform t;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += a->m[i][k] * b->m[k][j];
            t.m[i][j] = sum;
        }
    return t;
}

static rad_vec3 transform_point(const transform *t, rad_vec3 p) {
    const double(*m)[4] = t->m;
    double x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
    double y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
    double z = m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3];
    double w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
    if (w != 1.0 && w != 0.0) return v3(x / w, y / w, z / w);
    return v3(x, y, z);
}

static rad_vec3 transform_direction(const transform *t, rad_vec3 d) {
    const double(*m)[4] = t->m;
    return v3(m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z,
              m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z,
              m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z);
}

static double transform_determinant(const transform *t) {
    const double(*m)[4] = t->m;
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* ------------------------------------------------------------------------------------------- */
/* Polygon tests.                                                                               */

static int finite3(rad_vec3 p) { return isfinite(p.x) && isfinite(p.y) && isfinite(p.z); }

static int same_point(rad_vec3 a, rad_vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Newell's normal: its length is twice the area. */
static rad_vec3 newell_normal(const rad_vec3 *p, size_t n) { return v3_newell_normal(p, n); }

static int degenerate(const rad_vec3 *p, size_t n) {
    if (n < 3) return 1;
    double longest = 0;
    for (size_t k = 0; k < n; ++k) longest = fmax(longest, v3_length(v3_sub(p[(k + 1) % n], p[k])));
    double area = 0.5 * v3_length(newell_normal(p, n));
    return !(area > DEGENERATE_RELATIVE_AREA * longest * longest);
}

/* Convex and simple, seen from the side its Newell normal points to: projected onto the plane
 * across that normal (so slightly non-planar quads count), every corner turns left or goes
 * straight, and the turns add up to one full turn. A corner that turns right but lies less than
 * `dent` inside the line through its neighbours goes straight. Faces of more than
 * RAD_POLYGON_CORNERS_MAX corners are judged with a dent of STRAIGHT_DENT times their extent: a
 * circle of many corners written with six decimals has such dents everywhere, and cut as
 * non-convex it became a fan of slivers meeting in one corner (split_face). */
#define STRAIGHT_DENT 1e-6
static int convex_within(const rad_vec3 *p, size_t n, double dent) {
    rad_vec3 normal = v3_normalize(newell_normal(p, n)), u, v;
    v3_basis(normal, &u, &v);
    double turning = 0;
    for (size_t k = 0; k < n; ++k) {
        rad_vec3 a3 = v3_sub(p[(k + 1) % n], p[k]), b3 = v3_sub(p[(k + 2) % n], p[(k + 1) % n]);
        double ax = v3_dot(a3, u), ay = v3_dot(a3, v), bx = v3_dot(b3, u), by = v3_dot(b3, v);
        double sine = ax * by - ay * bx, cosine = ax * bx + ay * by;
        /* sine / |a + b| is how far the corner lies off the line through its neighbours. */
        if (sine < -1e-12 * (fabs(ax) + fabs(ay)) * (fabs(bx) + fabs(by)) &&
            -sine > dent * hypot(ax + bx, ay + by))
            return 0;
        turning += atan2(sine, cosine);
    }
    return fabs(turning - 2 * RAD_PI) < 1e-6;
}

static int convex(const rad_vec3 *p, size_t n) { return convex_within(p, n, 0); }

/* ------------------------------------------------------------------------------------------- */

typedef struct face {
    size_t count;
    rad_vec3 *points;
    uint32_t *corners; /* assimp vertex indices of the mesh */
} face;

typedef struct importer {
    rad_context *ctx;
    rad_scene *scene;
    const struct aiScene *ai;
    const char *path;
    int is_gltf;
    rad_gltf_extras gltf;
    uint32_t *material_of; /* per assimp material: scene material, or UINT32_MAX */
    name_set names;

    /* The (node, mesh) being read. */
    const struct aiNode *node;
    const struct aiMesh *mesh;
    uint32_t surface; /* UINT32_MAX until its first face */
    uint32_t *vertex_of; /* per mesh vertex: scene vertex, or UINT32_MAX */
    size_t vertex_of_capacity;
    rad_vec3 *points;   /* a face's corners: scratch */
    uint32_t *corners;
    size_t scratch_capacity;
    /* A triangle waiting for a partner to make a quad with. */
    int pending;
    rad_vec3 pending_points[3];
    uint32_t pending_corners[3];

    char label[256]; /* object_label's storage */
    rad_file_list opened; /* every file read: assimp's (recording_open) and textures */
    rad_status opened_status; /* RAD_ERROR_NO_MEMORY when a path could not be recorded */
    struct usemtl_scan *usemtl; /* OBJ: the scan for usemtl notes, beside assimp */
    pthread_t usemtl_thread;
    int usemtl_running;

    /* What was done, for the notes at the end. */
    size_t degenerate, points_and_lines, turned, cut, split, joined;
    size_t tangled; /* non-convex faces that cross themselves in their plane */
    size_t textured_without_uv; /* textured surfaces whose mesh has no texture coordinates */
    uint8_t *texture_lost; /* per scene material: its texture could not be used */
    size_t texture_lost_capacity;
    int last_texture_lost; /* set by material_texture */
} importer;

static int has_extension(const char *path, const char *extension);

/* The stem of a path: "dir/room.obj" -> "room". */
static void path_stem(const char *path, char *stem, size_t size) {
    const char *slash = strrchr(path, '/');
    const char *start = slash ? slash + 1 : path;
    const char *dot = strrchr(start, '.');
    size_t length = dot && dot > start ? (size_t)(dot - start) : strlen(start);
    if (length >= size) length = size - 1;
    memcpy(stem, start, length);
    stem[length] = '\0';
}

static int material_color(const struct aiMaterial *m, const char *key, unsigned type,
                          unsigned index, double rgb[3]) {
    struct aiColor4D c;
    if (aiGetMaterialColor(m, key, type, index, &c) != aiReturn_SUCCESS) return 0;
    rgb[0] = c.r;
    rgb[1] = c.g;
    rgb[2] = c.b;
    return 1;
}

static int material_float(const struct aiMaterial *m, const char *key, unsigned type,
                          unsigned index, double *value) {
    ai_real v;
    unsigned count = 1;
    if (aiGetMaterialFloatArray(m, key, type, index, &v, &count) != aiReturn_SUCCESS || count < 1)
        return 0;
    *value = v;
    return 1;
}

static int material_int(const struct aiMaterial *m, const char *key, unsigned type,
                        unsigned index, int *value) {
    unsigned count = 1;
    return aiGetMaterialIntegerArray(m, key, type, index, value, &count) == aiReturn_SUCCESS &&
           count >= 1;
}

/* ------------------------------------------------------------------------------------------- */
/* Textures                                                                                     */

/* The directory part of a path, with its slash ("dir/"), or "" for a bare name. */
static void path_directory(const char *path, char *out, size_t size) {
    const char *slash = strrchr(path, '/');
    size_t length = slash ? (size_t)(slash - path + 1) : 0;
    if (length >= size) length = size - 1;
    memcpy(out, path, length);
    out[length] = '\0';
}

/* An image embedded in the scene file: "*N" (glTF buffers, GLB, FBX) or one whose file name
 * the material gives. Decodes it into *out; 0 when the reference is not to an embedded image. */
static int embedded_texture(importer *im, const char *reference, char *name, size_t name_size,
                            rad_texture **out, rad_status *status) {
    const struct aiScene *ai = im->ai;
    unsigned index = ai->mNumTextures;
    if (reference[0] == '*') {
        char *end;
        unsigned long n = strtoul(reference + 1, &end, 10);
        if (*end || n >= ai->mNumTextures) {
            *status = rad_fail(im->ctx, RAD_ERROR_PARSE, "no embedded image %s", reference);
            return 1;
        }
        index = (unsigned)n;
    } else {
        for (unsigned i = 0; i < ai->mNumTextures; ++i)
            if (ai->mTextures[i] && strcmp(ai->mTextures[i]->mFilename.data, reference) == 0)
                index = i;
    }
    if (index >= ai->mNumTextures) return 0;
    const struct aiTexture *t = ai->mTextures[index];
    snprintf(name, name_size, "%s: embedded image %u", im->path, index);
    if (!t || !t->pcData) {
        *status = rad_fail(im->ctx, RAD_ERROR_PARSE, "the embedded image has no data");
    } else if (t->mHeight == 0) {
        *status = rad_texture_decode(im->ctx, name, t->pcData, t->mWidth, out);
    } else {
        /* Raw texels (B, G, R, A bytes each). */
        size_t count = (size_t)t->mWidth * t->mHeight;
        *status = rad_check_budget(im->ctx, 3.0 * (double)count, "the texture");
        uint8_t *texels = *status ? NULL : rad_alloc(im->ctx, count, 3);
        if (!*status && !texels) *status = RAD_ERROR_NO_MEMORY;
        for (size_t i = 0; texels && i < count; ++i) {
            texels[3 * i] = t->pcData[i].r;
            texels[3 * i + 1] = t->pcData[i].g;
            texels[3 * i + 2] = t->pcData[i].b;
        }
        if (!*status)
            *status = rad_texture_from_texels(im->ctx, name, t->mWidth, t->mHeight, texels, out);
        rad_free(im->ctx, texels);
    }
    return 1;
}

/* The colour texture of assimp material `m` for scene material `mat`, or NULL with a warning
 * when it cannot be used. Textures already read are shared by name. Only running out of memory
 * is an error. */
static rad_status material_texture(importer *im, const struct aiMaterial *m, rad_material *mat) {
    struct aiString reference;
    if (aiGetMaterialTexture(m, aiTextureType_BASE_COLOR, 0, &reference, NULL, NULL, NULL, NULL,
                             NULL, NULL) != aiReturn_SUCCESS &&
        aiGetMaterialTexture(m, aiTextureType_DIFFUSE, 0, &reference, NULL, NULL, NULL, NULL,
                             NULL, NULL) != aiReturn_SUCCESS)
        return RAD_OK;
    if (reference.length == 0) return RAD_OK;
    char name[2 * MAXLEN + 64], directory[MAXLEN];
    rad_texture *texture = NULL;
    rad_status status = RAD_OK;
    /* A failed decode is a warning: the context's error callback is not told. */
    rad_error_fn on_error = im->ctx->on_error;
    im->ctx->on_error = NULL;
    if (!embedded_texture(im, reference.data, name, sizeof name, &texture, &status)) {
        /* A file: relative to the scene's directory, with '\' read as '/'. */
        char relative[MAXLEN];
        snprintf(relative, sizeof relative, "%s", reference.data);
        for (char *c = relative; *c; ++c)
            if (*c == '\\') *c = '/';
        path_directory(im->path, directory, sizeof directory);
        snprintf(name, sizeof name, "%s%s", relative[0] == '/' ? "" : directory, relative);
        for (size_t i = 0; i < im->scene->texture_count; ++i)
            if (strcmp(im->scene->textures[i]->name, name) == 0) {
                im->ctx->on_error = on_error;
                mat->texture = im->scene->textures[i];
                return RAD_OK;
            }
        status = rad_texture_read(im->ctx, name, &texture);
        struct stat info; /* a texture there, read or not, is the scene's file */
        if (stat(name, &info) == 0 && !im->opened_status)
            im->opened_status = rad_file_list_add(im->ctx, &im->opened, name);
    }
    im->ctx->on_error = on_error;
    if (status == RAD_ERROR_NO_MEMORY) return status;
    if (status) {
        im->last_texture_lost = 1;
        rad_warn(im->ctx, "%s: material '%s': texture '%s' not used (%s); its colour factor "
                 "%g %g %g is used instead", im->path, mat->name, name,
                 rad_context_error(im->ctx), mat->reflectance[0], mat->reflectance[1],
                 mat->reflectance[2]);
        return RAD_OK;
    }
    status = rad_scene_add_texture(im->scene, texture, NULL);
    rad_texture_release(texture); /* the scene's reference is the one left */
    if (!status) mat->texture = texture;
    return status;
}

/* Translates assimp material `index` into a scene material (docs/formats.md, "Materials"). */
static rad_status convert_material(importer *im, unsigned index, uint32_t *out) {
    const struct aiMaterial *m = im->ai->mMaterials[index];
    rad_material mat = {0};
    char name[64];
    struct aiString ai_name;
    int named = aiGetMaterialString(m, AI_MATKEY_NAME, &ai_name) == aiReturn_SUCCESS &&
                ai_name.length > 0;
    /* assimp's stand-in for faces without a material: by name (OBJ, STL), as the extra last
     * material (glTF), or unnamed in formats without materials (PLY). */
    int fallback = named ? strcmp(ai_name.data, AI_DEFAULT_MATERIAL_NAME) == 0
                         : !im->is_gltf || index >= im->gltf.material_count;
    if (named) mat.name = ai_name.data;
    else {
        snprintf(name, sizeof name, fallback ? "default" : "material-%u", index);
        mat.name = name;
    }
    mat.kind = RAD_MATERIAL_DIFFUSE;
    mat.ior = 1.5;
    if (fallback) {
        for (int c = 0; c < 3; ++c) mat.reflectance[c] = DEFAULT_REFLECTANCE;
        return rad_scene_add_material(im->scene, &mat, out);
    }

    double base[3] = {DEFAULT_REFLECTANCE, DEFAULT_REFLECTANCE, DEFAULT_REFLECTANCE};
    if (!material_color(m, AI_MATKEY_BASE_COLOR, base)) material_color(m, AI_MATKEY_COLOR_DIFFUSE, base);
    memcpy(mat.reflectance, base, sizeof base);

    /* Emitted radiance: Ke (OBJ) or emissiveFactor x emissiveStrength (glTF). */
    double emission[3] = {0, 0, 0}, strength = 1;
    material_color(m, AI_MATKEY_COLOR_EMISSIVE, emission);
    if (!material_float(m, AI_MATKEY_EMISSIVE_INTENSITY, &strength) && im->is_gltf &&
        index < im->gltf.material_count)
        strength = im->gltf.emissive_strength[index];
    for (int c = 0; c < 3; ++c) mat.emission[c] = emission[c] * strength;

    double ior = 0, metallic = 0, roughness = 1, transmission = 0, opacity = 1, shininess = 0;
    material_float(m, AI_MATKEY_REFRACTI, &ior);
    if (ior > 1) mat.ior = ior;
    if (material_float(m, AI_MATKEY_METALLIC_FACTOR, &metallic)) {
        /* glTF metallic-roughness. */
        material_float(m, AI_MATKEY_ROUGHNESS_FACTOR, &roughness);
        material_float(m, AI_MATKEY_TRANSMISSION_FACTOR, &transmission);
        if (transmission > 0) {
            mat.kind = RAD_MATERIAL_GLASS;
            for (int c = 0; c < 3; ++c) {
                mat.specular[c] = base[c];
                mat.reflectance[c] = base[c] * (1 - transmission);
            }
            mat.roughness = roughness;
        } else if (metallic >= 0.5) {
            mat.kind = RAD_MATERIAL_MIRROR;
            for (int c = 0; c < 3; ++c) {
                mat.specular[c] = base[c];
                mat.reflectance[c] = base[c] * (1 - metallic);
            }
            mat.roughness = roughness;
        }
    } else {
        /* Wavefront MTL and other classic materials: illum, Ks, Ns, Ni, d, Tf. */
        int illum = -1;
        material_int(m, AI_MATKEY_OBJ_ILLUM, &illum);
        material_float(m, AI_MATKEY_OPACITY, &opacity);
        material_float(m, AI_MATKEY_SHININESS, &shininess);
        if (illum == 4 || illum == 6 || illum == 7 || illum == 9 || opacity < 1) {
            mat.kind = RAD_MATERIAL_GLASS;
            double filter[3] = {1, 1, 1};
            material_color(m, AI_MATKEY_COLOR_TRANSPARENT, filter);
            memcpy(mat.specular, filter, sizeof filter);
        } else if (illum == 3 || illum == 5) {
            mat.kind = RAD_MATERIAL_MIRROR;
            double specular[3] = {1, 1, 1};
            material_color(m, AI_MATKEY_COLOR_SPECULAR, specular);
            memcpy(mat.specular, specular, sizeof specular);
            /* Blender's convention: Ns = 1000 (1 - roughness)^2; no Ns means a perfect mirror. */
            mat.roughness = shininess > 0 ? fmin(1.0, fmax(0.0, 1 - sqrt(shininess / 1000))) : 0;
        }
    }
    int two_sided = 0; /* glTF doubleSided, and what else assimp marks two-sided */
    if (material_int(m, AI_MATKEY_TWOSIDED, &two_sided)) mat.two_sided = two_sided != 0;
    im->last_texture_lost = 0;
    rad_status status = material_texture(im, m, &mat);
    if (!status) status = rad_scene_add_material(im->scene, &mat, out);
    if (!status && im->last_texture_lost) {
        if (*out >= im->texture_lost_capacity) {
            size_t capacity = 2 * (size_t)*out + 16;
            uint8_t *grown = rad_realloc(im->ctx, im->texture_lost, capacity, 1);
            if (!grown) return RAD_ERROR_NO_MEMORY;
            memset(grown + im->texture_lost_capacity, 0, capacity - im->texture_lost_capacity);
            im->texture_lost = grown;
            im->texture_lost_capacity = capacity;
        }
        im->texture_lost[*out] = 1;
    }
    return status;
}

static rad_status material_for(importer *im, unsigned index, uint32_t *out) {
    if (index >= im->ai->mNumMaterials)
        return rad_fail(im->ctx, RAD_ERROR_PARSE, "%s: a mesh uses material %u of %u", im->path,
                        index, im->ai->mNumMaterials);
    if (im->material_of[index] == UINT32_MAX) {
        rad_status status = convert_material(im, index, &im->material_of[index]);
        if (status) return status;
    }
    *out = im->material_of[index];
    return RAD_OK;
}

/* The surface of the current (node, mesh), made on its first face. */
static rad_status current_surface(importer *im, uint32_t *out) {
    if (im->surface != UINT32_MAX) {
        *out = im->surface;
        return RAD_OK;
    }
    const struct aiNode *node = im->node;
    const struct aiMesh *mesh = im->mesh;
    char base[2 * MAXLEN + 2], name[2 * MAXLEN + 16], stem[256];
    path_stem(im->path, stem, sizeof stem);
    const char *node_name = node->mName.length ? node->mName.data : "";
    const char *mesh_name = mesh->mName.length ? mesh->mName.data : "";
    if (node->mNumMeshes > 1 && node_name[0]) {
        /* Several meshes under one node: one per material (OBJ usemtl, glTF primitives). */
        const char *detail = mesh_name;
        struct aiString material_name;
        if ((!detail[0] || strcmp(detail, node_name) == 0) &&
            mesh->mMaterialIndex < im->ai->mNumMaterials &&
            aiGetMaterialString(im->ai->mMaterials[mesh->mMaterialIndex], AI_MATKEY_NAME,
                                &material_name) == aiReturn_SUCCESS && material_name.length)
            detail = material_name.data;
        if (detail[0] && strcmp(detail, node_name) != 0)
            snprintf(base, sizeof base, "%s/%s", node_name, detail);
        else snprintf(base, sizeof base, "%s", node_name);
    } else {
        snprintf(base, sizeof base, "%s",
                 node_name[0] ? node_name : mesh_name[0] ? mesh_name : stem[0] ? stem : "surface");
    }
    /* Unique: "name", "name.2", "name.3", ... */
    snprintf(name, sizeof name, "%s", base);
    for (unsigned suffix = 2; name_set_has(&im->names, name); ++suffix)
        snprintf(name, sizeof name, "%s.%u", base, suffix);
    uint32_t material = 0;
    rad_status status = material_for(im, mesh->mMaterialIndex, &material);
    if (!status) status = rad_scene_add_surface(im->scene, name, material, &im->surface);
    if (!status && im->scene->materials[material].texture && !mesh->mTextureCoords[0])
        im->textured_without_uv++;
    if (!status)
        status = name_set_add(im->ctx, &im->names, im->scene->surfaces[im->surface].name);
    if (!status) *out = im->surface;
    return status;
}

/* Adds a polygon (already checked: convex, not degenerate) to the current surface. */
static rad_status emit(importer *im, const rad_vec3 *points, const uint32_t *corners, size_t n) {
    uint32_t surface, indices[RAD_POLYGON_CORNERS_MAX];
    rad_status status = current_surface(im, &surface);
    for (size_t k = 0; k < n && !status; ++k) {
        uint32_t *mapped = &im->vertex_of[corners[k]];
        if (*mapped == UINT32_MAX) status = rad_scene_add_vertex(im->scene, points[k], mapped);
        indices[k] = *mapped;
    }
    if (!status) status = rad_scene_add_polygon(im->scene, surface, indices, (uint32_t)n);
    /* Texture coordinates, for textured materials (channel 0). */
    if (!status && im->scene->materials[im->scene->surfaces[surface].material].texture &&
        im->mesh->mTextureCoords[0]) {
        float uv[RAD_POLYGON_CORNERS_MAX][2];
        for (size_t k = 0; k < n; ++k) {
            const struct aiVector3D *t = &im->mesh->mTextureCoords[0][corners[k]];
            uv[k][0] = (float)t->x;
            uv[k][1] = (float)t->y;
        }
        status = rad_scene_set_last_uvs(im->scene, (const float(*)[2])uv, (uint32_t)n);
    }
    return status;
}

static rad_status flush_pending(importer *im) {
    if (!im->pending) return RAD_OK;
    im->pending = 0;
    return emit(im, im->pending_points, im->pending_corners, 3);
}

/* Joins the pending triangle and triangle t into a convex, flat quad, if they share an edge. */
static int join_triangles(importer *im, const rad_vec3 *t, const uint32_t *tc, rad_vec3 *quad,
                          uint32_t *quad_corners) {
    const rad_vec3 *s = im->pending_points;
    rad_vec3 ns = v3_normalize(newell_normal(s, 3)), nt = v3_normalize(newell_normal(t, 3));
    if (v3_dot(ns, nt) < COPLANAR_COSINE) return 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            /* s has the edge x -> y (x = s[i]), t has y -> x: the quad is y, z, x, w. */
            if (!same_point(s[i], t[(j + 1) % 3]) || !same_point(s[(i + 1) % 3], t[j])) continue;
            int order_s[3] = {(i + 1) % 3, (i + 2) % 3, i};
            for (int k = 0; k < 3; ++k) {
                quad[k] = s[order_s[k]];
                quad_corners[k] = im->pending_corners[order_s[k]];
            }
            quad[3] = t[(j + 2) % 3];
            quad_corners[3] = tc[(j + 2) % 3];
            return convex(quad, 4) && !degenerate(quad, 4);
        }
    return 0;
}

static rad_status emit_piece(importer *im, const face *f, const uint32_t *piece, size_t n) {
    rad_vec3 points[RAD_POLYGON_CORNERS_MAX];
    uint32_t corners[RAD_POLYGON_CORNERS_MAX];
    for (size_t k = 0; k < n; ++k) {
        points[k] = f->points[piece[k]];
        corners[k] = f->corners[piece[k]];
    }
    return degenerate(points, n) ? RAD_OK : emit(im, points, corners, n);
}

/* Emits the pieces a face was cut or split into (scene/polygon_cut.h), each of at most
 * RAD_POLYGON_CORNERS_MAX corners; pieces with no area are dropped. */
static rad_status emit_pieces(importer *im, const face *f, rad_polygon_pieces *pieces,
                              rad_status status) {
    for (size_t k = 0; k < pieces->count && !status; ++k)
        status = emit_piece(im, f, pieces->corners + pieces->first[k],
                            pieces->first[k + 1] - pieces->first[k]);
    rad_polygon_pieces_free(im->ctx, pieces);
    return status;
}

/* Cuts a non-convex face into convex pieces in its plane (scene/polygon_cut.h: ear clipping
 * through a grid of reflex corners, then Hertel and Mehlhorn's removal of the diagonals that
 * convexity does not need); corners dented by less than `dent` count as straight, and pieces
 * of more than RAD_POLYGON_CORNERS_MAX corners are split as convex faces are. A face that
 * crosses itself in its plane is emitted as the triangles it was clipped into and counted. */
static rad_status cut_face(importer *im, const face *f, double dent) {
    rad_polygon_pieces pieces = {0};
    rad_status status = rad_polygon_cut_in_plane(im->ctx, f->points, f->count,
                                                 v3_normalize(newell_normal(f->points, f->count)),
                                                 dent, RAD_POLYGON_CORNERS_MAX, 0, &pieces);
    if (!status && !pieces.simple) im->tangled++;
    return emit_pieces(im, f, &pieces, status);
}

/* A convex face of more than RAD_POLYGON_CORNERS_MAX corners, split into a core polygon and
 * caps (rad_polygon_split): every corner is in a few pieces, where ear clipping made a fan of
 * n - 2 slivers meeting in one corner (the contact search then met every pair, the smooth
 * shading's neighbours every sliver). A cap whose corners all lie within `straight` of its
 * chord is dropped: it is the rounding's dents (turned inside out, as likely as not). */
static rad_status split_face(importer *im, const face *f, double straight) {
    rad_polygon_pieces pieces = {0};
    rad_status status = rad_polygon_cut_in_plane(im->ctx, f->points, f->count,
                                                 v3_normalize(newell_normal(f->points, f->count)),
                                                 straight, RAD_POLYGON_CORNERS_MAX, 1, &pieces);
    return emit_pieces(im, f, &pieces, status);
}

static rad_status add_face(importer *im, face *f) {
    if (degenerate(f->points, f->count)) {
        im->degenerate++;
        return RAD_OK;
    }
    if (f->count == 3) {
        rad_vec3 quad[4];
        uint32_t quad_corners[4];
        if (im->pending && join_triangles(im, f->points, f->corners, quad, quad_corners)) {
            im->pending = 0;
            im->joined++;
            return emit(im, quad, quad_corners, 4);
        }
        rad_status status = flush_pending(im);
        im->pending = 1;
        memcpy(im->pending_points, f->points, sizeof im->pending_points);
        memcpy(im->pending_corners, f->corners, sizeof im->pending_corners);
        return status;
    }
    rad_status status = flush_pending(im);
    if (status) return status;
    if (f->count <= RAD_POLYGON_CORNERS_MAX && convex(f->points, f->count))
        return emit(im, f->points, f->corners, f->count);
    double dent = 0;
    if (f->count > RAD_POLYGON_CORNERS_MAX) {
        rad_vec3 lo = f->points[0], hi = f->points[0];
        for (size_t k = 1; k < f->count; ++k) {
            lo = v3_min(lo, f->points[k]);
            hi = v3_max(hi, f->points[k]);
        }
        dent = STRAIGHT_DENT * v3_length(v3_sub(hi, lo));
    }
    if (f->count <= RAD_POLYGON_CORNERS_MAX || !convex_within(f->points, f->count, dent)) {
        im->cut++;
        return cut_face(im, f, dent);
    }
    im->split++;
    return split_face(im, f, dent);
}

static rad_status grow_scratch(importer *im, size_t corners, size_t vertices) {
    rad_context *ctx = im->ctx;
    if (corners > im->scratch_capacity) {
        rad_free(ctx, im->points);
        rad_free(ctx, im->corners);
        im->points = rad_alloc(ctx, corners, sizeof *im->points);
        im->corners = rad_alloc(ctx, corners, sizeof *im->corners);
        im->scratch_capacity = corners;
        if (!im->points || !im->corners) {
            im->scratch_capacity = 0;
            return RAD_ERROR_NO_MEMORY;
        }
    }
    if (vertices > im->vertex_of_capacity) {
        rad_free(ctx, im->vertex_of);
        im->vertex_of = rad_alloc(ctx, vertices, sizeof *im->vertex_of);
        im->vertex_of_capacity = im->vertex_of ? vertices : 0;
        if (!im->vertex_of) return RAD_ERROR_NO_MEMORY;
    }
    return RAD_OK;
}

/* A name for messages: the node's, the mesh's, or the file's. */
static const char *object_label(importer *im, const struct aiNode *node,
                                const struct aiMesh *mesh) {
    if (node->mName.length) return node->mName.data;
    if (mesh->mName.length) return mesh->mName.data;
    path_stem(im->path, im->label, sizeof im->label);
    return im->label;
}

static rad_status read_mesh(importer *im, const struct aiNode *node, const struct aiMesh *mesh,
                            const transform *world) {
    if (!mesh->mFaces || !mesh->mVertices) return RAD_OK; /* nothing to read */
    size_t largest = 3;
    for (unsigned i = 0; i < mesh->mNumFaces; ++i)
        if (mesh->mFaces[i].mNumIndices > largest) largest = mesh->mFaces[i].mNumIndices;
    rad_status status = grow_scratch(im, largest, mesh->mNumVertices ? mesh->mNumVertices : 1);
    if (status) return status;
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) im->vertex_of[i] = UINT32_MAX;
    im->node = node;
    im->mesh = mesh;
    im->surface = UINT32_MAX;
    im->pending = 0;
    int mirrored = transform_determinant(world) < 0;

    for (unsigned i = 0; i < mesh->mNumFaces && !status; ++i) {
        const struct aiFace *ai_face = &mesh->mFaces[i];
        if (ai_face->mNumIndices < 3) {
            im->points_and_lines++;
            continue;
        }
        face f = {0, im->points, im->corners};
        for (unsigned k = 0; k < ai_face->mNumIndices; ++k) {
            /* Turn faces under a mirroring transform: their front stays the front. */
            unsigned index = ai_face->mIndices[mirrored ? ai_face->mNumIndices - 1 - k : k];
            if (index >= mesh->mNumVertices)
                return rad_fail(im->ctx, RAD_ERROR_PARSE, "%s: object '%s': face %u uses vertex "
                                "%u, but the object has %u vertices", im->path,
                                object_label(im, node, mesh), i, index, mesh->mNumVertices);
            const struct aiVector3D *a = &mesh->mVertices[index];
            rad_vec3 p = transform_point(world, v3(a->x, a->y, a->z));
            if (!finite3(p) && finite3(v3(a->x, a->y, a->z)))
                return rad_fail(im->ctx, RAD_ERROR_PARSE, "%s: object '%s': vertex %u (%g %g "
                                "%g) is not finite once its node's transform is applied",
                                im->path, object_label(im, node, mesh), index, (double)a->x,
                                (double)a->y, (double)a->z);
            if (!finite3(p))
                return rad_fail(im->ctx, RAD_ERROR_PARSE, "%s: object '%s': vertex %u has a "
                                "coordinate that is not a finite number in single precision "
                                "(%g %g %g; assimp reads beyond 3.4e38 as inf)", im->path,
                                object_label(im, node, mesh), index, (double)a->x,
                                (double)a->y, (double)a->z);
            /* Repeated corners (consecutive, or the last one again) add nothing. */
            if (f.count > 0 && same_point(p, f.points[f.count - 1])) continue;
            f.points[f.count] = p;
            f.corners[f.count] = index;
            f.count++;
        }
        while (f.count > 1 && same_point(f.points[0], f.points[f.count - 1])) f.count--;
        if (mirrored) im->turned++;
        status = add_face(im, &f);
    }
    if (!status) status = flush_pending(im);
    return status;
}

static rad_status read_node(importer *im, const struct aiNode *node, const transform *parent,
                            int depth) {
    if (!node) return RAD_OK; /* assimp's RAW reader leaves empty child slots */
    if (depth > 1000)
        return rad_fail(im->ctx, RAD_ERROR_PARSE, "%s: the node tree is too deep", im->path);
    transform local = transform_from(&node->mTransformation);
    transform world = transform_multiply(parent, &local);
    rad_status status = RAD_OK;
    for (unsigned i = 0; i < node->mNumMeshes && !status; ++i) {
        unsigned index = node->mMeshes[i];
        if (index >= im->ai->mNumMeshes)
            return rad_fail(im->ctx, RAD_ERROR_PARSE, "%s: node '%s' uses mesh %u of %u",
                            im->path, node->mName.data, index, im->ai->mNumMeshes);
        if (!im->ai->mMeshes[index]) continue;
        status = read_mesh(im, node, im->ai->mMeshes[index], &world);
    }
    for (unsigned i = 0; i < node->mNumChildren && !status; ++i)
        status = read_node(im, node->mChildren[i], &world, depth + 1);
    return status;
}

/* The world transform of the node called `name`; returns 0 when there is none. */
static int find_node(const struct aiNode *node, const char *name, const transform *parent,
                     transform *out, int depth) {
    if (!node) return 0;
    transform local = transform_from(&node->mTransformation);
    transform world = transform_multiply(parent, &local);
    if (strcmp(node->mName.data, name) == 0) {
        *out = world;
        return 1;
    }
    for (unsigned i = 0; i < node->mNumChildren && depth < 1000; ++i)
        if (find_node(node->mChildren[i], name, &world, out, depth + 1)) return 1;
    return 0;
}

static const transform identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};

/* The first camera: position, view direction and up in world space; the vertical field of
 * view from glTF's yfov, or from assimp's half horizontal angle and aspect ratio. A glTF camera
 * is by definition at its node's origin looking along the node's -z with +y up; assimp 5.2.5
 * also copies the node's translation into mPosition (applying it twice), so for glTF the
 * camera's own fields are not used. */
static void read_camera(importer *im) {
    const struct aiCamera *camera = im->ai->mCameras[0];
    transform world = identity;
    find_node(im->ai->mRootNode, camera->mName.data, &identity, &world, 0);
    rad_vec3 position = v3(camera->mPosition.x, camera->mPosition.y, camera->mPosition.z);
    rad_vec3 look = v3(camera->mLookAt.x, camera->mLookAt.y, camera->mLookAt.z);
    rad_vec3 up = v3(camera->mUp.x, camera->mUp.y, camera->mUp.z);
    if (im->is_gltf) {
        position = v3(0, 0, 0);
        look = v3(0, 0, -1);
        up = v3(0, 1, 0);
    }
    /* 3DS files are z-up (assimp turns the root node to y-up), but assimp 5.2.5 leaves the
     * camera's up at its default +y of the file's space, which the turn makes -z: the camera
     * came in rolled by 90 degrees (Sponza's). Up in the file is +z. */
    if (has_extension(im->path, ".3ds")) up = v3(0, 0, 1);
    rad_vec3 eye = transform_point(&world, position);
    rad_vec3 view = v3_normalize(transform_direction(&world, look));
    up = v3_normalize(transform_direction(&world, up));
    double fov;
    if (im->is_gltf && im->gltf.camera_count > 0) {
        fov = im->gltf.camera_yfov[0] * 180 / RAD_PI;
    } else {
        double aspect = camera->mAspect > 0 ? camera->mAspect : 1;
        fov = 2 * atan(tan(camera->mHorizontalFOV) / aspect) * 180 / RAD_PI;
    }
    if (!(fov > 0 && fov < 180) || !finite3(eye) || !(v3_length(view) > 0) ||
        !(v3_length(up) > 0)) {
        rad_warn(im->ctx, "%s: camera '%s' is not a perspective camera this program can use; "
                 "ignored", im->path, camera->mName.data);
        return;
    }
    im->scene->has_camera = 1;
    im->scene->camera = (rad_camera){eye, v3_add(eye, view), up, fov};
}

/* OBJ: a note for each material a `usemtl` names that no MTL file gave (assimp makes a
 * material of that name with its own defaults). The MTL files are those `mtllib` names,
 * beside the OBJ; their `newmtl` names are the known ones. */
#define MTL_NAMES 4096

/* The text after a statement's keyword on a line, trimmed; NULL when the line is not it. */
static char *statement(char *line, const char *keyword) {
    size_t n = strlen(keyword);
    while (*line == ' ' || *line == '\t') ++line;
    if (strncmp(line, keyword, n) != 0 || (line[n] != ' ' && line[n] != '\t')) return NULL;
    line += n;
    while (*line == ' ' || *line == '\t') ++line;
    size_t length = strcspn(line, "\r\n");
    while (length > 0 && (line[length - 1] == ' ' || line[length - 1] == '\t')) --length;
    line[length] = '\0';
    return length ? line : NULL;
}

/* What the scan found: the first usemtl lines naming unknown materials (at most 8). */
typedef struct usemtl_scan {
    const char *path;
    char (*known)[128]; /* MTL_NAMES names: scratch */
    size_t notes;
    unsigned note_line[8];
    char note_name[8][128];
} usemtl_scan;

/* Reads the OBJ (and the MTL files it names) for the notes; touches nothing else, so it can
 * run beside assimp's reader. */
static void *usemtl_scan_run(void *user) {
    usemtl_scan *scan = user;
    FILE *file = fopen(scan->path, "r");
    if (!file) return NULL;
    char (*known)[128] = scan->known;
    size_t count = 0;
    char line[1024], directory[MAXLEN], mtl_path[2 * MAXLEN];
    path_directory(scan->path, directory, sizeof directory);
    while (fgets(line, sizeof line, file)) {
        const char *library = statement(line, "mtllib");
        if (!library) continue;
        snprintf(mtl_path, sizeof mtl_path, "%s%s", library[0] == '/' ? "" : directory, library);
        FILE *mtl = fopen(mtl_path, "r");
        if (!mtl) continue;
        char entry[1024];
        while (fgets(entry, sizeof entry, mtl) && count < MTL_NAMES) {
            const char *name = statement(entry, "newmtl");
            if (name) snprintf(known[count++], sizeof known[0], "%s", name);
        }
        fclose(mtl);
    }
    rewind(file);
    size_t first_unknown = count;
    for (unsigned number = 1; fgets(line, sizeof line, file); ++number) {
        const char *name = statement(line, "usemtl");
        if (!name) continue;
        int seen = 0;
        for (size_t i = 0; i < count && !seen; ++i) seen = strncmp(known[i], name, sizeof known[0] - 1) == 0;
        if (seen || count >= MTL_NAMES) continue;
        scan->note_line[scan->notes] = number;
        snprintf(scan->note_name[scan->notes++], sizeof scan->note_name[0], "%s", name);
        snprintf(known[count++], sizeof known[0], "%s", name); /* once per name */
        if (count - first_unknown >= 8) break;
    }
    fclose(file);
    return NULL;
}

/* Starts the scan of an OBJ: on a thread of its own beside assimp's reader when the context
 * has more than one (a 10^6-triangle OBJ is 57 MB read twice: 0.13 s), else later, in
 * note_unknown_usemtl. */
static void usemtl_scan_start(importer *im) {
    if (!has_extension(im->path, ".obj")) return;
    im->usemtl = rad_alloc_zero(im->ctx, 1, sizeof *im->usemtl);
    if (!im->usemtl) return;
    im->usemtl->path = im->path;
    im->usemtl->known = rad_alloc(im->ctx, MTL_NAMES, sizeof *im->usemtl->known);
    if (!im->usemtl->known) return;
    im->usemtl_running = rad_thread_count(im->ctx) > 1 &&
                         pthread_create(&im->usemtl_thread, NULL, usemtl_scan_run, im->usemtl) == 0;
}

/* Waits for the scan (importer_free calls it too, on every way out). */
static void usemtl_scan_finish(importer *im) {
    if (im->usemtl_running) pthread_join(im->usemtl_thread, NULL);
    im->usemtl_running = 0;
}

static void note_unknown_usemtl(importer *im) {
    usemtl_scan *scan = im->usemtl;
    if (!scan || !scan->known) return;
    if (im->usemtl_running) usemtl_scan_finish(im);
    else usemtl_scan_run(scan);
    for (size_t k = 0; k < scan->notes; ++k)
        rad_info(im->ctx, "%s:%u: usemtl '%s' names a material the MTL files lack; assimp gives "
                 "its faces a material of its own defaults", im->path, scan->note_line[k],
                 scan->note_name[k]);
}

/* assimp's point, spot and directional lights become the scene's lights (docs/lights.md): the
 * node of the light's name places them. glTF (KHR_lights_punctual) gives photometric strength,
 * colour times intensity in candela (lux for directional lights), which assimp folds into the
 * colour: it is turned into W/sr (W/m^2) at 179 lm/W. Other formats give a colour with no unit;
 * it is taken as radiant intensity in W/sr (irradiance in W/m^2 for directional lights). Spot
 * cones are half angles (assimp copies glTF's innerConeAngle and outerConeAngle). */
static rad_status read_lights(importer *im) {
    size_t ignored = 0;
    for (unsigned i = 0; i < im->ai->mNumLights; ++i) {
        const struct aiLight *source = im->ai->mLights[i];
        rad_light_desc d;
        memset(&d, 0, sizeof d);
        d.name = source->mName.data;
        if (source->mType == aiLightSource_POINT) d.type = RAD_LIGHT_TYPE_POINT;
        else if (source->mType == aiLightSource_SPOT) d.type = RAD_LIGHT_TYPE_SPOT;
        else if (source->mType == aiLightSource_DIRECTIONAL) d.type = RAD_LIGHT_TYPE_DIRECTIONAL;
        else {
            ++ignored;
            continue;
        }
        transform world = identity;
        find_node(im->ai->mRootNode, source->mName.data, &identity, &world, 0);
        rad_vec3 position = transform_point(&world, v3(source->mPosition.x, source->mPosition.y,
                                                       source->mPosition.z));
        rad_vec3 direction = transform_direction(&world, v3(source->mDirection.x,
                                                            source->mDirection.y,
                                                            source->mDirection.z));
        d.position[0] = position.x, d.position[1] = position.y, d.position[2] = position.z;
        d.direction[0] = direction.x, d.direction[1] = direction.y, d.direction[2] = direction.z;
        double color[3] = {source->mColorDiffuse.r, source->mColorDiffuse.g, source->mColorDiffuse.b};
        double peak = fmax(color[0], fmax(color[1], color[2]));
        if (!(peak > 0) || !isfinite(peak)) {
            rad_warn(im->ctx, "%s: light '%s' has colour (%g, %g, %g); ignored", im->path,
                     d.name, color[0], color[1], color[2]);
            continue;
        }
        for (int c = 0; c < 3; ++c) d.color[c] = color[c] / peak;
        d.strength = peak;
        d.units = im->is_gltf ? RAD_LIGHT_CANDELA : RAD_LIGHT_WATTS;
        d.inner_degrees = source->mAngleInnerCone * 180 / RAD_PI;
        d.outer_degrees = source->mAngleOuterCone * 180 / RAD_PI;
        if (d.type == RAD_LIGHT_TYPE_SPOT) {
            d.outer_degrees = fmin(fmax(d.outer_degrees, 1e-3), 90);
            d.inner_degrees = fmin(fmax(d.inner_degrees, 0), d.outer_degrees);
        }
        rad_status status = rad_scene_add_light(im->scene, &d);
        if (status == RAD_ERROR_NO_MEMORY) return status;
        if (status) rad_warn(im->ctx, "%s: %s; ignored", im->path, rad_context_error(im->ctx));
    }
    if (ignored)
        rad_info(im->ctx, "%s: ignored %zu ambient or area lights: only emitting surfaces, point, "
                 "spot and directional lights give light", im->path, ignored);
    if (im->scene->light_count)
        rad_info(im->ctx, "%s: %zu point, spot or directional lights (docs/lights.md)", im->path,
                 im->scene->light_count);
    return RAD_OK;
}

static void importer_free(importer *im) {
    rad_context *ctx = im->ctx;
    usemtl_scan_finish(im);
    if (im->usemtl) rad_free(ctx, im->usemtl->known);
    rad_free(ctx, im->usemtl);
    rad_free(ctx, im->material_of);
    rad_free(ctx, im->texture_lost);
    rad_free(ctx, im->names.names);
    rad_free(ctx, im->vertex_of);
    rad_free(ctx, im->points);
    rad_free(ctx, im->corners);
    rad_gltf_extras_free(ctx, &im->gltf);
    rad_file_list_free(ctx, &im->opened);
    if (im->ai) aiReleaseImport(im->ai);
}

/* assimp reads through these: stdio files, as its default IO system, and each file opened for
 * reading is recorded in the importer's list (the .mtl, .bin and other files beside the scene
 * file), which goes with the scene so that no output replaces one of them. */
static size_t recording_read(struct aiFile *file, char *buffer, size_t size, size_t count) {
    return fread(buffer, size, count, (FILE *)(void *)file->UserData);
}
static size_t recording_write(struct aiFile *file, const char *buffer, size_t size, size_t count) {
    (void)file, (void)buffer, (void)size, (void)count;
    return 0; /* importing never writes */
}
static size_t recording_tell(struct aiFile *file) {
    long at = ftell((FILE *)(void *)file->UserData);
    return at < 0 ? 0 : (size_t)at;
}
static size_t recording_size(struct aiFile *file) {
    FILE *stream = (FILE *)(void *)file->UserData;
    long at = ftell(stream), size = -1;
    if (at >= 0 && fseek(stream, 0, SEEK_END) == 0) size = ftell(stream);
    if (at >= 0) fseek(stream, at, SEEK_SET);
    return size < 0 ? 0 : (size_t)size;
}
static enum aiReturn recording_seek(struct aiFile *file, size_t offset, enum aiOrigin origin) {
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    if (offset > LONG_MAX) return aiReturn_FAILURE;
    return fseek((FILE *)(void *)file->UserData, (long)offset, whence) == 0 ? aiReturn_SUCCESS
                                                                           : aiReturn_FAILURE;
}
static void recording_flush(struct aiFile *file) { (void)file; }

static struct aiFile *recording_open(struct aiFileIO *io, const char *path, const char *mode) {
    importer *im = (importer *)(void *)io->UserData;
    if (!path || !mode || strchr(mode, 'w') || strchr(mode, 'a') || strchr(mode, '+'))
        return NULL; /* importing never writes */
    FILE *stream = fopen(path, "rb");
    if (!stream) return NULL;
    struct aiFile *file = calloc(1, sizeof *file);
    if (!file) {
        fclose(stream);
        return NULL;
    }
    file->ReadProc = recording_read;
    file->WriteProc = recording_write;
    file->TellProc = recording_tell;
    file->FileSizeProc = recording_size;
    file->SeekProc = recording_seek;
    file->FlushProc = recording_flush;
    file->UserData = (aiUserData)(void *)stream;
    if (!im->opened_status) im->opened_status = rad_file_list_add(im->ctx, &im->opened, path);
    return file;
}
static void recording_close(struct aiFileIO *io, struct aiFile *file) {
    (void)io;
    if (!file) return;
    fclose((FILE *)(void *)file->UserData);
    free(file);
}

static int has_extension(const char *path, const char *extension) {
    size_t n = strlen(path), m = strlen(extension);
    if (n < m) return 0;
    for (size_t i = 0; i < m; ++i) {
        char a = path[n - m + i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (a != extension[i]) return 0;
    }
    return 1;
}

/* An assimp log line; `user` points at a flag set when its glTF reader dropped faces. */
static void import_log_listen(const char *message, char *user) {
    if (strstr(message, "out-of-range indices")) *(int *)(void *)user = 1;
}

rad_status rad_scene_import_here(rad_context *ctx, const char *path, rad_scene **out) {
    *out = NULL;
    /* A clear message for a file that is not there, before assimp's own. */
    FILE *probe = fopen(path, "rb");
    if (!probe) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
    fclose(probe);
    rad_status status = rad_import_check(ctx, path);
    if (status) return status;

    importer im = {0};
    im.ctx = ctx;
    im.path = path;
    im.is_gltf = has_extension(path, ".gltf") || has_extension(path, ".glb");
    /* assimp's glTF reader drops faces whose indices are past the vertex array with only a log
     * line; listen for it (import_log_listen) and refuse the file instead. */
    int dropped_faces = 0;
    struct aiLogStream listener = {import_log_listen, (char *)&dropped_faces};
    aiAttachLogStream(&listener);
    struct aiFileIO io = {recording_open, recording_close, (aiUserData)(void *)&im};
    im.opened_status = rad_file_list_add(ctx, &im.opened, path);
    if (!im.opened_status) {
        usemtl_scan_start(&im);
        im.ai = aiImportFileEx(path, 0, &io);
    }
    aiDetachLogStream(&listener);
    if (im.opened_status) {
        importer_free(&im);
        return im.opened_status;
    }
    if (im.ai && dropped_faces) {
        importer_free(&im);
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: faces with vertex indices past their "
                        "POSITION accessor (assimp would drop them)", path);
    }
    if (!im.ai && im.is_gltf && rad_gltf_extras_read(ctx, path, &im.gltf) != RAD_OK) {
        importer_free(&im);
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: assimp cannot read it: its glTF JSON is cut "
                        "short or damaged", path);
    }
    if (!im.ai) {
        importer_free(&im);
        const char *why = aiGetErrorString();
        const char *dot = strrchr(path, '.');
        if (!dot || !aiIsExtensionSupported(dot))
            return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: not a scene format assimp can read "
                            "(%s)", path, why && *why ? why : "unknown format");
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: assimp cannot read it: %s", path,
                        why && *why ? why : "unknown error");
    }
    if (!im.ai->mRootNode) {
        importer_free(&im);
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: the scene has no faces", path);
    }
    if (im.is_gltf && rad_gltf_extras_read(ctx, path, &im.gltf) != RAD_OK) {
        /* assimp read it, so this is unlikely; the defaults are safe. */
        rad_warn(ctx, "%s: emissive strength and camera field of view not read (%s)", path,
                 rad_context_error(ctx));
        rad_gltf_extras_free(ctx, &im.gltf);
    } else if (im.is_gltf && im.gltf.bad_rotation_node >= 0) {
        status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: node %ld ('%s') has a rotation of length "
                          "%g; glTF wants a unit quaternion (x, y, z, w), and [0, 0, 0, 1] for "
                          "none", path, im.gltf.bad_rotation_node, im.gltf.bad_rotation_name,
                          im.gltf.bad_rotation_length);
        importer_free(&im);
        return status;
    }
    im.material_of = rad_alloc(ctx, im.ai->mNumMaterials + 1, sizeof *im.material_of);
    if (!im.material_of) status = RAD_ERROR_NO_MEMORY;
    for (unsigned i = 0; i < im.ai->mNumMaterials && !status; ++i) im.material_of[i] = UINT32_MAX;
    if (!status) status = rad_scene_new(ctx, 1, path, &im.scene);
    if (!status) status = read_node(&im, im.ai->mRootNode, &identity, 0);
    if (!status && im.scene->polygon_count == 0) {
        if (im.degenerate)
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: every face is degenerate (%zu faces "
                              "with zero area or fewer than 3 distinct corners)", path,
                              im.degenerate);
        else
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: the scene has no faces%s", path,
                              im.points_and_lines ? " (only points and lines)" : "");
    }
    if (status) {
        rad_scene_destroy(im.scene);
        importer_free(&im);
        return status;
    }
    if (im.ai->mNumCameras > 0) read_camera(&im);

    if (im.degenerate)
        rad_warn(ctx, "%s: dropped %zu degenerate faces (zero area or fewer than 3 distinct "
                 "corners)", path, im.degenerate);
    if (im.points_and_lines)
        rad_info(ctx, "%s: ignored %zu points and lines", path, im.points_and_lines);
    if (im.turned)
        rad_info(ctx, "%s: turned %zu faces under mirroring transforms so their fronts stay "
                 "counter-clockwise", path, im.turned);
    if (im.cut) rad_info(ctx, "%s: cut %zu non-convex faces into convex pieces", path, im.cut);
    if (im.tangled)
        rad_warn(ctx, "%s: %zu non-convex faces cross or touch themselves; cut into triangles "
                 "as a fan would, some of them overlapping or turned over", path, im.tangled);
    if (im.split)
        rad_info(ctx, "%s: cut %zu convex faces of more than %d corners into convex pieces", path,
                 im.split, RAD_POLYGON_CORNERS_MAX);
    if (im.joined)
        rad_info(ctx, "%s: joined %zu pairs of triangles into quads", path, im.joined);
    rad_scene_warn_bright_materials(im.ctx, im.scene, im.path, im.texture_lost,
                                    im.texture_lost_capacity);
    note_unknown_usemtl(&im);
    if (im.textured_without_uv)
        rad_warn(ctx, "%s: %zu textured surfaces have no texture coordinates; they take their "
                 "material's colour factor", path, im.textured_without_uv);
    if (im.ai->mNumLights > 0 && (status = read_lights(&im))) {
        rad_scene_destroy(im.scene);
        importer_free(&im);
        return status;
    }
    if (im.opened_status) { /* a texture's path could not be recorded */
        rad_scene_destroy(im.scene);
        importer_free(&im);
        return RAD_ERROR_NO_MEMORY;
    }
    im.scene->files = im.opened; /* the scene's list now */
    memset(&im.opened, 0, sizeof im.opened);
    *out = im.scene;
    importer_free(&im);
    return RAD_OK;
}
