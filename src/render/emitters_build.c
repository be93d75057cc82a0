/* emitters_build.c - the renderer's emitter table (light/emitters.h) from the emitting elements
 * of the solution's leaves: what the final gather's and the second pass's emitter samples draw
 * from, and the density the gather rays that meet an emitter are weighted with.
 *
 * An emitting input polygon whose elements tile a planar parallelogram with one emitted
 * radiance (the Cornell box's light, a quad lamp) is one entry, sampled over the whole
 * parallelogram: the pixel's Owen-scrambled Sobol' points in the light dimension stay a net on
 * the light, so each camera sample's emitter points fall one in every part of the lamp, and in a
 * penumbra the share of them a block's edge hides varies little. Other emitters are their
 * elements' triangles, picked by power: u0 picks the triangle and places the point inside it,
 * which keeps the stratification along one direction only. Cornell 256 (docs/rendering.md,
 * "Emitter samples over the whole lamp"): the floor's penumbra in front of the short block,
 * where the worst 8x8 blocks were, was the emitter samples' noise. */
#include "render/render.h"

#include <stdlib.h>
#include <string.h>

/* Adds triangle (a, b, c) of an emitting element to the emitter table; its index, or -1. */
static int32_t add_emitter(rad_emitter_table *table, const rad_mesh *mesh, uint32_t a, uint32_t b,
                           uint32_t c, const double radiance[3]) {
    rad_vec3 p0 = mesh->vertices[a];
    rad_vec3 normal = v3_normalize(v3_cross(v3_sub(mesh->vertices[b], p0),
                                            v3_sub(mesh->vertices[c], p0)));
    return rad_emitter_table_add(table, p0, mesh->vertices[b], mesh->vertices[c], normal, radiance);
}

/* Emitted radiance L = E / pi of element e, rounded to float as the renderer keeps it; zero when
 * it does not emit. */
static int element_emits(const rad_solution_view *solution, size_t e, double radiance[3]) {
    double emission[3];
    solution->ops->emission(solution, e, emission);
    for (int c = 0; c < 3; ++c) radiance[c] = (float)(emission[c] / RAD_PI);
    return emission[0] > 0 || emission[1] > 0 || emission[2] > 0;
}

/* An emitting element: its key (input polygon << 32 | element) and its emitted radiance. */
typedef struct emitting_element {
    uint64_t key;
    double radiance[3];
} emitting_element;

static uint32_t element_of(const emitting_element *x) { return (uint32_t)x->key; }

/* Whether elements members[0 .. count) (one input polygon's) tile a planar parallelogram with
 * one emitted radiance: its corner p0 and sides e1, e2 (e1 x e2 along the front). The sides are
 * those of the first element's corner v0 (v0 -> v1 and v0 -> its last corner): every vertex is
 * written s e1 + t e2 from v0, and the box [s_min, s_max] x [t_min, t_max] must lie in the plane
 * and have the elements' summed area (they do not overlap and lie inside it, so they cover it).
 * Meshes whose elements' sides run otherwise (triangles across the diagonal) fail the area test
 * and keep their triangles. */
static int parallelogram_of(const rad_mesh *mesh, const emitting_element *members, size_t count,
                            rad_vec3 *p0, rad_vec3 *e1, rad_vec3 *e2) {
    const uint32_t *first = mesh->element_vertices[element_of(&members[0])];
    int last = rad_mesh_corner_count(mesh, element_of(&members[0])) - 1;
    rad_vec3 origin = mesh->vertices[first[0]];
    rad_vec3 a = v3_sub(mesh->vertices[first[1]], origin);
    rad_vec3 b = v3_sub(mesh->vertices[first[last]], origin);
    rad_vec3 normal = v3_cross(a, b);
    double cross2 = v3_dot(normal, normal);
    if (!(cross2 > 0)) return 0;
    double size = sqrt(sqrt(cross2)); /* the element's size, for the plane's tolerance */
    rad_vec3 unit = v3_scale(normal, 1 / sqrt(cross2));
    /* Dual basis: s = (d x b) . n / |n|^2, t = (a x d) . n / |n|^2. */
    double s_min = INFINITY, s_max = -INFINITY, t_min = INFINITY, t_max = -INFINITY, area = 0;
    const double *radiance = members[0].radiance;
    for (size_t i = 0; i < count; ++i) {
        size_t e = element_of(&members[i]);
        const double *own = members[i].radiance;
        if (own[0] != radiance[0] || own[1] != radiance[1] || own[2] != radiance[2]) return 0;
        area += mesh->element_area[e];
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            rad_vec3 d = v3_sub(mesh->vertices[mesh->element_vertices[e][k]], origin);
            if (fabs(v3_dot(d, unit)) > 1e-6 * size) return 0;
            double s = v3_dot(v3_cross(d, b), normal) / cross2;
            double t = v3_dot(v3_cross(a, d), normal) / cross2;
            s_min = fmin(s_min, s), s_max = fmax(s_max, s);
            t_min = fmin(t_min, t), t_max = fmax(t_max, t);
        }
    }
    double box = (s_max - s_min) * (t_max - t_min) * sqrt(cross2);
    if (!(fabs(box - area) <= 1e-6 * box)) return 0;
    *p0 = v3_add(origin, v3_add(v3_scale(a, s_min), v3_scale(b, t_min)));
    *e1 = v3_scale(a, s_max - s_min);
    *e2 = v3_scale(b, t_max - t_min);
    return 1;
}

