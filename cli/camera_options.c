/* camera_options.c - the camera flags shared by render and pathtrace (see camera_options.h). */
#include "camera_options.h"

#include <math.h>
#include <string.h>

void cli_camera_args_init(cli_camera_args *args) {
    args->eye[0] = args->look[0] = args->up[0] = args->fov = NAN;
}

int cli_camera_check(const char *command, const cli_camera_args *args) {
    if (!isnan(args->fov) && !(args->fov > 0 && args->fov < 180))
        return cli_error(EXIT_USAGE, "%s: the field of view (--fov) must be between 0 and 180 "
                                     "degrees, not %g", command, args->fov);
    return 0;
}

void cli_camera_get(const cli_camera_args *args, const rad_scene *scene, rad_camera_desc *camera) {
    rad_scene_get_camera(scene, camera);
    if (!isnan(args->eye[0])) memcpy(camera->eye, args->eye, sizeof args->eye);
    if (!isnan(args->look[0])) memcpy(camera->look, args->look, sizeof args->look);
    if (!isnan(args->up[0])) memcpy(camera->up, args->up, sizeof args->up);
    if (!isnan(args->fov)) camera->fov_degrees = args->fov;
}
