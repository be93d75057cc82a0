/* test_specular_first.c - the specular-first pass (system/specular_first.c,
 * docs/specular-first.md) against a closed form: a small emitter facing up under a plane mirror
 * throws its light down onto a diffuse floor beside it. By the image-source construction the
 * floor sees the emitter mirrored in the mirror plane: a small Lambertian source of area a and
 * radiance L at height h above the floor, facing down, so the irradiance at a floor point at
 * distance r from the image is E = L a cos_source cos_floor / r^2 = L a h^2 / r^4. Each floor
 * element's specular emission must be rho times the mean of E over it; the floor gets nothing
 * else (the emitter faces away from it). The same photons with 1 and 2 threads give the same
 * bits, and --specular-first 0 (on = 0) leaves the system without the pass. The renderer's
 * caustic map (render/caustics.c), made of the same photons, gives at floor points
 * rho / pi E(x) of the same closed form, and in place of the deposit, not on top of it.
 * A point light of intensity I where the emitter was (photons from lights, scene/light_emission.h):
 * the floor's deposit is rho times the mean over each element of its image's E = I h / r^3. */
#include "mesh/mesh.h"
#include "render/render.h"
#include "scene/scene.h"
#include "system/system.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

#define EMITTER_HALF 0.05   /* the emitter: a 0.1 x 0.1 square */
#define EMITTER_X (-1.5)
#define EMITTER_Y 1.0
#define MIRROR_Y 2.0
#define RADIANCE 10.0
#define RHO 0.5
#define PHOTONS 400000
#define INTENSITY 2.0 /* the point light's, W/sr */

static rad_context *make_context(int threads) {
    rad_context_options options = {0};
    options.threads = threads;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) {
        fprintf(stderr, "cannot create a context\n");
        exit(1);
    }
    return ctx;
}

static uint32_t add_surface(rad_scene *scene, const char *name, const rad_material *m) {
    uint32_t material, surface;
    if (rad_scene_add_material(scene, m, &material) || rad_scene_add_surface(scene, name, material, &surface))
        exit(1);
    return surface;
}

/* Floor [0, 2] x [-1, 1] at y = 0 facing up; a perfect mirror [-3, 3] x [-2, 2] at y = MIRROR_Y
 * facing down; at (EMITTER_X, EMITTER_Y, 0) the emitter facing up, or with `point` a point light
 * of INTENSITY. */
static rad_scene *mirror_scene(rad_context *ctx, int on, int point, uint64_t photons) {
    rad_scene *scene = NULL;
    if (rad_scene_new(ctx, 1, "mirror-floor", &scene)) exit(1);
    rad_material grey = {0}, light = {0}, mirror = {0};
    grey.name = "grey";
    grey.reflectance[0] = grey.reflectance[1] = grey.reflectance[2] = RHO;
    light.name = "light";
    light.emission[0] = light.emission[1] = light.emission[2] = RADIANCE;
    mirror.name = "mirror";
    mirror.kind = RAD_MATERIAL_MIRROR;
    mirror.specular[0] = mirror.specular[1] = mirror.specular[2] = 1;
    uint32_t floor = add_surface(scene, "floor", &grey);
    uint32_t glass = add_surface(scene, "mirror", &mirror);
    rad_vec3 f[4] = {v3(0, 0, -1), v3(0, 0, 1), v3(2, 0, 1), v3(2, 0, -1)};
    const double s = EMITTER_HALF, x = EMITTER_X, y = EMITTER_Y;
    rad_vec3 l[4] = {v3(x - s, y, -s), v3(x - s, y, s), v3(x + s, y, s), v3(x + s, y, -s)};
    rad_vec3 m[4] = {v3(-3, MIRROR_Y, -2), v3(3, MIRROR_Y, -2), v3(3, MIRROR_Y, 2),
                     v3(-3, MIRROR_Y, 2)};
    if (rad_scene_add_polygon_points(scene, floor, f, 4) ||
        rad_scene_add_polygon_points(scene, glass, m, 4))
        exit(1);
    if (point) {
        rad_light_desc bulb = {0};
        bulb.type = RAD_LIGHT_TYPE_POINT;
        bulb.position[0] = EMITTER_X, bulb.position[1] = EMITTER_Y;
        bulb.color[0] = bulb.color[1] = bulb.color[2] = 1;
        bulb.strength = INTENSITY;
        bulb.units = RAD_LIGHT_WATTS;
        CHECK(rad_scene_add_light(scene, &bulb) == RAD_OK);
    } else if (rad_scene_add_polygon_points(scene, add_surface(scene, "light", &light), l, 4)) {
        exit(1);
    }
    CHECK(rad_scene_set_specular_first(scene, on, photons) == RAD_OK);
    return scene;
}

