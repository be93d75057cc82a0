/* compare.h - image metrics and error maps (docs/images.md). The public functions are
 * rad_image_compare and rad_image_error_map (include/radiosity.h); this header adds the colour
 * scale for tests and other false-colour pictures. */
#ifndef RAD_RENDER_COMPARE_H
#define RAD_RENDER_COMPARE_H

#include "image/image.h"

/* The false-colour scale: 0 black, through blue, magenta and orange, to pale yellow at 1; linear
 * RGB (sRGB-encoded by the PNG writer back to the scale's colours). */
void rad_heat_colour(double value, float out[3]);

#endif
