/* factory.c - the list of form-factor methods, the choice of the default, and what every method
 * is built on (the rays of the input geometry, patch outlines, shaft culling, the row cache). */
#include "formfactor/geometric.h"

#include "core/options.h"
#include "core/team.h"
#include "scene/scene.h"

#include <limits.h>
#include <stdatomic.h>
#include <math.h>
#include <string.h>

const rad_ff_provider *rad_ff_cache_inner(const rad_ff_provider *provider);

/* The registry: one line per method, each defined in its own file as rad_ff_method_<name>. A
 * method's rad_ff_method value is its position here plus one, so new methods go at the end.
 * Defaults (samples, hemicube resolution, the default method) chosen by measurement:
 * docs/formfactors.md, "Choosing the default". */
#define RAD_FF_METHODS(X) X(analytic) X(hemicube) X(raycast) X(montecarlo)

#define RAD_FF_DECLARE(name) extern const rad_ff_method_entry rad_ff_method_##name;
RAD_FF_METHODS(RAD_FF_DECLARE)
#define RAD_FF_LIST(name) &rad_ff_method_##name,
static const rad_ff_method_entry *const methods[] = {RAD_FF_METHODS(RAD_FF_LIST)};
#define METHOD_COUNT (sizeof methods / sizeof methods[0])
#define DEFAULT_METHOD RAD_FF_ANALYTIC

/* The row cache may take this share of the memory budget (rad_context_options.max_memory). */
#define CACHE_SHARE 0.25

const rad_ff_method_entry *rad_ff_method_find(rad_ff_method method) {
    if (method == RAD_FF_DEFAULT) method = DEFAULT_METHOD;
    if ((int)method < 1 || (size_t)method > METHOD_COUNT) return NULL;
    return methods[method - 1];
}

const rad_ff_method_entry *rad_ff_method_by_name(const char *name) {
    int method = rad_ff_method_parse(name);
    return method < 0 ? NULL : rad_ff_method_find((rad_ff_method)method);
}

size_t rad_ff_method_count(void) { return METHOD_COUNT; }

const rad_ff_method_info *rad_ff_method_at(size_t index) {
    return index < METHOD_COUNT ? &methods[index]->info : NULL;
}

int rad_ff_method_parse(const char *name) {
    if (!name) return -1;
    if (strcmp(name, "default") == 0) return RAD_FF_DEFAULT;
    for (size_t i = 0; i < METHOD_COUNT; ++i)
        if (strcmp(methods[i]->info.name, name) == 0) return (int)i + 1;
    return -1;
}

void rad_ff_context_release(rad_ff_context *context) {
    if (!context) return;
    rad_rays_destroy(context->rays);
    rad_free(context->ctx, context->patches);
    rad_ff_shaft_destroy(context->shaft);
    rad_free(context->ctx, context->element_radius);
    context->element_radius = NULL;
    context->rays = NULL;
    context->patches = NULL;
    context->shaft = NULL;
}

