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

#include "core/sampler.h"
#include "light/emitters.h"
#include "render/photon_map.h"
#include "scene/camera.h"
#include "system/element_rays.h"
#include "scene/scene.h"
#include "system/solution_view.h"
#include "system/system.h"

/* The most points on the emitters penumbra.c tests an element against. */
#define RAD_PENUMBRA_LAMPS 16

typedef struct rad_render_settings {
    int width, height, samples_per_pixel;
    rad_shading shading;
    int final_gather, light_samples, max_depth, ambient;
    int light_samples_default; /* light_samples when the options left it to the renderer (0:
                                  they gave it), before the emitters double it (render.c) */
    int gather_filter; /* the final gather's irradiance filter (gather_filter.c) on */
} rad_render_settings;

struct rad_renderer {
    rad_context *ctx;
    const rad_system *system;
    /* The solution as the renderer reads it (system/solution_view.h), and its leaves: `mesh` and
     * everything built from it below (rays, emitters, fits, radiance arrays) belong to one
     * generation of the view and are rebuilt when the leaves change. */
    const rad_solution_view *solution;
    uint64_t generation;
    int leaves_ready; /* what is built from the leaves is complete (a failed rebuild is not) */
    const rad_mesh *mesh;
    rad_element_rays *rays;
    /* The same elements without Embree's robust traversal, for the rays that start on a surface
     * (gather and shadow rays: 87 % of the Cornell box's): 2.5 % less processor time for the
     * Cornell box's render (9 % with the camera rays' and the solve's too), where about
     * 2 rays in a million slip through an edge shared by two elements (a closed cube seen from
     * inside: 2 black pixels of 1024 x 1024 at one ray each, none robust). A camera ray that
     * slips shows a dark speck, so camera rays keep `rays`; a gather or shadow ray that slips
     * moves a pixel by a millionth of its light. Equal to `rays` without the final gather. */
    rad_element_rays *inner_rays;
    rad_view view;
    rad_render_settings settings;
    uint64_t seed;

    /* Materials by surface (copied from the scene, which may go away). */
    size_t surface_count;
    rad_material *surface_material;

    /* Light sampling: the emitting elements' triangles, or their polygon when it is a
     * parallelogram, picked by power (light/emitters.h, emitters_build.c). */
    rad_emitter_table emitters;
    int32_t (*element_emitter)[2]; /* per element, its emitter entries (-1: none) */
    /* The scene's point, spot and directional lights and its sky (light/lights.h), copied:
     * sampled at every final-gather point, the sky seen by rays that leave the scene. */
    size_t light_count;
    rad_light *lights;
    rad_sky sky;

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
    /* The emission beyond the material's own (the specular-first deposit, E / pi minus the
     * material's L) at each element's corners, smoothed but keeping each element's mean
     * (reconstruct.c); NULL when no element has any. */
    float (*corner_deposit)[4][3];
    /* B / pi at each element's corners, smooth but scaled so the element keeps its own mean:
     * what gather rays read (reconstruct.c, rad_reconstruct_gather_radiance). */
    float (*corner_radiance)[4][3];
    /* B / pi at each element's corners with the direct light evaluated there (collocate.c): what
     * the smooth bare picture (no final gather) shows; NULL otherwise. */
    float (*corner_collocated)[4][3];

    /* Textured surfaces (texture_shading.c): the irradiance (B - E) / (pi rho) averaged at mesh
     * vertices; NULL when no surface is textured. */
    float (*vertex_irradiance)[3];

    /* Under this radiance (B / pi, mean of the channels) a surface counts as dark: DARK times
     * the mean the pixel corners see (render.c); set by each render, 0: none. */
    double dark_radiance;
    /* How gather rays are gathered again at their hits (final_gather.c, rad_regather_choose):
     * on a hierarchy's coarse leaves every first gather ray (with two rays, deeper with one);
     * on a uniform mesh only short ones, once; on a finely refined hierarchy short ones, twice.
     * Set with the leaves. */
    struct rad_regather {
        int leaves; /* RAD_LEAVES_UNIFORM, _COARSE (every first gather ray is re-gathered, its
                       short range infinite) or _FINE: system/solution_view.h */
        int levels; /* at most this many re-gathers along a path */
        int rays;   /* gather rays of one re-gather */
        int first_rays; /* ... of a first gather ray's re-gather (level 1) */
        /* Short rays onto elements the emitters light evenly are gathered again only within
         * EVEN_RANGE element sizes (final_gather.c): on a uniform mesh whose direct light is
         * all the emitter table's (no point, spot or directional light, no sky). */
        int by_light;
    } regather;
    /* The emitters' test points (penumbra.c) and, per element, 0 not tested yet, 1 lit evenly,
     * 2 unevenly: filled as the picture asks (rad_penumbra_element_uneven). */
    rad_vec3 penumbra_lamp[RAD_PENUMBRA_LAMPS];
    int penumbra_lamps;
    _Atomic uint8_t *element_uneven;
    /* Per element, whether another surface is near (final_gather.c): 0 not tested yet, 1 no,
     * 2 yes; filled as short gather rays meet the elements. */
    _Atomic uint8_t *element_near;

