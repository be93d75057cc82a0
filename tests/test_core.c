/* test_core.c - the radiosity system in matrix form: the lecture's four-surface room round by
 * round and shot by shot, exact small systems, closed enclosures, and every solver against the
 * direct solution; and the worker threads the solver's rows run on. */
#include "core/team.h"
#include "radiosity.h"
#include "test.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static rad_context *ctx;

/* The lecture prints three decimals: the value must round to the printed number. Form factors
 * are stored in float32, so allow their rounding (1e-7) on top. */
#define PRINTED 5.001e-4
/* float32 form factors: about 7 significant digits. */
#define FLOAT_FF 1.5e-7

static rad_system *load(const char *name) {
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    CHECK(rad_scene_builtin(ctx, name, &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK);
    rad_scene_destroy(scene);
    return system;
}

static double radiosity_of(const rad_system *system, const char *name) {
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        if (strcmp(info.name, name) == 0) return info.radiosity[0];
    }
    return NAN;
}

/* Records the trace: per iteration, per surface, received / reflected / radiosity / unshot. */
typedef struct recorded {
    int count;
    long shooter[8];
    double received[8][4], reflected[8][4], radiosity[8][4], unshot[8][4];
} recorded;

static void record(void *user, const rad_trace_event *event) {
    recorded *r = user;
    if (r->count >= 8 || event->surface_count != 4) return;
    int i = r->count++;
    r->shooter[i] = event->shooter;
    for (int s = 0; s < 4; ++s) {
        r->received[i][s] = event->received[s][0];
        r->radiosity[i][s] = event->radiosity[s][0];
        r->reflected[i][s] = event->reflected ? event->reflected[s][0] : NAN;
        r->unshot[i][s] = event->unshot ? event->unshot[s][0] : NAN;
    }
}

enum { CEILING, FLOOR, LEFT, RIGHT };

/* The lecture's gathering example, to the printed digits. */
static void test_jacobi_rounds(void) {
    rad_system *system = load("four-walls");
    recorded r = {0};
    rad_solve_options options = {.solver = RAD_SOLVER_JACOBI, .max_iterations = 2,
                                 .trace = record, .trace_user = &r};
    rad_solve_report report;
    CHECK(rad_solve(system, &options, &report) == RAD_OK);
    CHECK(report.iterations == 2 && !report.converged && r.count == 2);
    CHECK_NEAR(r.radiosity[0][CEILING], .1875, PRINTED);
    CHECK_NEAR(r.radiosity[0][FLOOR], .025, PRINTED);
    CHECK_NEAR(r.radiosity[0][LEFT], .375, PRINTED);
    CHECK_NEAR(r.radiosity[0][RIGHT], 1, PRINTED);
    CHECK_NEAR(r.received[1][FLOOR], .438, PRINTED);
    CHECK_NEAR(r.received[1][LEFT], .553, PRINTED);
    CHECK_NEAR(r.received[1][CEILING], .356, PRINTED);
    CHECK_NEAR(r.received[1][RIGHT], .241, PRINTED);
    CHECK_NEAR(r.radiosity[1][FLOOR], .044, PRINTED);
    CHECK_NEAR(r.radiosity[1][LEFT], .415, PRINTED);
    CHECK_NEAR(r.radiosity[1][CEILING], .267, PRINTED);
    CHECK_NEAR(r.radiosity[1][RIGHT], 1.002, PRINTED);
    CHECK(r.shooter[0] == -1);
    rad_system_destroy(system);
}

