/* render.c - the renderer: options, camera, the pixel loop on all cores, the public API (see
 * render.h and docs/rendering.md).
 *
 * Each pixel averages samples_per_pixel camera rays through jittered points of the pixel (a box
 * filter), as the path tracer does. Every pixel draws its samples (pixel position, gather
 * directions, light points) as Owen-scrambled Sobol' points keyed by (seed, pixel, dimension)
 * (core/sampler.h), so the image does not depend on the thread count or on the order rows are
 * handed out. */
#include "render/render.h"

#include "image/image.h"

#include <omp.h>
#include <stdio.h>
#include <string.h>

#define DEFAULT_SIZE 512
#define DEFAULT_SAMPLES 4
#define DEFAULT_MAX_DEPTH 16
#define MAX_SAMPLES (1 << 20)
/* Camera probe: rays per side of the grid that checks the camera sees something. */
#define PROBE_SIDE 64

int rad_shading_parse(const char *name) {
    if (!name) return -1;
    if (strcmp(name, "smooth") == 0) return RAD_SHADING_SMOOTH;
    if (strcmp(name, "flat") == 0) return RAD_SHADING_FLAT;
    return -1;
}

/* Frees what was built from one generation of the solution's leaves. */
static void leaves_free(rad_renderer *r) {
    rad_context *ctx = r->ctx;
    if (r->inner_rays != r->rays) rad_element_rays_destroy(r->inner_rays);
    rad_element_rays_destroy(r->rays);
    rad_emitter_table_free(ctx, &r->emitters);
    rad_free(ctx, r->element_emitter);
    rad_free(ctx, r->fit_vertex);
    rad_free(ctx, r->fit_first);
    rad_free(ctx, r->fit_size);
    rad_free(ctx, r->fit_element);
    rad_free(ctx, r->fit_weight);
    rad_free(ctx, r->vertex_radiance);
    rad_free(ctx, r->element_radiance);
    rad_free(ctx, r->element_emission);
    rad_free(ctx, r->element_reflectance);
    rad_free(ctx, r->vertex_irradiance);
    r->vertex_irradiance = NULL;
    rad_free(ctx, r->corner_deposit);
    r->corner_deposit = NULL;
    rad_free(ctx, r->corner_radiance);
    r->corner_radiance = NULL;
    rad_free(ctx, r->corner_collocated);
    r->corner_collocated = NULL;
    rad_free(ctx, (void *)r->element_uneven);
    r->element_uneven = NULL;
    rad_free(ctx, (void *)r->element_near);
    r->element_near = NULL;
    r->rays = r->inner_rays = NULL;
    memset(&r->emitters, 0, sizeof r->emitters);
    r->element_emitter = NULL;
    r->fit_count = 0;
    r->fit_vertex = r->fit_first = r->fit_size = r->fit_element = NULL;
    r->fit_weight = NULL;
    r->vertex_radiance = r->element_radiance = r->element_emission = r->element_reflectance = NULL;
}

/* Builds, from the solution's current leaves, the rays, the emitter table, the reconstruction
 * weights and the radiance arrays. */
static rad_status leaves_build(rad_renderer *r) {
    rad_context *ctx = r->ctx;
    leaves_free(r);
    r->leaves_ready = 0;
    r->generation = rad_solution_generation(r->solution);
    const rad_mesh *mesh = r->mesh = rad_solution_leaves(r->solution);
    rad_regather_choose(r, r->solution && r->solution->ops ? r->solution->ops->leaf_kind : RAD_LEAVES_UNIFORM);
    if (!mesh && r->system->geometry) {
        /* A scene's solution always has leaves: its view failed to build them and said why
         * (the hierarchy's, out of memory). */
        char why[RAD_ERROR_MESSAGE_SIZE];
        snprintf(why, sizeof why, "%s", rad_context_error(ctx));
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "render: %s", why);
    }
    if (!mesh)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "render: the solution has no leaves");
    r->vertex_radiance = rad_alloc(ctx, mesh->vertex_count + 1, sizeof *r->vertex_radiance);
    r->element_radiance = rad_alloc(ctx, mesh->element_count + 1, sizeof *r->element_radiance);
    r->element_emission = rad_alloc(ctx, mesh->element_count + 1, sizeof *r->element_emission);
    r->element_reflectance = rad_alloc(ctx, mesh->element_count + 1, sizeof *r->element_reflectance);
    if (!r->vertex_radiance || !r->element_radiance || !r->element_emission ||
        !r->element_reflectance)
        return RAD_ERROR_NO_MEMORY;
    rad_status status = rad_element_rays_create(ctx, mesh, &r->rays);
    /* Gather and shadow rays on a structure without Embree's robust traversal (see render.h). */
    r->inner_rays = r->rays;
    if (!status && r->settings.final_gather > 0)
        status = rad_element_rays_create_with(ctx, mesh, 0, &r->inner_rays);
    if (!status) status = rad_emitters_build(r);
    if (!status) status = rad_penumbra_prepare(r);
    if (!status) status = rad_regather_prepare(r);
    /* More lamps than the exact choice takes (a light tree, light/emitters.h): its samples find
     * their lamps less well, their noise is most of the image's, and their shadow rays are a
     * small part of the rays, so twice as many by default. Office 100000 (841 lamps), seeds
     * 0 / 1: 4x4 RMSE 2.74 / 2.54% -> 2.19 / 2.06% for 1-3% more processor time; office 20000
     * (169 lamps, the exact choice) gained 4% for 9% more, Cornell 3.5% for 5% more, so they
     * keep half the gather rays (docs/rendering.md, "Twice the emitter samples under a light
     * tree"). */
    if (!status && r->settings.light_samples_default)
        r->settings.light_samples = r->settings.light_samples_default * (r->emitters.nodes ? 2 : 1);
    if (!status) status = rad_reconstruct_build(r);
    r->leaves_ready = status == RAD_OK;
    return status;
}

void rad_renderer_destroy(rad_renderer *r) {
    if (!r) return;
    rad_context *ctx = r->ctx;
    leaves_free(r);
    rad_photon_map_free(ctx, &r->caustics);
    rad_free(ctx, r->surface_material);
    rad_lights_free(ctx, r->lights, r->light_count);
    rad_free(ctx, r);
}

