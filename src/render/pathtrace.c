/* pathtrace.c - the reference path tracer (see pathtrace.h, docs/pathtracing.md).
 *
 * Kajiya 1986 path tracing, with the estimator of Veach 1997 (ch. 9, 10):
 *   - at every vertex with a non-delta lobe, one emitter sample (next-event estimation): an
 *     emitting triangle chosen by power, a point uniform on it, a shadow ray;
 *   - one BSDF sample to continue the path; when it hits an emitter, its emission counts with
 *     the power-heuristic weight against the emitter sample, or fully after a delta lobe;
 *   - Russian roulette after three bounces, on the path throughput.
 * Pixels: uniform jitter inside the pixel, box filter, each pixel with its own random stream
 * derived from (seed, pixel index), so the image does not depend on the thread count. */
#include "render/pathtrace.h"

#include "image/image.h"

#include <omp.h>
#include <string.h>

#define HARD_MAX_BOUNCES 1024 /* a safety net; Russian roulette ends paths long before */
#define ROULETTE_START 3
#define DEFAULT_SIZE 512
#define DEFAULT_SPP 64

static double luminance_weight(const double c[3]) { return c[0] + c[1] + c[2]; }

/* ---- set-up ------------------------------------------------------------------------------- */

rad_status rad_tracer_create(rad_context *ctx, const rad_scene *scene, int max_bounces,
                             rad_tracer **out) {
    *out = NULL;
    if (!scene || !scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: path tracing needs geometry, not a patch system",
                        scene && scene->source ? scene->source : "scene");
    if (scene->polygon_count == 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: the scene has no faces",
                        scene->source);
    rad_tracer *t = rad_alloc_zero(ctx, 1, sizeof *t);
    if (!t) return RAD_ERROR_NO_MEMORY;
    t->ctx = ctx;
    t->scene = scene;
    t->max_bounces = max_bounces > 0 ? max_bounces : HARD_MAX_BOUNCES;
    t->next_event = 1;
    size_t polygons = scene->polygon_count;
    t->polygon_material = rad_alloc(ctx, polygons, sizeof *t->polygon_material);
    t->polygon_light_pdf = rad_alloc_zero(ctx, polygons, sizeof *t->polygon_light_pdf);
    if (!t->polygon_material || !t->polygon_light_pdf) {
        rad_tracer_destroy(t);
        return RAD_ERROR_NO_MEMORY;
    }
    /* Emitters: every triangle of an emitting polygon, chosen by power (area times the sum of
     * the emitted radiance over the channels). */
    size_t light_triangles = 0;
    double total_power = 0;
    for (size_t i = 0; i < polygons; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const rad_material *m = &scene->materials[scene->surfaces[p->surface].material];
        t->polygon_material[i] = m;
        double weight = luminance_weight(m->emission);
        if (weight > 0) {
            light_triangles += p->count - 2;
            total_power += weight * rad_polygon_area(scene, p);
        }
    }
    if (light_triangles && total_power > 0) {
        t->lights = rad_alloc(ctx, light_triangles, sizeof *t->lights);
        t->light_cdf = rad_alloc(ctx, light_triangles, sizeof *t->light_cdf);
        if (!t->lights || !t->light_cdf) {
            rad_tracer_destroy(t);
            return RAD_ERROR_NO_MEMORY;
        }
        double running = 0;
        size_t n = 0;
        for (size_t i = 0; i < polygons; ++i) {
            const rad_polygon *p = &scene->polygons[i];
            double weight = luminance_weight(t->polygon_material[i]->emission);
            if (!(weight > 0)) continue;
            /* Area density of a point on this polygon: its share of the power over its area. */
            t->polygon_light_pdf[i] = weight / total_power;
            rad_vec3 normal = rad_polygon_normal(scene, p);
            rad_vec3 p0 = rad_polygon_vertex(scene, p, 0);
            for (uint32_t k = 1; k + 1 < p->count; ++k) {
                rad_light_triangle *l = &t->lights[n];
                l->p0 = p0;
                l->e1 = v3_sub(rad_polygon_vertex(scene, p, k), p0);
                l->e2 = v3_sub(rad_polygon_vertex(scene, p, k + 1), p0);
                l->normal = normal;
                l->polygon = (uint32_t)i;
                running += weight * 0.5 * v3_length(v3_cross(l->e1, l->e2));
                t->light_cdf[n++] = running / total_power;
            }
        }
        t->light_count = n;
        t->light_cdf[n - 1] = 1;
    }
    rad_status status = rad_rays_create(ctx, scene, &t->rays);
    if (status) {
        rad_tracer_destroy(t);
        return status;
    }
    *out = t;
    return RAD_OK;
}

