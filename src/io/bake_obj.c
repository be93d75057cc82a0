/* bake_obj.c - the baked mesh as Wavefront OBJ through assimp's exporter ("objnomtl").
 *
 * OBJ has no standard vertex colour; the common extension, read by MeshLab, assimp, newer
 * Blender and others, puts three more numbers on the position line: `v x y z r g b`. assimp 5.2.5
 * writes exactly that when the mesh has colours, one `g NAME` group per mesh, the normals as
 * `vn`, and the elements as faces (quads stay quads); an `o NAME` is added before each group.
 * The colours are display values in [0, 1]: the 8-bit sRGB bytes of the PLY divided by 255
 * (after exposure and tone curve), since viewers show them as they are. The linear radiance is
 * not in an OBJ; use glTF or PLY for it.
 *
 * assimp exports to a memory blob, which goes to the file through rad_atomic_file, so a failed
 * export leaves nothing behind. OBJ names end at whitespace: a surface name's spaces become '_'. */
#include "io/bake.h"

#include "core/atomic_file.h"

#include <assimp/cexport.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <stdio.h>
#include <string.h>

static void set_name(struct aiString *out, const char *name) {
    size_t length = strlen(name);
    if (length > MAXLEN - 1) length = MAXLEN - 1;
    for (size_t k = 0; k < length; ++k) {
        unsigned char c = (unsigned char)name[k];
        out->data[k] = c <= ' ' || c == 0x7f ? '_' : (char)c;
    }
    out->data[length] = '\0';
    out->length = (ai_uint32)length;
}

typedef struct obj_scene {
    rad_context *ctx;
    struct aiScene scene;
    struct aiNode root;
    struct aiNode *nodes;
    struct aiNode **children;
    unsigned int *mesh_indices;
    struct aiMesh *meshes;
    struct aiMesh **mesh_pointers;
    struct aiVector3D *positions, *normals;
    struct aiColor4D *colours;
    struct aiFace *faces;
    unsigned int *indices;
    /* One material, named: assimp's OBJ writer asks every mesh for its material's name. */
    struct aiMaterial material;
    struct aiMaterial *material_pointer;
    struct aiMaterialProperty name_property;
    struct aiMaterialProperty *property_pointer;
    char name_data[4 + 16];
} obj_scene;

static void obj_scene_free(obj_scene *o) {
    rad_context *ctx = o->ctx;
    rad_free(ctx, o->nodes);
    rad_free(ctx, o->children);
    rad_free(ctx, o->mesh_indices);
    rad_free(ctx, o->meshes);
    rad_free(ctx, o->mesh_pointers);
    rad_free(ctx, o->positions);
    rad_free(ctx, o->normals);
    rad_free(ctx, o->colours);
    rad_free(ctx, o->faces);
    rad_free(ctx, o->indices);
}

static const struct aiMatrix4x4 identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

