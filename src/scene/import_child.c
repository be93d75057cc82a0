/* import_child.c - scene import in a child process (docs/errors.md, "Files that break assimp").
 *
 * assimp's readers crash, loop or allocate without bound on some damaged files, and the cheap
 * pre-checks of import_check.c cannot keep up with every reader. So the import runs in a
 * forked child:
 * 1. The child gets no outputs: standard input, output and error go to /dev/null (set
 *    RAD_IMPORT_STDERR=1 to keep standard error, for debugging), every other descriptor but its
 *    end of the pipe is closed. It has an address-space limit (what it has mapped now plus the
 *    context's memory budget; not under ASan or valgrind, which map far more than they use), a
 *    CPU-time limit and no core files.
 * 2. It runs rad_scene_import_here and writes to the pipe, as records: every log message, then
 *    either the error (status and message) or the scene (counts, then the arrays), then an end
 *    mark; it frees what it made and leaves with _exit (no atexit handlers, no stdio flush of
 *    the parent's buffers).
 * 3. The parent reads the records under the memory budget and a wall-clock limit, replays the
 *    messages, checks every index of the scene it gets back, and turns a signal, a time-out or
 *    an overrun into one line: "FILE: assimp could not read it (it crashed: SIGSEGV)".
 * Both processes run the same binary, so the records hold native structs.
 * RAD_IMPORT_SECONDS overrides the CPU limit (the wall-clock limit is twice it).
 * In the sanitizer build the child's ASan/UBSan reports stay visible (child_outputs), and their
 * exit status 86 is named in the parent's line. */
#define _GNU_SOURCE
#include "scene/scene.h"
#include "scene/texture.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#if defined(__has_include)
#if __has_include(<valgrind/valgrind.h>)
#include <valgrind/valgrind.h>
#endif
#endif
#ifndef RUNNING_ON_VALGRIND
#define RUNNING_ON_VALGRIND 0
#endif
#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif
#ifndef UNDER_ASAN
#define UNDER_ASAN 0
#endif
#if UNDER_ASAN
#include <sanitizer/common_interface_defs.h>
#endif

/* CPU seconds an import may take; the wall clock gets twice as long (a blocked read). */
#define IMPORT_CPU_SECONDS 120
/* Address space the child may map beyond the budget: assimp's own tables and stacks. */
#define IMPORT_SLACK_BYTES (64u << 20)

enum record_kind { RECORD_INFO, RECORD_WARNING, RECORD_ERROR, RECORD_SCENE, RECORD_END,
                   RECORD_TEXTURES, RECORD_FILES };

typedef struct record_header {
    uint32_t kind;
    int32_t status;  /* RECORD_ERROR */
    uint64_t length; /* bytes that follow */
} record_header;

/* A light as it crosses the pipe (after the materials: a uint64 count, then each light and its
 * name); IES profiles are never in a file's import, so none travels. */
typedef struct light_record {
    int32_t kind;
    rad_vec3 position, direction;
    double intensity[3];
    double inner_angle, outer_angle;
} light_record;

typedef struct scene_counts {
    uint64_t vertices, polygon_vertices, polygons, surfaces, materials;
    int32_t has_camera;
    rad_camera camera;
} scene_counts;

/* ------------------------------------------------------------------------------------------- */
/* The child.                                                                                   */

static int pipe_fd = -1;