void rad_tracer_destroy(rad_tracer *t) {
    if (!t) return;
    rad_rays_destroy(t->rays);
    rad_free(t->ctx, t->polygon_material);
    rad_free(t->ctx, t->polygon_light_pdf);
    rad_free(t->ctx, t->lights);
    rad_free(t->ctx, t->light_cdf);
    rad_free(t->ctx, t);
}

/* ---- one path ----------------------------------------------------------------------------- */

/* A point on the emitters: position, front normal, and the polygon it lies on. */
static const rad_light_triangle *sample_light(const rad_tracer *t, rad_rng *rng, rad_vec3 *point) {
    double u = rad_rng_uniform(rng);
    size_t lo = 0, hi = t->light_count - 1;
    while (lo < hi) { /* the first entry with cdf > u */
        size_t mid = (lo + hi) / 2;
        if (t->light_cdf[mid] > u) hi = mid;
        else lo = mid + 1;
    }
    const rad_light_triangle *l = &t->lights[lo];
    double s = rad_rng_uniform(rng), r = rad_rng_uniform(rng);
    if (s + r > 1) {
        s = 1 - s;
        r = 1 - r;
    }
    *point = v3_add(l->p0, v3_add(v3_scale(l->e1, s), v3_scale(l->e2, r)));
    return l;
}

static double power_heuristic(double f, double g) {
    double f2 = f * f, g2 = g * g;
    return f2 + g2 > 0 ? f2 / (f2 + g2) : 0;
}

