/* lights_direct.c - the light pre-pass of a geometric system (system.h): the point, spot and
 * directional lights and the sky shoot first, straight onto the elements, and what each element
 * reflects of it becomes part of its emitted radiosity (light_emission, added to emission). Every
 * solver then starts from it as it starts from the emitting surfaces' light (docs/lights.md).
 *
 *   point, spot  the exact point-to-element factor: the element's solid angle Omega seen from
 *                the light (Van Oosterom & Strackee 1983, per triangle), so the flux it
 *                receives is I(w) Omega and its mean irradiance I(w) Omega / A (w towards its
 *                centroid: exact for a point light, the cone or IES profile taken at the
 *                centroid), times the fraction of sample points on the element that see the
 *                light (Embree shadow rays);
 *   directional  E_perp cos(theta) times the fraction of sample points whose ray towards the
 *                light escapes the scene;
 *   sky          E = integral L_sky(w) V(w) cos dw by `samples` cosine-distributed rays from
 *                points spread over the element: E ~ pi mean L_sky over the rays that escape.
 * Each element's light is rho E_direct. */
#include "system/system.h"

#include "core/rng.h"
#include "mesh/mesh.h"
#include "scene/rays.h"
#include "scene/scene.h"

#include <omp.h>
#include <string.h>

/* Points on the element for the visibility tests: the centroid and the midpoints between it
 * and each corner. */
static int visibility_points(const rad_mesh *mesh, size_t e, rad_vec3 *points) {
    int corners = rad_mesh_corner_count(mesh, e);
    rad_vec3 c = mesh->element_centroid[e];
    points[0] = c;
    for (int k = 0; k < corners; ++k)
        points[1 + k] = v3_lerp(c, mesh->vertices[mesh->element_vertices[e][k]], 0.5);
    return 1 + corners;
}

/* The solid angle of a polygon's front (3 or 4 corners) seen from x (zero from behind). */
static double polygon_solid_angle(const rad_vec3 *corners, int count, rad_vec3 x) {
    double omega = 0;
    for (int k = 1; k + 1 < count; ++k)
        omega += rad_triangle_solid_angle(x, corners[0], corners[k], corners[k + 1]);
    return omega > 0 ? omega : 0;
}

/* A point uniform on a polygon of 3 or 4 corners (a fan triangle by area, then a uniform point
 * on it). */
static rad_vec3 polygon_point(const rad_vec3 *corners, int count, rad_rng *rng) {
    rad_vec3 a = corners[0], b = corners[1], c = corners[2];
    if (count == 4) {
        rad_vec3 d = corners[3];
        double first = v3_length(v3_cross(v3_sub(b, a), v3_sub(c, a)));
        double second = v3_length(v3_cross(v3_sub(c, a), v3_sub(d, a)));
        if (rad_rng_uniform(rng) * (first + second) >= first) {
            b = c;
            c = d;
        }
    }
    double s = sqrt(rad_rng_uniform(rng)), t = rad_rng_uniform(rng);
    return v3_add(a, v3_add(v3_scale(v3_sub(b, a), s * (1 - t)), v3_scale(v3_sub(c, a), s * t)));
}

/* Irradiance E_direct of a polygon (corners, normal n, centroid, area) from the point, spot
 * and directional lights, with visibility from `points`. With `spread`, the largest difference
 * between the irradiance at two of the points (of the largest channel, visibility and the
 * point-to-point factor included). */
static void lights_irradiance(const rad_rays *rays, const rad_scene *scene, const rad_vec3 *corners,
                              int count, rad_vec3 n, rad_vec3 centroid, double area,
                              const rad_vec3 *points, int point_count, double out[3],
                              double *spread) {
    double at_point[16] = {0};
    for (size_t i = 0; i < scene->light_count; ++i) {
        const rad_light *light = &scene->lights[i];
        rad_light_arrival arrival;
        if (!rad_light_arrive(light, centroid, &arrival)) continue;
        double factor; /* mean irradiance over the element per unit of arrival.irradiance */
        if (light->kind == RAD_LIGHT_DIRECTIONAL) {
            factor = v3_dot(n, arrival.direction);
        } else {
            /* I Omega / A, and arrival.irradiance is I / r^2 at the centroid. */
            factor = area > 0 ? polygon_solid_angle(corners, count, light->position) / area *
                                    arrival.distance * arrival.distance
                              : 0;
            if (v3_dot(n, arrival.direction) <= 0) factor = 0;
        }
        if (!(factor > 0)) continue;
        int seen = 0;
        double brightest = fmax(arrival.irradiance[0], fmax(arrival.irradiance[1], arrival.irradiance[2]));
        for (int k = 0; k < point_count; ++k) {
            int visible;
            if (light->kind == RAD_LIGHT_DIRECTIONAL) {
                rad_hit hit;
                visible = !rad_rays_intersect(rays, points[k], arrival.direction, rays->epsilon,
                                              INFINITY, &hit);
                if (visible && spread) at_point[k] += brightest * factor;
            } else {
                visible = !rad_rays_occluded(rays, points[k], light->position);
                rad_light_arrival here;
                if (visible && spread && rad_light_arrive(light, points[k], &here))
                    at_point[k] += fmax(0, v3_dot(n, here.direction)) *
                                   fmax(here.irradiance[0], fmax(here.irradiance[1], here.irradiance[2]));
            }
            seen += visible;
        }
        factor *= (double)seen / point_count;
        for (int c = 0; c < 3; ++c) out[c] += arrival.irradiance[c] * factor;
    }
    if (spread) {
        double lo = INFINITY, hi = 0;
        for (int k = 0; k < point_count; ++k) lo = fmin(lo, at_point[k]), hi = fmax(hi, at_point[k]);
        *spread = point_count ? hi - lo : 0;
    }
}

