/* system.c - building systems, their bookkeeping and the public getters. */
#include "system/system.h"

#include "system/solution_view.h"

#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mesh/mesh.h"

rad_status rad_system_alloc(rad_context *ctx, size_t elements, size_t patches, size_t surfaces,
                            rad_system **out) {
    *out = NULL;
    rad_system *s = rad_alloc_zero(ctx, 1, sizeof *s);
    if (!s) return RAD_ERROR_NO_MEMORY;
    s->ctx = ctx;
    s->element_count = elements;
    s->patch_count = patches;
    s->surface_count = surfaces;
    s->area = rad_alloc_zero(ctx, elements, sizeof *s->area);
    s->reflectance = rad_alloc_zero(ctx, elements, sizeof *s->reflectance);
    s->emission = rad_alloc_zero(ctx, elements, sizeof *s->emission);
    s->element_patch = rad_alloc_zero(ctx, elements, sizeof *s->element_patch);
    s->element_surface = rad_alloc_zero(ctx, elements, sizeof *s->element_surface);
    s->patch_first = rad_alloc_zero(ctx, patches + 1, sizeof *s->patch_first);
    s->patch_area = rad_alloc_zero(ctx, patches, sizeof *s->patch_area);
    s->surface_name = rad_alloc_zero(ctx, surfaces, sizeof *s->surface_name);
    s->surface_area = rad_alloc_zero(ctx, surfaces, sizeof *s->surface_area);
    s->surface_first = rad_alloc_zero(ctx, surfaces + 1, sizeof *s->surface_first);
    s->surface_elements = rad_alloc_zero(ctx, elements, sizeof *s->surface_elements);
    s->radiosity = rad_alloc_zero(ctx, elements, sizeof *s->radiosity);
    s->unshot = rad_alloc_zero(ctx, elements, sizeof *s->unshot);
    if (!s->area || !s->reflectance || !s->emission || !s->element_patch || !s->element_surface ||
        !s->patch_first || !s->patch_area || !s->surface_name || !s->surface_area ||
        !s->surface_first || !s->surface_elements || !s->radiosity || !s->unshot) {
        rad_system_destroy(s);
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for a system of %zu elements",
                        elements);
    }
    s->view.ops = &rad_uniform_view_ops;
    s->view.state = s;
    *out = s;
    return RAD_OK;
}

void rad_system_destroy(rad_system *s) {
    if (!s) return;
    rad_context *ctx = s->ctx;
    rad_system_set_view(s, NULL, NULL);
    rad_ff_provider_destroy(s->ff);
    rad_mesh_destroy(s->mesh);
    rad_scene_destroy(s->geometry);
    if (s->surface_name)
        for (size_t i = 0; i < s->surface_count; ++i) rad_free(ctx, s->surface_name[i]);
    rad_free(ctx, s->area);
    rad_free(ctx, s->reflectance);
    rad_free(ctx, s->emission);
    rad_free(ctx, s->light_emission);
    rad_free(ctx, s->specular_emission);
    rad_free(ctx, s->specular_reflection);
    rad_free(ctx, s->caustic_landings);
    rad_free(ctx, s->element_patch);
    rad_free(ctx, s->element_surface);
    rad_free(ctx, s->patch_first);
    rad_free(ctx, s->patch_area);
    rad_free(ctx, s->surface_name);
    rad_free(ctx, s->surface_area);
    rad_free(ctx, s->surface_first);
    rad_free(ctx, s->surface_elements);
    rad_free(ctx, s->radiosity);
    rad_free(ctx, s->unshot);
    rad_free(ctx, s);
}

void rad_system_finish_areas(rad_system *s) {
    for (size_t p = 0; p < s->patch_count; ++p) {
        double area = 0;
        for (size_t e = s->patch_first[p]; e < s->patch_first[p + 1]; ++e) area += s->area[e];
        s->patch_area[p] = area;
    }
    memset(s->surface_area, 0, s->surface_count * sizeof *s->surface_area);
    for (size_t e = 0; e < s->element_count; ++e) s->surface_area[s->element_surface[e]] += s->area[e];
    /* Each surface's elements (a counting sort, increasing within each surface). */
    memset(s->surface_first, 0, (s->surface_count + 1) * sizeof *s->surface_first);
    for (size_t e = 0; e < s->element_count; ++e) s->surface_first[s->element_surface[e] + 1]++;
    for (size_t i = 0; i < s->surface_count; ++i) s->surface_first[i + 1] += s->surface_first[i];
    for (size_t e = 0; e < s->element_count; ++e) {
        uint32_t i = s->element_surface[e];
        s->surface_elements[s->surface_first[i]++] = (uint32_t)e;
    }
    for (size_t i = s->surface_count; i > 0; --i) s->surface_first[i] = s->surface_first[i - 1];
    s->surface_first[0] = 0;
}

