/* screen_share.h - the share of a camera's image each element covers (screen_share.c). */
#ifndef RAD_SOLVE_SCREEN_SHARE_H
#define RAD_SOLVE_SCREEN_SHARE_H

#include "scene/scene.h"
#include "system/system.h"

/* Pixels per side when the caller gives no size. */
#define RAD_SCREEN_SHARE_SIZE 256

#endif
