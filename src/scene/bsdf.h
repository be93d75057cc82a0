/* bsdf.h - how a material scatters light: sampling and evaluation shared by the path tracer
 * (render/pathtrace.c), the ray-traced second pass and the photon paths (scene/photon_path.h)
 * of photon mapping and the specular-first pass. Beside the materials, below system/, so the
 * pre-passes of the solution can use it.
 *
 * Lobes, by material kind (scene/scene.h):
 *   DIFFUSE  Lambert, albedo `reflectance`, from the front side only (surfaces are one-sided:
 *            light arriving at the back is absorbed, as in the radiosity solution).
 *   MIRROR   `reflectance` as a Lambert lobe plus a specular lobe tinted by `specular`: a perfect
 *            mirror when roughness is 0, otherwise a GGX microfacet lobe (Walter et al. 2007)
 *            with alpha = roughness^2, sampled by its visible normals (Heitz 2018). Front only.
 *   GLASS    smooth dielectric with index `ior` (outside = the front side, index 1): exact
 *            Fresnel reflection and refraction, total internal reflection, tinted by `specular`;
 *            `reflectance` is ignored. Both sides.
 *
 * Conventions: every direction is unit and points AWAY from the surface point (wo towards the
 * viewer or the previous vertex, wi towards where the light comes from). `normal` is the
 * geometric front normal of the polygon that was hit. f excludes the cosine; weights include it:
 * weight = f * |cos(wi, normal)| / pdf. Radiance crossing a refracting boundary is scaled by
 * (eta_wo / eta_wi)^2 (Veach 1997, sec. 5.2), so a path traced from the camera carries radiance. */
#ifndef RAD_SCENE_BSDF_H
#define RAD_SCENE_BSDF_H

#include "scene/scene.h"

typedef enum rad_lobe {
    RAD_LOBE_NONE = 0,        /* absorbed: no sample */
    RAD_LOBE_DIFFUSE,         /* Lambert */
    RAD_LOBE_GLOSSY,          /* GGX reflection (roughness > 0) */
    RAD_LOBE_SPECULAR,        /* perfect mirror reflection (a delta lobe) */
    RAD_LOBE_TRANSMISSION     /* refraction through glass (a delta lobe) */
} rad_lobe;

typedef struct rad_bsdf_sample {
    rad_vec3 direction; /* wi, unit */
    double weight[3];   /* f * |cos| / pdf, the factor the path throughput is multiplied by */
    double pdf;         /* solid-angle density of the whole BSDF at wi; 0 for a delta lobe */
    rad_lobe lobe;
    int delta;          /* nonzero for the specular and transmission lobes: no light sampling */
} rad_bsdf_sample;

/* Nonzero when the material has only delta lobes (perfect mirror without diffuse part, glass):
 * next-event estimation is useless there. */
int rad_bsdf_is_delta(const rad_material *material);

/* Nonzero when the material has a lobe light sampling can reach (diffuse or glossy). */
int rad_bsdf_has_smooth_lobe(const rad_material *material);

/* Draws wi for the outgoing direction wo from three uniform numbers in [0, 1) (u[0] picks the
 * lobe, u[1], u[2] the direction). Returns the lobe; RAD_LOBE_NONE (weight 0) when the light is
 * absorbed (the back of a one-sided surface, a zero albedo, a microfacet sample under the
 * surface). */
rad_lobe rad_bsdf_sample_direction(const rad_material *material, rad_vec3 normal, rad_vec3 wo,
                                   const double u[3], rad_bsdf_sample *out);

/* The non-delta part of the BSDF for the pair (wo, wi): f[3] (without the cosine) and the
 * solid-angle pdf rad_bsdf_sample_direction would draw wi with. Zero for delta-only materials
 * and for directions on the wrong sides. Returns nonzero when f is nonzero. */
int rad_bsdf_eval(const rad_material *material, rad_vec3 normal, rad_vec3 wo, rad_vec3 wi,
                  double f[3], double *pdf);

/* Exact Fresnel reflectance of a smooth dielectric boundary for unpolarised light, with
 * cos_incident > 0 measured on the side of index eta_incident. 1 under total internal
 * reflection. */
double rad_fresnel_dielectric(double cos_incident, double eta_incident, double eta_transmitted);

/* The Fresnel reflectance F of glass material m seen from wo (unit, away from the surface): the
 * probability rad_bsdf_sample_direction chooses its reflection (1 - F: its refraction). */
double rad_bsdf_glass_reflectance(const rad_material *m, rad_vec3 normal, rad_vec3 wo);

/* A cosine-distributed direction about the unit normal n from two uniform numbers in [0, 1). */
rad_vec3 rad_cosine_direction(rad_vec3 n, double u1, double u2);

/* Mirror reflection of the unit direction w (pointing away) about the unit normal n. */
static inline rad_vec3 rad_reflect(rad_vec3 w, rad_vec3 n) {
    return v3_sub(v3_scale(n, 2 * v3_dot(w, n)), w);
}

#endif
