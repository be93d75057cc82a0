/* TEMPORARY until the geometry issue lands in this session. */
#include "solve/system.h"
#include "scene/scene.h"
void rad_mesh_destroy(struct rad_mesh *mesh) { (void)mesh; }
rad_status rad_system_from_geometry(rad_context *ctx, const struct rad_scene *scene,
                                    const rad_mesh_options *mesh, const rad_ff_options *ff,
                                    rad_system **out) {
    (void)scene; (void)mesh; (void)ff; *out = NULL;
    return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "geometry not yet");
}
rad_status rad_builtin_geometry(rad_context *ctx, const char *name, rad_scene **out) {
    *out = NULL; return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: geometry not yet", name);
}
rad_status rad_scene_import(rad_context *ctx, const char *path, rad_scene **out) {
    *out = NULL; return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: import not yet", path);
}
