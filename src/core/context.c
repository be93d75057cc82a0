/* context.c - the library context: allocator, errors, logging, progress and limits. */
#include "core/context.h"
#include "core/team.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void *default_allocate(void *user, size_t size) { (void)user; return malloc(size); }
static void *default_reallocate(void *user, void *pointer, size_t size) {
    (void)user;
    return realloc(pointer, size);
}
static void default_release(void *user, void *pointer) { (void)user; free(pointer); }

const char *rad_version(void) { return RAD_VERSION_STRING; }

const char *rad_status_name(rad_status status) {
    switch (status) {
    case RAD_OK: return "ok";
    case RAD_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RAD_ERROR_PARSE: return "parse error";
    case RAD_ERROR_IO: return "input/output error";
    case RAD_ERROR_NO_MEMORY: return "out of memory";
    case RAD_ERROR_MEMORY_BUDGET: return "over the memory budget";
    case RAD_ERROR_UNSUPPORTED: return "unsupported";
    case RAD_ERROR_CANCELLED: return "cancelled";
    case RAD_ERROR_INTERNAL: return "internal error";
    }
    return "unknown status";
}

rad_status rad_context_create(const rad_context_options *options, rad_context **out) {
    if (!out) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    rad_context_options defaults = {0};
    if (!options) options = &defaults;
    rad_allocator allocator = options->allocator;
    int given = (allocator.allocate != NULL) + (allocator.reallocate != NULL) +
                (allocator.release != NULL);
    if (given != 0 && given != 3) return RAD_ERROR_INVALID_ARGUMENT;
    if (given == 0) {
        allocator.allocate = default_allocate;
        allocator.reallocate = default_reallocate;
        allocator.release = default_release;
        allocator.user = NULL;
    }
    if (options->threads < 0 || options->threads > RAD_MAX_THREADS) {
        /* No context to keep the message on: tell the error callback, if there is one. */
        if (options->on_error) {
            char message[128];
            snprintf(message, sizeof message, "threads is %d; it must be 0 (all cores) to %d",
                     options->threads, RAD_MAX_THREADS);
            options->on_error(options->error_user, RAD_ERROR_INVALID_ARGUMENT, message);
        }
        return RAD_ERROR_INVALID_ARGUMENT;
    }
    rad_context *ctx = allocator.allocate(allocator.user, sizeof *ctx);
    if (!ctx) return RAD_ERROR_NO_MEMORY;
    memset(ctx, 0, sizeof *ctx);
    ctx->allocator = allocator;
    ctx->log = options->log;
    ctx->log_user = options->log_user;
    ctx->progress = options->progress;
    ctx->progress_user = options->progress_user;
    ctx->on_error = options->on_error;
    ctx->error_user = options->error_user;
    ctx->threads = options->threads;
    ctx->seed = options->seed;
    ctx->max_memory = options->max_memory ? options->max_memory : RAD_DEFAULT_MAX_MEMORY;
    *out = ctx;
    return RAD_OK;
}

void rad_context_destroy(rad_context *ctx) {
    if (!ctx) return;
    if (ctx->ray_device && ctx->release_ray_device) ctx->release_ray_device(ctx->ray_device);
    rad_team_destroy(ctx);
    ctx->allocator.release(ctx->allocator.user, ctx);
}

const char *rad_context_error(const rad_context *ctx) { return ctx ? ctx->error : ""; }

rad_status rad_failv(rad_context *ctx, rad_status status, const char *format, va_list args) {
    if (!ctx) return status;
    vsnprintf(ctx->error, sizeof ctx->error, format, args);
    if (ctx->on_error) ctx->on_error(ctx->error_user, status, ctx->error);
    return status;
}

rad_status rad_fail(rad_context *ctx, rad_status status, const char *format, ...) {
    va_list args;
    va_start(args, format);
    rad_failv(ctx, status, format, args);
    va_end(args);
    return status;
}

static void log_message(rad_context *ctx, rad_log_level level, const char *format, va_list args) {
    if (!ctx || !ctx->log) return;
    char message[RAD_ERROR_MESSAGE_SIZE];
    vsnprintf(message, sizeof message, format, args);
    ctx->log(ctx->log_user, level, message);
}

void rad_warn(rad_context *ctx, const char *format, ...) {
    va_list args;
    va_start(args, format);
    log_message(ctx, RAD_LOG_WARNING, format, args);
    va_end(args);
}

void rad_info(rad_context *ctx, const char *format, ...) {
    va_list args;
    va_start(args, format);
    log_message(ctx, RAD_LOG_INFO, format, args);
    va_end(args);
}

int rad_progress(rad_context *ctx, const char *phase, double done, double total) {
    if (!ctx || !ctx->progress) return 0;
    return ctx->progress(ctx->progress_user, phase, done, total) != 0;
}

int rad_size_mul(size_t count, size_t size, size_t *product) {
    if (size != 0 && count > SIZE_MAX / size) return 1;
    *product = count * size;
    return 0;
}

void *rad_alloc(rad_context *ctx, size_t count, size_t size) {
    size_t bytes;
    if (rad_size_mul(count, size, &bytes)) {
        rad_fail(ctx, RAD_ERROR_NO_MEMORY, "allocation of %zu x %zu bytes overflows", count, size);
        return NULL;
    }
    if (bytes == 0) bytes = 1;
    void *pointer = ctx->allocator.allocate(ctx->allocator.user, bytes);
    if (!pointer) rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory allocating %zu bytes", bytes);
    return pointer;
}

void *rad_alloc_zero(rad_context *ctx, size_t count, size_t size) {
    void *pointer = rad_alloc(ctx, count, size);
    if (pointer) memset(pointer, 0, count * size);
    return pointer;
}

void *rad_realloc(rad_context *ctx, void *pointer, size_t count, size_t size) {
    size_t bytes;
    if (rad_size_mul(count, size, &bytes)) {
        rad_fail(ctx, RAD_ERROR_NO_MEMORY, "allocation of %zu x %zu bytes overflows", count, size);
        return NULL;
    }
    if (bytes == 0) bytes = 1;
    void *grown = ctx->allocator.reallocate(ctx->allocator.user, pointer, bytes);
    if (!grown) rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory allocating %zu bytes", bytes);
    return grown;
}

void rad_free(rad_context *ctx, void *pointer) {
    if (pointer) ctx->allocator.release(ctx->allocator.user, pointer);
}

char *rad_strdup(rad_context *ctx, const char *text) {
    size_t length = strlen(text);
    char *copy = rad_alloc(ctx, length + 1, 1);
    if (copy) memcpy(copy, text, length + 1);
    return copy;
}

rad_status rad_check_budget(rad_context *ctx, double bytes, const char *what) {
    if (bytes <= (double)ctx->max_memory) return RAD_OK;
    return rad_fail(ctx, RAD_ERROR_MEMORY_BUDGET,
                    "%s needs %.1f MiB, over the memory budget of %.1f MiB (--max-memory)", what,
                    bytes / 1048576.0, (double)ctx->max_memory / 1048576.0);
}

rad_status rad_context_check_memory(rad_context *context, double bytes, const char *what) {
    return rad_check_budget(context, bytes, what);
}

int rad_thread_count(const rad_context *ctx) {
    if (ctx && ctx->threads > 0) return ctx->threads;
    int n = omp_get_num_procs();
    return n > 0 ? n : 1;
}

double rad_seconds(void) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

double rad_processor_seconds(void) {
    struct timespec now;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}
