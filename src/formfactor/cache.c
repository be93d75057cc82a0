/* cache.c - a row cache in front of a form-factor provider.
 *
 * Progressive refinement shoots the brightest patches again and again (Cornell box at 10,000
 * elements: about three shots per patch before 1% of the power is left unshot). Rows are
 * deterministic, so a row asked for again can be copied instead of computed. The cache holds
 * at most a given number of bytes and evicts the least recently used row.
 *
 * Gathering and direct solvers ask for each row once, in order (0, 1, 2, ...), and keep the
 * matrix themselves; caching would only double their memory. So rows asked for in such a sweep
 * are not kept; the first request out of order (or a row asked for again) starts the keeping. */
#include "formfactor/geometric.h"

#include <string.h>

typedef struct cache_provider {
    rad_ff_provider base;
    rad_context *ctx;
    rad_ff_provider *inner;
    size_t patch_count, element_count, capacity, used;
    int32_t *slot_of;    /* patch -> slot, or -1 */
    size_t sweep;        /* rows asked for so far, while they came as 0, 1, 2, ... */
    int keeping;         /* the requests left the sweep: keep rows from now on */
    size_t *slot_patch;  /* slot -> patch */
    uint64_t *slot_time; /* last use */
    float **slot_row;
    uint64_t clock;
} cache_provider;

static rad_status cache_row(rad_ff_provider *self, size_t patch, float *row) {
    cache_provider *cache = (cache_provider *)self;
    size_t n = cache->element_count;
    ++cache->clock;
    int32_t slot = cache->slot_of[patch];
    if (slot >= 0) {
        memcpy(row, cache->slot_row[slot], n * sizeof *row);
        cache->slot_time[slot] = cache->clock;
        return RAD_OK;
    }
    if (!cache->keeping) {
        if (patch == cache->sweep) ++cache->sweep;
        else cache->keeping = 1;
    }
    rad_status status = cache->inner->row(cache->inner, patch, row);
    if (status || !cache->keeping) return status;

    /* Keep it: a fresh slot while there is room, else the least recently used one. */
    size_t s;
    float *copy = NULL;
    if (cache->used < cache->capacity && !(copy = rad_alloc(cache->ctx, n, sizeof *copy))) {
        cache->capacity = cache->used; /* out of memory: stop growing, keep going */
        rad_fail(cache->ctx, RAD_OK, "%s", "");
    }
    if (!copy && cache->used == 0) return RAD_OK; /* no room and nothing to evict */
    if (copy) {
        s = cache->used++;
        cache->slot_row[s] = copy;
    } else {
        s = 0;
        for (size_t k = 1; k < cache->used; ++k)
            if (cache->slot_time[k] < cache->slot_time[s]) s = k;
        cache->slot_of[cache->slot_patch[s]] = -1;
    }
    memcpy(cache->slot_row[s], row, n * sizeof *row);
    cache->slot_patch[s] = patch;
    cache->slot_time[s] = cache->clock;
    cache->slot_of[patch] = (int32_t)s;
    return RAD_OK;
}

static int cache_holds(const rad_ff_provider *self, size_t patch) {
    const cache_provider *cache = (const cache_provider *)self;
    return patch < cache->patch_count && cache->slot_of[patch] >= 0;
}

/* Computes the rows of wanted[0 .. k) into fresh slots (out: room for k row pointers). */
static rad_status prefetch_kept(cache_provider *cache, const size_t *wanted, size_t k,
                                float **out) {
    for (size_t j = 0; j < k; ++j) {
        out[j] = rad_alloc(cache->ctx, cache->element_count, sizeof *out[j]);
        if (!out[j]) { /* out of memory: keep going one row at a time */
            while (j > 0) rad_free(cache->ctx, out[--j]);
            rad_fail(cache->ctx, RAD_OK, "%s", "");
            return RAD_OK;
        }
    }
    rad_status status = cache->inner->rows(cache->inner, wanted, k, out);
    if (status) {
        for (size_t j = 0; j < k; ++j) rad_free(cache->ctx, out[j]);
        return status;
    }
    cache->keeping = 1;
    ++cache->clock;
    for (size_t j = 0; j < k; ++j) {
        size_t s = cache->used++;
        cache->slot_row[s] = out[j];
        cache->slot_patch[s] = wanted[j];
        cache->slot_time[s] = cache->clock;
        cache->slot_of[wanted[j]] = (int32_t)s;
    }
    return RAD_OK;
}

