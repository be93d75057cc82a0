/* pathtrace.h - the reference path tracer (docs/pathtracing.md): unbiased for every material of
 * render/bsdf.h, next-event estimation over the emitters with multiple importance sampling
 * (Veach & Guibas 1995, power heuristic), Russian roulette, jittered samples with a box filter.
 * The public entry point is rad_pathtrace (include/radiosity.h); the pieces below are shared
 * with the tests and the benchmark. */
#ifndef RAD_RENDER_PATHTRACE_H
#define RAD_RENDER_PATHTRACE_H

#include "core/rng.h"
#include "render/bsdf.h"
#include "scene/camera.h"
#include "scene/rays.h"

/* One triangle of an emitting polygon, fanned the way Embree sees it. */
typedef struct rad_light_triangle {
    rad_vec3 p0, e1, e2; /* p = p0 + s e1 + t e2 */
    rad_vec3 normal;     /* front, unit: only the front emits */
    uint32_t polygon;
} rad_light_triangle;

/* Everything the path tracer looks up per hit, precomputed once. */
typedef struct rad_tracer {
    rad_context *ctx;
    const rad_scene *scene;
    rad_rays *rays;
    const rad_material **polygon_material; /* polygon -> material */
    double *polygon_light_pdf;             /* polygon -> area density of light sampling */
    size_t light_count;
    rad_light_triangle *lights;
    double *light_cdf; /* light_count entries, the last is 1 */
    int max_bounces;   /* 0: no limit (Russian roulette ends paths) */
    int next_event;    /* nonzero (the default): sample the emitters at every smooth vertex;
                          zero: BSDF sampling only (a slower estimator, for tests) */
} rad_tracer;

rad_status rad_tracer_create(rad_context *ctx, const rad_scene *scene, int max_bounces,
                             rad_tracer **out);
void rad_tracer_destroy(rad_tracer *tracer);

/* Counters one thread keeps. */
typedef struct rad_trace_counts {
    uint64_t paths, rays, camera_hits, back_hits;
} rad_trace_counts;

/* The radiance arriving at `origin` from `direction` (unit) along one random path. */
void rad_tracer_radiance(const rad_tracer *tracer, rad_rng *rng, rad_vec3 origin,
                         rad_vec3 direction, rad_trace_counts *counts, double out[3]);

#endif
