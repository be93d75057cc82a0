/* photon_path.c - one photon from the emitters through the scene (photon_path.h). */
#include "scene/photon_path.h"

#include "core/sampler.h"
#include "scene/texture.h"

#include <math.h>

int rad_photon_path_trace(const rad_photon_scene *scene, uint64_t seed, uint64_t index,
                          int specular_only, int max_bounces, rad_photon_visit visit, void *user,
                          uint64_t *rays) {
    const rad_light_emission *sources = scene->sources;
    if (!(sources->total_power > 0)) return 1;
    rad_sampler sampler = rad_sampler_make(seed, index);
    double u[4];
    rad_sampler_4d(&sampler, u);
    /* Emitted by power from one of the sources, with its flux over the density of the choice,
     * before dividing by the photon count. */
    rad_vec3 origin, direction;
    rad_photon_arrival a;
    if (!rad_light_emission_sample(sources, u, &origin, &direction, a.power)) return 1;
    a.specular_path = 1;
    for (int bounce = 0; bounce < max_bounces; ++bounce) {
        /* The next surface; none, or the back of a one-sided one, absorbs it. */
        ++*rays;
        rad_hit hit;
        if (!rad_rays_intersect(scene->rays, origin, direction, scene->rays->epsilon, INFINITY, &hit))
            break;
        const rad_material *m = scene->polygon_material[hit.polygon];
        if (!hit.front && m->kind != RAD_MATERIAL_GLASS) break;
        rad_vec3 x = v3_add(origin, v3_scale(direction, hit.t));
        rad_material textured;
        m = rad_scene_material_at(scene->scene, m, hit.polygon, x, &textured);
        rad_vec3 wi = v3_scale(direction, -1);
        if (rad_bsdf_has_smooth_lobe(m)) {
            a.origin = origin;
            a.direction = direction;
            a.position = x;
            a.hit = hit;
            a.material = m;
            a.bounce = bounce;
            if (!visit(user, &a)) return 0;
        }
        /* Scatter: the BSDF is symmetric, so sampling it from wi gives the outgoing direction
         * and the flux weight f |cos_out| / pdf. */
        rad_sampler_4d(&sampler, u);
        rad_bsdf_sample s;
        if (rad_bsdf_sample_direction(m, hit.normal, wi, u, &s) == RAD_LOBE_NONE) break;
        if (specular_only && !s.delta) break;
        if (s.lobe == RAD_LOBE_TRANSMISSION) /* flux does not scale by eta^2 as radiance does */
            for (int c = 0; c < 3; ++c) s.weight[c] = fmax(0, m->specular[c]);
        a.specular_path = a.specular_path && s.delta;
        /* Russian roulette: survive with the largest weight (at most 1). */
        double q = fmin(1, fmax(s.weight[0], fmax(s.weight[1], s.weight[2])));
        if (!(u[3] < q)) break;
        for (int c = 0; c < 3; ++c) a.power[c] *= s.weight[c] / q;
        origin = x;
        direction = s.direction;
    }
    return 1;
}
