/* rays.h - ray queries against the input geometry with Embree 3: occlusion between two points
 * (form-factor visibility) and closest hits (rendering, path tracing). Polygons are fanned into
 * triangles; a hit reports the input polygon it belongs to. */
#ifndef RAD_SCENE_RAYS_H
#define RAD_SCENE_RAYS_H

#include "scene/scene.h"

#include <embree3/rtcore.h>

/* The coordinates Embree sees. Embree works in single precision and its triangle tests
 * multiply three coordinates together, which overflows for a scene measured in 1e15 units and
 * underflows for one in 1e-15 units (issue 13: the room so scaled lost its lamp's shadow). So
 * every point handed to Embree is first moved to the scene's centre and scaled to about unit
 * size, in double precision: p' = (p - centre) * scale. Rays keep their parameter t: a
 * direction d goes in as d * scale, or unit with t scaled (see rays.c). Results are then the
 * same whatever the length unit and wherever the scene sits. */
typedef struct rad_ray_frame {
    rad_vec3 centre;
    double scale;
} rad_ray_frame;

/* The frame of the box [lo, hi]: its centre, and a power of two within a factor 2 of 1 / half
 * its diagonal (the identity for an empty, flat-to-a-point or non-finite box). */
rad_ray_frame rad_ray_frame_of_box(rad_vec3 lo, rad_vec3 hi);

/* A point in the frame, as Embree's floats. */
static inline void rad_ray_frame_point(const rad_ray_frame *frame, rad_vec3 p, float out[3]) {
    out[0] = (float)((p.x - frame->centre.x) * frame->scale);
    out[1] = (float)((p.y - frame->centre.y) * frame->scale);
    out[2] = (float)((p.z - frame->centre.z) * frame->scale);
}

/* Fills Embree's single ray from a world origin and direction (any length) and t in
 * (tnear, tfar) in units of that direction: the direction goes in unit length, t scaled to
 * match. Returns the factor that turns Embree's t back into the caller's. */
double rad_ray_frame_ray(const rad_ray_frame *frame, struct RTCRay *ray, rad_vec3 origin,
                         rad_vec3 direction, double tnear, double tfar);
/* The same for lane i of a packet of 16 (the same floats as rad_ray_frame_ray's). */
double rad_ray_frame_lane(const rad_ray_frame *frame, struct RTCRay16 *ray, int i, rad_vec3 origin,
                          rad_vec3 direction, double tnear, double tfar);
/* An empty lane i: a finite ray at the origin whose segment is empty (tnear > tfar, both >= 0).
 * Embree reads every lane of a packet on some processors whatever valid[] says (Debian's
 * Embree asserts ray.valid() and tnear >= 0 across all 16), so no lane may hold garbage. */
void rad_ray16_empty_lane(struct RTCRay16 *ray, int i);

typedef struct rad_rays {
    rad_context *ctx;
    RTCDevice device;
    RTCScene scene;
    uint32_t *triangle_polygon; /* Embree primID -> input polygon */
    size_t triangle_count;
    double epsilon; /* scene-scaled offset that keeps rays off the surfaces they start on */
    rad_ray_frame frame; /* world -> Embree coordinates */
    _Atomic long holders; /* holders beyond the first (0: one; rad_rays_share) */
} rad_rays;

/* The rays of the scene's polygons. Built once per scene and context: the scene keeps them
 * (scene->rays) and later calls get the same structure, shared, until the geometry changes
 * (rad_scene_geometry_changed). Each call's rays are released with rad_rays_destroy. */
rad_status rad_rays_create(rad_context *ctx, const rad_scene *scene, rad_rays **out);
/* One more holder of `rays` (released with rad_rays_destroy); returns rays. Thread safe. */
rad_rays *rad_rays_share(rad_rays *rays);

/* The context's Embree device (made on first use with the context's threads; its errors land
 * on the context), retained for the caller to release, and an empty robust, high-quality scene
 * on it: what every ray structure of the project starts from. */
rad_status rad_embree_open(rad_context *ctx, RTCDevice *device, RTCScene *scene);
/* Releases one holder's rays; the last frees them. NULL is fine. Thread safe. */
void rad_rays_destroy(rad_rays *rays);

/* Nonzero when something blocks the segment between a and b (ends excluded by epsilon).
 * Thread safe. */
int rad_rays_occluded(const rad_rays *rays, rad_vec3 a, rad_vec3 b);

/* The same for many segments a[i] -> b[i]: occluded[i] is set nonzero when something blocks
 * segment i. Segments go to Embree in packets of 16 (coherent batches, such as the rays from one
 * receiver to points on one patch, trace fastest). Thread safe. */
void rad_rays_occluded_batch(const rad_rays *rays, const rad_vec3 *a, const rad_vec3 *b,
                             size_t count, uint8_t *occluded);

/* How rad_rays_occluded_batch calls Embree (for benchmarks): 1 single rays, 4, 8 or 16
 * packets, 0 the stream interface rtcOccluded1M. Not thread safe; the default is 16. */
void rad_rays_set_batch_mode(int mode);

/* A packet of up to 16 segments for rad_rays_trace_packet, filled by the caller (form factors
 * fill it straight from the vectors they already have, so no segment is normalised twice). */
typedef struct rad_ray_packet {
    struct RTCRay16 ray;
    RTC_ALIGN(64) int valid[16];
    int count;
    rad_vec3 origin[16], direction[16]; /* world; moved into the rays' frame when traced */
} rad_ray_packet;

/* Empties a packet and sets what every lane shares (time, mask, id, flags). Call once before
 * first use; rad_rays_trace_packet leaves the packet empty and ready again. */
void rad_ray_packet_init(rad_ray_packet *packet);

/* Adds the segment origin -> origin + direction, blocked only for t in (tnear, tfar) (in units
 * of the direction's length). Returns the lane. The packet must not be full. */
static inline int rad_ray_packet_add(rad_ray_packet *packet, rad_vec3 origin, rad_vec3 direction,
                                     double tnear, double tfar) {
    int i = packet->count++;
    packet->origin[i] = origin;
    packet->direction[i] = direction;
    packet->ray.tnear[i] = (float)tnear;
    packet->ray.tfar[i] = (float)tfar;
    return i;
}

/* Traces the packet's segments; afterwards rad_ray_packet_occluded tells lane by lane (until
 * the next rad_ray_packet_add; the caller resets count to 0 to refill it). */
void rad_rays_trace_packet(const rad_rays *rays, rad_ray_packet *packet);

static inline int rad_ray_packet_occluded(const rad_ray_packet *packet, int lane) {
    return packet->ray.tfar[lane] < 0;
}

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
