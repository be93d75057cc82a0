/* test_lights.c - point, spot and directional lights, the sky and IES profiles (docs/lights.md)
 * against closed forms: a point light above a plane (irradiance I cos / r^2 per element, total
 * flux I Omega of the square), the sun on a plane (E cos), a uniform and an overcast sky on an
 * open plane (pi L, 7 pi L_z / 9), a shadow, a spot cone, photometric units, every solver
 * starting from the same pre-pass, the lights of scenes/lights-room.gltf through the import
 * child, and IES LM-63 files good and bad (file:line). */
#include "hierarchy/hierarchy.h"
#include "light/lights.h"
#include "mesh/mesh.h"
#include "scene/rays.h"
#include "scene/scene.h"
#include "system/system.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static rad_context *make_context(void) {
    rad_context_options options = {0};
    options.threads = 2;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) {
        fprintf(stderr, "cannot create a context\n");
        exit(1);
    }
    return ctx;
}

/* A square [-a, a]^2 in the plane y = 0 facing +Y, reflectance rho. */
static rad_scene *plane_scene(rad_context *ctx, double a, double rho) {
    rad_scene *scene = NULL;
    if (rad_scene_new(ctx, 1, "plane", &scene)) exit(1);
    rad_material grey = {0};
    grey.name = "grey";
    grey.reflectance[0] = grey.reflectance[1] = grey.reflectance[2] = rho;
    uint32_t material, surface;
    rad_scene_add_material(scene, &grey, &material);
    rad_scene_add_surface(scene, "floor", material, &surface);
    rad_vec3 square[4] = {v3(-a, 0, -a), v3(-a, 0, a), v3(a, 0, a), v3(a, 0, -a)};
    rad_scene_add_polygon_points(scene, surface, square, 4);
    return scene;
}

static rad_system *build(rad_context *ctx, const rad_scene *scene, double element_size) {
    rad_mesh_options mesh = {0};
    mesh.patch_size = element_size * 2;
    mesh.element_size = element_size;
    rad_ff_options ff = {0};
    rad_system *system = NULL;
    rad_status status = rad_system_create(ctx, scene, &mesh, &ff, &system);
    if (status) {
        fprintf(stderr, "system: %s\n", rad_context_error(ctx));
        exit(1);
    }
    return system;
}

static void point_light_above_plane(rad_context *ctx) {
    const double a = 1, h = 0.7, rho = 0.5, I = 3;
    rad_scene *scene = plane_scene(ctx, a, rho);
    rad_light_desc bulb = {0};
    bulb.name = "bulb";
    bulb.type = RAD_LIGHT_TYPE_POINT;
    bulb.position[1] = h;
    bulb.strength = I;
    CHECK(rad_scene_add_light(scene, &bulb) == RAD_OK);
    rad_system *s = build(ctx, scene, 0.1);
    /* Each element: rho times the mean of I cos / r^2 = I h / r^3 over it; at the centroid
     * that is within the element's curvature of the mean. */
    double worst = 0, power = 0;
    for (size_t e = 0; e < s->element_count; ++e) {
        rad_vec3 x = s->mesh->element_centroid[e];
        double r = sqrt(x.x * x.x + h * h + x.z * x.z);
        double expected = rho * I * h / (r * r * r);
        worst = fmax(worst, fabs(s->light_emission[e][0] / expected - 1));
        power += s->light_emission[e][0] * s->area[e];
    }
    CHECK(worst < 0.01);
    /* The whole square: flux I Omega with Omega = 4 asin(a^2 / (a^2 + h^2)) for a square of
     * side 2a seen from height h above its centre; the element factors add up to it exactly. */
    double omega = 4 * asin(a * a / (a * a + h * h));
    CHECK_NEAR(power / (rho * I * omega), 1, 1e-9);
    rad_system_destroy(s);
    rad_scene_destroy(scene);
}

