/* test_pathtrace.c - the reference path tracer against closed forms:
 *   - furnace: a closed box whose walls all emit L and reflect rho shows L / (1 - rho) in every
 *     pixel; a clear glass sphere and a white perfect mirror inside it must stay invisible;
 *   - direct light on two parallel squares against the point-to-polygon form factor, with
 *     light sampling + MIS and with BSDF sampling alone;
 *   - the Cornell box: MIS and BSDF-only estimators agree on the mean;
 *   - the same seed gives the same image with 1 and 2 threads; another seed does not;
 *   - --clamp (Cycles' Clamp Indirect) only scales down light that scattered twice or more:
 *     with the same seed every pixel lies between the direct-light image and the unclamped one;
 *   - cornell-mirror: the sphere is closed, faces out, and touches neither block;
 *   - a camera that sees nothing or sits inside a block is refused. */
#include "formfactor/geometric.h"
#include "image/image.h"
#include "render/pathtrace.h"
#include "test.h"

#include <string.h>

static rad_context *make_context(int threads, uint64_t seed) {
    rad_context_options options = {0};
    options.threads = threads;
    options.seed = seed;
    rad_context *ctx = NULL;
    rad_context_create(&options, &ctx);
    return ctx;
}

static void add_quad(rad_scene *scene, uint32_t surface, rad_vec3 a, rad_vec3 b, rad_vec3 c,
                     rad_vec3 d) {
    rad_vec3 points[4] = {a, b, c, d};
    rad_scene_add_polygon_points(scene, surface, points, 4);
}

/* A closed box [0, s]^3 seen from inside: every wall emits L and reflects rho. */
static rad_scene *furnace_box(rad_context *ctx, double rho, double radiance) {
    rad_scene *scene;
    if (rad_scene_new(ctx, 1, "furnace", &scene)) return NULL;
    rad_material wall = {0};
    wall.name = "wall";
    for (int c = 0; c < 3; ++c) {
        wall.reflectance[c] = rho;
        wall.emission[c] = radiance;
    }
    uint32_t material, surface;
    rad_scene_add_material(scene, &wall, &material);
    rad_scene_add_surface(scene, "walls", material, &surface);
    double s = 10;
    rad_vec3 p000 = v3(0, 0, 0), p100 = v3(s, 0, 0), p010 = v3(0, s, 0), p110 = v3(s, s, 0);
    rad_vec3 p001 = v3(0, 0, s), p101 = v3(s, 0, s), p011 = v3(0, s, s), p111 = v3(s, s, s);
    add_quad(scene, surface, p000, p100, p110, p010); /* z = 0, facing +z */
    add_quad(scene, surface, p001, p011, p111, p101); /* z = s, facing -z */
    add_quad(scene, surface, p000, p001, p101, p100); /* y = 0, facing +y */
    add_quad(scene, surface, p010, p110, p111, p011); /* y = s, facing -y */
    add_quad(scene, surface, p000, p010, p011, p001); /* x = 0, facing +x */
    add_quad(scene, surface, p100, p101, p111, p110); /* x = s, facing -x */
    scene->has_camera = 1;
    scene->camera = (rad_camera){v3(5, 5, 0.5), v3(5, 5, 10), v3(0, 1, 0), 90};
    return scene;
}

/* An octahedron-ish closed glass or mirror object: a UV sphere of quads and triangles. */
static void add_sphere(rad_scene *scene, uint32_t surface, rad_vec3 center, double radius) {
    enum { SLICES = 16, STACKS = 8 };
    rad_vec3 ring[STACKS + 1][SLICES];
    for (int i = 0; i <= STACKS; ++i)
        for (int j = 0; j < SLICES; ++j) {
            double theta = RAD_PI * i / STACKS, phi = 2 * RAD_PI * j / SLICES;
            ring[i][j] = v3_add(center, v3(radius * sin(theta) * cos(phi), radius * cos(theta),
                                           radius * sin(theta) * sin(phi)));
        }
    for (int i = 0; i < STACKS; ++i)
        for (int j = 0; j < SLICES; ++j) {
            int k = (j + 1) % SLICES;
            rad_vec3 a = ring[i][j], b = ring[i][k], c = ring[i + 1][k], d = ring[i + 1][j];
            if (i == 0) rad_scene_add_polygon_points(scene, surface, (rad_vec3[]){a, c, d}, 3);
            else if (i == STACKS - 1)
                rad_scene_add_polygon_points(scene, surface, (rad_vec3[]){a, b, c}, 3);
            else rad_scene_add_polygon_points(scene, surface, (rad_vec3[]){a, b, c, d}, 4);
        }
}