static int write_all(const void *data, size_t size) {
    const char *p = data;
    while (size > 0) {
        ssize_t n = write(pipe_fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return -1;
        p += n;
        size -= (size_t)n;
    }
    return 0;
}

static int write_record(uint32_t kind, int32_t status, const void *data, uint64_t length) {
    record_header header = {kind, status, length};
    if (write_all(&header, sizeof header)) return -1;
    return length ? write_all(data, (size_t)length) : 0;
}

static void child_log(void *user, rad_log_level level, const char *message) {
    (void)user;
    write_record(level == RAD_LOG_WARNING ? RECORD_WARNING : RECORD_INFO, 0, message,
                 strlen(message) + 1);
}

static uint64_t string_bytes(const char *text) { return sizeof(uint32_t) + strlen(text); }

static int write_string(const char *text) {
    uint32_t length = (uint32_t)strlen(text);
    return write_all(&length, sizeof length) || write_all(text, length);
}

static int write_scene(const rad_scene *scene) {
    /* Structs go out zeroed first and filled field by field: no padding byte is left unset. */
    scene_counts counts;
    memset(&counts, 0, sizeof counts);
    counts.vertices = scene->vertex_count;
    counts.polygon_vertices = scene->polygon_vertex_count;
    counts.polygons = scene->polygon_count;
    counts.surfaces = scene->surface_count;
    counts.materials = scene->material_count;
    counts.has_camera = scene->has_camera;
    counts.camera = scene->camera;
    uint64_t length = sizeof counts + counts.vertices * sizeof *scene->vertices +
                      counts.polygon_vertices * sizeof *scene->polygon_vertices +
                      counts.polygons * sizeof *scene->polygons;
    for (size_t i = 0; i < scene->surface_count; ++i)
        length += sizeof(uint32_t) + string_bytes(scene->surfaces[i].name);
    for (size_t i = 0; i < scene->material_count; ++i)
        length += sizeof(rad_material) + string_bytes(scene->materials[i].name);
    length += sizeof(uint64_t);
    for (size_t i = 0; i < scene->light_count; ++i)
        length += sizeof(light_record) + string_bytes(scene->lights[i].name);
    record_header header = {RECORD_SCENE, 0, length};
    if (write_all(&header, sizeof header) || write_all(&counts, sizeof counts) ||
        write_all(scene->vertices, counts.vertices * sizeof *scene->vertices) ||
        write_all(scene->polygon_vertices,
                  counts.polygon_vertices * sizeof *scene->polygon_vertices) ||
        write_all(scene->polygons, counts.polygons * sizeof *scene->polygons))
        return -1;
    for (size_t i = 0; i < scene->surface_count; ++i)
        if (write_all(&scene->surfaces[i].material, sizeof(uint32_t)) ||
            write_string(scene->surfaces[i].name))
            return -1;
    for (size_t i = 0; i < scene->material_count; ++i) {
        const rad_material *m = &scene->materials[i];
        rad_material copy;
        memset(&copy, 0, sizeof copy);
        memcpy(copy.reflectance, m->reflectance, sizeof copy.reflectance);
        memcpy(copy.emission, m->emission, sizeof copy.emission);
        memcpy(copy.specular, m->specular, sizeof copy.specular);
        copy.kind = m->kind;
        copy.roughness = m->roughness;
        copy.ior = m->ior;
        copy.two_sided = m->two_sided; /* texture: the textures record */
        if (write_all(&copy, sizeof copy) || write_string(m->name)) return -1;
    }
    uint64_t light_count = scene->light_count;
    if (write_all(&light_count, sizeof light_count)) return -1;
    for (size_t i = 0; i < scene->light_count; ++i) {
        const rad_light *l = &scene->lights[i];
        light_record record;
        memset(&record, 0, sizeof record);
        record.kind = (int32_t)l->kind;
        record.position = l->position;
        record.direction = l->direction;
        memcpy(record.intensity, l->intensity, sizeof record.intensity);
        record.inner_angle = l->inner_angle;
        record.outer_angle = l->outer_angle;
        if (write_all(&record, sizeof record) || write_string(l->name)) return -1;
    }
    return 0;
}

/* Textures and texture coordinates (scene/texture.h): one record after the scene, when it has
 * any: the corners' (u, v), then each texture (name, width, height, sRGB texels), then per
 * material the index of its texture plus one (0: none). */
static int write_textures(const rad_scene *scene) {
    if (!scene->texture_count && !scene->polygon_uv_count) return 0;
    uint64_t uvs = scene->polygon_uv_count, textures = scene->texture_count;
    uint64_t length = 2 * sizeof(uint64_t) + uvs * sizeof *scene->polygon_uvs +
                      scene->material_count * sizeof(uint32_t);
    for (size_t i = 0; i < scene->texture_count; ++i)
        length += string_bytes(scene->textures[i]->name) + 2 * sizeof(uint32_t) +
                  3 * (uint64_t)scene->textures[i]->width * scene->textures[i]->height;
    record_header header = {RECORD_TEXTURES, 0, length};
    if (write_all(&header, sizeof header) || write_all(&uvs, sizeof uvs) ||
        write_all(scene->polygon_uvs, uvs * sizeof *scene->polygon_uvs) ||
        write_all(&textures, sizeof textures))
        return -1;
    for (size_t i = 0; i < scene->texture_count; ++i) {
        const rad_texture *t = scene->textures[i];
        uint32_t size[2] = {t->width, t->height};
        if (write_string(t->name) || write_all(size, sizeof size) ||
            write_all(t->texels, 3 * (size_t)t->width * t->height))
            return -1;
    }
    for (size_t i = 0; i < scene->material_count; ++i) {
        uint32_t which = 0;
        for (size_t k = 0; k < scene->texture_count && scene->materials[i].texture; ++k)
            if (scene->textures[k] == scene->materials[i].texture) which = (uint32_t)k + 1;
        if (write_all(&which, sizeof which)) return -1;
    }
    return 0;
}

/* The files the import read (scene.h, rad_file_list): a count, then each path. */
static int write_files(const rad_scene *scene) {
    uint64_t count = scene->files.count, length = sizeof count;
    for (size_t i = 0; i < scene->files.count; ++i) length += string_bytes(scene->files.paths[i]);
    record_header header = {RECORD_FILES, 0, length};
    if (write_all(&header, sizeof header) || write_all(&count, sizeof count)) return -1;
    for (size_t i = 0; i < scene->files.count; ++i)
        if (write_string(scene->files.paths[i])) return -1;
    return 0;
}

/* Pages mapped now, from /proc/self/statm; 0 when unknown. */
static uint64_t mapped_bytes(void) {
    FILE *statm = fopen("/proc/self/statm", "r");
    unsigned long long pages = 0;
    if (!statm) return 0;
    if (fscanf(statm, "%llu", &pages) != 1) pages = 0;
    fclose(statm);
    return (uint64_t)pages * (uint64_t)sysconf(_SC_PAGESIZE);
}

static void child_limits(rad_context *ctx, int cpu_seconds) {
    struct rlimit none = {0, 0};
    setrlimit(RLIMIT_CORE, &none);
    struct rlimit cpu = {(rlim_t)cpu_seconds, (rlim_t)cpu_seconds + 1};
    setrlimit(RLIMIT_CPU, &cpu);
    if (!UNDER_ASAN && !RUNNING_ON_VALGRIND) {
        uint64_t now = mapped_bytes();
        if (now) {
            struct rlimit as = {(rlim_t)(now + ctx->max_memory + IMPORT_SLACK_BYTES),
                                (rlim_t)(now + ctx->max_memory + IMPORT_SLACK_BYTES)};
            setrlimit(RLIMIT_AS, &as);
        }
    }
}

static void child_outputs(int write_fd) {
    if (write_fd != 3) {
        dup2(write_fd, 3);
        close(write_fd);
    }
    pipe_fd = 3;
    int keep_stderr = getenv("RAD_IMPORT_STDERR") && strcmp(getenv("RAD_IMPORT_STDERR"), "1") == 0;
#if UNDER_ASAN
    /* The sanitizers' reports on our own code in the child (the walk over assimp's scene) must
     * reach whoever runs the sanitizer build: to ASAN_OPTIONS' log_path when it is set (the
     * runtime opens that file per process), else to the parent's standard error, kept on
     * descriptor 4 past the clean-up below. */
    const char *asan_options = getenv("ASAN_OPTIONS");
    int report_fd = -1;
    if (!keep_stderr && !(asan_options && strstr(asan_options, "log_path=")))
        report_fd = dup2(2, 4);
#endif
    int null_fd = open("/dev/null", O_RDWR);
    if (null_fd >= 0) {
        dup2(null_fd, 0);
        dup2(null_fd, 1);
        if (!keep_stderr) dup2(null_fd, 2);
        if (null_fd > 3) close(null_fd);
    }
#if UNDER_ASAN
    int first_closed = report_fd == 4 ? 5 : 4;
#else
    int first_closed = 4;
#endif
    if (close_range((unsigned)first_closed, ~0u, 0) != 0)
        for (int fd = first_closed; fd < 1024; ++fd) close(fd);
#if UNDER_ASAN
    if (report_fd == 4) __sanitizer_set_report_fd((void *)(intptr_t)4);
    /* A crash inside assimp (not instrumented) is the parent's to report: a signal ends the
     * child as it would without the sanitizers. */
    if (!keep_stderr) {
        static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
        for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; ++i) signal(fatal[i], SIG_DFL);
    }
#endif
}

