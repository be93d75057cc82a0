/* camera.h - pinhole cameras: the scene's own (or one that frames the scene), overridden by
 * --eye/--look/--up/--fov; primary ray directions for pixel positions. Vertical field of view,
 * square pixels; pixel (0, 0) is the top-left corner of the image; +x on screen is
 * forward x up (so the Cornell box shows its red wall on the left). */
#ifndef RAD_RENDER_CAMERA_H
#define RAD_RENDER_CAMERA_H

#include "scene/scene.h"

typedef struct rad_view {
    rad_vec3 eye;
    rad_vec3 forward, right, up; /* orthonormal */
    double tan_half_fov;         /* vertical */
    int width, height;
} rad_view;

/* A camera that frames the whole scene from the -z side looking along +z, for scenes without
 * one. */
rad_camera rad_camera_framing(const rad_scene *scene);

/* The scene's camera or, when it has none, the automatic one (rad_scene_auto_camera), or one
 * that frames it. */
rad_camera rad_scene_camera(const rad_scene *scene);

/* For a geometric scene without a camera: the framing camera when it sees front faces (an
 * object seen from outside); otherwise (a closed room, whose outside is the backs of its
 * walls) a camera inside the largest open space, looking level along its longest free view
 * (docs/rendering.md, "The automatic camera"). Sets scene->camera and camera_automatic, and
 * says which in a note. Does nothing when the rays cannot be built. */
void rad_scene_auto_camera(rad_scene *scene);

/* Checks the camera (finite, eye != look, up not parallel to the view, 0 < fov < 180) and the
 * size (1 .. 16384 per side) and builds the view. */
rad_status rad_view_make(rad_context *ctx, const rad_camera *camera, int width, int height,
                         rad_view *out);

/* The one camera rule of every command that makes an image (render, pathtrace, photonmap):
 * rays through a grid of pixel centres (at most 64 x 64), then through every pixel while none
 * has met a front, must meet something (the sky counts: `see` reports it as a front). `see`
 * casts one ray and tells whether it hit, and if so whether it counts as a front and which
 * surface it met. Error: "camera sees nothing ..." when no ray hits. When every hit is a back,
 * a warning ("the camera sees only the backs of surfaces (such as 'S'), which are one-sided and
 * drawn black ...") and RAD_OK: the image is drawn, black where the backs are. */
typedef int (*rad_view_see)(const void *user, rad_vec3 eye, rad_vec3 direction, int *front,
                            const char **surface);
rad_status rad_view_check(rad_context *ctx, const rad_view *view, rad_view_see see,
                          const void *user);

/* The public camera description and the internal camera, both ways (the one conversion). */
void rad_camera_to_desc(const rad_camera *camera, rad_camera_desc *out);
rad_camera rad_camera_from_desc(const rad_camera_desc *desc);

/* Unit direction through the image point (px, py) in pixels: (0, 0) top-left corner,
 * (width, height) bottom-right. */
static inline rad_vec3 rad_view_direction(const rad_view *view, double px, double py) {
    double aspect = (double)view->width / view->height;
    double sx = (2 * px / view->width - 1) * view->tan_half_fov * aspect;
    double sy = (1 - 2 * py / view->height) * view->tan_half_fov;
    return v3_normalize(v3_add(view->forward, v3_add(v3_scale(view->right, sx), v3_scale(view->up, sy))));
}

#endif
