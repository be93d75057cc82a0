/* photonmap.c - photon mapping (Jensen 1996, "Global illumination using photon maps"; Jensen
 * 2001, "Realistic Image Synthesis Using Photon Mapping"), docs/photonmapping.md.
 *
 * Pass 1, photon tracing: photons leave the emitter table (light/emitters.h) by power, cosine
 * distributed, with equal flux; at each surface with a diffuse or glossy lobe they are stored
 * (the global map; the caustic map too when every bounce so far was a mirror or glass one:
 * L S+ D paths), then scattered by the path tracer's BSDFs (scene/bsdf.h) with Russian
 * roulette on the scattering weight, so stored flux stays near the emitted flux. More photons
 * are traced for the caustic map alone (only specular bounces are followed).
 * Then irradiance is precomputed at every fourth global photon (Christensen 1999, "Faster photon
 * map global illumination") into a map of its own.
 * Pass 2, per camera sample: follow mirrors and glass from the camera; at the first point with a
 * diffuse or glossy lobe add emitted light, direct light (one emitter sample, as the path tracer's
 * next-event estimation), caustics (the caustic map's k nearest photons through the BSDF) and
 * indirect light: final-gather rays, cosine distributed, each ending (through mirrors and glass)
 * at a diffuse point y whose radiance is reflectance/pi times the precomputed irradiance nearest
 * to y. The delta lobes of that point go on with one BSDF sample.
 * Where a pixel holds an edge of a light (or of its image in a mirror) or shows glass, what it sees
 * of the sources directly or through mirrors and glass is taken from 16 times as many cheap rays
 * (splitting at every glass surface), the reflected light from the camera samples.
 * --progressive: passes with fresh photons and radii shrinking as in progressive photon mapping
 * (Hachisuka, Ogaki & Jensen 2008) in its probabilistic form (Knaus & Zwicker 2011: r_{i+1}^2 =
 * r_i^2 (i + alpha) / (i + 1)), each pass's image averaged in, so bias and noise both fall.
 * Every random number is an Owen-scrambled Sobol' point (core/sampler.h) indexed by the photon
 * or the pixel sample; photons are traced in fixed blocks whose stores are joined in block
 * order, so the maps and the image do not depend on the thread count. */
#include "core/context.h"
#include "render/lights_next_event.h"
#include "render/pathtrace.h"
#include "render/photon_map.h"
#include "scene/photon_path.h"
#include "scene/texture.h"

#include "image/image.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#define DEFAULT_SIZE 512
#define DEFAULT_SPP 4
#define DEFAULT_GATHER 16
#define DEFAULT_PHOTONS 200000
#define DEFAULT_NEAREST 20
#define DEFAULT_ALPHA (2.0 / 3.0)
#define PHOTON_BLOCK 4096
#define MAX_PHOTON_BOUNCES 64
#define MAX_SPECULAR_CHAIN 16  /* mirror and glass bounces followed from the camera or a gather */
#define GLASS_SPLITS 2 /* glass surfaces on a camera path where both lobes are followed */
#define STORES_PER_PHOTON 4.0  /* budget: photons stored per photon emitted, a generous average */
#define IRRADIANCE_STRIDE 4    /* irradiance precomputed at one global photon in four */
#define PHOTON_SALT 0x7f4a7c159e3779b9ull
#define GATHER_SALT 0x94d049bb133111ebull
#define SEEN_SALT 0xd6e8feb86659fd93ull
#define SEEN_SAMPLES 16 /* rays per camera sample for the sources seen, at a source's edge */
#define SEEN_GLASS_SAMPLES 4 /* the same where glass is seen (they split at every surface) */
#define SEEN_EDGE_CONTRAST 0.05f /* centres seeing sources this far apart make an edge */
#define SEEN_SPLITS MAX_SPECULAR_CHAIN /* glass splits of a path that only looks for sources */
#define SEEN_ROULETTE 0.05 /* its branches below this throughput play Russian roulette */
#define GATHER_DIM 256 /* the gather samplers' first dimension, past the camera path's */

/* The next surface along origin + t direction: its material, the hit and the point; NULL when the
 * ray leaves the scene (*left set: it sees the sky) or meets the back of a one-sided surface
 * (absorbed). A textured material comes back as a copy in *textured reflecting its texture at the
 * point (as the path tracer's). */
static const rad_material *next_surface(const rad_tracer *t, rad_vec3 origin, rad_vec3 direction,
                                        uint64_t *rays, rad_hit *hit, rad_vec3 *x,
                                        rad_material *textured, int *left) {
    ++*rays;
    *left = 0;
    if (!rad_rays_intersect(t->rays, origin, direction, t->rays->epsilon, INFINITY, hit)) {
        *left = 1;
        return NULL;
    }
    const rad_material *m = t->polygon_material[hit->polygon];
    if (!hit->front && m->kind != RAD_MATERIAL_GLASS) return NULL;
    *x = v3_add(origin, v3_scale(direction, hit->t));
    return rad_scene_material_at(t->scene, m, hit->polygon, *x, textured);
}

/* ---- photon tracing ----------------------------------------------------------------------- */

typedef struct photon_list {
    rad_photon *items;
    size_t count, capacity;
} photon_list;

static int list_push(rad_context *ctx, photon_list *list, const rad_photon *photon) {
    if (list->count == list->capacity) {
        size_t capacity = list->capacity ? 2 * list->capacity : 2 * PHOTON_BLOCK;
        rad_photon *grown = rad_realloc(ctx, list->items, capacity, sizeof *grown);
        if (!grown) return 0;
        list->items = grown;
        list->capacity = capacity;
    }
    list->items[list->count++] = *photon;
    return 1;
}

