/* lights_next_event.c - the lights' next-event estimation (lights_next_event.h). */
#include "render/lights_next_event.h"

void rad_lights_next_event(const rad_tracer *t, const rad_material *m, rad_vec3 x,
                           rad_vec3 normal, rad_vec3 wo, const double throughput[3],
                           uint64_t *rays, double out[3]) {
    for (size_t i = 0; i < t->scene->light_count; ++i) {
        const rad_light *light = &t->scene->lights[i];
        rad_light_arrival arrival;
        double f[3], bsdf_pdf;
        if (!rad_light_arrive(light, x, &arrival) ||
            !rad_bsdf_eval(m, normal, wo, arrival.direction, f, &bsdf_pdf))
            continue;
        ++*rays;
        rad_hit blocker;
        if (isinf(arrival.distance)
                ? rad_rays_intersect(t->rays, x, arrival.direction, t->rays->epsilon, INFINITY,
                                     &blocker)
                : rad_rays_occluded(t->rays, x, light->position))
            continue;
        double cos_surface = fabs(v3_dot(arrival.direction, normal));
        for (int c = 0; c < 3; ++c) out[c] += throughput[c] * f[c] * arrival.irradiance[c] * cos_surface;
    }
}
