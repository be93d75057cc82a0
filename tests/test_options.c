/* test_options.c - the per-method option bag (rad_options): setting and replacing values, a
 * full bag, a solver and a form-factor method reading their own options from it with the same
 * result as the older shared fields, and the errors for a name the method did not register and
 * for a value that is not a number. */
#include "radiosity.h"
#include "system/system.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static void test_bag(void) {
    rad_options bag = {0};
    CHECK(rad_options_get(&bag, "overshoot") == NULL);
    CHECK(rad_options_set(&bag, "overshoot", "1") == RAD_OK);
    CHECK(rad_options_set_number(&bag, "link-error", 0.1) == RAD_OK);
    CHECK(strcmp(rad_options_get(&bag, "overshoot"), "1") == 0);
    CHECK(strtod(rad_options_get(&bag, "link-error"), NULL) == 0.1); /* "%.17g" round-trips */
    CHECK(rad_options_set(&bag, "overshoot", "0") == RAD_OK);         /* replaced, not added */
    CHECK(bag.count == 2 && strcmp(rad_options_get(&bag, "overshoot"), "0") == 0);
    char name[40];
    for (int i = (int)bag.count; i < RAD_OPTIONS_MAX; ++i) {
        snprintf(name, sizeof name, "option-%d", i);
        CHECK(rad_options_set(&bag, name, "1") == RAD_OK);
    }
    CHECK(rad_options_set(&bag, "one-too-many", "1") == RAD_ERROR_INVALID_ARGUMENT);
    rad_options small = {0};
    CHECK(rad_options_set(&small, "a-name-longer-than-thirty-one-characters", "1") ==
          RAD_ERROR_INVALID_ARGUMENT);
    CHECK(rad_options_set(&small, "", "1") == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(small.count == 0);
}

/* The Cornell box at 300 elements, solved; NULL on failure (message printed). */
static rad_system *solve(rad_context *ctx, const rad_scene *scene, const rad_ff_options *ff,
                         const rad_solve_options *options) {
    rad_mesh_options mesh = {0, 0, 300, 0, 0};
    rad_system *system = NULL;
    rad_status status = rad_system_create(ctx, scene, &mesh, ff, &system);
    if (!status) status = rad_solve(system, options, NULL);
    if (status) {
        printf("  %s\n", rad_context_error(ctx));
        rad_system_destroy(system);
        return NULL;
    }
    return system;
}

static int same_solution(const rad_system *a, const rad_system *b) {
    return a && b && a->element_count == b->element_count &&
           memcmp(a->radiosity, b->radiosity, a->element_count * sizeof *a->radiosity) == 0 &&
           memcmp(a->ambient, b->ambient, sizeof a->ambient) == 0;
}

static void test_methods_read_the_bag(rad_context *ctx, const rad_scene *scene) {
    /* Shooting with overshooting and the ambient term: the bag gives what the fields gave. */
    rad_solve_options fields = {0};
    fields.solver = RAD_SOLVER_SHOOTING;
    fields.tolerance = 1e-3;
    fields.overshoot = 1;
    fields.ambient = 1;
    rad_options own = {0};
    rad_options_set(&own, "overshoot", "1");
    rad_options_set(&own, "ambient", "1");
    rad_solve_options bagged = {0};
    bagged.solver = RAD_SOLVER_SHOOTING;
    bagged.tolerance = 1e-3;
    bagged.method_options = &own;
    rad_solve_options plain = bagged;
    plain.method_options = NULL;
    rad_system *a = solve(ctx, scene, NULL, &fields), *b = solve(ctx, scene, NULL, &bagged);
    rad_system *c = solve(ctx, scene, NULL, &plain);
    CHECK(same_solution(a, b));
    CHECK(c && !same_solution(a, c)); /* the options do change the result */
    rad_system_destroy(a);
    rad_system_destroy(b);
    rad_system_destroy(c);

    /* Form factors: "ff-samples" in the bag is the older `samples`. */
    rad_options rays = {0};
    rad_options_set(&rays, "ff-samples", "9");
    rad_ff_options ff_fields = {RAD_FF_RAYCAST, 9, 0, NULL};
    rad_ff_options ff_bagged = {RAD_FF_RAYCAST, 0, 0, &rays};
    rad_ff_options ff_plain = {RAD_FF_RAYCAST, 0, 0, NULL};
    a = solve(ctx, scene, &ff_fields, &plain);
    b = solve(ctx, scene, &ff_bagged, &plain);
    c = solve(ctx, scene, &ff_plain, &plain);
    CHECK(same_solution(a, b));
    CHECK(c && !same_solution(a, c));
    rad_system_destroy(a);
    rad_system_destroy(b);
    rad_system_destroy(c);
}

static void test_refusals(rad_context *ctx, const rad_scene *scene) {
    /* A name the solver did not register: the error lists the ones it has. */
    rad_options own = {0};
    rad_options_set(&own, "overshoot", "1");
    rad_solve_options options = {0};
    options.solver = RAD_SOLVER_GAUSS_SEIDEL;
    options.method_options = &own;
    CHECK(solve(ctx, scene, NULL, &options) == NULL);
    CHECK(strcmp(rad_context_error(ctx),
                 "solver gauss-seidel has no option 'overshoot' (it has no options)") == 0);
    rad_options_set(&own, "omega", "1.5");
    options.solver = RAD_SOLVER_SHOOTING;
    CHECK(solve(ctx, scene, NULL, &options) == NULL);
    CHECK(strcmp(rad_context_error(ctx),
                 "solver shooting has no option 'omega' (its options: overshoot, ambient)") == 0);
    rad_options word = {0};
    rad_options_set(&word, "overshoot", "yes");
    options.method_options = &word;
    CHECK(solve(ctx, scene, NULL, &options) == NULL);
    CHECK(strcmp(rad_context_error(ctx),
                 "solver shooting: option 'overshoot' must be a number, not 'yes'") == 0);
    /* And a form-factor method. */
    rad_options cube = {0};
    rad_options_set(&cube, "hemicube-res", "64");
    rad_ff_options ff = {RAD_FF_ANALYTIC, 0, 0, &cube};
    rad_solve_options plain = {0};
    CHECK(solve(ctx, scene, &ff, &plain) == NULL);
    CHECK(strcmp(rad_context_error(ctx), "form-factor method analytic has no option "
                 "'hemicube-res' (its options: ff-samples)") == 0);
    rad_options half = {0};
    rad_options_set(&half, "ff-samples", "2.5");
    ff = (rad_ff_options){RAD_FF_RAYCAST, 0, 0, &half};
    CHECK(solve(ctx, scene, &ff, &plain) == NULL);
    CHECK(strstr(rad_context_error(ctx), "whole numbers") != NULL);
}

int main(void) {
    test_bag();
    rad_context_options context_options = {0};
    context_options.threads = 2;
    rad_context *ctx = NULL;
    rad_scene *scene = NULL;
    CHECK(rad_context_create(&context_options, &ctx) == RAD_OK);
    CHECK(ctx && rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK);
    if (scene) {
        test_methods_read_the_bag(ctx, scene);
        test_refusals(ctx, scene);
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return test_finish();
}
