/* emitters.h - the emitter table: the emitting surfaces of a scene cut into triangles, one
 * distribution to pick a point on them, and the density of that choice (docs/rendering.md,
 * "Light sampling"). Shared by every method that samples light: the path tracer
 * (render/pathtrace.c) builds it from the scene's emitting polygons, the renderer's final gather
 * and second pass (render/final_gather.c, render/second_pass.c) from the emitting elements.
 *
 * A sample for two uniform numbers (u0, u1): a triangle k with probability P_k (by power, area
 * times summed emitted radiance, or by area), u0 rescaled inside k's share of the cumulative
 * distribution and reused, then a point uniform on k (Turk 1990: sqrt(u0) along the edges). Its
 * density at the receiver x is the area density P_k / A_k turned to solid angle:
 *     pdf(w) = P_k / A_k * |x - y|^2 / cos(theta_y)    (Veach 1997, sec. 8.2.2).
 * A table whose entries were put in 2 to RAD_EMITTERS_LOCAL_MAX groups (one per lamp:
 * rad_emitter_table_close_group) picks the group for the receiver x instead, then the entry in
 * it by power: P_k(x) = P_g(x) P_k / P_g, P_g(x) by the light group g would bring to x
 * unoccluded, roughly, mixed with the global choice (emitters.c, group_probabilities). The
 * final gather in a generated office of 169 lamps drew its emitter samples mostly on lamps far
 * from the point, and its walls and floor were speckled. The density is then P_k(x) / A_k
 * turned to solid angle. With more groups than that, P_g(x) comes from a light tree over the
 * groups (Conty Estevez & Kulla 2018), in O(log groups) a sample. */
#ifndef RAD_LIGHT_EMITTERS_H
#define RAD_LIGHT_EMITTERS_H

#define RAD_EMITTERS_LOCAL_MAX 256

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>

/* One emitting triangle: p = p0 + s e1 + t e2, s, t >= 0, s + t <= 1; or a parallelogram,
 * s, t in [0, 1). */
typedef struct rad_emitter {
    rad_vec3 p0, e1, e2;
    rad_vec3 normal;    /* front, unit: only the front emits */
    double area;
    double radiance[3]; /* emitted radiance L_e */
    int parallelogram;  /* a parallelogram (rad_emitter_table_add_parallelogram), not a triangle */
} rad_emitter;

/* How a triangle is picked. */
typedef enum rad_emitter_selection {
    RAD_EMITTERS_BY_POWER = 0, /* P_k proportional to A_k (L_r + L_g + L_b) */
    RAD_EMITTERS_BY_AREA       /* P_k proportional to A_k */
} rad_emitter_selection;

typedef struct rad_emitter_table {
    size_t count, capacity;
    rad_emitter *emitters;
    double *cdf; /* count entries, the last is 1 (after rad_emitter_table_finish) */
    /* A guide table (Chen & Asau 1974): guide[b] is the first entry whose cdf exceeds b / count,
     * where the search for u in [b / count, (b + 1) / count) starts (count + 1 entries). */
    uint32_t *guide;
    /* Groups of consecutive entries (one lamp each), for the choice by receiver: group_first[g]
     * .. group_first[g + 1] - 1 are group g's entries (group_count + 1 values); each group's
     * own: its front (unit), centre (in its plane), area, radius and global probability
     * (filled by rad_emitter_table_finish). */
    size_t group_count;
    uint32_t *group_first;
    struct rad_emitter_group {
        rad_vec3 normal, centre;
        double area, radius, probability; /* radius: the farthest corner from the centre */
    } *groups;
    /* The same numbers the choice by receiver reads, one array of group_count values each
     * (emitters.c, GROUP_FIELDS of them), so that its loop over the groups runs in vector
     * registers; with 2 or more groups only. */
    float *group_fields;
    /* More than RAD_EMITTERS_LOCAL_MAX groups: a light tree over them (2 group_count - 1 nodes,
     * the root first), and each group's leaf (emitters.c, "The light tree"). */
    struct rad_emitter_node {
        rad_vec3 low, high;    /* bounds */
        rad_vec3 centre, axis; /* of the bounds; of the cone holding the fronts (unit) */
        double radius;         /* half the bounds' diagonal */
        double cos_spread, sin_spread; /* the cone's half-angle (cos -1: any direction) */
        double power;          /* the sum of its groups' probabilities */
        uint32_t child;        /* inner: the first child (the second follows); leaf: its first
                                  group's place in tree_order */
        uint32_t parent;       /* the root's is UINT32_MAX */
        uint32_t leaf;         /* a leaf's group count (at most 8); 0: inner */
    } *nodes;
    uint32_t *leaf_of;    /* per group */
    uint32_t *tree_order; /* the groups, leaf by leaf */
} rad_emitter_table;

/* A point drawn on the emitters, as seen from a receiver x. */
typedef struct rad_emitter_point {
    rad_vec3 position, direction; /* direction: unit, from x to the point */
    double distance2;             /* |position - x|^2 */
    double pdf;                   /* solid-angle density at x */
    const double *radiance;       /* emitted radiance L_e of the triangle */
    size_t index;                 /* the triangle */
} rad_emitter_point;