    /* The caustic map (caustics.c): the specular-first pass's landed photons; empty when none. */
    rad_photon_map caustics;
    double caustic_radius; /* the largest radius of its density estimate */
};

/* Counters one thread keeps while rendering. */
typedef struct rad_ray_counts {
    uint64_t camera, gather, shadow, specular;
} rad_ray_counts;

/* What the final gather at a camera ray's first hit leaves for the irradiance filter
 * (gather_filter.c), summed over the camera samples of one pixel. */
typedef struct rad_gather_tally {
    int gathers;              /* samples gathered at their first hit, untextured */
    double reflected[3];      /* sum of the mean radiance the gather rays read, emitted aside */
    double inverse_distance;  /* sum over the gather rays of 1 / hit distance (0: left) */
    uint32_t rays;            /* the gather rays in that sum */
    double position[3];       /* sum of the gathered points */
    float rho[3];             /* the reflectance there (one polygon, untextured: constant) */
    double ray_emitted[3];    /* the current gather ray's emitted light, weighted */
} rad_gather_tally;

/* One camera sample: its pixel and its place among the samples of the pixel, from which every
 * random number it needs is drawn (core/sampler.h: Owen-scrambled Sobol' points, the pixels in
 * Morton order). The final gather spreads its rays and emitter samples over the whole pixel:
 * ray i of sample `index` of `count` is point index * n + i of the pixel's count * n points, one
 * net over the pixel, so the pixel's estimate is stratified, not only each sample's. */
typedef struct rad_sample {
    uint64_t seed;
    uint32_t x, y, index, count;
    rad_ray_counts *counts;
    /* Set by rad_trace_radiance on camera paths: the input polygon the camera ray met first
     * (RAD_RENDER_NO_POLYGON when it left the scene), which render.c groups samples by. */
    uint32_t first_polygon;
    /* The pixel's tally for the irradiance filter (gather_filter.c); NULL: none. */
    rad_gather_tally *tally;
    /* Gather rays of this camera sample; zero: the settings' final_gather. */
    int gather_rays;
    /* Emitter samples of this camera sample; zero: the settings' light_samples. */
    int light_samples;
    /* Where they are in the pixel's sequence of gather points (gather_total points, of which
     * this sample's are gather_first on; render.c varies the rays per sample). Zero total: each
     * sample has gather_rays points, sample `index` the run index * gather_rays on. */
    uint32_t gather_first, gather_total;
} rad_sample;

#define RAD_RENDER_NO_POLYGON UINT32_MAX

/* The sampler's 2D dimensions in the renderer: the position in the pixel, the final gather's
 * directions and emitter points, and three per bounce of a camera path through mirrors and
 * glass (emitter point, BSDF direction, lobe choice) from RAD_RENDER_DIM_BOUNCE, of a gather
 * ray's path from RAD_RENDER_DIM_GATHER_BOUNCE. */
enum {
    RAD_RENDER_DIM_PIXEL = 0,
    RAD_RENDER_DIM_GATHER = 1,
    RAD_RENDER_DIM_LIGHT = 2,
    RAD_RENDER_DIM_BOUNCE = 3,
    RAD_RENDER_DIM_COVERAGE = 900, /* render.c: the rays that measure what covers a pixel */
    RAD_RENDER_DIM_GATHER_BOUNCE = 1000,
    RAD_RENDER_DIM_SHORT = 2000 /* short gather rays, level L: 2000 + 2L (light), + 1 (ray) */
};

/* Number i of `per_sample` numbers of this sample (of count * per_sample for the pixel) in 2D
 * dimension `dimension`. */
