/* tonemap.h - from linear radiance to display values: exposure (in stops), a tone curve, and
 * the sRGB transfer function. Linear outputs (.hdr, .pfm) are never tone mapped. */
#ifndef RAD_RENDER_TONEMAP_H
#define RAD_RENDER_TONEMAP_H

#include <stdint.h>

typedef enum rad_tonemap {
    RAD_TONEMAP_CLAMP = 0, /* clip at 1 */
    RAD_TONEMAP_NONE,      /* same as clamp for 8-bit output; named for clarity */
    RAD_TONEMAP_REINHARD,  /* x / (1 + x) on luminance, Reinhard et al. 2002 */
    RAD_TONEMAP_ACES       /* Narkowicz's fit of the ACES filmic curve */
} rad_tonemap;

/* Parses "none", "clamp", "reinhard", "aces"; -1 when unknown. */
int rad_tonemap_parse(const char *name);

/* Linear RGB -> display-referred linear RGB in [0, 1]: times 2^exposure, then the curve. */
void rad_tonemap_apply(rad_tonemap curve, double exposure, const float in[3], float out[3]);

/* Linear [0, 1] -> 8-bit sRGB. */
uint8_t rad_srgb_encode(float linear);

#endif
