/* system.h - a scene cut into patches (which shoot) and elements (which receive and are shown),
 * with its form-factor provider and the radiosity solution.
 *
 * Elements of one patch are contiguous: patch p owns elements patch_first[p] .. patch_first[p+1].
 * The radiosity of a patch is the area-weighted mean of its elements (Cohen et al. 1986). */
#ifndef RAD_SOLVE_SYSTEM_H
#define RAD_SOLVE_SYSTEM_H

#include "core/context.h"
#include "core/vec3.h"
#include "formfactor/provider.h"

#include <stdint.h>

struct rad_mesh;
struct rad_rays;

typedef double rad_rgb[3];

/* The solution as the outputs read it (system/solution_view.h). */
struct rad_solution_view_ops;
typedef struct rad_solution_view {
    const struct rad_solution_view_ops *ops;
    void *state;
} rad_solution_view;

struct rad_system {
    rad_context *ctx;
    size_t element_count, patch_count, surface_count;

    /* Elements. */
    double *area;
    rad_rgb *reflectance;
    rad_rgb *emission; /* radiosity units: B = pi L for Lambertian emitters, plus light_emission */
    rad_rgb *light_emission; /* the part of `emission` that is the direct light of the point,
                                spot and directional lights and the sky reflected at once
                                (lights_direct.c): rho E_direct; NULL without such sources */
    rad_rgb *specular_emission; /* the part of `emission` that arrived from the emitters through
                                   mirrors and glass (specular_first.c): rho E_specular; NULL
                                   when the pass did not run */
    rad_rgb *specular_reflection; /* the part of `emission` that left diffuse elements of the
                                     solved radiosity and came back through mirrors and glass
                                     (D S+ D, specular_first.c): rho E; NULL until a solve adds
                                     it */
    uint64_t specular_photons; /* photons of the specular-first pass (0 when it did not run) */
    struct rad_caustic_landing *caustic_landings; /* the first half's landings (L S+ D photons,
                                                     specular_first.c), for the renderer's
                                                     caustic map; NULL when none landed */
    size_t caustic_landing_count;
    uint32_t *element_patch;
    uint32_t *element_surface;

    /* Patches. */
    size_t *patch_first; /* patch_count + 1 entries */
    double *patch_area;

    /* Named input surfaces. */
    char **surface_name;
    double *surface_area;
    /* The elements of surface i, in increasing order: surface_elements[surface_first[i] ..
     * surface_first[i + 1] - 1] (rad_system_finish_areas), so that a per-surface query costs the
     * surface's elements, not the whole mesh (a table of 10^5 surfaces was quadratic). */
    size_t *surface_first; /* surface_count + 1 entries */
    uint32_t *surface_elements;

    /* The solution. */
    rad_rgb *radiosity;
    rad_rgb *unshot;
    double ambient[3]; /* Cohen et al. 1988 ambient radiosity; zero unless asked for */

    rad_ff_provider *ff;
    struct rad_mesh *mesh; /* geometric scenes only; owned */
    struct rad_scene *geometry; /* geometric scenes only: a copy of the input polygons for the
                                   hierarchical solver (src/hierarchy); owned */
    rad_solution_view view; /* what render, bake and solution files read: the uniform mesh
                               (solution_view.h) unless a solver installs another */
};

/* One photon of the specular-first pass where it landed on a diffuse element after mirrors and
 * glass (an L S+ D path): the renderer draws caustics from these (render/caustics.c), while
 * their sum per element feeds the solve (specular_emission). */
typedef struct rad_caustic_landing {
    rad_vec3 position;
    float power[3];    /* flux divided by the photon count (the scene's radiosity units x area) */
    float normal[3];   /* front normal of the surface it landed on */
    float incoming[3]; /* unit, from the surface towards where the photon came from */
} rad_caustic_landing;

/* Allocates the arrays of a system with the given counts (zeroed). */
rad_status rad_system_alloc(rad_context *ctx, size_t elements, size_t patches, size_t surfaces,
                            rad_system **out);

/* Derives patch_area and surface_area from element areas, and the elements of each surface
 * (surface_first, surface_elements); call after filling elements. */
void rad_system_finish_areas(rad_system *system);

/* RAD_OK when every surface's area and emitted power, and their sums, are finite numbers
 * (finite inputs may overflow: an area of 1e200 emitting 1e200); otherwise an error naming the
 * first surface that overflows. `source` names the scene. Call after rad_system_finish_areas. */