static rad_status settings_from(rad_context *ctx, const rad_render_options *o,
                                rad_render_settings *s) {
    rad_render_options zero = {0};
    if (!o) o = &zero;
    if (o->width < 0 || o->height < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "image size %dx%d: each side must be 1 to 16384 pixels", o->width,
                        o->height);
    if (o->samples_per_pixel < 0 || o->samples_per_pixel > MAX_SAMPLES)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "samples per pixel must be 1 to %d, not %d", MAX_SAMPLES,
                        o->samples_per_pixel);
    if (o->final_gather < 0 || o->final_gather > RAD_RENDER_MAX_GATHER || o->light_samples < 0 ||
        o->light_samples > RAD_RENDER_MAX_GATHER)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "final gather: rays and light samples must be 0 to %d",
                        RAD_RENDER_MAX_GATHER);
    if (o->max_depth < 0 || o->max_depth > 1000)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "max depth must be 0 to 1000, not %d", o->max_depth);
    if (o->shading != RAD_SHADING_SMOOTH && o->shading != RAD_SHADING_FLAT)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "unknown shading %d", (int)o->shading);
    s->width = o->width ? o->width : DEFAULT_SIZE;
    s->height = o->height ? o->height : DEFAULT_SIZE;
    s->samples_per_pixel = o->samples_per_pixel ? o->samples_per_pixel : DEFAULT_SAMPLES;
    s->shading = o->shading;
    s->final_gather = o->final_gather;
    s->gather_filter = !o->no_gather_filter;
    /* Emitter samples: half the gather rays with the irradiance filter, which takes the gather
     * rays' noise away and leaves the penumbras' (Cornell 256: 4x4 RMSE 1.06 % -> 0.90 %, seed
     * 1), a quarter without it (where the gather rays' noise is most of it). */
    int share = s->gather_filter ? 2 : 4;
    s->light_samples_default = o->light_samples || o->final_gather <= 0
                                   ? 0
                                   : (o->final_gather + share - 1) / share;
    s->light_samples = o->light_samples ? o->light_samples : s->light_samples_default;
    s->max_depth = o->max_depth ? o->max_depth : DEFAULT_MAX_DEPTH;
    s->ambient = o->ambient;
    return RAD_OK;
}

/* Refuses cameras that see nothing, warns of one that sees only the backs of one-sided
 * surfaces (scene/camera.h's rule, the same for every image command); the sky is seen. */
static int renderer_see(const void *user, rad_vec3 eye, rad_vec3 direction, int *front,
                        const char **surface) {
    const rad_renderer *r = user;
    rad_element_hit hit;
    if (!rad_element_rays_intersect(r->rays, eye, direction, 0, INFINITY, &hit)) {
        *front = 1;
        *surface = "sky";
        return r->sky.kind != RAD_SKY_OFF;
    }
    *front = hit.front || rad_renderer_material(r, hit.element)->kind == RAD_MATERIAL_GLASS;
    *surface = r->system->surface_name[r->mesh->element_surface[hit.element]];
    return 1;
}

static rad_status probe_camera(const rad_renderer *r) {
    return rad_view_check(r->ctx, &r->view, renderer_see, r);
}

static rad_status renderer_create(const rad_scene *scene, const rad_system *system,
                                  const rad_render_options *options, int for_pictures,
                                  rad_renderer **out) {
    if (!out) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    if (!scene || !system) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = system->ctx;
    if (!rad_solution_leaves(rad_system_view(system)) || !scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: a patch system has no geometry to render", scene->source);
    if (scene->surface_count != system->surface_count)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "render: the scene is not the one the system was built from");
    rad_render_settings settings;
    rad_status status = settings_from(ctx, options, &settings);
    if (status) return status;
    rad_camera camera =
        options && options->camera ? rad_camera_from_desc(options->camera) : rad_scene_camera(scene);
    rad_view view;
    status = rad_view_make(ctx, &camera, settings.width, settings.height, &view);
    if (status) return status;
    /* The image, before the work: a size that cannot be kept fails now, not after the solve. */
    status = rad_check_budget(ctx, (double)settings.width * settings.height * 3 * sizeof(float),
                              "the image");
    if (status) return status;

    rad_renderer *r = rad_alloc_zero(ctx, 1, sizeof *r);
    if (!r) return RAD_ERROR_NO_MEMORY;
    r->ctx = ctx;
    r->system = system;
    r->solution = rad_system_view(system);
    r->view = view;
    r->settings = settings;
    r->seed = ctx->seed;
    r->surface_count = scene->surface_count;
    r->surface_material = rad_alloc_zero(ctx, scene->surface_count + 1, sizeof *r->surface_material);
    if (!r->surface_material) {
        rad_renderer_destroy(r);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t s = 0; s < scene->surface_count; ++s) {
        r->surface_material[s] = scene->materials[scene->surfaces[s].material];
        r->surface_material[s].name = NULL; /* the scene may go away */
    }
    r->sky = scene->sky;
    status = rad_lights_copy(ctx, scene->lights, scene->light_count, &r->lights);
    if (!status) r->light_count = scene->light_count;
    if (!status) status = leaves_build(r);
    if (!status) status = rad_caustics_build(r);
    if (!status && for_pictures) status = probe_camera(r);
    if (status) {
        rad_renderer_destroy(r);
        return status;
    }
    *out = r;
    return RAD_OK;
}

rad_status rad_renderer_create(const rad_scene *scene, const rad_system *system,
                               const rad_render_options *options, rad_renderer **out) {
    return renderer_create(scene, system, options, 1, out);
}

rad_status rad_renderer_create_for_points(const rad_scene *scene, const rad_system *system,
                                          const rad_render_options *options, rad_renderer **out) {
    return renderer_create(scene, system, options, 0, out);
}

/* Pixels on an edge between input polygons (a wall against the black outside, the light against
 * the ceiling, a block against the floor) are split by what covers them. A pixel is on an edge
 * when the camera rays through its four corners (one grid of (width + 1) x (height + 1) rays
 * for the image, corner_polygons) do not all meet the same face (surface and normal): any
 * straight edge that crosses the pixel separates its corners. How much of such a pixel each polygon covers is
 * measured by COVERAGE_RAYS camera rays that only find the polygon (RAD_RENDER_DIM_COVERAGE,
 * one (0,m,2)-net over the pixel: a straight edge is placed to 1/64 of the pixel, not the 1/16
 * of 16 samples), and the pixel is the sum over the polygons of that fraction times the mean of
 * its samples that met the polygon. A polygon only the coverage rays found is shaded at the
 * first of them (with its own sampler seed). With the light beside the ceiling, 150 times
 * darker, a coverage error weighs 150 times more: when a corner ray near the pixel met an
 * emitter, or one polygon's samples are over BRIGHT times the pixel's mean, BRIGHT_RAYS are
 * cast instead (the light's corner inside a pixel was missed by 64). The choice of pixels does not depend on
 * the samples, and each fraction and each mean is unbiased and independent of the others, so
 * the pixel still converges to the box filter the path tracer converges to. (Choosing the
 * pixels by their samples instead, where they met two polygons, lost the light's thin slivers
 * no sample met: the mean 0.65% dark at 4 samples per pixel.) More than MAX_GROUPS polygons:
 * the plain mean; so is one sample per pixel. */