static void photometric_units(rad_context *ctx) {
    rad_scene *scene = plane_scene(ctx, 1, 0.5);
    rad_light_desc d = {0};
    d.type = RAD_LIGHT_TYPE_POINT;
    d.strength = 179;
    d.units = RAD_LIGHT_CANDELA;
    CHECK(rad_scene_add_light(scene, &d) == RAD_OK);
    CHECK_NEAR(scene->lights[0].intensity[0], 1, 1e-12);
    d.strength = 4 * RAD_PI * 179;
    d.units = RAD_LIGHT_LUMENS;
    CHECK(rad_scene_add_light(scene, &d) == RAD_OK);
    CHECK_NEAR(scene->lights[1].intensity[1], 1, 1e-12);
    d.type = RAD_LIGHT_TYPE_DIRECTIONAL;
    d.direction[1] = -1;
    d.strength = 179000;
    d.units = RAD_LIGHT_CANDELA; /* lux for a directional light */
    CHECK(rad_scene_add_light(scene, &d) == RAD_OK);
    CHECK_NEAR(scene->lights[2].intensity[2], 1000, 1e-9);
    /* Bad values. */
    d.strength = -1;
    CHECK(rad_scene_add_light(scene, &d) == RAD_ERROR_INVALID_ARGUMENT);
    d.strength = NAN;
    CHECK(rad_scene_add_light(scene, &d) == RAD_ERROR_INVALID_ARGUMENT);
    d.strength = 1;
    d.direction[1] = 0;
    CHECK(rad_scene_add_light(scene, &d) == RAD_ERROR_INVALID_ARGUMENT);
    d.type = RAD_LIGHT_TYPE_SPOT;
    d.direction[1] = -1;
    d.outer_degrees = 100;
    CHECK(rad_scene_add_light(scene, &d) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(scene->light_count == 3);
    rad_scene_destroy(scene);
}

static void sun_and_sky_on_plane(rad_context *ctx) {
    const double rho = 0.5;
    rad_scene *scene = plane_scene(ctx, 1, rho);
    rad_light_desc sun = {0};
    sun.type = RAD_LIGHT_TYPE_DIRECTIONAL;
    sun.direction[0] = -1; /* travels down at 60 degrees from the normal */
    sun.direction[1] = -sqrt(3) / 3;
    sun.direction[1] = -1 / sqrt(3);
    sun.direction[0] = -1;
    sun.strength = 100;
    CHECK(rad_scene_add_light(scene, &sun) == RAD_OK);
    rad_system *s = build(ctx, scene, 0.25);
    double cos_theta = 1 / sqrt(3) / sqrt(1 + 1.0 / 3);
    for (size_t e = 0; e < s->element_count; ++e)
        CHECK_NEAR(s->light_emission[e][1], rho * 100 * cos_theta, 1e-9);
    rad_system_destroy(s);
    rad_scene_destroy(scene);

    scene = plane_scene(ctx, 1, rho);
    rad_sky_desc sky = {RAD_SKY_MODEL_UNIFORM, {2, 2, 2}, {0, 0, 0}, 0};
    CHECK(rad_scene_set_sky(scene, &sky) == RAD_OK);
    s = build(ctx, scene, 0.25);
    for (size_t e = 0; e < s->element_count; ++e)
        CHECK_NEAR(s->light_emission[e][0], rho * RAD_PI * 2, 1e-9);
    rad_system_destroy(s);
    /* Overcast: integral of L_z (1 + 2 cos) / 3 cos over the hemisphere is 7 pi L_z / 9; 64
     * stratified rays per element estimate it to well under 1%. */
    sky.model = RAD_SKY_MODEL_CIE_OVERCAST;
    CHECK(rad_scene_set_sky(scene, &sky) == RAD_OK);
    s = build(ctx, scene, 0.25);
    double mean = 0, worst = 0;
    for (size_t e = 0; e < s->element_count; ++e) {
        double ratio = s->light_emission[e][0] / (rho * 7 * RAD_PI * 2 / 9);
        mean += ratio / s->element_count;
        worst = fmax(worst, fabs(ratio - 1));
    }
    CHECK_NEAR(mean, 1, 0.002);
    CHECK(worst < 0.02);
    rad_system_destroy(s);
    /* Bad skies. */
    sky.radiance[1] = -1;
    CHECK(rad_scene_set_sky(scene, &sky) == RAD_ERROR_INVALID_ARGUMENT);
    sky.radiance[1] = INFINITY;
    CHECK(rad_scene_set_sky(scene, &sky) == RAD_ERROR_INVALID_ARGUMENT);
    rad_scene_destroy(scene);
}

/* A 0.4 x 0.4 blocker at height 0.5 under a point light at 1: the floor beneath it is dark,
 * the floor far from it fully lit; a spot's cone leaves the floor outside it dark. */
static void shadow_and_spot(rad_context *ctx) {
    rad_scene *scene = plane_scene(ctx, 1, 0.5);
    uint32_t surface;
    rad_scene_add_surface(scene, "blocker", 0, &surface);
    rad_vec3 blocker[4] = {v3(-0.2, 0.5, -0.2), v3(-0.2, 0.5, 0.2), v3(0.2, 0.5, 0.2),
                           v3(0.2, 0.5, -0.2)};
    rad_scene_add_polygon_points(scene, surface, blocker, 4);
    rad_light_desc bulb = {0};
    bulb.type = RAD_LIGHT_TYPE_POINT;
    bulb.position[1] = 1;
    bulb.strength = 1;
    CHECK(rad_scene_add_light(scene, &bulb) == RAD_OK);
    rad_system *s = build(ctx, scene, 0.1);
    int dark = 0, lit = 0, wrong = 0;
    for (size_t e = 0; e < s->element_count; ++e) {
        if (s->element_surface[e] != 0) continue;
        rad_vec3 x = s->mesh->element_centroid[e];
        double r = fmax(fabs(x.x), fabs(x.z));
        if (r < 0.3) { /* the shadow is 0.4 x 0.4 half way down: 0.8 x 0.8 on the floor */
            dark += s->light_emission[e][0] == 0;
            wrong += s->light_emission[e][0] != 0;
        } else if (r > 0.5) {
            double d = sqrt(x.x * x.x + 1 + x.z * x.z);
            lit += fabs(s->light_emission[e][0] / (0.5 / (d * d * d)) - 1) < 0.01;
            wrong += fabs(s->light_emission[e][0] / (0.5 / (d * d * d)) - 1) >= 0.01;
        }
    }
    CHECK(dark > 0 && lit > 0 && wrong == 0);
    rad_system_destroy(s);
    rad_scene_destroy(scene);

    scene = plane_scene(ctx, 1, 0.5);
    rad_light_desc spot = {0};
    spot.type = RAD_LIGHT_TYPE_SPOT;
    spot.position[1] = 1;
    spot.direction[1] = -1;
    spot.strength = 1;
    spot.inner_degrees = 20;
    spot.outer_degrees = 30;
    CHECK(rad_scene_add_light(scene, &spot) == RAD_OK);
    s = build(ctx, scene, 0.05);
    int inside = 0, outside = 0;
    wrong = 0;
    for (size_t e = 0; e < s->element_count; ++e) {
        rad_vec3 x = s->mesh->element_centroid[e];
        double angle = atan(sqrt(x.x * x.x + x.z * x.z)) * 180 / RAD_PI;
        double d = sqrt(x.x * x.x + 1 + x.z * x.z);
        if (angle < 19) {
            inside += fabs(s->light_emission[e][0] / (0.5 / (d * d * d)) - 1) < 0.01;
            wrong += fabs(s->light_emission[e][0] / (0.5 / (d * d * d)) - 1) >= 0.01;
        } else if (angle > 31) {
            outside += s->light_emission[e][0] == 0;
            wrong += s->light_emission[e][0] != 0;
        }
    }
    CHECK(inside > 0 && outside > 0 && wrong == 0);
    rad_system_destroy(s);
    rad_scene_destroy(scene);
}

/* The pre-pass is the solvers' emitted light: direct, Jacobi, Gauss-Seidel and shooting agree on
 * a lit corner (floor and wall), and the hierarchical solver with them. */
static void every_solver_starts_lit(rad_context *ctx) {
    rad_scene *scene = plane_scene(ctx, 1, 0.5);
    uint32_t surface;
    rad_scene_add_surface(scene, "wall", 0, &surface);
    rad_vec3 wall[4] = {v3(-1, 0, -1), v3(1, 0, -1), v3(1, 2, -1), v3(-1, 2, -1)};
    rad_scene_add_polygon_points(scene, surface, wall, 4);
    rad_light_desc bulb = {0};
    bulb.type = RAD_LIGHT_TYPE_POINT;
    bulb.position[0] = 0.3;
    bulb.position[1] = 1;
    bulb.strength = 2;
    rad_scene_add_light(scene, &bulb);
    rad_system *s = build(ctx, scene, 0.25);
    rad_solver_kind kinds[] = {RAD_SOLVER_DIRECT, RAD_SOLVER_JACOBI, RAD_SOLVER_GAUSS_SEIDEL,
                               RAD_SOLVER_SHOOTING};
    double floor_b[4], wall_b[4];
    for (int k = 0; k < 4; ++k) {
        rad_solve_options options = {0};
        options.solver = kinds[k];
        options.tolerance = 1e-9;
        CHECK(rad_solve(s, &options, NULL) == RAD_OK);
        rad_surface_info floor_info, wall_info;
        rad_system_surface(s, 0, &floor_info);
        rad_system_surface(s, 1, &wall_info);
        floor_b[k] = floor_info.radiosity[0];
        wall_b[k] = wall_info.radiosity[0];
    }
    for (int k = 1; k < 4; ++k) {
        CHECK_NEAR(floor_b[k] / floor_b[0], 1, 1e-5);
        CHECK_NEAR(wall_b[k] / wall_b[0], 1, 1e-5);
    }
    /* More than the pre-pass alone: the wall lights the floor and the floor the wall. */
    rad_rgb floor_direct = {0};
    double area = 0;
    for (size_t e = 0; e < s->element_count; ++e)
        if (s->element_surface[e] == 0) {
            floor_direct[0] += s->light_emission[e][0] * s->area[e];
            area += s->area[e];
        }
    CHECK(floor_b[0] > 1.01 * floor_direct[0] / area);
    /* The hierarchy takes the pre-pass as its leaves' emission: the same surfaces within 2%
     * (its own discretisation: quadtree leaves, not the elements). */
    rad_solve_options hierarchical = {0};
    hierarchical.solver = RAD_SOLVER_HIERARCHICAL;
    hierarchical.link_error = 1e-4;
    CHECK(rad_solve(s, &hierarchical, NULL) == RAD_OK);
    rad_surface_info floor_h, wall_h;
    rad_system_surface(s, 0, &floor_h);
    rad_system_surface(s, 1, &wall_h);
    printf("lit corner: floor %.5f (hierarchical) against %.5f (direct), wall %.5f against %.5f\n",
           floor_h.radiosity[0], floor_b[0], wall_h.radiosity[0], wall_b[0]);
    CHECK_NEAR(floor_h.radiosity[0] / floor_b[0], 1, 0.02);
    CHECK_NEAR(wall_h.radiosity[0] / wall_b[0], 1, 0.02);
    rad_system_destroy(s);
    rad_scene_destroy(scene);
}

static void imported_lights(rad_context *ctx) {
    rad_scene *scene = NULL;
    rad_status status = rad_scene_load(ctx, RAD_SOURCE_DIR "/scenes/lights-room.gltf", &scene);
    CHECK(status == RAD_OK);
    if (status) {
        fprintf(stderr, "%s\n", rad_context_error(ctx));
        return;
    }
    CHECK(rad_scene_light_count(scene) == 2);
    if (scene->light_count == 2) {
        const rad_light *bulb = &scene->lights[0], *spot = &scene->lights[1];
        CHECK(strcmp(bulb->name, "bulb") == 0 && bulb->kind == RAD_LIGHT_POINT);
        CHECK_NEAR(bulb->position.x, 1.2, 1e-6);
        CHECK_NEAR(bulb->position.y, 2.5, 1e-6);
        /* colour (1, 0.9, 0.8) times 179 cd: (1, 0.9, 0.8) W/sr */
        CHECK_NEAR(bulb->intensity[0], 1, 1e-6);
        CHECK_NEAR(bulb->intensity[2], 0.8, 1e-6);
        CHECK(strcmp(spot->name, "spot") == 0 && spot->kind == RAD_LIGHT_SPOT);
        CHECK_NEAR(spot->direction.y, -1, 1e-6);
        CHECK_NEAR(spot->outer_angle, 0.52, 1e-6);
        CHECK_NEAR(spot->inner_angle, 0.35, 1e-6);
        CHECK_NEAR(spot->intensity[2], 3, 1e-5);
    }
    rad_scene_destroy(scene);
}

static const char good_ies[] =
    "IESNA:LM-63-2002\n"
    "[TEST] test_lights\n"
    "TILT=NONE\n"
    "1 1000 2 3 1 1 2 0 0 0\n"
    "1 1 100\n"
    "0 45 90\n"
    "0\n"
    "100 50, 0\n";

static void ies_files(rad_context *ctx) {
    rad_ies_profile *p = NULL;
    CHECK(rad_ies_parse(ctx, good_ies, strlen(good_ies), "good.ies", &p) == RAD_OK);
    if (p) {
        CHECK(p->vertical_count == 3 && p->horizontal_count == 1);
        CHECK_NEAR(rad_ies_candela(p, 0, 0), 200, 1e-9);       /* times the multiplier 2 */
        CHECK_NEAR(rad_ies_candela(p, 22.5, 123), 150, 1e-9);  /* round: any horizontal */
        CHECK_NEAR(rad_ies_candela(p, 90, 0), 0, 1e-9);
        CHECK_NEAR(rad_ies_candela(p, 120, 0), 0, 1e-9);       /* outside the range */
        rad_ies_free(ctx, p);
    }
    /* A point light with the profile: straight down it sends 200 cd = 200 / 179 W/sr. */
    rad_scene *scene = plane_scene(ctx, 1, 0.5);
    rad_light_desc bulb = {0};
    bulb.name = "lamp";
    bulb.type = RAD_LIGHT_TYPE_POINT;
    bulb.position[1] = 1;
    bulb.strength = 1;
    rad_scene_add_light(scene, &bulb);
    char path[] = "/tmp/test_lights_XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0) {
        CHECK(write(fd, good_ies, strlen(good_ies)) == (ssize_t)strlen(good_ies));
        close(fd);
        CHECK(rad_scene_set_light_ies(scene, "nobody", path) == RAD_ERROR_INVALID_ARGUMENT);
        CHECK(rad_scene_set_light_ies(scene, "lamp", path) == RAD_OK);
        double intensity[3];
        rad_light_intensity(&scene->lights[0], v3(0, -1, 0), intensity);
        CHECK_NEAR(intensity[0], 200 / 179.0, 1e-9);
        unlink(path);
    }
    rad_scene_destroy(scene);
    /* Malformed: one line naming file:line. */
    static const struct { const char *text, *message; } bad[] = {
        {"IESNA:LM-63-2002\n1 2 3\n", "bad.ies:2: no TILT= line"},
        {"TILT=lamp.tlt\n", "bad.ies:1: TILT=lamp.tlt"},
        {"TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 100\n0 45 90\n0\n100 50\n", "bad.ies:6: the file "
                                                                             "ends"},
        {"TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 100\n0 90 45\n0\n1 1 1\n", "bad.ies:4: a vertical "
                                                                           "angle must increase"},
        {"TILT=NONE\n1 1000 1 0 1 1 2 0 0 0\n", "bad.ies:2: the number of vertical angles"},
        {"TILT=NONE\n1 1000 1 3 1 2 2 0 0 0\n", "bad.ies:2: photometric type 2"},
        {"TILT=NONE\n1 1000 1 1 1 1 2 0 0 0\n1 1 100\n0\n0\nx\n", "bad.ies:6: a candela value should"},
        {"TILT=NONE\n1 1000 1 1 1 1 2 0 0 0\n1 1 100\n0\n0\n-5\n", "bad.ies:6: a candela value must"},
        {"TILT=NONE\n1 1000 1e308 1 1 1 2 0 0 0\n1 1 100\n0\n0\n1e300\n", "not a finite number"},
        {"TILT=NONE\n1 1000 1 99999 99999 1 2 0 0 0\n", "too many"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        p = NULL;
        CHECK(rad_ies_parse(ctx, bad[i].text, strlen(bad[i].text), "bad.ies", &p) ==
              RAD_ERROR_PARSE);
        CHECK(p == NULL);
        const char *message = rad_context_error(ctx);
        if (!strstr(message, bad[i].message)) {
            fprintf(stderr, "case %zu: '%s' lacks '%s'\n", i, message, bad[i].message);
            CHECK(0);
        }
        CHECK(strchr(message, '\n') == NULL);
    }
}

/* The hierarchy lights its own nodes (rad_node_lights_reflected, docs/hierarchical.md): the
 * sun straight down on a 4 x 4 floor with a 1.3 x 1.3 square held over it, its edges off the
 * quadtree's lines. Leaves split where the shadow's edge crosses them, not on the open floor;
 * each leaf's light is rho E where it is wholly lit, zero where wholly shadowed, and the
 * floor's area-weighted light is rho E times the lit fraction (16 - 1.69) / 16. */
static void hierarchy_refines_at_shadow_edges(rad_context *ctx) {
    const double rho = 0.5;
    rad_scene *scene = plane_scene(ctx, 2, rho);
    uint32_t surface;
    rad_scene_add_surface(scene, "shade", 0, &surface);
    const double lo = -0.7, hi = 0.6; /* the shade's sides, and so its shadow's */
    rad_vec3 shade[4] = {v3(lo, 1, lo), v3(hi, 1, lo), v3(hi, 1, hi), v3(lo, 1, hi)};
    CHECK(rad_scene_add_polygon_points(scene, surface, shade, 4) == RAD_OK);
    rad_light_desc sun = {0};
    sun.type = RAD_LIGHT_TYPE_DIRECTIONAL;
    sun.direction[1] = -1;
    sun.strength = 1;
    CHECK(rad_scene_add_light(scene, &sun) == RAD_OK);
    rad_node_lights hs = {scene, NULL};
    CHECK(rad_rays_create(ctx, scene, &hs.rays) == RAD_OK);
    rad_hier_options options = {0};
    options.link_error = 1e-3;
    options.light = rad_node_lights_reflected;
    options.light_user = &hs;
    rad_hier *h = NULL;
    CHECK(rad_hier_create(ctx, scene, &options, &h) == RAD_OK);
    CHECK(rad_hier_link_roots(h) == RAD_OK);
    for (int step = 0; step < 30; ++step) {
        CHECK(rad_hier_solve(h, 1e-7, 1000) == RAD_OK);
        CHECK(rad_hier_refine(h) == RAD_OK);
        if (rad_hier_get_stats(h).refined == 0) break;
    }
    size_t count;
    const rad_hier_node *nodes = rad_hier_nodes(h, &count);
    double light_sum = 0, area = 0, worst_lit = 0, worst_dark = 0, near_area = 0, open_area = 0;
    size_t near_edge = 0, open_floor = 0;
    for (size_t i = 0; i < count; ++i) {
        const rad_hier_node *n = &nodes[i];
        if (n->corner_count == 0 || n->polygon != 0 || n->first_child != RAD_HIER_NO_NODE) continue;
        double lo_x = INFINITY, hi_x = -INFINITY, lo_z = INFINITY, hi_z = -INFINITY;
        for (int k = 0; k < n->corner_count; ++k) {
            lo_x = fmin(lo_x, n->corner[k].x), hi_x = fmax(hi_x, n->corner[k].x);
            lo_z = fmin(lo_z, n->corner[k].z), hi_z = fmax(hi_z, n->corner[k].z);
        }
        rad_vec3 centre = v3(0.5 * (lo_x + hi_x), 0, 0.5 * (lo_z + hi_z));
        double light[3];
        rad_hier_light_at(h, 0, centre, light);
        light_sum += light[0] * n->area;
        area += n->area;
        int inside = lo_x >= lo && hi_x <= hi && lo_z >= lo && hi_z <= hi;
        int outside = hi_x <= lo || lo_x >= hi || hi_z <= lo || lo_z >= hi;
        if (inside) worst_dark = fmax(worst_dark, light[0]);
        if (outside) worst_lit = fmax(worst_lit, fabs(light[0] - rho) / rho);
        /* Leaves that the shadow's edge crosses, against those more than 0.75 m from it. */
        double dx = fmax(lo - centre.x, centre.x - hi), dz = fmax(lo - centre.z, centre.z - hi);
        if (!inside && !outside) ++near_edge, near_area += n->area;
        else if (fmax(dx, dz) > 0.75) ++open_floor, open_area += n->area;
    }
    double lit = (16 - (hi - lo) * (hi - lo)) / 16;
    printf("sun on the hierarchy: %zu leaves crossed by the shadow's edge (mean area %.4f m^2), "
           "%zu on the open floor (%.4f m^2); floor light %.4f against %.4f; worst lit leaf "
           "%.2g off, darkest shadowed leaf %.2g\n",
           near_edge, near_area / near_edge, open_floor, open_area / open_floor,
           light_sum / area, rho * lit, worst_lit, worst_dark);
    CHECK(near_edge > 0 && open_floor > 0);
    CHECK(near_area / near_edge < open_area / open_floor / 16);
    CHECK_NEAR(light_sum / area, rho * lit, 0.01 * rho);
    CHECK(worst_lit < 1e-9);
    CHECK(worst_dark < 1e-9);
    rad_hier_destroy(h);
    rad_rays_destroy(hs.rays);
    rad_scene_destroy(scene);
}

int main(void) {
    rad_context *ctx = make_context();
    point_light_above_plane(ctx);
    photometric_units(ctx);
    sun_and_sky_on_plane(ctx);
    shadow_and_spot(ctx);
    every_solver_starts_lit(ctx);
    imported_lights(ctx);
    ies_files(ctx);
    hierarchy_refines_at_shadow_edges(ctx);
    rad_context_destroy(ctx);
    return test_finish();
}
