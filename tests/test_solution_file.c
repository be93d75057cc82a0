/* test_solution_file.c - saving and resuming solutions: the round trip is exact, N shots + save
 * + load into a new system + M shots equals N + M shots bit for bit, and damaged files or files
 * of another scene, mesh or form factors are refused with one line, leaving the system as it
 * was. */
#include "radiosity.h"
#include "test.h"

#include "io/solution.h"
#include "system/system.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static rad_context *ctx;
static char dir[] = "/tmp/radiosity-solution-XXXXXX";

static rad_system *build(const char *name, size_t elements, rad_ff_method method) {
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_mesh_options mesh = {0};
    mesh.elements = elements;
    rad_ff_options ff = {0};
    ff.method = method;
    CHECK(rad_scene_builtin(ctx, name, &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, &mesh, &ff, &system) == RAD_OK);
    rad_scene_destroy(scene);
    return system;
}

static char *path_of(const char *name) {
    static char path[8][128];
    static int next;
    char *p = path[next++ % 8];
    snprintf(p, sizeof path[0], "%s/%s", dir, name);
    return p;
}

static int same(const rad_system *a, const rad_system *b) {
    size_t bytes = 3 * a->element_count * sizeof(double);
    return a->element_count == b->element_count && memcmp(a->radiosity, b->radiosity, bytes) == 0 &&
           memcmp(a->unshot, b->unshot, bytes) == 0 &&
           memcmp(a->ambient, b->ambient, sizeof a->ambient) == 0;
}

static unsigned char *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    unsigned char *bytes = malloc(1 << 24);
    *size = fread(bytes, 1, 1 << 24, f);
    fclose(f);
    return bytes;
}

static void write_file(const char *path, const unsigned char *bytes, size_t size) {
    FILE *f = fopen(path, "wb");
    fwrite(bytes, 1, size, f);
    fclose(f);
}

static void test_round_trip_and_resume(void) {
    /* Straight: 60 shots. */
    rad_system *straight = build("cornell", 300, RAD_FF_DEFAULT);
    rad_solve_options o = {.solver = RAD_SOLVER_SHOOTING, .overshoot = 1, .ambient = 1,
                           .max_iterations = 60};
    CHECK(rad_solve(straight, &o, NULL) == RAD_OK);

    /* Stopped after 25, saved, loaded into a new system, 35 more. */
    rad_system *first = build("cornell", 300, RAD_FF_DEFAULT);
    o.max_iterations = 25;
    CHECK(rad_solve(first, &o, NULL) == RAD_OK);
    rad_solution_info info = {RAD_SOLVER_SHOOTING, 25};
    const char *path = path_of("cornell.sol");
    CHECK(rad_system_save_solution(first, path, &info) == RAD_OK);
    struct stat st;
    CHECK(stat(path, &st) == 0 &&
          (size_t)st.st_size == RAD_SOLUTION_HEADER_SIZE + 48 * first->element_count + 8);

    rad_system *second = build("cornell", 300, RAD_FF_DEFAULT);
    rad_solution_info loaded = {0};
    CHECK(rad_system_load_solution(second, path, &loaded) == RAD_OK);
    CHECK(loaded.solver == RAD_SOLVER_SHOOTING && loaded.steps == 25);
    CHECK(same(first, second)); /* the round trip is exact */
    o.max_iterations = 35;
    o.resume = 1;
    CHECK(rad_solve(second, &o, NULL) == RAD_OK);
    CHECK(same(straight, second)); /* as if it never stopped */

    /* The same for the importance solver: importance is recomputed the same way. */
    rad_camera_desc camera = {{186, 200, -100}, {186, 80, 170}, {0, 1, 0}, 30};
    o = (rad_solve_options){.solver = RAD_SOLVER_IMPORTANCE, .camera = &camera, .view_width = 64,
                            .view_height = 64, .max_iterations = 50};
    CHECK(rad_solve(straight, &o, NULL) == RAD_OK);
    o.max_iterations = 20;
    CHECK(rad_solve(first, &o, NULL) == RAD_OK);
    CHECK(rad_system_save_solution(first, path, NULL) == RAD_OK);
    CHECK(rad_system_load_solution(second, path, &loaded) == RAD_OK);
    CHECK(loaded.steps == 0);
    o.max_iterations = 30;
    o.resume = 1;
    CHECK(rad_solve(second, &o, NULL) == RAD_OK);
    CHECK(same(straight, second));
    rad_system_destroy(straight);
    rad_system_destroy(first);
    rad_system_destroy(second);

    /* A patch system too. */
    rad_system *walls = build("four-walls", 0, RAD_FF_DEFAULT);
    o = (rad_solve_options){.solver = RAD_SOLVER_SHOOTING, .max_iterations = 2};
    CHECK(rad_solve(walls, &o, NULL) == RAD_OK);
    CHECK(rad_system_save_solution(walls, path_of("walls.sol"), NULL) == RAD_OK);
    rad_system *again = build("four-walls", 0, RAD_FF_DEFAULT);
    CHECK(rad_system_load_solution(again, path_of("walls.sol"), NULL) == RAD_OK);
    CHECK(same(walls, again));
    rad_system_destroy(walls);
    rad_system_destroy(again);
}