/* The lecture's shooting example: the right wall shoots, then the left wall. */
static void test_shooting_shots(void) {
    rad_system *system = load("four-walls");
    recorded r = {0};
    rad_solve_options options = {.solver = RAD_SOLVER_SHOOTING, .max_iterations = 2,
                                 .trace = record, .trace_user = &r};
    CHECK(rad_solve(system, &options, NULL) == RAD_OK);
    CHECK(r.count == 2);
    CHECK(r.shooter[0] == RIGHT);
    CHECK_NEAR(r.received[0][LEFT], .5, PRINTED);
    CHECK_NEAR(r.reflected[0][LEFT], .375, PRINTED);
    CHECK_NEAR(r.received[0][CEILING], .25, PRINTED);
    CHECK_NEAR(r.reflected[0][CEILING], .188, PRINTED);
    CHECK_NEAR(r.received[0][FLOOR], .25, PRINTED);
    CHECK_NEAR(r.reflected[0][FLOOR], .025, PRINTED);
    CHECK_NEAR(r.unshot[0][RIGHT], 0, 1e-12);
    CHECK(r.shooter[1] == LEFT);
    CHECK_NEAR(r.received[1][CEILING], .094, PRINTED);
    CHECK_NEAR(r.reflected[1][CEILING], .070, PRINTED * 10); /* printed with two decimals */
    CHECK_NEAR(r.received[1][RIGHT], .188, PRINTED);
    CHECK_NEAR(r.reflected[1][RIGHT], .002, PRINTED);
    CHECK_NEAR(r.received[1][FLOOR], .094, PRINTED);
    CHECK_NEAR(r.reflected[1][FLOOR], .009, PRINTED);
    CHECK_NEAR(r.unshot[1][LEFT], 0, 1e-12);
    CHECK_NEAR(r.radiosity[1][LEFT], .375, PRINTED);
    rad_system_destroy(system);
}

/* Every solver (and over-relaxed variants) converges to the direct solution. */
static void test_solvers_agree(const char *scene) {
    rad_system *system = load(scene);
    size_t n = rad_system_surface_count(system);
    double direct[16];
    rad_solve_options options = {.solver = RAD_SOLVER_DIRECT};
    CHECK(rad_solve(system, &options, NULL) == RAD_OK);
    for (size_t i = 0; i < n && i < 16; ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        direct[i] = info.radiosity[0];
    }
    struct { rad_solver_kind kind; double omega; } runs[] = {
        {RAD_SOLVER_JACOBI, 1},   {RAD_SOLVER_GAUSS_SEIDEL, 1}, {RAD_SOLVER_GAUSS_SEIDEL, 1.2},
        {RAD_SOLVER_SHOOTING, 1}, {RAD_SOLVER_SHOOTING, 1.3},
    };
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; ++k) {
        rad_solve_options o = {.solver = runs[k].kind, .omega = runs[k].omega, .tolerance = 1e-10};
        rad_solve_report report;
        CHECK(rad_solve(system, &o, &report) == RAD_OK);
        CHECK(report.converged);
        for (size_t i = 0; i < n && i < 16; ++i) {
            rad_surface_info info;
            rad_system_surface(system, i, &info);
            CHECK_NEAR(info.radiosity[0], direct[i], 1e-6);
        }
    }
    rad_system_destroy(system);
}

/* Each surface's numbers are the area-weighted means over exactly its elements, wherever they
 * lie in the mesh (the generated office's surfaces, one per material, have elements spread over
 * every room): the surfaces' powers add up to the elements' power, their areas to the mesh's. */
static void test_surface_sums(void) {
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    CHECK(rad_scene_generate_office(ctx, 2000, &scene) == RAD_OK);
    rad_mesh_options mesh = {.elements = 3000};
    CHECK(rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_OK);
    rad_solve_options o = {.solver = RAD_SOLVER_SHOOTING, .max_iterations = 50};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    double element_area = 0, element_power = 0, surface_area = 0, surface_power = 0;
    for (size_t e = 0; e < rad_system_element_count(system); ++e) {
        double radiosity[3];
        rad_system_element_radiosity(system, e, radiosity);
        element_area += rad_system_element_area(system, e);
        element_power += rad_system_element_area(system, e) * radiosity[1];
    }
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        CHECK(rad_system_surface(system, i, &info) == RAD_OK);
        surface_area += info.area;
        surface_power += info.power[1];
    }
    CHECK(rad_system_surface_count(system) > 2 && element_power > 0);
    CHECK_NEAR(surface_area / element_area, 1, 1e-12);
    CHECK_NEAR(surface_power / element_power, 1, 1e-12);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
}

