/* gltf_extras.h - what assimp 5.2.5 does not pass on from a glTF 2.0 file, read from its JSON:
 * each material's KHR_materials_emissive_strength and each camera's vertical field of view
 * (assimp stores yfov * aspectRatio as the horizontal angle, which cannot be undone when the
 * aspect ratio is missing); and whether every node's rotation is a unit quaternion. Used by the importer only (src/scene/import.c). */
#ifndef RAD_SCENE_GLTF_EXTRAS_H
#define RAD_SCENE_GLTF_EXTRAS_H

#include "core/context.h"

typedef struct rad_gltf_extras {
    size_t material_count;    /* materials in the file's "materials" array */
    double *emissive_strength; /* per material; 1 when the extension is absent */
    size_t camera_count;
    double *camera_yfov; /* per camera, radians; 0 for orthographic cameras */
    /* The first node whose "rotation" is not a unit quaternion (assimp turns it into a matrix
     * that is no rotation: [0,0,0,0] gives the identity); -1 when every node's is one. */
    long bad_rotation_node;
    double bad_rotation_length; /* that quaternion's length */
    char bad_rotation_name[64]; /* that node's name, as written (escapes kept), or "" */
} rad_gltf_extras;

/* How far a node's rotation quaternion may be from length 1 (the glTF validator's tolerance is
 * tighter; exporters that write 7 digits stay well within this). */
#define RAD_GLTF_UNIT_TOLERANCE 1e-3

/* Reads `path` (.gltf text or .glb binary). A file whose JSON cannot be walked gives
 * RAD_ERROR_PARSE; the caller decides whether that matters. */
rad_status rad_gltf_extras_read(rad_context *ctx, const char *path, rad_gltf_extras *out);
void rad_gltf_extras_free(rad_context *ctx, rad_gltf_extras *extras);

#endif