static inline void rad_sample_2d_at(const rad_sample *sample, uint32_t total, uint32_t point,
                                    uint32_t dimension, double out[2]) {
    rad_sampler sampler = rad_sampler_make(sample->seed, 0);
    sampler.index = rad_sampler_pixel_index(sample->x, sample->y, total, point);
    sampler.dimension = dimension;
    rad_sampler_2d(&sampler, out);
}

/* Points first .. first + count - 1 of the pixel's `total` in `dimension`: rad_sample_2d_at's
 * numbers, the pixel's index and the dimension's hash made once for the run rather than once a
 * point (a packet of at most 16 gather rays or emitter samples; rad_sampler_run_bits). */
static inline void rad_sample_2d_run(const rad_sample *sample, uint32_t total, uint32_t first,
                                     int count, uint32_t dimension, double (*out)[2]) {
    rad_sampler sampler = rad_sampler_make(sample->seed, 0);
    uint32_t bits[16][2];
    rad_sampler_run_bits(sampler.seed, rad_sampler_pixel_index(sample->x, sample->y, total, first),
                         count, dimension, bits);
    for (int i = 0; i < count; ++i) {
        out[i][0] = rad_sampler_fraction(bits[i][0]);
        out[i][1] = rad_sampler_fraction(bits[i][1]);
    }
}

static inline void rad_sample_2d(const rad_sample *sample, uint32_t per_sample, uint32_t i,
                                 uint32_t dimension, double out[2]) {
    rad_sample_2d_at(sample, sample->count * per_sample, sample->index * per_sample + i, dimension,
                     out);
}

/* The material of an element. */
static inline const rad_material *rad_renderer_material(const rad_renderer *r, uint32_t element) {
    return &r->surface_material[r->mesh->element_surface[element]];
}

/* reconstruct.c: the solution's radiance B / pi at (u, v) on an element (smooth or flat). */
void rad_reconstruct_radiance(const rad_renderer *r, uint32_t element, double u, double v,
                              double out[3]);
/* reconstruct.c: the radiance an element emits itself at (u, v): its material's emission, flat,
 * plus the deposit (corner_deposit) interpolated as rad_reconstruct_radiance does (smooth
 * shading), or the element's E / pi (flat shading). */
void rad_reconstruct_emission(const rad_renderer *r, uint32_t element, double u, double v,
                              double out[3]);
/* reconstruct.c: the radiance a gather ray reads at (u, v) on an element: smooth, but with each
 * element's mean kept (flat shading: the element's value). */
void rad_reconstruct_gather_radiance(const rad_renderer *r, uint32_t element, double u, double v,
                                     double out[3]);
/* collocate.c: nonzero when the picture shows the smooth solution itself (no final gather), so
 * the direct light is evaluated at the element corners. */
int rad_collocate_wanted(const rad_renderer *r);
/* collocate.c: the light reflected just inside each corner of each element, B / pi units: rho
 * times the direct light from the emitting leaves and the lights plus the light gathered from
 * the solution (after rad_reconstruct_prepare's other arrays). */
rad_status rad_collocate_light(rad_renderer *r, float (*corner)[4][3]);
/* Finds the boundary vertices and their fitting weights (geometry only, once). */
rad_status rad_reconstruct_build(rad_renderer *r);
/* Fills the radiance arrays from the system's current solution. */
rad_status rad_reconstruct_prepare(rad_renderer *r);

/* emitters_build.c: the emitter table of the emitting elements (a parallelogram lamp one entry)
 * and each element's entries (element_emitter). */
rad_status rad_emitters_build(rad_renderer *r);
/* penumbra.c: the fixed points on the emitters the test below aims at (at most
 * RAD_PENUMBRA_LAMPS); their count, 0 without the final gather or emitters. */
int rad_penumbra_lamps(const rad_renderer *r, rad_vec3 *points);
/* Whether the emitters light `element` unevenly, tested on those points (0 when lamps is 0 and
 * on emitters); thread-safe, deterministic. */
int rad_penumbra_uneven(const rad_renderer *r, uint32_t element, const rad_vec3 *lamp, int lamps);
/* The same for the renderer's own lamp points (penumbra_lamp), each element tested once, when
 * first asked, and kept (element_uneven); thread-safe, deterministic. */