/* Where one photon is stored: the global map (unless caustic_only), and the caustic map for
 * L S+ D paths. */
typedef struct photon_stores {
    rad_context *ctx;
    int caustic_only;
    photon_list *global, *caustic;
    double global_share, caustic_share; /* 1 / the photons that could have fed each map */
} photon_stores;

/* Stored with its flux already divided by the photons that could have fed the map (packed once:
 * no unpacking and repacking when the map is built). */
static int store_photon(void *user, const rad_photon_arrival *a) {
    photon_stores *stores = user;
    rad_vec3 wi = v3_scale(a->direction, -1);
    double power[3];
    if (!stores->caustic_only) {
        for (int c = 0; c < 3; ++c) power[c] = a->power[c] * stores->global_share;
        rad_photon p = rad_photon_pack(a->position, power, a->hit.normal, wi);
        if (!list_push(stores->ctx, stores->global, &p)) return 0;
    }
    if (a->specular_path && a->bounce > 0) {
        for (int c = 0; c < 3; ++c) power[c] = a->power[c] * stores->caustic_share;
        rad_photon p = rad_photon_pack(a->position, power, a->hit.normal, wi);
        if (!list_push(stores->ctx, stores->caustic, &p)) return 0;
    }
    return 1;
}

/* One photon (scene/photon_path.h), then scattered until absorbed. With `caustic_only`, only
 * L S+ D photons are followed and stored. Returns 0 when out of memory. */
/* The photons of one pass: what they travel through, where they start, their sequence, and the
 * photon counts their flux is divided by in the global and caustic maps. */
typedef struct photon_source {
    const rad_tracer *t;
    const rad_light_emission *sources;
    uint64_t seed;
    double global_share, caustic_share;
} photon_source;

static int trace_photon(const photon_source *source, uint64_t index, int caustic_only,
                        photon_list *global, photon_list *caustic, uint64_t *rays) {
    const rad_tracer *t = source->t;
    rad_photon_scene scene = {t->rays, t->polygon_material, source->sources, t->scene};
    photon_stores stores = {t->ctx, caustic_only, global, caustic, source->global_share,
                            source->caustic_share};
    return rad_photon_path_trace(&scene, source->seed, index, caustic_only, MAX_PHOTON_BOUNCES,
                                 store_photon, &stores, rays);
}

/* Where one block's stores went: the thread that traced it and its runs in that thread's lists. */
typedef struct photon_block {
    int thread;
    size_t global_first, global_count, caustic_first, caustic_count;
} photon_block;

/* The stored photons of a pass as runs in block order (photon_map.h), kept in the lists of the
 * threads that traced them: the maps are built from the runs, with no joined copy (a joined
 * copy of hundreds of megabytes cost more in page faults than the tracing). */
typedef struct photon_runs {
    rad_photon_run *global, *caustic;
    size_t global_runs, caustic_runs, run_capacity;
    size_t global_count, caustic_count;
    photon_list *lists; /* every thread list of every trace_photons call */
    size_t list_count;
} photon_runs;

static void runs_free(rad_context *ctx, photon_runs *runs) {
    for (size_t i = 0; i < runs->list_count; ++i) rad_free(ctx, runs->lists[i].items);
    rad_free(ctx, runs->lists);
    rad_free(ctx, runs->global);
    rad_free(ctx, runs->caustic);
    memset(runs, 0, sizeof *runs);
}

/* Traces photons [first, first + count) of the sequence in blocks, in parallel. Each thread
 * stores into lists of its own, kept for all its blocks; each block's stores are then added to
 * `runs` in block order, so the maps are the same for any thread count. */
