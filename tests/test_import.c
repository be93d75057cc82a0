/* test_import.c - scene files: the sample scenes in scenes/ (OBJ/MTL, glTF, GLB, PLY) imported
 * with their names, transforms, materials and cameras; bad input refused with a clear message;
 * OBJ export and re-import of the built-in scenes giving the same surfaces and solution. */
#include "scene/polygon_cut.h"
#include "scene/scene.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char log_text[16384];

static void on_log(void *user, rad_log_level level, const char *message) {
    (void)user;
    size_t used = strlen(log_text);
    snprintf(log_text + used, sizeof log_text - used, "%s%s\n",
             level == RAD_LOG_WARNING ? "warning: " : "", message);
}

static rad_context *make_context(void) {
    rad_context_options options = {0};
    options.log = on_log;
    options.threads = 2;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) {
        fprintf(stderr, "cannot create a context\n");
        exit(1);
    }
    return ctx;
}

static char temp_dir[256];

static const char *temp_path(const char *name) {
    static char path[4][512];
    static int next;
    char *p = path[next++ % 4];
    snprintf(p, 512, "%s/%s", temp_dir, name);
    return p;
}

static void write_text(const char *path, const char *text) {
    FILE *file = fopen(path, "w");
    if (!file) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    fputs(text, file);
    fclose(file);
}

static long find_surface(const rad_scene *scene, const char *name) {
    for (size_t i = 0; i < scene->surface_count; ++i)
        if (strcmp(scene->surfaces[i].name, name) == 0) return (long)i;
    return -1;
}

static double surface_area(const rad_scene *scene, long surface) {
    double area = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        if ((long)scene->polygons[i].surface == surface)
            area += rad_polygon_area(scene, &scene->polygons[i]);
    return area;
}

static size_t surface_polygons(const rad_scene *scene, long surface, size_t *corners) {
    size_t count = 0;
    *corners = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        if ((long)scene->polygons[i].surface == surface) {
            count++;
            *corners += scene->polygons[i].count;
        }
    return count;
}

/* Area-weighted mean normal and centroid of a surface. */
static rad_vec3 surface_normal(const rad_scene *scene, long surface) {
    rad_vec3 sum = v3(0, 0, 0);
    for (size_t i = 0; i < scene->polygon_count; ++i)
        if ((long)scene->polygons[i].surface == surface) {
            const rad_polygon *p = &scene->polygons[i];
            sum = v3_add(sum, v3_scale(rad_polygon_normal(scene, p), rad_polygon_area(scene, p)));
        }
    return v3_normalize(sum);
}

static rad_vec3 surface_centroid(const rad_scene *scene, long surface) {
    rad_vec3 sum = v3(0, 0, 0);
    double weight = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        if ((long)scene->polygons[i].surface == surface) {
            const rad_polygon *p = &scene->polygons[i];
            rad_vec3 c = v3(0, 0, 0);
            for (uint32_t k = 0; k < p->count; ++k) c = v3_add(c, rad_polygon_vertex(scene, p, k));
            double a = rad_polygon_area(scene, p);
            sum = v3_add(sum, v3_scale(c, a / p->count));
            weight += a;
        }
    return v3_scale(sum, 1.0 / weight);
}

static const rad_material *surface_material(const rad_scene *scene, long surface) {
    return &scene->materials[scene->surfaces[surface].material];
}

#define CHECK_VEC(actual, ex, ey, ez, tolerance)                                                  \
    do {                                                                                          \
        rad_vec3 check_v = (actual);                                                              \
        CHECK_NEAR(check_v.x, ex, tolerance);                                                     \
        CHECK_NEAR(check_v.y, ey, tolerance);                                                     \
        CHECK_NEAR(check_v.z, ez, tolerance);                                                     \
    } while (0)

#define CHECK_RGB(array, r, g, b, tolerance)                                                      \
    do {                                                                                          \
        CHECK_NEAR((array)[0], r, tolerance);                                                     \
        CHECK_NEAR((array)[1], g, tolerance);                                                     \
        CHECK_NEAR((array)[2], b, tolerance);                                                     \
    } while (0)

/* ------------------------------------------------------------------------------------------- */