int rad_penumbra_element_uneven(const rad_renderer *r, uint32_t element);
/* Makes the renderer's lamp points and the empty table of answers (with the leaves). */
rad_status rad_penumbra_prepare(rad_renderer *r);
/* final_gather.c: the radiance leaving the diffuse point x (on element, front normal n) by
 * direct light plus gathered indirect light; first_hit: x is the camera ray's first hit, whose
 * gather the pixel's tally records. */
void rad_final_gather(const rad_renderer *r, rad_sample *sample, const rad_element_hit *hit,
                      rad_vec3 x, rad_vec3 n, int first_hit, double out[3]);

/* Where a gather ray starts: what multiple importance sampling between the emitter samples and
 * the gather rays needs to weigh the emitted light a gather ray finds. */
typedef struct rad_gather_origin {
    rad_vec3 normal;
    int light_samples, gather_rays;
    /* This gather ray's point in the pixel's sequence of `run` gather points (rad_sample_2d_at);
     * a short gather ray's recursion (final_gather.c, level > 0) keeps its parent's. */
    uint32_t ray;
    int level;
    uint32_t run;
    /* Level 0 at a camera ray's first hit, with the irradiance filter on: what the gather rays
     * met is tallied here (hit distance, emitted light); NULL otherwise. */
    rad_gather_tally *tally;
    /* Gather rays nearer than this many element sizes of what they hit are gathered again
     * (final_gather.c, rad_gather_is_short). */
    double short_range;
    /* The emitter choice at this point (light/emitters.h), made once for its emitter samples
     * and the emitted light its rays find; NULL exactly when it takes no emitter samples (none
     * asked for, or no emitters). */
    const rad_emitter_choice *choice;
} rad_gather_origin;

/* The power heuristic (Veach & Guibas 1995) for a sample of the strategy with (count times
 * density) a against the other's b. */
static inline double rad_power_heuristic(double a, double b) {
    return a * a + b * b > 0 ? a * a / (a * a + b * b) : 0;
}

/* final_gather.c: the solid-angle density rad_emitter_table_sample has (on r->emitters, for the
 * receiver `origin` of front `normal`, or the zero vector as the sample had) for the point a ray
 * from `origin` along `direction` meets at `hit`; zero when that is not the front of an
 * emitter. */
double rad_emitter_pdf(const rad_renderer *r, rad_vec3 origin, rad_vec3 normal, rad_vec3 direction,
                       const rad_element_hit *hit);

/* final_gather.c: the weight (power heuristic, Veach 1997) of the emitted radiance a gather ray
 * from `from` (its own point) along `direction` meets straight away at `hit`. */
double rad_gather_emission_weight(const rad_renderer *r, const rad_gather_origin *from,
                                  rad_vec3 direction, const rad_element_hit *hit);

/* final_gather.c: whether a gather ray from `from` that hits `hit` is short: nearer than a few
 * element sizes, where the solution's piecewise values are too coarse to be seen (the floor
 * just beside a block's base), so the radiance there is gathered once more instead; on a
 * uniform mesh lit by the emitter table only, beyond half an element only when the element hit
 * is near another surface or lit unevenly (regather.by_light). */
int rad_gather_is_short(const rad_renderer *r, const rad_gather_origin *from, const rad_element_hit *hit);
/* The empty table of elements near other surfaces that rad_gather_is_short fills (with the
 * leaves). */
rad_status rad_regather_prepare(rad_renderer *r);
/* final_gather.c: sets r->regather for a solution's kind of leaves (RAD_LEAVES_UNIFORM,
 * _COARSE or _FINE: system/solution_view.h). */
void rad_regather_choose(rad_renderer *r, int leaves);
/* final_gather.c: the reflected radiance leaving diffuse point y (element hit->element, front
 * normal n) towards a short gather ray from `from`: one emitter sample and r->regather.rays
 * gather rays. */
void rad_gather_short(const rad_renderer *r, rad_sample *sample, const rad_gather_origin *from,
                      const rad_element_hit *hit, rad_vec3 y, rad_vec3 n, double out[3]);

/* final_gather.c: whether point, spot or directional light i, arriving at x as `arrival`
 * (rad_light_arrive), reaches it: one shadow ray, counted. */
int rad_light_unblocked(const rad_renderer *r, size_t i, rad_vec3 x,
                        const rad_light_arrival *arrival, rad_ray_counts *counts);

/* second_pass.c: the radiance arriving at `origin` from `direction`, following mirrors and glass
 * up to max_depth bounces. Camera rays (`gather` NULL) take B / pi where they land, or a final
 * gather when it is on. Gather rays take the reflected part (B - E) / pi at their first hit plus
 * the emitted part weighted against the emitter samples (rad_gather_emission_weight); after a
 * mirror or glass the direct light is not sampled, and they take B / pi. */