static rad_system *build(rad_context *ctx, rad_scene *scene) {
    rad_mesh_options mesh = {0};
    mesh.patch_size = 0.5;
    mesh.element_size = 0.5;
    rad_ff_options ff = {0};
    rad_system *system = NULL;
    if (rad_system_create(ctx, scene, &mesh, &ff, &system)) {
        fprintf(stderr, "system: %s\n", rad_context_error(ctx));
        exit(1);
    }
    return system;
}

/* L a h^2 / r^4 at floor point (x, 0, z). */
static double image_source_at(double x, double z) {
    const double h = 2 * MIRROR_Y - EMITTER_Y, a = 4 * EMITTER_HALF * EMITTER_HALF;
    double dx = x - EMITTER_X, r2 = dx * dx + z * z + h * h;
    return RADIANCE * a * h * h / (r2 * r2);
}

/* What the camera sees the floor emit at points of a grid inside it (a radius of the estimate
 * from its edges): the caustic map's rho / pi E(x), against the image source. */
static void test_caustic_map(rad_scene *scene, rad_system *s) {
    rad_camera_desc camera = {{1, 1.5, 0}, {1, 0, 0}, {0, 0, 1}, 60};
    rad_render_options o = {0};
    o.width = o.height = 8;
    o.final_gather = 1;
    o.camera = &camera;
    rad_renderer *r = NULL;
    CHECK(rad_renderer_create(scene, s, &o, &r) == RAD_OK);
    if (!r) return;
    rad_image *image = NULL;
    CHECK(rad_renderer_render(r, &image, NULL) == RAD_OK); /* fills the radiance arrays */
    rad_image_destroy(image);
    CHECK(r->caustics.count > 0 && r->caustics.count == s->caustic_landing_count);
    const int n = 12;
    double sum = 0, expected_sum = 0, worst = 0, square = 0;
    int points = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double x = 0.3 + 1.4 * (i + 0.5) / n, z = -0.7 + 1.4 * (j + 0.5) / n;
            rad_element_hit hit;
            if (!rad_element_rays_intersect(r->rays, v3(x, 1.5, z), v3(0, -1, 0), 0, INFINITY,
                                            &hit)) {
                CHECK(0);
                continue;
            }
            const float rho[3] = {RHO, RHO, RHO};
            double seen[3];
            rad_visible_emission(r, &hit, v3(x, 0, z), v3(0, 1, 0), rho, seen);
            double expected = RHO / RAD_PI * image_source_at(x, z);
            sum += seen[0];
            expected_sum += expected;
            worst = fmax(worst, fabs(seen[0] / expected - 1));
            square += (seen[0] / expected - 1) * (seen[0] / expected - 1);
            ++points;
        }
    double rms = points ? sqrt(square / points) : 1;
    printf("caustic map: %zu photons, %d floor points: mean %.2f%%, RMS %.2f%%, worst point "
           "%.2f%% off the image source\n",
           r->caustics.count, points, 100 * (sum / expected_sum - 1), 100 * rms, 100 * worst);
    /* The deposit and the map together would be twice the mean. A point's estimate holds 31
     * photons: its noise is about 1 / sqrt(31) = 18%. Measured: mean 0.43%, RMS 12%, worst 44%. */
    CHECK(fabs(sum / expected_sum - 1) < 0.03);
    CHECK(rms < 0.25);
    CHECK(worst < 0.7);
    rad_renderer_destroy(r);
}

