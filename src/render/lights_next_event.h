/* lights_next_event.h - next-event estimation of the point, spot and directional lights
 * (light/lights.h) at a surface point: each light sampled exactly, one shadow ray each, with no
 * multiple-importance weight (no BSDF sample finds a point or a direction). One function for
 * the path tracer (pathtrace.c) and photon mapping's camera side (photonmap.c). */
#ifndef RAD_RENDER_LIGHTS_NEXT_EVENT_H
#define RAD_RENDER_LIGHTS_NEXT_EVENT_H

#include "render/pathtrace.h"

/* Adds to out[3] the radiance towards wo (unit, away from x) that material m at x (front normal
 * `normal`) reflects of every light of the tracer's scene that x sees, times `throughput`; adds
 * the shadow rays cast to *rays. */
void rad_lights_next_event(const rad_tracer *tracer, const rad_material *m, rad_vec3 x,
                           rad_vec3 normal, rad_vec3 wo, const double throughput[3],
                           uint64_t *rays, double out[3]);

#endif
