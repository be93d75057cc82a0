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
 *   - glass and rough mirrors: one direction drawn from the BSDF (scene/bsdf.h, shared with the
 *     path tracer): Fresnel reflection or refraction, or a GGX lobe; at glossy points camera
 *     paths also sample the emitters, combined with the BSDF sample by multiple importance
 *     sampling (the glossy highlight of a light would otherwise be specks);
 * for at most max_depth bounces, until it lands on a diffuse surface (radiance from the solution,
 * or a final gather there when asked for), leaves the scene (the sky's radiance, black without
 * one) or hits the back of a
 * one-sided surface (black: surfaces reflect from their front only, as in the solution).
 *
 * Light that reaches a diffuse surface by way of a mirror or through glass (caustics, and the
 * brightening next to the mirror) comes from the first pass: the specular-first pass
 * (system/specular_first.c, docs/specular-first.md) makes it the emission of the element it
 * lands on. The solver itself treats mirrors and glass as what their diffuse part says:
 * absorbers that cast shadows. The final gather leaves it out here: its gather rays could find
 * a lamp through a mirror or the glass, but a few rays per pixel would only scatter bright
 * specks over the image (and count the deposit twice). What they find behind a mirror or the
 * glass on a diffuse surface, a deposit included, they take (D S+ D light at the pixel). */
#include "render/render.h"

#include "scene/bsdf.h"


static double largest3(const double c[3]) { return fmax(c[0], fmax(c[1], c[2])); }

/* The solution's radiance at a hit. Camera paths take it whole. Gather rays take the reflected
 * part (B - E) / pi, and the emitted part only at their first hit, weighted against the emitter
 * samples of the final gather; a lamp's light a gather ray finds behind a mirror or through
 * glass is a caustic, which the first pass carries (see above), and is left out. */
static void solution_radiance(const rad_renderer *r, const rad_element_hit *hit,
                              const rad_gather_origin *gather, int depth, rad_vec3 direction,
                              rad_vec3 x, double out[3]) {
    /* Camera paths on textured surfaces: the texture times the irradiance (texture_shading.c). */
    if (!gather && rad_texture_shading_radiance(r, hit, x, out)) return;
    if (gather) rad_reconstruct_gather_radiance(r, hit->element, hit->u, hit->v, out);
    else rad_reconstruct_radiance(r, hit->element, hit->u, hit->v, out);
    if (!gather) return;
    const float *emitted = r->element_emission[hit->element];
    if (!(emitted[0] > 0 || emitted[1] > 0 || emitted[2] > 0)) return;
    if (depth > 0) {
        /* Behind a mirror or glass only a lamp's own light is left out: a specular-first
         * deposit there is light on a diffuse surface (L S+ D), and this ray carries it on. */
        const double *lamp = rad_renderer_material(r, hit->element)->emission;
        for (int c = 0; c < 3; ++c) out[c] = fmax(0.0, out[c] - fmin(lamp[c], emitted[c]));
        return;
    }
    double weight = rad_gather_emission_weight(r, gather, direction, hit);
    for (int c = 0; c < 3; ++c) out[c] = fmax(0.0, out[c] - emitted[c]) + weight * emitted[c];
    if (gather->tally)
        for (int c = 0; c < 3; ++c) gather->tally->ray_emitted[c] = weight * emitted[c];
}

/* Light straight from the emitters reflected at a glossy point x towards wo: one emitter sample,
 * weighted against the BSDF sample that continues the path (multiple importance sampling, as
 * the path tracer does at every vertex). Without it, a rough mirror would show the light it
 * reflects only where a BSDF sample happens to hit the emitter: bright specks. */