void rad_trace_radiance(const rad_renderer *r, rad_sample *sample, rad_vec3 origin,
                        rad_vec3 direction, const rad_gather_origin *gather, double out[3]);
/* The same with the first hit given (traced by the caller, gather rays in packets: final_gather.c);
 * first->element RAD_NO_ELEMENT: the ray left the scene. */
void rad_trace_radiance_hit(const rad_renderer *r, rad_sample *sample, rad_vec3 origin,
                            rad_vec3 direction, const rad_gather_origin *gather,
                            const rad_element_hit *first, double out[3]);

/* gather_filter.c: one pixel's record for the irradiance filter: the pixel's samples all met
 * one untextured diffuse polygon and were gathered there (polygon RAD_RENDER_NO_POLYGON: not
 * filtered, and not used by its neighbours). */
typedef struct rad_gather_pixel {
    uint32_t polygon;
    float position[3];  /* mean of the gathered points */
    float distance;     /* harmonic mean distance of the gather rays' hits */
    float reflected[3]; /* mean radiance the gather rays read (emitted light aside) */
    float rho[3];
} rad_gather_pixel;

/* gather_filter.c: the record of a pixel from its tally (split: an edge pixel, not filtered). */
void rad_gather_pixel_make(const rad_gather_tally *tally, int samples, uint32_t polygon, int split,
                           rad_gather_pixel *out);
/* gather_filter.c: replaces, in every filtered pixel of the image, rho times its own gathered
 * radiance by rho times the weighted mean of its neighbours' (irradiance filtering, Kontkanen,
 * Raesaenen & Keller 2004). */
rad_status rad_gather_filter(const rad_renderer *r, const rad_gather_pixel *pixels, float *image);

/* texture_shading.c: the reflectance at point x of element (the texture's, times the factor,
 * on textured surfaces; 1 then), else the element's (0). */
int rad_renderer_albedo(const rad_renderer *r, uint32_t element, rad_vec3 x, float rho[3]);
/* Fills vertex_irradiance from the current solution (after rad_reconstruct_prepare). */
rad_status rad_texture_shading_prepare(rad_renderer *r);
/* The radiance a camera ray sees at x on a textured element: E / pi (rad_reconstruct_emission)
 * + rho(x) times the interpolated irradiance. 0 (out untouched) when the element is not textured. */
int rad_texture_shading_radiance(const rad_renderer *r, const rad_element_hit *hit, rad_vec3 x,
                                 double out[3]);

/* A point evaluated "at" an element's corner lies this far from the corner towards the
 * element's centroid (collocate.c, rad_renderer_vertex_radiosity): on that element, not on the
 * neighbours that share the corner. */
#define RAD_CORNER_INSET 1e-3

/* Final gather rays and emitter samples per point, at most (render options, bake). */
#define RAD_RENDER_MAX_GATHER (1 << 20)

/* render.c: a renderer for rad_renderer_vertex_radiosity only: its camera is not asked to see
 * anything (a bake's scene need not have a camera that does). */
rad_status rad_renderer_create_for_points(const rad_scene *scene, const rad_system *system,
                                          const rad_render_options *options, rad_renderer **out);
/* render.c: the final-gathered radiosity at every vertex of the leaves (pi times the radiance
 * leaving the front there, emission included), for bake --final-gather (io/bake.c): one point
 * per vertex just inside the largest element around it, `rays` gather rays and rays / 2
 * emitter samples, no irradiance filter. The same for any thread count; cancellable through
 * the context's progress callback. */
rad_status rad_renderer_vertex_radiosity(rad_renderer *r, int rays, rad_rgb *out);

/* caustics.c: the caustic map from the specular-first pass's landings (system.h), at renderer
 * creation; nothing when the pass landed none. */
rad_status rad_caustics_build(rad_renderer *r);
/* caustics.c: what a camera path sees a diffuse point emit at x: with a caustic map, the
 * material's own emission plus the map's caustic (the deposit left to the solve); without one,
 * rad_reconstruct_emission (the deposit smoothed). */
void rad_visible_emission(const rad_renderer *r, const rad_element_hit *hit, rad_vec3 x,
                          rad_vec3 n, const float rho[3], double out[3]);

#endif