rad_status rad_ff_context_build(rad_context *ctx, const rad_scene *scene, const rad_mesh *mesh,
                                const rad_ff_options *options, int cull, rad_ff_context *out) {
    memset(out, 0, sizeof *out);
    const rad_ff_method_entry *entry = rad_ff_method_find(options->method);
    if (!entry)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "form-factor method %d is not available",
                        (int)options->method);
    /* The method's own options: only the names it registered, read into the older fields. */
    rad_status checked = rad_options_check(ctx, options->method_options, entry->info.options,
                                           entry->info.option_count, "form-factor method",
                                           entry->info.name);
    if (checked) return checked;
    rad_ff_options resolved = *options;
    resolved.method_options = NULL; /* the caller's bag is not kept */
    double samples = rad_options_number(options->method_options, "ff-samples", options->samples);
    double resolution = rad_options_number(options->method_options, "hemicube-res",
                                           options->hemicube_resolution);
    if (samples != floor(samples) || resolution != floor(resolution) || samples > INT_MAX ||
        resolution > INT_MAX)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "form-factor samples and hemicube resolution must be whole numbers");
    resolved.samples = (int)fmax(samples, INT_MIN);
    resolved.hemicube_resolution = (int)fmax(resolution, INT_MIN);
    options = &resolved;
    if (options->samples < 0 || options->hemicube_resolution < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "form-factor samples and hemicube resolution must be positive");
    if (options->hemicube_resolution > 4096)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "hemicube resolution %d is too large (at most 4096)",
                        options->hemicube_resolution);
    out->ctx = ctx;
    out->mesh = mesh;
    out->options = *options;
    out->options.method = options->method == RAD_FF_DEFAULT ? DEFAULT_METHOD : options->method;
    if (out->options.samples == 0) out->options.samples = entry->info.default_samples;
    if (out->options.samples == 0) out->options.samples = 1;
    if (out->options.hemicube_resolution == 0) {
        const rad_ff_method_entry *hemicube = rad_ff_method_find(RAD_FF_HEMICUBE);
        out->options.hemicube_resolution = hemicube->default_resolution;
    }
    rad_status status = rad_rays_create(ctx, scene, &out->rays);
    if (!status) status = rad_ff_patches_create(ctx, mesh, &out->patches, &out->max_members);
    if (!status && cull)
        status = rad_ff_shaft_create(ctx, scene, mesh, RAD_FF_SHAFT_OCCLUDERS, &out->shaft);
    if (!status) {
        out->element_radius = rad_alloc(ctx, mesh->element_count ? mesh->element_count : 1,
                                        sizeof *out->element_radius);
        if (!out->element_radius) status = RAD_ERROR_NO_MEMORY;
        for (size_t e = 0; e < mesh->element_count && !status; ++e) {
            double radius = 0;
            for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k)
                radius = fmax(radius, v3_length(v3_sub(rad_element_corner(mesh, e, k),
                                                       mesh->element_centroid[e])));
            out->element_radius[e] = radius;
        }
    }
    if (status) rad_ff_context_release(out);
    return status;
}

rad_status rad_ff_create(rad_context *ctx, const rad_scene *scene, const rad_mesh *mesh,
                         const rad_ff_options *options, rad_ff_provider **out) {
    *out = NULL;
    rad_ff_context context;
    rad_status status = rad_ff_context_build(ctx, scene, mesh, options, 1, &context);
    if (status) return status;
    rad_ff_provider *provider = NULL;
    status = rad_ff_method_find(context.options.method)->create(&context, &provider);
    if (status) {
        rad_ff_context_release(&context);
        return status;
    }
    /* Rows are deterministic: keep the ones asked for again (progressive refinement shoots the
     * brightest patches many times) within a share of the memory budget. */
    uint64_t budget = ctx->max_memory ? ctx->max_memory : RAD_DEFAULT_MAX_MEMORY;
    return rad_ff_cache_create(ctx, provider, mesh->patch_count, mesh->element_count,
                               CACHE_SHARE * (double)budget, out);
}

/* ------------------------------------------------------------------------------------------- */

rad_status rad_ff_common_create(const rad_ff_context *context, size_t size, const char *method,
                                rad_status (*row)(rad_ff_provider *, size_t, float *),
                                void (*destroy)(rad_ff_provider *), rad_ff_common **out) {
    *out = NULL;
    rad_context *ctx = context->ctx;
    rad_ff_common *common = rad_alloc_zero(ctx, 1, size);
    if (!common) return RAD_ERROR_NO_MEMORY;
    common->maps[0] = rad_alloc(ctx, (size_t)context->max_members, sizeof *common->maps[0]);
    common->views[0] = rad_ff_shaft_view_create(context->shaft);
    if (!common->maps[0] || (context->shaft && !common->views[0])) {
        rad_ff_shaft_view_destroy(common->views[0]);
        rad_free(ctx, common->maps[0]);
        rad_free(ctx, common);
        return RAD_ERROR_NO_MEMORY;
    }
    common->c = *context;
    common->base.method = method;
    common->base.row = row;
    common->base.destroy = destroy;
    *out = common;
    return RAD_OK;
}

