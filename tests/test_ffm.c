/* test_ffm.c - the .ffm patch-system format: what it accepts, and every rejection naming
 * file:line and what is wrong. */
#include "radiosity.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static rad_context *ctx;
static char last_warning[512];

static void on_log(void *user, rad_log_level level, const char *message) {
    (void)user;
    if (level == RAD_LOG_WARNING) snprintf(last_warning, sizeof last_warning, "%s", message);
}

/* Parsing `text` fails with a message containing `expected`. */
static void rejects_bytes(const char *text, size_t length, const char *expected) {
    rad_scene *scene = (rad_scene *)1;
    rad_status status = rad_scene_parse_ffm(ctx, text, length, "bad.ffm", &scene);
    CHECK(status == RAD_ERROR_PARSE);
    CHECK(scene == NULL);
    const char *message = rad_context_error(ctx);
    if (!strstr(message, expected)) {
        fprintf(stderr, "  message '%s' lacks '%s'\n", message, expected);
        CHECK(0);
    }
}

static void rejects(const char *text, const char *expected) {
    rejects_bytes(text, strlen(text), expected);
}

static rad_scene *accepts(const char *text) {
    rad_scene *scene = NULL;
    rad_status status = rad_scene_parse_ffm(ctx, text, strlen(text), "good.ffm", &scene);
    CHECK(status == RAD_OK);
    if (status) fprintf(stderr, "  %s\n", rad_context_error(ctx));
    return scene;
}

#define P "patch a area 1 reflectance 0.5 emission 1\npatch b area 2 reflectance 0.5\n"

