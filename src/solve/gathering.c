/* gathering.c - shared set-up for the gathering solvers. */
#include "solve/gathering.h"

rad_status rad_gathering_begin(rad_solver_run *run, rad_gathering *g) {
    rad_system *s = run->system;
    *g = (rad_gathering){0};
    rad_status status = rad_gather_matrix(s, &g->matrix);
    if (status) return status;
    for (int c = 0; c < 3; ++c) {
        g->patch_b[c] = rad_alloc(s->ctx, s->patch_count, sizeof(double));
        if (!g->patch_b[c]) {
            rad_gathering_end(run, g);
            return RAD_ERROR_NO_MEMORY;
        }
    }
    for (size_t p = 0; p < s->patch_count; ++p) rad_gathering_update_patch(s, g, p);
    return RAD_OK;
}

void rad_gathering_end(rad_solver_run *run, rad_gathering *g) {
    rad_context *ctx = run->system->ctx;
    rad_free(ctx, g->matrix);
    for (int c = 0; c < 3; ++c) rad_free(ctx, g->patch_b[c]);
    *g = (rad_gathering){0};
}

void rad_gathering_update_patch(const rad_system *s, rad_gathering *g, size_t p) {
    double mean[3];
    rad_system_patch_mean(s, (const rad_rgb *)s->radiosity, p, mean);
    for (int c = 0; c < 3; ++c) g->patch_b[c][p] = mean[c];
}
