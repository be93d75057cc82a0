/* specular_first.c - the specular-first pass of a geometric system (system.h): ray tracing
 * first, then radiosity (Wallace, Cohen & Greenberg 1987, "A two-pass solution to the rendering
 * equation"; Sillion & Puech 1989, "A general two-pass method integrating specular and diffuse
 * reflection", whose extended form factors carry light through mirrors and glass).
 *
 * Photons leave the emitting surfaces (scene/photon_path.h, the photon tracer of photon mapping)
 * and are followed through mirrors and glass only: a photon whose first surface is diffuse is
 * dropped (that light is the solver's own emitter-to-element transfer). Where a photon that has
 * bounced on mirrors or glass at least once reaches a surface with a diffuse lobe (an L S+ D
 * path), its flux lands on the element it hits. Each element's mean irradiance from such paths,
 *     E_specular(e) = sum of the flux that landed on e / N / A_e,
 * reflected once, rho_e E_specular(e), becomes part of its emitted radiosity (specular_emission,
 * added to emission): every solver then spreads it as light of its own, as it does the lights'
 * pre-pass (lights_direct.c).
 *
 * For the renderer the deposit is the element's own emission (rad_system_own_emission), as a
 * lamp's is: the final gather samples it
 * as an emitter (final_gather.c) and takes it from the gather rays that meet the element
 * directly, weighted against those samples. Nothing else in the render finds L S+ D light: a
 * gather ray that reaches a lamp through a mirror or glass takes only the reflected part
 * (B - E) / pi of what it meets there (second_pass.c), so the same light is not counted twice.
 * The camera sees the caustic itself from the same photons, kept where they landed
 * (caustic_landings): the renderer's caustic map (render/caustics.c) replaces the deposit at the
 * visible point.
 *
 * The second half (rad_system_add_specular_reflection, called by the solve driver once a solve
 * has converged): the same photons leave every element with its solved reflected radiosity
 * B - pi L_material and follow mirrors and glass; what lands on diffuse elements (D S+ D light,
 * which the form factors stop at mirrors and glass) becomes emitted and unshot radiosity too,
 * and the solve resumes. The renderer finds that light with its own gather rays through mirrors
 * and glass, so it is not the element's own emission (rad_system_own_emission).
 *
 * Photons are traced in fixed blocks whose deposits are summed in block order: the result does
 * not depend on the thread count. */
#include "system/system.h"

#include "mesh/mesh.h"
#include "scene/photon_path.h"
#include "scene/scene.h"
#include "system/element_rays.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#define SPECULAR_BLOCK 4096
#define SPECULAR_SEED 0x5bd1e9955bd1e995ull
#define MAX_SPECULAR_BOUNCES 32

/* One landing: the element, the flux, and where and from where it arrived (kept by the first
 * half as the renderer's caustic photons). */
typedef struct deposit {
    uint32_t element;
    float power[3];
    rad_vec3 position;
    float normal[3], incoming[3];
} deposit;

typedef struct deposit_list {
    rad_context *ctx;
    const rad_element_rays *elements;
    deposit *items;
    size_t count, capacity;
} deposit_list;

/* At a smooth surface: keep the flux of L S+ D photons, on the element the ray meets. */
static int land(void *user, const rad_photon_arrival *a) {
    if (a->bounce == 0 || !a->specular_path) return 1;
    deposit_list *list = user;
    rad_element_hit hit;
    if (!rad_element_rays_intersect(list->elements, a->origin, a->direction,
                                    list->elements->epsilon, INFINITY, &hit) ||
        !hit.front)
        return 1;
    if (list->count == list->capacity) {
        size_t capacity = list->capacity ? 2 * list->capacity : 256;
        deposit *grown = rad_realloc(list->ctx, list->items, capacity, sizeof *grown);
        if (!grown) return 0;
        list->items = grown;
        list->capacity = capacity;
    }
    deposit *d = &list->items[list->count++];
    d->element = hit.element;
    d->position = a->position;
    d->normal[0] = (float)a->hit.normal.x, d->normal[1] = (float)a->hit.normal.y;
    d->normal[2] = (float)a->hit.normal.z;
    d->incoming[0] = (float)-a->direction.x, d->incoming[1] = (float)-a->direction.y;
    d->incoming[2] = (float)-a->direction.z;
    for (int c = 0; c < 3; ++c) d->power[c] = (float)a->power[c];
    return 1;
}