#define COVERAGE_RAYS 64
#define BRIGHT_RAYS 256
/* Pixels where a surface's edge meets the black outside (the box's front edges): a sliver of
 * a wall is the whole pixel's light, and at 64 rays a 0.7 % sliver (the red wall's front edge
 * in the Cornell box's fourth column) is met by 0 or 1 of them. They are measured along scan
 * lines (scan_coverage, below), about 240 rays a pixel; 1024 coverage rays did it before
 * (2.4 of the Cornell box's 3.5 million camera rays at 256 x 256). */
#define BRIGHT 4.0
#define MAX_GROUPS 8
#define EXTRA_SEED_SALT 0x3c6ef372fe94f82bull

typedef struct pixel_group {
    uint32_t polygon;
    int shaded;
    double covered; /* coverage rays that met it, or length of the scan lines' (scan_coverage) */
    double sum[3];
} pixel_group;

static int group_of(pixel_group *groups, int *count, uint32_t polygon) {
    for (int g = 0; g < *count; ++g)
        if (groups[g].polygon == polygon) return g;
    if (*count == MAX_GROUPS) return -1;
    pixel_group *g = &groups[(*count)++];
    memset(g, 0, sizeof *g);
    g->polygon = polygon;
    return *count - 1;
}

static double luminance(const double c[3]) { return (c[0] + c[1] + c[2]) / 3; }

/* Pixels against the outside: their coverage along SCAN_LINES lines across the pixel, each
 * cut into SCAN_PIECES pieces whose ends are traced; a piece whose two ends meet different
 * polygons is halved (one more ray) until it is SCAN_FINEST of the pixel long, then split
 * evenly between them. A straight edge is so placed to 1/4096 of the pixel on each line for
 * about 10 rays (about 240 a pixel, where the 1024 coverage rays used before counted the share
 * to about 1/1000). The lines run across the edge: horizontal ones (at stratified heights of
 * the pixel's own sequence, so the mean over them is unbiased) unless the pixel's corners say
 * the edge runs along the rows. For an edge that crosses two opposite sides the covered length
 * is linear across the lines and their mean is off by about 0.005 times the edge's slope
 * (tests/test_render.c, test_scan_coverage). */
#define SCAN_LINES 16
#define SCAN_PIECES 4
#define SCAN_FINEST (1.0 / 4096)

typedef struct scan_state {
    const rad_renderer *r;
    rad_sample *sample, *extra;
    pixel_group *groups;
    int *count;
    int vertical;     /* lines at constant x */
    double position;  /* the line's y (x when vertical), in the pixel */
} scan_state;

/* The polygon the camera ray through point t of the current line meets (shading a polygon no
 * sample met there); -1 when the pixel has too many polygons. */
static int scan_point(scan_state *s, double t) {
    const rad_view *view = &s->r->view;
    double px = s->sample->x + (s->vertical ? s->position : t);
    double py = s->sample->y + (s->vertical ? t : s->position);
    rad_vec3 direction = rad_view_direction(view, px, py);
    rad_element_hit hit;
    s->sample->counts->camera++;
    uint32_t polygon = rad_element_rays_intersect(s->r->rays, view->eye, direction, 0, INFINITY, &hit)
                           ? s->r->mesh->element_polygon[hit.element]
                           : RAD_RENDER_NO_POLYGON;
    int g = group_of(s->groups, s->count, polygon);
    if (g < 0) return -1;
    pixel_group *group = &s->groups[g];
    if (group->shaded == 0 && s->extra->index < s->extra->count) {
        double radiance[3];
        rad_trace_radiance(s->r, s->extra, view->eye, direction, NULL, radiance);
        s->extra->index++;
        group->shaded = 1;
        for (int c = 0; c < 3; ++c) group->sum[c] = radiance[c];
    }
    return g;
}

/* Adds the piece [a, b] of the line, its ends meeting groups ga and gb; 0: too many polygons. */
static int scan_piece(scan_state *s, double a, double b, int ga, int gb) {
    if (ga == gb) {
        s->groups[ga].covered += b - a;
        return 1;
    }
    if (b - a <= SCAN_FINEST) {
        s->groups[ga].covered += 0.5 * (b - a);
        s->groups[gb].covered += 0.5 * (b - a);
        return 1;
    }
    double m = 0.5 * (a + b);
    int gm = scan_point(s, m);
    return gm >= 0 && scan_piece(s, a, m, ga, gm) && scan_piece(s, m, b, gm, gb);
}

static int scan_coverage(const rad_renderer *r, rad_sample *sample, rad_sample *extra,
                         pixel_group *groups, int *count, int vertical) {
    scan_state s = {r, sample, extra, groups, count, vertical, 0};
    for (int line = 0; line < SCAN_LINES; ++line) {
        /* The line's place: a stratified point of the pixel's own sequence. */
        rad_sampler sampler = rad_sampler_make(sample->seed, 0);
        sampler.index = rad_sampler_pixel_index(sample->x, sample->y, SCAN_LINES, (uint32_t)line);
        sampler.dimension = RAD_RENDER_DIM_COVERAGE;
        double u[2];
        rad_sampler_2d(&sampler, u);
        s.position = u[0];
        int previous = scan_point(&s, 0);
        if (previous < 0) return 0;
        for (int k = 1; k <= SCAN_PIECES; ++k) {
            double a = (double)(k - 1) / SCAN_PIECES, b = (double)k / SCAN_PIECES;
            int next = scan_point(&s, b);
            if (next < 0 || !scan_piece(&s, a, b, previous, next)) return 0;
            previous = next;
        }
    }
    return 1;
}

/* The pixel from its samples split by polygon (see above); 0 when there are too many polygons.
 * outside: 0, or against the outside with the edge running 1 across, 2 along the rows. */
