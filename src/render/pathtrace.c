/* pathtrace.c - the reference path tracer (see pathtrace.h, docs/pathtracing.md).
 *
 * Kajiya 1986 path tracing, with the estimator of Veach 1997 (ch. 9, 10):
 *   - at every vertex with a non-delta lobe, one emitter sample (next-event estimation): an
 *     emitting triangle chosen by power, a point uniform on it (the emitter table of
 *     light/emitters.h, which the renderer's final gather shares), a shadow ray;
 *   - one BSDF sample to continue the path; when it hits an emitter, its emission counts with
 *     the power-heuristic weight against the emitter sample, or fully after a delta lobe;
 *   - Russian roulette after three bounces, only on paths whose throughput is below 0.1;
 *   - optionally (not by default: it is biased) Cycles' clamping of indirect contributions.
 * Samples: Owen-scrambled Sobol' points (core/sampler.h, Burley 2020), one 2D dimension for the
 * position in the pixel (box filter) and three per bounce (emitter point, BSDF direction, lobe
 * choice and roulette), each a pure function of (seed, pixel, sample, dimension), so the image
 * does not depend on the thread count. */
#include "render/pathtrace.h"
#include "render/lights_next_event.h"
#include "scene/texture.h"

#include "image/image.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#define HARD_MAX_BOUNCES 1024 /* a safety net; Russian roulette ends paths long before */
#define ROULETTE_START 3   /* the first bounce whose continuation may be cut short */
#define ROULETTE_WEIGHT 0.1 /* paths whose throughput is above this always continue (default) */
#define ROULETTE_CAP_START 32 /* from here on at most 0.95, so lossless loops end too */
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
    t->roulette_weight = ROULETTE_WEIGHT;
    size_t polygons = scene->polygon_count;
    t->polygon_material = rad_alloc(ctx, polygons, sizeof *t->polygon_material);
    t->polygon_emitter = rad_alloc(ctx, polygons, sizeof *t->polygon_emitter);
    if (!t->polygon_material || !t->polygon_emitter) {
        rad_tracer_destroy(t);
        return RAD_ERROR_NO_MEMORY;
    }
    /* Emitters: every triangle of an emitting polygon, fanned the way Embree sees it, in one
     * table (light/emitters.h) that picks them by power, or by receiver among several lamps. */
    size_t light_triangles = 0;
    for (size_t i = 0; i < polygons; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const rad_material *m = &scene->materials[scene->surfaces[p->surface].material];
        t->polygon_material[i] = m;
        t->polygon_emitter[i] = -1;
        if (luminance_weight(m->emission) > 0) light_triangles += p->count - 2;
    }
    rad_status status = rad_emitter_table_reserve(ctx, &t->emitters, light_triangles);
    if (status) {
        rad_tracer_destroy(t);
        return status;
    }
    for (size_t i = 0; i < polygons && light_triangles; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const double *emission = t->polygon_material[i]->emission;
        if (!(luminance_weight(emission) > 0)) continue;
        rad_vec3 normal = rad_polygon_normal(scene, p);
        rad_vec3 p0 = rad_polygon_vertex(scene, p, 0);
        for (uint32_t k = 1; k + 1 < p->count; ++k) {
            int32_t index = rad_emitter_table_add(&t->emitters, p0, rad_polygon_vertex(scene, p, k),
                                                  rad_polygon_vertex(scene, p, k + 1), normal,
                                                  emission);
            if (t->polygon_emitter[i] < 0) t->polygon_emitter[i] = index;
        }
        /* One group per emitting polygon, for the choice by receiver (light/emitters.h). A hit
         * anywhere on the polygon maps to its first triangle: right, since the polygon's
         * emission is uniform, so every triangle of it has the same P_k / A_k, by receiver too. */
        rad_emitter_table_close_group(&t->emitters);
    }
    status = rad_emitter_table_finish(ctx, &t->emitters, RAD_EMITTERS_BY_POWER);
    if (!status) status = rad_rays_create(ctx, scene, &t->rays);
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
    rad_free(t->ctx, t->polygon_emitter);
    rad_emitter_table_free(t->ctx, &t->emitters);
    rad_free(t->ctx, t);
}

