/* rays.h - ray queries against the input geometry with Embree 3: occlusion between two points
 * (form-factor visibility) and closest hits (rendering, path tracing). Polygons are fanned into
 * triangles; a hit reports the input polygon it belongs to. */
#ifndef RAD_SCENE_RAYS_H
#define RAD_SCENE_RAYS_H

#include "scene/scene.h"

#include <embree3/rtcore.h>

typedef struct rad_rays {
    rad_context *ctx;
    RTCDevice device;
    RTCScene scene;
    uint32_t *triangle_polygon; /* Embree primID -> input polygon */
    size_t triangle_count;
    double epsilon; /* scene-scaled offset that keeps rays off the surfaces they start on */
} rad_rays;

rad_status rad_rays_create(rad_context *ctx, const rad_scene *scene, rad_rays **out);
void rad_rays_destroy(rad_rays *rays);

/* Nonzero when something blocks the segment between a and b (ends excluded by epsilon).
 * Thread safe. */
int rad_rays_occluded(const rad_rays *rays, rad_vec3 a, rad_vec3 b);

typedef struct rad_hit {
    double t;
    uint32_t polygon;
    rad_vec3 normal; /* geometric, unit, of the polygon's front */
    int front;       /* nonzero when the ray hit the front side */
} rad_hit;

/* The closest hit along origin + t * direction (direction need not be unit), t in (tnear, tfar).
 * Returns nonzero on a hit. Thread safe. */
int rad_rays_intersect(const rad_rays *rays, rad_vec3 origin, rad_vec3 direction, double tnear,
                       double tfar, rad_hit *hit);

#endif
