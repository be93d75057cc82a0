/* factory.c - the list of form-factor methods and the choice of the default. */
#include "formfactor/geometric.h"

#include "scene/scene.h"

rad_status rad_ff_analytic_create(const rad_ff_context *context, rad_ff_provider **out);

/* Defaults chosen by measurement: docs/formfactors.md. */
static const rad_ff_method_entry methods[] = {
    {RAD_FF_ANALYTIC, "analytic", 4, rad_ff_analytic_create},
};
#define METHOD_COUNT (sizeof methods / sizeof methods[0])
#define DEFAULT_METHOD RAD_FF_ANALYTIC

const rad_ff_method_entry *rad_ff_method_find(rad_ff_method method) {
    if (method == RAD_FF_DEFAULT) method = DEFAULT_METHOD;
    for (size_t i = 0; i < METHOD_COUNT; ++i)
        if (methods[i].method == method) return &methods[i];
    return NULL;
}

rad_vec3 rad_element_sample(const rad_mesh *mesh, size_t element, double u1, double u2) {
    rad_vec3 a = rad_element_corner(mesh, element, 0), b = rad_element_corner(mesh, element, 1),
             c = rad_element_corner(mesh, element, 2);
    if (rad_mesh_corner_count(mesh, element) == 4) {
        /* Bilinear: exactly uniform for parallelograms, the elements a grid makes. */
        rad_vec3 d = rad_element_corner(mesh, element, 3);
        return v3_add(v3_add(v3_scale(a, (1 - u1) * (1 - u2)), v3_scale(b, u1 * (1 - u2))),
                      v3_add(v3_scale(c, u1 * u2), v3_scale(d, (1 - u1) * u2)));
    }
    double s = sqrt(u1);
    return v3_add(v3_scale(a, 1 - s), v3_add(v3_scale(b, s * (1 - u2)), v3_scale(c, s * u2)));
}

rad_status rad_ff_create(rad_context *ctx, const rad_scene *scene, const rad_mesh *mesh,
                         const rad_ff_options *options, rad_ff_provider **out) {
    *out = NULL;
    const rad_ff_method_entry *entry = rad_ff_method_find(options->method);
    if (!entry)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "form-factor method %d is not available",
                        (int)options->method);
    if (options->samples < 0 || options->hemicube_resolution < 0)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "samples and resolution must be positive");
    rad_ff_context context = {ctx, mesh, NULL, *options};
    context.options.method = entry->method;
    if (context.options.samples == 0) context.options.samples = entry->default_samples;
    rad_rays *rays = NULL;
    rad_status status = rad_rays_create(ctx, scene, &rays);
    if (status) return status;
    context.rays = rays;
    status = entry->create(&context, out); /* the provider takes the rays */
    if (status) rad_rays_destroy(rays);
    return status;
}
