/* emitters.c - the emitter table (see emitters.h). */
#include "light/emitters.h"

#include <math.h>

rad_status rad_emitter_table_reserve(rad_context *ctx, rad_emitter_table *table, size_t capacity) {
    table->count = 0;
    table->capacity = 0;
    if (capacity == 0) return RAD_OK;
    table->emitters = rad_alloc(ctx, capacity, sizeof *table->emitters);
    table->cdf = rad_alloc(ctx, capacity, sizeof *table->cdf);
    table->guide = capacity < UINT32_MAX ? rad_alloc(ctx, capacity + 1, sizeof *table->guide) : NULL;
    if (!table->emitters || !table->cdf || !table->guide) return RAD_ERROR_NO_MEMORY;
    table->capacity = capacity;
    return RAD_OK;
}

int32_t rad_emitter_table_add(rad_emitter_table *table, rad_vec3 a, rad_vec3 b, rad_vec3 c,
                              rad_vec3 normal, const double radiance[3]) {
    if (table->count >= table->capacity) return -1;
    rad_emitter t;
    t.p0 = a;
    t.e1 = v3_sub(b, a);
    t.e2 = v3_sub(c, a);
    t.area = 0.5 * v3_length(v3_cross(t.e1, t.e2));
    if (!(t.area > 0)) return -1;
    t.normal = normal;
    for (int k = 0; k < 3; ++k) t.radiance[k] = radiance[k];
    t.parallelogram = 0;
    table->emitters[table->count] = t;
    return (int32_t)table->count++;
}

int32_t rad_emitter_table_add_parallelogram(rad_emitter_table *table, rad_vec3 p0, rad_vec3 e1,
                                            rad_vec3 e2, rad_vec3 normal, const double radiance[3]) {
    int32_t k = rad_emitter_table_add(table, p0, v3_add(p0, e1), v3_add(p0, e2), normal, radiance);
    if (k < 0) return k;
    table->emitters[k].area *= 2;
    table->emitters[k].parallelogram = 1;
    return k;
}

/* The point of entry `light` for (u0, u1): uniform on its parallelogram or triangle (Turk 1990). */
static rad_vec3 emitter_point(const rad_emitter *light, double u0, double u1) {
    if (light->parallelogram)
        return v3_add(light->p0, v3_add(v3_scale(light->e1, u0), v3_scale(light->e2, u1)));
    double root = sqrt(u0);
    return v3_add(light->p0, v3_add(v3_scale(light->e1, root * (1 - u1)),
                                    v3_scale(light->e2, root * u1)));
}

void rad_emitter_table_finish(rad_emitter_table *table, rad_emitter_selection selection) {
    /* Cumulative weights, then normalised: the last entry is exactly 1. */
    double total = 0;
    for (size_t i = 0; i < table->count; ++i) {
        const rad_emitter *e = &table->emitters[i];
        double weight = selection == RAD_EMITTERS_BY_AREA
                            ? e->area
                            : e->area * (e->radiance[0] + e->radiance[1] + e->radiance[2]);
        total += weight;
        table->cdf[i] = total;
    }
    if (!(total > 0)) {
        table->count = 0;
        return;
    }
    for (size_t i = 0; i < table->count; ++i) table->cdf[i] /= total;
    table->cdf[table->count - 1] = 1;
    size_t first = 0;
    for (size_t b = 0; b <= table->count; ++b) {
        double u = (double)b / (double)table->count;
        while (first + 1 < table->count && table->cdf[first] <= u) ++first;
        table->guide[b] = (uint32_t)first;
    }
}

void rad_emitter_table_free(rad_context *ctx, rad_emitter_table *table) {
    rad_free(ctx, table->emitters);
    rad_free(ctx, table->cdf);
    rad_free(ctx, table->guide);
    *table = (rad_emitter_table){0};
}

/* The triangle whose share of the cumulative distribution holds u, and u rescaled to [0, 1)
 * inside that share (so one number picks the triangle and places the point). */
static size_t pick(const rad_emitter_table *table, double *u) {
    /* The first entry with cdf > u lies between the guides of u's bucket and the next one. */
    size_t bucket = (size_t)(*u * (double)table->count);
    if (bucket >= table->count) bucket = table->count - 1;
    size_t lo = table->guide[bucket], hi = table->guide[bucket + 1];
    while (lo < hi) { /* the first entry with cdf > u */
        size_t mid = (lo + hi) / 2;
        if (table->cdf[mid] <= *u) lo = mid + 1;
        else hi = mid;
    }
    /* u's bucket by rounding may be one off where a cdf entry lies within an ulp of its edge. */
    while (lo > 0 && table->cdf[lo - 1] > *u) --lo;
    while (lo + 1 < table->count && table->cdf[lo] <= *u) ++lo;
    double before = lo ? table->cdf[lo - 1] : 0;
    double p = table->cdf[lo] - before;
    *u = p > 0 ? fmin((*u - before) / p, 0x1.fffffffffffffp-1) : 0;
    return lo;
}

int rad_emitter_table_sample(const rad_emitter_table *table, double u0, double u1, rad_vec3 x,
                             rad_emitter_point *out) {
    if (table->count == 0) return 0;
    size_t k = pick(table, &u0);
    const rad_emitter *light = &table->emitters[k];
    out->position = emitter_point(light, u0, u1);
    rad_vec3 to_light = v3_sub(out->position, x);
    double distance2 = v3_dot(to_light, to_light);
    if (!(distance2 > 0)) return 0;
    out->direction = v3_scale(to_light, 1 / sqrt(distance2));
    double cos_y = -v3_dot(light->normal, out->direction);
    if (cos_y <= 0) return 0;
    out->distance2 = distance2;
    out->pdf = rad_emitter_table_probability(table, k) / light->area * distance2 / cos_y;
    out->radiance = light->radiance;
    out->index = k;
    return 1;
}

double rad_emitter_table_pdf(const rad_emitter_table *table, size_t k, rad_vec3 direction,
                             double distance) {
    if (k >= table->count) return 0;
    const rad_emitter *light = &table->emitters[k];
    double cos_y = -v3_dot(light->normal, direction);
    if (cos_y <= 0) return 0;
    return rad_emitter_table_probability(table, k) / light->area * distance * distance / cos_y;
}

size_t rad_emitter_table_sample_point(const rad_emitter_table *table, double u0, double u1,
                                      rad_vec3 *position) {
    size_t k = pick(table, &u0);
    *position = emitter_point(&table->emitters[k], u0, u1);
    return k;
}
