/* rays.c - Embree scene of the input geometry (see rays.h). */
#include "scene/rays.h"

#include <float.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

static void embree_error(void *user, enum RTCError code, const char *message) {
    rad_context *ctx = user;
    rad_fail(ctx, RAD_ERROR_INTERNAL, "Embree error %d: %s", (int)code, message ? message : "");
}

rad_ray_frame rad_ray_frame_of_box(rad_vec3 lo, rad_vec3 hi) {
    rad_ray_frame frame = {v3(0, 0, 0), 1};
    double half = 0.5 * v3_length(v3_sub(hi, lo));
    if (!(half > 0) || !isfinite(half)) return frame; /* empty, a point, or not finite */
    frame.centre = v3_scale(v3_add(lo, hi), 0.5);
    /* A power of two near 1 / half: scaling is then exact, and a scene scaled by a power of
     * two meets Embree in the very same floats. */
    int exponent;
    frexp(half, &exponent);
    frame.scale = ldexp(1, -exponent);
    return frame;
}

/* The floats of a ray in the frame (rad_ray_frame_ray), for a single ray or a packet's lane. */
typedef struct frame_floats {
    float org[3], dir[3], tnear, tfar;
} frame_floats;

static double frame_floats_make(const rad_ray_frame *frame, rad_vec3 origin, rad_vec3 direction,
                                double tnear, double tfar, frame_floats *f) {
    rad_ray_frame_point(frame, origin, f->org);
    double length = v3_length(direction);
    if (!(length > 0)) length = 1;
    double to_frame = length * frame->scale; /* caller's t -> Embree's t along a unit direction */
    double inverse = 1 / length; /* one division, not three: the rays' hottest line */
    f->dir[0] = (float)(direction.x * inverse);
    f->dir[1] = (float)(direction.y * inverse);
    f->dir[2] = (float)(direction.z * inverse);
    f->tnear = (float)(tnear * to_frame);
    double far = tfar * to_frame;
    f->tfar = far < FLT_MAX ? (float)far : FLT_MAX;
    return 1 / to_frame;
}

double rad_ray_frame_ray(const rad_ray_frame *frame, struct RTCRay *ray, rad_vec3 origin,
                         rad_vec3 direction, double tnear, double tfar) {
    frame_floats f;
    double to_caller = frame_floats_make(frame, origin, direction, tnear, tfar, &f);
    ray->org_x = f.org[0];
    ray->org_y = f.org[1];
    ray->org_z = f.org[2];
    ray->dir_x = f.dir[0];
    ray->dir_y = f.dir[1];
    ray->dir_z = f.dir[2];
    ray->tnear = f.tnear;
    ray->tfar = f.tfar;
    ray->time = 0;
    ray->mask = UINT32_MAX;
    ray->id = 0;
    ray->flags = 0;
    return to_caller;
}

double rad_ray_frame_lane(const rad_ray_frame *frame, struct RTCRay16 *ray, int i, rad_vec3 origin,
                          rad_vec3 direction, double tnear, double tfar) {
    frame_floats f;
    double to_caller = frame_floats_make(frame, origin, direction, tnear, tfar, &f);
    ray->org_x[i] = f.org[0];
    ray->org_y[i] = f.org[1];
    ray->org_z[i] = f.org[2];
    ray->dir_x[i] = f.dir[0];
    ray->dir_y[i] = f.dir[1];
    ray->dir_z[i] = f.dir[2];
    ray->tnear[i] = f.tnear;
    ray->tfar[i] = f.tfar;
    ray->time[i] = 0;
    ray->mask[i] = UINT32_MAX;
    ray->id[i] = (unsigned)i;
    ray->flags[i] = 0;
    return to_caller;
}

static void release_device(void *device) { rtcReleaseDevice((RTCDevice)device); }

