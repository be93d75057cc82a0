/* mgf.h - the MGF (Materials and Geometry Format 2.0) reader, src/scene/mgf.c. */
#ifndef RAD_SCENE_MGF_H
#define RAD_SCENE_MGF_H

#include "scene/scene.h"

/* Reads an .mgf file (and the files it includes) into a geometric scene. A malformed file:
 * RAD_ERROR_PARSE with "FILE:LINE: what is wrong". */
rad_status rad_scene_load_mgf(rad_context *ctx, const char *path, rad_scene **out);

#endif
