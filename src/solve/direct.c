/* direct.c - the direct solve: Gaussian elimination with partial pivoting (LAPACK dgesv) on
 * the patch-level system.
 *
 * Elements gather from patches, b = E + diag(rho) G B_patch, and a patch is the area-weighted
 * mean of its elements, B_patch = W b. So (I - W diag(rho) G) B_patch = W E: a dense
 * patch_count system per colour channel (one factorisation when every reflectance is grey),
 * after which one gathering step gives the elements. Same fixed point as the iterative solvers. */
#include "solve/gathering.h"

#include <stdio.h>
#include <string.h>

/* LAPACK: solves A X = B by LU with partial pivoting; A column-major n x n. */
extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
                   const int *ldb, int *info);

static int grey_reflectance(const rad_system *s) {
    for (size_t e = 0; e < s->element_count; ++e)
        if (s->reflectance[e][0] != s->reflectance[e][1] ||
            s->reflectance[e][0] != s->reflectance[e][2])
            return 0;
    return 1;
}

/* A = I - W diag(rho_c) G, column-major: A[q + p * n] couples patch q to patch p. */
static void build_matrix(const rad_system *s, const float *g, int channel, double *a) {
    size_t n = s->patch_count;
    memset(a, 0, n * n * sizeof *a);
    for (size_t q = 0; q < n; ++q) {
        for (size_t e = s->patch_first[q]; e < s->patch_first[q + 1]; ++e) {
            double w = s->area[e] / s->patch_area[q] * s->reflectance[e][channel];
            if (w == 0) continue;
            const float *row = g + e * n;
            for (size_t p = 0; p < n; ++p) a[q + p * n] -= w * (double)row[p];
        }
        a[q + q * n] += 1.0;
    }
}

static rad_status direct_begin(rad_solver_run *run) {
    rad_system *s = run->system;
    size_t n = s->patch_count;
    if (n > 46340) /* n * n must fit an int for LAPACK */
        return rad_fail(s->ctx, RAD_ERROR_MEMORY_BUDGET,
                        "%zu patches are too many for the direct solver; use --solver "
                        "gauss-seidel, jacobi or shooting", n);
    double bytes = 8.0 * (double)n * (double)n + 4.0 * (double)n * (double)s->element_count;
    rad_status status = rad_check_budget(s->ctx, bytes, "the direct solver");
    if (status) {
        char message[RAD_ERROR_MESSAGE_SIZE];
        snprintf(message, sizeof message, "%s; the iterative solvers (--solver gauss-seidel, "
                 "jacobi or shooting) need less", rad_context_error(s->ctx));
        return rad_fail(s->ctx, status, "%s", message);
    }
    rad_gathering *g = rad_alloc_zero(s->ctx, 1, sizeof *g);
    if (!g) return RAD_ERROR_NO_MEMORY;
    run->state = g;
    return rad_gathering_begin(run, g);
}

static rad_status direct_step(rad_solver_run *run, int iteration, double *residual) {
    (void)iteration;
    rad_system *s = run->system;
    rad_gathering *g = run->state;
    size_t n = s->patch_count;
    int grey = grey_reflectance(s);
    double *a = rad_alloc(s->ctx, n * n, sizeof *a);
    double *rhs = rad_alloc(s->ctx, 3 * n, sizeof *rhs);
    int *pivots = rad_alloc(s->ctx, n, sizeof *pivots);
    rad_status status = (a && rhs && pivots) ? RAD_OK : RAD_ERROR_NO_MEMORY;
    /* Right-hand sides: W E, one column per channel. */
    for (size_t p = 0; p < n && !status; ++p) {
        double mean[3];
        rad_system_patch_mean(s, (const rad_rgb *)s->emission, p, mean);
        for (int c = 0; c < 3; ++c) rhs[p + (size_t)c * n] = mean[c];
    }
    int order = (int)n, info = 0;
    for (int c = 0; c < 3 && !status; c += grey ? 3 : 1) {
        build_matrix(s, g->matrix, c, a);
        int columns = grey ? 3 : 1;
        dgesv_(&order, &columns, a, &order, pivots, rhs + (size_t)c * n, &order, &info);
        if (info > 0)
            status = rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT,
                              "the radiosity system is singular (a closed scene with "
                              "reflectance 1?); no unique solution");
    }
    if (!status) {
        for (int c = 0; c < 3; ++c) memcpy(g->patch_b[c], rhs + (size_t)c * n, n * sizeof(double));
        /* One gathering step from the exact patch radiosities gives the elements. */
        for (size_t e = 0; e < s->element_count; ++e) {
            double received[3];
            rad_gathering_gather(g, n, e, received);
            for (int c = 0; c < 3; ++c) {
                s->radiosity[e][c] = s->emission[e][c] + s->reflectance[e][c] * received[c];
                s->unshot[e][c] = 0;
                if (run->tracing) run->received[e][c] = received[c];
            }
        }
    }
    rad_free(s->ctx, a);
    rad_free(s->ctx, rhs);
    rad_free(s->ctx, pivots);
    *residual = 0;
    return status;
}

static void direct_end(rad_solver_run *run) {
    rad_gathering *g = run->state;
    if (!g) return;
    rad_gathering_end(run, g);
    rad_free(run->system->ctx, g);
    run->state = NULL;
}

const rad_solver_impl rad_solver_direct = {
    {"direct", "Gaussian elimination with partial pivoting on the patch system (LAPACK dgesv)",
     RAD_SOLVER_NEEDS_MATRIX | RAD_SOLVER_KEEPS_UNSHOT, NULL, 0, NULL, 0, 0},
    direct_begin, direct_step, direct_end,
};