static int render_edge_pixel(const rad_renderer *r, rad_sample *sample, pixel_group *groups,
                             int count, int near_emitter, int outside, float out[3]) {
    const rad_view *view = &r->view;
    int samples = r->settings.samples_per_pixel;
    double mean = 0, brightest = 0;
    for (int g = 0; g < count; ++g) {
        double group_mean = luminance(groups[g].sum) / groups[g].shaded;
        mean += luminance(groups[g].sum) / samples;
        brightest = fmax(brightest, group_mean);
    }
    uint32_t rays = outside ? SCAN_LINES
                    : near_emitter || brightest > BRIGHT * mean ? BRIGHT_RAYS : COVERAGE_RAYS;
    rad_sample extra = *sample;
    extra.seed = sample->seed ^ EXTRA_SEED_SALT;
    extra.index = 0;
    if (outside && !scan_coverage(r, sample, &extra, groups, &count, outside == 2)) return 0;
    for (uint32_t k = 0; k < rays && !outside; ++k) {
        rad_sampler sampler = rad_sampler_make(sample->seed, 0);
        sampler.index = rad_sampler_pixel_index(sample->x, sample->y, rays, k);
        sampler.dimension = RAD_RENDER_DIM_COVERAGE;
        double u[2];
        rad_sampler_2d(&sampler, u);
        rad_vec3 direction = rad_view_direction(view, sample->x + u[0], sample->y + u[1]);
        rad_element_hit hit;
        sample->counts->camera++;
        uint32_t polygon = rad_element_rays_intersect(r->rays, view->eye, direction, 0, INFINITY, &hit)
                               ? r->mesh->element_polygon[hit.element]
                               : RAD_RENDER_NO_POLYGON;
        int g = group_of(groups, &count, polygon);
        if (g < 0) return 0;
        groups[g].covered++;
        if (groups[g].shaded == 0 && extra.index < extra.count) {
            /* Found by the coverage rays alone: shaded here. */
            double radiance[3];
            rad_trace_radiance(r, &extra, view->eye, direction, NULL, radiance);
            extra.index++;
            groups[g].shaded = 1;
            for (int c = 0; c < 3; ++c) groups[g].sum[c] = radiance[c];
        }
    }
    double sum[3] = {0, 0, 0};
    for (int g = 0; g < count; ++g) {
        if (!groups[g].covered || !groups[g].shaded) continue;
        double fraction = (double)groups[g].covered / rays;
        for (int c = 0; c < 3; ++c) sum[c] += fraction * groups[g].sum[c] / groups[g].shaded;
    }
    for (int c = 0; c < 3; ++c) out[c] = (float)sum[c];
    return 1;
}

/* What the camera ray through a pixel corner meets first: the surface (its key: the surface's
 * index, with EMITTER_BIT set when its material emits; CORNER_OUTSIDE when the ray meets
 * nothing, a value of its own with the emitter bit clear, as the outside emits nothing), and the
 * element's normal. Corners are compared by surface and normal, not by polygon: the triangles
 * of one tessellated surface (a column, an arch of Sponza) are not edges worth splitting a pixel
 * for, a block's two faces or the light against the ceiling are. (2^31 - 1 surfaces would not
 * fit in memory: no surface's index reaches CORNER_OUTSIDE.) */
#define EMITTER_BIT 0x80000000u
#define CORNER_OUTSIDE (EMITTER_BIT - 1)
#define SAME_NORMAL 0.9 /* cosine above which two corners' normals count as one face */

typedef struct pixel_corner {
    uint32_t key;
    uint32_t element; /* the element its camera ray meets; UINT32_MAX: none */
    float normal[3];
    float light; /* the solution's radiance there (the element's, mean of the channels) */
    int uneven;  /* the emitters light its element unevenly (penumbra.c) */
} pixel_corner;

/* Marks the corners whose element the emitters light unevenly (penumbra.c). Each element is
 * tested once, when a corner or a short gather ray first meets it (rad_penumbra_element_uneven),
 * not every element (a hierarchy's leaves, Sponza's 209,507, against its 19,481 corners), nor
 * each corner (the Cornell box's 66,049 corners meet a few hundred of its 2,500 elements). */
static void mark_uneven(const rad_renderer *r, pixel_corner *corner, size_t count) {
    if (r->penumbra_lamps == 0) return;
#pragma omp parallel for schedule(dynamic, 256) num_threads(rad_thread_count(r->ctx))
    for (long i = 0; i < (long)count; ++i)
        corner[i].uneven = corner[i].element != UINT32_MAX &&
                           rad_penumbra_element_uneven(r, corner[i].element);
}

/* The (width + 1) x (height + 1) pixel corners in rows; NULL at one sample per pixel. */
static rad_status corner_polygons_make(const rad_renderer *r, pixel_corner **out) {
    const rad_view *view = &r->view;
    *out = NULL;
    if (r->settings.samples_per_pixel < 2) return RAD_OK;
    size_t stride = (size_t)view->width + 1, rows = (size_t)view->height + 1;
    pixel_corner *corner = rad_alloc(r->ctx, stride * rows, sizeof *corner);
    *out = corner;
    if (!corner) return RAD_ERROR_NO_MEMORY;
#pragma omp parallel for schedule(dynamic, 4) num_threads(rad_thread_count(r->ctx))
    for (size_t y = 0; y < rows; ++y)
        for (size_t x = 0; x < stride; ++x) {
            rad_element_hit hit;
            pixel_corner c = {CORNER_OUTSIDE, UINT32_MAX, {0, 0, 0}, 0, 0};
            if (rad_element_rays_intersect(r->rays, view->eye, rad_view_direction(view, (double)x, (double)y),
                                           0, INFINITY, &hit)) {
                const double *emission = rad_renderer_material(r, hit.element)->emission;
                rad_vec3 n = r->mesh->element_normal[hit.element];
                c.key = r->mesh->element_surface[hit.element] & ~EMITTER_BIT;
                if (emission[0] > 0 || emission[1] > 0 || emission[2] > 0) c.key |= EMITTER_BIT;
                c.normal[0] = (float)n.x;
                c.normal[1] = (float)n.y;
                c.normal[2] = (float)n.z;
                const float *radiance = r->element_radiance[hit.element];
                c.light = (radiance[0] + radiance[1] + radiance[2]) / 3;
                c.element = hit.element;
            }
            corner[y * stride + x] = c;
        }
    mark_uneven(r, corner, stride * rows);
    return RAD_OK;
}

