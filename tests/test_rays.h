/* test_rays.h - a check of the element rays' shapes (system/element_rays.h) for the mesh and
 * hierarchy tests. Uses test.h's CHECK. */
#ifndef RAD_TEST_RAYS_H
#define RAD_TEST_RAYS_H

#include "core/rng.h"
#include "system/element_rays.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>

/* Flat grids and trees traced as one quad each (element_rays.h) hit what the elements would:
 * rays from random points in random directions against the mesh with its shapes and against a
 * copy without them (every element a primitive). Both hit or both miss, at the same distance;
 * the element found is the same one (away from the elements' shared edges, where either may be
 * hit); and the element's map at the u, v given is the point hit (bilinear on a shape's quad
 * element, Embree's triangles otherwise). Between fewest and most shapes are taken. */
static inline void check_shape_hits(rad_context *ctx, const char *name, const rad_mesh *mesh,
                                    size_t fewest, size_t most) {
    rad_mesh plain = *mesh;
    plain.grid_count = plain.tree_count = 0;
    rad_element_rays *grids = NULL, *elements = NULL;
    /* Robust traversal in both (the renderer's camera rays'): without it a ray that passes
     * within rounding of a shared edge may slip through one structure and not the other. */
    CHECK(rad_element_rays_create(ctx, mesh, &grids) == RAD_OK);
    CHECK(rad_element_rays_create(ctx, &plain, &elements) == RAD_OK);
    if (!grids || !elements) goto done;
    CHECK(grids->quad_count >= fewest && grids->quad_count <= most);
    CHECK(elements->quad_count == 0);
    rad_vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < mesh->vertex_count; ++i) {
        rad_vec3 p = mesh->vertices[i];
        lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    double diagonal = v3_length(v3_sub(hi, lo));
    /* The elements traced as themselves. */
    unsigned char *loose = calloc(mesh->element_count + 1, 1);
    if (!loose) goto done;
    for (size_t i = 0; i < grids->loose_count; ++i)
        loose[grids->loose ? grids->loose[i] : i] = 1;
    rad_rng rng = rad_rng_make(7, 0);
    int hits = 0, same_hit = 1, other_element = 0, far = 0, off = 0;
    const int rays = 20000;
    for (int n = 0; n < rays; ++n) {
        rad_vec3 o = v3(lo.x + (hi.x - lo.x) * rad_rng_uniform(&rng),
                        lo.y + (hi.y - lo.y) * rad_rng_uniform(&rng),
                        lo.z + (hi.z - lo.z) * rad_rng_uniform(&rng));
        rad_vec3 d = v3_normalize(v3(rad_rng_uniform(&rng) - 0.5, rad_rng_uniform(&rng) - 0.5,
                                     rad_rng_uniform(&rng) - 0.5));
        rad_element_hit a, b;
        int ha = rad_element_rays_intersect(elements, o, d, 0, INFINITY, &a);
        int hb = rad_element_rays_intersect(grids, o, d, 0, INFINITY, &b);
        if (ha != hb) {
            same_hit = 0;
            continue;
        }
        if (!ha) continue;
        ++hits;
        if (fabs(a.t - b.t) > 1e-5 * diagonal) ++far;
        /* The point at u, v: the element's bilinear map on a grid, Embree's two triangles
         * (rad_element_point) on the other elements, as before. */
        rad_vec3 x = v3_add(o, v3_scale(d, b.t)), at = rad_element_point(mesh, b.element, b.u, b.v);
        if (!loose[b.element] && rad_mesh_corner_count(mesh, b.element) == 4) {
            double weight[4];
            rad_element_weights(mesh, b.element, b.u, b.v, weight);
            at = v3(0, 0, 0);
            for (int k = 0; k < 4; ++k)
                at = v3_add(at, v3_scale(mesh->vertices[mesh->element_vertices[b.element][k]],
                                         weight[k]));
        }
        if (v3_length(v3_sub(at, x)) > 1e-5 * diagonal) ++off;
        other_element += a.element != b.element;
    }
    printf("%s: %zu grids and trees as quads, %d of %d rays hit, %d on another element\n", name,
           grids->quad_count, hits, rays, other_element);
    CHECK(hits > rays / 10);
    CHECK(same_hit);
    CHECK(far == 0);
    CHECK(off == 0);
    CHECK(other_element <= hits / 500);
    free(loose);
done:
    rad_element_rays_destroy(grids);
    rad_element_rays_destroy(elements);
}

#endif