/* ---- one path ----------------------------------------------------------------------------- */

/* Adds one contribution to the radiance, scaled down so that its R + G + B is at most `limit`
 * when `limit` is positive (Cycles' sample clamping; biased). */
static void accumulate(double radiance[3], const double add[3], double limit) {
    double sum = fabs(add[0]) + fabs(add[1]) + fabs(add[2]);
    double factor = limit > 0 && sum > limit ? limit / sum : 1;
    for (int c = 0; c < 3; ++c) radiance[c] += add[c] * factor;
}

static double power_heuristic(double f, double g) {
    double f2 = f * f, g2 = g * g;
    return f2 + g2 > 0 ? f2 / (f2 + g2) : 0;
}

void rad_tracer_radiance(const rad_tracer *t, rad_sampler *sampler, rad_vec3 origin, rad_vec3 direction,
                         rad_trace_counts *counts, double out[3]) {
    const rad_rays *rays = t->rays;
    double radiance[3] = {0, 0, 0};
    double throughput[3] = {1, 1, 1};
    double previous_pdf = 0; /* solid-angle pdf of the BSDF sample that made this ray */
    int previous_delta = 1;  /* the camera ray counts as a delta: emitters seen fully */
    /* The front of the vertex this ray left, as its emitter sample saw it (the choice of lamp
     * depends on it): the hit's normal turned towards the outgoing direction, since the lobes
     * light is sampled for (diffuse, glossy) only reflect. */
    rad_vec3 previous_front = v3(0, 0, 0);
    double next_light[2] = {0, 0}; /* the emitter point of the next bounce */
    ++counts->paths;
    for (int bounce = 0;; ++bounce) {
        rad_hit hit;
        ++counts->rays;
        if (!rad_rays_intersect(rays, origin, direction, rays->epsilon, INFINITY, &hit)) {
            /* Left the scene: the sky (light/lights.h), found only this way. */
            double sky[3];
            rad_sky_radiance(&t->scene->sky, direction, sky);
            double add[3];
            for (int c = 0; c < 3; ++c) add[c] = throughput[c] * sky[c];
            accumulate(radiance, add, bounce >= 2 ? t->clamp_indirect : 0);
            break;
        }
        if (bounce == 0) {
            ++counts->camera_hits;
            if (!hit.front && t->polygon_material[hit.polygon]->kind != RAD_MATERIAL_GLASS)
                ++counts->back_hits;
        }
        const rad_material *m = t->polygon_material[hit.polygon];
        rad_vec3 x = v3_add(origin, v3_scale(direction, hit.t));
        /* A textured surface reflects its texture at x times the factor (scene/texture.h). */
        rad_material textured;
        m = rad_scene_material_at(t->scene, m, hit.polygon, x, &textured);
        rad_vec3 wo = v3_scale(direction, -1);
        rad_vec3 front = v3_dot(hit.normal, wo) >= 0 ? hit.normal : v3_scale(hit.normal, -1);

        /* Emission seen along the path (front sides only). */
        if (hit.front && t->polygon_emitter[hit.polygon] >= 0) {
            double weight = 1;
            if (!previous_delta && t->next_event) {
                double light_pdf = rad_emitter_table_pdf(
                    &t->emitters, (size_t)t->polygon_emitter[hit.polygon], origin, previous_front,
                    direction, hit.t);
                weight = power_heuristic(previous_pdf, light_pdf);
            }
            double add[3];
            for (int c = 0; c < 3; ++c) add[c] = throughput[c] * weight * m->emission[c];
            accumulate(radiance, add, bounce >= 2 ? t->clamp_indirect : 0);
        }
        if (bounce >= t->max_bounces) break;
        /* This bounce's numbers: the emitter point from the 4D set it shares with the
         * direction that led here (the pixel position at bounce 0), this bounce's direction
         * from the next set, and (lobe, roulette). */
        double u_light[2], u_direction[2], u_choice[2];
        if (bounce == 0) {
            sampler->dimension = RAD_PATH_DIM_PIXEL;
            double set[4];
            rad_sampler_4d(sampler, set);
            next_light[0] = set[2];
            next_light[1] = set[3];
        }
        u_light[0] = next_light[0];
        u_light[1] = next_light[1];
        {
            double set[4];
            sampler->dimension = RAD_PATH_DIM_BOUNCE + RAD_PATH_DIMS_PER_BOUNCE * (uint32_t)bounce;
            rad_sampler_4d(sampler, set);
            rad_sampler_2d(sampler, u_choice);
            u_direction[0] = set[0];
            u_direction[1] = set[1];
            next_light[0] = set[2];
            next_light[1] = set[3];
        }

        /* Next-event estimation: one point on the emitters, weighted against BSDF sampling. */
        if (t->next_event && t->emitters.count && rad_bsdf_has_smooth_lobe(m)) {
            rad_emitter_point light;
            double f[3], bsdf_pdf;
            if (rad_emitter_table_sample(&t->emitters, u_light[0], u_light[1], x, front, &light) &&
                rad_bsdf_eval(m, hit.normal, wo, light.direction, f, &bsdf_pdf)) {
                ++counts->rays;
                if (!rad_rays_occluded(rays, x, light.position)) {
                    double weight = power_heuristic(light.pdf, bsdf_pdf);
                    double cos_surface = fabs(v3_dot(light.direction, hit.normal));
                    double scale = weight * cos_surface / light.pdf, add[3];
                    for (int c = 0; c < 3; ++c)
                        add[c] = throughput[c] * f[c] * light.radiance[c] * scale;
                    accumulate(radiance, add, bounce >= 1 ? t->clamp_indirect : 0);
                }
            }
        }

        /* Point, spot and directional lights: each sampled exactly, with no weight (a BSDF
         * sample never finds a point or a direction). */
        if (rad_bsdf_has_smooth_lobe(m)) {
            double limit = bounce >= 1 ? t->clamp_indirect : 0;
            if (limit > 0) { /* the lights' sum clamped as one contribution */
                double add[3] = {0, 0, 0};
                rad_lights_next_event(t, m, x, hit.normal, wo, throughput, &counts->rays, add);
                accumulate(radiance, add, limit);
            } else {
                rad_lights_next_event(t, m, x, hit.normal, wo, throughput, &counts->rays,
                                      radiance);
            }
        }

        /* Continue the path by sampling the BSDF. */
        double u[3] = {u_choice[0], u_direction[0], u_direction[1]};
        rad_bsdf_sample s;
        if (rad_bsdf_sample_direction(m, hit.normal, wo, u, &s) == RAD_LOBE_NONE) break;
        for (int c = 0; c < 3; ++c) throughput[c] *= s.weight[c];
        previous_pdf = s.pdf;
        previous_delta = s.delta;
        previous_front = front;

        /* Russian roulette, only on paths that carry little: continue with probability
         * throughput / ROULETTE_WEIGHT where that is below 1. Cutting paths of larger weight
         * (the textbook q = throughput) is cheaper per path but throws away the tail of
         * paths that still carry much light: in the Cornell box it made the 4x4-block error at
         * 64 spp 1.5x larger, for 1.7x less time (docs/pathtracing.md, "Russian roulette"). */
        if (bounce + 1 >= ROULETTE_START) {
            double weight = v3_max_component(v3(throughput[0], throughput[1], throughput[2]));
            double q = fmin(bounce + 1 >= ROULETTE_CAP_START ? 0.95 : 1.0, weight / t->roulette_weight);
            if (!(u_choice[1] < q)) break;
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

/* Before any work: the camera must see the front of something (scene/camera.h's rule). */
static int tracer_see(const void *user, rad_vec3 eye, rad_vec3 direction, int *front,
                      const char **surface) {
    const rad_tracer *t = user;
    rad_hit hit;
    if (!rad_rays_intersect(t->rays, eye, direction, 0, INFINITY, &hit)) {
        *front = 1; /* the sky, when there is one, is what the camera sees */
        *surface = "sky";
        return t->scene->sky.kind != RAD_SKY_OFF;
    }
    *front = hit.front || t->polygon_material[hit.polygon]->kind == RAD_MATERIAL_GLASS;
    *surface = t->scene->surfaces[t->scene->polygons[hit.polygon].surface].name;
    return 1;
}

rad_status rad_tracer_check_view(const rad_tracer *t, const rad_view *view) {
    return rad_view_check(t->ctx, view, tracer_see, t);
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
    if (!(o.clamp_indirect >= 0) || isinf(o.clamp_indirect))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "path tracing: the indirect clamp must be zero (off) or a positive number");
    int width = o.width ? o.width : DEFAULT_SIZE, height = o.height ? o.height : DEFAULT_SIZE;
    int spp = o.samples_per_pixel ? o.samples_per_pixel : DEFAULT_SPP;
    if (!scene) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "path tracing: no scene");
    if (!scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: path tracing needs geometry, not a patch system", scene->source);
    rad_camera camera = o.camera ? rad_camera_from_desc(o.camera) : rad_scene_camera(scene);
    rad_view view;
    rad_status status = rad_view_make(ctx, &camera, width, height, &view);
    if (status) return status;

    rad_tracer *t;
    status = rad_tracer_create(ctx, scene, o.max_bounces, &t);
    if (status) return status;
    t->clamp_indirect = o.clamp_indirect;
    status = rad_tracer_check_view(t, &view);
    if (!status && !rad_scene_is_lit(scene))
        rad_warn(ctx, "%s: nothing emits light: the image is black", scene->source);
    rad_image *image = NULL;
    if (!status) status = rad_image_new(ctx, width, height, &image);
    if (status) {
        rad_tracer_destroy(t);
        return status;
    }

    /* Passes over the whole image: 1 path per pixel first, then passes sized to last about as
     * long as the render so far (at least a second), so a render of any length can be stopped
     * (Ctrl-C through the progress callback, or the time budget, checked after every row) with
     * an image of the whole frame, and the first pass's time forecasts the rest. Each pixel's
     * paths are added in sample order into a double sum, so the image has the same bits however
     * the passes fall: the one of a single pass. When the sums do not fit the memory budget
     * beside the image, one pass writes the image directly, as before passes. */
    const size_t pixels = (size_t)width * (size_t)height;
    double *sums = NULL;
    int *row_samples = rad_alloc_zero(ctx, (size_t)height, sizeof *row_samples);
    if (row_samples && spp > 1 &&
        (double)pixels * (3 * sizeof(float) + 3 * sizeof(double)) <= (double)ctx->max_memory)
        sums = rad_alloc_zero(ctx, 3 * pixels, sizeof *sums); /* NULL: one pass */
    if (!row_samples) {
        rad_image_free(image);
        rad_tracer_destroy(t);
        return RAD_ERROR_NO_MEMORY;
    }
    int threads = rad_thread_count(ctx);
    rad_trace_counts total = {0};
    int cancelled = 0, timed_out = 0, done = 0;
    const double deadline = o.time_budget > 0 ? start + o.time_budget : INFINITY;
    double first_pass_seconds = 0, passes_start = rad_seconds();
    uint64_t seed = ctx->seed;
    while (done < spp && !cancelled && !timed_out) {
        int pass = sums ? 1 : spp;
        if (done > 0) {
            /* Samples that fit in max(1 s, the time so far) at the rate measured so far. */
            double elapsed = rad_seconds() - start, per_sample = first_pass_seconds;
            if (done > 1) per_sample = elapsed / done;
            double fit = fmax(1.0, elapsed) / fmax(per_sample, 1e-9);
            pass = fit >= spp - done ? spp - done : (int)fmax(1.0, fit);
        }
        const int s0 = done, s1 = done + pass;
        int rows_done = 0;
#pragma omp parallel num_threads(threads)
        {
            rad_trace_counts counts = {0};
#pragma omp for schedule(dynamic, 1)
            for (int y = 0; y < height; ++y) {
                int stop;
#pragma omp atomic read
                stop = cancelled;
                if (!stop) {
#pragma omp atomic read
                    stop = timed_out;
                }
                if (stop) continue;
                for (int x = 0; x < width; ++x) {
                    uint64_t pixel = (uint64_t)y * (uint64_t)width + (uint64_t)x;
                    rad_sampler sampler = rad_sampler_make(seed, 0);
                    double local[3] = {0, 0, 0};
                    double *sum = sums ? sums + 3 * pixel : local;
                    for (int s = s0; s < s1; ++s) {
                        sampler.index = rad_sampler_pixel_index((uint32_t)x, (uint32_t)y,
                                                                (uint32_t)spp, (uint32_t)s);
                        sampler.dimension = RAD_PATH_DIM_PIXEL;
                        double jitter[4];
                        rad_sampler_4d(&sampler, jitter);
                        double px = x + jitter[0], py = y + jitter[1];
                        double radiance[3];
                        rad_tracer_radiance(t, &sampler, view.eye,
                                            rad_view_direction(&view, px, py), &counts, radiance);
                        for (int c = 0; c < 3; ++c) sum[c] += radiance[c];
                    }
                    float *p = image->pixels + 3 * pixel;
                    for (int c = 0; c < 3; ++c) p[c] = (float)(sum[c] / s1);
                }
                row_samples[y] = s1;
                int finished;
#pragma omp atomic capture
                finished = ++rows_done;
                /* The budget is checked from the second pass on: the first gives every pixel
                 * a path. */
                if (s0 > 0 && rad_seconds() >= deadline) {
#pragma omp atomic write
                    timed_out = 1;
                }
                double progress = s0 + (double)(s1 - s0) * finished / height;
                if (omp_get_thread_num() == 0 && rad_progress(ctx, "path tracing", progress, spp)) {
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
        if (rows_done == height) done = s1;
        if (s0 == 0 && done == s1) {
            /* The first pass forecasts the rest: said when it is long. */
            first_pass_seconds = (rad_seconds() - passes_start) / s1;
            double forecast = first_pass_seconds * spp;
            if (spp > s1 && forecast > 60 && !cancelled)
                rad_info(ctx, "path tracing: %d paths per pixel will take about %.3g %s at %.3g s "
                              "a path per pixel; Ctrl-C or a time budget stops with the image so "
                              "far", spp, forecast >= 86400 ? forecast / 86400
                                          : forecast >= 3600 ? forecast / 3600 : forecast / 60,
                         forecast >= 86400 ? "days" : forecast >= 3600 ? "hours" : "minutes",
                         first_pass_seconds);
        }
    }
    rad_tracer_destroy(t);
    rad_free(ctx, sums);
    int fewest = spp, most = 0;
    for (int y = 0; y < height; ++y) {
        fewest = row_samples[y] < fewest ? row_samples[y] : fewest;
        most = row_samples[y] > most ? row_samples[y] : most;
    }
    rad_free(ctx, row_samples);
    /* Stopped before every pixel had a path: nothing to show (the time budget waits for it). */
    if (fewest == 0 || (!cancelled && !timed_out &&
                        rad_progress(ctx, "path tracing", spp, spp))) {
        rad_image_free(image);
        return rad_fail(ctx, RAD_ERROR_CANCELLED, "path tracing cancelled");
    }
    if (stats) {
        stats->seconds = rad_seconds() - start;
        stats->paths = total.paths;
        stats->rays = total.rays;
        stats->samples_min = fewest;
        stats->samples_max = most;
        stats->stopped = cancelled ? RAD_PATHTRACE_CANCELLED
                         : timed_out ? RAD_PATHTRACE_TIME_BUDGET : RAD_PATHTRACE_DONE;
    }
    *out = image;
    return RAD_OK;
}