int main(void) {
    rad_context_options options = {.log = on_log};
    CHECK(rad_context_create(&options, &ctx) == RAD_OK);

    /* Accepted: comments, blank lines, RGB values, any key order, missing ff pairs. */
    rad_scene *scene = accepts("# a comment\n\npatch x emission 0.1 0.2 0.3 reflectance 0.2 0.4 "
                               "0.6 area 3  # trailing comment\npatch y area 1 reflectance 0\n"
                               "ff x y 0.25\n");
    rad_system *system = NULL;
    CHECK(rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK);
    rad_surface_info info;
    CHECK(rad_system_surface(system, 0, &info) == RAD_OK);
    CHECK(strcmp(info.name, "x") == 0 && info.area == 3);
    CHECK_NEAR(info.reflectance[2], 0.6, 1e-15);
    CHECK_NEAR(info.emission[1], 0.2, 1e-15);
    rad_system_destroy(system);
    rad_scene_destroy(scene);

    /* Rejected, each with file:line. */
    rejects(P "patch c area 1 reflectance 1.5\n", "bad.ffm:3: reflectance of 'c' must be in [0, 1]");
    rejects(P "patch c area 1 reflectance -0.1\n", "bad.ffm:3:");
    rejects(P "patch c area -1 reflectance 0.5\n", "bad.ffm:3: area of 'c' must be positive");
    rejects(P "patch c area 0 reflectance 0.5\n", "area of 'c' must be positive");
    rejects(P "patch c area 1 reflectance 0.5 emission -2\n", "emission of 'c' must not be negative");
    rejects(P "patch c area nan reflectance 0.5\n", "not a finite number");
    rejects(P "patch c area 1 reflectance inf\n", "not a finite number");
    rejects(P "patch c area 1e999 reflectance 0.5\n", "not a finite number");
    rejects(P "patch c area one reflectance 0.5\n", "'one' is not a number");
    rejects(P "patch a area 1 reflectance 0.5\n", "bad.ffm:3: duplicate patch name 'a'");
    rejects(P "ff a c 0.5\n", "bad.ffm:3: unknown patch 'c'");
    rejects(P "ff a b 1.5\n", "form factor a -> b must be in [0, 1]");
    rejects(P "ff a b -0.5\n", "must be in [0, 1]");
    rejects(P "ff a b 0.5\nff a b 0.25\n", "bad.ffm:4: duplicate form factor a -> b");
    rejects(P "ff a b 0.6\nff a a 0.5\n", "bad.ffm:4: form factors leaving 'a' sum to 1.1");
    rejects(P "ff a b\n", "bad.ffm:3: expected 'ff FROM TO VALUE'");
    rejects(P "light c\n", "bad.ffm:3: unknown keyword 'light'");
    rejects(P "patch c area 1\n", "patch 'c' needs a reflectance");
    rejects(P "patch c reflectance 0.5\n", "patch 'c' needs an area");
    rejects(P "patch c area 1 reflectance 0.5 colour 3\n", "unknown patch property 'colour'");
    rejects("# nothing\n", "no patches");
    static const char binary[] = "patch a area 1 reflectance 0.5\0garbage\n";
    rejects_bytes(binary, sizeof binary - 1, "bad.ffm:1: binary data");

    /* Slack: rows may sum to 1 + 1e-3 (rounded inputs). */
    scene = accepts(P "ff a b 0.6\nff a a 0.4005\n");
    rad_scene_destroy(scene);

    /* Warnings, not errors: reflectance 1, nothing emitting. */
    last_warning[0] = '\0';
    scene = accepts("patch a area 1 reflectance 1 emission 1\n");
    CHECK(strstr(last_warning, "may not converge") != NULL);
    rad_scene_destroy(scene);
    last_warning[0] = '\0';
    scene = accepts("patch a area 1 reflectance 0.5\n");
    CHECK(strstr(last_warning, "nothing emits") != NULL);
    rad_scene_destroy(scene);

    /* Many patches (names found through the hash index as it grows): every ff line lands in the
     * right cell, and a repeated name or pair far down the file is still refused with its line. */
    enum { MANY = 600 };
    size_t capacity = (size_t)MANY * 128, length = 0;
    char *many = malloc(capacity);
    CHECK(many != NULL);
    if (!many) return test_finish();
    for (int i = 0; i < MANY; ++i) /* lines 1..MANY */
        length += (size_t)snprintf(many + length, capacity - length,
                                   "patch p%d area 1 reflectance 0.5 emission %d\n", i, i % 2);
    for (int i = 0; i < MANY; ++i) /* lines MANY+1..2 MANY: p_i -> p_{7i+1 mod MANY} */
        length += (size_t)snprintf(many + length, capacity - length, "ff p%d p%d %.9g\n", i,
                                   (7 * i + 1) % MANY, (i % 100) / 128.0);
    scene = accepts(many);
    system = NULL;
    CHECK(rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK);
    double *matrix = malloc(sizeof(double) * MANY * MANY);
    CHECK(matrix && rad_system_surface_form_factors(system, matrix) == RAD_OK);
    int cells_right = 1;
    for (int i = 0; matrix && i < MANY; ++i)
        for (int j = 0; j < MANY; ++j) {
            double expected = j == (7 * i + 1) % MANY ? (i % 100) / 128.0 : 0.0;
            if (matrix[(size_t)i * MANY + j] != expected) cells_right = 0;
        }
    CHECK(cells_right);
    CHECK(rad_system_surface(system, MANY - 1, &info) == RAD_OK);
    CHECK(strcmp(info.name, "p599") == 0);
    free(matrix);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    char *tail = many + length;
    snprintf(tail, capacity - length, "patch p417 area 1 reflectance 0.5\n");
    rejects(many, "bad.ffm:1201: duplicate patch name 'p417'");
    snprintf(tail, capacity - length, "ff p10 p71 0.5\n");
    rejects(many, "bad.ffm:1201: duplicate form factor p10 -> p71 (first on line 611)");
    snprintf(tail, capacity - length, "ff p10 p600 0.5\n");
    rejects(many, "bad.ffm:1201: unknown patch 'p600'");
    snprintf(tail, capacity - length, "ff p99 p0 0.5\n");
    rejects(many, "bad.ffm:1201: form factors leaving 'p99' sum to 1.27344, more than 1");
    free(many);

    /* Files: missing, empty, and the shipped four-walls equal to the built-in. */
    CHECK(rad_scene_load(ctx, "/nonexistent/room.ffm", &scene) == RAD_ERROR_IO);
    CHECK(strstr(rad_context_error(ctx), "/nonexistent/room.ffm") != NULL);
    CHECK(rad_scene_load(ctx, RAD_SOURCE_DIR "/scenes/four-walls.ffm", &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK);
    rad_solve_options solve = {.solver = RAD_SOLVER_DIRECT};
    CHECK(rad_solve(system, &solve, NULL) == RAD_OK);
    CHECK(rad_system_surface(system, 3, &info) == RAD_OK);
    CHECK(strcmp(info.name, "right") == 0);
    CHECK_NEAR(info.radiosity[0], 1.00305, 5e-6);
    rad_system_destroy(system);
    rad_scene_destroy(scene);

    rad_context_destroy(ctx);
    return test_finish();
}
