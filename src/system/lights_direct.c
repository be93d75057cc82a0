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

/* The solid angle of the element's front seen from x (zero from behind). */
static double element_solid_angle(const rad_mesh *mesh, size_t e, rad_vec3 x) {
    const uint32_t *v = mesh->element_vertices[e];
    int corners = rad_mesh_corner_count(mesh, e);
    double omega = 0;
    for (int k = 1; k + 1 < corners; ++k)
        omega += rad_triangle_solid_angle(x, mesh->vertices[v[0]], mesh->vertices[v[k]],
                                          mesh->vertices[v[k + 1]]);
    return omega > 0 ? omega : 0;
}

/* A point uniform on the element (a fan triangle by area, then a uniform point on it). */
static rad_vec3 element_point(const rad_mesh *mesh, size_t e, rad_rng *rng) {
    const uint32_t *v = mesh->element_vertices[e];
    rad_vec3 a = mesh->vertices[v[0]], b = mesh->vertices[v[1]], c = mesh->vertices[v[2]];
    if (rad_mesh_corner_count(mesh, e) == 4) {
        rad_vec3 d = mesh->vertices[v[3]];
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

/* Irradiance E_direct of element e. */
static void element_irradiance(const rad_mesh *mesh, const rad_rays *rays, const rad_scene *scene,
                               size_t e, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    rad_vec3 n = mesh->element_normal[e], centroid = mesh->element_centroid[e];
    double area = mesh->element_area[e];
    rad_vec3 points[5];
    int point_count = visibility_points(mesh, e, points);
    for (size_t i = 0; i < scene->light_count; ++i) {
        const rad_light *light = &scene->lights[i];
        rad_light_arrival arrival;
        if (!rad_light_arrive(light, centroid, &arrival)) continue;
        double factor; /* mean irradiance over the element per unit of arrival.irradiance */
        if (light->kind == RAD_LIGHT_DIRECTIONAL) {
            factor = v3_dot(n, arrival.direction);
        } else {
            /* I Omega / A, and arrival.irradiance is I / r^2 at the centroid. */
            factor = area > 0 ? element_solid_angle(mesh, e, light->position) / area *
                                    arrival.distance * arrival.distance
                              : 0;
            if (v3_dot(n, arrival.direction) <= 0) factor = 0;
        }
        if (!(factor > 0)) continue;
        int seen = 0;
        for (int k = 0; k < point_count; ++k) {
            if (light->kind == RAD_LIGHT_DIRECTIONAL) {
                rad_hit hit;
                seen += !rad_rays_intersect(rays, points[k], arrival.direction, rays->epsilon,
                                            INFINITY, &hit);
            } else {
                seen += !rad_rays_occluded(rays, points[k], light->position);
            }
        }
        factor *= (double)seen / point_count;
        for (int c = 0; c < 3; ++c) out[c] += arrival.irradiance[c] * factor;
    }
    const rad_sky *sky = &scene->sky;
    if (sky->kind != RAD_SKY_OFF && sky->samples > 0) {
        rad_rng rng = rad_rng_make(0x736b79u, e);
        rad_vec3 t, b;
        v3_basis(n, &t, &b);
        double sum[3] = {0, 0, 0};
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
            rad_hit hit;
            if (rad_rays_intersect(rays, element_point(mesh, e, &rng), w, rays->epsilon, INFINITY,
                                   &hit))
                continue;
            for (int c = 0; c < 3; ++c) sum[c] += radiance[c];
        }
        for (int c = 0; c < 3; ++c) out[c] += RAD_PI * sum[c] / sky->samples;
    }
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