static rad_status trace_photons(const photon_source *source, uint64_t first, uint64_t count,
                                int caustic_only, int threads, photon_runs *runs, uint64_t *rays) {
    rad_context *ctx = source->t->ctx;
    size_t blocks = (size_t)((count + PHOTON_BLOCK - 1) / PHOTON_BLOCK);
    photon_block *block = rad_alloc_zero(ctx, blocks ? blocks : 1, sizeof *block);
    photon_list *lists = rad_realloc(ctx, runs->lists, runs->list_count + 2 * (size_t)threads,
                                     sizeof *lists);
    if (lists) {
        runs->lists = lists;
        memset(lists + runs->list_count, 0, 2 * (size_t)threads * sizeof *lists);
        lists += runs->list_count;
        runs->list_count += 2 * (size_t)threads;
    }
    size_t capacity = runs->run_capacity + blocks + 1;
    rad_photon_run *global_runs = rad_realloc(ctx, runs->global, capacity, sizeof *global_runs);
    if (global_runs) runs->global = global_runs;
    rad_photon_run *caustic_runs = rad_realloc(ctx, runs->caustic, capacity, sizeof *caustic_runs);
    if (caustic_runs) runs->caustic = caustic_runs;
    if (!block || !lists || !global_runs || !caustic_runs) {
        rad_free(ctx, block);
        return RAD_ERROR_NO_MEMORY;
    }
    runs->run_capacity = capacity;
    int failed = 0, cancelled = 0;
    long long done_blocks = 0;
    uint64_t total_rays = 0;
#pragma omp parallel num_threads(threads) reduction(+ : total_rays)
    {
        int me = omp_get_thread_num();
        photon_list *my_global = &lists[2 * me], *my_caustic = &lists[2 * me + 1];
#pragma omp for schedule(dynamic, 1)
        for (long long b = 0; b < (long long)blocks; ++b) {
            int stop;
#pragma omp atomic read
            stop = failed;
            if (stop) continue;
            uint64_t begin = first + (uint64_t)b * PHOTON_BLOCK;
            uint64_t end = first + count < begin + PHOTON_BLOCK ? first + count : begin + PHOTON_BLOCK;
            uint64_t block_rays = 0;
            block[b].thread = me;
            block[b].global_first = my_global->count;
            block[b].caustic_first = my_caustic->count;
            for (uint64_t i = begin; i < end; ++i)
                if (!trace_photon(source, i, caustic_only, my_global, my_caustic, &block_rays)) {
#pragma omp atomic write
                    failed = 1;
                    break;
                }
            block[b].global_count = my_global->count - block[b].global_first;
            block[b].caustic_count = my_caustic->count - block[b].caustic_first;
            total_rays += block_rays;
            long long done;
#pragma omp atomic capture
            done = ++done_blocks;
            if (me == 0 && rad_progress(ctx, "photon tracing", (double)done, (double)blocks)) {
#pragma omp atomic write
                cancelled = 1;
#pragma omp atomic write
                failed = 1;
            }
        }
    }
    *rays += total_rays;
    /* The runs, in block order (the lists no longer move). */
    for (size_t b = 0; b < blocks && !failed; ++b) {
        const photon_list *g = &lists[2 * block[b].thread], *c = &lists[2 * block[b].thread + 1];
        if (block[b].global_count) {
            runs->global[runs->global_runs++] =
                (rad_photon_run){g->items + block[b].global_first, block[b].global_count};
            runs->global_count += block[b].global_count;
        }
        if (block[b].caustic_count) {
            runs->caustic[runs->caustic_runs++] =
                (rad_photon_run){c->items + block[b].caustic_first, block[b].caustic_count};
            runs->caustic_count += block[b].caustic_count;
        }
    }
    rad_free(ctx, block);
    if (cancelled) return rad_fail(ctx, RAD_ERROR_CANCELLED, "photon mapping cancelled");
    if (failed) return RAD_ERROR_NO_MEMORY;
    return RAD_OK;
}

/* ---- the maps of one pass ----------------------------------------------------------------- */

typedef struct photon_pass {
    rad_photon_map global, caustic, irradiance; /* irradiance: `power` holds E */
    double radius, caustic_radius;
    size_t nearest; /* k; zero: every photon in the radius */
} photon_pass;

static void pass_free(rad_context *ctx, photon_pass *pass) {
    rad_photon_map_free(ctx, &pass->global);
    rad_photon_map_free(ctx, &pass->caustic);
    rad_photon_map_free(ctx, &pass->irradiance);
}

/* Total area of the surfaces where photons are stored. */
static double storing_area(const rad_tracer *t) {
    const rad_scene *scene = t->scene;
    double area = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        if (rad_bsdf_has_smooth_lobe(t->polygon_material[i]))
            area += rad_polygon_area(scene, &scene->polygons[i]);
    return area;
}

/* Irradiance at every IRRADIANCE_STRIDE-th global photon (Christensen 1999), as a map. */
static rad_status precompute_irradiance(rad_context *ctx, photon_pass *pass, int threads) {
    const rad_photon_map *global = &pass->global;
    size_t count = (global->count + IRRADIANCE_STRIDE - 1) / IRRADIANCE_STRIDE;
    rad_photon *points = rad_alloc(ctx, count ? count : 1, sizeof *points);
    size_t k = pass->nearest;
    rad_photon_near *scratch = k ? rad_alloc(ctx, (size_t)threads * k, sizeof *scratch) : NULL;
    if (!points || (k && !scratch)) {
        rad_free(ctx, points);
        rad_free(ctx, scratch);
        return RAD_ERROR_NO_MEMORY;
    }
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256)
    for (long long i = 0; i < (long long)count; ++i) {
        const rad_photon *p = &global->photons[(size_t)i * IRRADIANCE_STRIDE];
        rad_vec3 normal = rad_photon_normal(p), position = rad_photon_position(p);
        double e[3];
        rad_photon_map_irradiance(global, position, normal, pass->radius, k,
                                  k ? scratch + (size_t)omp_get_thread_num() * k : NULL, e);
        points[i] = rad_photon_pack(position, e, normal, rad_photon_incoming(p));
    }
    rad_free(ctx, scratch);
    return rad_photon_map_build(ctx, points, count, pass->radius, threads, &pass->irradiance);
}

/* ---- rendering ---------------------------------------------------------------------------- */

typedef struct render_state {
    const rad_tracer *t;
    const photon_pass *pass;
    size_t scratch_size;
} render_state;

/* Radiance leaving the diffuse point y (normal n) towards the gather ray: reflectance/pi times
 * the nearest precomputed irradiance on the same surface (or, with none near, the global map's
 * own estimate there). */
static void global_radiance(const render_state *r, const rad_material *m, rad_vec3 y, rad_vec3 n,
                            rad_photon_near *scratch, double out[3]) {
    const photon_pass *pass = r->pass;
    double r2, e[3];
    if (rad_photon_map_nearest_heap(&pass->irradiance, y, n, pass->radius, 1, scratch, &r2)) {
        rad_photon_power(scratch[0].photon, 1, e);
    } else {
        rad_photon_map_irradiance(&pass->global, y, n, pass->radius, pass->nearest, scratch, e);
    }
    for (int c = 0; c < 3; ++c) out[c] = fmax(0, m->reflectance[c]) / RAD_PI * e[c];
}