static void glossy_direct(const rad_renderer *r, const double u[2], const rad_material *material,
                          rad_vec3 x, rad_vec3 normal, rad_vec3 wo, rad_ray_counts *counts,
                          double out[3]) {
    out[0] = out[1] = out[2] = 0;
    rad_emitter_point light;
    /* No receiver front: the weight below against rad_emitter_pdf at the next hit, which does
     * not carry this point's normal, needs the same density. */
    if (!rad_emitter_table_sample(&r->emitters, u[0], u[1], x, v3(0, 0, 0), &light)) return;
    double f[3], pdf_bsdf;
    if (!rad_bsdf_eval(material, normal, wo, light.direction, f, &pdf_bsdf)) return;
    counts->shadow++;
    if (rad_element_rays_occluded(r->rays, x, light.position)) return;
    double cos_x = fabs(v3_dot(normal, light.direction));
    double weight = rad_power_heuristic(light.pdf, pdf_bsdf);
    for (int c = 0; c < 3; ++c) out[c] = f[c] * light.radiance[c] * cos_x / light.pdf * weight;
}

/* Light of the point, spot and directional lights reflected at a glossy point x towards wo:
 * each is one point or direction, sampled exactly with no weight (no BSDF sample finds it), on
 * camera and gather paths alike (without it a rough mirror shows no lamp at all). */
static void glossy_lights(const rad_renderer *r, const rad_material *material, rad_vec3 x,
                          rad_vec3 normal, rad_vec3 wo, rad_ray_counts *counts, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    for (size_t i = 0; i < r->light_count; ++i) {
        rad_light_arrival arrival;
        double f[3], pdf_bsdf;
        if (!rad_light_arrive(&r->lights[i], x, &arrival) ||
            !rad_bsdf_eval(material, normal, wo, arrival.direction, f, &pdf_bsdf) ||
            !rad_light_unblocked(r, i, x, &arrival, counts))
            continue;
        double cos_x = fabs(v3_dot(normal, arrival.direction));
        for (int c = 0; c < 3; ++c) out[c] += f[c] * arrival.irradiance[c] * cos_x;
    }
}

void rad_trace_radiance(const rad_renderer *r, rad_sample *sample, rad_vec3 origin,
                        rad_vec3 direction, const rad_gather_origin *gather, double out[3]) {
    rad_trace_radiance_hit(r, sample, origin, direction, gather, NULL, out);
}