/* Corners of quarter q of a polygon: a quad's 2 x 2 cells in its bilinear parameters, a
 * triangle's four midpoint triangles (the corners' three, then the middle one). */
static int polygon_quarter(const rad_vec3 *c, int count, int q, rad_vec3 *out) {
    if (count == 4) {
        double u0 = 0.5 * (q & 1), v0 = 0.5 * (q >> 1);
        for (int k = 0; k < 4; ++k) {
            double u = u0 + 0.5 * (k == 1 || k == 2), v = v0 + 0.5 * (k >= 2);
            out[k] = v3_lerp(v3_lerp(c[0], c[1], u), v3_lerp(c[3], c[2], u), v);
        }
        return 4;
    }
    rad_vec3 m01 = v3_lerp(c[0], c[1], 0.5), m12 = v3_lerp(c[1], c[2], 0.5), m20 = v3_lerp(c[2], c[0], 0.5);
    const rad_vec3 t[4][3] = {{c[0], m01, m20}, {m01, c[1], m12}, {m20, m12, c[2]}, {m12, m20, m01}};
    for (int k = 0; k < 3; ++k) out[k] = t[q][k];
    return 3;
}

/* Irradiance from the sky, added to out: E = integral L_sky(w) V(w) cos dw by sky->samples
 * cosine-distributed rays, stratified on an m x m grid, from points spread over the polygon.
 * With `spread`, ray i starts in quarter i % 4 and *spread is the largest difference between
 * the quarters' estimates (largest channel) less twice the noise of a quarter's estimate, pi
 * L_max / sqrt(samples): a shadow edge or the rim of an opening, not the sampling noise. */
static void sky_irradiance(const rad_rays *rays, const rad_sky *sky, const rad_vec3 *corners,
                           int count, rad_vec3 n, rad_rng rng, double out[3], double *spread) {
    if (spread) *spread = 0;
    if (sky->kind == RAD_SKY_OFF || sky->samples <= 0) return;
    rad_vec3 t, b, quarter[4][4];
    int quarter_count[4] = {0, 0, 0, 0};
    if (spread)
        for (int q = 0; q < 4; ++q) quarter_count[q] = polygon_quarter(corners, count, q, quarter[q]);
    v3_basis(n, &t, &b);
    double sum[3] = {0, 0, 0}, quarter_sum[4] = {0, 0, 0, 0}, brightest = 0;
    int m = (int)ceil(sqrt((double)sky->samples));
    for (int i = 0; i < sky->samples; ++i) {
        /* Cosine-distributed, stratified on an m x m grid. */
        double u0 = ((double)(i % m) + rad_rng_uniform(&rng)) / m;
        double u1 = ((double)((i / m) % m) + rad_rng_uniform(&rng)) / m;
        double radius = sqrt(u0), phi = 2 * RAD_PI * u1;
        rad_vec3 w = v3_normalize(v3_add(v3_add(v3_scale(t, radius * cos(phi)),
                                                v3_scale(b, radius * sin(phi))),
                                         v3_scale(n, sqrt(fmax(0.0, 1 - u0)))));
        double radiance[3];
        rad_sky_radiance(sky, w, radiance);
        if (!(radiance[0] > 0 || radiance[1] > 0 || radiance[2] > 0)) continue;
        double most = fmax(radiance[0], fmax(radiance[1], radiance[2]));
        brightest = fmax(brightest, most);
        rad_vec3 from = spread ? polygon_point(quarter[i % 4], quarter_count[i % 4], &rng)
                               : polygon_point(corners, count, &rng);
        rad_hit hit;
        if (rad_rays_intersect(rays, from, w, rays->epsilon, INFINITY, &hit)) continue;
        for (int c = 0; c < 3; ++c) sum[c] += radiance[c];
        quarter_sum[i % 4] += most;
    }
    for (int c = 0; c < 3; ++c) out[c] += RAD_PI * sum[c] / sky->samples;
    if (spread && sky->samples >= 4) {
        double lo = INFINITY, hi = 0;
        for (int q = 0; q < 4; ++q) {
            int rays_in = (sky->samples - q + 3) / 4;
            double e = RAD_PI * quarter_sum[q] / rays_in;
            lo = fmin(lo, e);
            hi = fmax(hi, e);
        }
        *spread = fmax(0, hi - lo - 2 * RAD_PI * brightest / sqrt((double)sky->samples));
    }
}