rad_status rad_system_check_finite(rad_system *system, const char *source);

/* Patch means of a per-element quantity (area-weighted). */
void rad_system_patch_mean(const rad_system *system, const rad_rgb *per_element, size_t patch,
                           double out[3]);

/* Surface means of a per-element quantity (area-weighted), into surface_count entries. */
void rad_system_surface_means(const rad_system *system, const rad_rgb *per_element,
                              rad_rgb *per_surface);

/* The light pre-pass (lights_direct.c): the irradiance each element gets straight from the
 * scene's point, spot and directional lights and its sky, with visibility, reflected once into
 * light_emission and added to emission, so every solver starts from it as emitted radiosity. */
rad_status rad_system_add_light_emission(rad_system *system, const struct rad_scene *scene);

/* The same direct irradiance for one planar polygon of 3 or 4 corners (counter-clockwise about
 * its front normal), for solvers with their own elements (the hierarchy's nodes): point and
 * spot lights by the exact solid angle of the polygon, directional lights by its cosine, both
 * with visibility from the centres of its 16 sixteenths (quarters of quarters); the sky by
 * scene->sky.samples rays from its four quarters, seeded by `stream`. With `spread`, how much
 * the irradiance changes across it (a shadow edge, the rim of an opening): the largest
 * difference between the points' (lights) and between the quarters' estimates beyond their
 * noise (sky), largest channel. Thread-safe. */
void rad_lights_polygon_irradiance(const struct rad_scene *scene, const struct rad_rays *rays,
                                   const rad_vec3 *corners, int count, rad_vec3 normal,
                                   uint64_t stream, double out[3], double *spread);

/* The same times the reflectance of input polygon `polygon` (whose piece `corners` is): the
 * radiosity the piece reflects of the direct light, and its spread. `user` is a
 * rad_node_lights; the signature is rad_hier_options.light's (the hierarchy's nodes). */
typedef struct rad_node_lights {
    const struct rad_scene *scene;
    struct rad_rays *rays;
} rad_node_lights;
void rad_node_lights_reflected(void *user, uint32_t polygon, const rad_vec3 *corners, int count,
                               uint64_t stream, double out[3], double *spread);

/* The specular-first pass (specular_first.c; docs/specular-first.md): photons from the emitting
 * surfaces through mirrors and glass; what lands on each element (its mean irradiance from
 * L S+ D paths) is reflected once into specular_emission and added to emission, so every solver
 * starts from it as emitted radiosity. Runs as scene->specular_first asks. */
rad_status rad_system_add_specular_emission(rad_system *system, const struct rad_scene *scene);

/* The radiosity element e emits itself, channel c: what makes it a light source for the
 * renderer. Its material's emission and the light it got through mirrors and glass
 * (specular_emission: the renderer's gather rays leave emitted light behind mirrors and glass
 * out, second_pass.c, so the deposit is sampled as an emitter of its own), without the light of
 * the lights' pre-pass (which the renderer samples from the lights themselves). */
static inline double rad_system_own_emission(const rad_system *s, size_t e, int c) {
    double own = s->light_emission ? s->emission[e][c] - s->light_emission[e][c] : s->emission[e][c];
    /* The D S+ D light is found by the renderer's own gather rays through mirrors and glass. */
    return s->specular_reflection ? own - s->specular_reflection[e][c] : own;
}

/* One element per input polygon (polygon_mesh.c), for rad_mesh_options.polygons_only. */
rad_status rad_system_polygon_mesh(rad_context *ctx, const struct rad_scene *scene,
                                   struct rad_mesh **out);
/* The second specular-first pass (specular_first.c): after a solve, photons leave every
 * element with its reflected radiosity B - pi L_material and follow mirrors and glass; what
 * lands on diffuse elements (D S+ D light, which the form factors leave out) is reflected once
 * into specular_reflection and added to emission, radiosity and unshot, for the solver to
 * spread on resuming. Does nothing (RAD_OK) when the first pass did not run or it was added
 * already. rad_system_remove_specular_reflection takes it out of emission again. */
rad_status rad_system_add_specular_reflection(rad_system *system);
void rad_system_remove_specular_reflection(rad_system *system);

/* Geometric systems (src/mesh, src/formfactor): builds mesh and provider. */
rad_status rad_system_from_geometry(rad_context *ctx, const struct rad_scene *scene,
                                    const rad_mesh_options *mesh, const rad_ff_options *ff,
                                    rad_system **out);

#endif
