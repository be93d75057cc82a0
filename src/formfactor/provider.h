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
    /* Optional (NULL when not offered): the rows of patches[0 .. count) into out[0 .. count),
     * the same values as row() gives, computed together (any count: up to rad_ff_rows_ahead
     * block by block, more one row a task). */
    rad_status (*rows)(rad_ff_provider *self, const size_t *patches, size_t count,
                       float *const *out);
    /* Optional, for providers that keep rows (the row cache): nonzero when the row of `patch`
     * is kept, so row() copies it; and the rows of patches[0 .. count) that a solver will ask
     * for soon, computed together and kept (those not kept yet; nothing when they would not
     * fit without evicting others or the inner provider cannot compute rows together). */
    int (*holds)(const rad_ff_provider *self, size_t patch);
    rad_status (*prefetch)(rad_ff_provider *self, const size_t *patches, size_t count);
};

/* Rows a solver hands to prefetch() as a guess of what comes next; more when it asks for every
 * row of a small system at once (shooting.c). */
enum { rad_ff_rows_ahead = 8 };

/* The provider of a system whose form factors are given (a .ffm file or dense arrays):
 * n patches, n elements, row-major n x n matrix, copied. */
rad_status rad_ff_given_create(rad_context *ctx, size_t n, const double *form_factors,
                               const float *form_factors_float, rad_ff_provider **out);

static inline void rad_ff_provider_destroy(rad_ff_provider *provider) {
    if (provider) provider->destroy(provider);
}

#endif