/* Caustic radiance at x towards wo: the k nearest caustic photons through the smooth BSDF. */
static void caustic_radiance(const render_state *r, const rad_material *m, rad_vec3 x,
                             rad_vec3 n, rad_vec3 wo, rad_photon_near *scratch, double out[3]) {
    const photon_pass *pass = r->pass;
    out[0] = out[1] = out[2] = 0;
    if (pass->caustic.count == 0) return;
    double r2;
    size_t k = pass->nearest ? pass->nearest : r->scratch_size;
    size_t found =
        rad_photon_map_nearest_heap(&pass->caustic, x, n, pass->caustic_radius, k, scratch, &r2);
    /* Of k found, the k-th (the heap's first) only sets the radius. */
    size_t first = pass->nearest && found == k && k > 1 ? 1 : 0;
    if (!(r2 > 0)) return;
    for (size_t i = first; i < found; ++i) {
        const rad_photon *p = scratch[i].photon;
        double f[3], pdf, power[3];
        if (!rad_bsdf_eval(m, n, wo, rad_photon_incoming(p), f, &pdf)) continue;
        rad_photon_power(p, 1, power);
        for (int c = 0; c < 3; ++c) out[c] += f[c] * power[c];
    }
    for (int c = 0; c < 3; ++c) out[c] /= RAD_PI * r2;
}

/* One final-gather ray from x along `direction`: through mirrors and glass to a diffuse point,
 * whose global-map radiance it returns (emission is left out: direct light is sampled). */
static void gather_ray(const render_state *r, rad_sampler *sampler, rad_vec3 x, rad_vec3 direction,
                       rad_photon_near *scratch, uint64_t *rays, double out[3]) {
    const rad_tracer *t = r->t;
    double throughput[3] = {1, 1, 1};
    out[0] = out[1] = out[2] = 0;
    for (int chain = 0; chain < MAX_SPECULAR_CHAIN; ++chain) {
        rad_hit hit;
        rad_vec3 y;
        rad_material textured;
        int left;
        const rad_material *m = next_surface(t, x, direction, rays, &hit, &y, &textured, &left);
        if (!m) {
            /* Straight to the sky: its direct light at x (the light it sends through mirrors and
             * glass is in the caustic map). */
            if (left && chain == 0) rad_sky_radiance(&t->scene->sky, direction, out);
            return;
        }
        if (!rad_bsdf_is_delta(m)) {
            double l[3];
            global_radiance(r, m, y, hit.normal, scratch, l);
            for (int c = 0; c < 3; ++c) out[c] = throughput[c] * l[c];
            return;
        }
        double u[4];
        rad_sampler_4d(sampler, u);
        rad_bsdf_sample s;
        if (rad_bsdf_sample_direction(m, hit.normal, v3_scale(direction, -1), u, &s) ==
            RAD_LOBE_NONE)
            return;
        for (int c = 0; c < 3; ++c) throughput[c] *= s.weight[c];
        x = y;
        direction = s.direction;
    }
}

/* The parts of a camera path's radiance: what it sees of the sources (emitting surfaces and the
 * sky, directly or through mirrors and glass) and the light reflected at its diffuse and glossy
 * points (direct, caustic, indirect). The image takes them together, or the seen sources apart
 * with more samples where they have an edge in the pixel (render_pass). */
enum { PART_SEEN = 1, PART_REFLECTED = 2, PART_ALL = 3 };

/* One camera sample's state: its samplers, the gather rays' sequence, which parts it adds. */
typedef struct camera_sample {
    rad_sampler *sampler, *gather;
    uint64_t gather_base;
    int gather_rays;
    int parts;
    int splits;     /* glass surfaces where both lobes are followed */
    int *met_glass; /* set when the path meets glass, or NULL */
    rad_photon_near *scratch;
    uint64_t *rays;
} camera_sample;

/* Russian roulette on a branch of a camera path that only looks for the sources it sees: one
 * whose throughput is below SEEN_ROULETTE goes on with probability throughput / SEEN_ROULETTE,
 * its throughput divided by it (so splitting at every glass surface keeps a bounded number of
 * branches, each of weight SEEN_ROULETTE or more). Returns 0 when the branch ends. */
static int seen_roulette(const camera_sample *cs, double throughput[3]) {
    double largest = fmax(throughput[0], fmax(throughput[1], throughput[2]));
    if (!(largest > 0)) return 0;
    if (cs->parts != PART_SEEN || largest >= SEEN_ROULETTE) return 1;
    double u[2];
    rad_sampler_2d(cs->sampler, u);
    double survive = largest / SEEN_ROULETTE;
    if (u[0] >= survive) return 0;
    for (int c = 0; c < 3; ++c) throughput[c] /= survive;
    return 1;
}

/* Adds to out[3] the radiance along a camera path from `origin` with `start` throughput, its
 * specular chain already `first_chain` long, that may still split at `splits` glass surfaces. */