/* Two opposed unit squares one apart: F = 0.199824895698, rho = 0.5, E = 1 on one. */
static void test_two_squares_exact(void) {
    const char text[] = "patch a area 1 reflectance 0.5 emission 1\n"
                        "patch b area 1 reflectance 0.5 emission 0\n"
                        "ff a b 0.199824895698\nff b a 0.199824895698\n";
    rad_scene *scene;
    rad_system *system;
    CHECK(rad_scene_parse_ffm(ctx, text, strlen(text), "squares", &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK);
    for (int kind = RAD_SOLVER_DIRECT; kind <= RAD_SOLVER_SHOOTING; ++kind) {
        rad_solve_options o = {.solver = (rad_solver_kind)kind, .tolerance = 1e-13};
        CHECK(rad_solve(system, &o, NULL) == RAD_OK);
        CHECK_NEAR(radiosity_of(system, "a"), 1.01008315227, FLOAT_FF);
        CHECK_NEAR(radiosity_of(system, "b"), 0.100919880275, FLOAT_FF);
    }
    rad_system_destroy(system);
    rad_scene_destroy(scene);
}

/* A closed enclosure (the inside of a sphere: F_ij = A_j / A) with uniform rho and E has
 * B = E / (1 - rho) everywhere, and absorbs what it emits. */
static void test_enclosure(void) {
    enum { N = 40 };
    rad_patch_desc patches[N];
    static float ff[N * N];
    double total = 0, rho = 0.8, emission = 2.5;
    for (int i = 0; i < N; ++i) {
        patches[i] = (rad_patch_desc){NULL, 0.5 + (i % 7) * 0.3, {rho, rho, rho},
                                      {emission, emission, emission}};
        total += patches[i].area;
    }
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) ff[i * N + j] = (float)(patches[j].area / total);
    rad_system *system;
    CHECK(rad_system_create_dense(ctx, patches, N, ff, &system) == RAD_OK);
    for (int kind = RAD_SOLVER_DIRECT; kind <= RAD_SOLVER_SHOOTING; ++kind) {
        rad_solve_options o = {.solver = (rad_solver_kind)kind, .tolerance = 1e-9};
        CHECK(rad_solve(system, &o, NULL) == RAD_OK);
        double absorbed = 0, emitted = 0, worst = 0;
        for (int i = 0; i < N; ++i) {
            rad_surface_info info;
            rad_system_surface(system, (size_t)i, &info);
            worst = fmax(worst, fabs(info.radiosity[1] - emission / (1 - rho)));
            double irradiance = (info.radiosity[1] - emission) / rho;
            absorbed += (1 - rho) * irradiance * info.area;
            emitted += emission * info.area;
        }
        CHECK_NEAR(worst, 0, 1e-5 * emission / (1 - rho));
        CHECK_NEAR(absorbed / emitted, 1, 1e-5);
    }
    rad_system_destroy(system);
}

/* Colour: each channel is its own system; the direct solver factorises per channel. */
static void test_colour(void) {
    const char text[] = "patch red area 2 reflectance 0.9 0.2 0.1 emission 0\n"
                        "patch lamp area 1 reflectance 0.5 emission 1 2 3\n"
                        "ff red lamp 0.3\nff lamp red 0.6\n";
    rad_scene *scene;
    rad_system *system;
    CHECK(rad_scene_parse_ffm(ctx, text, strlen(text), "colour", &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, NULL, NULL, &system) == RAD_OK);
    rad_solve_options o = {.solver = RAD_SOLVER_DIRECT};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    /* B_lamp = E + rho_l * F_red,lamp * A_red / A_lamp * B_red, B_red = rho_r * F_lamp,red * A_lamp / A_red * B_lamp */
    for (int c = 0; c < 3; ++c) {
        double rho_r = c == 0 ? 0.9 : c == 1 ? 0.2 : 0.1, e = c + 1.0;
        double a = 0.5 * 0.3 * 2.0, b = rho_r * 0.6 * 0.5;
        double lamp = e / (1 - a * b), red = b * lamp;
        rad_surface_info info;
        rad_system_surface(system, 0, &info);
        CHECK_NEAR(info.radiosity[c], red, FLOAT_FF * red);
        rad_system_surface(system, 1, &info);
        CHECK_NEAR(info.radiosity[c], lamp, FLOAT_FF * lamp);
        CHECK_NEAR(info.power[c], lamp * 1.0, FLOAT_FF * lamp);
    }
    rad_system_destroy(system);
    rad_scene_destroy(scene);
}

