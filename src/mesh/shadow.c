/* shadow.c - shadow boundaries of area emitters as segments on receivers (D1/D2; see shadow.h).
 *
 * 1. Emitters: the polygons that emit at least EMITTER_SHARE of the power emitted by
 *    polygons, the brightest RAD_SHADOW_EMITTERS of them.
 * 2. Adjacency: edges and corners of the scene's polygons welded by position (to 1e-7 of the
 *    scene's diagonal), so a box's faces know their neighbours across each edge and corner.
 * 3. EV events (Heckbert 1992): an emitter corner v and a blocker edge that is a silhouette
 *    seen from v (its polygons face v on one side and away on the other, or it has one
 *    polygon). VE events: an emitter edge and a blocker corner all of whose neighbours lie on
 *    one side of the plane through them. Each event's plane (the "wedge" behind the edge or
 *    corner) is traced with rays at three places: from the emitter to the blocker unblocked,
 *    then on past it to the first surface hit from the front, the receiver.
 * 4. The wedge meets the receiver's plane in a segment (the edge or corner projected from the
 *    emitter), clipped to the receiver. Segments shorter than a quarter of an element are
 *    dropped; the cutter (contact.c) dedupes and caps what is left per polygon.
 * Budget: at most MAX_EVENTS events are traced, in a fixed order (brightest emitter first), so
 * a scene of many polygons costs bounded time and the result is the same on every run. */
#include "mesh/shadow.h"

#include "mesh/contact.h"
#include "scene/rays.h"
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EMITTER_SHARE 0.05
#define MAX_EVENTS 200000
#define SAMPLES 3

typedef struct edge_record {
    int64_t a[3], b[3]; /* welded endpoints, a < b */
    uint32_t polygon, corner;
} edge_record;

typedef struct corner_record {
    int64_t at[3];
    rad_vec3 neighbour; /* the other end of an edge from this corner */
    uint32_t polygon;
} corner_record;

typedef struct tracer {
    const rad_scene *scene;
    const rad_rays *rays;
    const uint8_t *emits;
    const rad_vec3 *normal;
    const double *offset;
    double delta, eps, min_length;
    rad_shadow_segment *out;
    size_t count, capacity;
    rad_context *ctx;
} tracer;