/* Irradiance E_direct of element e. */
static void element_irradiance(const rad_mesh *mesh, const rad_rays *rays, const rad_scene *scene,
                               size_t e, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    rad_vec3 n = mesh->element_normal[e], centroid = mesh->element_centroid[e];
    double area = mesh->element_area[e];
    rad_vec3 points[5], corners[4];
    int point_count = visibility_points(mesh, e, points), count = rad_mesh_corner_count(mesh, e);
    for (int k = 0; k < count; ++k) corners[k] = mesh->vertices[mesh->element_vertices[e][k]];
    lights_irradiance(rays, scene, corners, count, n, centroid, area, points, point_count, out, NULL);
    sky_irradiance(rays, &scene->sky, corners, count, n, rad_rng_make(0x736b79u, e), out, NULL);
}

void rad_lights_polygon_irradiance(const rad_scene *scene, const rad_rays *rays,
                                   const rad_vec3 *corners, int count, rad_vec3 normal,
                                   uint64_t stream, double out[3], double *spread) {
    out[0] = out[1] = out[2] = 0;
    rad_vec3 centroid = v3(0, 0, 0), points[16];
    for (int k = 0; k < count; ++k) centroid = v3_add(centroid, v3_scale(corners[k], 1.0 / count));
    double area = count == 3
                      ? 0.5 * v3_length(v3_cross(v3_sub(corners[1], corners[0]), v3_sub(corners[2], corners[0])))
                      : 0.5 * v3_length(v3_cross(v3_sub(corners[2], corners[0]), v3_sub(corners[3], corners[1])));
    /* Visibility from the centres of its 16 sixteenths (quarters of quarters): a node's shadow
     * edges are found where five points (the elements' rule) would step over them. */
    for (int q = 0; q < 4; ++q) {
        rad_vec3 quarter[4], sixteenth[4];
        int quarter_count = polygon_quarter(corners, count, q, quarter);
        for (int r = 0; r < 4; ++r) {
            int n = polygon_quarter(quarter, quarter_count, r, sixteenth);
            rad_vec3 centre = v3(0, 0, 0);
            for (int k = 0; k < n; ++k) centre = v3_add(centre, v3_scale(sixteenth[k], 1.0 / n));
            points[4 * q + r] = centre;
        }
    }
    double lights_spread = 0, sky_spread = 0;
    lights_irradiance(rays, scene, corners, count, normal, centroid, area, points, 16, out,
                      &lights_spread);
    sky_irradiance(rays, &scene->sky, corners, count, normal, rad_rng_make(0x736b79u, stream), out,
                   &sky_spread);
    if (spread) *spread = lights_spread + sky_spread;
}

void rad_node_lights_reflected(void *user, uint32_t polygon, const rad_vec3 *corners, int count,
                               uint64_t stream, double out[3], double *spread) {
    const rad_node_lights *lights = user;
    const rad_scene *scene = lights->scene;
    const rad_rays *rays = lights->rays;
    const rad_polygon *p = &scene->polygons[polygon];
    const double *rho = scene->materials[scene->surfaces[p->surface].material].reflectance;
    double irradiance_spread;
    rad_lights_polygon_irradiance(scene, rays, corners, count, rad_polygon_normal(scene, p),
                                  stream, out, &irradiance_spread);
    for (int c = 0; c < 3; ++c) out[c] *= rho[c];
    if (spread) *spread = irradiance_spread * fmax(rho[0], fmax(rho[1], rho[2]));
}

rad_status rad_system_add_light_emission(rad_system *s, const rad_scene *scene) {
    rad_context *ctx = s->ctx;
    const rad_mesh *mesh = s->mesh;
    if (!mesh || (scene->light_count == 0 && scene->sky.kind == RAD_SKY_OFF)) return RAD_OK;
    rad_rays *rays = NULL;
    rad_status status = rad_rays_create(ctx, scene, &rays);
    if (status) return status;
    rad_free(ctx, s->light_emission);
    s->light_emission = rad_alloc_zero(ctx, s->element_count, sizeof *s->light_emission);
    if (!s->light_emission) {
        rad_rays_destroy(rays);
        return RAD_ERROR_NO_MEMORY;
    }
    long count = (long)s->element_count;
#pragma omp parallel for schedule(dynamic, 64) num_threads(rad_thread_count(ctx))
    for (long e = 0; e < count; ++e) {
        double irradiance[3];
        element_irradiance(mesh, rays, scene, (size_t)e, irradiance);
        for (int c = 0; c < 3; ++c) {
            s->light_emission[e][c] = s->reflectance[e][c] * irradiance[c];
            s->emission[e][c] += s->light_emission[e][c];
        }
    }
    rad_rays_destroy(rays);
    return RAD_OK;
}