static int same_face(const pixel_corner *a, const pixel_corner *b) {
    if (a->key != b->key) return 0;
    if (a->key == CORNER_OUTSIDE) return 1;
    return a->normal[0] * b->normal[0] + a->normal[1] * b->normal[1] + a->normal[2] * b->normal[2] >
           SAME_NORMAL;
}

/* Whether a corner's ray met an emitter. */
static int emits(const pixel_corner *c) { return (c->key & EMITTER_BIT) != 0; }

/* Whether a corner of the pixel whose first corner is c sees the outside. */
static int any_outside(const pixel_corner *c, size_t stride) {
    return c[0].key == CORNER_OUTSIDE || c[1].key == CORNER_OUTSIDE ||
           c[stride].key == CORNER_OUTSIDE || c[stride + 1].key == CORNER_OUTSIDE;
}

/* Whether the rays through the corners of pixel (x, y) meet more than one face: 0 no, 1 yes,
 * 2 yes and one of them emits, 3 yes and one of them sees the outside (none emits). */
static int on_edge(const rad_view *view, const pixel_corner *corners, int x, int y) {
    if (x < 0 || y < 0 || x >= view->width || y >= view->height) return 0;
    size_t stride = (size_t)view->width + 1;
    const pixel_corner *c = corners + (size_t)y * stride + (size_t)x;
    if (same_face(c, c + 1) && same_face(c, c + stride) && same_face(c, c + stride + 1)) return 0;
    if (emits(&c[0]) || emits(&c[1]) || emits(&c[stride]) || emits(&c[stride + 1])) return 2;
    return any_outside(c, stride) ? 3 : 1;
}

/* Whether a corner of pixel (x, y) sees the outside (no surface): 0 no; 2 yes and the edge
 * runs along the rows (the corners agree in pairs along the top and the bottom, not across), 1
 * yes otherwise (scan_coverage's lines run across the edge). */
static int sees_outside(const rad_view *view, const pixel_corner *corners, int x, int y) {
    size_t stride = (size_t)view->width + 1;
    const pixel_corner *c = corners + (size_t)y * stride + (size_t)x;
    if (!any_outside(c, stride)) return 0;
    int along_rows = same_face(c, c + 1) && same_face(c + stride, c + stride + 1) &&
                     !same_face(c, c + stride);
    return along_rows ? 2 : 1;
}

/* Whether pixel (x, y) is on an edge, or one of its four neighbours on an emitter's edge or
 * against the outside (0, 1, 2: an emitter near): the light's corner inside a pixel leaves the pixel's own corners alone,
 * but its two edges cross the neighbours, and a sliver of the light is worth much. (Every
 * neighbour of every edge tripled the split pixels for little: Sponza's 0.58 M coverage rays.) */
