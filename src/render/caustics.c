/* caustics.c - caustics in the radiosity render from a caustic photon map (Jensen 1996, "Global
 * illumination using photon maps": caustics are drawn from the caustic map at the visible point,
 * not from a coarse solution), docs/specular-first.md, "Caustics in the image".
 *
 * The specular-first pass (system/specular_first.c) lands photons that reached diffuse elements
 * through mirrors and glass (L S+ D paths). Summed per element, they are the deposit that feeds
 * the solve (specular_emission: the light it sends on, L S+ D D..., is in the solution, and the
 * final gather samples the deposit as an emitter). The same photons, kept where they landed, are
 * the caustic map here: at the diffuse point a camera path reaches, the light that came through
 * mirrors and glass is
 *     L_c(x) = rho(x) / pi * E_c(x),   E_c(x) = sum of the k - 1 nearest photons' flux / (pi r_k^2)
 * (Jensen's k nearest, within a largest radius; rho(x) the texture's on textured surfaces), in
 * place of the deposit drawn at element resolution. So each kind of light is counted once: the
 * deposit for the light it sends on, the map for what the camera sees of it. */
#include "render/render.h"

#include <string.h>

/* Measured on cornell-mirror at 128 x 128 against the 4096-spp path trace (the 8x8 blocks over
 * the caustic; docs/specular-first.md): k 16 to 128 and largest radii of 0.25 to 2 element sizes
 * were tried; k 32 within half an element, cone-filtered, keeps the caustic's edge within 4% and
 * its noise on the dim ceiling no worse than the reference's own. */
#define CAUSTIC_NEAREST 32          /* k of the density estimate */
#define CAUSTIC_RADIUS_ELEMENTS 0.5 /* the largest radius, in element sizes (sqrt of mean area) */
#define CAUSTIC_CONE 1.1            /* Jensen's cone filter constant k >= 1 (2001, sec. 7.2) */

rad_status rad_caustics_build(rad_renderer *r) {
    const rad_system *s = r->system;
    rad_photon_map_free(r->ctx, &r->caustics);
    if (!s->caustic_landings || s->caustic_landing_count == 0 || !r->mesh ||
        r->mesh->element_count == 0)
        return RAD_OK;
    /* The largest radius: half an element, finer than the deposit's resolution. */
    double area = 0;
    for (size_t e = 0; e < r->mesh->element_count; ++e) area += r->mesh->element_area[e];
    r->caustic_radius = CAUSTIC_RADIUS_ELEMENTS * sqrt(area / (double)r->mesh->element_count);
    if (!(r->caustic_radius > 0) || !isfinite(r->caustic_radius)) return RAD_OK;
    size_t count = s->caustic_landing_count;
    rad_photon *photons = rad_alloc(r->ctx, count, sizeof *photons);
    if (!photons) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < count; ++i) {
        const rad_caustic_landing *l = &s->caustic_landings[i];
        double power[3] = {l->power[0], l->power[1], l->power[2]};
        photons[i] = rad_photon_pack(l->position, power, v3(l->normal[0], l->normal[1], l->normal[2]),
                                     v3(l->incoming[0], l->incoming[1], l->incoming[2]));
    }
    return rad_photon_map_build(r->ctx, photons, count, r->caustic_radius, rad_thread_count(r->ctx),
                                &r->caustics);
}

/* Irradiance (as radiosity) at x from the caustic map: the k - 1 nearest photons on the same side
 * of the same surface within the largest radius, weighted by the cone filter
 * w = 1 - d / (c r_k) and normalised by pi r_k^2 (1 - 2 / (3 c)); with fewer than k found, the
 * disc is the largest radius. */
static void caustic_irradiance(const rad_renderer *r, rad_vec3 x, rad_vec3 n, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    rad_photon_near nearest[CAUSTIC_NEAREST];
    double r2;
    size_t found = rad_photon_map_nearest_heap(&r->caustics, x, n, r->caustic_radius,
                                               CAUSTIC_NEAREST, nearest, &r2);
    /* Of k found, the k-th (the heap's first) only sets the radius. */
    size_t first = found == CAUSTIC_NEAREST ? 1 : 0;
    if (!(r2 > 0)) return;
    for (size_t i = first; i < found; ++i) {
        const rad_photon *p = nearest[i].photon;
        /* Only light arriving on the front. */
        if (v3_dot(rad_photon_incoming(p), n) <= 0) continue;
        double power[3];
        rad_photon_power(p, 1 - sqrt(nearest[i].distance2 / r2) / CAUSTIC_CONE, power);
        for (int c = 0; c < 3; ++c) out[c] += power[c];
    }
    double norm = RAD_PI * r2 * (1 - 2 / (3 * CAUSTIC_CONE));
    for (int c = 0; c < 3; ++c) out[c] /= norm;
}

void rad_visible_emission(const rad_renderer *r, const rad_element_hit *hit, rad_vec3 x,
                          rad_vec3 n, const float rho[3], double out[3]) {
    if (r->caustics.count == 0) {
        rad_reconstruct_emission(r, hit->element, hit->u, hit->v, out);
        return;
    }
    /* The material's own emission; the caustic from the map, rho(x) / pi E_c(x), in place of the
     * deposit (which stays in the solution for the light it sends on). */
    const double *own = rad_renderer_material(r, hit->element)->emission;
    double e[3];
    caustic_irradiance(r, x, n, e);
    for (int c = 0; c < 3; ++c)
        out[c] = fmin(own[c], r->element_emission[hit->element][c]) + fmax(0.0, rho[c]) / RAD_PI * e[c];
}
