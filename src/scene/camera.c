/* camera.c - pinhole cameras (see camera.h). */
#include "scene/camera.h"

rad_camera rad_camera_framing(const rad_scene *scene) {
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    if (!scene->vertex_count) lo = hi = v3(0, 0, 0);
    rad_vec3 center = v3_scale(v3_add(lo, hi), 0.5);
    double radius = 0.5 * v3_length(v3_sub(hi, lo));
    if (!(radius > 0)) radius = 1;
    double fov = 40;
    double distance = radius / sin(0.5 * fov * RAD_PI / 180) * 1.05;
    rad_camera camera = {v3_sub(center, v3(0, 0, distance)), center, v3(0, 1, 0), fov};
    return camera;
}

rad_camera rad_scene_camera(const rad_scene *scene) {
    return scene->has_camera ? scene->camera : rad_camera_framing(scene);
}

static int finite3(rad_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

rad_status rad_view_make(rad_context *ctx, const rad_camera *camera, int width, int height,
                         rad_view *out) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "image size %dx%d: each side must be 1 to 16384 pixels", width, height);
    if (!finite3(camera->eye) || !finite3(camera->look) || !finite3(camera->up) ||
        !isfinite(camera->fov_degrees))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "camera: values must be finite");
    if (!(camera->fov_degrees > 0 && camera->fov_degrees < 180))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera: field of view must be between 0 and 180 degrees, not %g",
                        camera->fov_degrees);
    rad_vec3 forward = v3_sub(camera->look, camera->eye);
    if (!(v3_length(forward) > 0))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "camera: eye and look are the same point");
    forward = v3_normalize(forward);
    rad_vec3 right = v3_cross(forward, camera->up);
    if (!(v3_length(right) > 1e-9 * v3_length(camera->up)) || !(v3_length(camera->up) > 0))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera: up must not be zero or parallel to the view direction");
    right = v3_normalize(right);
    out->eye = camera->eye;
    out->forward = forward;
    out->right = right;
    out->up = v3_cross(right, forward);
    out->tan_half_fov = tan(0.5 * camera->fov_degrees * RAD_PI / 180);
    out->width = width;
    out->height = height;
    return RAD_OK;
}

/* ---- the public camera description ---------------------------------------------------- */

void rad_scene_get_camera(const rad_scene *scene, rad_camera_desc *out) {
    rad_camera camera = rad_scene_camera(scene);
    rad_camera_to_desc(&camera, out);
}

void rad_camera_to_desc(const rad_camera *camera, rad_camera_desc *out) {
    const rad_vec3 v[3] = {camera->eye, camera->look, camera->up};
    double *d[3] = {out->eye, out->look, out->up};
    for (int k = 0; k < 3; ++k) {
        d[k][0] = v[k].x;
        d[k][1] = v[k].y;
        d[k][2] = v[k].z;
    }
    out->fov_degrees = camera->fov_degrees;
}

rad_camera rad_camera_from_desc(const rad_camera_desc *desc) {
    rad_camera camera = {
        v3(desc->eye[0], desc->eye[1], desc->eye[2]),
        v3(desc->look[0], desc->look[1], desc->look[2]),
        v3(desc->up[0], desc->up[1], desc->up[2]),
        desc->fov_degrees,
    };
    return camera;
}