/* A refused load names the problem and leaves the system untouched. */
static void check_refused(rad_system *system, const char *path, rad_status expected,
                          const char *message) {
    double *before = malloc(6 * system->element_count * sizeof *before);
    memcpy(before, system->radiosity, 3 * system->element_count * sizeof *before);
    memcpy(before + 3 * system->element_count, system->unshot,
           3 * system->element_count * sizeof *before);
    rad_status status = rad_system_load_solution(system, path, NULL);
    CHECK(status == expected);
    const char *error = rad_context_error(ctx);
    CHECK(strstr(error, message) != NULL);
    CHECK(strchr(error, '\n') == NULL);
    if (status == RAD_OK || !strstr(error, message)) fprintf(stderr, "  got: %s\n", error);
    CHECK(memcmp(before, system->radiosity, 3 * system->element_count * sizeof *before) == 0);
    CHECK(memcmp(before + 3 * system->element_count, system->unshot,
                 3 * system->element_count * sizeof *before) == 0);
    free(before);
}

static void test_refusals(void) {
    rad_system *system = build("cornell", 300, RAD_FF_DEFAULT);
    rad_solve_options o = {.solver = RAD_SOLVER_SHOOTING, .max_iterations = 10};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    const char *good = path_of("good.sol");
    CHECK(rad_system_save_solution(system, good, NULL) == RAD_OK);
    size_t size = 0;
    unsigned char *bytes = read_file(good, &size);
    CHECK(bytes != NULL);

    rad_system *target = build("cornell", 300, RAD_FF_DEFAULT);
    o.max_iterations = 3;
    CHECK(rad_solve(target, &o, NULL) == RAD_OK);

    const char *bad = path_of("bad.sol");
    write_file(bad, bytes, size - 100);
    check_refused(target, bad, RAD_ERROR_PARSE, "truncated");
    write_file(bad, bytes, 40);
    check_refused(target, bad, RAD_ERROR_PARSE, "truncated");
    bytes[size / 2] ^= 0x10;
    write_file(bad, bytes, size);
    check_refused(target, bad, RAD_ERROR_PARSE, "checksum");
    bytes[size / 2] ^= 0x10;
    write_file(bad, bytes, size + 1);
    check_refused(target, bad, RAD_ERROR_PARSE, "checksum");
    bytes[0] = 'X';
    write_file(bad, bytes, size);
    check_refused(target, bad, RAD_ERROR_PARSE, "not a radiosity solution file");
    bytes[0] = 'R';
    bytes[8] = 7; /* version 7 */
    write_file(bad, bytes, size);
    check_refused(target, bad, RAD_ERROR_UNSUPPORTED, "version 7");
    bytes[8] = 1;
    write_file(bad, bytes, size);
    CHECK(rad_system_load_solution(target, bad, NULL) == RAD_OK); /* intact again */
    /* A negative radiosity with the checksum made to match: refused all the same. */
    {
        unsigned char *forged = malloc(size);
        memcpy(forged, bytes, size);
        double minus_one = -1.0;
        uint64_t raw;
        memcpy(&raw, &minus_one, 8);
        unsigned char *value = forged + RAD_SOLUTION_HEADER_SIZE + 48 * 5 + 8; /* element 5, G */
        for (int k = 0; k < 8; ++k) value[k] = (unsigned char)(raw >> (8 * k));
        uint64_t sum = rad_fnv1a(RAD_FNV1A_START, forged, size - 8);
        for (int k = 0; k < 8; ++k) forged[size - 8 + k] = (unsigned char)(sum >> (8 * k));
        write_file(bad, forged, size);
        check_refused(target, bad, RAD_ERROR_PARSE, "element 5 has a negative radiosity, -1");
        free(forged);
    }
    check_refused(target, path_of("missing.sol"), RAD_ERROR_IO, "cannot read");
    check_refused(target, "/", RAD_ERROR_IO, "/");

    /* Another scene, another mesh, other form factors. */
    rad_system *cube = build("unit-cube", 300, RAD_FF_DEFAULT);
    check_refused(cube, good, RAD_ERROR_INVALID_ARGUMENT, "different scene");
    rad_system *finer = build("cornell", 400, RAD_FF_DEFAULT);
    check_refused(finer, good, RAD_ERROR_INVALID_ARGUMENT, "different mesh");
    rad_system *other_ff = build("cornell", 300, RAD_FF_HEMICUBE);
    check_refused(other_ff, good, RAD_ERROR_INVALID_ARGUMENT, "different form factors");

    /* A path that cannot be written: an error, and nothing left behind. */
    CHECK(rad_system_save_solution(system, "/nonexistent-dir/x.sol", NULL) == RAD_ERROR_IO);
    CHECK(rad_system_save_solution(system, dir, NULL) == RAD_ERROR_IO); /* a directory */
    /* Saving over a good file replaces it whole. */
    CHECK(rad_system_save_solution(target, good, NULL) == RAD_OK);
    CHECK(rad_system_load_solution(system, good, NULL) == RAD_OK);
    CHECK(same(system, target));

    free(bytes);
    rad_system_destroy(system);
    rad_system_destroy(target);
    rad_system_destroy(cube);
    rad_system_destroy(finer);
    rad_system_destroy(other_ff);
}