static void camera_path(const render_state *r, const camera_sample *cs, rad_vec3 origin,
                        rad_vec3 direction, const double start[3], int first_chain, int splits,
                        double out[3]) {
    const rad_tracer *t = r->t;
    rad_sampler *sampler = cs->sampler, *gather = cs->gather;
    rad_photon_near *scratch = cs->scratch;
    uint64_t *rays = cs->rays;
    int gather_rays = cs->gather_rays;
    uint64_t gather_base = cs->gather_base;
    double throughput[3] = {start[0], start[1], start[2]};
    for (int chain = first_chain; chain < MAX_SPECULAR_CHAIN; ++chain) {
        rad_hit hit;
        rad_vec3 x;
        rad_material textured;
        int left;
        const rad_material *m = next_surface(t, origin, direction, rays, &hit, &x, &textured, &left);
        if (!m) {
            /* Left the scene: the sky, seen directly or through mirrors and glass. */
            if (left && (cs->parts & PART_SEEN)) {
                double sky[3];
                rad_sky_radiance(&t->scene->sky, direction, sky);
                for (int c = 0; c < 3; ++c) out[c] += throughput[c] * sky[c];
            }
            return;
        }
        rad_vec3 wo = v3_scale(direction, -1);
        /* Emission seen directly or through mirrors and glass. */
        if ((cs->parts & PART_SEEN) && hit.front && t->polygon_emitter[hit.polygon] >= 0)
            for (int c = 0; c < 3; ++c) out[c] += throughput[c] * m->emission[c];
        double u[4];
        rad_sampler_4d(sampler, u); /* (emitter point, lobe choice, spare) */
        if ((cs->parts & PART_REFLECTED) && rad_bsdf_has_smooth_lobe(m) && hit.front) {
            double l[3] = {0, 0, 0};
            /* Direct light: one point on the emitters (next-event estimation). */
            rad_emitter_point light;
            double f[3], pdf;
            if (t->emitters.count &&
                rad_emitter_table_sample(&t->emitters, u[0], u[1], x, hit.normal, &light) &&
                rad_bsdf_eval(m, hit.normal, wo, light.direction, f, &pdf)) {
                ++*rays;
                if (!rad_rays_occluded(t->rays, x, light.position)) {
                    double scale = fabs(v3_dot(light.direction, hit.normal)) / light.pdf;
                    for (int c = 0; c < 3; ++c) l[c] += f[c] * light.radiance[c] * scale;
                }
            }
            /* Point, spot and directional lights, each sampled exactly. */
            double one[3] = {1, 1, 1};
            rad_lights_next_event(t, m, x, hit.normal, wo, one, rays, l);
            /* Caustics from the caustic map. */
            double caustic[3];
            caustic_radiance(r, m, x, hit.normal, wo, scratch, caustic);
            for (int c = 0; c < 3; ++c) l[c] += caustic[c];
            /* Indirect light: cosine-distributed gather rays into the global map. */
            double indirect[3] = {0, 0, 0};
            for (int g = 0; g < gather_rays; ++g) {
                gather->index = gather_base + (uint64_t)g;
                gather->dimension = GATHER_DIM + 8 * (uint32_t)chain;
                double v[2];
                rad_sampler_2d(gather, v);
                rad_vec3 wi = rad_cosine_direction(hit.normal, v[0], v[1]);
                double cos_i = v3_dot(wi, hit.normal);
                if (!(cos_i > 0) || !rad_bsdf_eval(m, hit.normal, wo, wi, f, &pdf)) continue;
                double incoming[3];
                gather_ray(r, gather, x, wi, scratch, rays, incoming);
                for (int c = 0; c < 3; ++c) indirect[c] += f[c] * RAD_PI * incoming[c];
            }
            for (int c = 0; c < 3; ++c) l[c] += indirect[c] / gather_rays;
            for (int c = 0; c < 3; ++c) out[c] += throughput[c] * l[c];
        }
        /* Glass: both the reflection and the refraction, each weighted by its Fresnel share, in
         * place of choosing one (splitting, as a Whitted ray tracer does): the light's reflection
         * in the glass sphere, chosen by a few percent of the samples with all its weight, was
         * most of cornell-mirror's block error at 16 samples per pixel. */
        if (m->kind == RAD_MATERIAL_GLASS && cs->met_glass) *cs->met_glass = 1;
        if (m->kind == RAD_MATERIAL_GLASS && splits > 0) {
            double fresnel = rad_bsdf_glass_reflectance(m, hit.normal, wo);
            if (fresnel > 0 && fresnel < 1) {
                const double reflect_u[3] = {0, 0.5, 0.5}, refract_u[3] = {1, 0.5, 0.5};
                rad_bsdf_sample s;
                if (rad_bsdf_sample_direction(m, hit.normal, wo, reflect_u, &s) ==
                    RAD_LOBE_SPECULAR) {
                    double branch[3];
                    for (int c = 0; c < 3; ++c) branch[c] = throughput[c] * s.weight[c] * fresnel;
                    if (seen_roulette(cs, branch))
                        camera_path(r, cs, x, s.direction, branch, chain + 1, splits - 1, out);
                }
                if (rad_bsdf_sample_direction(m, hit.normal, wo, refract_u, &s) !=
                    RAD_LOBE_TRANSMISSION)
                    return;
                for (int c = 0; c < 3; ++c) throughput[c] *= s.weight[c] * (1 - fresnel);
                if (!seen_roulette(cs, throughput)) return;
                origin = x;
                direction = s.direction;
                --splits;
                continue;
            }
        }
        /* The delta lobes go on with one BSDF sample; the smooth ones are done above. */
        if (rad_bsdf_is_delta(m) || (m->kind != RAD_MATERIAL_DIFFUSE)) {
            double v[3] = {u[2], u[3], 0.5};
            double w[2];
            rad_sampler_2d(sampler, w);
            v[1] = w[0], v[2] = w[1];
            rad_bsdf_sample s;
            if (rad_bsdf_sample_direction(m, hit.normal, wo, v, &s) == RAD_LOBE_NONE || !s.delta)
                return;
            for (int c = 0; c < 3; ++c) throughput[c] *= s.weight[c];
            origin = x;
            direction = s.direction;
            continue;
        }
        return;
    }
}