rad_status rad_system_check_finite(rad_system *s, const char *source) {
    double total = 0;
    for (size_t i = 0; i < s->surface_count; ++i) total += s->surface_area[i];
    if (!isfinite(total))
        return rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: the total area (%g) is not a "
                        "finite number; scale the scene down", source, total);
    double *power = rad_alloc_zero(s->ctx, s->surface_count, sizeof *power);
    if (!power) return RAD_ERROR_NO_MEMORY;
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c) power[s->element_surface[e]] += s->area[e] * s->emission[e][c];
    rad_status status = RAD_OK;
    total = 0;
    for (size_t i = 0; i < s->surface_count && !status; ++i) {
        total += power[i];
        if (!isfinite(power[i]) || !isfinite(total))
            status = rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: surface '%s': its emitted "
                              "power (area %g times its emission) is not a finite number, and "
                              "no radiosity would be; scale the scene or its emission down",
                              source, s->surface_name[i] ? s->surface_name[i] : "?",
                              s->surface_area[i]);
    }
    rad_free(s->ctx, power);
    return status;
}

void rad_system_patch_mean(const rad_system *s, const rad_rgb *per_element, size_t patch,
                           double out[3]) {
    double sum[3] = {0, 0, 0};
    for (size_t e = s->patch_first[patch]; e < s->patch_first[patch + 1]; ++e)
        for (int c = 0; c < 3; ++c) sum[c] += per_element[e][c] * s->area[e];
    for (int c = 0; c < 3; ++c) out[c] = sum[c] / s->patch_area[patch];
}

void rad_system_surface_means(const rad_system *s, const rad_rgb *per_element, rad_rgb *out) {
    memset(out, 0, s->surface_count * sizeof *out);
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c) out[s->element_surface[e]][c] += per_element[e][c] * s->area[e];
    for (size_t i = 0; i < s->surface_count; ++i)
        for (int c = 0; c < 3; ++c)
            out[i][c] = s->surface_area[i] > 0 ? out[i][c] / s->surface_area[i] : 0;
}

void rad_system_reset(rad_system *s) {
    if (!s) return;
    memcpy(s->radiosity, s->emission, s->element_count * sizeof *s->radiosity);
    memcpy(s->unshot, s->emission, s->element_count * sizeof *s->unshot);
    memset(s->ambient, 0, sizeof s->ambient);
}

/* A patch system: one patch, one element and one surface per .ffm patch. */
static rad_status system_from_patches(rad_context *ctx, const char *source,
                                      const rad_patch_desc *patches, size_t n, const double *ff,
                                      const float *ff_float, rad_system **out) {
    rad_system *s;
    rad_status status = rad_system_alloc(ctx, n, n, n, &s);
    if (status) return status;
    for (size_t i = 0; i < n; ++i) {
        if (!(patches[i].area > 0)) {
            rad_system_destroy(s);
            return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "patch %zu: area must be positive", i);
        }
        s->area[i] = patches[i].area;
        for (int c = 0; c < 3; ++c) {
            s->reflectance[i][c] = patches[i].reflectance[c];
            s->emission[i][c] = patches[i].emission[c];
        }
        s->element_patch[i] = (uint32_t)i;
        s->element_surface[i] = (uint32_t)i;
        s->patch_first[i] = i;
        char fallback[32];
        snprintf(fallback, sizeof fallback, "patch%zu", i);
        s->surface_name[i] = rad_strdup(ctx, patches[i].name ? patches[i].name : fallback);
        if (!s->surface_name[i]) {
            rad_system_destroy(s);
            return RAD_ERROR_NO_MEMORY;
        }
    }
    s->patch_first[n] = n;
    rad_system_finish_areas(s);
    status = rad_system_check_finite(s, source);
    if (!status) status = rad_ff_given_create(ctx, n, ff, ff_float, &s->ff);
    if (status) {
        rad_system_destroy(s);
        return status;
    }
    rad_system_reset(s);
    *out = s;
    return RAD_OK;
}

rad_status rad_system_create_dense(rad_context *ctx, const rad_patch_desc *patches, size_t count,
                                   const float *form_factors, rad_system **out) {
    if (!ctx || !patches || !form_factors || !out || count == 0) return RAD_ERROR_INVALID_ARGUMENT;
    return system_from_patches(ctx, "the patch system", patches, count, NULL, form_factors, out);
}