/* The checksum (the last 8 bytes) made to match the bytes before it. */
static void forge_checksum(unsigned char *bytes, size_t size) {
    rad_le_put_u64(bytes + size - 8, rad_fnv1a(RAD_FNV1A_START, bytes, size - 8));
}

static rad_system *hierarchy_system(int iterations) {
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_mesh_options mesh = {0};
    mesh.polygons_only = 1; /* as the commands build it for the hierarchy */
    CHECK(rad_scene_builtin(ctx, "cornell", &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_OK);
    rad_scene_destroy(scene);
    rad_solve_options o = {.solver = RAD_SOLVER_HIERARCHICAL, .max_iterations = iterations};
    o.link_error = 3e-4;
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    return system;
}

/* A hierarchy's file (version 2) is read as a stream, in two passes: cut short anywhere,
 * damaged, or forged with a matching checksum (found in the first pass or only while the
 * second rebuilds), it is refused in one line with the system as it was; whole, it loads and
 * gives the saved solution back. rad_solution_file_info reads its solver from the header. */
static void test_hierarchy_refusals(void) {
    rad_system *system = hierarchy_system(0);
    const char *good = path_of("hier.sol"), *bad = path_of("bad.sol");
    rad_solution_info saved = {RAD_SOLVER_HIERARCHICAL, 5};
    CHECK(rad_system_save_solution(system, good, &saved) == RAD_OK);
    rad_solution_info info = {0};
    CHECK(rad_solution_file_info(ctx, good, &info) == RAD_OK);
    CHECK(info.solver == RAD_SOLVER_HIERARCHICAL && info.steps == 5);
    CHECK(rad_solution_file_info(NULL, path_of("missing.sol"), &info) == RAD_ERROR_IO);
    size_t size = 0;
    unsigned char *bytes = read_file(good, &size);
    CHECK(bytes != NULL && size > 1000);
    /* Where the sections start (docs/formats.md, "Hierarchy solution files"). */
    uint32_t flags = rad_le_get_u32(bytes + 56);
    uint64_t nodes = rad_le_get_u64(bytes + 64), roots = rad_le_get_u64(bytes + 72),
             splits = rad_le_get_u64(bytes + 80);
    size_t node_bytes = 24 + (flags & 2 ? 28 : 0) + (flags & 1 ? 8 : 0);
    /* Version 3 keeps six exposure pairs (48 bytes) per root. */
    size_t node_at = 160 + 8 * splits, link_at = node_at + nodes * node_bytes + 48 * roots;
    CHECK(splits > 0 && link_at + 8 < size);

    rad_system *target = hierarchy_system(1);
    const size_t cuts[] = {100, 168, node_at + 3, link_at + 13, size - 9, size - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; ++k) {
        write_file(bad, bytes, cuts[k]);
        check_refused(target, bad, RAD_ERROR_PARSE, "truncated solution file");
    }
    write_file(bad, bytes, size + 1);
    check_refused(target, bad, RAD_ERROR_PARSE, "checksum mismatch");
    /* A bit of the first link's factor (its run's 8 bytes, its source's 4, then the factor). */
    bytes[link_at + 13] ^= 0x10;
    write_file(bad, bytes, size);
    check_refused(target, bad, RAD_ERROR_PARSE, "checksum mismatch");
    bytes[link_at + 13] ^= 0x10;
    /* Every link carries a mark (flag 256), and a marked one its sample after it: the first
     * marked link's mark, run after run (a receiver and a count, then the links). */
    CHECK(flags & 256);
    size_t mark_at = 0, at = link_at;
    for (uint64_t run = 0; run < rad_le_get_u64(bytes + 96) && !mark_at && at + 8 < size; ++run) {
        uint32_t count = rad_le_get_u32(bytes + at + 4);
        at += 8;
        for (uint32_t k = 0; k < count && !mark_at && at + 13 < size; ++k) {
            if (bytes[at + 12]) mark_at = at + 12;
            at += 13 + (bytes[at + 12] ? 24 : 0);
        }
    }
    CHECK(mark_at > 0);
    /* Forged, the checksum made to match: a negative radiosity and a link to no receiver are
     * found by the first pass, a split of a node that does not exist only by the rebuild. */
    const struct {
        size_t at;
        uint32_t value;
        const char *message;
    } forgeries[] = {{node_at + 4, 0xbff00000u, "a negative radiosity"},
                     {link_at, 0xfffffff0u, "a link's receiver"},
                     {160, (uint32_t)nodes + 7, "the refinement tree"},
                     {link_at + 20, (rad_le_get_u32(bytes + link_at + 20) & ~0xffu) | 2u, "a link"},
                     {mark_at + 1, (uint32_t)roots, "a link's sample"}};
    for (size_t k = 0; k < sizeof forgeries / sizeof forgeries[0]; ++k) {
        unsigned char *forged = malloc(size);
        memcpy(forged, bytes, size);
        rad_le_put_u32(forged + forgeries[k].at, forgeries[k].value);
        forge_checksum(forged, size);
        write_file(bad, forged, size);
        check_refused(target, bad, RAD_ERROR_PARSE, forgeries[k].message);
        free(forged);
    }
    /* Whole: the saved solution back, surface by surface. */
    CHECK(rad_system_load_solution(target, good, &info) == RAD_OK);
    CHECK(info.solver == RAD_SOLVER_HIERARCHICAL && info.steps == 5);
    for (size_t i = 0; i < rad_system_surface_count(system); ++i) {
        rad_surface_info a, b;
        rad_system_surface(system, i, &a);
        rad_system_surface(target, i, &b);
        CHECK(memcmp(a.radiosity, b.radiosity, sizeof a.radiosity) == 0);
    }
    free(bytes);
    unlink(good);
    rad_system_destroy(system);
    rad_system_destroy(target);
}

/* A hierarchy file written before the links kept their samples (no flag 256): `bytes` without
 * the links' marks and samples, the flag cleared, the checksum made again. */
static unsigned char *without_samples(const unsigned char *bytes, size_t size, size_t *out_size) {
    uint32_t flags = rad_le_get_u32(bytes + 56);
    uint64_t nodes = rad_le_get_u64(bytes + 64), roots = rad_le_get_u64(bytes + 72),
             splits = rad_le_get_u64(bytes + 80), runs = rad_le_get_u64(bytes + 96);
    size_t node_bytes = 24 + (flags & 2 ? 28 : 0) + (flags & 1 ? 8 : 0);
    size_t link_at = 160 + 8 * splits + nodes * node_bytes + 48 * roots;
    unsigned char *old = malloc(size);
    memcpy(old, bytes, link_at);
    rad_le_put_u32(old + 56, flags & ~256u);
    size_t at = link_at, put = link_at;
    for (uint64_t run = 0; run < runs; ++run) {
        uint32_t count = rad_le_get_u32(bytes + at + 4);
        memcpy(old + put, bytes + at, 8);
        at += 8;
        put += 8;
        for (uint32_t k = 0; k < count; ++k) {
            memcpy(old + put, bytes + at, 12);
            put += 12;
            at += 13 + (bytes[at + 12] ? 24 : 0);
        }
    }
    memcpy(old + put, bytes + at, size - at); /* the tail and the checksum's place */
    *out_size = put + (size - at);
    forge_checksum(old, *out_size);
    return old;
}

/* A generated office of 2,000 triangles solved by `steps` hierarchical steps: its cluster links
 * keep samples that matter (the Cornell box's gather reads none that a change of its weights
 * would show). */
static rad_system *office_system(int steps) {
    rad_scene *scene = NULL;
    rad_system *system = NULL;
    rad_mesh_options mesh = {0};
    mesh.polygons_only = 1;
    CHECK(rad_scene_generate_office(ctx, 2000, &scene) == RAD_OK);
    CHECK(rad_system_create(ctx, scene, &mesh, NULL, &system) == RAD_OK);
    rad_scene_destroy(scene);
    rad_solve_options o = {.solver = RAD_SOLVER_HIERARCHICAL, .max_iterations = steps};
    CHECK(rad_solve(system, &o, NULL) == RAD_OK);
    return system;
}

/* Such a file still loads (the cluster links' samples drawn again from their own rays) and
 * goes on exactly as the same solution saved with its samples. */
static void test_hierarchy_without_samples(void) {
    rad_system *system = office_system(1); /* one step: the rest is left to do */
    const char *with = path_of("good.sol"), *without = path_of("bad.sol");
    CHECK(rad_system_save_solution(system, with, NULL) == RAD_OK);
    size_t size = 0, old_size = 0;
    unsigned char *bytes = read_file(with, &size);
    unsigned char *old = without_samples(bytes, size, &old_size);
    CHECK(old_size < size);
    write_file(without, old, old_size);
    rad_system *a = office_system(1), *b = office_system(1);
    CHECK(rad_system_load_solution(a, with, NULL) == RAD_OK);
    CHECK(rad_system_load_solution(b, without, NULL) == RAD_OK);
    rad_solve_options o = {.solver = RAD_SOLVER_HIERARCHICAL, .max_iterations = 3, .resume = 1};
    CHECK(rad_solve(a, &o, NULL) == RAD_OK);
    CHECK(rad_solve(b, &o, NULL) == RAD_OK);
    CHECK(same(a, b));
    free(bytes);
    free(old);
    unlink(with);
    unlink(without);
    rad_system_destroy(system);
    rad_system_destroy(a);
    rad_system_destroy(b);
}

/* The fingerprints: meshing-independent for the scene, exact for the mesh. */
static void test_fingerprints(void) {
    rad_system *a = build("cornell", 300, RAD_FF_DEFAULT), *b = build("cornell", 300, RAD_FF_DEFAULT),
               *c = build("cornell", 500, RAD_FF_DEFAULT);
    rad_solution_fingerprint fa, fb, fc;
    CHECK(rad_solution_fingerprint_compute(a, &fa) == RAD_OK);
    CHECK(rad_solution_fingerprint_compute(b, &fb) == RAD_OK);
    CHECK(rad_solution_fingerprint_compute(c, &fc) == RAD_OK);
    CHECK(fa.scene == fb.scene && fa.mesh == fb.mesh && fa.form_factors == fb.form_factors);
    CHECK(fa.scene == fc.scene && fa.mesh != fc.mesh);
    /* The known FNV-1a 64 value of "a". */
    CHECK(rad_fnv1a(RAD_FNV1A_START, "a", 1) == 0xaf63dc4c8601ec8cull);
    rad_system_destroy(a);
    rad_system_destroy(b);
    rad_system_destroy(c);
}

int main(void) {
    CHECK(rad_context_create(&(rad_context_options){.threads = 2}, &ctx) == RAD_OK);
    CHECK(mkdtemp(dir) != NULL);
    test_round_trip_and_resume();
    test_refusals();
    test_hierarchy_refusals();
    test_hierarchy_without_samples();
    test_fingerprints();
    /* Clean up the scratch directory. */
    const char *names[] = {"cornell.sol", "walls.sol", "good.sol", "bad.sol"};
    for (int k = 0; k < 4; ++k) unlink(path_of(names[k]));
    CHECK(rmdir(dir) == 0); /* empty: no temporary files were left behind */
    rad_context_destroy(ctx);
    return test_finish();
}