/* The radiance of one camera sample (the parts `cs` asks for). */
static void camera_radiance(const render_state *r, const camera_sample *cs, rad_vec3 origin,
                            rad_vec3 direction, double out[3]) {
    const double one[3] = {1, 1, 1};
    out[0] = out[1] = out[2] = 0;
    camera_path(r, cs, origin, direction, one, 0, cs->splits, out);
}

/* ---- the image ---------------------------------------------------------------------------- */

static rad_status check_options(rad_context *ctx, const rad_photonmap_options *o) {
    if (o->width < 0 || o->height < 0 || o->samples_per_pixel < 0 || o->gather_rays < 0 ||
        o->nearest < 0 || o->iterations < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "photon mapping: sizes, samples, gather rays, nearest and iterations must "
                        "not be negative");
    if (!(o->radius >= 0) || !isfinite(o->radius))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "photon mapping: the radius must be positive and finite");
    if (!(o->alpha >= 0 && o->alpha < 1))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "photon mapping: alpha must be in (0, 1)");
    return RAD_OK;
}

/* Emits the photons of pass `iteration` and builds its maps. */
static rad_status build_pass(const rad_tracer *t, const rad_light_emission *sources,
                             const rad_photonmap_options *o, uint64_t photons,
                             uint64_t caustic_photons, int iteration, double radius,
                             int threads, photon_pass *pass, rad_photonmap_stats *stats) {
    rad_context *ctx = t->ctx;
    uint64_t seed = rad_mix64(ctx->seed ^ PHOTON_SALT) + (uint64_t)iteration;
    photon_runs runs;
    memset(&runs, 0, sizeof runs);
    uint64_t rays = 0;
    double start = rad_seconds(), cpu = rad_processor_seconds();
    /* Each stored photon's flux over the photons that could have fed its map. */
    photon_source source = {t, sources, seed, 1.0 / (double)photons,
                            1.0 / ((double)photons + (double)caustic_photons)};
    rad_status status = trace_photons(&source, 0, photons, 0, threads, &runs, &rays);
    if (!status && caustic_photons)
        status = trace_photons(&source, photons, caustic_photons, 1, threads, &runs, &rays);
    stats->trace_seconds += rad_seconds() - start;
    stats->trace_cpu_seconds += rad_processor_seconds() - cpu;
    stats->photons_emitted += photons + caustic_photons;
    if (status) {
        runs_free(ctx, &runs);
        return status;
    }
    pass->nearest = (size_t)(o->nearest ? o->nearest : DEFAULT_NEAREST);
    if (radius > 0) {
        pass->radius = radius;
    } else {
        /* The radius whose disc holds `nearest` photons on average over the storing surfaces. */
        double area = storing_area(t);
        pass->radius =
            runs.global_count ? sqrt(pass->nearest * area / (RAD_PI * runs.global_count)) : 1;
        if (!(pass->radius > 0)) pass->radius = 1;
    }
    pass->caustic_radius = pass->radius;
    if (o->iterations > 1) pass->nearest = 0; /* progressive: fixed, shrinking radii */
    stats->global_stored = runs.global_count;
    stats->caustic_stored = runs.caustic_count;
    start = rad_seconds();
    status = rad_photon_map_build_runs(ctx, runs.global, runs.global_runs, pass->radius, threads,
                                       &pass->global);
    if (!status)
        status = rad_photon_map_build_runs(ctx, runs.caustic, runs.caustic_runs,
                                           pass->caustic_radius, threads, &pass->caustic);
    runs_free(ctx, &runs);
    if (!status) status = precompute_irradiance(ctx, pass, threads);
    stats->build_seconds += rad_seconds() - start;
    stats->radius = pass->radius;
    stats->caustic_radius = pass->caustic_radius;
    return status;
}

/* What the ray through the middle of each pixel sees of the sources (PART_SEEN): its luminance
 * into seen[width * height], and into glass[] whether it met glass. */
static void seen_at_centres(const render_state *r, const rad_view *view, int threads, float *seen,
                            uint8_t *glass, uint64_t *rays_out) {
    uint64_t seed = (r->t->ctx->seed ^ SEEN_SALT) + 1, total_rays = 0;
    int width = view->width, height = view->height;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 4) reduction(+ : total_rays)
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            rad_sampler sampler =
                rad_sampler_make(seed, rad_sampler_pixel_index((uint32_t)x, (uint32_t)y, 1, 0));
            uint64_t rays = 0;
            int met_glass = 0;
            camera_sample cs = {&sampler, NULL, 0, 0, PART_SEEN, GLASS_SPLITS, &met_glass, NULL,
                                &rays};
            double radiance[3];
            camera_radiance(r, &cs, view->eye, rad_view_direction(view, x + 0.5, y + 0.5),
                            radiance);
            size_t i = (size_t)y * (size_t)width + (size_t)x;
            seen[i] = (float)((radiance[0] + radiance[1] + radiance[2]) / 3);
            glass[i] = (uint8_t)met_glass;
            total_rays += rays;
        }
    *rays_out += total_rays;
}

/* How many rays per camera sample pixel (x, y) takes the sources it sees from, apart from the
 * reflected light (render_pass; 0: none, they come with the samples): SEEN_SAMPLES when the
 * centres of its 3 x 3 neighbourhood see sources that differ by more than SEEN_EDGE_CONTRAST of
 * the brightest (an edge of a light, or of its image in a mirror or through glass), else
 * SEEN_GLASS_SAMPLES when one of them meets glass (where a light is seen after several glass
 * surfaces, along paths a few samples miss). */