/* Keys (input polygon << 32 | element) in increasing order. */
static int compare_keys(const void *pa, const void *pb) {
    uint64_t a = ((const emitting_element *)pa)->key, b = ((const emitting_element *)pb)->key;
    return a < b ? -1 : a > b;
}

rad_status rad_emitters_build(rad_renderer *r) {
    const rad_mesh *mesh = r->mesh;
    const rad_solution_view *solution = r->solution;
    r->element_emitter = rad_alloc(r->ctx, mesh->element_count + 1, sizeof *r->element_emitter);
    if (!r->element_emitter) return RAD_ERROR_NO_MEMORY;
    for (size_t e = 0; e < mesh->element_count; ++e) r->element_emitter[e][0] = r->element_emitter[e][1] = -1;
    /* The emitting elements with their radiance (each asked once), in order of their input
     * polygon, then of their index. */
    emitting_element *members = NULL;
    size_t count = 0, emitting = 0, capacity = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        double radiance[3];
        if (!element_emits(solution, e, radiance)) continue;
        if (emitting == capacity) {
            size_t next = capacity ? 2 * capacity : 64;
            emitting_element *grown = rad_realloc(r->ctx, members, next, sizeof *grown);
            if (!grown) {
                rad_free(r->ctx, members);
                return RAD_ERROR_NO_MEMORY;
            }
            members = grown, capacity = next;
        }
        members[emitting].key = (uint64_t)mesh->element_polygon[e] << 32 | e;
        memcpy(members[emitting++].radiance, radiance, sizeof radiance);
        count += (size_t)rad_mesh_corner_count(mesh, e) - 2;
    }
    rad_status status = rad_emitter_table_reserve(r->ctx, &r->emitters, count);
    if (status || count == 0) {
        rad_free(r->ctx, members);
        return status;
    }
    qsort(members, emitting, sizeof *members, compare_keys);
    for (size_t i = 0; i < emitting;) {
        size_t end = i + 1;
        while (end < emitting && members[end].key >> 32 == members[i].key >> 32) ++end;
        rad_vec3 p0, e1, e2;
        if (parallelogram_of(mesh, members + i, end - i, &p0, &e1, &e2)) {
            int32_t k = rad_emitter_table_add_parallelogram(&r->emitters, p0, e1, e2,
                                                            v3_normalize(v3_cross(e1, e2)),
                                                            members[i].radiance);
            for (size_t j = i; j < end; ++j)
                r->element_emitter[element_of(&members[j])][0] = r->element_emitter[element_of(&members[j])][1] = k;
            rad_emitter_table_close_group(&r->emitters);
            i = end;
            continue;
        }
        for (; i < end; ++i) {
            uint32_t e = element_of(&members[i]);
            const uint32_t *v = mesh->element_vertices[e];
            const double *radiance = members[i].radiance;
            if (rad_mesh_corner_count(mesh, e) == 3) {
                r->element_emitter[e][0] = add_emitter(&r->emitters, mesh, v[0], v[1], v[2], radiance);
            } else {
                /* Embree's split of a quad: (v0, v1, v3) and (v2, v3, v1). */
                r->element_emitter[e][0] = add_emitter(&r->emitters, mesh, v[0], v[1], v[3], radiance);
                r->element_emitter[e][1] = add_emitter(&r->emitters, mesh, v[2], v[3], v[1], radiance);
            }
        }
        /* One input polygon's pieces: a group, for the choice by receiver (light/emitters.h). */
        rad_emitter_table_close_group(&r->emitters);
    }
    rad_free(r->ctx, members);
    return rad_emitter_table_finish(r->ctx, &r->emitters, RAD_EMITTERS_BY_POWER);
}