void rad_trace_radiance_hit(const rad_renderer *r, rad_sample *sample, rad_vec3 origin,
                            rad_vec3 direction, const rad_gather_origin *gather,
                            const rad_element_hit *first, double out[3]) {
    rad_ray_counts *counts = sample->counts;
    out[0] = out[1] = out[2] = 0;
    double throughput[3] = {1, 1, 1};
    double tnear = gather ? r->rays->epsilon : 0;
    /* The solid-angle density of the last bounce when it was drawn from a glossy (non-delta)
     * lobe of a camera path, whose emitter sample then shares the emitted light found next. */
    double glossy_pdf = 0;
    for (int depth = 0;; ++depth) {
        if (depth > 0) counts->specular++;
        else if (gather) counts->gather++;
        else counts->camera++;
        rad_element_hit hit;
        int found;
        if (depth == 0 && first) { /* traced already (a packet of gather rays) */
            hit = *first;
            found = hit.element != RAD_NO_ELEMENT;
        } else
            found = rad_element_rays_intersect(gather ? r->inner_rays : r->rays, origin, direction,
                                               tnear, INFINITY, &hit);
        if (depth == 0 && !gather)
            sample->first_polygon = found ? r->mesh->element_polygon[hit.element] : RAD_RENDER_NO_POLYGON;
        if (depth == 0 && gather && gather->tally) {
            gather->tally->rays++;
            if (found && hit.t > 0) gather->tally->inverse_distance += 1 / hit.t;
        }
        if (!found) {
            /* Left the scene: the sky, if there is one (light/lights.h). */
            double sky[3];
            rad_sky_radiance(&r->sky, direction, sky);
            for (int c = 0; c < 3; ++c) out[c] += throughput[c] * sky[c];
            return;
        }
        const rad_material *material = rad_renderer_material(r, hit.element);
        rad_vec3 x = v3_add(origin, v3_scale(direction, hit.t));
        rad_vec3 normal = r->mesh->element_normal[hit.element];

        if (material->kind == RAD_MATERIAL_DIFFUSE) {
            if (!hit.front) return;
            double radiance[3];
            if (!gather && r->settings.final_gather > 0)
                rad_final_gather(r, sample, &hit, x, normal, depth == 0, radiance);
            else if (depth == 0 && rad_gather_is_short(r, gather, &hit)) {
                /* Too near for the solution: gathered again from x, plus the emitted light
                 * weighted as solution_radiance weighs it. */
                rad_gather_short(r, sample, gather, &hit, x, normal, radiance);
                const float *emitted = r->element_emission[hit.element];
                double weight = rad_gather_emission_weight(r, gather, direction, &hit);
                for (int c = 0; c < 3; ++c) radiance[c] += weight * emitted[c];
                if (gather->tally)
                    for (int c = 0; c < 3; ++c) gather->tally->ray_emitted[c] = weight * emitted[c];
            } else solution_radiance(r, &hit, gather, depth, direction, x, radiance);
            const float *emitted = r->element_emission[hit.element];
            if (glossy_pdf > 0 && (emitted[0] > 0 || emitted[1] > 0 || emitted[2] > 0)) {
                double weight = rad_power_heuristic(glossy_pdf, rad_emitter_pdf(r, origin, v3(0, 0, 0), direction, &hit));
                for (int c = 0; c < 3; ++c) radiance[c] -= (1 - weight) * emitted[c];
            }
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
                solution_radiance(r, &hit, gather, depth, direction, x, radiance);
                for (int c = 0; c < 3; ++c) out[c] += throughput[c] * radiance[c];
            }
            for (int c = 0; c < 3; ++c) throughput[c] *= fmax(0.0, material->specular[c]);
            direction = rad_reflect(wo, normal);
            glossy_pdf = 0;
        } else {
            /* Glass, rough mirrors: one sample of the whole BSDF, and on camera paths the light
             * straight from the emitters at glossy points. */
            /* This bounce's numbers: (emitter point, BSDF direction, lobe choice), drawn for the
             * camera sample, or for this gather ray among the pixel's. */
            uint32_t total = gather ? gather->run : sample->count;
            uint32_t point = gather ? gather->ray : sample->index;
            uint32_t dimension = (gather ? RAD_RENDER_DIM_GATHER_BOUNCE + 100 * (uint32_t)gather->level
                                         : RAD_RENDER_DIM_BOUNCE) +
                                 3 * (uint32_t)depth;
            double u_light[2], u_direction[2], u_choice[2];
            rad_sample_2d_at(sample, total, point, dimension, u_light);
            rad_sample_2d_at(sample, total, point, dimension + 1, u_direction);
            rad_sample_2d_at(sample, total, point, dimension + 2, u_choice);
            if (!gather && rad_bsdf_has_smooth_lobe(material)) {
                double direct[3];
                glossy_direct(r, u_light, material, x, normal, wo, counts, direct);
                for (int c = 0; c < 3; ++c) out[c] += throughput[c] * direct[c];
            }
            if (r->light_count && rad_bsdf_has_smooth_lobe(material)) {
                double direct[3];
                glossy_lights(r, material, x, normal, wo, counts, direct);
                for (int c = 0; c < 3; ++c) out[c] += throughput[c] * direct[c];
            }
            double u[3] = {u_choice[0], u_direction[0], u_direction[1]};
            rad_bsdf_sample scatter;
            if (rad_bsdf_sample_direction(material, normal, wo, u, &scatter) == RAD_LOBE_NONE) return;
            for (int c = 0; c < 3; ++c) throughput[c] *= scatter.weight[c];
            direction = scatter.direction;
            glossy_pdf = !gather && !scatter.delta ? scatter.pdf : 0;
        }
        if (!(largest3(throughput) > 0)) return;
        origin = x;
        tnear = r->rays->epsilon;
    }
}