/* The mean of L a h^2 / r^4 (the emitter's image) or I h / r^3 (with `point`: the point light's)
 * over the element (32 x 32 points of its bounding box, which is the element: the floor's
 * elements are axis-aligned squares). */
static double image_irradiance(const rad_system *s, size_t e, int point) {
    const rad_mesh *mesh = s->mesh;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
        rad_vec3 v = mesh->vertices[mesh->element_vertices[e][k]];
        lo[0] = fmin(lo[0], v.x), hi[0] = fmax(hi[0], v.x);
        lo[1] = fmin(lo[1], v.z), hi[1] = fmax(hi[1], v.z);
    }
    const double h = 2 * MIRROR_Y - EMITTER_Y, a = 4 * EMITTER_HALF * EMITTER_HALF;
    const int n = 32;
    double sum = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double dx = lo[0] + (hi[0] - lo[0]) * (i + 0.5) / n - EMITTER_X;
            double dz = lo[1] + (hi[1] - lo[1]) * (j + 0.5) / n;
            double r2 = dx * dx + dz * dz + h * h;
            sum += point ? INTENSITY * h / (r2 * sqrt(r2)) : RADIANCE * a * h * h / (r2 * r2);
        }
    return sum / (n * n);
}

/* The point light's photons through the mirror: each floor element's deposit against rho times
 * the image's mean E = I h / r^3 over it. */
static void test_point_light(rad_context *ctx) {
    rad_scene *scene = mirror_scene(ctx, 1, 1, 4 * PHOTONS);
    rad_system *s = build(ctx, scene);
    CHECK(s->specular_emission != NULL);
    double worst = 0, flux = 0, expected_flux = 0;
    size_t floor_elements = 0;
    for (size_t e = 0; s->specular_emission && e < s->element_count; ++e) {
        if (strcmp(s->surface_name[s->element_surface[e]], "floor") != 0) continue;
        ++floor_elements;
        double expected = RHO * image_irradiance(s, e, 1);
        worst = fmax(worst, fabs(s->specular_emission[e][0] / expected - 1));
        flux += s->specular_emission[e][0] * s->area[e];
        expected_flux += expected * s->area[e];
    }
    printf("point light: %zu floor elements, worst element %.2f%%, flux %.3f%% off the image "
           "source\n",
           floor_elements, 100 * worst, 100 * (flux / expected_flux - 1));
    CHECK(floor_elements == 16);
    CHECK(worst < 0.03);                          /* measured 0.47% (Sobol' photons) */
    CHECK(fabs(flux / expected_flux - 1) < 0.01); /* measured 0.04% */
    rad_system_destroy(s);
    rad_scene_destroy(scene);
}

