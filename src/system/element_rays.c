/* element_rays.c - Embree scene of the element mesh (see element_rays.h). */
#include "system/element_rays.h"

#include "scene/rays.h"

#include <float.h>
#include <stdio.h>

void rad_element_rays_destroy(rad_element_rays *rays) {
    if (!rays) return;
    if (rays->scene) rtcReleaseScene(rays->scene);
    if (rays->device) rtcReleaseDevice(rays->device);
    rad_free(rays->ctx, rays->quads);
    rad_free(rays->ctx, rays->loose);
    rad_free(rays->ctx, rays);
}

/* One Embree quad geometry holding every element: a triangle (v0, v1, v2) goes in as the quad
 * (v0, v1, v2, v2), which Embree documents as the way to mix the two; its hits all fall in the
 * quad's first half (v0, v1, v3), where u and v are the triangle's own. One geometry rather than
 * a quad and a triangle geometry: one BVH to traverse (less processor time on the Cornell render
 * and on Sponza, the same hits on the Cornell box: docs/rendering.md, "One element geometry").
 *
 * Flat convex grids go in as one quad each, before the other elements (rad_grid_quad): the
 * fewer primitives, the shallower the tree and the fewer boxes a ray enters. A grid is taken
 * when its corners lie within GRID_FLAT epsilons of one plane (its elements then lie in it too:
 * a bilinear map of a flat quad is flat), it turns the same way at every corner, and it holds
 * more than one element. */
#define GRID_FLAT 1e-3

static double cross2(const double a[2], const double b[2]) { return a[0] * b[1] - a[1] * b[0]; }

/* The grid's quad, or 0 when it is not flat and convex (or holds one element). */
static int grid_quad_make(const rad_mesh *mesh, const rad_mesh_grid *grid, double epsilon,
                          rad_grid_quad *out) {
    if ((uint64_t)grid->nu * grid->nv < 2) return 0;
    rad_vec3 c[4];
    for (int k = 0; k < 4; ++k) c[k] = mesh->vertices[grid->corner[k]];
    rad_vec3 normal = v3_cross(v3_sub(c[2], c[0]), v3_sub(c[3], c[1]));
    if (!(v3_length(normal) > 0)) return 0;
    normal = v3_normalize(normal);
    rad_vec3 centre = v3_scale(v3_add(v3_add(c[0], c[1]), v3_add(c[2], c[3])), 0.25);
    for (int k = 0; k < 4; ++k) {
        if (!(fabs(v3_dot(normal, v3_sub(c[k], centre))) <= GRID_FLAT * epsilon)) return 0;
        rad_vec3 in = v3_sub(c[k], c[(k + 3) % 4]), next = v3_sub(c[(k + 1) % 4], c[k]);
        if (!(v3_dot(v3_cross(in, next), normal) > 0)) return 0;
    }
    rad_vec3 axis_x = v3_normalize(v3_sub(c[1], c[0])), axis_y = v3_cross(normal, axis_x);
    double p[4][2];
    for (int k = 0; k < 4; ++k) {
        rad_vec3 d = v3_sub(c[k], c[0]);
        p[k][0] = v3_dot(d, axis_x);
        p[k][1] = v3_dot(d, axis_y);
    }
    for (int a = 0; a < 2; ++a) {
        out->e[a] = p[1][a];
        out->f[a] = p[3][a];
        out->c2[a] = p[2][a];
        out->g[a] = p[2][a] - p[1][a] - p[3][a];
    }
    out->ef = cross2(out->e, out->f);
    out->gf = cross2(out->g, out->f);
    /* A parallelogram, to rounding: Embree's u, v on the quad are the grid's own s, t. */
    double size = fabs(out->e[0]) + fabs(out->e[1]) + fabs(out->f[0]) + fabs(out->f[1]);
    out->affine = fabs(out->g[0]) + fabs(out->g[1]) <= 1e-9 * size;
    out->grid = grid;
    return 1;
}

/* Where on a grid's element Embree's hit of the grid's quad at (u, v) is: the element, and the
 * point's coordinates in the element's own bilinear map (the grid's cell (s nu - i, t nv - j),
 * s, t the point's coordinates in the grid's map). On a parallelogram those are Embree's u, v
 * of the element's two triangles (rad_element_point); on another flat quad (the Cornell floor's
 * pieces beside the rotated blocks) they differ from them as the quad from a parallelogram: a
 * parametrisation as good for interpolating the element's corners, continuous from one element
 * to the next. Rounding (or a degenerate quad's NaN) is clamped into the grid. */