static _Noreturn void child_run(rad_context *ctx, const char *path, int write_fd,
                                int cpu_seconds) {
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGPIPE, SIG_DFL);
    child_outputs(write_fd);
    child_limits(ctx, cpu_seconds);
    ctx->log = child_log;
    ctx->log_user = NULL;
    ctx->progress = NULL;
    rad_scene *scene = NULL;
    rad_status status = rad_scene_import_here(ctx, path, &scene);
    int failed = status ? write_record(RECORD_ERROR, (int32_t)status, ctx->error,
                                       strlen(ctx->error) + 1)
                        : write_scene(scene);
    if (!failed && !status) failed = write_textures(scene);
    if (!failed && !status) failed = write_files(scene);
    if (!failed) failed = write_record(RECORD_END, 0, NULL, 0);
    rad_scene_destroy(scene);
    _exit(failed ? 3 : 0);
}

/* ------------------------------------------------------------------------------------------- */
/* The parent.                                                                                  */

typedef struct reply {
    char *data;
    size_t length, capacity;
} reply;

static double now_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Reads the child's records until the pipe ends. 1: timed out; -1: over the budget or out of
 * memory (*failure and the error set); 0: done. */
static int read_reply(rad_context *ctx, int fd, double seconds, reply *r, rad_status *failure) {
    double deadline = now_seconds() + seconds;
    for (;;) {
        double left = deadline - now_seconds();
        if (left <= 0) return 1;
        struct pollfd p = {fd, POLLIN, 0};
        int ready = poll(&p, 1, left > 1e6 ? 1000000000 : (int)(left * 1000) + 1);
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) continue;
        if (r->length + 65536 > r->capacity) {
            size_t capacity = r->capacity ? 2 * r->capacity : 1 << 20;
            *failure = rad_check_budget(ctx, (double)capacity, "the imported scene");
            if (*failure) return -1;
            char *grown = rad_realloc(ctx, r->data, capacity, 1);
            *failure = RAD_ERROR_NO_MEMORY;
            if (!grown) return -1;
            r->data = grown;
            r->capacity = capacity;
        }
        ssize_t n = read(fd, r->data + r->length, r->capacity - r->length);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return 0;
        r->length += (size_t)n;
    }
}