/* The emitting polygons' triangles, by power, as the path tracer's table (pathtrace.c). */
static rad_status build_emitters(rad_context *ctx, const rad_scene *scene,
                                 const rad_material **polygon_material, rad_emitter_table *table) {
    size_t triangles = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const rad_material *m = &scene->materials[scene->surfaces[p->surface].material];
        polygon_material[i] = m;
        if (m->emission[0] > 0 || m->emission[1] > 0 || m->emission[2] > 0) triangles += p->count - 2;
    }
    rad_status status = rad_emitter_table_reserve(ctx, table, triangles);
    if (status || triangles == 0) return status;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const double *emission = polygon_material[i]->emission;
        if (!(emission[0] > 0 || emission[1] > 0 || emission[2] > 0)) continue;
        rad_vec3 normal = rad_polygon_normal(scene, p);
        rad_vec3 p0 = rad_polygon_vertex(scene, p, 0);
        for (uint32_t k = 1; k + 1 < p->count; ++k)
            rad_emitter_table_add(table, p0, rad_polygon_vertex(scene, p, k),
                                  rad_polygon_vertex(scene, p, k + 1), normal, emission);
    }
    return rad_emitter_table_finish(ctx, table, RAD_EMITTERS_BY_POWER);
}

/* Traces the photons and sums their flux per element into `flux` (element_count entries). With
 * `landings`, every landing is also kept there (in block order, flux over `count`). */
static rad_status trace(rad_context *ctx, const rad_photon_scene *photons,
                        const rad_element_rays *elements, uint64_t seed, uint64_t count,
                        rad_rgb *flux, rad_caustic_landing **landings, size_t *landing_count) {
    size_t blocks = (size_t)((count + SPECULAR_BLOCK - 1) / SPECULAR_BLOCK);
    deposit_list *block = rad_alloc_zero(ctx, blocks ? blocks : 1, sizeof *block);
    if (!block) return RAD_ERROR_NO_MEMORY;
    int failed = 0;
    uint64_t rays = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(rad_thread_count(ctx)) reduction(+ : rays)
    for (long long b = 0; b < (long long)blocks; ++b) {
        int stop;
#pragma omp atomic read
        stop = failed;
        if (stop) continue;
        block[b].ctx = ctx;
        block[b].elements = elements;
        uint64_t begin = (uint64_t)b * SPECULAR_BLOCK;
        uint64_t end = count < begin + SPECULAR_BLOCK ? count : begin + SPECULAR_BLOCK;
        for (uint64_t i = begin; i < end; ++i)
            if (!rad_photon_path_trace(photons, seed, i, 1, MAX_SPECULAR_BOUNCES, land,
                                       &block[b], &rays)) {
#pragma omp atomic write
                failed = 1;
                break;
            }
    }
    /* Sum in block order, and keep the landings in the same order. */
    size_t kept = 0, total = 0;
    for (size_t b = 0; b < blocks; ++b) total += block[b].count;
    rad_caustic_landing *keep = NULL;
    if (landings && !failed && total) {
        /* The caustic map is an image's refinement: past a quarter of the memory budget it is
         * left out (the render then draws the deposit), with a warning. */
        if ((double)total * sizeof *keep > 0.25 * (double)ctx->max_memory) {
            rad_warn(ctx, "the specular-first pass's %zu landed photons are not kept for the "
                          "caustic map: over a quarter of the memory budget (--max-memory)",
                     total);
        } else {
            keep = rad_alloc(ctx, total, sizeof *keep);
            if (!keep) failed = 1;
        }
    }
    for (size_t b = 0; b < blocks; ++b) {
        for (size_t i = 0; i < block[b].count && keep; ++i) {
            const deposit *d = &block[b].items[i];
            rad_caustic_landing *l = &keep[kept++];
            l->position = d->position;
            for (int c = 0; c < 3; ++c) {
                l->power[c] = (float)(d->power[c] / (double)count);
                l->normal[c] = d->normal[c];
                l->incoming[c] = d->incoming[c];
            }
        }
        for (size_t i = 0; i < block[b].count && !failed; ++i)
            for (int c = 0; c < 3; ++c) flux[block[b].items[i].element][c] += block[b].items[i].power[c];
        rad_free(ctx, block[b].items);
    }
    rad_free(ctx, block);
    if (failed) {
        rad_free(ctx, keep);
        return RAD_ERROR_NO_MEMORY;
    }
    if (landings) *landings = keep, *landing_count = kept;
    return RAD_OK;
}

