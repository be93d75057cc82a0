/* test_alloc_faults.c - every allocation failure comes back as an error, never a crash or a
 * leak. Each scenario runs once to count its allocations, then once for every N with the Nth
 * allocation failing (through rad_context_options.allocator, as SQLite tests its malloc
 * failures). Each run must return RAD_ERROR_NO_MEMORY with a message, or, where the library
 * can do without the memory (a cache that stops growing), succeed with exactly the result of
 * the clean run; and after destroying everything no block may be left (counted here; ASan
 * checks the rest in test-sanitize).
 *
 * RAD_TEST_QUICK=1 (test-sanitize) fails every Nth allocation for N in a stride over the
 * larger scenarios instead of every one.
 *
 * Kept short (tidy12; it was the longest test of the suite, 61 s wall and 39 s of processor
 * on a loaded machine, now about 3 s), testing the same allocations:
 *   - scenes/room.obj is imported once: assimp fills a 16 MB read buffer on every import, which
 *     made each of the room's 465 failure runs cost a page-faulting memset. The import has its
 *     own scenario (its 30 allocations, each failed); the others build on the imported scene.
 *   - the room traces 20,000 specular photons instead of the default million: the same
 *     allocation sites, five blocks of photons instead of 245 (each block's list is allocated
 *     once either way; 465 allocations became 30 + 196);
 *   - both specular passes run on the room (a mirror and glass, 51 elements) instead of
 *     cornell-mirror, whose glass sphere meshes into 1,277 elements and 177 shots of analytic
 *     rows per run: the passes' allocations are the same, 229 failure points;
 *   - the files go to a directory in memory (/dev/shm when there is one): the library syncs
 *     every file it writes, and on a disk the syncs made the file scenario wait. */
#include "radiosity.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- a counting allocator that can fail the Nth request ---------------------------------- */

typedef struct fault_allocator {
    long requests;  /* allocate and reallocate calls so far */
    long fail_at;   /* the request that fails (1-based); 0: none */
    long live;      /* blocks allocated and not released */
    int failed;     /* the failing request happened */
} fault_allocator;

static void *fault_allocate(void *user, size_t size) {
    fault_allocator *a = user;
    long n = __atomic_add_fetch(&a->requests, 1, __ATOMIC_SEQ_CST);
    if (n == a->fail_at) {
        a->failed = 1;
        return NULL;
    }
    void *pointer = malloc(size);
    if (pointer) __atomic_add_fetch(&a->live, 1, __ATOMIC_SEQ_CST);
    return pointer;
}

static void *fault_reallocate(void *user, void *pointer, size_t size) {
    fault_allocator *a = user;
    long n = __atomic_add_fetch(&a->requests, 1, __ATOMIC_SEQ_CST);
    if (n == a->fail_at) {
        a->failed = 1;
        return NULL;
    }
    void *grown = realloc(pointer, size);
    if (grown && !pointer) __atomic_add_fetch(&a->live, 1, __ATOMIC_SEQ_CST);
    return grown;
}

static void fault_release(void *user, void *pointer) {
    fault_allocator *a = user;
    if (pointer) __atomic_sub_fetch(&a->live, 1, __ATOMIC_SEQ_CST);
    free(pointer);
}

/* ---- scenarios: each does its work on a fresh context and cleans up ------------------------ */

/* A scenario does its work on a fresh context, cleans up, and leaves a fingerprint of its
 * results (a sum of radiosities) in *result. */
typedef rad_status (*scenario_fn)(rad_context *ctx, const void *arg, double *result);

static rad_status solve_all(rad_system *system, int trace, double *result);

/* Adds every surface's radiosity to *result: a scenario's fingerprint. */
static void add_radiosities(const rad_system *system, double *result) {
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info info;
        rad_system_surface(system, i, &info);
        *result += info.radiosity[0] + info.radiosity[1] + info.radiosity[2];
    }
}

/* Where the scenarios write their files: under /dev/shm when it is a writable directory (the
 * library syncs every file it writes), else /tmp. */
static char work_directory[64];

static void ignore_trace(void *user, const rad_trace_event *event) {
    (void)user;
    (void)event;
}

/* A scene (built-in name or file) through its system and every solver. */
typedef struct scene_job {
    const char *name; /* built-in name, or a path when `file` */
    int file;
    rad_mesh_options mesh;
    rad_ff_method method;
    int solve;        /* 0: stop after the system is built */
    int hierarchical; /* also the hierarchical solver */
} scene_job;

