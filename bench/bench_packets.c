/* bench_packets.c - what one ray costs in Embree by packet width and by the lanes a call fills:
 * rtcIntersect1 / rtcOccluded1 once a ray, or one rtcIntersect4/8/16 (rtcOccluded4/8/16) call
 * per point holding its n rays, as the renderer's gather packets and shadow packets are made
 * (render/final_gather.c). The rays are the Cornell box's (the default mesh, robust traversal
 * off as for the renderer's gather and shadow rays): 20,000 points where camera rays through a
 * 256 x 256 image first meet a front face, each with 16 cosine-distributed directions and 16
 * segments to random points of the lamp. Prints nanoseconds of processor time per ray (the best
 * of three, one thread) as Markdown tables, for the renderer's structure (each flat grid of
 * elements one quad, element_rays.h) and for every element a primitive. Timings only: nothing
 * here passes or fails.
 * Usage: bench_packets */
#include "radiosity.h"
#include "core/rng.h"
#include "scene/camera.h"
#include "system/element_rays.h"
#include "system/system.h"

#include <stdio.h>
#include <time.h>

#define POINTS 20000
#define RAYS 16 /* per point */

static double processor_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The rays in Embree's frame: origin, unit directions (gather) and unit directions with the
 * segment's end (shadow). */
static float origin[POINTS][3], gather[POINTS][RAYS][3], shadow[POINTS][RAYS][4];
static float tnear;
static volatile unsigned long long sink; /* keeps the results alive */

static void single_ray(struct RTCRay *ray, int point, int k, int occlusion) {
    ray->org_x = origin[point][0];
    ray->org_y = origin[point][1];
    ray->org_z = origin[point][2];
    const float *d = occlusion ? shadow[point][k] : gather[point][k];
    ray->dir_x = d[0];
    ray->dir_y = d[1];
    ray->dir_z = d[2];
    ray->tfar = occlusion ? shadow[point][k][3] : 3.4e38f;
    ray->tnear = tnear;
    ray->time = 0;
    ray->mask = UINT32_MAX;
    ray->id = (unsigned)k;
    ray->flags = 0;
}

/* Lane i of a packet from a single ray, or empty (a segment with tnear > tfar). */
#define SET_LANE(packet, i, single, used)                                                        \
    do {                                                                                         \
        (packet).org_x[i] = used ? (single).org_x : 0;                                           \
        (packet).org_y[i] = used ? (single).org_y : 0;                                           \
        (packet).org_z[i] = used ? (single).org_z : 0;                                           \
        (packet).dir_x[i] = used ? (single).dir_x : 0;                                           \
        (packet).dir_y[i] = used ? (single).dir_y : 0;                                           \
        (packet).dir_z[i] = used ? (single).dir_z : 1;                                           \
        (packet).tnear[i] = used ? (single).tnear : 1;                                           \
        (packet).tfar[i] = used ? (single).tfar : 0;                                             \
        (packet).time[i] = 0;                                                                    \
        (packet).mask[i] = UINT32_MAX;                                                           \
        (packet).id[i] = (unsigned)(i);                                                          \
        (packet).flags[i] = 0;                                                                   \
    } while (0)

/* One call of width K for rays first .. first + n - 1 of a point. */
#define CALL_OF(K)                                                                               \
    static void call_##K(RTCScene scene, struct RTCIntersectContext *context, int point,         \
                         int first, int n, int occlusion) {                                      \
        RTC_ALIGN(4 * K) struct RTCRayHit##K rh;                                                 \
        RTC_ALIGN(4 * K) int valid[K];                                                           \
        for (int i = 0; i < K; ++i) {                                                            \
            struct RTCRay single;                                                                \
            if (i < n) single_ray(&single, point, first + i, occlusion);                         \
            SET_LANE(rh.ray, i, single, i < n);                                                  \
            valid[i] = i < n ? -1 : 0;                                                           \
            rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;                                          \
        }                                                                                        \
        if (occlusion) {                                                                         \
            rtcOccluded##K(valid, scene, context, &rh.ray);                                      \
            sink += rh.ray.tfar[0] < 0;                                                          \
        } else {                                                                                 \
            rtcIntersect##K(valid, scene, context, &rh);                                         \
            sink += rh.hit.primID[0];                                                            \
        }                                                                                        \
    }
CALL_OF(4)
CALL_OF(8)
CALL_OF(16)

/* Nanoseconds per ray: every point's first `lanes` rays, `width` to a call (1: one at a time). */
static double per_ray(RTCScene scene, int width, int lanes, int occlusion) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    double start = processor_seconds();
    for (int point = 0; point < POINTS; ++point)
        for (int first = 0; first < lanes; first += width) {
            int n = lanes - first < width ? lanes - first : width;
            if (width == 1) {
                struct RTCRayHit rh;
                single_ray(&rh.ray, point, first, occlusion);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                if (occlusion) {
                    rtcOccluded1(scene, &context, &rh.ray);
                    sink += rh.ray.tfar < 0;
                } else {
                    rtcIntersect1(scene, &context, &rh);
                    sink += rh.hit.primID;
                }
            } else if (width == 4) call_4(scene, &context, point, first, n, occlusion);
            else if (width == 8) call_8(scene, &context, point, first, n, occlusion);
            else call_16(scene, &context, point, first, n, occlusion);
        }
    return (processor_seconds() - start) / ((double)POINTS * lanes) * 1e9;
}

static int fail(rad_context *ctx, const char *what) {
    fprintf(stderr, "bench_packets: %s: %s\n", what, ctx ? rad_context_error(ctx) : "");
    return 1;
}