static void check_furnace(const char *what, rad_scene *scene, double expected, int spp) {
    rad_context *ctx = scene->ctx;
    rad_pathtrace_options options = {0};
    options.width = options.height = 24;
    options.samples_per_pixel = spp;
    rad_image *image = NULL;
    rad_status status = rad_pathtrace(ctx, scene, &options, &image, NULL);
    CHECK(status == RAD_OK);
    if (status) {
        fprintf(stderr, "%s: %s\n", what, rad_context_error(ctx));
        return;
    }
    double sum = 0, worst = 0;
    size_t count = (size_t)image->width * image->height * 3;
    for (size_t i = 0; i < count; ++i) {
        sum += image->pixels[i];
        worst = fmax(worst, fabs(image->pixels[i] - expected) / expected);
    }
    fprintf(stderr, "%s: mean %.5f (expected %.5f), worst pixel %.1f%%\n", what, sum / count,
            expected, 100 * worst);
    /* The mean is known to about 0.1 % (512 paths in each of 576 pixels); single pixels behind
     * the glass scatter by about 4 %. */
    CHECK_NEAR(sum / count, expected, 0.005 * expected);
    CHECK(worst < 0.25);
    rad_image_free(image);
}

static void test_furnace(void) {
    rad_context *ctx = make_context(0, 1);
    const double rho = 0.5, radiance = 0.75;
    rad_scene *scene = furnace_box(ctx, rho, radiance);
    CHECK(scene != NULL);
    if (!scene) return;
    check_furnace("furnace", scene, radiance / (1 - rho), 512);

    /* A clear glass sphere (tint 1) and a white perfect mirror sphere: invisible in a furnace,
     * because neither absorbs and radiance crossing the glass is scaled back on the way out. */
    rad_material glass = {0};
    glass.name = "glass";
    glass.kind = RAD_MATERIAL_GLASS;
    glass.specular[0] = glass.specular[1] = glass.specular[2] = 1;
    glass.ior = 1.5;
    rad_material mirror = glass;
    mirror.name = "mirror";
    mirror.kind = RAD_MATERIAL_MIRROR;
    uint32_t glass_material, mirror_material, surface;
    rad_scene_add_material(scene, &glass, &glass_material);
    rad_scene_add_material(scene, &mirror, &mirror_material);
    rad_scene_add_surface(scene, "glass ball", glass_material, &surface);
    add_sphere(scene, surface, v3(3.5, 5, 6), 2.2);
    rad_scene_add_surface(scene, "mirror ball", mirror_material, &surface);
    add_sphere(scene, surface, v3(7, 4, 7), 1.5);
    check_furnace("furnace with glass and mirror", scene, radiance / (1 - rho), 512);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

/* Direct light only (max_bounces 1) on the receiver of two-squares: reflected radiance at a
 * point x is rho * L * F(dx -> emitter), Lambert's closed form. */
static void test_direct_light(void) {
    rad_context *ctx = make_context(1, 3);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(ctx, "two-squares", &scene) == RAD_OK);
    if (!scene) return;
    rad_tracer *tracer = NULL;
    CHECK(rad_tracer_create(ctx, scene, 1, &tracer) == RAD_OK);
    if (!tracer) return;
    rad_vec3 emitter[4] = {v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0), v3(0, 1, 0)};
    const double rho = 0.5, radiance = 1 / RAD_PI;
    const rad_vec3 points[3] = {v3(0.5, 0.5, 1), v3(0.1, 0.2, 1), v3(0.95, 0.6, 1)};
    for (int strategy = 1; strategy >= 0; --strategy) {
        tracer->next_event = strategy;
        for (int i = 0; i < 3; ++i) {
            rad_vec3 n = v3(0, 0, -1);
            double expected = rho * radiance * rad_ff_point_polygon(points[i], n, emitter, 4);
            rad_sampler sampler = rad_sampler_make(5, (uint64_t)i << 32);
            rad_trace_counts counts = {0};
            double sum = 0;
            const int samples = strategy ? 20000 : 80000;
            for (int s = 0; s < samples; ++s) {
                double radiance_out[3];
                sampler.index = ((uint64_t)i << 32) + (uint64_t)s;
                sampler.dimension = RAD_PATH_DIM_BOUNCE;
                rad_tracer_radiance(tracer, &sampler, v3_add(points[i], v3(0, 0, -0.5)), v3(0, 0, 1),
                                    &counts, radiance_out);
                sum += radiance_out[0];
            }
            double estimate = sum / samples;
            CHECK_NEAR(estimate, expected, 0.015 * expected);
            if (fabs(estimate - expected) > 0.015 * expected)
                fprintf(stderr, "direct light (%s) at point %d: %.6f, expected %.6f\n",
                        strategy ? "MIS" : "BSDF only", i, estimate, expected);
        }
    }
    rad_tracer_destroy(tracer);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

