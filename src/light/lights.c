/* lights.c - point, spot and directional lights and the sky: what each sends towards a point
 * (lights.h, docs/lights.md). */
#include "light/lights.h"

#include <math.h>
#include <string.h>

/* Spot falloff between the outer and inner cone: smoothstep in cos(theta), as pbrt-v4's
 * SpotLight (Pharr, Jakob & Humphreys 2023, sec. 12.2.1); a hard edge when the cones agree. */
static double spot_falloff(const rad_light *light, double cos_theta) {
    double cos_outer = cos(light->outer_angle), cos_inner = cos(light->inner_angle);
    if (cos_theta < cos_outer) return 0;
    if (cos_theta >= cos_inner || cos_inner <= cos_outer) return 1;
    double t = (cos_theta - cos_outer) / (cos_inner - cos_outer);
    return t * t * (3 - 2 * t);
}

void rad_light_intensity(const rad_light *light, rad_vec3 w, double out[3]) {
    double scale = 1;
    double cos_axis = v3_dot(w, light->direction);
    if (light->kind == RAD_LIGHT_SPOT) scale = spot_falloff(light, cos_axis);
    if (light->ies && scale > 0) {
        /* Vertical 0 is down the axis; horizontal around it from the basis' first vector. */
        rad_vec3 t, b;
        v3_basis(light->direction, &t, &b);
        double vertical = acos(fmax(-1.0, fmin(1.0, cos_axis))) * 180 / RAD_PI;
        double horizontal = atan2(v3_dot(w, b), v3_dot(w, t)) * 180 / RAD_PI;
        if (horizontal < 0) horizontal += 360;
        double peak = fmax(light->intensity[0], fmax(light->intensity[1], light->intensity[2]));
        double candela = rad_ies_candela(light->ies, vertical, horizontal);
        for (int c = 0; c < 3; ++c)
            out[c] = peak > 0 ? scale * light->intensity[c] / peak * candela / RAD_LUMINOUS_EFFICACY
                              : 0;
        return;
    }
    for (int c = 0; c < 3; ++c) out[c] = scale * light->intensity[c];
}

int rad_light_arrive(const rad_light *light, rad_vec3 x, rad_light_arrival *out) {
    if (light->kind == RAD_LIGHT_DIRECTIONAL) {
        out->direction = v3_scale(light->direction, -1);
        out->distance = INFINITY;
        for (int c = 0; c < 3; ++c) out->irradiance[c] = light->intensity[c];
    } else {
        rad_vec3 to_light = v3_sub(light->position, x);
        double r2 = v3_dot(to_light, to_light);
        if (!(r2 > 0)) return 0;
        out->distance = sqrt(r2);
        out->direction = v3_scale(to_light, 1 / out->distance);
        double intensity[3];
        rad_light_intensity(light, v3_scale(out->direction, -1), intensity);
        for (int c = 0; c < 3; ++c) out->irradiance[c] = intensity[c] / r2;
    }
    return out->irradiance[0] > 0 || out->irradiance[1] > 0 || out->irradiance[2] > 0;
}

void rad_sky_radiance(const rad_sky *sky, rad_vec3 w, double out[3]) {
    double cos_zenith = v3_dot(w, sky->up);
    double scale = 0;
    if (sky->kind != RAD_SKY_OFF && cos_zenith > 0)
        scale = sky->kind == RAD_SKY_CIE_OVERCAST ? (1 + 2 * cos_zenith) / 3 : 1;
    for (int c = 0; c < 3; ++c) out[c] = scale * sky->radiance[c];
}

void rad_lights_free(rad_context *ctx, rad_light *lights, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        rad_free(ctx, lights[i].name);
        rad_ies_free(ctx, lights[i].ies);
    }
    rad_free(ctx, lights);
}

static rad_ies_profile *ies_copy(rad_context *ctx, const rad_ies_profile *from) {
    rad_ies_profile *to = rad_alloc_zero(ctx, 1, sizeof *to);
    if (!to) return NULL;
    *to = *from;
    size_t nv = from->vertical_count, nh = from->horizontal_count;
    to->vertical = rad_alloc(ctx, nv, sizeof *to->vertical);
    to->horizontal = rad_alloc(ctx, nh, sizeof *to->horizontal);
    to->candela = rad_alloc(ctx, nv * nh, sizeof *to->candela);
    if (!to->vertical || !to->horizontal || !to->candela) {
        rad_ies_free(ctx, to);
        return NULL;
    }
    memcpy(to->vertical, from->vertical, nv * sizeof *to->vertical);
    memcpy(to->horizontal, from->horizontal, nh * sizeof *to->horizontal);
    memcpy(to->candela, from->candela, nv * nh * sizeof *to->candela);
    return to;
}

rad_status rad_lights_copy(rad_context *ctx, const rad_light *lights, size_t count, rad_light **out) {
    *out = NULL;
    if (!count) return RAD_OK;
    rad_light *copy = rad_alloc_zero(ctx, count, sizeof *copy);
    if (!copy) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < count; ++i) {
        copy[i] = lights[i];
        copy[i].name = rad_strdup(ctx, lights[i].name ? lights[i].name : "");
        copy[i].ies = lights[i].ies ? ies_copy(ctx, lights[i].ies) : NULL;
        if (!copy[i].name || (lights[i].ies && !copy[i].ies)) {
            rad_lights_free(ctx, copy, i + 1);
            return RAD_ERROR_NO_MEMORY;
        }
    }
    *out = copy;
    return RAD_OK;
}

double rad_triangle_solid_angle(rad_vec3 x, rad_vec3 a, rad_vec3 b, rad_vec3 c) {
    rad_vec3 ra = v3_sub(a, x), rb = v3_sub(b, x), rc = v3_sub(c, x);
    double la = v3_length(ra), lb = v3_length(rb), lc = v3_length(rc);
    double numerator = v3_dot(ra, v3_cross(rb, rc));
    double denominator = la * lb * lc + v3_dot(ra, rb) * lc + v3_dot(ra, rc) * lb +
                         v3_dot(rb, rc) * la;
    /* The sign: corners counter-clockwise seen from x give a negative triple product. */
    return -2 * atan2(numerator, denominator);
}
