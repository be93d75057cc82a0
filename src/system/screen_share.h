/* screen_share.h - the share of a camera's image each element covers (screen_share.c), and the
 * conversions between the public camera description and the internal camera. */
#ifndef RAD_SOLVE_SCREEN_SHARE_H
#define RAD_SOLVE_SCREEN_SHARE_H

#include "scene/scene.h"
#include "system/system.h"

/* Pixels per side when the caller gives no size. */
#define RAD_SCREEN_SHARE_SIZE 256

void rad_camera_to_desc(const rad_camera *camera, rad_camera_desc *out);
rad_camera rad_camera_from_desc(const rad_camera_desc *desc);

#endif
