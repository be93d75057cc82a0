/* geometric.h - what every geometric form-factor method shares: the mesh, the input geometry's
 * ray queries, the options, and small helpers for points on elements. One file per method:
 * analytic.c, hemicube.c, raycast.c, montecarlo.c; the table in factory.c lists them. */
#ifndef RAD_FORMFACTOR_GEOMETRIC_H
#define RAD_FORMFACTOR_GEOMETRIC_H

#include "formfactor/provider.h"
#include "mesh/mesh.h"
#include "scene/rays.h"

typedef struct rad_ff_context {
    rad_context *ctx;
    const rad_mesh *mesh;   /* owned by the system */
    const rad_rays *rays;   /* owned by the provider that holds this */
    rad_ff_options options; /* samples and resolution already defaulted */
} rad_ff_context;

typedef struct rad_ff_method_entry {
    rad_ff_method method;
    const char *name;
    int default_samples;
    rad_status (*create)(const rad_ff_context *context, rad_ff_provider **out);
} rad_ff_method_entry;

/* Creates the provider for options->method over a mesh (RAD_FF_DEFAULT picks the default). */
rad_status rad_ff_create(rad_context *ctx, const struct rad_scene *scene, const rad_mesh *mesh,
                         const rad_ff_options *options, rad_ff_provider **out);

/* The method table (factory.c). */
const rad_ff_method_entry *rad_ff_method_find(rad_ff_method method);

/* A point on element e from two uniform numbers (uniform by area). */
rad_vec3 rad_element_sample(const rad_mesh *mesh, size_t element, double u1, double u2);

/* Corner k of element e. */
static inline rad_vec3 rad_element_corner(const rad_mesh *mesh, size_t element, int k) {
    return mesh->vertices[mesh->element_vertices[element][k]];
}

/* Point-to-polygon form factor (Lambert's contour integral, Baum et al. 1989): the fraction of
 * the energy leaving a differential area at x with unit normal n that arrives at the polygon,
 * or by reciprocity F(dA -> polygon). The polygon (counter-clockwise seen from its front) is
 * clipped to the hemisphere above x; only its front side receives. */
double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *polygon, int count);

#endif