static rad_status run_scene(rad_context *ctx, const void *arg, double *result) {
    const scene_job *job = arg;
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_status status = job->file ? rad_scene_load(ctx, job->name, &scene)
                                  : rad_scene_builtin(ctx, job->name, &scene);
    rad_ff_options ff = {job->method, 0, 0, NULL};
    if (!status) status = rad_system_create(ctx, scene, &job->mesh, &ff, &system);
    rad_scene_destroy(scene); /* the system keeps what it needs */
    if (!status && job->solve) status = solve_all(system, 1, result);
    if (!status && job->hierarchical) {
        rad_solve_options options = {0};
        options.solver = RAD_SOLVER_HIERARCHICAL;
        options.link_error = 1e-2;
        options.max_iterations = 1;
        status = rad_solve(system, &options, NULL);
        /* Saved, loaded back (the hierarchy rebuilt from its file) and gone on from. */
        char path[128];
        snprintf(path, sizeof path, "%s/hierarchy.sol", work_directory);
        if (!status) status = rad_system_save_solution(system, path, NULL);
        if (!status) status = rad_system_load_solution(system, path, NULL);
        remove(path);
        options.max_iterations = 0;
        options.resume = 1;
        if (!status) status = rad_solve(system, &options, NULL);
        if (!status) add_radiosities(system, result);
    }
    if (!status) {
        size_t n = rad_system_surface_count(system);
        double *matrix = calloc(n * n, sizeof *matrix);
        if (matrix) status = rad_system_surface_form_factors(system, matrix);
        for (size_t i = 0; matrix && !status && i < n * n; ++i) *result += matrix[i];
        free(matrix);
    }
    rad_system_destroy(system);
    return status;
}

static rad_status solve_all(rad_system *system, int trace, double *result) {
    static const rad_solver_kind kinds[] = {RAD_SOLVER_DIRECT, RAD_SOLVER_JACOBI,
                                            RAD_SOLVER_GAUSS_SEIDEL, RAD_SOLVER_SHOOTING};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
        for (int traced = 0; traced <= trace; ++traced) {
            rad_solve_options options = {0};
            options.solver = kinds[k];
            options.max_iterations = 3;
            if (traced) options.trace = ignore_trace;
            rad_status status = rad_solve(system, &options, NULL);
            if (status) return status;
            add_radiosities(system, result);
        }
    }
    return RAD_OK;
}

/* scenes/room.obj, imported once (the import's own failures are run_import's): its mirror and
 * glass ask for the specular passes, with 20,000 photons (five blocks). The scenarios below
 * build their systems from it in their own contexts; a scene is read only by them. */
static rad_scene *room_scene;

/* The import alone: assimp and the importer, every allocation failure. */
static rad_status run_import(rad_context *ctx, const void *arg, double *result) {
    (void)arg;
    rad_scene *scene = NULL;
    rad_status status = rad_scene_load(ctx, RAD_SOURCE_DIR "/scenes/room.obj", &scene);
    if (!status) status = rad_scene_set_specular_first(scene, -1, 20000);
    *result = scene ? (double)rad_scene_file_count(scene) + rad_scene_is_geometric(scene) : -1;
    rad_scene_destroy(scene);
    return status;
}

/* room.obj's mirror and glass with both specular passes (docs/specular-first.md): photons through the mirror
 * and the glass before the solve, and the solved light through them after it, then the solve
 * resumed. Few photons and elements keep each run short. */
static rad_status run_mirror(rad_context *ctx, const void *arg, double *result) {
    (void)arg;
    rad_system *system = NULL;
    rad_status status = RAD_OK;
    rad_mesh_options mesh = {0, 0, 60, 0, 0};
    rad_ff_options ff = {RAD_FF_DEFAULT, 0, 0, NULL};
    if (!status) status = rad_system_create(ctx, room_scene, &mesh, &ff, &system);
    rad_solve_options options = {0};
    options.solver = RAD_SOLVER_SHOOTING;
    options.tolerance = 1e-2;
    if (!status) status = rad_solve(system, &options, NULL);
    if (!status) add_radiosities(system, result);
    rad_system_destroy(system);
    return status;
}

static rad_status run_parse(rad_context *ctx, const void *arg, double *result) {
    const char *text = arg;
    rad_scene *scene = NULL;
    rad_status status = rad_scene_parse_ffm(ctx, text, strlen(text), "test.ffm", &scene);
    *result = scene ? rad_scene_is_geometric(scene) : -1;
    rad_scene_destroy(scene);
    return status;
}