/* The mean of a small Cornell image, by the MIS estimator and by BSDF sampling alone. */
static void test_estimators_agree(void) {
    rad_context *ctx = make_context(0, 9);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK);
    if (!scene) return;
    rad_tracer *tracer = NULL;
    CHECK(rad_tracer_create(ctx, scene, 0, &tracer) == RAD_OK);
    if (!tracer) return;
    rad_view view;
    rad_camera camera = rad_scene_camera(scene);
    rad_view_make(ctx, &camera, 16, 16, &view);
    double mean[2][3] = {{0}};
    for (int strategy = 0; strategy < 2; ++strategy) {
        tracer->next_event = strategy;
        const int spp = strategy ? 512 : 8192;
        double sum[3] = {0, 0, 0};
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : sum[:3])
        for (int pixel = 0; pixel < 16 * 16; ++pixel) {
            rad_sampler sampler = rad_sampler_make(17 + strategy, 0);
            rad_trace_counts counts = {0};
            for (int s = 0; s < spp; ++s) {
                double jitter[2];
                sampler.index = rad_sampler_pixel_index((uint32_t)(pixel % 16),
                                                        (uint32_t)(pixel / 16), (uint32_t)spp,
                                                        (uint32_t)s);
                sampler.dimension = RAD_PATH_DIM_PIXEL;
                rad_sampler_2d(&sampler, jitter);
                double px = pixel % 16 + jitter[0], py = pixel / 16 + jitter[1];
                double radiance[3];
                rad_tracer_radiance(tracer, &sampler, view.eye, rad_view_direction(&view, px, py),
                                    &counts, radiance);
                for (int c = 0; c < 3; ++c) sum[c] += radiance[c] / spp;
            }
        }
        for (int c = 0; c < 3; ++c) mean[strategy][c] = sum[c] / 256;
    }
    for (int c = 0; c < 3; ++c) {
        fprintf(stderr, "cornell mean, channel %d: MIS %.5f, BSDF only %.5f\n", c, mean[1][c],
                mean[0][c]);
        CHECK_NEAR(mean[1][c], mean[0][c], 0.02 * mean[1][c]);
    }
    rad_tracer_destroy(tracer);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static rad_image *trace_cornell(int threads, uint64_t seed, const char *scene_name) {
    rad_context *ctx = make_context(threads, seed);
    rad_scene *scene = NULL;
    rad_image *image = NULL;
    if (rad_scene_builtin(ctx, scene_name, &scene) == RAD_OK) {
        rad_pathtrace_options options = {0};
        options.width = 20;
        options.height = 16;
        options.samples_per_pixel = 4;
        rad_status status = rad_pathtrace(ctx, scene, &options, &image, NULL);
        if (status) fprintf(stderr, "pathtrace: %s\n", rad_context_error(ctx));
    }
    rad_scene_destroy(scene);
    /* The image keeps a pointer to its context for freeing: copy it out. */
    rad_image *copy = NULL;
    if (image) {
        rad_context *keep = make_context(1, 0);
        if (rad_image_new(keep, image->width, image->height, &copy) == RAD_OK)
            memcpy(copy->pixels, image->pixels, sizeof(float) * 3 * image->width * image->height);
        rad_image_free(image);
    }
    rad_context_destroy(ctx);
    return copy;
}

/* The Cornell box, 24 x 24 pixels, 8 paths, seed 5, with the given bounce limit and clamp. */
static rad_image *trace_clamped(int max_bounces, double clamp_indirect) {
    rad_context *ctx = make_context(1, 5);
    rad_scene *scene = NULL;
    rad_image *image = NULL;
    if (rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK) {
        rad_pathtrace_options options = {0};
        options.width = options.height = 24;
        options.samples_per_pixel = 8;
        options.max_bounces = max_bounces;
        options.clamp_indirect = clamp_indirect;
        if (rad_pathtrace(ctx, scene, &options, &image, NULL))
            fprintf(stderr, "pathtrace: %s\n", rad_context_error(ctx));
    }
    rad_scene_destroy(scene);
    return image; /* freed with its context by free_with_context */
}