/* The direct solver refuses, naming the iterative solvers, when the matrix would not fit. */
static void test_memory_budget(void) {
    rad_context_options options = {.max_memory = 1000};
    rad_context *small;
    CHECK(rad_context_create(&options, &small) == RAD_OK);
    rad_scene *scene;
    rad_system *system = NULL;
    CHECK(rad_scene_builtin(small, "four-walls", &scene) == RAD_OK);
    CHECK(rad_system_create(small, scene, NULL, NULL, &system) == RAD_OK);
    rad_system_destroy(system);
    rad_scene_destroy(scene);

    enum { N = 64 };
    rad_patch_desc patches[N];
    static float ff[N * N];
    for (int i = 0; i < N; ++i) patches[i] = (rad_patch_desc){NULL, 1, {0.5, 0.5, 0.5}, {1, 1, 1}};
    options.max_memory = 4 * N * N + 100; /* the matrix fits, the dense solve does not */
    rad_context *tight;
    CHECK(rad_context_create(&options, &tight) == RAD_OK);
    CHECK(rad_system_create_dense(tight, patches, N, ff, &system) == RAD_OK);
    rad_solve_options o = {.solver = RAD_SOLVER_DIRECT};
    CHECK(rad_solve(system, &o, NULL) == RAD_ERROR_MEMORY_BUDGET);
    CHECK(strstr(rad_context_error(tight), "gauss-seidel") != NULL);
    o.solver = RAD_SOLVER_SHOOTING;
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    rad_system_destroy(system);
    rad_context_destroy(tight);
    rad_context_destroy(small);
}

/* The registries: names parse back to their kinds, a zeroed options struct runs the default
 * solver (shooting: same shots, same radiosity), the resume rule, the form-factor methods. */
static void test_registries(void) {
    CHECK(rad_solver_count() >= 5);
    for (size_t i = 0; i < rad_solver_count(); ++i) {
        const rad_solver_info *info = rad_solver_at(i);
        CHECK(info && info->name && info->description && *info->description);
        CHECK(rad_solver_kind_parse(info->name) == (int)i + 1);
        CHECK(strcmp(rad_solver_kind_name((rad_solver_kind)(i + 1)), info->name) == 0);
        CHECK(rad_solver_get((rad_solver_kind)(i + 1)) == info);
    }
    CHECK(rad_solver_at(rad_solver_count()) == NULL);
    CHECK(rad_solver_kind_parse("no-such-solver") == -1 && rad_solver_kind_parse(NULL) == -1);
    CHECK(rad_solver_get(RAD_SOLVER_DEFAULT) == rad_solver_get(RAD_SOLVER_SHOOTING));
    CHECK(rad_solver_get((rad_solver_kind)(rad_solver_count() + 1)) == NULL);
    CHECK(rad_solver_get(RAD_SOLVER_SHOOTING)->capabilities & RAD_SOLVER_SHOOTS);
    CHECK(!(rad_solver_get(RAD_SOLVER_JACOBI)->capabilities & RAD_SOLVER_SHOOTS));
    CHECK(rad_solver_get(RAD_SOLVER_IMPORTANCE)->capabilities & RAD_SOLVER_NEEDS_CAMERA);
    CHECK(!rad_solver_can_resume(RAD_SOLVER_SHOOTING, RAD_SOLVER_JACOBI));
    CHECK(rad_solver_can_resume(RAD_SOLVER_SHOOTING, RAD_SOLVER_DIRECT));
    CHECK(rad_solver_can_resume(RAD_SOLVER_IMPORTANCE, RAD_SOLVER_SHOOTING));
    CHECK(rad_solver_can_resume(RAD_SOLVER_GAUSS_SEIDEL, RAD_SOLVER_SHOOTING));
    rad_system *system = load("four-walls");
    rad_solve_options zeroed = {0}, shooting = {.solver = RAD_SOLVER_SHOOTING};
    rad_solve_report a = {0}, b = {0};
    CHECK(rad_solve(system, &zeroed, &a) == RAD_OK);
    double floor_zeroed = radiosity_of(system, "floor");
    CHECK(rad_solve(system, &shooting, &b) == RAD_OK);
    CHECK(a.iterations == b.iterations && a.iterations > 1);
    CHECK(floor_zeroed == radiosity_of(system, "floor"));
    rad_system_destroy(system);
    CHECK(rad_ff_method_count() >= 4);
    for (size_t i = 0; i < rad_ff_method_count(); ++i) {
        const rad_ff_method_info *info = rad_ff_method_at(i);
        CHECK(info && rad_ff_method_parse(info->name) == (int)i + 1);
        CHECK(strcmp(rad_ff_method_name((rad_ff_method)(i + 1)), info->name) == 0);
    }
    CHECK(rad_ff_method_parse("default") == RAD_FF_DEFAULT && rad_ff_method_parse("x") == -1);
}