static rad_status run_dense(rad_context *ctx, const void *arg, double *result) {
    (void)arg;
    const rad_patch_desc patches[3] = {
        {"light", 1, {0.2, 0.2, 0.2}, {1, 1, 1}},
        {"floor", 2, {0.5, 0.6, 0.7}, {0, 0, 0}},
        {"wall", 1.5, {0.8, 0.1, 0.3}, {0, 0, 0}},
    };
    const float form_factors[9] = {0, 0.5f, 0.3f, 0.25f, 0, 0.4f, 0.2f, 0.5f, 0};
    rad_system *system = NULL;
    rad_status status = rad_system_create_dense(ctx, patches, 3, form_factors, &system);
    if (!status) status = solve_all(system, 1, result);
    rad_system_destroy(system);
    return status;
}

/* Adds every pixel of an image to *result. */
static void add_pixels(const rad_image *image, double *result) {
    size_t count = (size_t)rad_image_width(image) * (size_t)rad_image_height(image) * 3;
    const float *pixels = rad_image_pixels(image);
    for (size_t i = 0; i < count; ++i) *result += pixels[i];
}

/* The Cornell box, coarse: a shooting solve, then `what` of the outputs. */
enum { OUT_RENDER, OUT_PATHTRACE, OUT_FILES, OUT_IMPORT };

static rad_status run_outputs(rad_context *ctx, const void *arg, double *result) {
    int what = *(const int *)arg;
    char path[128];
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_image *image = NULL, *read_back = NULL, *error_map = NULL;
    rad_status status;
    if (what == OUT_IMPORT) status = RAD_OK; /* room_scene, imported once */
    else status = rad_scene_builtin(ctx, "cornell", &scene);
    rad_mesh_options mesh = {0, 0, 60, 0, 0};
    rad_ff_options ff = {RAD_FF_DEFAULT, 0, 0, NULL};
    if (!status && what != OUT_PATHTRACE)
        status = rad_system_create(ctx, scene ? scene : room_scene, &mesh, &ff, &system);
    if (!status && system) {
        rad_solve_options solve = {0};
        solve.solver = RAD_SOLVER_SHOOTING;
        solve.max_iterations = 5;
        status = rad_solve(system, &solve, NULL);
    }
    if (!status && what == OUT_RENDER) {
        rad_render_options render = {0};
        render.width = 6;
        render.height = 5;
        render.samples_per_pixel = 1;
        render.final_gather = 2;
        status = rad_render(scene, system, &render, &image);
    }
    if (!status && what == OUT_PATHTRACE) {
        rad_pathtrace_options trace = {0};
        trace.width = 6;
        trace.height = 5;
        trace.samples_per_pixel = 2;
        status = rad_pathtrace(ctx, scene, &trace, &image, NULL);
    }
    if (!status && image) add_pixels(image, result);
    if (!status && what == OUT_FILES) {
        /* Every file the library writes, and reads back. */
        static const char *const names[] = {"out.ply", "out.glb", "out.gltf", "out.obj"};
        for (size_t i = 0; i < 4 && !status; ++i) {
            snprintf(path, sizeof path, "%s/%s", work_directory, names[i]);
            status = rad_bake(system, path, NULL);
        }
        snprintf(path, sizeof path, "%s/scene.obj", work_directory);
        if (!status) status = rad_scene_export_obj(ctx, scene, path);
        snprintf(path, sizeof path, "%s/out.sol", work_directory);
        if (!status) status = rad_system_save_solution(system, path, NULL);
        if (!status) status = rad_system_load_solution(system, path, NULL);
        rad_render_options render = {0};
        render.width = 4;
        render.height = 3;
        render.samples_per_pixel = 1;
        if (!status) status = rad_render(scene, system, &render, &image);
        static const char *const images[] = {"out.png", "out.hdr", "out.pfm"};
        for (size_t i = 0; i < 3 && !status; ++i) {
            snprintf(path, sizeof path, "%s/%s", work_directory, images[i]);
            status = rad_image_save(image, path, NULL);
        }
        if (!status) status = rad_image_read(ctx, path, &read_back);
        rad_image_comparison comparison;
        if (!status) status = rad_image_compare(ctx, read_back, image, &comparison);
        double scale = 0;
        if (!status) status = rad_image_error_map(ctx, read_back, image, &scale, &error_map);
        if (!status) {
            add_pixels(read_back, result);
            add_pixels(error_map, result);
            *result += comparison.rmse;
        }
    }
    if (!status && system) {
        add_radiosities(system, result);
    }
    rad_image_destroy(image);
    rad_image_destroy(read_back);
    rad_image_destroy(error_map);
    rad_system_destroy(system);
    rad_scene_destroy(scene);
    return status;
}