void rad_ff_common_destroy(rad_ff_common *common) {
    if (!common) return;
    rad_context *ctx = common->c.ctx;
    rad_ff_context_release(&common->c);
    for (int slot = 0; slot < RAD_FF_ROWS_AHEAD; ++slot) {
        rad_free(ctx, common->maps[slot]);
        rad_ff_shaft_view_destroy(common->views[slot]);
    }
    rad_free(ctx, common);
}

rad_ff_stats rad_ff_provider_stats(const rad_ff_provider *provider) {
    rad_ff_stats none = {0, 0, 0};
    if (!provider) return none;
    provider = rad_ff_cache_inner(provider);
    if (!rad_ff_method_by_name(provider->method)) return none;
    return ((const rad_ff_common *)provider)->stats;
}

const char *rad_ff_method_name(rad_ff_method method) {
    const rad_ff_method_entry *entry = rad_ff_method_find(method);
    return entry ? entry->info.name : NULL;
}

void rad_ff_row_begin(rad_ff_common *common, size_t patch, int slot, rad_ff_row *row) {
    const rad_ff_context *c = &common->c;
    row->c = c;
    row->mesh = c->mesh;
    row->rays = c->rays;
    rad_ff_source_begin(&row->source, c, patch, c->options.samples, common->maps[slot]);
    row->shaft = common->views[slot];
    rad_ff_shaft_begin(c->shaft, common->views[slot], row->source.patch);
    row->p = row->source.patch;
    row->patch = patch;
    row->np = row->p->normal;
    row->epsilon = c->rays->epsilon;
    row->inverse_area = 1.0 / row->p->area;
    row->samples = c->options.samples;
    row->seed = rad_ff_row_seed(c, patch);
    row->n = (long)c->mesh->element_count;
    row->blocks = (row->n + RAD_FF_BLOCK - 1) / RAD_FF_BLOCK;
}

void rad_ff_row_end(rad_ff_common *common, uint64_t receivers, uint64_t rays) {
    common->stats.rows++;
    common->stats.receivers += receivers;
    common->stats.rays += rays;
}

/* Rows in flight: block index i is block i % blocks of row i / blocks (every row of a mesh has
 * the same blocks). */
typedef struct {
    rad_ff_common *common;
    const size_t *patches;
    rad_ff_row row[RAD_FF_ROWS_AHEAD];
    rad_ff_block_fn block;
    float *const *out;
    long blocks;
    _Atomic uint64_t receivers[RAD_FF_ROWS_AHEAD], rays[RAD_FF_ROWS_AHEAD];
} row_run;

static void row_run_begin(void *user, long slot, int worker) {
    (void)worker;
    row_run *run = user;
    rad_ff_row_begin(run->common, run->patches[slot], (int)slot, &run->row[slot]);
}

static void row_run_block(void *user, long index, int worker) {
    (void)worker;
    row_run *run = user;
    const long slot = index / run->blocks;
    rad_ff_block b;
    rad_ff_block_begin(&run->row[slot], index % run->blocks, &b);
    run->block(&run->row[slot], &b, run->out[slot]);
    atomic_fetch_add_explicit(&run->receivers[slot], b.receivers, memory_order_relaxed);
    atomic_fetch_add_explicit(&run->rays[slot], b.queue.cast, memory_order_relaxed);
}

/* The scratch of slots [1, count) (slot 0 is made with the provider), each made the first time
 * so many rows are in flight. */
static rad_status scratch_make(rad_ff_common *common, size_t count) {
    rad_context *ctx = common->c.ctx;
    for (size_t slot = 1; slot < count; ++slot) {
        if (!common->maps[slot])
            common->maps[slot] = rad_alloc(ctx, (size_t)common->c.max_members, sizeof *common->maps[slot]);
        if (common->c.shaft && !common->views[slot])
            common->views[slot] = rad_ff_shaft_view_create(common->c.shaft);
        if (!common->maps[slot] || (common->c.shaft && !common->views[slot])) return RAD_ERROR_NO_MEMORY;
    }
    return RAD_OK;
}