/* Rows a solver will ask for soon: those not held, computed in one go by the inner provider
 * into fresh slots. Nothing when they would not all fit beside what is kept (evicting rows to
 * make room for guesses could throw away rows still in use). */
static rad_status cache_prefetch(rad_ff_provider *self, const size_t *patches, size_t count) {
    cache_provider *cache = (cache_provider *)self;
    if (!cache->inner->rows || !count) return RAD_OK;
    size_t *wanted = rad_alloc(cache->ctx, count, sizeof *wanted);
    float **out = rad_alloc(cache->ctx, count, sizeof *out);
    /* Each patch once: one listed is marked -2 in slot_of until the list is made (a small
     * system's every row comes in lists of thousands). */
    size_t k = 0;
    for (size_t i = 0; wanted && out && i < count; ++i) {
        if (patches[i] >= cache->patch_count || cache->slot_of[patches[i]] != -1) continue;
        cache->slot_of[patches[i]] = -2;
        wanted[k++] = patches[i];
    }
    for (size_t j = 0; j < k; ++j) cache->slot_of[wanted[j]] = -1;
    rad_status status = RAD_OK;
    if (!wanted || !out) rad_fail(cache->ctx, RAD_OK, "%s", ""); /* rows one at a time, as asked */
    else if (k && cache->used + k <= cache->capacity) status = prefetch_kept(cache, wanted, k, out);
    rad_free(cache->ctx, wanted);
    rad_free(cache->ctx, out);
    return status;
}

static void cache_destroy(rad_ff_provider *self) {
    cache_provider *cache = (cache_provider *)self;
    rad_context *ctx = cache->ctx;
    rad_ff_provider_destroy(cache->inner);
    for (size_t s = 0; s < cache->used; ++s) rad_free(ctx, cache->slot_row[s]);
    rad_free(ctx, cache->slot_of);
    rad_free(ctx, cache->slot_patch);
    rad_free(ctx, cache->slot_time);
    rad_free(ctx, cache->slot_row);
    rad_free(ctx, cache);
}

const rad_ff_provider *rad_ff_cache_inner(const rad_ff_provider *provider) {
    if (provider && provider->destroy == cache_destroy)
        return ((const cache_provider *)provider)->inner;
    return provider;
}

rad_status rad_ff_cache_create(rad_context *ctx, rad_ff_provider *inner, size_t patch_count,
                               size_t element_count, double bytes, rad_ff_provider **out) {
    *out = inner;
    double row_bytes = 4.0 * (double)(element_count ? element_count : 1);
    double rows = bytes / row_bytes;
    if (rows > (double)patch_count) rows = (double)patch_count;
    size_t capacity = rows > 0 ? (size_t)rows : 0;
    if (capacity < 2 || patch_count > INT32_MAX) return RAD_OK; /* not worth it: no cache */
    cache_provider *cache = rad_alloc_zero(ctx, 1, sizeof *cache);
    if (!cache) goto no_memory;
    cache->ctx = ctx;
    cache->inner = inner;
    cache->patch_count = patch_count;
    cache->element_count = element_count;
    cache->capacity = capacity;
    cache->slot_of = rad_alloc(ctx, patch_count, sizeof *cache->slot_of);
    cache->slot_patch = rad_alloc(ctx, capacity, sizeof *cache->slot_patch);
    cache->slot_time = rad_alloc(ctx, capacity, sizeof *cache->slot_time);
    cache->slot_row = rad_alloc_zero(ctx, capacity, sizeof *cache->slot_row);
    if (!cache->slot_of || !cache->slot_patch || !cache->slot_time ||
        !cache->slot_row) {
        cache->inner = NULL;
        cache_destroy(&cache->base);
        goto no_memory;
    }
    for (size_t p = 0; p < patch_count; ++p) cache->slot_of[p] = -1;
    cache->base.method = inner->method;
    cache->base.row = cache_row;
    cache->base.destroy = cache_destroy;
    cache->base.holds = cache_holds;
    cache->base.prefetch = cache_prefetch;
    *out = &cache->base;
    return RAD_OK;
no_memory:
    rad_ff_provider_destroy(inner);
    *out = NULL;
    return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for the form-factor row cache");
}
