/* test_progressive.c - progressive refinement you can watch and stop: the iteration callback,
 * the time budget, resuming (N shots then M more equal N + M shots, bit for bit), overshooting
 * (same solution, fewer shots), what a camera sees, and importance-driven shooting (the view
 * reaches a given error in fewer shots than plain shooting, the whole solution is still right). */
#include "radiosity.h"
#include "test.h"

#include "system/system.h"

#include <stdlib.h>
#include <string.h>

static rad_context *ctx;

static rad_system *build(const char *name, size_t elements) {
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_mesh_options mesh = {0};
    mesh.elements = elements;
    CHECK(rad_scene_builtin(ctx, name, &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_OK);
    rad_scene_destroy(scene);
    return system;
}

/* The solution as one array (radiosity then unshot, per element). */
static double *snapshot(const rad_system *s) {
    double *copy = malloc(6 * s->element_count * sizeof *copy);
    memcpy(copy, s->radiosity, 3 * s->element_count * sizeof *copy);
    memcpy(copy + 3 * s->element_count, s->unshot, 3 * s->element_count * sizeof *copy);
    return copy;
}

static int same_solution(const rad_system *s, const double *copy) {
    return memcmp(copy, s->radiosity, 3 * s->element_count * sizeof *copy) == 0 &&
           memcmp(copy + 3 * s->element_count, s->unshot, 3 * s->element_count * sizeof *copy) == 0;
}

/* ------------------------------------------------------------------------------------------- */

typedef struct watched {
    int calls, stop_after;
    long last_shots, last_rounds;
    double last_seconds, last_residual, last_unshot;
    int monotone_time, shots_count_up;
} watched;

static int watch(void *user, const rad_iteration_event *event) {
    watched *w = user;
    w->calls++;
    if (event->seconds < w->last_seconds) w->monotone_time = 0;
    if (event->shots && event->shots != w->last_shots + 1) w->shots_count_up = 0;
    w->last_seconds = event->seconds;
    w->last_shots = event->shots;
    w->last_rounds = event->rounds;
    w->last_residual = event->residual;
    w->last_unshot = event->unshot_fraction;
    return w->stop_after && w->calls >= w->stop_after;
}

static void test_iteration_callback(void) {
    rad_system *system = build("four-walls", 0);
    watched w = {0, 0, 0, 0, 0, 0, 0, 1, 1};
    rad_solve_options o = {.solver = RAD_SOLVER_SHOOTING, .on_iteration = watch, .iteration_user = &w};
    rad_solve_report report;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(w.calls == report.iterations);
    CHECK(w.last_shots == report.iterations && w.last_rounds == 0);
    CHECK(w.monotone_time && w.shots_count_up);
    CHECK(w.last_unshot == w.last_residual && w.last_residual == report.residual);
    CHECK(report.stop == RAD_STOP_CONVERGED && report.converged);
    CHECK(report.unshot_fraction == report.residual);

    /* Gathering: rounds, and no unshot fraction. */
    watched g = {0, 0, 0, 0, 0, 0, 0, 1, 1};
    o = (rad_solve_options){.solver = RAD_SOLVER_JACOBI, .on_iteration = watch, .iteration_user = &g};
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(g.calls == report.iterations && g.last_rounds == report.iterations && g.last_shots == 0);
    CHECK(isnan(g.last_unshot));

    /* Asking to stop: the solution so far, no error. */
    watched s = {0, 3, 0, 0, 0, 0, 0, 1, 1};
    o = (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .on_iteration = watch, .iteration_user = &s};
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(report.iterations == 3 && report.stop == RAD_STOP_CALLBACK && !report.converged);
    rad_system_destroy(system);
}

static void test_time_budget(void) {
    rad_system *system = build("four-walls", 0);
    /* A budget used up by the first shot: one step, the best so far, no error. */
    rad_solve_options o = {.solver = RAD_SOLVER_SHOOTING, .time_budget = 1e-12};
    rad_solve_report report;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(report.iterations == 1 && report.stop == RAD_STOP_TIME_BUDGET && !report.converged);
    /* A generous one does not get in the way. */
    o.time_budget = 100;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(report.converged && report.stop == RAD_STOP_CONVERGED);
    o.time_budget = -1;
    CHECK(rad_solve(system, &o, &report) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "time budget") != NULL);
    o.time_budget = NAN;
    CHECK(rad_solve(system, &o, &report) == RAD_ERROR_INVALID_ARGUMENT);
    rad_system_destroy(system);
}

