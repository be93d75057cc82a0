/* import.c - PLACEHOLDER until the assimp importer lands (geometry issue). */
#include "scene/scene.h"
rad_status rad_scene_import(rad_context *ctx, const char *path, rad_scene **out) {
    *out = NULL;
    return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: import is not written yet", path);
}
