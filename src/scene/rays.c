/* rays.c - Embree scene of the input geometry (see rays.h). */
#include "scene/rays.h"

#include <float.h>
#include <stdio.h>
#include <string.h>

static void embree_error(void *user, enum RTCError code, const char *message) {
    rad_context *ctx = user;
    rad_fail(ctx, RAD_ERROR_INTERNAL, "Embree error %d: %s", (int)code, message ? message : "");
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

rad_status rad_rays_create(rad_context *ctx, const rad_scene *scene, rad_rays **out) {
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
    for (size_t i = 0; i < scene->vertex_count; ++i) {
        positions[3 * i + 0] = (float)scene->vertices[i].x;
        positions[3 * i + 1] = (float)scene->vertices[i].y;
        positions[3 * i + 2] = (float)scene->vertices[i].z;
    }
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
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double diagonal = scene->vertex_count ? v3_length(v3_sub(hi, lo)) : 1;
    double magnitude = fmax(v3_max_component(v3(fabs(lo.x), fabs(lo.y), fabs(lo.z))),
                            v3_max_component(v3(fabs(hi.x), fabs(hi.y), fabs(hi.z))));
    /* Larger than float rounding at the scene's coordinates, small against its features. */
    rays->epsilon = fmax(diagonal * 1e-5, magnitude * 4e-6);
    *out = rays;
    return RAD_OK;
}

void rad_rays_destroy(rad_rays *rays) {
    if (!rays) return;
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
    ray.org_x = (float)a.x;
    ray.org_y = (float)a.y;
    ray.org_z = (float)a.z;
    ray.dir_x = (float)(d.x / length);
    ray.dir_y = (float)(d.y / length);
    ray.dir_z = (float)(d.z / length);
    ray.tnear = (float)rays->epsilon;
    ray.tfar = (float)(length - rays->epsilon);
    ray.time = 0;
    ray.mask = UINT32_MAX;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(rays->scene, &context, &ray);
    return ray.tfar < 0;
}

int rad_rays_intersect(const rad_rays *rays, rad_vec3 origin, rad_vec3 direction, double tnear,
                       double tfar, rad_hit *hit) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRayHit rh;
    rh.ray.org_x = (float)origin.x;
    rh.ray.org_y = (float)origin.y;
    rh.ray.org_z = (float)origin.z;
    rh.ray.dir_x = (float)direction.x;
    rh.ray.dir_y = (float)direction.y;
    rh.ray.dir_z = (float)direction.z;
    rh.ray.tnear = (float)tnear;
    rh.ray.tfar = tfar < FLT_MAX ? (float)tfar : FLT_MAX;
    rh.ray.time = 0;
    rh.ray.mask = UINT32_MAX;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rays->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    hit->t = rh.ray.tfar;
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
    double inverse = 1.0 / length;
    org[0] = (float)a.x;
    org[1] = (float)a.y;
    org[2] = (float)a.z;
    dir[0] = (float)(d.x * inverse);
    dir[1] = (float)(d.y * inverse);
    dir[2] = (float)(d.z * inverse);
    *tnear = (float)rays->epsilon;
    *tfar = (float)(length - rays->epsilon);
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

/* An empty lane: a finite ray at the origin whose segment is empty (tnear > tfar, both >= 0).
 * Embree reads every lane of a packet on some processors whatever valid[] says (Debian's
 * Embree asserts ray.valid() and tnear >= 0 across all 16), so no lane may hold garbage. */
static void empty_lane(struct RTCRay16 *ray, int i) {
    ray->org_x[i] = ray->org_y[i] = ray->org_z[i] = 0;
    ray->dir_x[i] = ray->dir_y[i] = 0;
    ray->dir_z[i] = 1;
    ray->tnear[i] = 1;
    ray->tfar[i] = 0;
}

void rad_ray_packet_init(rad_ray_packet *packet) {
    for (int i = 0; i < 16; ++i) {
        empty_lane(&packet->ray, i);
        packet->ray.time[i] = 0;
        packet->ray.mask[i] = UINT32_MAX;
        packet->ray.id[i] = (unsigned)i;
        packet->ray.flags[i] = 0;
    }
    packet->count = 0;
}

void rad_rays_trace_packet(const rad_rays *rays, rad_ray_packet *packet) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int i = 0; i < 16; ++i) {
        if (i >= packet->count) empty_lane(&packet->ray, i); /* unused lanes: filled, inactive */
        packet->valid[i] = i < packet->count && packet->ray.tnear[i] < packet->ray.tfar[i] ? -1 : 0;
    }
    rtcOccluded16(packet->valid, rays->scene, &context, &packet->ray);
    for (int i = 0; i < packet->count; ++i)
        if (!packet->valid[i]) packet->ray.tfar[i] = 1; /* a segment too short to be blocked */
}