/* N steps, then M more with resume, against N + M in one go: bit for bit. */
static void check_resume(rad_system *system, rad_solve_options o, int n, int m) {
    rad_solve_report report;
    o.max_iterations = n + m;
    o.resume = 0;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(report.iterations == n + m);
    double *straight = snapshot(system);
    o.max_iterations = n;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    o.max_iterations = m;
    o.resume = 1;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(report.iterations == m);
    CHECK(same_solution(system, straight));
    free(straight);
}

static void test_resume(void) {
    rad_system *walls = build("four-walls", 0);
    check_resume(walls, (rad_solve_options){.solver = RAD_SOLVER_SHOOTING}, 3, 4);
    check_resume(walls, (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .omega = 1.3}, 2, 5);
    check_resume(walls, (rad_solve_options){.solver = RAD_SOLVER_JACOBI}, 3, 4);
    check_resume(walls, (rad_solve_options){.solver = RAD_SOLVER_GAUSS_SEIDEL, .omega = 1.2}, 2, 3);
    rad_system_destroy(walls);

    rad_system *cornell = build("cornell", 300);
    rad_camera_desc camera = {{186, 200, -100}, {186, 80, 170}, {0, 1, 0}, 30};
    check_resume(cornell, (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .overshoot = 1}, 40, 35);
    check_resume(cornell, (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .ambient = 1}, 25, 25);
    check_resume(cornell, (rad_solve_options){.solver = RAD_SOLVER_IMPORTANCE, .camera = &camera,
                                              .view_width = 64, .view_height = 64}, 30, 20);
    rad_system_destroy(cornell);
}

/* Overshooting reaches the same solution as the direct solver, in fewer shots than plain
 * shooting. */
static void test_overshooting(void) {
    rad_system *system = build("four-walls", 0);
    rad_solve_options o = {.solver = RAD_SOLVER_DIRECT};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    double *exact = snapshot(system);
    o = (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .overshoot = 1, .tolerance = 1e-12};
    rad_solve_report report;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    CHECK(report.converged);
    for (size_t e = 0; e < system->element_count; ++e)
        for (int c = 0; c < 3; ++c) CHECK_NEAR(system->radiosity[e][c], exact[3 * e + c], 1e-6);
    free(exact);
    rad_system_destroy(system);

    /* Cornell box, 600 elements: shots to 1e-3 unshot power. Measured: 796 plain, 427
     * overshooting (1.86x); the test holds 1.5x. */
    system = build("cornell", 600);
    o = (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .tolerance = 1e-3};
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    int plain = report.iterations;
    o.overshoot = 1;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    int over = report.iterations;
    printf("shots to 1e-3: plain %d, overshooting %d (%.2fx)\n", plain, over, (double)plain / over);
    CHECK(report.converged && over * 1.5 <= plain);
    rad_system_destroy(system);
}

/* ------------------------------------------------------------------------------------------- */
/* What the camera sees, and importance.                                                         */

static void test_screen_share(void) {
    /* Inside the closed unit cube every pixel sees an inward face. */
    rad_system *cube = build("unit-cube", 200);
    rad_camera_desc inside = {{0.5, 0.5, 0.1}, {0.5, 0.5, 1}, {0, 1, 0}, 90};
    double *share = calloc(cube->element_count, sizeof *share);
    CHECK(rad_system_screen_share(cube, &inside, 40, 30, share) == RAD_OK);
    double sum = 0;
    for (size_t e = 0; e < cube->element_count; ++e) sum += share[e];
    CHECK_NEAR(sum, 1.0, 1e-12);
    /* From outside, looking away: nothing. */
    rad_camera_desc away = {{0.5, 0.5, -1}, {0.5, 0.5, -2}, {0, 1, 0}, 40};
    CHECK(rad_system_screen_share(cube, &away, 16, 16, share) == RAD_OK);
    sum = 0;
    for (size_t e = 0; e < cube->element_count; ++e) sum += share[e];
    CHECK(sum == 0);
    free(share);
    rad_system_destroy(cube);

    rad_system *walls = build("four-walls", 0);
    double patch_share[4];
    CHECK(rad_system_screen_share(walls, &inside, 8, 8, patch_share) == RAD_ERROR_INVALID_ARGUMENT);
    rad_solve_options o = {.solver = RAD_SOLVER_IMPORTANCE, .camera = &inside};
    CHECK(rad_solve(walls, &o, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "geometric") != NULL);
    o.camera = NULL;
    CHECK(rad_solve(walls, &o, NULL) == RAD_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(rad_context_error(ctx), "camera") != NULL);
    rad_system_destroy(walls);
}

