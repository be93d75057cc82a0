/* emitters.c - the emitter table (see emitters.h). */
#include "light/emitters.h"

#include <math.h>

rad_status rad_emitter_table_reserve(rad_context *ctx, rad_emitter_table *table, size_t capacity) {
    table->count = 0;
    table->capacity = 0;
    table->group_count = 0;
    if (capacity == 0) return RAD_OK;
    table->emitters = rad_alloc(ctx, capacity, sizeof *table->emitters);
    table->cdf = rad_alloc(ctx, capacity, sizeof *table->cdf);
    table->guide = capacity < UINT32_MAX ? rad_alloc(ctx, capacity + 1, sizeof *table->guide) : NULL;
    table->group_first = rad_alloc_zero(ctx, capacity + 1, sizeof *table->group_first);
    table->groups = rad_alloc(ctx, capacity, sizeof *table->groups);
    if (!table->emitters || !table->cdf || !table->guide || !table->group_first || !table->groups)
        return RAD_ERROR_NO_MEMORY;
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

void rad_emitter_table_close_group(rad_emitter_table *table) {
    if (!table->capacity || table->count == table->group_first[table->group_count]) return;
    table->group_first[++table->group_count] = (uint32_t)table->count;
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
    /* Entries added after the last group ended (or in a table without groups) make none. */
    if (table->group_count && table->group_first[table->group_count] != table->count)
        table->group_count = 0;
    for (size_t g = 0; g < table->group_count; ++g) {
        struct rad_emitter_group *group = &table->groups[g];
        uint32_t first = table->group_first[g], end = table->group_first[g + 1];
        rad_vec3 weighted = v3(0, 0, 0);
        group->area = 0;
        for (uint32_t k = first; k < end; ++k) {
            const rad_emitter *e = &table->emitters[k];
            double to_centre = e->parallelogram ? 0.5 : 1.0 / 3;
            rad_vec3 centre = v3_add(e->p0, v3_scale(v3_add(e->e1, e->e2), to_centre));
            weighted = v3_add(weighted, v3_scale(centre, e->area));
            group->area += e->area;
        }
        group->p0 = table->emitters[first].p0;
        group->normal = table->emitters[first].normal;
        group->centre = v3_scale(weighted, 1 / group->area);
        group->probability = table->cdf[end - 1] - (first ? table->cdf[first - 1] : 0);
    }
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
    rad_free(ctx, table->group_first);
    rad_free(ctx, table->groups);
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

/* The choice for a receiver (tables of 2 to RAD_EMITTERS_LOCAL_MAX groups). Group g's local
 * weight at x is its global probability (its power) times h / (d^2 + A)^(3/2), h the height of
 * x in front of g's plane, d the distance to g's centre and A its area: the irradiance a small
 * lamp gives at distance d and height h (L A cos_y / d^2 with cos_y = h / d), kept finite near
 * large ones; 0 behind the plane, from where g sends nothing to x. The group's probability
 * mixes it with the global one, LOCAL_GLOBAL_SHARE of it, so that a lamp near x but behind a
 * wall cannot take every sample from the lamps that do light x: occlusion is not known here. */
#define LOCAL_GLOBAL_SHARE 0.25

static int local_choice(const rad_emitter_table *table) {
    return table->group_count > 1 && table->group_count <= RAD_EMITTERS_LOCAL_MAX;
}

/* The groups' probabilities P_g(x) into p[0 .. group_count). */
static void group_probabilities(const rad_emitter_table *table, rad_vec3 x, double *p) {
    double total = 0;
    for (size_t g = 0; g < table->group_count; ++g) {
        const struct rad_emitter_group *group = &table->groups[g];
        double h = v3_dot(v3_sub(x, group->p0), group->normal);
        rad_vec3 d = v3_sub(x, group->centre);
        double s = v3_dot(d, d) + group->area;
        total += (p[g] = h > 0 ? group->probability * h / (s * sqrt(s)) : 0);
    }
    for (size_t g = 0; g < table->group_count; ++g) {
        double global = table->groups[g].probability;
        p[g] = total > 0 ? (1 - LOCAL_GLOBAL_SHARE) * p[g] / total + LOCAL_GLOBAL_SHARE * global
                         : global;
    }
}

/* An entry for receiver x: the group holding u under P_g(x), then the entry in it by the global
 * distribution, u rescaled and reused at each step. Its probability P_k(x) in *probability. */
static size_t pick_local(const rad_emitter_table *table, rad_vec3 x, double *u,
                         double *probability) {
    double p[RAD_EMITTERS_LOCAL_MAX], before = 0;
    group_probabilities(table, x, p);
    size_t g = 0;
    while (g + 1 < table->group_count && *u >= before + p[g]) before += p[g++];
    double v = p[g] > 0 ? fmin(fmax(*u - before, 0) / p[g], 0x1.fffffffffffffp-1) : 0;
    /* Within the group: its span of the cumulative distribution. */
    uint32_t first = table->group_first[g], last = table->group_first[g + 1] - 1;
    double low = first ? table->cdf[first - 1] : 0;
    double w = low + v * table->groups[g].probability;
    size_t k = pick(table, &w);
    if (k < first || k > last) { /* rounding at the span's ends */
        k = k < first ? first : last;
        w = v;
    }
    *u = w;
    *probability = p[g] * rad_emitter_table_probability(table, k) / table->groups[g].probability;
    return k;
}

int rad_emitter_table_sample(const rad_emitter_table *table, double u0, double u1, rad_vec3 x,
                             rad_emitter_point *out) {
    if (table->count == 0) return 0;
    size_t k;
    double probability;
    if (local_choice(table)) {
        k = pick_local(table, x, &u0, &probability);
    } else {
        k = pick(table, &u0);
        probability = rad_emitter_table_probability(table, k);
    }
    const rad_emitter *light = &table->emitters[k];
    out->position = emitter_point(light, u0, u1);
    rad_vec3 to_light = v3_sub(out->position, x);
    double distance2 = v3_dot(to_light, to_light);
    if (!(distance2 > 0)) return 0;
    out->direction = v3_scale(to_light, 1 / sqrt(distance2));
    double cos_y = -v3_dot(light->normal, out->direction);
    if (cos_y <= 0) return 0;
    out->distance2 = distance2;
    out->pdf = probability / light->area * distance2 / cos_y;
    out->radiance = light->radiance;
    out->index = k;
    return 1;
}

double rad_emitter_table_pdf(const rad_emitter_table *table, size_t k, rad_vec3 x,
                             rad_vec3 direction, double distance) {
    if (k >= table->count) return 0;
    const rad_emitter *light = &table->emitters[k];
    double cos_y = -v3_dot(light->normal, direction);
    if (cos_y <= 0) return 0;
    double probability = rad_emitter_table_probability(table, k);
    if (local_choice(table)) {
        /* k's group: the last whose first entry is at most k. */
        size_t lo = 0, hi = table->group_count - 1;
        while (lo < hi) {
            size_t mid = (lo + hi + 1) / 2;
            if (table->group_first[mid] <= k) lo = mid;
            else hi = mid - 1;
        }
        double p[RAD_EMITTERS_LOCAL_MAX];
        group_probabilities(table, x, p);
        probability *= p[lo] / table->groups[lo].probability;
    }
    return probability / light->area * distance * distance / cos_y;
}

size_t rad_emitter_table_sample_point(const rad_emitter_table *table, double u0, double u1,
                                      rad_vec3 *position) {
    size_t k = pick(table, &u0);
    *position = emitter_point(&table->emitters[k], u0, u1);
    return k;
}