static const char *signal_name(int number) {
    static const struct {
        int number;
        const char *name;
    } names[] = {{SIGSEGV, "SIGSEGV"}, {SIGABRT, "SIGABRT"}, {SIGBUS, "SIGBUS"},
                 {SIGFPE, "SIGFPE"},   {SIGILL, "SIGILL"},   {SIGKILL, "SIGKILL"},
                 {SIGTERM, "SIGTERM"}, {SIGINT, "SIGINT"},   {SIGPIPE, "SIGPIPE"},
                 {SIGTRAP, "SIGTRAP"}, {SIGSYS, "SIGSYS"}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (names[i].number == number) return names[i].name;
    return "a signal";
}

/* A cursor over one record's bytes. */
typedef struct cursor {
    const char *p, *end;
} cursor;

static int take(cursor *c, void *out, size_t size) {
    if ((size_t)(c->end - c->p) < size) return -1;
    memcpy(out, c->p, size);
    c->p += size;
    return 0;
}

static rad_status take_string(rad_context *ctx, cursor *c, char **out) {
    uint32_t length;
    if (take(c, &length, sizeof length) || (size_t)(c->end - c->p) < length)
        return RAD_ERROR_PARSE;
    char *text = rad_alloc(ctx, (size_t)length + 1, 1);
    if (!text) return RAD_ERROR_NO_MEMORY;
    memcpy(text, c->p, length);
    text[length] = '\0';
    c->p += length;
    *out = text;
    return RAD_OK;
}

/* A zeroed table of `count` items that each take at least one byte of what is left. */
static rad_status take_table(rad_context *ctx, cursor *c, void **items, size_t *capacity,
                             uint64_t count, size_t size) {
    if (count > (uint64_t)(c->end - c->p)) return RAD_ERROR_PARSE;
    if (count == 0) return RAD_OK;
    *items = rad_alloc_zero(ctx, (size_t)count, size);
    if (!*items) return RAD_ERROR_NO_MEMORY;
    *capacity = (size_t)count;
    return RAD_OK;
}

static rad_status take_array(rad_context *ctx, cursor *c, void **out, uint64_t count,
                             size_t size) {
    if (count == 0) return RAD_OK;
    if (count > (uint64_t)(c->end - c->p) / size) return RAD_ERROR_PARSE;
    *out = rad_alloc(ctx, (size_t)count, size);
    if (!*out) return RAD_ERROR_NO_MEMORY;
    memcpy(*out, c->p, (size_t)count * size);
    c->p += (size_t)count * size;
    return RAD_OK;
}

/* Every index of the scene points inside it. */
static int scene_consistent(const rad_scene *s) {
    for (size_t i = 0; i < s->polygon_vertex_count; ++i)
        if (s->polygon_vertices[i] >= s->vertex_count) return 0;
    for (size_t i = 0; i < s->polygon_count; ++i) {
        const rad_polygon *p = &s->polygons[i];
        if (p->count < 3 || p->first > s->polygon_vertex_count ||
            p->count > s->polygon_vertex_count - p->first || p->surface >= s->surface_count)
            return 0;
    }
    for (size_t i = 0; i < s->surface_count; ++i)
        if (s->surfaces[i].material >= s->material_count) return 0;
    return 1;
}

static rad_status read_scene(rad_context *ctx, const char *path, cursor *c, rad_scene **out) {
    scene_counts n;
    if (take(c, &n, sizeof n)) return RAD_ERROR_PARSE;
    rad_scene *scene = NULL;
    rad_status status = rad_scene_new(ctx, 1, path, &scene);
    if (status) return status;
    status = take_array(ctx, c, (void **)&scene->vertices, n.vertices, sizeof *scene->vertices);
    if (!status) scene->vertex_count = scene->vertex_capacity = n.vertices;
    if (!status)
        status = take_array(ctx, c, (void **)&scene->polygon_vertices, n.polygon_vertices,
                            sizeof *scene->polygon_vertices);
    if (!status) scene->polygon_vertex_count = scene->polygon_vertex_capacity = n.polygon_vertices;
    if (!status)
        status = take_array(ctx, c, (void **)&scene->polygons, n.polygons, sizeof *scene->polygons);
    if (!status) scene->polygon_count = scene->polygon_capacity = n.polygons;
    if (!status)
        status = take_table(ctx, c, (void **)&scene->surfaces, &scene->surface_capacity,
                            n.surfaces, sizeof *scene->surfaces);
    for (uint64_t i = 0; !status && i < n.surfaces; ++i) {
        rad_surface_def *surface = &scene->surfaces[i];
        status = take(c, &surface->material, sizeof surface->material) ? RAD_ERROR_PARSE
                 : take_string(ctx, c, &surface->name);
        if (!status) scene->surface_count++;
    }
    if (!status)
        status = take_table(ctx, c, (void **)&scene->materials, &scene->material_capacity,
                            n.materials, sizeof *scene->materials);
    for (uint64_t i = 0; !status && i < n.materials; ++i) {
        rad_material *material = &scene->materials[i];
        status = take(c, material, sizeof *material) ? RAD_ERROR_PARSE : RAD_OK;
        material->name = NULL;
        material->texture = NULL; /* the child's pointer; set by the textures record */
        if (!status) status = take_string(ctx, c, &material->name);
        if (!status) scene->material_count++;
    }
    uint64_t light_count = 0;
    if (!status && take(c, &light_count, sizeof light_count)) status = RAD_ERROR_PARSE;
    for (uint64_t i = 0; !status && i < light_count; ++i) {
        light_record record;
        rad_light light;
        memset(&light, 0, sizeof light);
        if (take(c, &record, sizeof record) || record.kind < RAD_LIGHT_POINT ||
            record.kind > RAD_LIGHT_DIRECTIONAL) {
            status = RAD_ERROR_PARSE;
            break;
        }
        light.kind = (rad_light_kind)record.kind;
        light.position = record.position;
        light.direction = record.direction;
        memcpy(light.intensity, record.intensity, sizeof light.intensity);
        light.inner_angle = record.inner_angle;
        light.outer_angle = record.outer_angle;
        status = take_string(ctx, c, &light.name);
        if (!status) status = rad_scene_append_light(scene, &light);
        rad_free(ctx, light.name);
    }
    if (!status && (c->p != c->end || !scene_consistent(scene))) status = RAD_ERROR_PARSE;
    if (!status) {
        scene->has_camera = n.has_camera;
        scene->camera = n.camera;
        *out = scene;
        return RAD_OK;
    }
    rad_scene_destroy(scene);
    return status;
}

/* The textures record (write_textures) into the scene read before it. */
static rad_status read_textures(rad_context *ctx, cursor *c, rad_scene *scene) {
    uint64_t uvs, textures;
    if (take(c, &uvs, sizeof uvs) || uvs > scene->polygon_vertex_count) return RAD_ERROR_PARSE;
    rad_status status = take_array(ctx, c, (void **)&scene->polygon_uvs, uvs,
                                   sizeof *scene->polygon_uvs);
    if (status) return status;
    scene->polygon_uv_count = scene->polygon_uv_capacity = uvs;
    if (take(c, &textures, sizeof textures) || textures > (uint64_t)(c->end - c->p))
        return RAD_ERROR_PARSE;
    for (uint64_t i = 0; i < textures; ++i) {
        char *name = NULL;
        uint32_t size[2];
        status = take_string(ctx, c, &name);
        if (status) return status;
        rad_texture *texture = NULL;
        if (take(c, size, sizeof size) || size[0] == 0 || size[1] == 0 ||
            3 * (uint64_t)size[0] * size[1] > (uint64_t)(c->end - c->p))
            status = RAD_ERROR_PARSE;
        if (!status) status = rad_texture_from_texels(ctx, name, size[0], size[1],
                                                      (const uint8_t *)c->p, &texture);
        rad_free(ctx, name);
        if (status) return status;
        c->p += 3 * (size_t)size[0] * size[1];
        status = rad_scene_add_texture(scene, texture, NULL);
        rad_texture_release(texture);
        if (status) return status;
    }
    for (size_t i = 0; i < scene->material_count; ++i) {
        uint32_t which;
        if (take(c, &which, sizeof which) || which > scene->texture_count) return RAD_ERROR_PARSE;
        scene->materials[i].texture = which ? scene->textures[which - 1] : NULL;
    }
    return c->p == c->end ? RAD_OK : RAD_ERROR_PARSE;
}

/* Replays the records into *status (and *out); returns 1 when they end with the end mark. */
static rad_status read_files(rad_context *ctx, cursor *c, rad_scene *scene) {
    uint64_t count;
    if (take(c, &count, sizeof count)) return RAD_ERROR_PARSE;
    for (uint64_t i = 0; i < count; ++i) {
        char *path = NULL;
        rad_status status = take_string(ctx, c, &path);
        if (!status) status = rad_file_list_add(ctx, &scene->files, path);
        rad_free(ctx, path);
        if (status) return status;
    }
    return RAD_OK;
}

static int replay(rad_context *ctx, const char *path, const reply *r, rad_scene **out,
                  rad_status *status) {
    cursor all = {r->data, r->data + r->length};
    *status = RAD_OK;
    for (;;) {
        record_header header;
        if (take(&all, &header, sizeof header) || header.length > (uint64_t)(all.end - all.p))
            break;
        cursor body = {all.p, all.p + header.length};
        all.p += header.length;
        if (header.kind == RECORD_INFO || header.kind == RECORD_WARNING) {
            if (ctx->log && header.length > 0 && body.end[-1] == '\0')
                ctx->log(ctx->log_user, header.kind == RECORD_WARNING ? RAD_LOG_WARNING
                                                                      : RAD_LOG_INFO, body.p);
        } else if (header.kind == RECORD_ERROR && !*status && !*out) {
            if (header.length == 0 || body.end[-1] != '\0' || header.status <= 0) break;
            *status = rad_fail(ctx, (rad_status)header.status, "%s", body.p);
        } else if (header.kind == RECORD_SCENE && !*status && !*out) {
            rad_status read = read_scene(ctx, path, &body, out);
            if (read == RAD_ERROR_PARSE) break;
            if (read) {
                *status = read;
                return 1;
            }
        } else if ((header.kind == RECORD_TEXTURES || header.kind == RECORD_FILES) &&
                   !*status && *out) {
            rad_status read = header.kind == RECORD_TEXTURES ? read_textures(ctx, &body, *out)
                                                             : read_files(ctx, &body, *out);
            if (read == RAD_ERROR_PARSE) break;
            if (read) {
                *status = read;
                rad_scene_destroy(*out);
                *out = NULL;
                return 1;
            }
        } else if (header.kind == RECORD_END && (*status || *out)) {
            return 1;
        } else {
            break;
        }
    }
    rad_scene_destroy(*out);
    *out = NULL;
    *status = RAD_OK;
    return 0;
}

static int import_seconds(void) {
    const char *text = getenv("RAD_IMPORT_SECONDS");
    if (text) {
        char *end;
        long seconds = strtol(text, &end, 10);
        if (end != text && !*end && seconds >= 1 && seconds <= 86400) return (int)seconds;
    }
    return IMPORT_CPU_SECONDS;
}

rad_status rad_scene_import(rad_context *ctx, const char *path, rad_scene **out) {
    *out = NULL;
    int cpu_seconds = import_seconds();
    int fds[2];
    if (pipe(fds) != 0)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot start the import (pipe: %s)", path,
                        strerror(errno));
    fflush(NULL); /* nothing buffered is written twice */
    pid_t child = fork();
    if (child < 0) {
        int error = errno;
        close(fds[0]);
        close(fds[1]);
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot start the import (fork: %s)", path,
                        strerror(error));
    }
    if (child == 0) {
        close(fds[0]);
        child_run(ctx, path, fds[1], cpu_seconds);
    }
    close(fds[1]);

    reply r = {0};
    rad_status status = RAD_OK;
    int outcome = read_reply(ctx, fds[0], 2.0 * cpu_seconds, &r, &status);
    close(fds[0]);
    if (outcome != 0) kill(child, SIGKILL);
    int wait_status = 0;
    struct rusage usage;
    memset(&usage, 0, sizeof usage);
    while (wait4(child, &wait_status, 0, &usage) < 0 && errno == EINTR) {
    }
    if (outcome == 1) {
        status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: assimp could not read it (it timed out "
                          "after %d s)", path, 2 * cpu_seconds);
    } else if (outcome < 0) {
        /* status and message set by read_reply */
    } else if (WIFSIGNALED(wait_status)) {
        int number = WTERMSIG(wait_status);
        double peak = (double)usage.ru_maxrss * 1024.0;
        long cpu = (long)usage.ru_utime.tv_sec + (long)usage.ru_stime.tv_sec;
        if (number == SIGXCPU || (number == SIGKILL && cpu >= cpu_seconds))
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: assimp could not read it (it took more "
                              "than %d s of CPU time)", path, cpu_seconds);
        else if (peak >= 0.5 * (double)ctx->max_memory)
            status = rad_fail(ctx, RAD_ERROR_MEMORY_BUDGET, "%s: assimp could not read it (it "
                              "exceeded the memory budget of %.1f MiB, --max-memory)", path,
                              (double)ctx->max_memory / 1048576.0);
        else
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: assimp could not read it (it crashed: "
                              "%s)", path, signal_name(number));
    } else {
        int complete = replay(ctx, path, &r, out, &status);
        if (!complete || WEXITSTATUS(wait_status) != 0) {
            rad_scene_destroy(*out);
            *out = NULL;
            status = rad_fail(ctx, RAD_ERROR_PARSE, "%s: assimp could not read it (the import "
                              "stopped with status %d%s)", path, WEXITSTATUS(wait_status),
                              UNDER_ASAN && WEXITSTATUS(wait_status) == 86
                                  ? ": a sanitizer report, on standard error or in log_path"
                                  : "");
        } else if (status && strstr(ctx->error, "bad_alloc")) {
            status = rad_fail(ctx, RAD_ERROR_MEMORY_BUDGET, "%s: assimp could not read it (it "
                              "exceeded the memory budget of %.1f MiB, --max-memory)", path,
                              (double)ctx->max_memory / 1048576.0);
        }
    }
    rad_free(ctx, r.data);
    return status;
}