typedef struct view_error {
    const rad_system *system;
    const double *reference, *share;
    double norm;
    const double *thresholds;
    int count;
    int *shots; /* first shot at or under each threshold */
} view_error;

/* The error of the picture: sum over elements of share |B - B*|, relative to sum share B*, which
 * is the relative L1 error of a flat-shaded image at one ray per pixel. */
static double measure_view_error(const view_error *v) {
    double error = 0;
    for (size_t e = 0; e < v->system->element_count; ++e)
        for (int c = 0; c < 3; ++c)
            error += v->share[e] * fabs(v->system->radiosity[e][c] - v->reference[3 * e + c]);
    return error / v->norm;
}

static int on_shot(void *user, const rad_iteration_event *event) {
    view_error *v = user;
    double error = measure_view_error(v);
    int pending = 0;
    for (int k = 0; k < v->count; ++k) {
        if (v->shots[k] == 0 && error <= v->thresholds[k]) v->shots[k] = event->iteration;
        if (v->shots[k] == 0) pending = 1;
    }
    return !pending;
}

static void test_importance(void) {
    rad_system *system = build("cornell", 1000);
    size_t n = system->element_count;
    /* The converged solution. */
    rad_solve_options o = {.solver = RAD_SOLVER_GAUSS_SEIDEL, .tolerance = 1e-10};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    double *reference = snapshot(system);

    /* A camera close on the short block: it fills the picture. */
    rad_camera_desc camera = {{186, 200, -100}, {186, 80, 170}, {0, 1, 0}, 30};
    double *share = calloc(n, sizeof *share);
    CHECK(rad_system_screen_share(system, &camera, 128, 128, share) == RAD_OK);
    double norm = 0, block = 0;
    for (size_t e = 0; e < n; ++e) {
        norm += share[e] * (reference[3 * e] + reference[3 * e + 1] + reference[3 * e + 2]);
        if (strcmp(system->surface_name[system->element_surface[e]], "short-block") == 0)
            block += share[e];
    }
    CHECK(block > 0.99);

    static const double thresholds[] = {0.3, 0.2, 0.1, 0.05};
    enum { COUNT = 4 };
    int plain[COUNT] = {0}, important[COUNT] = {0};
    view_error v = {system, reference, share, norm, thresholds, COUNT, plain};
    o = (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .on_iteration = on_shot,
                            .iteration_user = &v};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    v.shots = important;
    o.solver = RAD_SOLVER_IMPORTANCE;
    o.camera = &camera;
    o.view_width = o.view_height = 128;
    rad_solve_report report;
    CHECK(rad_solve(system, &o, &report) == RAD_OK);
    for (int k = 0; k < COUNT; ++k)
        printf("view error %.2f: shooting %d shots, importance %d (+%d for importance) %.2fx\n",
               thresholds[k], plain[k], important[k], report.importance_shots,
               (double)plain[k] / important[k]);
    /* Measured (1078 elements, 305 patches): to 20% view error, 174 shots plain and 48 with
     * importance (3.6x; 2.3x counting the 27 rows of the importance pass too); to 10%, 314 and
     * 164 (1.9x). The test holds 1.5x at 20% with the importance pass counted, and at 10%. */
    CHECK(important[1] > 0 && (important[1] + report.importance_shots) * 1.5 <= plain[1]);
    CHECK(important[2] > 0 && important[2] * 1.5 <= plain[2]);
    /* Later it keeps pace. */
    CHECK(important[3] > 0 && important[3] <= plain[3] * 1.1);

    /* Still a full solution: converged, it matches the reference everywhere. */
    o = (rad_solve_options){.solver = RAD_SOLVER_IMPORTANCE, .camera = &camera, .tolerance = 1e-9};
    CHECK(rad_solve(system, &o, &report) == RAD_OK && report.converged);
    double worst = 0;
    for (size_t e = 0; e < n; ++e)
        for (int c = 0; c < 3; ++c) {
            double b = reference[3 * e + c];
            worst = fmax(worst, fabs(system->radiosity[e][c] - b) / fmax(b, 1e-3));
        }
    CHECK(worst < 1e-5);
    free(reference);
    free(share);
    rad_system_destroy(system);
}

int main(void) {
    CHECK(rad_context_create(&(rad_context_options){.threads = 2}, &ctx) == RAD_OK);
    test_iteration_callback();
    test_time_budget();
    test_resume();
    test_overshooting();
    test_screen_share();
    test_importance();
    rad_context_destroy(ctx);
    return test_finish();
}
