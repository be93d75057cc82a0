/* photon_path.h - one light path (a photon) from the emitting surfaces through the scene, the one
 * photon tracer shared by photon mapping (render/photonmap.c) and the specular-first pass
 * (system/specular_first.c): emitted by power from every source (scene/light_emission.h: the
 * emitting surfaces cosine distributed, point, spot and directional lights, the sky), then scattered by the BSDFs (scene/bsdf.h) with Russian roulette on the
 * scattering weight, so a surviving photon keeps its flux on grey surfaces.
 *
 * The caller sees the photon at every surface with a diffuse or glossy lobe (where it is stored
 * or deposited) through a callback; it decides what to keep. Every random number is an
 * Owen-scrambled Sobol' point of (seed, index) (core/sampler.h): a photon is the same for any
 * thread count. */
#ifndef RAD_SCENE_PHOTON_PATH_H
#define RAD_SCENE_PHOTON_PATH_H

#include "scene/bsdf.h"
#include "scene/light_emission.h"
#include "scene/rays.h"
#include "scene/scene.h"

/* What a photon travels through: the scene's rays, each polygon's material, the emitters. */
typedef struct rad_photon_scene {
    const rad_rays *rays;
    const rad_material *const *polygon_material; /* polygon -> material */
    const rad_light_emission *sources; /* where photons start: surfaces, lights, sky, by power */
    const rad_scene *scene; /* for textures (the albedo at a hit), or NULL: materials as they are */
} rad_photon_scene;

/* A photon arriving at a surface with a diffuse or glossy lobe. */
typedef struct rad_photon_arrival {
    rad_vec3 origin, direction; /* the ray it arrived along (direction unit) */
    rad_vec3 position;          /* origin + hit.t direction */
    rad_hit hit;
    const rad_material *material;
    double power[3];            /* its flux, before dividing by the photon count */
    int bounce;                 /* surfaces met before this one (0: straight from the emitter) */
    int specular_path;          /* nonzero when every earlier bounce was a mirror or glass one */
} rad_photon_arrival;

/* Called at each arrival; returns 0 to stop the photon and report failure (out of memory). */
typedef int (*rad_photon_visit)(void *user, const rad_photon_arrival *arrival);

/* Traces photon `index` of the sequence `seed`, calling `visit` at each smooth surface. With
 * `specular_only`, the photon ends at its first diffuse or glossy bounce (L S* D paths only).
 * `max_bounces` bounds the path. Adds the rays cast to *rays. Returns 0 when `visit` did. */
int rad_photon_path_trace(const rad_photon_scene *scene, uint64_t seed, uint64_t index,
                          int specular_only, int max_bounces, rad_photon_visit visit, void *user,
                          uint64_t *rays);

#endif
