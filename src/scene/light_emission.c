/* light_emission.c - where light paths start (light_emission.h). */
#include "scene/light_emission.h"

#include "scene/bsdf.h"

#include <math.h>
#include <string.h>

#define INTEGRATION_STEPS 512 /* cosine steps of the sky's power integral */

static double channel_sum(const double v[3]) { return v[0] + v[1] + v[2]; }

/* A light's intensity summed over its channels is its shape (light_directions.h) times this. */
static double colour_sum(const rad_light *light) {
    if (!light->ies) return channel_sum(light->intensity);
    double peak = fmax(light->intensity[0], fmax(light->intensity[1], light->intensity[2]));
    return peak > 0 ? channel_sum(light->intensity) / peak : 0;
}

/* The tables of the lights that need one (light_directions.h), one per kind, cone and profile:
 * lights that share them point at the same one. */
static rad_status build_directions(rad_context *ctx, rad_light_emission *out) {
    if (!out->light_count) return RAD_OK;
    out->light_directions = rad_alloc(ctx, out->light_count, sizeof *out->light_directions);
    out->directions = rad_alloc_zero(ctx, out->light_count, sizeof *out->directions);
    if (!out->light_directions || !out->directions) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < out->light_count; ++i) {
        const rad_light *light = &out->lights[i];
        out->light_directions[i] = NULL;
        if (!rad_light_directions_needed(light)) continue;
        for (size_t d = 0; d < out->direction_count && !out->light_directions[i]; ++d)
            if (rad_light_directions_fit(&out->directions[d], light))
                out->light_directions[i] = &out->directions[d];
        if (out->light_directions[i]) continue;
        rad_status status =
            rad_light_directions_build(ctx, light, &out->directions[out->direction_count]);
        if (status) return status;
        out->light_directions[i] = &out->directions[out->direction_count++];
    }
    return RAD_OK;
}

/* The integral of a point or spot light's intensity over the sphere, summed over channels:
 * 4 pi I for a bare point light, else its table's (light_directions.h). */
static double light_power(const rad_light_emission *e, size_t i) {
    const rad_light *light = &e->lights[i];
    if (light->kind == RAD_LIGHT_DIRECTIONAL) return 0; /* by the disc, in build */
    if (!e->light_directions[i]) return 4 * RAD_PI * channel_sum(light->intensity);
    return colour_sum(light) * e->light_directions[i]->shape_power;
}

/* The integral of the sky's radiance over the upper hemisphere, summed over channels (it
 * depends on the zenith cosine alone). */
static double sky_integral(const rad_sky *sky) {
    double sum = 0, step = 1.0 / INTEGRATION_STEPS;
    for (int i = 0; i < INTEGRATION_STEPS; ++i) {
        double c = (i + 0.5) * step, s = sqrt(fmax(0, 1 - c * c));
        rad_vec3 t, b;
        v3_basis(sky->up, &t, &b);
        double radiance[3];
        rad_sky_radiance(sky, v3_add(v3_scale(sky->up, c), v3_scale(t, s)), radiance);
        sum += channel_sum(radiance) * step * 2 * RAD_PI;
    }
    return sum;
}

rad_status rad_light_emission_build(rad_context *ctx, const rad_emitter_table *surfaces,
                                    const rad_scene *scene, int with_sky,
                                    rad_light_emission *out) {
    memset(out, 0, sizeof *out);
    out->surfaces = surfaces;
    if (scene) {
        out->lights = scene->lights;
        out->light_count = scene->light_count;
        if (with_sky && scene->sky.kind != RAD_SKY_OFF) out->sky = &scene->sky;
        /* The bounding sphere of the scene's vertices. */
        rad_vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
        for (size_t i = 0; i < scene->vertex_count; ++i) {
            rad_vec3 v = scene->vertices[i];
            lo = v3(fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z));
            hi = v3(fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z));
        }
        if (scene->vertex_count) {
            out->center = v3_scale(v3_add(lo, hi), 0.5);
            out->radius = 0.5 * v3_length(v3_sub(hi, lo));
        }
        if (!(out->radius > 0) || !isfinite(out->radius)) out->radius = 1;
    }
    out->source_count = 1 + out->light_count + 1;
    out->power = rad_alloc_zero(ctx, out->source_count, sizeof *out->power);
    out->cdf = rad_alloc_zero(ctx, out->source_count, sizeof *out->cdf);
    rad_status status = out->power && out->cdf ? build_directions(ctx, out) : RAD_ERROR_NO_MEMORY;
    if (status) {
        rad_light_emission_free(ctx, out);
        return status;
    }
    for (size_t k = 0; k < surfaces->count; ++k)
        out->power[0] += RAD_PI * surfaces->emitters[k].area * channel_sum(surfaces->emitters[k].radiance);
    double disc = RAD_PI * out->radius * out->radius;
    for (size_t i = 0; i < out->light_count; ++i) {
        const rad_light *light = &out->lights[i];
        out->power[1 + i] = light->kind == RAD_LIGHT_DIRECTIONAL
                                ? disc * channel_sum(light->intensity)
                                : light_power(out, i);
        if (!(out->power[1 + i] > 0) || !isfinite(out->power[1 + i])) out->power[1 + i] = 0;
    }
    if (out->sky) out->power[out->source_count - 1] = disc * sky_integral(out->sky);
    double total = 0;
    for (size_t i = 0; i < out->source_count; ++i) {
        total += out->power[i];
        out->cdf[i] = total;
    }
    out->total_power = total;
    if (total > 0) {
        for (size_t i = 0; i < out->source_count; ++i) out->cdf[i] /= total;
        /* The last source with power ends the distribution at exactly 1. */
        for (size_t i = out->source_count; i-- > 0;) {
            if (out->power[i] > 0) {
                for (size_t j = i; j < out->source_count; ++j) out->cdf[j] = 1;
                break;
            }
        }
    }
    return RAD_OK;
}