static void test_obj_room(void) {
    rad_context *ctx = make_context();
    log_text[0] = '\0';
    rad_scene *scene = NULL;
    rad_status status = rad_scene_load(ctx, RAD_SOURCE_DIR "/scenes/room.obj", &scene);
    CHECK(status == RAD_OK);
    if (status) {
        fprintf(stderr, "room.obj: %s\n", rad_context_error(ctx));
        rad_context_destroy(ctx);
        return;
    }
    CHECK(scene->geometric);
    CHECK(scene->surface_count == 8);
    static const char *const names[] = {"floor", "lamp", "wall/red", "wall/white",
                                        "mirror", "glass", "block", "step"};
    for (int i = 0; i < 8; ++i) CHECK(find_surface(scene, names[i]) == i);

    long floor = find_surface(scene, "floor");
    CHECK_NEAR(surface_area(scene, floor), 3.0, 1e-6); /* the non-convex L, cut in two */
    CHECK_VEC(surface_normal(scene, floor), 0, 1, 0, 1e-9);
    size_t corners, polygons = surface_polygons(scene, floor, &corners);
    CHECK(polygons == 2 && corners == 8); /* two convex quads */
    CHECK(strstr(log_text, "cut 1 non-convex faces into convex pieces") != NULL);

    long lamp = find_surface(scene, "lamp");
    CHECK_NEAR(surface_area(scene, lamp), 0.25, 1e-6);
    CHECK_VEC(surface_normal(scene, lamp), 0, -1, 0, 1e-9);
    CHECK_RGB(surface_material(scene, lamp)->emission, 4, 4, 4, 1e-6);
    CHECK_RGB(surface_material(scene, lamp)->reflectance, 0.5, 0.5, 0.5, 1e-6);
    CHECK(surface_material(scene, lamp)->kind == RAD_MATERIAL_DIFFUSE);

    long red = find_surface(scene, "wall/red"), white = find_surface(scene, "wall/white");
    CHECK_NEAR(surface_area(scene, red), 2.0, 1e-6);
    CHECK_NEAR(surface_area(scene, white), 2.0, 1e-6);
    CHECK_VEC(surface_normal(scene, red), 1, 0, 0, 1e-9);
    CHECK_RGB(surface_material(scene, red)->reflectance, 0.7, 0.1, 0.1, 1e-6);
    CHECK_RGB(surface_material(scene, white)->reflectance, 0.8, 0.8, 0.8, 1e-6);
    CHECK_RGB(surface_material(scene, white)->emission, 0, 0, 0, 0);

    const rad_material *chrome = surface_material(scene, find_surface(scene, "mirror"));
    CHECK(chrome->kind == RAD_MATERIAL_MIRROR);
    CHECK_RGB(chrome->specular, 0.9, 0.9, 0.9, 1e-6);
    CHECK_NEAR(chrome->roughness, 0.0, 1e-9); /* Ns 1000 */
    CHECK_VEC(surface_normal(scene, find_surface(scene, "mirror")), 0, 0, -1, 1e-9);

    const rad_material *glass = surface_material(scene, find_surface(scene, "glass"));
    CHECK(glass->kind == RAD_MATERIAL_GLASS);
    CHECK_NEAR(glass->ior, 1.5, 1e-6);
    CHECK_RGB(glass->specular, 0.9, 1, 0.9, 1e-6);
    CHECK_VEC(surface_normal(scene, find_surface(scene, "glass")), -1, 0, 0, 1e-9);

    /* The step keeps its quad; a face with a repeated corner and a collinear one are dropped. */
    long step = find_surface(scene, "step");
    CHECK_NEAR(surface_area(scene, step), 0.16, 1e-6);
    CHECK(surface_polygons(scene, step, &corners) == 1);
    CHECK(strstr(log_text, "warning: ") && strstr(log_text, "dropped 2 degenerate faces"));
    CHECK(strstr(log_text, "ignored 1 points and lines") != NULL);
    CHECK(!scene->has_camera);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static void test_gltf_lamp_room(const char *path) {
    rad_context *ctx = make_context();
    log_text[0] = '\0';
    rad_scene *scene = NULL;
    rad_status status = rad_scene_load(ctx, path, &scene);
    CHECK(status == RAD_OK);
    if (status) {
        fprintf(stderr, "%s: %s\n", path, rad_context_error(ctx));
        rad_context_destroy(ctx);
        return;
    }
    static const char *const names[] = {"floor", "lamp", "shelf", "shelf.2", "pane", "mirror"};
    CHECK(scene->surface_count == 6);
    for (int i = 0; i < 6; ++i) CHECK(find_surface(scene, names[i]) == i);
    /* Every node's quad comes as two triangles and is joined back into one quad. */
    for (long s = 0; s < (long)scene->surface_count; ++s) {
        size_t corners;
        CHECK(surface_polygons(scene, s, &corners) == 1 && corners == 4);
    }
    long floor = find_surface(scene, "floor");
    CHECK_NEAR(surface_area(scene, floor), 4.0, 1e-6); /* scale 2 x 2 */
    CHECK_VEC(surface_normal(scene, floor), 0, 1, 0, 1e-9);
    CHECK_RGB(surface_material(scene, floor)->reflectance, 0.8, 0.7, 0.6, 1e-6);

    /* Upside down at y = 2; emission = emissiveFactor x KHR_materials_emissive_strength. */
    long lamp = find_surface(scene, "lamp");
    CHECK_NEAR(surface_area(scene, lamp), 1.0, 1e-6);
    CHECK_VEC(surface_normal(scene, lamp), 0, -1, 0, 1e-6);
    CHECK_VEC(surface_centroid(scene, lamp), 0, 2, 0, 1e-6);
    CHECK_RGB(surface_material(scene, lamp)->emission, 5, 4, 3, 1e-5);

    /* Nested nodes: translation of the parent, scale of the child. */
    long shelf = find_surface(scene, "shelf");
    CHECK_NEAR(surface_area(scene, shelf), 0.16, 1e-6);
    CHECK_VEC(surface_centroid(scene, shelf), 0, 0.5, 0, 1e-6);
    CHECK_VEC(surface_normal(scene, shelf), 0, 1, 0, 1e-9);

    /* A mirroring transform (scale y -1): the face is turned, its front faces -y. */
    long turned = find_surface(scene, "shelf.2");
    CHECK_VEC(surface_normal(scene, turned), 0, -1, 0, 1e-9);
    CHECK_VEC(surface_centroid(scene, turned), 0, 1, 0, 1e-6);
    CHECK(strstr(log_text, "turned 2 faces") != NULL);

    const rad_material *pane = surface_material(scene, find_surface(scene, "pane"));
    CHECK(pane->kind == RAD_MATERIAL_GLASS);
    CHECK_NEAR(pane->ior, 1.33, 1e-6);
    CHECK_RGB(pane->reflectance, 0, 0, 0, 1e-9); /* transmission 1 */
    CHECK_VEC(surface_normal(scene, find_surface(scene, "pane")), 0, 0, 1, 1e-6);

    const rad_material *metal = surface_material(scene, find_surface(scene, "mirror"));
    CHECK(metal->kind == RAD_MATERIAL_MIRROR);
    CHECK_NEAR(metal->roughness, 0.2, 1e-6);
    CHECK_RGB(metal->specular, 0.9, 0.9, 0.9, 1e-6);
    CHECK_VEC(surface_normal(scene, find_surface(scene, "mirror")), -1, 0, 0, 1e-6);

    /* The camera node: at (0, 1, 4) looking along -z, yfov 0.8 rad. */
    CHECK(scene->has_camera);
    CHECK_VEC(scene->camera.eye, 0, 1, 4, 1e-6);
    CHECK_VEC(v3_normalize(v3_sub(scene->camera.look, scene->camera.eye)), 0, 0, -1, 1e-6);
    CHECK_VEC(scene->camera.up, 0, 1, 0, 1e-6);
    CHECK_NEAR(scene->camera.fov_degrees, 0.8 * 180 / RAD_PI, 1e-4);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

static void test_ply(void) {
    rad_context *ctx = make_context();
    rad_scene *scene = NULL;
    rad_status status = rad_scene_load(ctx, RAD_SOURCE_DIR "/scenes/square.ply", &scene);
    CHECK(status == RAD_OK);
    if (!status) {
        /* No names in PLY: the surface is named after the file. No materials: grey 0.5. */
        CHECK(scene->surface_count == 1 && find_surface(scene, "square") == 0);
        CHECK_NEAR(surface_area(scene, 0), 1.5, 1e-6);
        CHECK(scene->polygon_count == 2);
        CHECK(scene->polygon_count == 2 && scene->polygons[0].count == 4 &&
              scene->polygons[1].count == 3);
        CHECK_RGB(surface_material(scene, 0)->reflectance, 0.5, 0.5, 0.5, 0);
        CHECK_RGB(surface_material(scene, 0)->emission, 0, 0, 0, 0);
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

/* Faces the mesher cannot take as they are: non-convex ones and ones of more than 64 corners are
 * cut into convex pieces that cover the same area and face the same way. */
static int polygon_convex(const rad_scene *scene, const rad_polygon *p) {
    rad_vec3 n = rad_polygon_normal(scene, p);
    for (uint32_t k = 0; k < p->count; ++k) {
        rad_vec3 a = rad_polygon_vertex(scene, p, k), b = rad_polygon_vertex(scene, p, (k + 1) % p->count),
                 c = rad_polygon_vertex(scene, p, (k + 2) % p->count);
        if (v3_dot(v3_cross(v3_sub(b, a), v3_sub(c, b)), n) < -1e-12) return 0;
    }
    return 1;
}

static void test_faces(void) {
    rad_context *ctx = make_context();
    /* A U (3 x 2 less a 1 x 1 notch), a comb (4 x 1 less two 1 x 0.5 notches) and a 100-gon. */
    char text[8192];
    size_t used = 0;
    used += (size_t)snprintf(text + used, sizeof text - used,
                             "o u\nv 0 0 0\nv 3 0 0\nv 3 2 0\nv 2 2 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\n"
                             "v 0 2 0\nf 1 2 3 4 5 6 7 8\n"
                             "o comb\nv 0 0 1\nv 4 0 1\nv 4 1 1\nv 3.5 1 1\nv 3.5 0.5 1\nv 2.5 0.5 1\n"
                             "v 2.5 1 1\nv 1.5 1 1\nv 1.5 0.5 1\nv 0.5 0.5 1\nv 0.5 1 1\nv 0 1 1\n"
                             "f 9 10 11 12 13 14 15 16 17 18 19 20\no circle\n");
    for (int k = 0; k < 100; ++k)
        used += (size_t)snprintf(text + used, sizeof text - used, "v %.17g %.17g 2\n",
                                 cos(2 * RAD_PI * k / 100), sin(2 * RAD_PI * k / 100));
    used += (size_t)snprintf(text + used, sizeof text - used, "f");
    for (int k = 0; k < 100; ++k) used += (size_t)snprintf(text + used, sizeof text - used, " %d", 21 + k);
    snprintf(text + used, sizeof text - used, "\n");
    write_text(temp_path("faces.obj"), text);
    rad_scene *scene = NULL;
    CHECK(rad_scene_load(ctx, temp_path("faces.obj"), &scene) == RAD_OK);
    if (scene) {
        CHECK(scene->surface_count == 3);
        CHECK_NEAR(surface_area(scene, find_surface(scene, "u")), 6 - 1, 1e-6);
        CHECK_NEAR(surface_area(scene, find_surface(scene, "comb")), 4 - 2 * 0.5, 1e-6);
        CHECK_NEAR(surface_area(scene, find_surface(scene, "circle")),
                   0.5 * 100 * sin(2 * RAD_PI / 100), 1e-5);
        for (size_t i = 0; i < scene->polygon_count; ++i) {
            const rad_polygon *p = &scene->polygons[i];
            CHECK(p->count <= 64);
            CHECK(polygon_convex(scene, p));
            CHECK(rad_polygon_normal(scene, p).z > 1 - 1e-9);
        }
        size_t corners;
        printf("non-convex faces: the U in %zu pieces, the comb in %zu, the 100-gon in %zu\n",
               surface_polygons(scene, find_surface(scene, "u"), &corners),
               surface_polygons(scene, find_surface(scene, "comb"), &corners),
               surface_polygons(scene, find_surface(scene, "circle"), &corners));
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

/* A circle of 10,000 corners written with six decimals: the rounding leaves dents far below its
 * size, so it is convex and is cut into convex pieces of at most 64 corners that share corners
 * with a few others at most. Cut as non-convex (ear clipping), it was a fan of 9,998 slivers
 * meeting in one corner, and the contact search and the smooth shading's neighbours then took
 * every pair of them (minutes at 100,000 corners). */
static void test_large_circle(void) {
    rad_context *ctx = make_context();
    enum { CORNERS = 10000 };
    char *text = malloc(64 * (size_t)CORNERS + 64);
    CHECK(text != NULL);
    if (!text) return;
    size_t used = (size_t)sprintf(text, "o disk\n");
    for (int k = 0; k < CORNERS; ++k)
        used += (size_t)sprintf(text + used, "v %.6f %.6f 0\n", cos(2 * RAD_PI * k / CORNERS),
                                sin(2 * RAD_PI * k / CORNERS));
    used += (size_t)sprintf(text + used, "f");
    for (int k = 0; k < CORNERS; ++k) used += (size_t)sprintf(text + used, " %d", k + 1);
    sprintf(text + used, "\n");
    write_text(temp_path("circle.obj"), text);
    free(text);
    rad_scene *scene = NULL;
    CHECK(rad_scene_load(ctx, temp_path("circle.obj"), &scene) == RAD_OK);
    if (scene) {
        CHECK_NEAR(surface_area(scene, find_surface(scene, "disk")), RAD_PI, 1e-5);
        uint32_t *pieces = calloc(scene->vertex_count + 1, sizeof *pieces);
        uint32_t most = 0;
        for (size_t i = 0; i < scene->polygon_count && pieces; ++i) {
            const rad_polygon *p = &scene->polygons[i];
            CHECK(p->count <= 64);
            CHECK(rad_polygon_normal(scene, p).z > 1 - 1e-9);
            for (uint32_t k = 0; k < p->count; ++k) {
                uint32_t v = scene->polygon_vertices[p->first + k];
                if (++pieces[v] > most) most = pieces[v];
            }
        }
        printf("a 10,000-gon: %zu pieces, a corner in %u of them at most\n", scene->polygon_count,
               most);
        CHECK(pieces && most <= 8);
        free(pieces);
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

/* A convex 500-gon read from an OBJ file (through assimp, in 32-bit floats) and from an MGF
 * file (by the project's own reader, in doubles), its corners exact in both: the same pieces,
 * corner for corner (scene/polygon_cut.h's split, shared by both readers), where the MGF reader
 * fanned 64-gons around corner 0 and the importer spread its core by index. */
static void test_split_through_both_readers(void) {
    rad_context *ctx = make_context();
    enum { CORNERS = 500 }; /* an MGF entity has at most 512 words */
    char *obj = malloc(128 * (size_t)CORNERS), *mgf = malloc(128 * (size_t)CORNERS);
    CHECK(obj && mgf);
    if (!obj || !mgf) return;
    size_t o = (size_t)sprintf(obj, "o disk\n"), m = (size_t)sprintf(mgf, "o disk\n");
    for (int k = 0; k < CORNERS; ++k) {
        /* On a grid of 2^-24, exact in a float. */
        double x = ldexp(round(ldexp(cos(2 * RAD_PI * k / CORNERS), 24)), -24);
        double y = ldexp(round(ldexp(sin(2 * RAD_PI * k / CORNERS), 24)), -24);
        o += (size_t)sprintf(obj + o, "v %.17g %.17g 0\n", x, y);
        m += (size_t)sprintf(mgf + m, "v c%d =\n\tp %.17g %.17g 0\n", k, x, y);
    }
    o += (size_t)sprintf(obj + o, "f");
    m += (size_t)sprintf(mgf + m, "f");
    for (int k = 0; k < CORNERS; ++k) {
        o += (size_t)sprintf(obj + o, " %d", k + 1);
        m += (size_t)sprintf(mgf + m, " c%d", k);
    }
    sprintf(obj + o, "\n");
    sprintf(mgf + m, "\no\n");
    write_text(temp_path("disk500.obj"), obj);
    write_text(temp_path("disk500.mgf"), mgf);
    free(obj);
    free(mgf);
    rad_scene *a = NULL, *b = NULL;
    CHECK(rad_scene_load(ctx, temp_path("disk500.obj"), &a) == RAD_OK);
    CHECK(rad_scene_load(ctx, temp_path("disk500.mgf"), &b) == RAD_OK);
    if (a && b) {
        printf("a 500-gon: %zu pieces from the OBJ file, %zu from the MGF file\n",
               a->polygon_count, b->polygon_count);
        CHECK(a->polygon_count == b->polygon_count && a->polygon_count > 1);
        size_t same = 0;
        for (size_t i = 0; i < a->polygon_count && i < b->polygon_count; ++i) {
            const rad_polygon *p = &a->polygons[i], *q = &b->polygons[i];
            int equal = p->count == q->count && p->count <= RAD_POLYGON_CORNERS_MAX;
            for (uint32_t k = 0; k < p->count && equal; ++k) {
                rad_vec3 u = rad_polygon_vertex(a, p, k), v = rad_polygon_vertex(b, q, k);
                equal = u.x == v.x && u.y == v.y && u.z == v.z;
            }
            same += equal;
        }
        CHECK(same == a->polygon_count);
        CHECK_NEAR(surface_area(a, find_surface(a, "disk")), surface_area(b, 0), 1e-12);
        CHECK_NEAR(surface_area(a, find_surface(a, "disk")), 0.5 * CORNERS * sin(2 * RAD_PI / CORNERS), 1e-6);
    }
    rad_scene_destroy(a);
    rad_scene_destroy(b);
    rad_context_destroy(ctx);
}

/* ------------------------------------------------------------------------------------------- */
/* Bad input: each one a clear message and the right status, never a crash.                     */

static const char quad_obj[] = "o square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

static void expect_failure(rad_context *ctx, const char *path, rad_status expected,
                           const char *fragment) {
    rad_scene *scene = NULL;
    rad_status status = rad_scene_load(ctx, path, &scene);
    CHECK(status == expected);
    CHECK(scene == NULL);
    const char *message = rad_context_error(ctx);
    CHECK(strstr(message, fragment) != NULL);
    CHECK(strchr(message, '\n') == NULL);
    if (status != expected || !strstr(message, fragment))
        fprintf(stderr, "  %s: status %s, message '%s' (wanted '%s')\n", path,
                rad_status_name(status), message, fragment);
    rad_scene_destroy(scene);
}

static void test_bad_input(void) {
    rad_context *ctx = make_context();
    expect_failure(ctx, temp_path("missing.obj"), RAD_ERROR_IO, "No such file");

    write_text(temp_path("noise.xyz"), "this is not a scene\n");
    expect_failure(ctx, temp_path("noise.xyz"), RAD_ERROR_UNSUPPORTED, "not a scene format");

    write_text(temp_path("tiny.obj"), "hello\n");
    expect_failure(ctx, temp_path("tiny.obj"), RAD_ERROR_PARSE, "assimp cannot read it");

    write_text(temp_path("empty.obj"), "# nothing but corners, and no faces at all\n"
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n");
    expect_failure(ctx, temp_path("empty.obj"), RAD_ERROR_PARSE, "no faces");

    write_text(temp_path("lines.obj"), "# lines only, no faces\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                       "l 1 2\nl 2 3\n");
    expect_failure(ctx, temp_path("lines.obj"), RAD_ERROR_PARSE, "no faces");

    write_text(temp_path("nan.obj"), "o broken\nv 0 0 0\nv nan 0 0\nv 1 1 0\nf 1 2 3\n");
    expect_failure(ctx, temp_path("nan.obj"), RAD_ERROR_PARSE, "not a finite number");

    write_text(temp_path("inf.obj"), "o broken\nv 0 0 0\nv 1 0 0\nv 1 inf 0\nf 1 2 3\n");
    expect_failure(ctx, temp_path("inf.obj"), RAD_ERROR_PARSE, "not a finite number");

    write_text(temp_path("flat.obj"), "o flat\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\n"
                                      "f 1 2 3\nf 1 2 4\nf 1 1 2\n");
    expect_failure(ctx, temp_path("flat.obj"), RAD_ERROR_PARSE, "every face is degenerate");

    write_text(temp_path("index.obj"), "o bad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n");
    expect_failure(ctx, temp_path("index.obj"), RAD_ERROR_PARSE, "index.obj");

    write_text(temp_path("broken.gltf"), "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
    expect_failure(ctx, temp_path("broken.gltf"), RAD_ERROR_PARSE, "broken.gltf");

    write_text(temp_path("empty.gltf"), "{\"asset\": {\"version\": \"2.0\"}}");
    expect_failure(ctx, temp_path("empty.gltf"), RAD_ERROR_PARSE, "empty.gltf");

    /* A truncated binary glTF. */
    FILE *in = fopen(RAD_SOURCE_DIR "/scenes/lamp-room.glb", "rb");
    char bytes[4096];
    size_t got = in ? fread(bytes, 1, sizeof bytes, in) : 0;
    if (in) fclose(in);
    FILE *out = fopen(temp_path("cut.glb"), "wb");
    if (out) {
        fwrite(bytes, 1, got < 400 ? got : 400, out);
        fclose(out);
    }
    expect_failure(ctx, temp_path("cut.glb"), RAD_ERROR_PARSE, "cut.glb");

    /* Headers assimp would hang on or believe: checked first (src/scene/import_check.c). */
    write_text(temp_path("open.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
    expect_failure(ctx, temp_path("open.ply"), RAD_ERROR_PARSE, "no end_header");
    write_text(temp_path("greedy.ply"), "ply\nformat binary_little_endian 1.0\nelement vertex "
                                        "400000000\nproperty float x\nproperty float y\nproperty "
                                        "float z\nend_header\n0123456789ab");
    expect_failure(ctx, temp_path("greedy.ply"), RAD_ERROR_PARSE, "promises at least 4800000000");
    if (got >= 20) {
        bytes[15] = (char)0xe1; /* the JSON chunk now claims 3.7 GB */
        out = fopen(temp_path("greedy.glb"), "wb");
        if (out) {
            fwrite(bytes, 1, got, out);
            fclose(out);
        }
        expect_failure(ctx, temp_path("greedy.glb"), RAD_ERROR_PARSE, "chunk 0 claims 3774");
    }
    /* assimp matches end_header case by case and loops forever on "End_header". */
    write_text(temp_path("end-case.ply"), "ply\nformat ascii 1.0\nelement vertex 0\n"
                                          "property float x\nEnd_header\n");
    expect_failure(ctx, temp_path("end-case.ply"), RAD_ERROR_PARSE, "end-case.ply:5: 'End_header' must be written end_header");

    /* OBJ polylines of one vertex: assimp 5.2.5 writes past its vertex array (a heap overflow
     * that aborts in glibc) once two of them precede a longer polyline. Every way of writing
     * one is refused, with its line; polylines of two vertices or more still import. */
    static const struct {
        const char *name, *text, *fragment;
    } polylines[] = {
        {"one.obj", "v 0 0 0\nl 1\nl 1\nl 1 1 1\n", "one.obj:2: a polyline ('l') needs"},
        {"lod.obj", "v 0 0 0\nv 1 0 0\nlod 1\n", "lod.obj:3: assimp reads 'lod' as a polyline"},
        {"bare.obj", "v 0 0 0\r\nv 1 0 0\r\nl\r\n", "bare.obj:3: a polyline"},
        {"cr.obj", "v 0 0 0\rv 1 0 0\rl 2\r", "cr.obj:3: a polyline"},
        {"hidden.obj", "v 0 0 0\nv 1 0 0\n# x\fl 1\n", "hidden.obj:3: a polyline"},
        {"zero-padded.obj", "v 0 0 0\nv 1 0 0\nl 01 2\n", "zero-padded.obj:3: a polyline"},
        {"normal-as-texture.obj", "v 0 0 0\nv 1 0 0\nvn 0 0 1\nl 1/1/1 2/1/1\n",
         "normal-as-texture.obj:4: a polyline"},
        {"polyline.txt", "v 0 0 0\nv 1 0 0\nl 1\n", "polyline.txt:3: a polyline"},
        {"continued.obj", "v 0 0 0\nv 1 0 0\nf 1 2 \\\r1\n", "continued.obj:3: a line "
                                                             "continuation"},
        {"last-byte.obj", "v 0 0 0\nv 1 0 0\nf 1 2 1\\", "last-byte.obj:3: a line continuation"},
    };
    for (size_t i = 0; i < sizeof polylines / sizeof polylines[0]; ++i) {
        write_text(temp_path(polylines[i].name), polylines[i].text);
        expect_failure(ctx, temp_path(polylines[i].name), RAD_ERROR_PARSE, polylines[i].fragment);
    }
    static const char *const fine[] = {
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 1 2 3\nl -1 -2\nl\t1//1\t2//1\nf 1 2 3\n",
        "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nvt 0 0\r\nl 1/1/1 2/1/1\r\nf 1 2 \\\r\n3\r\n",
    };
    for (size_t i = 0; i < sizeof fine / sizeof fine[0]; ++i) {
        write_text(temp_path("fine.obj"), fine[i]);
        rad_scene *scene = NULL;
        CHECK(rad_scene_load(ctx, temp_path("fine.obj"), &scene) == RAD_OK);
        CHECK(scene && scene->polygon_count == 1);
        if (!scene) fprintf(stderr, "  fine.obj %zu: %s\n", i, rad_context_error(ctx));
        rad_scene_destroy(scene);
    }

    /* Some faces degenerate: dropped and counted, the rest imported. */
    log_text[0] = '\0';
    write_text(temp_path("some.obj"), "o some\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
                                      "f 1 2 3 4\nf 1 2 5\nf 2 2 3\n");
    rad_scene *scene = NULL;
    CHECK(rad_scene_load(ctx, temp_path("some.obj"), &scene) == RAD_OK);
    CHECK(scene && scene->polygon_count == 1);
    CHECK(strstr(log_text, "warning: ") && strstr(log_text, "dropped 2 degenerate faces"));
    rad_scene_destroy(scene);

    /* Reflectance above 1 is kept as given, so building the system refuses it. */
    write_text(temp_path("bright.mtl"), "newmtl bright\nKd 1.5 0.5 0.5\nKe 1 1 1\n");
    write_text(temp_path("bright.obj"), "mtllib bright.mtl\nusemtl bright\nv 0 0 0\nv 1 0 0\n"
                                        "v 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    CHECK(rad_scene_load(ctx, temp_path("bright.obj"), &scene) == RAD_OK);
    if (scene) {
        CHECK_NEAR(scene->materials[scene->surfaces[0].material].reflectance[0], 1.5, 1e-6);
        rad_system *system = NULL;
        rad_mesh_options mesh = {0, 0, 16, 0, 0};
        CHECK(rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_ERROR_INVALID_ARGUMENT);
        CHECK(strstr(rad_context_error(ctx), "reflectance 1.5") != NULL);
        rad_system_destroy(system);
    }
    rad_scene_destroy(scene);

    /* No emitters: a warning, and a black result. */
    log_text[0] = '\0';
    write_text(temp_path("dark.obj"), quad_obj);
    CHECK(rad_scene_load(ctx, temp_path("dark.obj"), &scene) == RAD_OK);
    if (scene) {
        rad_system *system = NULL;
        rad_mesh_options mesh = {0, 0, 16, 0, 0};
        CHECK(rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_OK);
        CHECK(strstr(log_text, "nothing emits light") != NULL);
        if (system) {
            rad_solve_report report;
            rad_solve_options solve = {0};
            solve.solver = RAD_SOLVER_SHOOTING;
            CHECK(rad_solve(system, &solve, &report) == RAD_OK);
            rad_surface_info info;
            CHECK(rad_system_surface(system, 0, &info) == RAD_OK);
            CHECK(info.radiosity[0] == 0 && info.radiosity[1] == 0 && info.radiosity[2] == 0);
        }
        rad_system_destroy(system);
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
}

/* ------------------------------------------------------------------------------------------- */
/* Export and re-import.                                                                        */

static rad_system *solve_scene(rad_context *ctx, const rad_scene *scene) {
    rad_system *system = NULL;
    rad_mesh_options mesh = {0, 0, 400, 0, 0};
    rad_ff_options ff = {RAD_FF_ANALYTIC, 0, 0, NULL};
    if (rad_system_create(ctx, scene, &mesh, &ff, &system)) {
        fprintf(stderr, "system: %s\n", rad_context_error(ctx));
        return NULL;
    }
    rad_solve_options solve = {0};
    solve.solver = RAD_SOLVER_SHOOTING;
    solve.tolerance = 1e-10;
    rad_solve_report report;
    if (rad_solve(system, &solve, &report)) {
        fprintf(stderr, "solve: %s\n", rad_context_error(ctx));
        rad_system_destroy(system);
        return NULL;
    }
    return system;
}

static double relative_difference(double a, double b) {
    double scale = fmax(fabs(a), fabs(b));
    return scale > 0 ? fabs(a - b) / scale : 0;
}

static void test_round_trip(const char *name, int solve) {
    rad_context *ctx = make_context();
    rad_scene *original = NULL, *copy = NULL;
    char file[64];
    snprintf(file, sizeof file, "%s.obj", name);
    const char *path = temp_path(file);
    CHECK(rad_scene_builtin(ctx, name, &original) == RAD_OK);
    CHECK(original && rad_scene_export_obj(ctx, original, path) == RAD_OK);
    CHECK(rad_scene_load(ctx, path, &copy) == RAD_OK);
    if (!original || !copy) {
        fprintf(stderr, "%s: %s\n", name, rad_context_error(ctx));
        rad_scene_destroy(original);
        rad_context_destroy(ctx);
        return;
    }
    /* Same surfaces in the same order, same areas and materials. */
    CHECK(copy->surface_count == original->surface_count);
    CHECK(copy->polygon_count == original->polygon_count);
    double worst_area = 0, worst_material = 0;
    for (size_t s = 0; s < original->surface_count && s < copy->surface_count; ++s) {
        CHECK(strcmp(copy->surfaces[s].name, original->surfaces[s].name) == 0);
        worst_area = fmax(worst_area, relative_difference(surface_area(copy, (long)s),
                                                          surface_area(original, (long)s)));
        const rad_material *a = surface_material(original, (long)s);
        const rad_material *b = surface_material(copy, (long)s);
        for (int c = 0; c < 3; ++c) {
            worst_material = fmax(worst_material, relative_difference(a->reflectance[c],
                                                                      b->reflectance[c]));
            worst_material = fmax(worst_material, relative_difference(a->emission[c],
                                                                      b->emission[c]));
        }
        CHECK(a->kind == b->kind);
    }
    CHECK(worst_area < 1e-6);
    CHECK(worst_material < 1e-6);
    if (solve) {
        /* assimp reads coordinates in single precision (ai_real is float), so the file carries
         * each coordinate rounded to float: the same solution as the scene rounded so, and,
         * as long as the form factors are stable under such 1e-8 changes, as the scene. */
        rad_scene *rounded = NULL;
        CHECK(rad_scene_builtin(ctx, name, &rounded) == RAD_OK);
        for (size_t i = 0; rounded && i < rounded->vertex_count; ++i) {
            rad_vec3 *p = &rounded->vertices[i];
            *p = v3((float)p->x, (float)p->y, (float)p->z);
        }
        rad_system *x = rounded ? solve_scene(ctx, rounded) : NULL, *y = solve_scene(ctx, copy);
        rad_system *z = solve_scene(ctx, original);
        CHECK(x && y && z);
        double worst = 0, worst_unrounded = 0;
        for (size_t s = 0; x && y && z && s < rad_system_surface_count(x); ++s) {
            rad_surface_info a, b, c;
            rad_system_surface(x, s, &a);
            rad_system_surface(y, s, &b);
            rad_system_surface(z, s, &c);
            for (int k = 0; k < 3; ++k) {
                worst = fmax(worst, relative_difference(a.radiosity[k], b.radiosity[k]));
                worst_unrounded = fmax(worst_unrounded,
                                       relative_difference(c.radiosity[k], b.radiosity[k]));
            }
        }
        printf("round trip %s: largest relative difference: area %.2g, material %.2g, surface "
               "radiosity %.2g (%.2g against the scene before rounding to float)\n", name,
               worst_area, worst_material, worst, worst_unrounded);
        CHECK(worst < 1e-6);
        CHECK(worst_unrounded < 1e-6);
        rad_system_destroy(x);
        rad_system_destroy(y);
        rad_system_destroy(z);
        rad_scene_destroy(rounded);
    }
    rad_scene_destroy(original);
    rad_scene_destroy(copy);
    rad_context_destroy(ctx);
}

/* glTF in, OBJ out, OBJ in: mirror and glass hints survive the MTL file. */
static void test_gltf_to_obj(void) {
    rad_context *ctx = make_context();
    rad_scene *original = NULL, *copy = NULL;
    CHECK(rad_scene_load(ctx, RAD_SOURCE_DIR "/scenes/lamp-room.gltf", &original) == RAD_OK);
    CHECK(original && rad_scene_export_obj(ctx, original, temp_path("lamp-room.obj")) == RAD_OK);
    CHECK(rad_scene_load(ctx, temp_path("lamp-room.obj"), &copy) == RAD_OK);
    if (original && copy) {
        CHECK(copy->surface_count == original->surface_count);
        for (size_t s = 0; s < original->surface_count && s < copy->surface_count; ++s) {
            const rad_material *a = surface_material(original, (long)s);
            const rad_material *b = surface_material(copy, (long)s);
            CHECK(strcmp(copy->surfaces[s].name, original->surfaces[s].name) == 0);
            CHECK(a->kind == b->kind);
            if (a->kind == RAD_MATERIAL_MIRROR) CHECK_NEAR(b->roughness, a->roughness, 1e-6);
            if (a->kind == RAD_MATERIAL_GLASS) CHECK_NEAR(b->ior, a->ior, 1e-6);
            CHECK_NEAR(surface_area(copy, (long)s), surface_area(original, (long)s), 1e-6);
        }
    }
    /* A patch system has no geometry to export. */
    rad_scene *ffm = NULL;
    CHECK(rad_scene_builtin(ctx, "four-walls", &ffm) == RAD_OK);
    CHECK(rad_scene_export_obj(ctx, ffm, temp_path("four-walls.obj")) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(access(temp_path("four-walls.obj"), F_OK) != 0);
    /* A directory that does not exist: an error, and nothing left behind. */
    CHECK(rad_scene_export_obj(ctx, original, temp_path("no/such/dir.obj")) == RAD_ERROR_IO);
    rad_scene_destroy(ffm);
    rad_scene_destroy(original);
    rad_scene_destroy(copy);
    rad_context_destroy(ctx);
}

int main(void) {
    snprintf(temp_dir, sizeof temp_dir, "/tmp/test_import.XXXXXX");
    if (!mkdtemp(temp_dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_obj_room();
    test_gltf_lamp_room(RAD_SOURCE_DIR "/scenes/lamp-room.gltf");
    test_gltf_lamp_room(RAD_SOURCE_DIR "/scenes/lamp-room.glb");
    test_ply();
    test_faces();
    test_large_circle();
    test_split_through_both_readers();
    test_bad_input();
    test_round_trip("cornell", 1);
    test_round_trip("two-squares", 1);
    test_round_trip("unit-cube", 1);
    test_round_trip("cornell-mirror", 0);
    test_gltf_to_obj();
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", temp_dir);
    if (system(command) != 0) fprintf(stderr, "could not remove %s\n", temp_dir);
    return test_finish();
}