/* A generated office of about 2,500 triangles (1,136 polygons) on two threads: the contact
 * cut's parallel chunks (two of 1,024 polygons), the meshing and one hierarchical refinement,
 * with allocations failing on worker threads. Which allocation is the Nth differs between runs
 * on two threads, so each failure point is some allocation near the Nth; each must still come
 * back as an error with a message, or make no difference, and leak nothing. */
static rad_status run_parallel(rad_context *ctx, const void *arg, double *result) {
    (void)arg;
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_status status = rad_scene_generate_office(ctx, 2500, &scene);
    rad_mesh_options mesh = {0};
    rad_ff_options ff = {RAD_FF_DEFAULT, 0, 0, NULL};
    if (!status) status = rad_system_create(ctx, scene, &mesh, &ff, &system);
    rad_scene_destroy(scene);
    rad_solve_options options = {0};
    options.solver = RAD_SOLVER_HIERARCHICAL;
    options.link_error = 1e-2;
    options.max_iterations = 1;
    if (!status) status = rad_solve(system, &options, NULL);
    if (!status) add_radiosities(system, result);
    rad_system_destroy(system);
    return status;
}

/* ---- the driver ----------------------------------------------------------------------------- */

/* The worker threads of the scenarios' contexts: 1, so that the Nth allocation is the same one
 * every run, except for the scenario of failures inside parallel chunks. */
static int scenario_threads = 1;

/* Runs the scenario on a context using `a`; returns the status (context creation included). */
static rad_status run_once(fault_allocator *a, scenario_fn scenario, const void *arg,
                           double *result, char *message, size_t message_size) {
    rad_context_options options = {0};
    options.allocator.allocate = fault_allocate;
    options.allocator.reallocate = fault_reallocate;
    options.allocator.release = fault_release;
    options.allocator.user = a;
    options.threads = scenario_threads;
    rad_context *ctx = NULL;
    rad_status status = rad_context_create(&options, &ctx);
    message[0] = '\0';
    *result = 0;
    if (!status) {
        status = scenario(ctx, arg, result);
        snprintf(message, message_size, "%s", rad_context_error(ctx));
        rad_context_destroy(ctx);
    }
    return status;
}

static int quick(void) {
    const char *value = getenv("RAD_TEST_QUICK");
    return value && *value && strcmp(value, "0") != 0;
}

/* Fails each allocation of the scenario in turn (every `quick_stride`-th in quick mode; when
 * `quick_stride` is negative, about -quick_stride allocations spread evenly, always; always the
 * first and the last). Returns the number of allocations of a clean run. */
static long check_scenario(const char *label, scenario_fn scenario, const void *arg,
                           long quick_stride) {
    char message[1024];
    fault_allocator clean = {0};
    double clean_result, result;
    rad_status status = run_once(&clean, scenario, arg, &clean_result, message, sizeof message);
    if (status) {
        fprintf(stderr, "%s: the clean run failed: %s (%s)\n", label, rad_status_name(status),
                message);
        CHECK(status == RAD_OK);
        return 0;
    }
    CHECK(clean.live == 0);
    long total = clean.requests;
    long stride = quick() && quick_stride > 1 ? quick_stride : 1;
    if (quick_stride < 0) stride = total / -quick_stride > 1 ? total / -quick_stride : 1;
    int bad_status = 0, leaks = 0, silent = 0, tried = 0;
    for (long step = 1; step <= total + stride - 1; step += stride) {
        long n = step <= total ? step : total; /* the last allocation always */
        if (step > total && (total - 1) % stride == 0) break;
        fault_allocator a = {0};
        a.fail_at = n;
        status = run_once(&a, scenario, arg, &result, message, sizeof message);
        ++tried;
        /* The failure must be reported as what it is, with a message, or make no difference;
         * and nothing may be kept. */
        int harmless = status == RAD_OK && result == clean_result;
        if (a.failed && status != RAD_ERROR_NO_MEMORY && !harmless) {
            if (bad_status++ < 5)
                fprintf(stderr, "%s: allocation %ld of %ld failed, but the call returned '%s' "
                                "(%s)\n", label, n, total, rad_status_name(status), message);
        }
        if (a.failed && n > 1 && status == RAD_ERROR_NO_MEMORY && !message[0]) {
            if (silent++ < 5)
                fprintf(stderr, "%s: allocation %ld of %ld failed without a message\n", label,
                        n, total);
        }
        if (a.live != 0) {
            if (leaks++ < 5)
                fprintf(stderr, "%s: allocation %ld of %ld failed and %ld blocks leaked\n",
                        label, n, total, a.live);
        }
    }
    CHECK(bad_status == 0);
    CHECK(leaks == 0);
    CHECK(silent == 0);
    fprintf(stderr, "%s: %ld allocations, %d failure points tried\n", label, total, tried);
    return total;
}

