/* gather_matrix.c - assembling the whole form-factor matrix for gathering and direct solvers.
 * Rows come from the provider (F_pe: patch p to element e) and are stored transposed and scaled,
 * G_ep = A_p F_pe / A_e, the coefficient of B_p in what element e gathers. */
#include "solve/solver.h"

#include <stdio.h>

rad_status rad_gather_matrix(rad_system *s, float **out) {
    *out = NULL;
    rad_context *ctx = s->ctx;
    size_t cells;
    if (rad_size_mul(s->element_count, s->patch_count, &cells))
        return rad_fail(ctx, RAD_ERROR_MEMORY_BUDGET, "the form-factor matrix is too large");
    char what[160];
    snprintf(what, sizeof what,
             "the form-factor matrix (%zu elements x %zu patches, float32; use --solver "
             "shooting, which needs no matrix)", s->element_count, s->patch_count);
    rad_status status = rad_check_budget(ctx, 4.0 * (double)cells, what);
    if (status) return status;
    float *g = rad_alloc(ctx, cells, sizeof *g);
    float *row = rad_alloc(ctx, s->element_count, sizeof *row);
    if (!g || !row) {
        rad_free(ctx, g);
        rad_free(ctx, row);
        return RAD_ERROR_NO_MEMORY;
    }
    size_t np = s->patch_count;
    for (size_t p = 0; p < np; ++p) {
        status = s->ff->row(s->ff, p, row);
        if (status) break;
        double area_p = s->patch_area[p];
        for (size_t e = 0; e < s->element_count; ++e)
            g[e * np + p] = (float)(area_p * row[e] / s->area[e]);
        if (rad_progress(ctx, "form factors", (double)(p + 1), (double)np)) {
            status = rad_fail(ctx, RAD_ERROR_CANCELLED, "cancelled while computing form factors");
            break;
        }
    }
    rad_free(ctx, row);
    if (status) {
        rad_free(ctx, g);
        return status;
    }
    *out = g;
    return RAD_OK;
}

double rad_max_radiosity(const rad_system *s) {
    double m = 1e-300;
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c)
            if (s->radiosity[e][c] > m) m = s->radiosity[e][c];
    return m;
}