/* Many rows (a small system's every row: shooting.c): one task a row, computed whole by one
 * thread in that thread's scratch slot, so one parallel loop for them all where eight rows at a
 * time wake the workers twice per eight (the Cornell box's 804 rows: 202 loops, each costing
 * the waking of a sleeping worker). The same values: a row's blocks do not depend on the thread
 * or the order that computes them. */
typedef struct {
    rad_ff_common *common;
    const size_t *patches;
    rad_ff_block_fn block;
    float *const *out;
    uint64_t (*tally)[2]; /* per row: receivers, rays */
} rows_each_job;

static void rows_each_task(void *user, long index, int worker) {
    rows_each_job *job = user;
    rad_ff_row row;
    rad_ff_row_begin(job->common, job->patches[index], worker, &row);
    uint64_t receivers = 0, rays = 0;
    for (long k = 0; k < row.blocks; ++k) {
        rad_ff_block b;
        rad_ff_block_begin(&row, k, &b);
        job->block(&row, &b, job->out[index]);
        receivers += b.receivers;
        rays += b.queue.cast;
    }
    job->tally[index][0] = receivers;
    job->tally[index][1] = rays;
}

static rad_status rows_each(rad_ff_common *common, const size_t *patches, size_t count,
                            rad_ff_block_fn block, float *const *out) {
    rad_context *ctx = common->c.ctx;
    const int threads = rad_thread_count(ctx);
    if (threads > RAD_FF_ROWS_AHEAD) { /* more threads than scratch slots: eight at a time */
        for (size_t first = 0; first < count; first += RAD_FF_ROWS_AHEAD) {
            size_t n = count - first < RAD_FF_ROWS_AHEAD ? count - first : RAD_FF_ROWS_AHEAD;
            rad_status status = rad_ff_rows_run(common, patches + first, n, block, out + first);
            if (status) return status;
        }
        return RAD_OK;
    }
    rad_status status = scratch_make(common, (size_t)threads);
    if (status) return status;
    rows_each_job job = {common, patches, block, out, rad_alloc(ctx, count, sizeof *job.tally)};
    if (!job.tally) return RAD_ERROR_NO_MEMORY;
    rad_team_for(ctx, (long)count, rows_each_task, &job);
    for (size_t i = 0; i < count; ++i) rad_ff_row_end(common, job.tally[i][0], job.tally[i][1]);
    rad_free(ctx, job.tally);
    return RAD_OK;
}

rad_status rad_ff_rows_run(rad_ff_common *common, const size_t *patches, size_t count,
                           rad_ff_block_fn block, float *const *out) {
    if (count > RAD_FF_ROWS_AHEAD) return rows_each(common, patches, count, block, out);
    rad_context *ctx = common->c.ctx;
    rad_status status = scratch_make(common, count);
    if (status) return status;
    row_run rows, *run = &rows;
    memset(run, 0, sizeof *run);
    run->common = common;
    run->patches = patches;
    run->block = block;
    run->out = out;
    if (count == 1) row_run_begin(run, 0, 0);
    else rad_team_for(ctx, (long)count, row_run_begin, run);
    run->blocks = run->row[0].blocks;
    rad_team_for(ctx, run->blocks * (long)count, row_run_block, run);
    for (size_t slot = 0; slot < count; ++slot)
        rad_ff_row_end(common, atomic_load(&run->receivers[slot]), atomic_load(&run->rays[slot]));
    return RAD_OK;
}

rad_status rad_ff_row_run(rad_ff_common *common, size_t patch, rad_ff_block_fn block, float *out) {
    return rad_ff_rows_run(common, &patch, 1, block, &out);
}