int main(void) {
    static const char ffm[] =
        "patch light area 1 reflectance 0.2 emission 1\n"
        "patch floor area 2 reflectance 0.5 0.6 0.7\n"
        "patch wall area 1.5 reflectance 0.8 0.1 0.3\n"
        "ff light floor 0.5\nff light wall 0.3\nff floor light 0.25\nff floor wall 0.4\n"
        "ff wall light 0.2\nff wall floor 0.5\n";
    /* Many patches: the parser's tables grow several times. */
    static char many[64 * 80];
    size_t used = 0;
    for (int i = 0; i < 40; ++i)
        used += (size_t)snprintf(many + used, sizeof many - used,
                                 "patch p%d area 1 reflectance 0.5 emission %d\n", i, i % 2);
    for (int i = 0; i < 20; ++i)
        used += (size_t)snprintf(many + used, sizeof many - used, "ff p%d p%d 0.25\n", i, 39 - i);

    check_scenario("parse .ffm", run_parse, ffm, 1);
    check_scenario("parse a larger .ffm", run_parse, many, 1);
    check_scenario("dense system, every solver", run_dense, NULL, 1);

    snprintf(work_directory, sizeof work_directory, "%s/rad-alloc-faults-XXXXXX",
             access("/dev/shm", W_OK | X_OK) == 0 ? "/dev/shm" : "/tmp");
    CHECK(mkdtemp(work_directory) != NULL);

    scene_job four_walls = {"four-walls", 0, {0, 0, 0, 0, 0}, RAD_FF_DEFAULT, 1, 0};
    check_scenario("four-walls, every solver", run_scene, &four_walls, 1);
    scene_job file = {RAD_SOURCE_DIR "/scenes/four-walls.ffm", 1, {0, 0, 0, 0, 0}, RAD_FF_DEFAULT, 0, 0};
    check_scenario("four-walls.ffm from its file", run_scene, &file, 1);

    /* A small geometric scene: meshing, Embree, form factors, every solver. */
    scene_job cube = {"unit-cube", 0, {0, 0, 24, 0, 0}, RAD_FF_ANALYTIC, 1, 0};
    check_scenario("unit-cube, 24 elements, every solver", run_scene, &cube, 7);
    scene_job hierarchy = {"unit-cube", 0, {0, 0, 24, 0, 0}, RAD_FF_ANALYTIC, 0, 1};
    check_scenario("unit-cube, hierarchical", run_scene, &hierarchy, 3);
    /* room.obj, imported once for the scenarios that start from it. */
    rad_context *plain = NULL;
    CHECK(rad_context_create(NULL, &plain) == RAD_OK);
    CHECK(rad_scene_load(plain, RAD_SOURCE_DIR "/scenes/room.obj", &room_scene) == RAD_OK);
    CHECK(rad_scene_set_specular_first(room_scene, -1, 20000) == RAD_OK);
    check_scenario("room.obj imported", run_import, NULL, 5);
    check_scenario("room.obj, both specular passes, shooting", run_mirror, NULL, 5);
    static const rad_ff_method methods[] = {RAD_FF_HEMICUBE, RAD_FF_RAYCAST, RAD_FF_MONTECARLO};
    static const char *const method_labels[] = {"unit-cube, hemicube form factors",
                                                "unit-cube, ray-cast form factors",
                                                "unit-cube, Monte Carlo form factors"};
    for (int m = 0; m < 3; ++m) {
        scene_job job = {"unit-cube", 0, {0, 0, 24, 0, 0}, methods[m], 1, 0};
        check_scenario(method_labels[m], run_scene, &job, 7);
    }

    /* The outputs: render, path trace, every file written and read back, an imported scene. */
    static const int render = OUT_RENDER, pathtrace = OUT_PATHTRACE, files = OUT_FILES,
                     import = OUT_IMPORT;
    check_scenario("cornell, render with final gather", run_outputs, &render, 5);
    check_scenario("cornell, path trace", run_outputs, &pathtrace, 5);
    check_scenario("cornell, bake, export, solution, images written and read", run_outputs,
                   &files, 11);
    check_scenario("room.obj solved", run_outputs, &import, 5);
    rad_scene_destroy(room_scene);
    rad_context_destroy(plain);

    scenario_threads = 2;
    check_scenario("office 2500 on two threads, contacts and hierarchy", run_parallel, NULL,
                   quick() ? -15 : -30);
    scenario_threads = 1;
    char command[128];
    snprintf(command, sizeof command, "rm -rf '%s'", work_directory);
    CHECK(system(command) == 0);
    return test_finish();
}