static void free_with_context(rad_image *image);

static void test_clamp(void) {
    rad_image *direct = trace_clamped(1, 0), *full = trace_clamped(0, 0);
    rad_image *clamped = trace_clamped(0, 0.05);
    CHECK(direct && full && clamped);
    if (direct && full && clamped) {
        /* The same paths: clamping scales down some of the indirect terms, never the direct
         * ones (which a one-bounce path sums in the same order), so per pixel and channel
         * direct <= clamped <= full; with a clamp this low, the sum is strictly lower. */
        size_t n = 3 * (size_t)full->width * full->height;
        int ordered = 1;
        double sum_clamped = 0, sum_full = 0;
        for (size_t i = 0; i < n; ++i) {
            ordered &= direct->pixels[i] <= clamped->pixels[i];
            ordered &= clamped->pixels[i] <= full->pixels[i];
            sum_clamped += clamped->pixels[i];
            sum_full += full->pixels[i];
        }
        CHECK(ordered);
        CHECK(sum_clamped < 0.99 * sum_full);
    }
    free_with_context(direct);
    free_with_context(full);
    free_with_context(clamped);
    /* A negative or NaN clamp is refused. */
    rad_context *ctx = make_context(1, 0);
    rad_scene *scene = NULL;
    rad_image *image = NULL;
    CHECK(rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK);
    rad_pathtrace_options options = {0};
    options.width = options.height = 4;
    options.clamp_indirect = -1;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    options.clamp_indirect = NAN;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(image == NULL);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static void free_with_context(rad_image *image) {
    if (!image) return;
    rad_context *ctx = image->ctx;
    rad_image_free(image);
    rad_context_destroy(ctx);
}

static void test_determinism(void) {
    const char *scenes[2] = {"cornell", "cornell-mirror"};
    for (int s = 0; s < 2; ++s) {
        rad_image *one = trace_cornell(1, 42, scenes[s]);
        rad_image *two = trace_cornell(2, 42, scenes[s]);
        rad_image *other = trace_cornell(2, 43, scenes[s]);
        CHECK(one && two && other);
        if (one && two && other) {
            size_t bytes = sizeof(float) * 3 * one->width * one->height;
            CHECK(memcmp(one->pixels, two->pixels, bytes) == 0);
            CHECK(memcmp(one->pixels, other->pixels, bytes) != 0);
            if (s == 0) {
                /* Upright and not mirrored: red wall on the left, green on the right, the
                 * light in the top rows. (The wider image also sees past the walls.) */
                int w = one->width, h = one->height;
                const float *left = one->pixels + 3 * (size_t)(w * (h / 2) + 3);
                const float *right = one->pixels + 3 * (size_t)(w * (h / 2) + w - 4);
                CHECK(left[0] > 2 * left[1]);
                CHECK(right[1] > 2 * right[0]);
                /* The light fills pixels of row 2 (row 1 holds only its edge, which four
                 * samples a pixel may all miss): the top three rows against the bottom three. */
                double top = 0, bottom = 0;
                for (int row = 0; row < 3; ++row)
                    for (int x = 0; x < w; ++x) {
                        top += one->pixels[3 * (size_t)(w * row + x)];
                        bottom += one->pixels[3 * (size_t)(w * (h - 1 - row) + x)];
                    }
                CHECK(top > bottom);
            }
        }
        free_with_context(one);
        free_with_context(two);
        free_with_context(other);
    }
}

static void test_cornell_mirror_scene(void) {
    rad_context *ctx = make_context(1, 0);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(ctx, "cornell-mirror", &scene) == RAD_OK);
    if (!scene) return;
    int glass = 0, mirror = 0, outward = 1;
    double sphere_area = 0;
    rad_vec3 lo = v3(1e9, 1e9, 1e9), hi = v3(-1e9, -1e9, -1e9);
    rad_vec3 sum = v3(0, 0, 0);
    size_t corners = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const rad_material *m = &scene->materials[scene->surfaces[p->surface].material];
        if (m->kind == RAD_MATERIAL_MIRROR) {
            ++mirror;
            CHECK(m->reflectance[0] == 0 && m->reflectance[1] == 0 && m->reflectance[2] == 0);
        }
        if (m->kind != RAD_MATERIAL_GLASS) continue;
        ++glass;
        CHECK(m->reflectance[0] == 0 && m->ior == 1.5);
        sphere_area += rad_polygon_area(scene, p);
        for (uint32_t k = 0; k < p->count; ++k) {
            rad_vec3 v = rad_polygon_vertex(scene, p, k);
            lo = v3(fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z));
            hi = v3(fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z));
            sum = v3_add(sum, v);
            ++corners;
        }
    }
    CHECK(mirror == 5);
    CHECK(glass > 500); /* fine enough to look round */
    rad_vec3 center = v3_scale(v3_add(lo, hi), 0.5);
    double radius = 0.5 * (hi.y - lo.y);
    CHECK_NEAR(sphere_area, 4 * RAD_PI * radius * radius, 0.01 * sphere_area);
    CHECK(lo.y > 0 && lo.y < 1); /* on the floor */
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        if (scene->materials[scene->surfaces[p->surface].material].kind != RAD_MATERIAL_GLASS)
            continue;
        rad_vec3 c = v3(0, 0, 0);
        for (uint32_t k = 0; k < p->count; ++k) c = v3_add(c, rad_polygon_vertex(scene, p, k));
        c = v3_scale(c, 1.0 / p->count);
        if (v3_dot(rad_polygon_normal(scene, p), v3_sub(c, center)) <= 0) outward = 0;
    }
    CHECK(outward);
    /* Clear of both blocks: no block corner within the sphere's reach (in plan), and the
     * sphere's footprint square outside both block footprints' bounding boxes in x or z. */
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const char *name = scene->surfaces[p->surface].name;
        if (strcmp(name, "tall-block") && strcmp(name, "short-block")) continue;
        for (uint32_t k = 0; k < p->count; ++k) {
            rad_vec3 v = rad_polygon_vertex(scene, p, k);
            double dx = v.x - center.x, dz = v.z - center.z;
            CHECK(sqrt(dx * dx + dz * dz) > radius + 5);
        }
    }
    /* The ray through the sphere's centre from the camera hits glass first. */
    rad_rays *rays = NULL;
    CHECK(rad_rays_create(ctx, scene, &rays) == RAD_OK);
    if (rays) {
        rad_hit hit;
        rad_vec3 eye = scene->camera.eye;
        CHECK(rad_rays_intersect(rays, eye, v3_normalize(v3_sub(center, eye)), 0, INFINITY, &hit));
        CHECK(strcmp(scene->surfaces[scene->polygons[hit.polygon].surface].name, "glass-sphere") == 0);
        CHECK(hit.front);
    }
    rad_rays_destroy(rays);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static void test_bad_cameras(void) {
    rad_context *ctx = make_context(0, 0);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK);
    if (!scene) return;
    rad_camera_desc away = {{278, 273, -800}, {278, 273, -1600}, {0, 1, 0}, 39};
    rad_pathtrace_options options = {0};
    options.width = options.height = 8;
    options.samples_per_pixel = 1;
    options.camera = &away;
    rad_image *image = NULL;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(image == NULL);
    CHECK(strstr(rad_context_error(ctx), "camera sees nothing") != NULL);
    /* Inside the tall block (its faces point out): drawn, the backs black (a warning). */
    rad_camera_desc inside = {{368, 165, 351}, {368, 165, 600}, {0, 1, 0}, 60};
    options.camera = &inside;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_OK);
    if (image) {
        double sum = 0;
        for (size_t i = 0; i < (size_t)image->width * image->height * 3; ++i)
            sum += image->pixels[i];
        CHECK(sum == 0);
    }
    rad_image_destroy(image);
    image = NULL;
    /* Zero and huge sizes, bad field of view. */
    options.camera = NULL;
    options.width = 100000;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    options.width = -1;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    rad_camera_desc wide = {{278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 180};
    options.width = 8;
    options.camera = &wide;
    CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    rad_scene_destroy(scene);
    /* A patch system has no geometry. */
    const char *ffm = "patches 1\npatch a area 1 reflectance 0.5 emission 1\n";
    if (rad_scene_parse_ffm(ctx, ffm, strlen(ffm), "one.ffm", &scene) == RAD_OK) {
        options.camera = NULL;
        CHECK(rad_pathtrace(ctx, scene, &options, &image, NULL) == RAD_ERROR_INVALID_ARGUMENT);
        rad_scene_destroy(scene);
    }
    rad_context_destroy(ctx);
}

int main(void) {
    test_furnace();
    test_direct_light();
    test_estimators_agree();
    test_determinism();
    test_clamp();
    test_cornell_mirror_scene();
    test_bad_cameras();
    return test_finish();
}
