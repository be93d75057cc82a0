/* pathtrace.h - the reference path tracer (docs/pathtracing.md): unbiased for every material of
 * scene/bsdf.h, next-event estimation over the emitters with multiple importance sampling
 * (Veach & Guibas 1995, power heuristic), Russian roulette, Owen-scrambled Sobol' samples (core/sampler.h) with a box filter.
 * The public entry point is rad_pathtrace (include/radiosity.h); the pieces below are shared
 * with the tests and the benchmark. */
#ifndef RAD_RENDER_PATHTRACE_H
#define RAD_RENDER_PATHTRACE_H

#include "core/sampler.h"
#include "light/emitters.h"
#include "scene/bsdf.h"
#include "scene/camera.h"
#include "scene/rays.h"

/* Everything the path tracer looks up per hit, precomputed once. */
typedef struct rad_tracer {
    rad_context *ctx;
    const rad_scene *scene;
    rad_rays *rays;
    const rad_material **polygon_material; /* polygon -> material */
    rad_emitter_table emitters;            /* the emitting polygons' triangles, by power */
    int32_t *polygon_emitter;              /* polygon -> its first emitter triangle, or -1 */
    int max_bounces;   /* 0: no limit (Russian roulette ends paths) */
    int next_event;    /* nonzero (the default): sample the emitters at every smooth vertex;
                          zero: BSDF sampling only (a slower estimator, for tests) */
    double roulette_weight; /* Russian roulette continues with probability throughput / this
                               (0.1); 1 is the textbook q = throughput (for tests) */
    double clamp_indirect;  /* 0 (the default): unbiased. Else each contribution of light that
                               left its emitter and scattered at least twice (the NEE at the
                               second and later vertices, emission BSDF sampling finds from the
                               second vertex on) is scaled down until its R + G + B is at most
                               this: Cycles' "Clamp Indirect" (biased, darker, less noise) */
} rad_tracer;

rad_status rad_tracer_create(rad_context *ctx, const rad_scene *scene, int max_bounces,
                             rad_tracer **out);
void rad_tracer_destroy(rad_tracer *tracer);

/* Counters one thread keeps. */
typedef struct rad_trace_counts {
    uint64_t paths, rays, camera_hits, back_hits;
} rad_trace_counts;

/* The sampler's dimensions (core/sampler.h) along a path, the same for every path: a 4D set
 * RAD_PATH_DIM_PIXEL (the position in the pixel, bounce 0's emitter point), then two per bounce
 * b from RAD_PATH_DIM_BOUNCE + 2 b: a 4D set (b's BSDF direction, bounce b + 1's emitter point)
 * and a 2D one (lobe choice, Russian roulette). The camera is a pinhole: no lens dimensions. */
enum { RAD_PATH_DIM_PIXEL = 0, RAD_PATH_DIM_BOUNCE = 1, RAD_PATH_DIMS_PER_BOUNCE = 2 };

/* The radiance arriving at `origin` from `direction` (unit) along one path, its random numbers
 * drawn from `sampler` at its index in the dimensions above (the caller sets the index and
 * takes the position in the pixel from RAD_PATH_DIM_PIXEL; this sets the dimensions). */
void rad_tracer_radiance(const rad_tracer *tracer, rad_sampler *sampler, rad_vec3 origin,
                         rad_vec3 direction, rad_trace_counts *counts, double out[3]);

/* Before any work (the path tracer, photon mapping): primary rays through a grid over the image
 * must see the front of something; else RAD_ERROR_INVALID_ARGUMENT with the reason. */
rad_status rad_tracer_check_view(const rad_tracer *tracer, const rad_view *view);

#endif