rad_status rad_system_add_specular_emission(rad_system *s, const rad_scene *scene) {
    rad_context *ctx = s->ctx;
    const rad_mesh *mesh = s->mesh;
    if (!mesh || scene->polygon_count == 0 || !rad_scene_wants_specular_first(scene))
        return RAD_OK;
    uint64_t count = scene->specular_photons ? scene->specular_photons : RAD_SPECULAR_PHOTONS;
    const rad_material **polygon_material =
        rad_alloc(ctx, scene->polygon_count, sizeof *polygon_material);
    rad_emitter_table emitters;
    memset(&emitters, 0, sizeof emitters);
    rad_light_emission sources;
    memset(&sources, 0, sizeof sources);
    rad_rays *rays = NULL;
    rad_element_rays *elements = NULL;
    rad_rgb *flux = rad_alloc_zero(ctx, s->element_count, sizeof *flux);
    rad_status status = polygon_material && flux ? RAD_OK : RAD_ERROR_NO_MEMORY;
    if (!status) status = build_emitters(ctx, scene, polygon_material, &emitters);
    /* Photons leave the emitting surfaces and the point, spot and directional lights, by power
     * (scene/light_emission.h). Not the sky: the render's gather rays already take the sky they
     * see through mirrors and glass (second_pass.c), and the caustic map would count it again. */
    if (!status) status = rad_light_emission_build(ctx, &emitters, scene, 0, &sources);
    if (!status && !(sources.total_power > 0)) goto done;
    if (!status) status = rad_rays_create(ctx, scene, &rays);
    if (!status) status = rad_element_rays_create(ctx, mesh, &elements);
    if (!status) {
        rad_photon_scene photons = {rays, polygon_material, &sources, scene};
        rad_free(ctx, s->caustic_landings);
        s->caustic_landings = NULL;
        s->caustic_landing_count = 0;
        status = trace(ctx, &photons, elements, SPECULAR_SEED, count, flux, &s->caustic_landings,
                       &s->caustic_landing_count);
    }
    if (!status) {
        rad_free(ctx, s->specular_emission);
        s->specular_emission = rad_alloc_zero(ctx, s->element_count, sizeof *s->specular_emission);
        if (!s->specular_emission) status = RAD_ERROR_NO_MEMORY;
    }
    /* The element's mean irradiance from L S+ D paths, reflected once. */
    for (size_t e = 0; e < s->element_count && !status; ++e) {
        if (!(s->area[e] > 0)) continue;
        for (int c = 0; c < 3; ++c) {
            double irradiance = flux[e][c] / (double)count / s->area[e];
            s->specular_emission[e][c] = s->reflectance[e][c] * irradiance;
            s->emission[e][c] += s->specular_emission[e][c];
        }
    }
    if (!status) s->specular_photons = count;
done:
    rad_element_rays_destroy(elements);
    rad_rays_destroy(rays);
    rad_emitter_table_free(ctx, &emitters);
    rad_light_emission_free(ctx, &sources);
    rad_free(ctx, flux);
    rad_free(ctx, (void *)polygon_material);
    return status;
}

/* ------------------------------------------------------------------------------------------- */
/* The second pass: diffuse -> mirrors and glass -> diffuse                                     */

/* Each element's triangles with the radiance of its reflected radiosity, (B - pi L_material) / pi,
 * by power: light a diffuse surface sends on, which the form factors stop at mirrors and glass. */
