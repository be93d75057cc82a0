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

/* One photon where it landed. */
typedef struct rad_photon {
    rad_vec3 position;
    float power[3];    /* flux, watts (in the scene's radiance units times area) */
    float normal[3];   /* the front normal of the surface it landed on */
    float incoming[3]; /* unit, from the surface towards where the photon came from */
} rad_photon;

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

/* The same map over the runs' photons in their order (not taken: the caller frees them), each
 * photon's power divided by `divisor` as it is copied into the map. */
rad_status rad_photon_map_build_runs(rad_context *ctx, const rad_photon_run *runs, size_t run_count,
                                     double divisor, double cell, int threads, rad_photon_map *out);

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