rad_status rad_system_create(rad_context *ctx, const rad_scene *scene, const rad_mesh_options *mesh,
                             const rad_ff_options *ff, rad_system **out) {
    if (!ctx || !scene || !out) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    if (scene->geometric) {
        rad_mesh_options mesh_defaults = {0};
        rad_ff_options ff_defaults = {0};
        return rad_system_from_geometry(ctx, scene, mesh ? mesh : &mesh_defaults,
                                        ff ? ff : &ff_defaults, out);
    }
    size_t n = scene->patch_count;
    rad_patch_desc *patches = rad_alloc(ctx, n, sizeof *patches);
    if (!patches) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < n; ++i) {
        patches[i].name = scene->patches[i].name;
        patches[i].area = scene->patches[i].area;
        memcpy(patches[i].reflectance, scene->patches[i].reflectance, sizeof patches[i].reflectance);
        memcpy(patches[i].emission, scene->patches[i].emission, sizeof patches[i].emission);
    }
    rad_status status = system_from_patches(ctx, scene->source, patches, n, scene->form_factors, NULL, out);
    rad_free(ctx, patches);
    return status;
}

size_t rad_system_surface_count(const rad_system *s) { return s ? s->surface_count : 0; }
size_t rad_system_patch_count(const rad_system *s) { return s ? s->patch_count : 0; }
size_t rad_system_element_count(const rad_system *s) { return s ? s->element_count : 0; }

rad_status rad_system_surface(const rad_system *s, size_t index, rad_surface_info *out) {
    if (!s || !out || index >= s->surface_count) return RAD_ERROR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    out->name = s->surface_name[index];
    out->area = s->surface_area[index];
    for (size_t k = s->surface_first[index]; k < s->surface_first[index + 1]; ++k) {
        size_t e = s->surface_elements[k];
        double w = s->area[e] / out->area;
        for (int c = 0; c < 3; ++c) {
            out->reflectance[c] += w * s->reflectance[e][c];
            out->emission[c] += w * s->emission[e][c];
            out->radiosity[c] += w * s->radiosity[e][c];
            out->unshot[c] += w * s->unshot[e][c];
        }
    }
    for (int c = 0; c < 3; ++c) out->power[c] = out->radiosity[c] * out->area;
    return RAD_OK;
}

rad_status rad_system_element_radiosity(const rad_system *s, size_t element, double radiosity[3]) {
    if (!s || element >= s->element_count) return RAD_ERROR_INVALID_ARGUMENT;
    if (radiosity)
        for (int c = 0; c < 3; ++c) radiosity[c] = s->radiosity[element][c];
    return RAD_OK;
}

rad_status rad_system_surface_form_factors(rad_system *s, double *matrix) {
    if (!s || !matrix) return RAD_ERROR_INVALID_ARGUMENT;
    size_t ns = s->surface_count;
    memset(matrix, 0, ns * ns * sizeof *matrix);
    float *row = rad_alloc(s->ctx, s->element_count, sizeof *row);
    double *patch_to_surface = rad_alloc(s->ctx, ns, sizeof *patch_to_surface);
    if (!row || !patch_to_surface) {
        rad_free(s->ctx, row);
        rad_free(s->ctx, patch_to_surface);
        return RAD_ERROR_NO_MEMORY;
    }
    rad_status status = RAD_OK;
    /* F(surface i -> surface j) = sum over patches p of i of (A_p / A_i) sum_{e in j} F_pe. */
    for (size_t p = 0; p < s->patch_count && !status; ++p) {
        status = s->ff->row(s->ff, p, row);
        if (status) break;
        memset(patch_to_surface, 0, ns * sizeof *patch_to_surface);
        for (size_t e = 0; e < s->element_count; ++e) patch_to_surface[s->element_surface[e]] += row[e];
        size_t i = s->element_surface[s->patch_first[p]];
        double weight = s->patch_area[p] / s->surface_area[i];
        for (size_t j = 0; j < ns; ++j) matrix[i * ns + j] += weight * patch_to_surface[j];
        if (rad_progress(s->ctx, "form factors", (double)(p + 1), (double)s->patch_count))
            status = rad_fail(s->ctx, RAD_ERROR_CANCELLED, "cancelled");
    }
    rad_free(s->ctx, row);
    rad_free(s->ctx, patch_to_surface);
    return status;
}

const char *rad_system_ff_method(const rad_system *system) {
    return system && system->ff ? system->ff->method : NULL;
}
