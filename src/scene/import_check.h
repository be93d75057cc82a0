/* import_check.h - a look at a file before assimp reads it. assimp 5.2.5 loops forever on a PLY
 * header without end_header or one that promises far more elements than the file holds,
 * allocates (and clears) whatever a binary glTF's chunk lengths claim, gigabytes for a damaged
 * file, and writes past a heap array on an OBJ polyline ('l') of one vertex. These checks turn
 * such files into parse errors. Used by src/scene/import.c. */
#ifndef RAD_SCENE_IMPORT_CHECK_H
#define RAD_SCENE_IMPORT_CHECK_H

#include "core/context.h"

/* RAD_OK when `path`'s PLY (starting "ply") or binary glTF (starting "glTF") header is whole and
 * consistent with the file's size, and when every polyline of a file assimp may read as OBJ has
 * two vertices or more; RAD_ERROR_PARSE with a "FILE:LINE: ..." message otherwise. */
rad_status rad_import_check(rad_context *ctx, const char *path);

#endif
