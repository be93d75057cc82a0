/* gathering.h - what Jacobi, Gauss-Seidel and the direct solver share: the stored matrix and
 * the patch radiosities in structure-of-arrays form for vectorised dot products. */
#ifndef RAD_SOLVE_GATHERING_H
#define RAD_SOLVE_GATHERING_H

#include "solve/solver.h"

typedef struct rad_gathering {
    float *matrix;        /* G, element_count x patch_count */
    double *patch_b[3];   /* B_p per channel */
} rad_gathering;

rad_status rad_gathering_begin(rad_solver_run *run, rad_gathering *g);
void rad_gathering_end(rad_solver_run *run, rad_gathering *g);

/* Patch p's radiosity from its elements, into g->patch_b. */
void rad_gathering_update_patch(const rad_system *s, rad_gathering *g, size_t p);

/* What element e gathers: out[c] = sum_p G_ep B_p[c]. */
static inline void rad_gathering_gather(const rad_gathering *g, size_t patch_count, size_t e,
                                        double out[3]) {
    const float *row = g->matrix + e * patch_count;
    const double *b0 = g->patch_b[0], *b1 = g->patch_b[1], *b2 = g->patch_b[2];
    double r = 0, gr = 0, b = 0;
#pragma omp simd reduction(+ : r, gr, b)
    for (size_t p = 0; p < patch_count; ++p) {
        double f = (double)row[p];
        r += f * b0[p];
        gr += f * b1[p];
        b += f * b2[p];
    }
    out[0] = r;
    out[1] = gr;
    out[2] = b;
}

#endif