/* Room for `capacity` triangles (a zeroed table needs no call when nothing emits). */
rad_status rad_emitter_table_reserve(rad_context *ctx, rad_emitter_table *table, size_t capacity);
/* Appends the triangle (a, b, c) with front `normal` (unit) and emitted radiance; a triangle
 * without area is skipped. Returns its index, or -1 when skipped. Needs room (reserve). */
int32_t rad_emitter_table_add(rad_emitter_table *table, rad_vec3 a, rad_vec3 b, rad_vec3 c,
                              rad_vec3 normal, const double radiance[3]);
/* Appends the parallelogram p0 + s e1 + t e2, s, t in [0, 1), as one entry: a point on it is
 * p0 + u0 e1 + u1 e2, so the two numbers' stratification in the unit square (an Owen-scrambled
 * Sobol' net) is kept over the whole light, where triangles picked one by one by u0 keep it
 * only along one direction. Returns its index, or -1 when skipped (no area, no room). */
int32_t rad_emitter_table_add_parallelogram(rad_emitter_table *table, rad_vec3 p0, rad_vec3 e1,
                                            rad_vec3 e2, rad_vec3 normal, const double radiance[3]);
/* Ends a group (a lamp): the entries added since the last group ended. Each group must lie in
 * one plane and face one way (one input polygon's pieces), and rad_emitter_table_pdf must be
 * asked for the entry a point was drawn from, or one of the same group with the same P_k / A_k
 * (the path tracer's: a polygon's first triangle for any point of the polygon, its emission
 * uniform). Without groups the choice stays global. */
void rad_emitter_table_close_group(rad_emitter_table *table);
/* The selection distribution over what was added; a table whose triangles carry no power is
 * emptied (count 0: nothing to sample). A table of more than RAD_EMITTERS_LOCAL_MAX groups gets
 * its light tree here (RAD_ERROR_NO_MEMORY when it cannot). */
rad_status rad_emitter_table_finish(rad_context *ctx, rad_emitter_table *table,
                                    rad_emitter_selection selection);
void rad_emitter_table_free(rad_context *ctx, rad_emitter_table *table);

/* The probability P_k of picking triangle k for emission sampling (no receiver). */
static inline double rad_emitter_table_probability(const rad_emitter_table *table, size_t k) {
    return table->cdf[k] - (k ? table->cdf[k - 1] : 0);
}

/* A point on the emitters for two uniform numbers in [0, 1), as seen from receiver x whose
 * front is `normal` (unit: lamps wholly behind it are chosen only by the global share, since x
 * reflects nothing from there; the zero vector: a receiver of every direction, such as a
 * transmitting surface). Zero when the table is empty, the point is x itself or the triangle
 * faces away from x. */
int rad_emitter_table_sample(const rad_emitter_table *table, double u0, double u1, rad_vec3 x,
                             rad_vec3 normal, rad_emitter_point *out);

/* The solid-angle density rad_emitter_table_sample has at receiver x (front `normal`, the same
 * as given to the sample) for the point on triangle k that the ray from x along unit `direction`
 * meets at `distance`; zero from behind. */
double rad_emitter_table_pdf(const rad_emitter_table *table, size_t k, rad_vec3 x,
                             rad_vec3 normal, rad_vec3 direction, double distance);

/* The choice for one receiver, made once for several samples and densities there (the final
 * gather's emitter samples and the emitted light its rays find): with the exact choice (2 to
 * RAD_EMITTERS_LOCAL_MAX groups) the groups' probabilities at the receiver are computed once
 * instead of at every call, the loop over every group that made most of a render's or a bake's
 * time in scenes of a hundred lamps. rad_emitter_table_sample and rad_emitter_table_pdf are a
 * choice made for one call. */
typedef struct rad_emitter_choice {
    const rad_emitter_table *table;
    rad_vec3 x, normal;
    double probability[RAD_EMITTERS_LOCAL_MAX]; /* P_g(x) under the exact choice */
} rad_emitter_choice;

void rad_emitter_choice_init(rad_emitter_choice *choice, const rad_emitter_table *table,
                             rad_vec3 x, rad_vec3 normal);
/* rad_emitter_table_sample(table, u0, u1, x, normal, out). */
int rad_emitter_choice_sample(const rad_emitter_choice *choice, double u0, double u1,
                              rad_emitter_point *out);
/* rad_emitter_table_pdf(table, k, x, normal, direction, distance). */
double rad_emitter_choice_pdf(const rad_emitter_choice *choice, size_t k, rad_vec3 direction,
                              double distance);

/* Emission sampling for light paths (photons, light tracing): a triangle k by the table's
 * distribution and a point uniform on it for two uniform numbers (the same mapping as
 * rad_emitter_table_sample, without a receiver). Stores the point and returns k; the area density
 * of the choice is rad_emitter_table_probability(table, k) / area_k. The table must not be empty.
 * (Point, spot and sun lights, once in the table, add their own emission sampling here.) */
size_t rad_emitter_table_sample_point(const rad_emitter_table *table, double u0, double u1,
                                      rad_vec3 *position);

#endif