static int near_edge(const rad_view *view, const pixel_corner *corner_polygons, int x, int y,
                     int *beside_outside) {
    static const int offset[5][2] = {{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    int edge = 0;
    *beside_outside = 0;
    for (int k = 0; k < 5; ++k) {
        int e = on_edge(view, corner_polygons, x + offset[k][0], y + offset[k][1]);
        if (e == 3) *beside_outside = 1;
        /* The outside beside a neighbour splits this pixel too, with the plain coverage rays:
         * a corner ray through a crack where polygons meet sees the outside at one scale of
         * the scene and not at another (tests/cli_units.sh), and the pixel's class must not
         * follow it. */
        if (e == 3) e = 1;
        else if (k > 0 && e != 2) e = 0;
        if (e > edge) edge = e;
    }
    return edge;
}

/* Gather rays per sample, as a multiple of --final-gather, in edge pixels against the outside
 * (the box's front edges) when the irradiance filter is on (gather_filter.c): the filter leaves
 * edge pixels as they are, and there a few samples carry the whole pixel. On the Cornell box
 * (256 x 256, seeds 1 / 2, 4x4 RMSE): 1.06 / 1.40 % with none, 0.97 / 0.97 % with these, 0.90 /
 * 0.95 % with every edge pixel at 4 times (2 times: 0.92 / 1.04 %), which doubled Sponza's
 * gather rays (docs/rendering.md, "Irradiance filter"). */
#define EDGE_GATHER 4
/* ... and OUTSIDE_GATHER times in the pixels whose own corners see the outside: there the wall's
 * sliver is lit by the few samples that meet it (half of 16, or fewer), and its gather was the
 * noisiest part of the image. Cornell box 256 x 256, seeds 0-3 (cornell50, docs/rendering.md):
 * the 248 4x4 blocks holding such pixels, 6 % of the blocks, had 28 % of the 4x4 noise variance
 * (noise 1.60 % a block); at 16 times 0.93 % (8: 4x4 RMSE 0.79 %, 16: 0.77 %, 32: 0.76 %, against
 * 0.84 % at 4) for 7 % more gather rays. */
#define OUTSIDE_GATHER 16

/* Pixels inside one face (not near an edge: render_pixel) of a diffuse untextured surface, with
 * the final gather on, trace INTERIOR_SHARE times fewer camera samples, each with that many
 * times the gather rays and emitter samples: the pixel's gather points and emitter points are
 * the same runs of its sequence, and the camera samples there only move the gathered point
 * within the pixel, where the light varies little. Edges (split pixels), mirrors, glass and
 * textures keep every sample. Cornell box 256 x 256: 1.73 -> 1.04 million camera rays, block
 * errors as before (docs/rendering.md, "Interior pixels"). */
#define INTERIOR_SHARE 4

/* Interior pixels whose four corners meet elements the emitters light evenly (all of the lamp
 * seen, or none of it: penumbra.c) draw EVEN_SHARE times fewer emitter samples: there the
 * lamp's light varies little over the lamp and a net of 8 points over it (emitters_build.c)
 * gets it. Cornell 256, seeds 0-5: shadow rays 1.92 -> 1.23 million, every block error as
 * before to 0.01 % (8 times fewer: 4x4 0.82 / 0.87 / 0.87 -> 0.86 / 0.91 / 0.91 % in seeds
 * 0-2). */
#define EVEN_SHARE 4
/* And interior pixels with a corner on an unevenly lit element (a penumbra) draw UNEVEN_SHARE
 * times the emitter samples, on a uniform mesh: what is left of the default Cornell render's
 * 4x4 noise is mostly the floor's and the blocks' penumbras, where the lamp's share seen varies
 * over the pixel and over the lamp (docs/rendering.md, "One element geometry, and penumbra pixels"). Not on a hierarchy's
 * leaves, whose noise is the re-gathers' (docs/hierarchical.md). */
#define UNEVEN_SHARE 2

static int interior(const rad_renderer *r, const pixel_corner *corners, int x, int y) {
    if (!corners || r->settings.final_gather <= 0) return 0;
    uint32_t key = corners[(size_t)y * ((size_t)r->view.width + 1) + (size_t)x].key;
    if (key == CORNER_OUTSIDE) return 0;
    const rad_material *m = &r->surface_material[key & ~EMITTER_BIT];
    return m->kind == RAD_MATERIAL_DIFFUSE && !m->texture;
}

/* One pixel: the mean of its samples, at Owen-scrambled Sobol' points of the pixel (a (0,m,2)-net
 * for 2^m samples, core/sampler.h): every sample is uniform over the pixel, so the expected
 * value is the box-filtered image the path tracer converges to, with less noise along edges;
 * pixels on an edge between polygons are split by what covers them (render_edge_pixel). */
/* Dark pixels: where the solution's radiance at all four corners is under DARK times its mean
 * over the pixel corners that meet a surface other than an emitter (the light, 150 times
 * brighter, would count 3 times the rest). There the light is mostly gathered, and a block's
 * error is relative to little: the short block's front face and the floor in its shadow, the
 * top corners of the box. Dark pixels gather DARK_INTERIOR times the rays inside faces,
 * EDGE_GATHER times on edges, and their short gather rays reach twice as far (final_gather.c).
 * Cornell 256, seeds 0 / 1 / 2: 8x8 blocks over 4 % 3 / 1 / 0 -> 2 / 1 / 0, the short block's
 * front face -0.65 -> -0.17 % (mean of the 8x8 blocks of x 128-216, y 216-256), gather rays
 * +11 % (docs/rendering.md, "Dark pixels"). The choice reads the solution, never the samples. */
/* Split pixels with any dark corner (the ceiling's edge pixels in the box's top corners, whose
 * other corners meet the lit wall) count as dark ones too: with all four corners asked, seed 1's
 * 8x8 block of the top right corner was -7.1 % (-3.0 % over seeds 0-5, the ceiling's pixels
 * beside the green wall), with any corner -3.1 % (-1.7 %) for 1 % more gather rays. Edge pixels
 * that gather more also draw EDGE_GATHER times the emitter samples: the floor's last rows at
 * the bottom of the image lie in the short block's penumbra, and their pixels against the black
 * beyond the floor had a quarter of their samples on it (8x8 blocks at y 248 -4.7 / +4.3 % in
 * seed 0, within 3.6 % over seeds 0-5 with them; docs/rendering.md, "corn4"). */
#define DARK 0.25
#define DARK_INTERIOR 2
/* The other split pixels gather SPLIT_GATHER times the rays (their emitter samples stay as they
 * are). The concave edges where two faces meet, the ceiling and a wall in the box's top
 * corners, are split pixels the filter leaves alone: at 4 rays a sample their noise was 10-20 %
 * a pixel, and it made three quarters of the noise of the top left 8x8 block (x0 y0: -4.3 /
 * -4.1 % in seeds 0 / 2, a spread of 2.4 % over seeds 0-9). Cornell 256, seeds 0-9 (cornell51,
 * docs/rendering.md): that block within 3.1 % (spread 1.8 %), no 8x8 block over 4 % in any seed
 * (one in 2 of 10 before), gather rays +2.7 %, 4x4 RMSE 0.706 -> 0.697 %. Only the split pixels
 * with a corner under half the corners' mean, at 4 times: the same rays, 4x4 0.703 %; under
 * the mean, at 4 times: +6.3 %, 0.692 %. Not on a coarse hierarchy's leaves, whose every first
 * gather ray is gathered again up to three levels deep: Sponza 160 x 120 took 24 % more gather
 * rays and 6 % more processor time (8x8 1.68 -> 1.61 %) with the rule of half the mean at 4
 * times. Fine leaves, read like a uniform mesh's, take it: the hierarchical Cornell render
 * (256 x 256, seeds 0-3) 8x8 noise 0.385 -> 0.364 %, the top left block's standard deviation
 * over the seeds 3.4 -> 0.8 %, gather rays +3.5 % (docs/hierarchical.md, "hcornell2"). */
#define SPLIT_GATHER 2

/* The corners' radiance under which a pixel is dark (DARK times their mean, emitters aside). */
static double dark_light(const rad_renderer *r, const pixel_corner *corners) {
    double factor = DARK;
    size_t count = ((size_t)r->view.width + 1) * ((size_t)r->view.height + 1), seen = 0;
    double sum = 0;
    for (size_t i = 0; i < count; ++i)
        if (corners[i].key != CORNER_OUTSIDE && !emits(&corners[i])) {
            sum += corners[i].light;
            ++seen;
        }
    return seen ? factor * sum / (double)seen : 0;
}

/* How many of pixel (x, y)'s four corners the solution shows darker than `dark`. */
static int dark_corners(const rad_view *view, const pixel_corner *corners, int x, int y, double dark) {
    size_t stride = (size_t)view->width + 1;
    const pixel_corner *c = corners + (size_t)y * stride + (size_t)x;
    return (c[0].light < dark) + (c[1].light < dark) + (c[stride].light < dark) + (c[stride + 1].light < dark);
}
static int uneven_corner(const rad_view *view, const pixel_corner *corners, int x, int y) {
    size_t stride = (size_t)view->width + 1;
    const pixel_corner *c = corners + (size_t)y * stride + (size_t)x;
    return c[0].uneven || c[1].uneven || c[stride].uneven || c[stride + 1].uneven;
}

static void render_pixel(const rad_renderer *r, const pixel_corner *corner_polygons, double dark,
                         int x, int y, rad_ray_counts *counts, rad_gather_pixel *record, float out[3]) {
    const rad_view *view = &r->view;
    rad_sample sample;
    memset(&sample, 0, sizeof sample);
    sample.seed = r->seed;
    sample.x = (uint32_t)x;
    sample.y = (uint32_t)y;
    sample.count = (uint32_t)r->settings.samples_per_pixel;
    sample.counts = counts;
    sample.first_polygon = RAD_RENDER_NO_POLYGON;
    rad_gather_tally tally;
    memset(&tally, 0, sizeof tally);
    sample.tally = record ? &tally : NULL;
    uint32_t polygon = RAD_RENDER_NO_POLYGON; /* the one all samples met first, if any */
    int samples = r->settings.samples_per_pixel;
    double sum[3] = {0, 0, 0};
    pixel_group groups[MAX_GROUPS];

    int group_count = 0;
    /* One sample per pixel stays one camera ray per pixel (a preview, a flat look at the mesh). */
    int beside_outside = 0;
    int split = corner_polygons ? near_edge(view, corner_polygons, x, y, &beside_outside) : 0;
    /* With the irradiance filter, which leaves edge pixels alone, they gather more rays: those
     * against the outside and beside it (so a corner ray through a crack, which sees the
     * outside at one scale and not at another, changes only how the coverage is measured), and
     * those with a dark corner. */
    int outside = split && sees_outside(view, corner_polygons, x, y);
    int more = split && (beside_outside || dark_corners(view, corner_polygons, x, y, dark) > 0);
    int plain = split && !more && r->regather.leaves != RAD_LEAVES_COARSE; /* SPLIT_GATHER */
    sample.gather_rays = !record || !(more || plain)
                             ? 0
                             : (outside ? OUTSIDE_GATHER : more ? EDGE_GATHER : SPLIT_GATHER) *
                                   r->settings.final_gather;
    sample.light_samples = more && record ? EDGE_GATHER * r->settings.light_samples : 0;
    if (!split && interior(r, corner_polygons, x, y) && samples % INTERIOR_SHARE == 0) {
        /* The same gather rays and emitter samples from a quarter of the camera samples. */
        samples /= INTERIOR_SHARE;
        sample.count = (uint32_t)samples;
        sample.gather_rays = INTERIOR_SHARE * r->settings.final_gather;
        if (dark_corners(view, corner_polygons, x, y, dark) == 4) sample.gather_rays *= DARK_INTERIOR;
        sample.light_samples = INTERIOR_SHARE * r->settings.light_samples;
        /* Evenly lit: a quarter of the emitter samples (penumbra.c); in a penumbra on a
         * uniform mesh, twice as many (UNEVEN_SHARE). */
        if (!uneven_corner(view, corner_polygons, x, y)) {
            if (sample.light_samples >= EVEN_SHARE) sample.light_samples /= EVEN_SHARE;
        } else if (r->regather.leaves == RAD_LEAVES_UNIFORM) {
            sample.light_samples *= UNEVEN_SHARE;
        }
    }
    rad_vec3 direction[16];
    rad_element_hit first[16];
    for (int s = 0; s < samples; ++s) {
        if (s % 16 == 0) {
            /* The pixel's next (up to) 16 camera rays, which leave the eye together, as one
             * packet; each is then followed from its first hit. */
            int n = samples - s < 16 ? samples - s : 16;
            for (int i = 0; i < n; ++i) {
                double jitter[2];
                sample.index = (uint32_t)(s + i);
                rad_sample_2d(&sample, 1, 0, RAD_RENDER_DIM_PIXEL, jitter);
                direction[i] = rad_view_direction(view, x + jitter[0], y + jitter[1]);
            }
            rad_element_rays_intersect16(r->rays, view->eye, direction, n, 0, first);
        }
        sample.index = (uint32_t)s;
        double radiance[3];
        rad_trace_radiance_hit(r, &sample, view->eye, direction[s % 16], NULL, &first[s % 16],
                               radiance);
        for (int c = 0; c < 3; ++c) sum[c] += radiance[c];
        if (s == 0) polygon = sample.first_polygon;
        else if (polygon != sample.first_polygon) polygon = RAD_RENDER_NO_POLYGON;
        int g = split ? group_of(groups, &group_count, sample.first_polygon) : -1;
        if (g < 0) split = 0;
        else {
            groups[g].shaded++;
            for (int c = 0; c < 3; ++c) groups[g].sum[c] += radiance[c];
        }
    }
    if (record) rad_gather_pixel_make(&tally, samples, polygon, split, record);
    sample.tally = NULL;
    if (split && render_edge_pixel(r, &sample, groups, group_count, split == 2, outside, out))
        return;
    for (int c = 0; c < 3; ++c) out[c] = (float)(sum[c] / samples);
}

/* What a picture or the vertices' gather reads, made ready for the current solution: leaves
 * that appeared or vanished since the last use (a hierarchy refining) rebuild what was made
 * from them; then the smooth values and the textures' irradiance. */
static rad_status prepare_solution(rad_renderer *r) {
    rad_status status = r->leaves_ready && r->generation == rad_solution_generation(r->solution)
                            ? RAD_OK
                            : leaves_build(r);
    if (!status) status = rad_reconstruct_prepare(r);
    if (!status) status = rad_texture_shading_prepare(r);
    return status;
}

rad_status rad_renderer_render(rad_renderer *r, rad_image **out, rad_render_stats *stats) {
    if (!r || !out) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    rad_context *ctx = r->ctx;
    double start = rad_seconds();
    rad_status status = prepare_solution(r);
    rad_image *image = NULL;
    pixel_corner *corner_polygons = NULL;
    rad_gather_pixel *records = NULL; /* the irradiance filter's (gather_filter.c) */
    if (!status) status = rad_image_new(ctx, r->view.width, r->view.height, &image);
    if (!status) status = corner_polygons_make(r, &corner_polygons);
    /* The filter's records and its buffer (56 bytes a pixel); past the memory budget the image
     * is rendered without the filter rather than refused. */
    size_t pixels = (size_t)r->view.width * (size_t)r->view.height;
    if (!status && r->settings.final_gather > 0 && r->settings.gather_filter &&
        (double)pixels * (sizeof *records + 3 * sizeof(float)) <= (double)ctx->max_memory) {
        records = rad_alloc(ctx, pixels, sizeof *records);
        if (!records) status = RAD_ERROR_NO_MEMORY;
    }
    if (status) {
        rad_image_free(image);
        rad_free(ctx, corner_polygons);
        rad_free(ctx, records);
        return status;
    }

    const int width = r->view.width, height = r->view.height;
    double dark = corner_polygons ? dark_light(r, corner_polygons) : 0;
    r->dark_radiance = dark;
    rad_ray_counts total = {0, 0, 0, 0};
    int rows_done = 0, cancelled = 0;
    double last_report = start;
    if (rad_progress(ctx, "rendering", 0, height)) cancelled = 1;
#pragma omp parallel num_threads(rad_thread_count(ctx))
    {
        rad_ray_counts counts = {0, 0, 0, 0};
#pragma omp for schedule(dynamic, 1)
        for (int y = 0; y < height; ++y) {
            int stop;
#pragma omp atomic read
            stop = cancelled;
            if (stop) continue;
            for (int x = 0; x < width; ++x)
                render_pixel(r, corner_polygons, dark, x, y, &counts,
                             records ? records + (size_t)y * width + x : NULL,
                             image->pixels + 3 * ((size_t)y * width + x));
#pragma omp critical(rad_render_progress)
            {
                ++rows_done;
                double now = rad_seconds();
                if (!cancelled && (now - last_report > 0.05 || rows_done == height)) {
                    last_report = now;
                    if (rad_progress(ctx, "rendering", rows_done, height)) {
#pragma omp atomic write
                        cancelled = 1;
                    }
                }
            }
        }
#pragma omp critical(rad_render_counts)
        {
            total.camera += counts.camera;
            total.gather += counts.gather;
            total.shadow += counts.shadow;
            total.specular += counts.specular;
        }
    }
    rad_free(ctx, corner_polygons);
    if (!cancelled && records) status = rad_gather_filter(r, records, image->pixels);
    rad_free(ctx, records);
    if (status) {
        rad_image_free(image);
        return status;
    }
    if (cancelled) {
        rad_image_free(image);
        return rad_fail(ctx, RAD_ERROR_CANCELLED, "rendering cancelled after %d of %d rows",
                        rows_done, height);
    }
    if (stats) {
        stats->seconds = rad_seconds() - start;
        stats->camera_rays = total.camera;
        stats->gather_rays = total.gather;
        stats->shadow_rays = total.shadow;
        stats->specular_rays = total.specular;
    }
    *out = image;
    return RAD_OK;
}

/* ------------------------------------------------------------------------------------------- */
/* The final gather at the vertices (bake --final-gather)                                       */

rad_status rad_renderer_vertex_radiosity(rad_renderer *r, int rays, rad_rgb *out) {
    if (!r || !out || rays <= 0 || rays > RAD_RENDER_MAX_GATHER) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = r->ctx;
    rad_status status = prepare_solution(r);
    if (status) return status;
    const rad_mesh *mesh = r->mesh;
    size_t nv = mesh->vertex_count;
    /* Each vertex is gathered once, just inside the largest element around it (the inset
     * collocate.c uses, so that the point is on that element and not on its neighbours). */
    uint32_t *element = rad_alloc(ctx, nv + 1, sizeof *element);
    uint8_t *corner = rad_alloc(ctx, nv + 1, sizeof *corner);
    if (!element || !corner) {
        rad_free(ctx, element);
        rad_free(ctx, corner);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t v = 0; v < nv; ++v) element[v] = RAD_NO_ELEMENT;
    for (size_t e = 0; e < mesh->element_count; ++e)
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            uint32_t v = mesh->element_vertices[e][k];
            if (element[v] == RAD_NO_ELEMENT || mesh->element_area[e] > mesh->element_area[element[v]]) {
                element[v] = (uint32_t)e;
                corner[v] = (uint8_t)k;
            }
        }
    r->dark_radiance = 0; /* no picture's dark pixels to gather farther for */
    const long long count = (long long)nv;
    int cancelled = 0;
    long long done = 0;
    if (rad_progress(ctx, "gathering at the vertices", 0, (double)count)) cancelled = 1;
#pragma omp parallel num_threads(rad_thread_count(ctx))
    {
        rad_ray_counts counts = {0, 0, 0, 0};
#pragma omp for schedule(dynamic, 64)
        for (long long i = 0; i < count; ++i) {
            int stop;
#pragma omp atomic read
            stop = cancelled;
            if (stop) continue;
            size_t v = (size_t)i;
            for (int c = 0; c < 3; ++c) out[v][c] = 0;
            uint32_t e = element[v];
            if (e == RAD_NO_ELEMENT) continue;
            /* The corner's parameters and the centroid's (rad_element_hit's convention). */
            int quad = rad_mesh_corner_count(mesh, e) == 4;
            static const double quad_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            static const double triangle_uv[3][2] = {{0, 0}, {1, 0}, {0, 1}};
            const double *at = quad ? quad_uv[corner[v]] : triangle_uv[corner[v]];
            double middle = quad ? 0.5 : 1.0 / 3;
            rad_element_hit hit;
            hit.element = e;
            hit.u = at[0] + RAD_CORNER_INSET * (middle - at[0]);
            hit.v = at[1] + RAD_CORNER_INSET * (middle - at[1]);
            hit.t = 0;
            hit.front = 1;
            rad_vec3 x = v3_lerp(mesh->vertices[v], mesh->element_centroid[e], RAD_CORNER_INSET);
            rad_sample sample;
            memset(&sample, 0, sizeof sample);
            sample.seed = r->seed;
            sample.x = (uint32_t)(v & 0xffff);
            sample.y = (uint32_t)(v >> 16);
            sample.count = 1;
            sample.counts = &counts;
            sample.first_polygon = RAD_RENDER_NO_POLYGON;
            sample.gather_rays = rays;
            sample.light_samples = rays / 2 > 0 ? rays / 2 : 1;
            double radiance[3] = {0, 0, 0};
            rad_final_gather(r, &sample, &hit, x, mesh->element_normal[e], 0, radiance);
            for (int c = 0; c < 3; ++c) out[v][c] = RAD_PI * radiance[c];
#pragma omp atomic update
            ++done;
            if (omp_get_thread_num() == 0 && (i & 255) == 0) { /* now and then, one thread */
                long long now;
#pragma omp atomic read
                now = done;
                if (rad_progress(ctx, "gathering at the vertices", (double)now, (double)count)) {
#pragma omp atomic write
                    cancelled = 1;
                }
            }
        }
    }
    rad_free(ctx, element);
    rad_free(ctx, corner);
    if (cancelled)
        return rad_fail(ctx, RAD_ERROR_CANCELLED, "gathering at the vertices cancelled");
    return RAD_OK;
}

rad_status rad_render(const rad_scene *scene, const rad_system *system,
                      const rad_render_options *options, rad_image **out) {
    rad_renderer *r = NULL;
    rad_status status = rad_renderer_create(scene, system, options, &r);
    if (!status) status = rad_renderer_render(r, out, NULL);
    rad_renderer_destroy(r);
    return status;
}
