/* given.c - the form-factor provider for systems whose matrix is given (.ffm, dense arrays). */
#include "formfactor/provider.h"

#include <string.h>

typedef struct given_provider {
    rad_ff_provider base;
    rad_context *ctx;
    size_t n;
    float *matrix; /* row-major n x n */
} given_provider;

static rad_status given_row(rad_ff_provider *self, size_t patch, float *row) {
    given_provider *given = (given_provider *)self;
    memcpy(row, given->matrix + patch * given->n, given->n * sizeof *row);
    return RAD_OK;
}

static void given_destroy(rad_ff_provider *self) {
    given_provider *given = (given_provider *)self;
    rad_free(given->ctx, given->matrix);
    rad_free(given->ctx, given);
}

rad_status rad_ff_given_create(rad_context *ctx, size_t n, const double *form_factors,
                               const float *form_factors_float, rad_ff_provider **out) {
    *out = NULL;
    size_t cells;
    if (rad_size_mul(n, n, &cells))
        return rad_fail(ctx, RAD_ERROR_MEMORY_BUDGET, "%zu patches: matrix size overflows", n);
    rad_status status = rad_check_budget(ctx, 4.0 * (double)cells, "the form-factor matrix");
    if (status) return status;
    given_provider *given = rad_alloc_zero(ctx, 1, sizeof *given);
    if (!given) return RAD_ERROR_NO_MEMORY;
    given->matrix = rad_alloc(ctx, cells, sizeof(float));
    if (!given->matrix) {
        rad_free(ctx, given);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t i = 0; i < cells; ++i)
        given->matrix[i] = form_factors ? (float)form_factors[i] : form_factors_float[i];
    given->ctx = ctx;
    given->n = n;
    given->base.method = "given";
    given->base.row = given_row;
    given->base.destroy = given_destroy;
    *out = &given->base;
    return RAD_OK;
}
