/* element_rays.c - Embree scene of the element mesh (see element_rays.h). */
#include "system/element_rays.h"

#include "scene/rays.h"

#include <float.h>
#include <stdio.h>

void rad_element_rays_destroy(rad_element_rays *rays) {
    if (!rays) return;
    if (rays->scene) rtcReleaseScene(rays->scene);
    if (rays->device) rtcReleaseDevice(rays->device);
    rad_free(rays->ctx, rays);
}

/* One Embree quad geometry holding every element, primitive i being element i: a triangle
 * (v0, v1, v2) goes in as the quad (v0, v1, v2, v2), which Embree documents as the way to mix
 * the two; its hits all fall in the quad's first half (v0, v1, v3), where u and v are the
 * triangle's own. One geometry rather than a quad and a triangle geometry: no element table to
 * read after each hit, and one BVH to traverse (less processor time on the Cornell render and on
 * Sponza, the same hits on the Cornell box: docs/rendering.md, "One element geometry"). */
static rad_status add_elements(rad_element_rays *rays) {
    const rad_mesh *mesh = rays->mesh;
    if (mesh->element_count == 0) return RAD_OK;
    RTCGeometry geometry = rtcNewGeometry(rays->device, RTC_GEOMETRY_TYPE_QUAD);
    float *positions = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                               mesh->vertex_count);
    unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                RTC_FORMAT_UINT4, 4 * sizeof(unsigned),
                                                mesh->element_count);
    if (!positions || !indices) {
        rtcReleaseGeometry(geometry);
        return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "Embree: out of memory for %zu elements",
                        mesh->element_count);
    }
    for (size_t i = 0; i < mesh->vertex_count; ++i)
        rad_ray_frame_point(&rays->frame, mesh->vertices[i], positions + 3 * i);
    for (size_t e = 0; e < mesh->element_count; ++e) {
        const uint32_t *c = mesh->element_vertices[e];
        int corners = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < 4; ++k) indices[4 * e + k] = c[k < corners ? k : corners - 1];
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(rays->scene, geometry);
    rtcReleaseGeometry(geometry);
    return RAD_OK;
}

rad_status rad_element_rays_create(rad_context *ctx, const rad_mesh *mesh, rad_element_rays **out) {
    return rad_element_rays_create_with(ctx, mesh, 1, out);
}

rad_status rad_element_rays_create_with(rad_context *ctx, const rad_mesh *mesh, int robust,
                                          rad_element_rays **out) {
    *out = NULL;
    rad_element_rays *rays = rad_alloc_zero(ctx, 1, sizeof *rays);
    if (!rays) return RAD_ERROR_NO_MEMORY;
    rays->ctx = ctx;
    rays->mesh = mesh;
    rad_status status = rad_embree_open(ctx, &rays->device, &rays->scene);
    if (status) {
        rad_element_rays_destroy(rays);
        return status;
    }
    if (!robust) rtcSetSceneFlags(rays->scene, RTC_SCENE_FLAG_NONE);
    rad_vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < mesh->vertex_count; ++i) {
        rad_vec3 p = mesh->vertices[i];
        lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    rays->frame = rad_ray_frame_of_box(lo, hi);
    status = add_elements(rays);
    if (status) {
        rad_element_rays_destroy(rays);
        return status;
    }
    rtcCommitScene(rays->scene);
    if (rtcGetDeviceError(rays->device) != RTC_ERROR_NONE) {
        rad_element_rays_destroy(rays);
        return RAD_ERROR_INTERNAL;
    }
    double diagonal = mesh->vertex_count ? v3_length(v3_sub(hi, lo)) : 1;
    /* Larger than float rounding in the frame, small against the scene's features. */
    rays->epsilon = diagonal * 1e-5;
    *out = rays;
    return RAD_OK;
}