static int seen_apart(const float *seen, const uint8_t *glass, int width, int height, int x,
                      int y) {
    float lo = INFINITY, hi = 0;
    int met_glass = 0;
    for (int j = y > 0 ? y - 1 : 0; j <= y + 1 && j < height; ++j)
        for (int i = x > 0 ? x - 1 : 0; i <= x + 1 && i < width; ++i) {
            size_t k = (size_t)j * (size_t)width + (size_t)i;
            met_glass |= glass[k];
            lo = fminf(lo, seen[k]), hi = fmaxf(hi, seen[k]);
        }
    if (hi > 0 && hi - lo > SEEN_EDGE_CONTRAST * hi) return SEEN_SAMPLES;
    return met_glass ? SEEN_GLASS_SAMPLES : 0;
}

/* Adds pass `iteration`'s estimate to `sum` (per pixel, summed over samples). A pixel holding an
 * edge of a seen source (the light's outline, its image in the mirror) takes what it sees of the
 * sources from SEEN_SAMPLES times as many camera rays (they only follow mirrors and glass), the
 * reflected light from the `spp` samples: 16 samples put a light's edge into a pixel only in
 * steps of 1/16 of its coverage, which was the largest 16x16-block error of both Cornell boxes
 * against the path tracer (the row of pixels the light's front edge crosses). The estimate stays
 * unbiased: which pixels are edges depends on the centre rays alone. */
static rad_status render_pass(const rad_tracer *t, const photon_pass *pass, const rad_view *view,
                              int spp, int gather_rays, int iteration, int iterations, int threads,
                              double *sum, uint64_t *rays_out) {
    rad_context *ctx = t->ctx;
    render_state r = {t, pass, 0};
    r.scratch_size = pass->nearest ? pass->nearest : 4096;
    int width = view->width, height = view->height;
    rad_photon_near *scratch = rad_alloc(ctx, (size_t)threads * r.scratch_size, sizeof *scratch);
    float *seen = rad_alloc(ctx, (size_t)width * (size_t)height, sizeof *seen);
    uint8_t *glass = rad_alloc(ctx, (size_t)width * (size_t)height, sizeof *glass);
    if (!scratch || !seen || !glass) {
        rad_free(ctx, scratch);
        rad_free(ctx, seen);
        rad_free(ctx, glass);
        return RAD_ERROR_NO_MEMORY;
    }
    seen_at_centres(&r, view, threads, seen, glass, rays_out);
    int rows_done = 0, cancelled = 0;
    uint64_t total_rays = 0;
    uint64_t seed = ctx->seed;
    uint32_t samples = (uint32_t)spp * (uint32_t)iterations;
#pragma omp parallel num_threads(threads) reduction(+ : total_rays)
    {
        rad_photon_near *mine = scratch + (size_t)omp_get_thread_num() * r.scratch_size;
        uint64_t rays = 0;
#pragma omp for schedule(dynamic, 1)
        for (int y = 0; y < height; ++y) {
            int stop;
#pragma omp atomic read
            stop = cancelled;
            if (stop) continue;
            for (int x = 0; x < width; ++x) {
                double *p = sum + 3 * ((size_t)y * (size_t)width + (size_t)x);
                int seen_rays = seen_apart(seen, glass, width, height, x, y);
                for (int s = 0; s < spp; ++s) {
                    uint32_t sample = (uint32_t)(iteration * spp + s);
                    rad_sampler sampler = rad_sampler_make(
                        seed, rad_sampler_pixel_index((uint32_t)x, (uint32_t)y, samples, sample));
                    uint64_t gather_base = rad_sampler_pixel_index(
                        (uint32_t)x, (uint32_t)y, samples * (uint32_t)gather_rays,
                        sample * (uint32_t)gather_rays);
                    rad_sampler gather = rad_sampler_make(seed ^ GATHER_SALT, gather_base);
                    double jitter[4];
                    rad_sampler_4d(&sampler, jitter);
                    camera_sample cs = {&sampler, &gather, gather_base, gather_rays,
                                        seen_rays ? PART_REFLECTED : PART_ALL, GLASS_SPLITS, NULL,
                                        mine, &rays};
                    double radiance[3];
                    camera_radiance(&r, &cs, view->eye,
                                    rad_view_direction(view, x + jitter[0], y + jitter[1]),
                                    radiance);
                    for (int c = 0; c < 3; ++c) p[c] += radiance[c];
                }
                /* The sources seen, from seen_rays times as many rays, each worth
                 * 1 / seen_rays. */
                for (int s = 0; s < spp * seen_rays; ++s) {
                    uint32_t sample = (uint32_t)(iteration * spp * SEEN_SAMPLES + s);
                    rad_sampler sampler = rad_sampler_make(
                        seed ^ SEEN_SALT,
                        rad_sampler_pixel_index((uint32_t)x, (uint32_t)y, samples * SEEN_SAMPLES,
                                                sample));
                    double jitter[4];
                    rad_sampler_4d(&sampler, jitter);
                    camera_sample cs = {&sampler, NULL, 0, 0, PART_SEEN, SEEN_SPLITS, NULL, NULL,
                                        &rays};
                    double radiance[3];
                    camera_radiance(&r, &cs, view->eye,
                                    rad_view_direction(view, x + jitter[0], y + jitter[1]),
                                    radiance);
                    for (int c = 0; c < 3; ++c) p[c] += radiance[c] / seen_rays;
                }
            }
            int done;
#pragma omp atomic capture
            done = ++rows_done;
            if (omp_get_thread_num() == 0 &&
                rad_progress(ctx, "photon mapping", iteration * height + done,
                             (double)iterations * height)) {
#pragma omp atomic write
                cancelled = 1;
            }
        }
        total_rays += rays;
    }
    rad_free(ctx, scratch);
    rad_free(ctx, seen);
    rad_free(ctx, glass);
    *rays_out += total_rays;
    if (cancelled) return rad_fail(ctx, RAD_ERROR_CANCELLED, "photon mapping cancelled");
    return RAD_OK;
}