int main(void) {
    rad_context *ctx = NULL;
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_element_rays *rays = NULL;
    if (rad_context_create(NULL, &ctx)) return fail(NULL, "context");
    if (rad_scene_builtin(ctx, "cornell", &scene)) return fail(ctx, "scene");
    if (rad_system_create(ctx, scene, NULL, NULL, &system)) return fail(ctx, "system");
    const rad_mesh *mesh = system->mesh;
    if (rad_element_rays_create_with(ctx, mesh, 0, &rays)) return fail(ctx, "rays");
    rad_camera camera = rad_scene_camera(scene);
    rad_view view;
    if (rad_view_make(ctx, &camera, 256, 256, &view)) return fail(ctx, "view");

    /* The lamp's bounds: the emitting elements' corners. */
    rad_vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t e = 0; e < mesh->element_count; ++e) {
        const double *emission = system->emission[e];
        if (!(emission[0] > 0 || emission[1] > 0 || emission[2] > 0)) continue;
        const uint32_t *c = mesh->element_vertices[e];
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            rad_vec3 q = mesh->vertices[c[k]];
            lo = v3(fmin(lo.x, q.x), fmin(lo.y, q.y), fmin(lo.z, q.z));
            hi = v3(fmax(hi.x, q.x), fmax(hi.y, q.y), fmax(hi.z, q.z));
        }
    }
    rad_rng state = rad_rng_make(12345, 0);
    tnear = (float)(rays->epsilon * rays->frame.scale);
    for (int point = 0; point < POINTS;) {
        rad_element_hit hit;
        rad_vec3 d = rad_view_direction(&view, 256 * rad_rng_uniform(&state), 256 * rad_rng_uniform(&state));
        if (!rad_element_rays_intersect(rays, view.eye, d, 0, INFINITY, &hit) || !hit.front) continue;
        rad_vec3 x = v3_add(view.eye, v3_scale(d, hit.t)), n = mesh->element_normal[hit.element], t, b;
        v3_basis(n, &t, &b);
        rad_ray_frame_point(&rays->frame, x, origin[point]);
        for (int k = 0; k < RAYS; ++k) {
            double u0 = rad_rng_uniform(&state), u1 = rad_rng_uniform(&state), radius = sqrt(u0);
            rad_vec3 w = v3_add(v3_add(v3_scale(t, radius * cos(2 * RAD_PI * u1)),
                                       v3_scale(b, radius * sin(2 * RAD_PI * u1))),
                                v3_scale(n, sqrt(1 - u0)));
            for (int c = 0; c < 3; ++c) gather[point][k][c] = (float)(c == 0 ? w.x : c == 1 ? w.y : w.z);
            rad_vec3 lamp = v3(lo.x + rad_rng_uniform(&state) * (hi.x - lo.x), lo.y,
                               lo.z + rad_rng_uniform(&state) * (hi.z - lo.z));
            rad_vec3 s = v3_sub(lamp, x);
            double length = v3_length(s);
            shadow[point][k][0] = (float)(s.x / length);
            shadow[point][k][1] = (float)(s.y / length);
            shadow[point][k][2] = (float)(s.z / length);
            shadow[point][k][3] = (float)((length - rays->epsilon) * rays->frame.scale);
        }
        ++point;
    }

    /* The same mesh traced element by element (its grids not taken as quads). */
    rad_mesh plain = *mesh;
    plain.grid_count = plain.tree_count = 0;
    rad_element_rays *element_rays = NULL;
    if (rad_element_rays_create_with(ctx, &plain, 0, &element_rays)) return fail(ctx, "rays");
    printf("## Embree per ray by packet width, Cornell box elements (ns of processor time)\n\n");
    printf("Native packets (Embree's device): 4 %d, 8 %d, 16 %d.\n\n",
           (int)rtcGetDeviceProperty(rays->device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED),
           (int)rtcGetDeviceProperty(rays->device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED),
           (int)rtcGetDeviceProperty(rays->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED));
    static const int lanes[] = {1, 2, 4, 8, 16};
    static const int widths[] = {1, 4, 8, 16};
    for (int grids = 1; grids >= 0; --grids) {
        RTCScene traced = grids ? rays->scene : element_rays->scene;
        printf("### %s\n\n", grids ? "The renderer's structure: each flat grid one quad "
                                      "(element_rays.h), the element found after the hit"
                                    : "Every element a primitive (before the grids)");
        printf("%zu primitives for %zu elements; Embree's time alone (the element lookup "
               "after a grid's hit is not in it).\n\n",
               grids ? rays->quad_count + rays->loose_count : mesh->element_count,
               mesh->element_count);
        for (int occlusion = 0; occlusion < 2; ++occlusion) {
            printf("%s\n\n| rays a point | one at a time | width 4 | width 8 | width 16 |\n"
                   "|---|---|---|---|---|\n",
                   occlusion ? "Shadow rays (to the lamp, rtcOccluded*)"
                             : "Gather rays (cosine-distributed, rtcIntersect*)");
            for (size_t l = 0; l < sizeof lanes / sizeof lanes[0]; ++l) {
                printf("| %d", lanes[l]);
                for (size_t w = 0; w < sizeof widths / sizeof widths[0]; ++w) {
                    double best = INFINITY;
                    for (int run = 0; run < 3; ++run)
                        best = fmin(best, per_ray(traced, widths[w], lanes[l], occlusion));
                    printf(" | %.0f", best);
                }
                printf(" |\n");
            }
            printf("\n");
        }
    }
    rad_element_rays_destroy(element_rays);
    rad_element_rays_destroy(rays);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return 0;
}