rad_status rad_embree_open(rad_context *ctx, RTCDevice *device, RTCScene *scene) {
    *scene = NULL;
    *device = NULL;
    /* One device per context, made on first use; each structure holds a reference. */
    if (!ctx->ray_device) {
        char config[64];
        snprintf(config, sizeof config, "threads=%d", rad_thread_count(ctx));
        RTCDevice made = rtcNewDevice(config);
        if (!made) return rad_fail(ctx, RAD_ERROR_INTERNAL, "Embree: cannot create a device");
        rtcSetDeviceErrorFunction(made, embree_error, ctx);
        ctx->ray_device = made;
        ctx->release_ray_device = release_device;
    }
    *device = (RTCDevice)ctx->ray_device;
    rtcRetainDevice(*device);
    *scene = rtcNewScene(*device);
    if (!*scene) return rad_fail(ctx, RAD_ERROR_INTERNAL, "Embree: cannot create a scene");
    /* Robust traversal: no ray slips through an edge shared by two triangles or elements. */
    rtcSetSceneFlags(*scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(*scene, RTC_BUILD_QUALITY_HIGH);
    return RAD_OK;
}

rad_rays *rad_rays_share(rad_rays *rays) {
    atomic_fetch_add(&rays->holders, 1);
    return rays;
}

static rad_status rays_build(rad_context *ctx, const rad_scene *scene, rad_rays **out);

rad_status rad_rays_create(rad_context *ctx, const rad_scene *scene, rad_rays **out) {
    *out = NULL;
    if (scene->rays && scene->rays->ctx == ctx) {
        *out = rad_rays_share(scene->rays);
        return RAD_OK;
    }
    rad_status status = rays_build(ctx, scene, out);
    /* Kept on the scene (a cache: the scene is otherwise unchanged) for the next caller. */
    if (!status && ctx == scene->ctx && !scene->rays) ((rad_scene *)scene)->rays = rad_rays_share(*out);
    return status;
}

static rad_status rays_build(rad_context *ctx, const rad_scene *scene, rad_rays **out) {
    *out = NULL;
    rad_rays *rays = rad_alloc_zero(ctx, 1, sizeof *rays);
    if (!rays) return RAD_ERROR_NO_MEMORY;
    rays->ctx = ctx;
    size_t triangles = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i) triangles += scene->polygons[i].count - 2;
    rays->triangle_count = triangles;
    rays->triangle_polygon = rad_alloc(ctx, triangles + 1, sizeof *rays->triangle_polygon);
    if (!rays->triangle_polygon) {
        rad_rays_destroy(rays);
        return RAD_ERROR_NO_MEMORY;
    }
    rad_status opened = rad_embree_open(ctx, &rays->device, &rays->scene);
    if (opened) {
        rad_rays_destroy(rays);
        return opened;
    }
    RTCGeometry geometry = rtcNewGeometry(rays->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *positions = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                               scene->vertex_count ? scene->vertex_count : 1);
    unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                triangles ? triangles : 1);
    if (!positions || !indices) {
        rtcReleaseGeometry(geometry);
        rad_rays_destroy(rays);
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "Embree: out of memory for %zu triangles",
                        triangles);
    }
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    rays->frame = scene->vertex_count ? rad_ray_frame_of_box(lo, hi) : rad_ray_frame_of_box(lo, lo);
    for (size_t i = 0; i < scene->vertex_count; ++i)
        rad_ray_frame_point(&rays->frame, scene->vertices[i], positions + 3 * i);
    size_t t = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *polygon = &scene->polygons[i];
        const uint32_t *v = scene->polygon_vertices + polygon->first;
        for (uint32_t k = 1; k + 1 < polygon->count; ++k, ++t) {
            indices[3 * t + 0] = v[0];
            indices[3 * t + 1] = v[k];
            indices[3 * t + 2] = v[k + 1];
            rays->triangle_polygon[t] = (uint32_t)i;
        }
    }
    if (triangles == 0) { /* an empty scene still needs a valid (degenerate) triangle */
        positions[0] = positions[1] = positions[2] = 0;
        indices[0] = indices[1] = indices[2] = 0;
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(rays->scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(rays->scene);
    if (rtcGetDeviceError(rays->device) != RTC_ERROR_NONE) {
        rad_rays_destroy(rays);
        return RAD_ERROR_INTERNAL;
    }
    double diagonal = scene->vertex_count ? v3_length(v3_sub(hi, lo)) : 1;
    /* Larger than float rounding in the frame (about 1e-7 of the diagonal wherever the scene
     * sits), small against the scene's features. */
    rays->epsilon = diagonal * 1e-5;
    *out = rays;
    return RAD_OK;
}

void rad_rays_destroy(rad_rays *rays) {
    if (!rays) return;
    if (atomic_fetch_sub(&rays->holders, 1) > 0) return; /* others still hold them */
    if (rays->scene) rtcReleaseScene(rays->scene);
    if (rays->device) rtcReleaseDevice(rays->device);
    rad_free(rays->ctx, rays->triangle_polygon);
    rad_free(rays->ctx, rays);
}

int rad_rays_occluded(const rad_rays *rays, rad_vec3 a, rad_vec3 b) {
    rad_vec3 d = v3_sub(b, a);
    double length = v3_length(d);
    if (length <= 2 * rays->epsilon) return 0;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRay ray;
    rad_ray_frame_ray(&rays->frame, &ray, a, d, rays->epsilon / length, 1 - rays->epsilon / length);
    rtcOccluded1(rays->scene, &context, &ray);
    return ray.tfar < 0;
}

int rad_rays_intersect(const rad_rays *rays, rad_vec3 origin, rad_vec3 direction, double tnear,
                       double tfar, rad_hit *hit) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRayHit rh;
    double to_caller = rad_ray_frame_ray(&rays->frame, &rh.ray, origin, direction, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rays->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    hit->t = rh.ray.tfar * to_caller;
    hit->polygon = rays->triangle_polygon[rh.hit.primID];
    /* Embree's Ng is (e1 x e2) for v0, v1, v2 = counter-clockwise: the front normal. */
    rad_vec3 n = v3_normalize(v3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    hit->front = v3_dot(n, direction) < 0;
    hit->normal = n;
    return 1;
}

/* ------------------------------------------------------------------------------------------- */
/* Batches: packets of N rays (Embree's SIMD traversal) or the stream interface. Packets of 16
 * measured fastest for the coherent rays of form factors (bench/bench_formfactors.c).           */

static int batch_mode = 16;

void rad_rays_set_batch_mode(int mode) { batch_mode = mode; }

/* One segment as a ray: unit direction, t in (epsilon, length - epsilon). Returns 0 when the
 * segment is too short to be blocked. */
static int segment_ray(const rad_rays *rays, rad_vec3 a, rad_vec3 b, float org[3], float dir[3],
                       float *tnear, float *tfar) {
    rad_vec3 d = v3_sub(b, a);
    double length = v3_length(d);
    if (length <= 2 * rays->epsilon) return 0;
    double inverse = 1.0 / length, scale = rays->frame.scale;
    rad_ray_frame_point(&rays->frame, a, org);
    dir[0] = (float)(d.x * inverse);
    dir[1] = (float)(d.y * inverse);
    dir[2] = (float)(d.z * inverse);
    *tnear = (float)(rays->epsilon * scale);
    *tfar = (float)((length - rays->epsilon) * scale);
    return 1;
}

#define DEFINE_PACKET(N)                                                                          \
    static void occluded_packets##N(const rad_rays *rays, const rad_vec3 *a, const rad_vec3 *b,  \
                                    size_t count, uint8_t *occluded) {                           \
        struct RTCIntersectContext context;                                                      \
        rtcInitIntersectContext(&context);                                                       \
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;                                     \
        for (size_t start = 0; start < count; start += N) {                                      \
            RTC_ALIGN(64) struct RTCRay##N ray;                                                  \
            RTC_ALIGN(64) int valid[N];                                                          \
            size_t lanes = count - start < N ? count - start : N;                                \
            for (size_t i = 0; i < N; ++i) {                                                     \
                float org[3] = {0, 0, 0}, dir[3] = {0, 0, 1}, tnear = 1, tfar = 0; /* empty */ \
                int live = i < lanes &&                                                          \
                           segment_ray(rays, a[start + i], b[start + i], org, dir, &tnear, &tfar); \
                valid[i] = live ? -1 : 0;                                                        \
                ray.org_x[i] = org[0];                                                           \
                ray.org_y[i] = org[1];                                                           \
                ray.org_z[i] = org[2];                                                           \
                ray.dir_x[i] = dir[0];                                                           \
                ray.dir_y[i] = dir[1];                                                           \
                ray.dir_z[i] = dir[2];                                                           \
                ray.tnear[i] = tnear;                                                            \
                ray.tfar[i] = tfar;                                                              \
                ray.time[i] = 0;                                                                 \
                ray.mask[i] = UINT32_MAX;                                                        \
                ray.id[i] = (unsigned)i;                                                         \
                ray.flags[i] = 0;                                                                \
            }                                                                                    \
            rtcOccluded##N(valid, rays->scene, &context, &ray);                                  \
            for (size_t i = 0; i < lanes; ++i) occluded[start + i] = valid[i] && ray.tfar[i] < 0; \
        }                                                                                        \
    }

DEFINE_PACKET(4)
DEFINE_PACKET(8)
DEFINE_PACKET(16)

static void occluded_stream(const rad_rays *rays, const rad_vec3 *a, const rad_vec3 *b,
                            size_t count, uint8_t *occluded) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    enum { CHUNK = 64 };
    struct RTCRay ray[CHUNK];
    unsigned slot[CHUNK];
    for (size_t start = 0; start < count; start += CHUNK) {
        size_t lanes = count - start < CHUNK ? count - start : CHUNK;
        unsigned live = 0;
        for (size_t i = 0; i < lanes; ++i) {
            struct RTCRay *r = &ray[live];
            float org[3], dir[3];
            occluded[start + i] = 0;
            if (!segment_ray(rays, a[start + i], b[start + i], org, dir, &r->tnear, &r->tfar))
                continue;
            r->org_x = org[0];
            r->org_y = org[1];
            r->org_z = org[2];
            r->dir_x = dir[0];
            r->dir_y = dir[1];
            r->dir_z = dir[2];
            r->time = 0;
            r->mask = UINT32_MAX;
            r->id = (unsigned)i;
            r->flags = 0;
            slot[live++] = (unsigned)i;
        }
        if (live) rtcOccluded1M(rays->scene, &context, ray, live, sizeof ray[0]);
        for (unsigned k = 0; k < live; ++k) occluded[start + slot[k]] = ray[k].tfar < 0;
    }
}

