/* light_directions.c - a point or spot light's directions tabulated by its intensity
 * (light_directions.h). */
#include "scene/light_directions.h"

#include <math.h>
#include <string.h>

#define THETAS 180     /* steps of the angle to the axis (1 degree over the sphere) */
#define PHIS 72        /* steps of the azimuth when the light is not the same all round */

int rad_light_directions_needed(const rad_light *light) {
    return light->kind == RAD_LIGHT_SPOT || (light->kind == RAD_LIGHT_POINT && light->ies);
}

static int same_profile(const rad_ies_profile *a, const rad_ies_profile *b) {
    if (a == b) return 1;
    if (!a || !b || a->vertical_count != b->vertical_count ||
        a->horizontal_count != b->horizontal_count)
        return 0;
    size_t v = a->vertical_count, h = a->horizontal_count;
    return memcmp(a->vertical, b->vertical, v * sizeof *a->vertical) == 0 &&
           memcmp(a->horizontal, b->horizontal, h * sizeof *a->horizontal) == 0 &&
           memcmp(a->candela, b->candela, v * h * sizeof *a->candela) == 0;
}

int rad_light_directions_fit(const rad_light_directions *table, const rad_light *light) {
    const rad_light *of = table->of;
    if (of->kind != light->kind || !same_profile(of->ies, light->ies)) return 0;
    return light->kind != RAD_LIGHT_SPOT ||
           (of->inner_angle == light->inner_angle && of->outer_angle == light->outer_angle);
}

double rad_light_shape(const rad_light *light, rad_vec3 w) {
    rad_light white = *light;
    white.intensity[0] = white.intensity[1] = white.intensity[2] = 1;
    double intensity[3];
    rad_light_intensity(&white, w, intensity);
    return intensity[0];
}

/* The unit direction at angle theta from the axis and azimuth phi (from the basis' first vector,
 * as rad_light_intensity measures an IES profile's horizontal angle). */
static rad_vec3 direction_at(const rad_light *light, double cos_theta, double phi) {
    rad_vec3 t, b;
    v3_basis(light->direction, &t, &b);
    double s = sqrt(fmax(0, 1 - cos_theta * cos_theta));
    return v3_add(v3_scale(light->direction, cos_theta),
                  v3_add(v3_scale(t, s * cos(phi)), v3_scale(b, s * sin(phi))));
}

rad_status rad_light_directions_build(rad_context *ctx, const rad_light *light,
                                      rad_light_directions *out) {
    memset(out, 0, sizeof *out);
    out->of = light;
    out->thetas = THETAS;
    out->phis = light->ies && light->ies->horizontal_count > 1 ? PHIS : 1;
    out->theta_max = RAD_PI;
    if (light->kind == RAD_LIGHT_SPOT && light->outer_angle < RAD_PI)
        out->theta_max = fmax(0, light->outer_angle);
    int thetas = out->thetas, phis = out->phis;
    size_t cells = (size_t)thetas * (size_t)phis;
    out->cdf = rad_alloc(ctx, cells, sizeof *out->cdf);
    double *corner = rad_alloc(ctx, (size_t)(thetas + 1) * (size_t)phis, sizeof *corner);
    if (!out->cdf || !corner) {
        rad_free(ctx, corner);
        rad_light_directions_free(ctx, out);
        return RAD_ERROR_NO_MEMORY;
    }
    double step = out->theta_max / thetas, phi_step = 2 * RAD_PI / phis;
    /* The shape at the cells' corners (the azimuth wraps round)... */
    for (int i = 0; i <= thetas; ++i)
        for (int j = 0; j < phis; ++j)
            corner[(size_t)i * (size_t)phis + (size_t)j] =
                fmax(0, rad_light_shape(light, direction_at(light, cos(i * step), j * phi_step)));
    /* ... and each cell's weight: its solid angle times the mean of its corners and middle. */
    double total = 0;
    for (int i = 0; i < thetas; ++i) {
        double solid_angle = (cos(i * step) - cos((i + 1) * step)) * phi_step;
        for (int j = 0; j < phis; ++j) {
            int k = (j + 1) % phis;
            const double *row = corner + (size_t)i * (size_t)phis, *next = row + phis;
            double middle = fmax(0, rad_light_shape(light, direction_at(light, cos((i + 0.5) * step),
                                                                        (j + 0.5) * phi_step)));
            double shape = (row[j] + row[k] + next[j] + next[k]) / 8 + middle / 2;
            total += shape * solid_angle;
            out->cdf[(size_t)i * (size_t)phis + (size_t)j] = total;
        }
    }
    rad_free(ctx, corner);
    out->shape_power = total;
    if (total > 0)
        for (size_t c = 0; c < cells; ++c) out->cdf[c] /= total;
    return RAD_OK;
}

void rad_light_directions_free(rad_context *ctx, rad_light_directions *table) {
    if (!table) return;
    rad_free(ctx, table->cdf);
    memset(table, 0, sizeof *table);
}

rad_vec3 rad_light_directions_sample(const rad_light_directions *table, const rad_light *light,
                                     double u0, double u1, double *pdf) {
    *pdf = 0;
    if (!(table->shape_power > 0)) return light->direction;
    /* The first cell whose cdf is above u0 (binary search), then u0 rescaled inside it. */
    size_t cells = (size_t)table->thetas * (size_t)table->phis, lo = 0, hi = cells - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (u0 < table->cdf[mid]) hi = mid;
        else lo = mid + 1;
    }
    double below = lo ? table->cdf[lo - 1] : 0, p = table->cdf[lo] - below;
    if (!(p > 0)) return light->direction;
    double v = fmin(fmax((u0 - below) / p, 0), 1);
    int i = (int)(lo / (size_t)table->phis), j = (int)(lo % (size_t)table->phis);
    double step = table->theta_max / table->thetas, phi_step = 2 * RAD_PI / table->phis;
    double c0 = cos(i * step), c1 = cos((i + 1) * step);
    double solid_angle = (c0 - c1) * phi_step;
    if (!(solid_angle > 0)) return light->direction;
    *pdf = p / solid_angle;
    return direction_at(light, c0 + v * (c1 - c0), (j + u1) * phi_step);
}
