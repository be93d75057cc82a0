/* photon_map.h - a photon map (Jensen 1996): photons stored where they hit surfaces with a
 * diffuse or glossy lobe, in a hash grid of cells one search radius wide (docs/photonmapping.md).
 *
 * The grid: each photon's cell (floor(p / cell) per axis) goes to one of 2^m buckets by the low
 * bits of its Morton code; the photons are sorted by bucket (keys in parallel, a stable counting
 * sort), so a bucket is one run of the array and the array is in space order. A query visits the 27 cells around x, each bucket once. The order of the
 * photons is the order they were given in: the map, and every estimate from it, is the same for
 * any thread count. */
#ifndef RAD_RENDER_PHOTON_MAP_H
#define RAD_RENDER_PHOTON_MAP_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* One photon where it landed, in 24 bytes (Jensen 2001, sec. 6.1 packs his in 20: float
 * position, Ward's shared-exponent power, two angles): the position in floats, the flux as three
 * 16-bit mantissas with one shared exponent (relative error below 2^-16 on the largest channel,
 * 1e-3 on one a hundredth of it: none of the 8-bit RGBE's bias on coloured walls), the surface's
 * normal and the incoming direction as octahedral unit vectors (Cigolle et al. 2014, "A survey of
 * efficient representations for independent unit vectors"; 8 + 8 bits: within 1.5 degrees, enough
 * for the same-surface test; 12 + 12 bits for the incoming direction the BSDF is evaluated with).
 * Write with rad_photon_pack, read with the getters below. */
typedef struct rad_photon {
    float position[3];
    uint16_t power[3];    /* flux = power * 2^(exponent - 128 - 16), watts (the scene's units) */
    uint8_t exponent;     /* 0: no flux */
    uint8_t incoming_low; /* the incoming direction's low bits (12 + 12 with incoming_high) */
    uint16_t incoming_high;
    uint16_t normal;      /* the front normal of the surface it landed on */
} rad_photon;

/* A photon of flux `power` at `position` on a surface of front normal `normal` (unit), arrived
 * from `incoming` (unit, from the surface towards where it came from). Negative or non-finite
 * flux is stored as none. */
rad_photon rad_photon_pack(rad_vec3 position, const double power[3], rad_vec3 normal,
                           rad_vec3 incoming);

static inline rad_vec3 rad_photon_position(const rad_photon *p) {
    return v3(p->position[0], p->position[1], p->position[2]);
}

/* Flux times `scale`, into out[3]. */
static inline void rad_photon_power(const rad_photon *p, double scale, double out[3]) {
    /* 2^(exponent - 144) built as a double's bits (exponent 1..255: well inside its range). */
    uint64_t bits = (uint64_t)((int64_t)p->exponent - 144 + 1023) << 52;
    double unit;
    memcpy(&unit, &bits, sizeof unit);
    unit = p->exponent ? unit * scale : 0;
    for (int c = 0; c < 3; ++c) out[c] = p->power[c] * unit;
}

/* An octahedral code of `bits` + `bits` back to a unit vector. */
rad_vec3 rad_octahedral_decode(uint32_t code, int bits);

static inline rad_vec3 rad_photon_normal(const rad_photon *p) {
    return rad_octahedral_decode(p->normal, 8);
}

static inline rad_vec3 rad_photon_incoming(const rad_photon *p) {
    return rad_octahedral_decode((uint32_t)p->incoming_high << 8 | p->incoming_low, 12);
}

typedef struct rad_photon_map {
    rad_photon *photons; /* sorted by bucket */
    size_t count;
    double cell;         /* cell side: the largest radius a query may use */
    uint32_t *bucket_start; /* bucket_count + 1 entries */
    size_t bucket_count;    /* a power of two */
} rad_photon_map;

/* Builds the map over `photons` (taken: freed with the map, or on failure), cells of side
 * `cell` > 0. `threads` compute the keys. An empty map (count 0) answers every query with
 * nothing. */
rad_status rad_photon_map_build(rad_context *ctx, rad_photon *photons, size_t count, double cell,
                                 int threads, rad_photon_map *out);
void rad_photon_map_free(rad_context *ctx, rad_photon_map *map);

/* A run of photons: the map can be built from several, in order, without joining them first. */
typedef struct rad_photon_run {
    const rad_photon *photons;
    size_t count;
} rad_photon_run;

/* The same map over the runs' photons in their order (not taken: the caller frees them). */
rad_status rad_photon_map_build_runs(rad_context *ctx, const rad_photon_run *runs, size_t run_count,
                                     double cell, int threads, rad_photon_map *out);

/* A neighbour found by rad_photon_map_nearest. */
typedef struct rad_photon_near {
    const rad_photon *photon;
    double distance2;
} rad_photon_near;

/* The photons within `radius` (<= the cell side) of x whose surface normal agrees with `normal`
 * (cosine above 0.9: the same side of the same wall), nearest first, at most `k` of them (k >= 1;
 * `found` must have room for k). Returns how many; *radius2 is the squared radius of the disc
 * they fill: the k-th distance when k were found (Jensen's k nearest), else radius^2. */
size_t rad_photon_map_nearest(const rad_photon_map *map, rad_vec3 x, rad_vec3 normal,
                              double radius, size_t k, rad_photon_near *found, double *radius2);

/* The same k nearest in heap order (no sort: the farthest first when k were found), for
 * estimates that only sum over them. */
size_t rad_photon_map_nearest_heap(const rad_photon_map *map, rad_vec3 x, rad_vec3 normal,
                                   double radius, size_t k, rad_photon_near *found,
                                   double *radius2);

/* Irradiance at x on a surface of front normal `normal` from the photons within `radius`
 * (<= the cell side): the sum of their power over pi r^2 (a box kernel). With k > 0, from the k
 * nearest within `radius` (the k-th excluded from the sum: (k-1)/(pi r_k^2) is the unbiased
 * density of a Poisson process), `scratch` holding k entries. */
void rad_photon_map_irradiance(const rad_photon_map *map, rad_vec3 x, rad_vec3 normal,
                               double radius, size_t k, rad_photon_near *scratch, double out[3]);

#endif