void rad_tracer_radiance(const rad_tracer *t, rad_rng *rng, rad_vec3 origin, rad_vec3 direction,
                         rad_trace_counts *counts, double out[3]) {
    const rad_rays *rays = t->rays;
    double radiance[3] = {0, 0, 0};
    double throughput[3] = {1, 1, 1};
    double previous_pdf = 0; /* solid-angle pdf of the BSDF sample that made this ray */
    int previous_delta = 1;  /* the camera ray counts as a delta: emitters seen fully */
    ++counts->paths;
    for (int bounce = 0;; ++bounce) {
        rad_hit hit;
        ++counts->rays;
        if (!rad_rays_intersect(rays, origin, direction, rays->epsilon, INFINITY, &hit)) break;
        if (bounce == 0) {
            ++counts->camera_hits;
            if (!hit.front && t->polygon_material[hit.polygon]->kind != RAD_MATERIAL_GLASS)
                ++counts->back_hits;
        }
        const rad_material *m = t->polygon_material[hit.polygon];
        rad_vec3 x = v3_add(origin, v3_scale(direction, hit.t));
        rad_vec3 wo = v3_scale(direction, -1);

        /* Emission seen along the path (front sides only). */
        if (hit.front && t->polygon_light_pdf[hit.polygon] > 0) {
            double weight = 1;
            if (!previous_delta && t->next_event) {
                double cos_light = v3_dot(wo, hit.normal);
                double light_pdf = t->polygon_light_pdf[hit.polygon] * hit.t * hit.t / cos_light;
                weight = power_heuristic(previous_pdf, light_pdf);
            }
            for (int c = 0; c < 3; ++c) radiance[c] += throughput[c] * weight * m->emission[c];
        }
        if (bounce >= t->max_bounces) break;

        /* Next-event estimation: one point on the emitters, weighted against BSDF sampling. */
        if (t->next_event && t->light_count && rad_bsdf_has_smooth_lobe(m)) {
            rad_vec3 y;
            const rad_light_triangle *l = sample_light(t, rng, &y);
            rad_vec3 to_light = v3_sub(y, x);
            double distance2 = v3_dot(to_light, to_light);
            double distance = sqrt(distance2);
            rad_vec3 wi = v3_scale(to_light, 1 / distance);
            double cos_light = -v3_dot(wi, l->normal);
            double f[3], bsdf_pdf;
            if (cos_light > 0 && rad_bsdf_eval(m, hit.normal, wo, wi, f, &bsdf_pdf)) {
                ++counts->rays;
                if (!rad_rays_occluded(rays, x, y)) {
                    const double *emission = t->polygon_material[l->polygon]->emission;
                    double light_pdf = t->polygon_light_pdf[l->polygon] * distance2 / cos_light;
                    double weight = power_heuristic(light_pdf, bsdf_pdf);
                    double cos_surface = fabs(v3_dot(wi, hit.normal));
                    double scale = weight * cos_surface / light_pdf;
                    for (int c = 0; c < 3; ++c)
                        radiance[c] += throughput[c] * f[c] * emission[c] * scale;
                }
            }
        }

        /* Continue the path by sampling the BSDF. */
        double u[3] = {rad_rng_uniform(rng), rad_rng_uniform(rng), rad_rng_uniform(rng)};
        rad_bsdf_sample s;
        if (rad_bsdf_sample_direction(m, hit.normal, wo, u, &s) == RAD_LOBE_NONE) break;
        for (int c = 0; c < 3; ++c) throughput[c] *= s.weight[c];
        previous_pdf = s.pdf;
        previous_delta = s.delta;

        /* Russian roulette: continue with probability of the throughput, capped at 0.95. */
        if (bounce + 1 >= ROULETTE_START) {
            double q = fmin(0.95, v3_max_component(v3(throughput[0], throughput[1], throughput[2])));
            if (!(rad_rng_uniform(rng) < q)) break;
            for (int c = 0; c < 3; ++c) throughput[c] /= q;
        } else if (!(throughput[0] > 0 || throughput[1] > 0 || throughput[2] > 0)) {
            break;
        }
        origin = x;
        direction = s.direction;
    }
    for (int c = 0; c < 3; ++c) out[c] = radiance[c];
}

/* ---- the image ---------------------------------------------------------------------------- */

static rad_camera camera_from_desc(const rad_camera_desc *d) {
    rad_camera c;
    c.eye = v3(d->eye[0], d->eye[1], d->eye[2]);
    c.look = v3(d->look[0], d->look[1], d->look[2]);
    c.up = v3(d->up[0], d->up[1], d->up[2]);
    c.fov_degrees = d->fov_degrees;
    return c;
}

/* Before any work: primary rays through a grid over the image must see the front of
 * something. */
static rad_status check_view(const rad_tracer *t, const rad_view *view) {
    int nx = view->width < 64 ? view->width : 64, ny = view->height < 64 ? view->height : 64;
    int hits = 0, fronts = 0;
    const char *back_surface = NULL;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            double px = (i + 0.5) * view->width / nx, py = (j + 0.5) * view->height / ny;
            rad_hit hit;
            if (!rad_rays_intersect(t->rays, view->eye, rad_view_direction(view, px, py), 0,
                                    INFINITY, &hit))
                continue;
            ++hits;
            if (hit.front || t->polygon_material[hit.polygon]->kind == RAD_MATERIAL_GLASS) ++fronts;
            else if (!back_surface)
                back_surface = t->scene->surfaces[t->scene->polygons[hit.polygon].surface].name;
        }
    if (hits == 0)
        return rad_fail(t->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera sees nothing: no surface in the view (check --eye, --look, --fov)");
    if (fronts == 0)
        return rad_fail(t->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera is inside an object or behind the scene: it sees only the backs "
                        "of surfaces (such as '%s')", back_surface);
    return RAD_OK;
}

