/* tonemap.c - exposure, tone curves and sRGB encoding (see tonemap.h). */
#include "image/tonemap.h"

#include <math.h>
#include <string.h>

int rad_tonemap_parse(const char *name) {
    if (!name) return -1;
    if (strcmp(name, "clamp") == 0) return RAD_TONEMAP_CLAMP;
    if (strcmp(name, "none") == 0) return RAD_TONEMAP_NONE;
    if (strcmp(name, "reinhard") == 0) return RAD_TONEMAP_REINHARD;
    if (strcmp(name, "aces") == 0) return RAD_TONEMAP_ACES;
    return -1;
}

static float clamp01(float x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

void rad_tonemap_apply(rad_tonemap curve, double exposure, const float in[3], float out[3]) {
    float scale = (float)exp2(exposure);
    float c[3] = {in[0] * scale, in[1] * scale, in[2] * scale};
    switch (curve) {
    case RAD_TONEMAP_REINHARD: {
        float luminance = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
        float factor = luminance > 0 ? 1.0f / (1.0f + luminance) : 1.0f;
        for (int k = 0; k < 3; ++k) c[k] *= factor;
        break;
    }
    case RAD_TONEMAP_ACES:
        for (int k = 0; k < 3; ++k) {
            float x = c[k] * 0.6f; /* the fit's exposure, so mid grey stays near mid grey */
            c[k] = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
        }
        break;
    case RAD_TONEMAP_CLAMP:
    case RAD_TONEMAP_NONE: break;
    }
    for (int k = 0; k < 3; ++k) out[k] = clamp01(isfinite(c[k]) ? c[k] : 0);
}

uint8_t rad_srgb_encode(float linear) {
    float x = clamp01(linear);
    float s = x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(clamp01(s) * 255.0f);
}