int main(void) {
    rad_context *one = make_context(1), *two = make_context(2);
    rad_scene *scene = mirror_scene(two, -1, 0, PHOTONS);
    rad_system *s = build(two, scene);
    CHECK(s->specular_emission != NULL);
    /* Per floor element against the closed form; the floor's flux in total. */
    double worst = 0, flux = 0, expected_flux = 0;
    size_t floor_elements = 0;
    for (size_t e = 0; s->specular_emission && e < s->element_count; ++e) {
        if (strcmp(s->surface_name[s->element_surface[e]], "floor") != 0) {
            CHECK(s->specular_emission[e][0] == 0);
            continue;
        }
        ++floor_elements;
        double expected = RHO * image_irradiance(s, e, 0);
        worst = fmax(worst, fabs(s->specular_emission[e][0] / expected - 1));
        flux += s->specular_emission[e][0] * s->area[e];
        expected_flux += expected * s->area[e];
        /* The renderer sees the deposit as the floor's own emission (and nothing else). */
        CHECK(rad_system_own_emission(s, e, 0) == s->specular_emission[e][0]);
    }
    printf("floor: %zu elements, worst element %.2f%%, flux %.3f%% off the image source\n",
           floor_elements, 100 * worst, 100 * (flux / expected_flux - 1));
    CHECK(floor_elements == 16);
    CHECK(worst < 0.05);                          /* measured 1.4% (about 9000 photons each) */
    CHECK(fabs(flux / expected_flux - 1) < 0.01); /* measured 0.01% */

    /* The second pass (D S+ D): the emitter element given a reflected radiosity of pi L on top
     * of its emission, everything else black, is a diffuse source of radiance L where the
     * emitter is: the floor gets the same image-source irradiance, now as specular_reflection,
     * which the renderer finds through the mirror itself (not the floor's own emission). */
    rad_rgb *emission = malloc(s->element_count * sizeof *emission);
    CHECK(emission != NULL);
    if (emission) memcpy(emission, s->emission, s->element_count * sizeof *emission);
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c)
            s->radiosity[e][c] = strcmp(s->surface_name[s->element_surface[e]], "light") == 0
                                     ? 2 * RAD_PI * RADIANCE : 0;
    CHECK(rad_system_add_specular_reflection(s) == RAD_OK);
    CHECK(s->specular_reflection != NULL);
    double worst2 = 0, flux2 = 0;
    for (size_t e = 0; s->specular_reflection && e < s->element_count; ++e) {
        if (strcmp(s->surface_name[s->element_surface[e]], "floor") != 0) {
            CHECK(s->specular_reflection[e][0] == 0);
            continue;
        }
        double expected = RHO * image_irradiance(s, e, 0);
        worst2 = fmax(worst2, fabs(s->specular_reflection[e][0] / expected - 1));
        flux2 += s->specular_reflection[e][0] * s->area[e];
        CHECK(s->radiosity[e][0] == s->specular_reflection[e][0]); /* added to the solution */
        CHECK(fabs(rad_system_own_emission(s, e, 0) - s->specular_emission[e][0]) <= 1e-12);
    }
    printf("second pass: worst floor element %.2f%%, flux %.3f%% off the image source\n",
           100 * worst2, 100 * (flux2 / expected_flux - 1));
    CHECK(worst2 < 0.05);
    CHECK(fabs(flux2 / expected_flux - 1) < 0.01);
    /* Taken out again: the emission as before (a solve that starts over does this). */
    rad_system_remove_specular_reflection(s);
    CHECK(s->specular_reflection == NULL);
    for (size_t e = 0; emission && e < s->element_count; ++e)
        CHECK(fabs(s->emission[e][0] - emission[e][0]) <= 1e-12 * (1 + emission[e][0]));
    free(emission);
    /* A solve adds it once it has converged. */
    rad_solve_options solve = {0};
    CHECK(rad_solve(s, &solve, NULL) == RAD_OK);
    CHECK(s->specular_reflection != NULL);

    test_caustic_map(scene, s);
    test_point_light(two);

    /* The same bits for 1 and 2 threads. */
    rad_scene *again = mirror_scene(one, -1, 0, PHOTONS);
    rad_system *single = build(one, again);
    CHECK(single->specular_emission && s->specular_emission &&
          memcmp(single->specular_emission, s->specular_emission,
                 s->element_count * sizeof(rad_rgb)) == 0);
    rad_system_destroy(single);
    rad_scene_destroy(again);

    /* Off: no pass, no extra emission. */
    rad_scene *off = mirror_scene(two, 0, 0, PHOTONS);
    rad_system *plain = build(two, off);
    CHECK(plain->specular_emission == NULL);
    rad_system_destroy(plain);
    rad_scene_destroy(off);

    /* Bad values. */
    CHECK(rad_scene_set_specular_first(scene, 2, 0) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(rad_scene_set_specular_first(scene, 1, 2000000000u) == RAD_ERROR_INVALID_ARGUMENT);

    rad_system_destroy(s);
    rad_scene_destroy(scene);
    rad_context_destroy(one);
    rad_context_destroy(two);
    return test_finish();
}
