/* provider.h - the one interface between form factors and solvers.
 *
 * A provider answers rows: for a shooting patch p, the fraction of the energy leaving p that
 * arrives at every element j (F_pj, element_count floats). Solvers ask for rows on demand
 * (shooting: memory O(n)) or assemble the whole matrix (gathering, direct). Nothing in
 * src/solve/ knows how a row is computed. */
#ifndef RAD_FORMFACTOR_PROVIDER_H
#define RAD_FORMFACTOR_PROVIDER_H

#include "core/context.h"

#include <stddef.h>

typedef struct rad_ff_provider rad_ff_provider;

struct rad_ff_provider {
    const char *method; /* "given", "analytic", "hemicube", ... */
    /* Fills row[0 .. element_count) with F(patch -> element). Called from one thread; may run
     * in parallel inside. Rows do not depend on the order in which they are asked for. */
    rad_status (*row)(rad_ff_provider *self, size_t patch, float *row);
    void (*destroy)(rad_ff_provider *self);
};

/* The provider of a system whose form factors are given (a .ffm file or dense arrays):
 * n patches, n elements, row-major n x n matrix, copied. */
rad_status rad_ff_given_create(rad_context *ctx, size_t n, const double *form_factors,
                               const float *form_factors_float, rad_ff_provider **out);

static inline void rad_ff_provider_destroy(rad_ff_provider *provider) {
    if (provider) provider->destroy(provider);
}

#endif