/* The version macros agree with the library; the error callback sees each error as it is
 * recorded, with the message rad_context_error gives. */
typedef struct seen_errors {
    int count;
    rad_status status;
    char message[256];
} seen_errors;

static void on_error(void *user, rad_status status, const char *message) {
    seen_errors *seen = user;
    seen->count++;
    seen->status = status;
    snprintf(seen->message, sizeof seen->message, "%s", message);
}

static void test_version_and_error_callback(void) {
    char text[32];
    snprintf(text, sizeof text, "%d.%d.%d", RAD_VERSION_MAJOR, RAD_VERSION_MINOR, RAD_VERSION_PATCH);
    CHECK(strcmp(text, rad_version()) == 0);
    CHECK(RAD_VERSION_NUMBER == RAD_VERSION_MAJOR * 10000 + RAD_VERSION_MINOR * 100 + RAD_VERSION_PATCH);
    seen_errors seen = {0};
    rad_context_options options = {.on_error = on_error, .error_user = &seen};
    rad_context *context = NULL;
    CHECK(rad_context_create(&options, &context) == RAD_OK);
    rad_scene *scene = NULL;
    CHECK(rad_scene_builtin(context, "no-such-scene", &scene) != RAD_OK);
    CHECK(seen.count == 1 && seen.status != RAD_OK);
    CHECK(strcmp(seen.message, rad_context_error(context)) == 0 && seen.message[0]);
    rad_context_destroy(context);
    /* threads is bounded in the library, not only in the CLI; the callback gets the reason */
    seen_errors bad = {0};
    rad_context_options too_many = {.threads = RAD_MAX_THREADS + 1, .on_error = on_error,
                                    .error_user = &bad};
    context = NULL;
    CHECK(rad_context_create(&too_many, &context) == RAD_ERROR_INVALID_ARGUMENT && !context);
    CHECK(bad.count == 1 && strstr(bad.message, "4097") && strstr(bad.message, "4096"));
    too_many.threads = -1;
    CHECK(rad_context_create(&too_many, &context) == RAD_ERROR_INVALID_ARGUMENT && !context);
    too_many.threads = RAD_MAX_THREADS;
    CHECK(rad_context_create(&too_many, &context) == RAD_OK && context);
    rad_context_destroy(context);
}

/* The reference solution and the error measure of the solver comparison. */
static void test_reference_error(void) {
    rad_system *system = load("four-walls");
    size_t n = rad_system_element_count(system);
    double *reference = calloc(3 * n, sizeof *reference), *weights = calloc(n, sizeof *weights);
    rad_solver_kind used = RAD_SOLVER_DEFAULT;
    double tolerance = 0;
    CHECK(rad_system_solve_reference(system, reference, &used, &tolerance) == RAD_OK);
    CHECK(used == RAD_SOLVER_GAUSS_SEIDEL && tolerance == 1e-10);
    CHECK(rad_system_solution_error(system, reference, NULL) == 0);
    CHECK(isnan(rad_system_solution_error(system, reference, weights))); /* sees nothing */
    rad_system_reset(system); /* B = E: the light of one bounce and more is missing */
    double error = rad_system_solution_error(system, reference, NULL);
    CHECK(error > 0.05 && error < 1);
    for (size_t e = 0; e < n; ++e) weights[e] = rad_system_element_area(system, e);
    CHECK(rad_system_solution_error(system, reference, weights) == error);
    free(reference);
    free(weights);
    rad_system_destroy(system);
}

