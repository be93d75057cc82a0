/* second_pass.c - the ray-traced second pass: what radiosity cannot show.
 *
 * Radiosity is view independent and diffuse only. Wallace, Cohen & Greenberg 1987 ("A two-pass
 * solution to the rendering equation: a synthesis of ray tracing and radiosity methods") add the
 * view-dependent part in a second pass: rays from the eye that meet a mirror or glass follow the
 * specular bounce, and where they land on a diffuse surface they take its radiance from the
 * radiosity solution (the first pass).
 *
 * Here a camera (or gather) ray is followed through
 *   - perfect mirrors: the reflected ray, weighted by the specular tint; a diffuse part of the
 *     mirror material is taken from the solution, like any diffuse surface;
 *   - glass and rough mirrors: one direction drawn from the BSDF (render/bsdf.h, shared with the
 *     path tracer): Fresnel reflection or refraction, or a GGX lobe;
 * for at most max_depth bounces, until it lands on a diffuse surface (radiance from the solution,
 * or a final gather there when asked for), leaves the scene (black) or hits the back of a
 * one-sided surface (black: surfaces reflect from their front only, as in the solution).
 *
 * What this cannot show (docs/rendering.md): light that reaches a diffuse surface by way of a
 * mirror or through glass (caustics, and the brightening next to the mirror), because the first
 * pass treats mirrors and glass as what their diffuse part says: absorbers that cast shadows.
 * The final gather leaves them out too: its gather rays could find an emitter through a mirror
 * or the glass, but a few rays per pixel would only scatter bright specks over the image. */
#include "render/render.h"

#include "render/bsdf.h"


static double largest3(const double c[3]) { return fmax(c[0], fmax(c[1], c[2])); }

/* The solution's radiance at a hit. Camera paths take it whole. Gather rays take the reflected
 * part (B - E) / pi, and the emitted part only at their first hit, weighted against the emitter
 * samples of the final gather; emitted light a gather ray finds behind a mirror or through glass
 * is a caustic, which the first pass does not carry either (see above), and is left out. */
static void solution_radiance(const rad_renderer *r, const rad_element_hit *hit,
                              const rad_gather_origin *gather, int depth, rad_vec3 direction,
                              double out[3]) {
    rad_reconstruct_radiance(r, hit->element, hit->u, hit->v, out);
    if (!gather) return;
    const float *emitted = r->element_emission[hit->element];
    if (!(emitted[0] > 0 || emitted[1] > 0 || emitted[2] > 0)) return;
    double weight = depth == 0 ? rad_gather_emission_weight(r, gather, direction, hit) : 0;
    for (int c = 0; c < 3; ++c) out[c] = fmax(0.0, out[c] - emitted[c]) + weight * emitted[c];
}

void rad_trace_radiance(const rad_renderer *r, rad_sample *sample, rad_vec3 origin,
                        rad_vec3 direction, const rad_gather_origin *gather, double out[3]) {
    rad_ray_counts *counts = sample->counts;
    out[0] = out[1] = out[2] = 0;
    double throughput[3] = {1, 1, 1};
    double tnear = gather ? r->rays->epsilon : 0;
    for (int depth = 0;; ++depth) {
        if (depth > 0) counts->specular++;
        else if (gather) counts->gather++;
        else counts->camera++;
        rad_element_hit hit;
        if (!rad_element_rays_intersect(r->rays, origin, direction, tnear, INFINITY, &hit)) return;
        const rad_material *material = rad_renderer_material(r, hit.element);
        rad_vec3 x = v3_add(origin, v3_scale(direction, hit.t));
        rad_vec3 normal = r->mesh->element_normal[hit.element];

        if (material->kind == RAD_MATERIAL_DIFFUSE) {
            if (!hit.front) return;
            double radiance[3];
            if (!gather && r->settings.final_gather > 0)
                rad_final_gather(r, sample, &hit, x, normal, radiance);
            else solution_radiance(r, &hit, gather, depth, direction, radiance);
            for (int c = 0; c < 3; ++c) out[c] += throughput[c] * radiance[c];
            return;
        }
        if (depth >= r->settings.max_depth) return;
        rad_vec3 wo = v3_scale(direction, -1);
        if (material->kind == RAD_MATERIAL_MIRROR && material->roughness <= 0) {
            if (!hit.front) return;
            /* The diffuse part from the solution, the mirror part traced. */
            if (largest3(material->reflectance) > 0) {
                double radiance[3];
                solution_radiance(r, &hit, gather, depth, direction, radiance);
                for (int c = 0; c < 3; ++c) out[c] += throughput[c] * radiance[c];
            }
            for (int c = 0; c < 3; ++c) throughput[c] *= fmax(0.0, material->specular[c]);
            direction = rad_reflect(wo, normal);
        } else {
            /* Glass, rough mirrors: one sample of the whole BSDF. */
            double u[3] = {rad_rng_uniform(&sample->rng), rad_rng_uniform(&sample->rng),
                         rad_rng_uniform(&sample->rng)};
            rad_bsdf_sample sample;
            if (rad_bsdf_sample_direction(material, normal, wo, u, &sample) == RAD_LOBE_NONE) return;
            for (int c = 0; c < 3; ++c) throughput[c] *= sample.weight[c];
            direction = sample.direction;
        }
        if (!(largest3(throughput) > 0)) return;
        origin = x;
        tnear = r->rays->epsilon;
    }
}