rad_status rad_pathtrace(rad_context *ctx, const rad_scene *scene,
                         const rad_pathtrace_options *options, rad_image **out,
                         rad_pathtrace_stats *stats) {
    *out = NULL;
    double start = rad_seconds();
    rad_pathtrace_options o = options ? *options : (rad_pathtrace_options){0};
    if (o.width < 0 || o.height < 0 || o.samples_per_pixel < 0 || o.max_bounces < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "path tracing: sizes, samples and bounces must not be negative");
    int width = o.width ? o.width : DEFAULT_SIZE, height = o.height ? o.height : DEFAULT_SIZE;
    int spp = o.samples_per_pixel ? o.samples_per_pixel : DEFAULT_SPP;
    if (!scene) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "path tracing: no scene");
    if (!scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: path tracing needs geometry, not a patch system", scene->source);
    rad_camera camera = o.camera ? camera_from_desc(o.camera) : rad_scene_camera(scene);
    rad_view view;
    rad_status status = rad_view_make(ctx, &camera, width, height, &view);
    if (status) return status;

    rad_tracer *t;
    status = rad_tracer_create(ctx, scene, o.max_bounces, &t);
    if (status) return status;
    status = check_view(t, &view);
    if (!status && t->light_count == 0)
        rad_warn(ctx, "%s: nothing emits light: the image is black", scene->source);
    rad_image *image = NULL;
    if (!status) status = rad_image_new(ctx, width, height, &image);
    if (status) {
        rad_tracer_destroy(t);
        return status;
    }

    int threads = rad_thread_count(ctx);
    rad_trace_counts total = {0};
    int rows_done = 0, cancelled = 0;
    uint64_t seed = ctx->seed;
#pragma omp parallel num_threads(threads)
    {
        rad_trace_counts counts = {0};
#pragma omp for schedule(dynamic, 1)
        for (int y = 0; y < height; ++y) {
            int stop;
#pragma omp atomic read
            stop = cancelled;
            if (stop) continue;
            for (int x = 0; x < width; ++x) {
                uint64_t pixel = (uint64_t)y * (uint64_t)width + (uint64_t)x;
                rad_rng rng = rad_rng_make(seed, pixel);
                double sum[3] = {0, 0, 0};
                for (int s = 0; s < spp; ++s) {
                    double px = x + rad_rng_uniform(&rng), py = y + rad_rng_uniform(&rng);
                    double radiance[3];
                    rad_tracer_radiance(t, &rng, view.eye, rad_view_direction(&view, px, py),
                                        &counts, radiance);
                    for (int c = 0; c < 3; ++c) sum[c] += radiance[c];
                }
                float *p = image->pixels + 3 * pixel;
                for (int c = 0; c < 3; ++c) p[c] = (float)(sum[c] / spp);
            }
            int done;
#pragma omp atomic capture
            done = ++rows_done;
            if (omp_get_thread_num() == 0 && rad_progress(ctx, "path tracing", done, height)) {
#pragma omp atomic write
                cancelled = 1;
            }
        }
#pragma omp critical
        {
            total.paths += counts.paths;
            total.rays += counts.rays;
            total.camera_hits += counts.camera_hits;
            total.back_hits += counts.back_hits;
        }
    }
    rad_tracer_destroy(t);
    if (cancelled) {
        rad_image_free(image);
        return rad_fail(ctx, RAD_ERROR_CANCELLED, "path tracing cancelled");
    }
    if (rad_progress(ctx, "path tracing", height, height)) {
        rad_image_free(image);
        return rad_fail(ctx, RAD_ERROR_CANCELLED, "path tracing cancelled");
    }
    if (stats) {
        stats->seconds = rad_seconds() - start;
        stats->paths = total.paths;
        stats->rays = total.rays;
    }
    *out = image;
    return RAD_OK;
}