/* core/team.h: every index runs once, on a worker in range, whatever the thread count; a loop
 * started from inside a loop runs on its caller alone; the team stops with its context. */
typedef struct {
    rad_context *context;
    int threads, nested;
    _Atomic int runs[1000];
    _Atomic int bad_worker, inner_runs;
} team_job;

static void team_inner(void *user, long index, int worker) {
    team_job *job = user;
    (void)index;
    if (worker != 0) atomic_fetch_add(&job->bad_worker, 1);
    atomic_fetch_add(&job->inner_runs, 1);
}

static void team_task(void *user, long index, int worker) {
    team_job *job = user;
    atomic_fetch_add(&job->runs[index], 1);
    /* A few microseconds each, so the workers wake up and take their share. */
    volatile double work = 0;
    for (int k = 0; k < 2000; ++k) work += k;
    if (worker < 0 || worker >= job->threads) atomic_fetch_add(&job->bad_worker, 1);
    if (job->nested && index % 100 == 0) rad_team_for(job->context, 3, team_inner, job);
}

static void test_team(void) {
    for (int threads = 1; threads <= 4; threads *= 2) {
        rad_context_options options = {.threads = threads};
        rad_context *context;
        CHECK(rad_context_create(&options, &context) == RAD_OK);
        for (int round = 0; round < 20; ++round) {
            static team_job job;
            memset(&job, 0, sizeof job);
            job.context = context;
            job.threads = threads;
            job.nested = round % 2;
            long count = round == 0 ? 1 : 1000;
            rad_team_for(context, count, team_task, &job);
            int once = 1;
            for (long i = 0; i < 1000; ++i) once &= atomic_load(&job.runs[i]) == (i < count);
            CHECK(once);
            CHECK(atomic_load(&job.bad_worker) == 0);
            CHECK(atomic_load(&job.inner_runs) == (job.nested ? 30 : 0));
        }
        rad_context_destroy(context);
    }
}

/* A context's first loop has its worker too: the worker started by that loop once took the
 * loop as one it had seen and slept through it, so a small system's rows computed in one loop
 * (shooting.c) ran on one thread. Each task waits (up to 2 s) until both threads have begun
 * one; with the worker asleep the first task waits out the 2 s and the check fails. */
typedef struct {
    _Atomic int began[2];
} first_loop_job;

static void first_loop_task(void *user, long index, int worker) {
    first_loop_job *job = user;
    (void)index;
    if (worker == 0 || worker == 1) atomic_store(&job->began[worker], 1);
    double start = rad_seconds();
    while (!(atomic_load(&job->began[0]) && atomic_load(&job->began[1])) &&
           rad_seconds() - start < 2)
        ;
}

static void test_team_first_loop(void) {
    rad_context_options options = {.threads = 2};
    rad_context *context;
    CHECK(rad_context_create(&options, &context) == RAD_OK);
    static first_loop_job job;
    rad_team_for(context, 4, first_loop_task, &job);
    printf("team: the first loop's tasks ran on the caller %s and on the worker %s\n",
           atomic_load(&job.began[0]) ? "yes" : "no", atomic_load(&job.began[1]) ? "yes" : "no");
    CHECK(atomic_load(&job.began[1]));
    rad_context_destroy(context);
}

int main(void) {
    CHECK(rad_context_create(NULL, &ctx) == RAD_OK);
    test_team_first_loop();
    test_team();
    test_jacobi_rounds();
    test_shooting_shots();
    test_solvers_agree("four-walls");
    test_two_squares_exact();
    test_enclosure();
    test_surface_sums();
    test_colour();
    test_memory_budget();
    test_registries();
    test_version_and_error_callback();
    test_reference_error();
    rad_context_destroy(ctx);
    return test_finish();
}