rad_status rad_photonmap(rad_context *ctx, const rad_scene *scene,
                         const rad_photonmap_options *options, rad_image **out,
                         rad_photonmap_stats *stats) {
    *out = NULL;
    double start = rad_seconds();
    rad_photonmap_options o = options ? *options : (rad_photonmap_options){0};
    rad_status status = check_options(ctx, &o);
    if (status) return status;
    if (!scene) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "photon mapping: no scene");
    if (!scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: photon mapping needs geometry, not a patch system", scene->source);
    int width = o.width ? o.width : DEFAULT_SIZE, height = o.height ? o.height : DEFAULT_SIZE;
    int spp = o.samples_per_pixel ? o.samples_per_pixel : DEFAULT_SPP;
    int gather_rays = o.gather_rays ? o.gather_rays : DEFAULT_GATHER;
    int iterations = o.iterations > 1 ? o.iterations : 1;
    uint64_t photons = o.photons ? o.photons : DEFAULT_PHOTONS;
    uint64_t caustic_photons = o.caustic_photons ? o.caustic_photons : photons;
    if (!rad_scene_has_specular(scene)) caustic_photons = 0; /* no mirror or glass: no caustics */
    double alpha = o.alpha > 0 ? o.alpha : DEFAULT_ALPHA;
    if ((uint64_t)spp * (uint64_t)iterations *
            (uint64_t)(gather_rays > SEEN_SAMPLES ? gather_rays : SEEN_SAMPLES) >
        UINT32_MAX / 2)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "photon mapping: samples x iterations x gather rays is too large");
    /* The budget, before anything is allocated: the stored photons (a generous
     * STORES_PER_PHOTON per photon emitted), the grid and the image's sums. */
    status = rad_check_budget(ctx,
                              ((double)photons + (double)caustic_photons) * STORES_PER_PHOTON *
                                      (sizeof(rad_photon) * 2 + 2 * sizeof(uint32_t)) +
                                  (double)width * height * 3 * (sizeof(double) + sizeof(float)),
                              "photon mapping");
    if (status) return status;

    rad_camera camera = o.camera ? rad_camera_from_desc(o.camera) : rad_scene_camera(scene);
    rad_view view;
    status = rad_view_make(ctx, &camera, width, height, &view);
    if (status) return status;
    rad_tracer *t;
    status = rad_tracer_create(ctx, scene, 0, &t);
    if (status) return status;
    status = rad_tracer_check_view(t, &view);
    if (status) {
        rad_tracer_destroy(t);
        return status;
    }
    rad_photonmap_stats st = {0};
    rad_image *image = NULL;
    double *sum = NULL;
    status = rad_image_new(ctx, width, height, &image);
    if (!status) {
        sum = rad_alloc_zero(ctx, (size_t)width * (size_t)height * 3, sizeof *sum);
        if (!sum) status = RAD_ERROR_NO_MEMORY;
    }
    /* Photons leave the emitting surfaces, the point, spot and directional lights and the sky,
     * by power (scene/light_emission.h). */
    rad_light_emission sources;
    memset(&sources, 0, sizeof sources);
    if (!status) status = rad_light_emission_build(ctx, &t->emitters, scene, 1, &sources);
    if (!status && !rad_scene_is_lit(scene))
        rad_warn(ctx, "%s: nothing emits light: the image is black", scene->source);
    if (!status && !(sources.total_power > 0)) {
        /* Nothing to trace: a black image. */
        if (rad_scene_is_lit(scene))
            rad_warn(ctx, "%s: the lights send no power: the image is black", scene->source);
        iterations = 0;
    }
    int threads = rad_thread_count(ctx);
    double radius = o.radius;
    for (int i = 0; i < iterations && !status; ++i) {
        photon_pass pass;
        memset(&pass, 0, sizeof pass);
        status = build_pass(t, &sources, &o, photons, caustic_photons, i, radius, threads, &pass,
                            &st);
        if (!status) {
            double render_start = rad_seconds();
            status = render_pass(t, &pass, &view, spp, gather_rays, i, iterations, threads, sum,
                                 &st.rays);
            st.render_seconds += rad_seconds() - render_start;
        }
        /* Progressive: the next pass's radius^2 shrinks by (i + alpha) / (i + 1). */
        radius = pass.radius * sqrt((i + 1 + alpha) / (i + 2));
        pass_free(ctx, &pass);
    }
    rad_light_emission_free(ctx, &sources);
    rad_tracer_destroy(t);
    if (!status && image) {
        double samples = (double)spp * (iterations ? iterations : 1);
        for (size_t i = 0; i < (size_t)width * (size_t)height * 3; ++i)
            image->pixels[i] = (float)(sum[i] / samples);
    }
    rad_free(ctx, sum);
    if (status) {
        rad_image_free(image);
        return status;
    }
    st.seconds = rad_seconds() - start;
    if (stats) *stats = st;
    *out = image;
    return RAD_OK;
}