void rad_rays_occluded_batch(const rad_rays *rays, const rad_vec3 *a, const rad_vec3 *b,
                             size_t count, uint8_t *occluded) {
    switch (batch_mode) {
    case 0: occluded_stream(rays, a, b, count, occluded); break;
    case 4: occluded_packets4(rays, a, b, count, occluded); break;
    case 8: occluded_packets8(rays, a, b, count, occluded); break;
    case 16: occluded_packets16(rays, a, b, count, occluded); break;
    default:
        for (size_t i = 0; i < count; ++i) occluded[i] = (uint8_t)rad_rays_occluded(rays, a[i], b[i]);
    }
}

void rad_ray16_empty_lane(struct RTCRay16 *ray, int i) {
    ray->org_x[i] = ray->org_y[i] = ray->org_z[i] = 0;
    ray->dir_x[i] = ray->dir_y[i] = 0;
    ray->dir_z[i] = 1;
    ray->tnear[i] = 1;
    ray->tfar[i] = 0;
    ray->time[i] = 0;
    ray->mask[i] = UINT32_MAX;
    ray->id[i] = (unsigned)i;
    ray->flags[i] = 0;
}

void rad_ray_packet_init(rad_ray_packet *packet) {
    for (int i = 0; i < 16; ++i) rad_ray16_empty_lane(&packet->ray, i);
    packet->count = 0;
}

void rad_rays_trace_packet(const rad_rays *rays, rad_ray_packet *packet) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    double scale = rays->frame.scale;
    for (int i = 0; i < 16; ++i) {
        if (i >= packet->count) rad_ray16_empty_lane(&packet->ray, i); /* unused lanes: filled, inactive */
        else { /* into the frame: t stays in units of the (scaled) direction */
            float org[3];
            rad_ray_frame_point(&rays->frame, packet->origin[i], org);
            packet->ray.org_x[i] = org[0];
            packet->ray.org_y[i] = org[1];
            packet->ray.org_z[i] = org[2];
            packet->ray.dir_x[i] = (float)(packet->direction[i].x * scale);
            packet->ray.dir_y[i] = (float)(packet->direction[i].y * scale);
            packet->ray.dir_z[i] = (float)(packet->direction[i].z * scale);
        }
        packet->valid[i] = i < packet->count && packet->ray.tnear[i] < packet->ray.tfar[i] ? -1 : 0;
    }
    rtcOccluded16(packet->valid, rays->scene, &context, &packet->ray);
    for (int i = 0; i < packet->count; ++i)
        if (!packet->valid[i]) packet->ray.tfar[i] = 1; /* a segment too short to be blocked */
}
