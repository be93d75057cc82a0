/* light_emission.h - where light paths start: one distribution by power over every source of a
 * scene (the emitting surfaces' emitter table, each point, spot and directional light, the sky),
 * and for a choice a starting point, a direction and the flux it carries (docs/lights.md, "Light
 * paths"; pbrt-v4's Light::SampleLe, Pharr, Jakob & Humphreys 2023, sec. 12.x). Shared by photon
 * mapping (render/photonmap.c) and the specular-first pass (system/specular_first.c) through the
 * photon tracer (scene/photon_path.h); the camera side samples the same lights by next-event
 * estimation (light/emitters.h, light/lights.h).
 *
 * The sources' powers (W, summed over the three channels, the weight of the choice):
 *   surfaces          sum over triangles of pi A_k (L_r + L_g + L_b)
 *   point light       the integral of I(w) over the sphere: 4 pi I bare; for a spot's falloff
 *                     and an IES profile, from the table its directions are drawn from
 *                     (light_directions.h, made once at set-up)
 *   directional light E_perp pi R^2: a disc of radius R across its direction that covers the
 *                     scene's bounding sphere (centre c, radius R), outside it
 *   sky               pi R^2 times the integral of L(w) over the upper hemisphere, the same disc
 *                     across a direction drawn uniformly from the hemisphere
 * A photon's flux is the source's emission over the density of its choice, before dividing by
 * the number of photons: its expected sum is each channel's emitted power. */
#ifndef RAD_SCENE_LIGHT_EMISSION_H
#define RAD_SCENE_LIGHT_EMISSION_H

#include "light/emitters.h"
#include "scene/light_directions.h"
#include "scene/scene.h"

typedef struct rad_light_emission {
    const rad_emitter_table *surfaces; /* may be empty */
    const rad_light *lights;
    size_t light_count;
    const rad_sky *sky;  /* NULL when off */
    rad_vec3 center;     /* the scene's bounding sphere, for directional lights and the sky */
    double radius;
    size_t source_count; /* 1 (surfaces) + light_count + 1 (sky) */
    double *power;       /* per source, W summed over channels (0: never chosen) */
    double *cdf;         /* per source, normalised; the last is 1 */
    double total_power;
    rad_light_directions *directions; /* the lights' direction tables, direction_count of them */
    size_t direction_count;
    const rad_light_directions **light_directions; /* per light: its table, NULL: uniform */
} rad_light_emission;

/* The distribution over `surfaces` (built and finished by the caller) and, with `scene`, its
 * lights, and its sky when `with_sky` (`scene` NULL: the surfaces alone). An emission with no
 * power has total_power 0 and must not be sampled. */
rad_status rad_light_emission_build(rad_context *ctx, const rad_emitter_table *surfaces,
                                    const rad_scene *scene, int with_sky,
                                    rad_light_emission *out);
void rad_light_emission_free(rad_context *ctx, rad_light_emission *emission);

/* A light path's start for four uniform numbers: its origin, unit direction and flux (W, before
 * dividing by the photon count). Returns 0 when it carries nothing (rare: a spot's and an IES
 * profile's directions are drawn by their intensity, light_directions.h). With the surfaces alone, the same start as
 * rad_emitter_table_sample_point and a cosine direction give. */
int rad_light_emission_sample(const rad_light_emission *emission, const double u[4],
                              rad_vec3 *origin, rad_vec3 *direction, double flux[3]);

#endif