int rad_element_rays_intersect(const rad_element_rays *rays, rad_vec3 origin, rad_vec3 direction,
                               double tnear, double tfar, rad_element_hit *hit) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRayHit rh;
    double to_caller = rad_ray_frame_ray(&rays->frame, &rh.ray, origin, direction, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rays->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    hit->t = rh.ray.tfar * to_caller;
    hit->element = rh.hit.primID;
    hit->u = rh.hit.u;
    hit->v = rh.hit.v;
    /* Embree's Ng is (e1 x e2) for counter-clockwise corners: the front normal. */
    hit->front = (double)rh.hit.Ng_x * direction.x + (double)rh.hit.Ng_y * direction.y +
                     (double)rh.hit.Ng_z * direction.z < 0;
    return 1;
}

int rad_element_rays_occluded(const rad_element_rays *rays, rad_vec3 a, rad_vec3 b) {
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

void rad_element_rays_intersect16(const rad_element_rays *rays, rad_vec3 origin, const rad_vec3 *direction,
                                  int n, double tnear, rad_element_hit *hit) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTC_ALIGN(64) struct RTCRayHit16 rh;
    RTC_ALIGN(64) int valid[16];
    double to_caller[16];
    for (int i = 0; i < 16; ++i) {
        valid[i] = i < n ? -1 : 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        if (i < n)
            to_caller[i] = rad_ray_frame_lane(&rays->frame, &rh.ray, i, origin, direction[i], tnear, INFINITY);
        else
            rad_ray16_empty_lane(&rh.ray, i);
    }
    rtcIntersect16(valid, rays->scene, &context, &rh);
    for (int i = 0; i < n; ++i) {
        rad_element_hit *h = &hit[i];
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
            h->element = RAD_NO_ELEMENT;
            continue;
        }
        h->t = rh.ray.tfar[i] * to_caller[i];
        h->element = rh.hit.primID[i];
        h->u = rh.hit.u[i];
        h->v = rh.hit.v[i];
        h->front = (double)rh.hit.Ng_x[i] * direction[i].x + (double)rh.hit.Ng_y[i] * direction[i].y +
                       (double)rh.hit.Ng_z[i] * direction[i].z < 0;
    }
}

void rad_element_rays_occluded16(const rad_element_rays *rays, rad_vec3 a, const rad_vec3 *b, int n,
                                 int *occluded) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTC_ALIGN(64) struct RTCRay16 ray;
    RTC_ALIGN(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
        rad_vec3 d = i < n ? v3_sub(b[i], a) : v3(0, 0, 0);
        double length = v3_length(d);
        valid[i] = i < n && length > 2 * rays->epsilon ? -1 : 0;
        if (valid[i])
            rad_ray_frame_lane(&rays->frame, &ray, i, a, d, rays->epsilon / length, 1 - rays->epsilon / length);
        else
            rad_ray16_empty_lane(&ray, i);
    }
    rtcOccluded16(valid, rays->scene, &context, &ray);
    for (int i = 0; i < n; ++i) occluded[i] = valid[i] && ray.tfar[i] < 0;
}

rad_vec3 rad_element_point(const rad_mesh *mesh, uint32_t element, double u, double v) {
    const uint32_t *c = mesh->element_vertices[element];
    const rad_vec3 *p = mesh->vertices;
    if (rad_mesh_corner_count(mesh, element) == 3)
        return v3_add(p[c[0]], v3_add(v3_scale(v3_sub(p[c[1]], p[c[0]]), u),
                                      v3_scale(v3_sub(p[c[2]], p[c[0]]), v)));
    /* Embree's two triangles: (v0, v1, v3) below the diagonal, (v2, v3, v1) above it. */
    if (u + v <= 1)
        return v3_add(p[c[0]], v3_add(v3_scale(v3_sub(p[c[1]], p[c[0]]), u),
                                      v3_scale(v3_sub(p[c[3]], p[c[0]]), v)));
    return v3_add(p[c[2]], v3_add(v3_scale(v3_sub(p[c[3]], p[c[2]]), 1 - u),
                                  v3_scale(v3_sub(p[c[1]], p[c[2]]), 1 - v)));
}
