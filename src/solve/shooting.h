/* shooting.h - what plain shooting (shooting.c) and importance-driven shooting (importance.c)
 * share: the bookkeeping of emitted power and reflectance, one shot from a chosen patch (with
 * over-relaxation and overshooting), and the stopping measure with the ambient term after it.
 * They differ only in which patch shoots next. */
#ifndef RAD_SOLVE_SHOOTING_H
#define RAD_SOLVE_SHOOTING_H

#include "solve/solver.h"

typedef struct rad_shooting {
    float *row;                 /* F(shooter -> every element) */
    double emitted_power;       /* sum over elements and channels of E A */
    double mean_reflectance[3]; /* area-weighted */
    double total_area;
    double ambient[3];          /* Cohen et al. 1988, from the unshot radiosity after the last shot */
    /* Kept up to date by every shot, in the same order of additions as a fresh pass over the
     * elements would use, so they are bit-identical to recomputing them (resume depends on it). */
    double *patch_power;        /* rad_shooting_unshot_power of every patch */
    double unshot_total[3];     /* sum over elements of dB A, per channel */
    double (*chunk_unshot)[3];  /* scratch: each chunk of patches' share of unshot_total */
    int overshoot, with_ambient; /* the solver's options "overshoot" and "ambient" */
} rad_shooting;

/* Unshot power of a patch, sum over its elements and channels of dB A (signed); valid after
 * rad_shooting_begin and every shot. */
static inline double rad_shooting_patch_power(const rad_shooting *state, size_t patch) {
    return state->patch_power[patch];
}

rad_status rad_shooting_begin(rad_solver_run *run, rad_shooting *state);
void rad_shooting_end(rad_solver_run *run, rad_shooting *state);

/* Shoots from `patch`: its mean unshot radiosity times omega, plus the overshoot when asked,
 * goes to every element through the provider's row (or `row` when not NULL). */
rad_status rad_shooting_shoot(rad_solver_run *run, rad_shooting *state, size_t patch,
                              const float *row);

/* After a shot: the unshot power left as a fraction of the power emitted (the stopping
 * measure, also stored in run->unshot_fraction), and the ambient term. */
double rad_shooting_finish(rad_solver_run *run, rad_shooting *state);

#endif