/* An aiScene that points into arrays we own; assimp copies it before exporting. */
static rad_status obj_scene_build(const rad_baked_mesh *b, obj_scene *o) {
    rad_context *ctx = b->ctx;
    size_t n = b->surface_count, nv = b->vertex_count, nf = b->face_count, corners = 0;
    for (size_t f = 0; f < nf; ++f) corners += (size_t)rad_baked_corner_count(b, f);
    if (nv > UINT32_MAX || nf > UINT32_MAX || n > UINT32_MAX)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "bake: mesh too large for assimp");
    o->nodes = rad_alloc_zero(ctx, n, sizeof *o->nodes);
    o->children = rad_alloc(ctx, n, sizeof *o->children);
    o->mesh_indices = rad_alloc(ctx, n, sizeof *o->mesh_indices);
    o->meshes = rad_alloc_zero(ctx, n, sizeof *o->meshes);
    o->mesh_pointers = rad_alloc(ctx, n, sizeof *o->mesh_pointers);
    o->positions = rad_alloc(ctx, nv, sizeof *o->positions);
    o->normals = rad_alloc(ctx, nv, sizeof *o->normals);
    o->colours = rad_alloc(ctx, nv, sizeof *o->colours);
    o->faces = rad_alloc(ctx, nf, sizeof *o->faces);
    o->indices = rad_alloc(ctx, corners, sizeof *o->indices);
    if (!o->nodes || !o->children || !o->mesh_indices || !o->meshes || !o->mesh_pointers ||
        !o->positions || !o->normals || !o->colours || !o->faces || !o->indices)
        return RAD_ERROR_NO_MEMORY;

    for (size_t v = 0; v < nv; ++v) {
        const float *p = b->position[v];
        o->positions[v] = (struct aiVector3D){p[0], p[1], p[2]};
        o->normals[v] = (struct aiVector3D){b->normal[v][0], b->normal[v][1], b->normal[v][2]};
        o->colours[v] = (struct aiColor4D){b->display[v][0] / 255.0f, b->display[v][1] / 255.0f,
                                           b->display[v][2] / 255.0f, 1.0f};
    }
    unsigned int *index = o->indices;
    for (size_t f = 0; f < nf; ++f) {
        unsigned int count = (unsigned int)rad_baked_corner_count(b, f);
        o->faces[f].mNumIndices = count;
        o->faces[f].mIndices = index;
        for (unsigned int k = 0; k < count; ++k) *index++ = b->face[f][k];
    }
    for (size_t i = 0; i < n; ++i) {
        const rad_baked_surface *s = &b->surfaces[i];
        struct aiMesh *mesh = &o->meshes[i];
        mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON;
        mesh->mNumVertices = (unsigned int)s->vertex_count;
        mesh->mVertices = o->positions + s->first_vertex;
        mesh->mNormals = o->normals + s->first_vertex;
        mesh->mColors[0] = o->colours + s->first_vertex;
        mesh->mNumFaces = (unsigned int)s->face_count;
        mesh->mFaces = o->faces + s->first_face;
        mesh->mMaterialIndex = 0;
        set_name(&mesh->mName, s->name);
        o->mesh_pointers[i] = mesh;
        o->mesh_indices[i] = (unsigned int)i;
        struct aiNode *node = &o->nodes[i];
        node->mName = mesh->mName;
        node->mTransformation = identity;
        node->mParent = &o->root;
        node->mNumMeshes = 1;
        node->mMeshes = &o->mesh_indices[i];
        o->children[i] = node;
    }
    set_name(&o->root.mName, "baked");
    o->root.mTransformation = identity;
    o->root.mNumChildren = (unsigned int)n;
    o->root.mChildren = o->children;

    /* The material name as assimp stores an aiString property: length, bytes, NUL. */
    static const char material_name[] = "baked";
    uint32_t length = sizeof material_name - 1;
    memcpy(o->name_data, &length, 4);
    memcpy(o->name_data + 4, material_name, sizeof material_name);
    set_name(&o->name_property.mKey, "?mat.name");
    o->name_property.mType = aiPTI_String;
    o->name_property.mDataLength = 4 + sizeof material_name;
    o->name_property.mData = o->name_data;
    o->property_pointer = &o->name_property;
    o->material.mProperties = &o->property_pointer;
    o->material.mNumProperties = o->material.mNumAllocated = 1;
    o->material_pointer = &o->material;

    o->scene.mRootNode = &o->root;
    o->scene.mNumMeshes = (unsigned int)n;
    o->scene.mMeshes = o->mesh_pointers;
    o->scene.mNumMaterials = 1;
    o->scene.mMaterials = &o->material_pointer;
    return RAD_OK;
}

/* assimp's text, with `o NAME` before each `g NAME`: importers that split by object (Blender's
 * default) then make one object per surface too. */
static void write_with_objects(FILE *file, const void *data, size_t size) {
    const char *text = data, *end = text + size;
    while (text < end) {
        const char *newline = memchr(text, '\n', (size_t)(end - text));
        const char *next = newline ? newline + 1 : end;
        if (next - text > 2 && text[0] == 'g' && text[1] == ' ') {
            fputc('o', file);
            fwrite(text + 1, 1, (size_t)(next - text - 1), file);
        }
        fwrite(text, 1, (size_t)(next - text), file);
        text = next;
    }
}

rad_status rad_bake_write_obj(const rad_baked_mesh *b, const char *path) {
    rad_context *ctx = b->ctx;
    obj_scene o;
    memset(&o, 0, sizeof o);
    o.ctx = ctx;
    rad_status status = obj_scene_build(b, &o);
    if (status) {
        obj_scene_free(&o);
        return status;
    }
    const struct aiExportDataBlob *blob = aiExportSceneToBlob(&o.scene, "objnomtl", 0);
    obj_scene_free(&o);
    if (!blob)
        return rad_fail(ctx, RAD_ERROR_INTERNAL, "%s: assimp's OBJ exporter failed: %s", path,
                        aiGetErrorString());
    rad_atomic_file file;
    status = rad_atomic_open(ctx, path, &file);
    if (!status) {
        write_with_objects(file.file, blob->data, blob->size);
        status = rad_atomic_commit(&file);
    }
    aiReleaseExportBlob(blob);
    return status;
}