static void grid_locate(const rad_grid_quad *q, double u, double v, rad_element_hit *hit) {
    double s = u, t = v;
    if (!q->affine) {
        /* The point in the plane: Embree's triangles (0, 1, 3) and (2, 3, 1) of the quad. */
        double h[2];
        for (int a = 0; a < 2; ++a)
            h[a] = u + v <= 1 ? u * q->e[a] + v * q->f[a]
                              : q->c2[a] + (1 - u) * (q->f[a] - q->c2[a]) +
                                    (1 - v) * (q->e[a] - q->c2[a]);
        /* h = s e + t f + s t g: h - t f is parallel to e + t g, so
         * cross(h, e) + t (cross(h, g) + cross(e, f)) + t^2 cross(g, f) = 0. */
        double k0 = cross2(h, q->e), k1 = cross2(h, q->g) + q->ef, k2 = q->gf;
        /* The root in [0, 1] (the other lies outside a convex quad), from the stable pair. */
        double w = k1 * k1 - 4 * k0 * k2;
        w = sqrt(w > 0 ? w : 0);
        double r = -0.5 * (k1 + (k1 < 0 ? -w : w));
        double t1 = r / k2, t2 = k0 / r;
        double off1 = t1 < 0 ? -t1 : t1 > 1 ? t1 - 1 : 0, off2 = t2 < 0 ? -t2 : t2 > 1 ? t2 - 1 : 0;
        t = off1 <= off2 ? t1 : t2;
        double along[2] = {q->e[0] + t * q->g[0], q->e[1] + t * q->g[1]};
        s = ((h[0] - t * q->f[0]) * along[0] + (h[1] - t * q->f[1]) * along[1]) /
            (along[0] * along[0] + along[1] * along[1]);
    }
    const rad_mesh_grid *g = q->grid;
    double si = s * g->nu, tj = t * g->nv;
    uint32_t i = !(si > 0) ? 0 : si >= g->nu - 1 ? g->nu - 1 : (uint32_t)si;
    uint32_t j = !(tj > 0) ? 0 : tj >= g->nv - 1 ? g->nv - 1 : (uint32_t)tj;
    hit->element = rad_mesh_grid_element(g, i, j);
    si -= i;
    tj -= j;
    hit->u = !(si > 0) ? 0 : si > 1 ? 1 : si;
    hit->v = !(tj > 0) ? 0 : tj > 1 ? 1 : tj;
}

/* The element and u, v of Embree's hit of primitive `primitive` at (u, v). */
static inline void hit_element(const rad_element_rays *rays, unsigned primitive, float u, float v,
                               rad_element_hit *hit) {
    if (primitive < rays->quad_count) {
        grid_locate(&rays->quads[primitive], u, v, hit);
        return;
    }
    hit->element = rays->loose ? rays->loose[primitive - rays->quad_count] : primitive;
    hit->u = u;
    hit->v = v;
}

static rad_status add_elements(rad_element_rays *rays) {
    const rad_mesh *mesh = rays->mesh;
    if (mesh->element_count == 0) return RAD_OK;
    size_t in_grids = 0;
    if (mesh->grid_count) {
        rays->quads = rad_alloc(rays->ctx, mesh->grid_count, sizeof *rays->quads);
        if (!rays->quads)
            return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "out of memory for %zu grids",
                            mesh->grid_count);
        for (size_t g = 0; g < mesh->grid_count; ++g) {
            rad_grid_quad *quad = &rays->quads[rays->quad_count];
            if (grid_quad_make(mesh, &mesh->grids[g], rays->epsilon, quad)) {
                rays->quad_count++;
                in_grids += (size_t)mesh->grids[g].nu * mesh->grids[g].nv;
            }
        }
    }
    size_t loose = mesh->element_count - in_grids, primitives = rays->quad_count + loose;
    if (rays->quad_count) {
        rays->loose = rad_alloc(rays->ctx, loose + 1, sizeof *rays->loose);
        if (!rays->loose)
            return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "out of memory for %zu elements",
                            mesh->element_count);
    }
    RTCGeometry geometry = rtcNewGeometry(rays->device, RTC_GEOMETRY_TYPE_QUAD);
    float *positions = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                               mesh->vertex_count);
    unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                RTC_FORMAT_UINT4, 4 * sizeof(unsigned),
                                                primitives);
    if (!positions || !indices) {
        rtcReleaseGeometry(geometry);
        return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "Embree: out of memory for %zu elements",
                        mesh->element_count);
    }
    for (size_t i = 0; i < mesh->vertex_count; ++i)
        rad_ray_frame_point(&rays->frame, mesh->vertices[i], positions + 3 * i);
    size_t at = 0;
    for (size_t g = 0; g < rays->quad_count; ++g, ++at)
        for (int k = 0; k < 4; ++k) indices[4 * at + k] = rays->quads[g].grid->corner[k];
    /* The other elements, in order: the grids' elements are runs, grids in mesh order. */
    size_t next = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        if (next < rays->quad_count && e == rays->quads[next].grid->first) {
            e += (size_t)rays->quads[next].grid->nu * rays->quads[next].grid->nv - 1;
            ++next;
            continue;
        }
        if (rays->loose) rays->loose[at - rays->quad_count] = (uint32_t)e;
        const uint32_t *c = mesh->element_vertices[e];
        int corners = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < 4; ++k) indices[4 * at + k] = c[k < corners ? k : corners - 1];
        ++at;
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
    double diagonal = mesh->vertex_count ? v3_length(v3_sub(hi, lo)) : 1;
    /* Larger than float rounding in the frame, small against the scene's features. */
    rays->epsilon = diagonal * 1e-5;
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
    hit_element(rays, rh.hit.primID, rh.hit.u, rh.hit.v, hit);
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
        hit_element(rays, rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i], h);
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