void rad_light_emission_free(rad_context *ctx, rad_light_emission *emission) {
    if (!emission) return;
    rad_free(ctx, emission->power);
    rad_free(ctx, emission->cdf);
    for (size_t d = 0; d < emission->direction_count; ++d)
        rad_light_directions_free(ctx, &emission->directions[d]);
    rad_free(ctx, emission->directions);
    rad_free(ctx, emission->light_directions);
    memset(emission, 0, sizeof *emission);
}

/* A unit direction about `axis` with cosine uniform in [lowest, 1]: uniform over that cap. */
static rad_vec3 cap_direction(rad_vec3 axis, double lowest, double u1, double u2) {
    double c = 1 - u1 * (1 - lowest), s = sqrt(fmax(0, 1 - c * c)), phi = 2 * RAD_PI * u2;
    rad_vec3 t, b;
    v3_basis(axis, &t, &b);
    return v3_add(v3_scale(axis, c), v3_add(v3_scale(t, s * cos(phi)), v3_scale(b, s * sin(phi))));
}

/* A point on the disc of the bounding sphere's radius across `direction`, outside the sphere
 * on the side the light comes from. */
static rad_vec3 disc_origin(const rad_light_emission *e, rad_vec3 direction, double u0, double u1) {
    rad_vec3 t, b;
    v3_basis(direction, &t, &b);
    double r = e->radius * sqrt(u0), phi = 2 * RAD_PI * u1;
    rad_vec3 start = v3_sub(e->center, v3_scale(direction, 1.01 * e->radius));
    return v3_add(start, v3_add(v3_scale(t, r * cos(phi)), v3_scale(b, r * sin(phi))));
}

int rad_light_emission_sample(const rad_light_emission *e, const double u[4], rad_vec3 *origin,
                              rad_vec3 *direction, double flux[3]) {
    /* The source, by power; u0 rescaled inside its share and used again. */
    size_t i = 0;
    while (i + 1 < e->source_count && !(u[0] < e->cdf[i])) ++i;
    double below = i ? e->cdf[i - 1] : 0, share = e->cdf[i] - below;
    if (!(share > 0)) return 0;
    double u0 = share == 1 ? u[0] : fmin((u[0] - below) / share, 0x1.fffffffffffffp-1);
    if (i == 0) {
        /* An emitting surface: a triangle by power, a point uniform on it, cosine distributed,
         * flux L_e pi A_k / P_k (over the surfaces' share when other sources share the choice). */
        size_t k = rad_emitter_table_sample_point(e->surfaces, u0, u[1], origin);
        const rad_emitter *light = &e->surfaces->emitters[k];
        double scale = RAD_PI * light->area / rad_emitter_table_probability(e->surfaces, k);
        if (share != 1) scale /= share;
        for (int c = 0; c < 3; ++c) flux[c] = light->radiance[c] * scale;
        *direction = rad_cosine_direction(light->normal, u[2], u[3]);
        return 1;
    }
    if (i == e->source_count - 1) {
        /* The sky: a direction w uniform over the upper hemisphere (pdf 1 / 2 pi), light along
         * -w through the disc: flux L(w) pi R^2 2 pi / P. */
        rad_vec3 w = cap_direction(e->sky->up, 0, u[2], u[3]);
        double radiance[3];
        rad_sky_radiance(e->sky, w, radiance);
        *direction = v3_scale(w, -1);
        *origin = disc_origin(e, *direction, u0, u[1]);
        double scale = RAD_PI * e->radius * e->radius * 2 * RAD_PI / share;
        for (int c = 0; c < 3; ++c) flux[c] = radiance[c] * scale;
        return channel_sum(flux) > 0;
    }
    const rad_light *light = &e->lights[i - 1];
    if (light->kind == RAD_LIGHT_DIRECTIONAL) {
        /* The sun: E_perp pi R^2 / P through the disc. */
        *direction = light->direction;
        *origin = disc_origin(e, *direction, u0, u[1]);
        double scale = RAD_PI * e->radius * e->radius / share;
        for (int c = 0; c < 3; ++c) flux[c] = light->intensity[c] * scale;
        return 1;
    }
    /* A point light: a direction uniform over the sphere, flux 4 pi I / P; a spot light or an
     * IES profile: a direction drawn by its intensity (light_directions.h), flux I(w) / pdf / P. */
    *origin = light->position;
    double intensity[3], pdf = 1 / (4 * RAD_PI);
    const rad_light_directions *table = e->light_directions[i - 1];
    if (table) *direction = rad_light_directions_sample(table, light, u[2], u[3], &pdf);
    else *direction = cap_direction(light->direction, -1, u[2], u[3]);
    if (!(pdf > 0)) return 0;
    rad_light_intensity(light, *direction, intensity);
    for (int c = 0; c < 3; ++c) flux[c] = intensity[c] / pdf / share;
    return channel_sum(flux) > 0;
}
