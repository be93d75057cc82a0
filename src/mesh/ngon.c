/* ngon.c - cutting a convex polygon of many corners into well-shaped triangles (see ngon.h). */
#include "mesh/ngon.h"

#include <math.h>

/* A band triangle whose smallest corner is below this is a sign the ring does not fit (a
 * polygon far from round, edges of very different lengths): the rest is fanned instead. */
#define NGON_MIN_ANGLE_COSINE 0.906 /* 25 degrees */

/* Rings keep ceil(m / 2) corners each (at most n + log2 n in all) plus one centre; their
 * triangles are at most 1.5 m + 2 each (3 n + 2 log2 n in all) plus a fan of at most n. */
size_t ngon_max_points(size_t n) { return n + 66; }
size_t ngon_max_triangles(size_t n) { return 4 * n + 132; }

typedef struct ngon {
    const rad_vec3 *p;
    size_t n;
    rad_vec3 *extra;
    size_t extra_count;
    uint32_t (*triangles)[3];
    size_t count;
    rad_vec3 normal;
} ngon;

static rad_vec3 point(const ngon *g, uint32_t i) { return i < g->n ? g->p[i] : g->extra[i - g->n]; }

/* Counter-clockwise along the normal and no corner sharper than NGON_MIN_ANGLE_COSINE. */
static int good_triangle(const ngon *g, uint32_t a, uint32_t b, uint32_t c) {
    rad_vec3 q[3] = {point(g, a), point(g, b), point(g, c)};
    if (v3_dot(v3_cross(v3_sub(q[1], q[0]), v3_sub(q[2], q[0])), g->normal) <= 0) return 0;
    for (int k = 0; k < 3; ++k) {
        rad_vec3 u = v3_normalize(v3_sub(q[(k + 1) % 3], q[k]));
        rad_vec3 v = v3_normalize(v3_sub(q[(k + 2) % 3], q[k]));
        if (!(v3_dot(u, v) < NGON_MIN_ANGLE_COSINE)) return 0;
    }
    return 1;
}

static void put(ngon *g, uint32_t a, uint32_t b, uint32_t c) {
    g->triangles[g->count][0] = a;
    g->triangles[g->count][1] = b;
    g->triangles[g->count][2] = c;
    g->count++;
}

/* The area centroid, mean edge length and smallest corner distance from it of ring[0 .. m-1]. */
static rad_vec3 ring_shape(const ngon *g, const uint32_t *ring, size_t m, double *edge,
                           double *nearest) {
    rad_vec3 o = point(g, ring[0]), sum = v3(0, 0, 0);
    double area = 0, length = 0;
    for (size_t i = 1; i + 1 < m; ++i) {
        rad_vec3 b = point(g, ring[i]), c = point(g, ring[i + 1]);
        double a = v3_dot(v3_cross(v3_sub(b, o), v3_sub(c, o)), g->normal);
        area += a;
        sum = v3_add(sum, v3_scale(v3_add(v3_add(o, b), c), a / 3));
    }
    rad_vec3 centroid = area > 0 ? v3_scale(sum, 1 / area) : o;
    *nearest = INFINITY;
    for (size_t i = 0; i < m; ++i) {
        length += v3_length(v3_sub(point(g, ring[(i + 1) % m]), point(g, ring[i])));
        *nearest = fmin(*nearest, v3_length(v3_sub(point(g, ring[i]), centroid)));
    }
    *edge = length / (double)m;
    return centroid;
}

/* One ring: keeps ring[0], ring[2], ... moved `depth` toward the centroid, and cuts the band
 * between into triangles: over two outer edges a, a+1, a+2 (inner corners A, B) the three
 * (a, a+1, A), (a+1, B, A), (a+1, a+2, B); over one (odd m, at the end) (a, a+1, B), (a, B, A).
 * Returns the new corner count, or 0 (nothing kept) when a triangle would be poor. */
static size_t peel(ngon *g, uint32_t *ring, size_t m, rad_vec3 centroid, double depth) {
    size_t kept = (m + 1) / 2, first_extra = g->extra_count, first_triangle = g->count;
    for (size_t i = 0; i < kept; ++i) {
        rad_vec3 v = point(g, ring[2 * i]);
        rad_vec3 inward = v3_normalize(v3_sub(centroid, v));
        g->extra[g->extra_count++] = v3_add(v, v3_scale(inward, depth));
    }
    int good = 1;
    for (size_t i = 0; i < kept && good; ++i) {
        uint32_t A = (uint32_t)(g->n + first_extra + i);
        uint32_t B = (uint32_t)(g->n + first_extra + (i + 1) % kept);
        uint32_t a = ring[2 * i], b = ring[(2 * i + 1) % m];
        if (2 * i + 2 <= m) {
            uint32_t c = ring[(2 * i + 2) % m];
            good = good_triangle(g, a, b, A) && good_triangle(g, b, B, A) && good_triangle(g, b, c, B);
            if (good) put(g, a, b, A), put(g, b, B, A), put(g, b, c, B);
        } else {
            good = good_triangle(g, a, b, B) && good_triangle(g, a, B, A);
            if (good) put(g, a, b, B), put(g, a, B, A);
        }
    }
    if (!good) {
        g->extra_count = first_extra;
        g->count = first_triangle;
        return 0;
    }
    for (size_t i = 0; i < kept; ++i) ring[i] = (uint32_t)(g->n + first_extra + i);
    return kept;
}

size_t ngon_cut(const rad_vec3 *p, size_t n, rad_vec3 normal, rad_vec3 *extra, size_t *extra_count,
                uint32_t (*triangles)[3], uint32_t *ring) {
    ngon g = {p, n, extra, 0, triangles, 0, normal};
    for (size_t i = 0; i < n; ++i) ring[i] = (uint32_t)i;
    size_t m = n;
    double edge, nearest;
    rad_vec3 centroid = ring_shape(&g, ring, m, &edge, &nearest);
    /* Peel rings one mean edge deep while the polygon is more than twice that deep. */
    while (m > NGON_FAN_CORNERS && nearest > 3 * edge) {
        size_t kept = peel(&g, ring, m, centroid, edge);
        if (!kept) break;
        m = kept;
        centroid = ring_shape(&g, ring, m, &edge, &nearest);
    }
    /* Fan what is left from its centroid. */
    uint32_t centre = (uint32_t)(n + g.extra_count);
    g.extra[g.extra_count++] = centroid;
    for (size_t i = 0; i < m; ++i) put(&g, ring[i], ring[(i + 1) % m], centre);
    *extra_count = g.extra_count;
    return g.count;
}