static int compare3(const int64_t *a, const int64_t *b) {
    for (int k = 0; k < 3; ++k)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int by_edge(const void *x, const void *y) {
    const edge_record *a = x, *b = y;
    int c = compare3(a->a, b->a);
    return c ? c : compare3(a->b, b->b);
}

static int by_corner(const void *x, const void *y) {
    return compare3(((const corner_record *)x)->at, ((const corner_record *)y)->at);
}

static int by_polygon_weight(const void *x, const void *y) {
    const rad_shadow_segment *a = x, *b = y;
    if (a->polygon != b->polygon) return a->polygon < b->polygon ? -1 : 1;
    if (a->weight != b->weight) return a->weight > b->weight ? -1 : 1;
    return 0;
}

static void quantise(rad_vec3 p, rad_vec3 lo, double quantum, int64_t out[3]) {
    out[0] = llround((p.x - lo.x) / quantum);
    out[1] = llround((p.y - lo.y) / quantum);
    out[2] = llround((p.z - lo.z) / quantum);
}

static double plane_distance(const tracer *t, uint32_t polygon, rad_vec3 p) {
    return v3_dot(t->normal[polygon], p) - t->offset[polygon];
}

/* Clips the segment a-b (in the plane of `polygon`) to the polygon, margin inside its edges. */
static int clip_to_polygon(const tracer *t, uint32_t polygon, rad_vec3 *a, rad_vec3 *b) {
    const rad_polygon *p = &t->scene->polygons[polygon];
    rad_vec3 corners[64], d = v3_sub(*b, *a);
    double length = v3_length(d), t0 = 0, t1 = length;
    if (p->count > 64 || !(length > 0)) return 0;
    for (uint32_t k = 0; k < p->count; ++k) corners[k] = rad_polygon_vertex(t->scene, p, k);
    d = v3_scale(d, 1 / length);
    if (!rad_clip_line_convex(corners, p->count, t->normal[polygon], *a, d, t->eps, &t0, &t1)) return 0;
    rad_vec3 na = v3_add(*a, v3_scale(d, t0)), nb = v3_add(*a, v3_scale(d, t1));
    *a = na, *b = nb;
    return 1;
}

static rad_status add_segment(tracer *t, uint32_t polygon, rad_vec3 a, rad_vec3 b, double share) {
    if (!clip_to_polygon(t, polygon, &a, &b)) return RAD_OK;
    double length = v3_length(v3_sub(b, a));
    if (!(length >= t->min_length)) return RAD_OK;
    if (t->count == t->capacity) {
        size_t next = t->capacity ? 2 * t->capacity : 256;
        rad_shadow_segment *grown = rad_realloc(t->ctx, t->out, next, sizeof *grown);
        if (!grown) return RAD_ERROR_NO_MEMORY;
        t->out = grown, t->capacity = next;
    }
    t->out[t->count++] = (rad_shadow_segment){polygon, a, b, share * length};
    return RAD_OK;
}

/* Light from `from` (on the emitter) grazing the blocker at `at`: reaches it unblocked, and
 * on past it first meets the front of polygon *receiver. */
static int trace(const tracer *t, rad_vec3 from, rad_vec3 at, uint32_t *receiver) {
    rad_vec3 d = v3_sub(at, from);
    double length = v3_length(d);
    if (!(length > 4 * t->delta)) return 0;
    rad_hit hit;
    double margin = t->delta / length;
    if (rad_rays_intersect(t->rays, from, d, margin, 1 - margin, &hit)) return 0;
    if (!rad_rays_intersect(t->rays, at, d, margin, INFINITY, &hit) || !hit.front) return 0;
    if (t->emits[hit.polygon]) return 0;
    *receiver = hit.polygon;
    return 1;
}

/* Adds `receiver` to the list of distinct receivers (at most SAMPLES). */
static void note_receiver(uint32_t *list, int *n, uint32_t receiver) {
    for (int k = 0; k < *n; ++k)
        if (list[k] == receiver) return;
    list[(*n)++] = receiver;
}

/* EV: corner v of the emitter, blocker edge b0-b1 (a silhouette seen from v). */
static rad_status edge_event(tracer *t, rad_vec3 v, rad_vec3 b0, rad_vec3 b1, double share) {
    uint32_t receivers[SAMPLES];
    int found = 0;
    for (int s = 0; s < SAMPLES; ++s) {
        uint32_t r;
        if (trace(t, v, v3_lerp(b0, b1, (s + 1.0) / (SAMPLES + 1)), &r)) note_receiver(receivers, &found, r);
    }
    for (int k = 0; k < found; ++k) {
        uint32_t r = receivers[k];
        double dv = plane_distance(t, r, v), d0 = plane_distance(t, r, b0), d1 = plane_distance(t, r, b1);
        if (!(dv > t->eps)) continue;
        /* The part of the edge from 0 to 0.999 of v's height above the receiver projects onto
         * it from v (nearer v it projects far away; below it the wedge misses the plane). */
        double lo = 0, hi = 1, top = 0.999 * dv;
        if (fabs(d0) <= t->eps) d0 = 0;
        if (fabs(d1) <= t->eps) d1 = 0;
        double slope = d1 - d0;
        if (slope != 0) {
            double s_zero = -d0 / slope, s_top = (top - d0) / slope;
            if (slope > 0) lo = fmax(lo, s_zero), hi = fmin(hi, s_top);
            else lo = fmax(lo, s_top), hi = fmin(hi, s_zero);
        } else if (d0 < 0 || d0 > top) {
            continue;
        }
        if (!(hi > lo)) continue;
        rad_vec3 e0 = v3_lerp(b0, b1, lo), e1 = v3_lerp(b0, b1, hi);
        double h0 = fmax(0, d0 + lo * slope), h1 = fmax(0, d0 + hi * slope);
        rad_vec3 p0 = v3_add(v, v3_scale(v3_sub(e0, v), dv / (dv - h0)));
        rad_vec3 p1 = v3_add(v, v3_scale(v3_sub(e1, v), dv / (dv - h1)));
        rad_status status = add_segment(t, r, p0, p1, share);
        if (status) return status;
    }
    return RAD_OK;
}

/* VE: emitter edge v0-v1, blocker corner b (a silhouette seen from the edge). */
static rad_status corner_event(tracer *t, rad_vec3 v0, rad_vec3 v1, rad_vec3 b, double share) {
    uint32_t receivers[SAMPLES];
    int found = 0;
    for (int s = 0; s < SAMPLES; ++s) {
        uint32_t r;
        if (trace(t, v3_lerp(v0, v1, (s + 1.0) / (SAMPLES + 1)), b, &r)) note_receiver(receivers, &found, r);
    }
    for (int k = 0; k < found; ++k) {
        uint32_t r = receivers[k];
        double db = plane_distance(t, r, b), d0 = plane_distance(t, r, v0), d1 = plane_distance(t, r, v1);
        if (!(db > t->eps)) continue; /* a corner on the receiver casts a point */
        /* The part of the emitter edge above 1.001 times the corner's height projects. */
        double lo = 0, hi = 1, floor_height = 1.001 * db, slope = d1 - d0;
        if (slope != 0) {
            double s_floor = (floor_height - d0) / slope;
            if (slope > 0) lo = fmax(lo, s_floor);
            else hi = fmin(hi, s_floor);
        } else if (d0 < floor_height) {
            continue;
        }
        if (!(hi > lo)) continue;
        rad_vec3 w0 = v3_lerp(v0, v1, lo), w1 = v3_lerp(v0, v1, hi);
        double h0 = d0 + lo * slope, h1 = d0 + hi * slope;
        rad_vec3 p0 = v3_add(b, v3_scale(v3_sub(b, w0), db / (h0 - db)));
        rad_vec3 p1 = v3_add(b, v3_scale(v3_sub(b, w1), db / (h1 - db)));
        rad_status status = add_segment(t, r, p0, p1, share);
        if (status) return status;
    }
    return RAD_OK;
}

/* A source of shadows: an emitting polygon, or (light >= 0) a point or spot light of the scene. */
typedef struct emitter {
    uint32_t polygon;
    int32_t light;
    double power;
} emitter;

static int by_power(const void *x, const void *y) {
    const emitter *a = x, *b = y;
    if (a->power != b->power) return a->power > b->power ? -1 : 1;
    if (a->light != b->light) return a->light < b->light ? -1 : 1;
    return a->polygon < b->polygon ? -1 : a->polygon > b->polygon;
}

/* The power a point or spot light sends out (the mean of its channels): 4 pi I for a point
 * light, the cone's solid angle 2 pi (1 - cos outer) times I for a spot (its peak candela for an
 * IES profile, an upper bound); zero for directional lights (no position: no wedge). */
static double light_power(const rad_light *light) {
    double intensity = (light->intensity[0] + light->intensity[1] + light->intensity[2]) / 3;
    if (light->ies) intensity = light->ies->max_candela / RAD_LUMINOUS_EFFICACY;
    if (light->kind == RAD_LIGHT_POINT) return 4 * RAD_PI * intensity;
    if (light->kind == RAD_LIGHT_SPOT) return 2 * RAD_PI * (1 - cos(fmin(light->outer_angle, RAD_PI))) * intensity;
    return 0;
}

/* EV events of a point or spot light at v: each welded silhouette edge seen from v (the light
 * reaching it: inside a spot's cone) casts a hard shadow's edge on the receivers behind it. */
static rad_status point_events(tracer *t, const rad_light *light, const edge_record *edge, size_t edges,
                               double share, rad_shadow_stats *stats) {
    const rad_scene *scene = t->scene;
    rad_vec3 v = light->position;
    rad_status status = RAD_OK;
    for (size_t g = 0; g < edges && !status && !stats->capped;) {
        size_t end = g + 1;
        while (end < edges && by_edge(&edge[g], &edge[end]) == 0) end++;
        const rad_polygon *bp = &scene->polygons[edge[g].polygon];
        rad_vec3 b0 = rad_polygon_vertex(scene, bp, edge[g].corner);
        rad_vec3 b1 = rad_polygon_vertex(scene, bp, (edge[g].corner + 1) % bp->count);
        int skip = v3_length(v3_sub(b1, b0)) < t->min_length;
        for (size_t r = g; r < end; ++r) skip |= t->emits[edge[r].polygon];
        if (!skip && light->kind == RAD_LIGHT_SPOT) {
            double towards[3];
            rad_light_intensity(light, v3_normalize(v3_sub(v3_lerp(b0, b1, 0.5), v)), towards);
            skip = !(towards[0] > 0 || towards[1] > 0 || towards[2] > 0);
        }
        /* A silhouette: the polygons on the edge do not all face v the same way. */
        int front = 0, back = 0;
        for (size_t r = g; r < end && !skip; ++r) {
            double side = plane_distance(t, edge[r].polygon, v);
            if (side > t->eps) front = 1;
            else if (side < -t->eps) back = 1;
            else front = back = 2; /* v in the polygon's plane: no wedge */
        }
        size_t polygons = end - g;
        g = end;
        if (skip || front == 2 || (polygons > 1 && !(front && back))) continue;
        if (++stats->events > MAX_EVENTS) {
            stats->capped = 1;
            break;
        }
        status = edge_event(t, v, b0, b1, share);
    }
    return status;
}

rad_status rad_shadow_segments_find(rad_context *ctx, const rad_scene *scene, double element_size,
                                    rad_shadow_segment **out, size_t *count,
                                    rad_shadow_stats *stats) {
    *out = NULL;
    *count = 0;
    rad_shadow_stats none = {0};
    if (!stats) stats = &none;
    *stats = none;
    size_t np = scene->polygon_count;
    if (!np) return RAD_OK;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    double diagonal = v3_length(v3_sub(hi, lo));
    if (!(diagonal > 0) || !isfinite(diagonal)) return RAD_OK;
    double quantum = diagonal * 1e-7;

    /* Step 1: emitters. */
    uint8_t *emits = rad_alloc_zero(ctx, np, 1);
    emitter *emitters = rad_alloc(ctx, np + scene->light_count, sizeof *emitters);
    rad_vec3 *normal = rad_alloc(ctx, np, sizeof *normal);
    double *offset = rad_alloc(ctx, np, sizeof *offset);
    size_t edges = 0;
    for (size_t i = 0; i < np; ++i) edges += scene->polygons[i].count;
    edge_record *edge = rad_alloc(ctx, edges + 1, sizeof *edge);
    corner_record *corner = rad_alloc(ctx, 2 * edges + 1, sizeof *corner);
    tracer t = {0};
    rad_rays *rays = NULL;
    rad_status status = RAD_OK;
    if (!emits || !emitters || !normal || !offset || !edge || !corner) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    size_t emitter_count = 0;
    double total = 0;
    for (size_t i = 0; i < np; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        const double *e = scene->materials[scene->surfaces[p->surface].material].emission;
        normal[i] = rad_polygon_normal(scene, p);
        rad_vec3 sum = v3(0, 0, 0);
        for (uint32_t k = 0; k < p->count; ++k) sum = v3_add(sum, rad_polygon_vertex(scene, p, k));
        offset[i] = v3_dot(normal[i], v3_scale(sum, 1.0 / p->count));
        double radiance = (e[0] + e[1] + e[2]) / 3;
        if (!(radiance > 0)) continue;
        emits[i] = 1;
        double power = radiance * rad_polygon_area(scene, p);
        if (!isfinite(power) || !isfinite(offset[i])) continue;
        emitters[emitter_count++] = (emitter){(uint32_t)i, -1, RAD_PI * power};
        total += power;
    }
    for (size_t l = 0; l < scene->light_count; ++l) {
        double power = light_power(&scene->lights[l]);
        if (!(power > 0) || !isfinite(power)) continue;
        emitters[emitter_count++] = (emitter){0, (int32_t)l, power};
        total += power;
    }
    if (!emitter_count || !(total > 0)) goto done;
    qsort(emitters, emitter_count, sizeof *emitters, by_power);
    size_t used = 0;
    while (used < emitter_count && used < RAD_SHADOW_EMITTERS && emitters[used].power >= EMITTER_SHARE * total)
        used++;

    /* Step 2: edges and corners welded by position. */
    size_t corners = 0;
    edges = 0;
    for (size_t i = 0; i < np; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        if (!isfinite(offset[i])) continue;
        for (uint32_t k = 0; k < p->count; ++k) {
            rad_vec3 a = rad_polygon_vertex(scene, p, k), b = rad_polygon_vertex(scene, p, (k + 1) % p->count);
            edge_record r = {{0}, {0}, (uint32_t)i, k};
            quantise(a, lo, quantum, r.a);
            quantise(b, lo, quantum, r.b);
            if (compare3(r.a, r.b) == 0) continue;
            corner[corners++] = (corner_record){{r.a[0], r.a[1], r.a[2]}, b, (uint32_t)i};
            corner[corners++] = (corner_record){{r.b[0], r.b[1], r.b[2]}, a, (uint32_t)i};
            if (compare3(r.a, r.b) > 0) {
                int64_t swap[3];
                memcpy(swap, r.a, sizeof swap);
                memcpy(r.a, r.b, sizeof swap);
                memcpy(r.b, swap, sizeof swap);
            }
            edge[edges++] = r;
        }
    }
    qsort(edge, edges, sizeof *edge, by_edge);
    qsort(corner, corners, sizeof *corner, by_corner);

    status = rad_rays_create(ctx, scene, &rays);
    if (status) goto done;
    t = (tracer){scene, rays, emits, normal, offset, 1e-5 * diagonal, 1e-6 * diagonal,
                 0.25 * element_size, NULL, 0, 0, ctx};

    /* Step 3: events, brightest emitter first, within the budget. */
    for (size_t e = 0; e < used && !status && !stats->capped; ++e) {
        uint32_t ei = emitters[e].polygon;
        const rad_polygon *ep = &scene->polygons[ei];
        double share = emitters[e].power / total;
        stats->emitters++;
        if (emitters[e].light >= 0) {
            status = point_events(&t, &scene->lights[emitters[e].light], edge, edges, share, stats);
            continue;
        }
        /* EV: each welded edge once. */
        for (size_t g = 0; g < edges && !status && !stats->capped;) {
            size_t end = g + 1;
            while (end < edges && by_edge(&edge[g], &edge[end]) == 0) end++;
            int skip = 0;
            for (size_t r = g; r < end; ++r) skip |= emits[edge[r].polygon];
            const rad_polygon *bp = &scene->polygons[edge[g].polygon];
            rad_vec3 b0 = rad_polygon_vertex(scene, bp, edge[g].corner);
            rad_vec3 b1 = rad_polygon_vertex(scene, bp, (edge[g].corner + 1) % bp->count);
            if (v3_length(v3_sub(b1, b0)) < t.min_length) skip = 1;
            /* An edge (partly) behind the emitter casts nothing from it. */
            if (plane_distance(&t, ei, b0) < -t.eps || plane_distance(&t, ei, b1) < -t.eps) skip = 1;
            for (uint32_t k = 0; k < ep->count && !skip && !status; ++k) {
                rad_vec3 v = rad_polygon_vertex(scene, ep, k);
                /* A silhouette: the polygons on the edge do not all face v the same way. */
                int front = 0, back = 0;
                for (size_t r = g; r < end; ++r) {
                    double side = plane_distance(&t, edge[r].polygon, v);
                    if (side > t.eps) front = 1;
                    else if (side < -t.eps) back = 1;
                    else front = back = 2; /* v in the polygon's plane: no wedge */
                }
                if (front == 2 || (end - g > 1 && !(front && back))) continue;
                if (++stats->events > MAX_EVENTS) {
                    stats->capped = 1;
                    break;
                }
                status = edge_event(&t, v, b0, b1, share);
            }
            g = end;
        }
        /* VE: each welded corner once, against each emitter edge. */
        for (size_t g = 0; g < corners && !status && !stats->capped;) {
            size_t end = g + 1;
            while (end < corners && by_corner(&corner[g], &corner[end]) == 0) end++;
            int skip = 0;
            for (size_t r = g; r < end; ++r) skip |= emits[corner[r].polygon];
            const rad_polygon *bp = &scene->polygons[corner[g].polygon];
            rad_vec3 b = v3(0, 0, 0);
            /* The corner's position: the one of its polygon's corners that welds to it. */
            for (uint32_t k = 0; k < bp->count; ++k) {
                int64_t q[3];
                quantise(rad_polygon_vertex(scene, bp, k), lo, quantum, q);
                if (compare3(q, corner[g].at) == 0) b = rad_polygon_vertex(scene, bp, k);
            }
            if (plane_distance(&t, ei, b) < t.eps) skip = 1;
            for (uint32_t k = 0; k < ep->count && !skip && !status; ++k) {
                rad_vec3 v0 = rad_polygon_vertex(scene, ep, k), v1 = rad_polygon_vertex(scene, ep, (k + 1) % ep->count);
                rad_vec3 plane = v3_cross(v3_sub(v1, v0), v3_sub(b, v0));
                double size = v3_length(plane);
                if (!(size > 0)) continue;
                plane = v3_scale(plane, 1 / size);
                /* A silhouette: every neighbour on one side of the plane through the edge and b. */
                int above = 0, below = 0;
                for (size_t r = g; r < end; ++r) {
                    double side = v3_dot(plane, v3_sub(corner[r].neighbour, b));
                    if (side > t.eps) above = 1;
                    else if (side < -t.eps) below = 1;
                }
                if (above && below) continue;
                if (++stats->events > MAX_EVENTS) {
                    stats->capped = 1;
                    break;
                }
                status = corner_event(&t, v0, v1, b, share);
            }
            g = end;
        }
    }
    if (status) goto done;
    if (t.count) qsort(t.out, t.count, sizeof *t.out, by_polygon_weight);
    stats->segments = t.count;
    *out = t.out;
    *count = t.count;
    t.out = NULL;
done:
    if (status == RAD_ERROR_NO_MEMORY) status = rad_fail(ctx, status, "out of memory finding shadow boundaries");
    rad_rays_destroy(rays);
    rad_free(ctx, t.out);
    rad_free(ctx, emits);
    rad_free(ctx, emitters);
    rad_free(ctx, normal);
    rad_free(ctx, offset);
    rad_free(ctx, edge);
    rad_free(ctx, corner);
    return status;
}