static rad_status build_reflectors(rad_context *ctx, const rad_system *s,
                                   const rad_material **polygon_material, rad_emitter_table *table) {
    const rad_mesh *mesh = s->mesh;
    const rad_scene *scene = s->geometry;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        polygon_material[i] = &scene->materials[scene->surfaces[scene->polygons[i].surface].material];
    rad_status status = rad_emitter_table_reserve(ctx, table, 2 * mesh->element_count);
    if (status) return status;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        const rad_material *m = &scene->materials[scene->surfaces[s->element_surface[e]].material];
        double radiance[3];
        for (int c = 0; c < 3; ++c) radiance[c] = fmax(0, s->radiosity[e][c] / RAD_PI - m->emission[c]);
        if (!(radiance[0] > 0 || radiance[1] > 0 || radiance[2] > 0)) continue;
        const uint32_t *v = mesh->element_vertices[e];
        rad_vec3 normal = mesh->element_normal[e];
        rad_emitter_table_add(table, mesh->vertices[v[0]], mesh->vertices[v[1]], mesh->vertices[v[2]],
                              normal, radiance);
        if (rad_mesh_corner_count(mesh, e) == 4)
            rad_emitter_table_add(table, mesh->vertices[v[0]], mesh->vertices[v[2]],
                                  mesh->vertices[v[3]], normal, radiance);
    }
    return rad_emitter_table_finish(ctx, table, RAD_EMITTERS_BY_POWER);
}

rad_status rad_system_add_specular_reflection(rad_system *s) {
    rad_context *ctx = s->ctx;
    if (!s->specular_emission || s->specular_reflection || !s->mesh || !s->geometry ||
        s->geometry->surface_count != s->surface_count)
        return RAD_OK;
    uint64_t count = s->specular_photons;
    const rad_scene *scene = s->geometry;
    const rad_material **polygon_material =
        rad_alloc(ctx, scene->polygon_count + 1, sizeof *polygon_material);
    rad_emitter_table reflectors;
    memset(&reflectors, 0, sizeof reflectors);
    rad_light_emission sources;
    memset(&sources, 0, sizeof sources);
    rad_rays *rays = NULL;
    rad_element_rays *elements = NULL;
    rad_rgb *flux = rad_alloc_zero(ctx, s->element_count, sizeof *flux);
    rad_rgb *added = rad_alloc_zero(ctx, s->element_count, sizeof *added);
    rad_status status = polygon_material && flux && added ? RAD_OK : RAD_ERROR_NO_MEMORY;
    if (!status) status = build_reflectors(ctx, s, polygon_material, &reflectors);
    if (!status && reflectors.count == 0) goto done;
    /* The reflecting elements alone emit here (scene NULL: no lights, no sky). */
    if (!status) status = rad_light_emission_build(ctx, &reflectors, NULL, 0, &sources);
    if (!status) status = rad_rays_create(ctx, scene, &rays);
    if (!status) status = rad_element_rays_create(ctx, s->mesh, &elements);
    if (!status) {
        rad_photon_scene photons = {rays, polygon_material, &sources, scene};
        status = trace(ctx, &photons, elements, SPECULAR_SEED + 1, count, flux, NULL, NULL);
    }
    /* What lands is reflected once, as in the first pass, and joins the solution as light not
     * yet shot. */
    for (size_t e = 0; e < s->element_count && !status; ++e) {
        if (!(s->area[e] > 0)) continue;
        for (int c = 0; c < 3; ++c) {
            added[e][c] = s->reflectance[e][c] * flux[e][c] / (double)count / s->area[e];
            s->emission[e][c] += added[e][c];
            s->radiosity[e][c] += added[e][c];
            s->unshot[e][c] += added[e][c];
        }
    }
    if (!status) {
        s->specular_reflection = added;
        added = NULL;
    }
done:
    rad_element_rays_destroy(elements);
    rad_rays_destroy(rays);
    rad_emitter_table_free(ctx, &reflectors);
    rad_light_emission_free(ctx, &sources);
    rad_free(ctx, flux);
    rad_free(ctx, added);
    rad_free(ctx, (void *)polygon_material);
    return status;
}

void rad_system_remove_specular_reflection(rad_system *s) {
    if (!s || !s->specular_reflection) return;
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c) s->emission[e][c] -= s->specular_reflection[e][c];
    rad_free(s->ctx, s->specular_reflection);
    s->specular_reflection = NULL;
}
