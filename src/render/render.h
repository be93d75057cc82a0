/* render.h - pictures of a radiosity solution (docs/rendering.md).
 *
 * The renderer shoots camera rays at the element mesh (system/element_rays.h) and turns what
 * they hit into radiance:
 *   reconstruct.c   radiance from the solution at a point: B / pi interpolated from the element
 *                   vertices (smooth) or constant per element (flat), Cohen et al. 1986
 *   final_gather.c  direct light sampled from the emitters plus N gather rays into the solution,
 *                   at the first diffuse surface a camera path reaches (Reichert 1992)
 *   second_pass.c   the path of a ray through mirrors and glass until it lands on a diffuse
 *                   surface (Wallace, Cohen & Greenberg 1987)
 *   render.c        camera, pixels, threads, the public API
 *
 * Units: a pixel is the radiance seen, W / (m^2 sr) when the scene's emission is in those units:
 * B / pi on diffuse surfaces, which on an emitter includes its emitted radiance L = E / pi. */
#ifndef RAD_RENDER_RENDER_H
#define RAD_RENDER_RENDER_H

#include "core/rng.h"
#include "scene/camera.h"
#include "system/element_rays.h"
#include "scene/scene.h"
#include "system/system.h"

/* A piece of emitting surface for light sampling: a triangle of an emitting element, cut the
 * same way Embree cuts it, so sampled points lie exactly on the traced geometry. */
typedef struct rad_emitter {
    rad_vec3 p0, e1, e2; /* corner and edges: p = p0 + s e1 + t e2, s, t >= 0, s + t <= 1 */
    rad_vec3 normal;     /* front, unit */
    double area;
    float radiance[3];   /* emitted radiance L = E / pi */
} rad_emitter;

typedef struct rad_render_settings {
    int width, height, samples_per_pixel;
    rad_shading shading;
    int final_gather, light_samples, max_depth, ambient;
} rad_render_settings;

struct rad_renderer {
    rad_context *ctx;
    const rad_system *system;
    const rad_mesh *mesh;
    rad_element_rays *rays;
    rad_view view;
    rad_render_settings settings;
    uint64_t seed;

    /* Materials by surface (copied from the scene, which may go away). */
    size_t surface_count;
    rad_material *surface_material;

    /* Light sampling: emitter triangles and their cumulative distribution by power. */
    size_t emitter_count;
    rad_emitter *emitters;
    double *emitter_cdf;           /* emitter_count entries, the last is 1 */
    int32_t (*element_emitter)[2]; /* per element, its emitter triangles (-1: none) */

    /* Boundary vertices of the smooth reconstruction (reconstruct.c): their radiance is the
     * value at the vertex of a plane fitted to nearby element values, sum_k weight_k B_k over
     * the elements fit_element[first .. first + count). */
    size_t fit_count;
    uint32_t *fit_vertex, *fit_first, *fit_size;
    uint32_t *fit_element;
    double *fit_weight;

    /* The solution as radiance, refreshed by each render (the system may have been re-solved). */
    float (*vertex_radiance)[3];   /* B / pi averaged at mesh vertices (smooth) */
    float (*element_radiance)[3];  /* B / pi per element (flat) */
    float (*element_emission)[3];  /* E / pi per element */
    float (*element_reflectance)[3];
};

/* Counters one thread keeps while rendering. */
typedef struct rad_ray_counts {
    uint64_t camera, gather, shadow, specular;
} rad_ray_counts;

/* One camera sample: its random numbers, and its place among the samples of its pixel. The final
 * gather spreads its rays and emitter samples over the whole pixel: sample `index` of `count`
 * takes every count-th point of one stratified set per pixel (shifted by the pixel's offsets),
 * so the pixel's estimate is stratified, not only each sample's. */
typedef struct rad_sample {
    rad_rng rng;
    uint32_t index, count;
    double gather_shift[2], light_shift[2];
    rad_ray_counts *counts;
} rad_sample;

/* The material of an element. */
static inline const rad_material *rad_renderer_material(const rad_renderer *r, uint32_t element) {
    return &r->surface_material[r->mesh->element_surface[element]];
}

/* reconstruct.c: the solution's radiance B / pi at (u, v) on an element (smooth or flat). */
void rad_reconstruct_radiance(const rad_renderer *r, uint32_t element, double u, double v,
                              double out[3]);
/* Finds the boundary vertices and their fitting weights (geometry only, once). */
rad_status rad_reconstruct_build(rad_renderer *r);
/* Fills the radiance arrays from the system's current solution. */
rad_status rad_reconstruct_prepare(rad_renderer *r);

/* final_gather.c: the emitter table, and the radiance leaving the diffuse point x (on element,
 * front normal n) by direct light plus gathered indirect light. */
rad_status rad_emitters_build(rad_renderer *r);
void rad_final_gather(const rad_renderer *r, rad_sample *sample, const rad_element_hit *hit,
                      rad_vec3 x, rad_vec3 n, double out[3]);

/* Where a gather ray starts: what multiple importance sampling between the emitter samples and
 * the gather rays needs to weigh the emitted light a gather ray finds. */
typedef struct rad_gather_origin {
    rad_vec3 normal;
    int light_samples, gather_rays;
} rad_gather_origin;

/* A point drawn on the emitters, as seen from a point x. */
typedef struct rad_emitter_point {
    rad_vec3 position, direction; /* direction: unit, from x to the point */
    double pdf;                   /* solid-angle density at x */
    const float *radiance;        /* emitted radiance L_e */
} rad_emitter_point;

/* The power heuristic (Veach & Guibas 1995) for a sample of the strategy with (count times
 * density) a against the other's b. */
static inline double rad_power_heuristic(double a, double b) {
    return a * a + b * b > 0 ? a * a / (a * a + b * b) : 0;
}

/* final_gather.c: a point on the emitters for two uniform numbers (an emitter triangle by power,
 * then uniform on it); zero when it is not there or faces away from x. */
int rad_emitter_sample(const rad_renderer *r, double u0, double u1, rad_vec3 x,
                       rad_emitter_point *out);
/* The solid-angle density rad_emitter_sample has for the point a ray along `direction` meets at
 * `hit`; zero when that is not the front of an emitter. */
double rad_emitter_pdf(const rad_renderer *r, rad_vec3 direction, const rad_element_hit *hit);

/* final_gather.c: the weight (power heuristic, Veach 1997) of the emitted radiance a gather ray
 * from `from` meets straight away at distance t on the front of emitting `element`. */
double rad_gather_emission_weight(const rad_renderer *r, const rad_gather_origin *from,
                                  rad_vec3 direction, const rad_element_hit *hit);

/* second_pass.c: the radiance arriving at `origin` from `direction`, following mirrors and glass
 * up to max_depth bounces. Camera rays (`gather` NULL) take B / pi where they land, or a final
 * gather when it is on. Gather rays take the reflected part (B - E) / pi at their first hit plus
 * the emitted part weighted against the emitter samples (rad_gather_emission_weight); after a
 * mirror or glass the direct light is not sampled, and they take B / pi. */
void rad_trace_radiance(const rad_renderer *r, rad_sample *sample, rad_vec3 origin,
                        rad_vec3 direction, const rad_gather_origin *gather, double out[3]);

#endif
