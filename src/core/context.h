/* context.h - the library context: allocator, log, progress, threads, limits, last error.
 * Every internal allocation and every error message goes through here. */
#ifndef RAD_CORE_CONTEXT_H
#define RAD_CORE_CONTEXT_H

#include "radiosity.h"

#include <stdarg.h>
#include <stddef.h>

#define RAD_ERROR_MESSAGE_SIZE 1024
#define RAD_DEFAULT_MAX_MEMORY (2ull << 30)

struct rad_context {
    rad_allocator allocator;
    rad_log_fn log;
    void *log_user;
    rad_progress_fn progress;
    void *progress_user;
    int threads;
    uint64_t seed;
    uint64_t max_memory;
    char error[RAD_ERROR_MESSAGE_SIZE];
    rad_error_fn on_error;
    void *error_user;
    /* The one Embree device of the context: every ray structure commits its scenes on it
     * (scene/rays.c creates it on first use and sets the release); released with the context. */
    void *ray_device;
    void (*release_ray_device)(void *device);
    /* The worker threads of rad_team_for (core/team.c), started on first use; stopped with
     * the context. */
    struct rad_team *team;
};

#if defined(__GNUC__)
#define RAD_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define RAD_PRINTF(a, b)
#endif

/* Records `message` as the context's error and returns `status`, so callers can write
 * `return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: ...", ...)`. */
rad_status rad_fail(rad_context *ctx, rad_status status, const char *format, ...) RAD_PRINTF(3, 4);
rad_status rad_failv(rad_context *ctx, rad_status status, const char *format, va_list args);

/* Sends a warning or note to the log callback, if there is one. */
void rad_warn(rad_context *ctx, const char *format, ...) RAD_PRINTF(2, 3);
void rad_info(rad_context *ctx, const char *format, ...) RAD_PRINTF(2, 3);

/* Asks the progress callback; returns nonzero when the caller must stop (cancelled). */
int rad_progress(rad_context *ctx, const char *phase, double done, double total);

/* Allocation through the context's allocator. Count-times-size is checked for overflow;
 * a failure returns NULL and records RAD_ERROR_NO_MEMORY on the context. */
void *rad_alloc(rad_context *ctx, size_t count, size_t size);
void *rad_alloc_zero(rad_context *ctx, size_t count, size_t size);
void *rad_realloc(rad_context *ctx, void *pointer, size_t count, size_t size);
void rad_free(rad_context *ctx, void *pointer);
char *rad_strdup(rad_context *ctx, const char *text);

/* Nonzero when count * size overflows size_t; otherwise stores the product. */
int rad_size_mul(size_t count, size_t size, size_t *product);

/* Refuses (RAD_ERROR_MEMORY_BUDGET) when `bytes` exceeds the context's memory budget. */
rad_status rad_check_budget(rad_context *ctx, double bytes, const char *what);

/* The thread count the context asks for (at least 1). */
int rad_thread_count(const rad_context *ctx);

/* Wall-clock seconds from an arbitrary origin. */
double rad_seconds(void);
/* Processor seconds of this process (every thread's): steadier than the wall clock on a shared
 * machine. */
double rad_processor_seconds(void);

#endif
