/* solve_watch.h - watching `radiosity solve` converge (cli/solve_watch.c): the iteration
 * callback behind --log (CSV rows), --plot (residual against time), --snapshots (an image
 * every K shots), the progress line on a terminal, and Ctrl-C (cli/interrupt.h: the solver
 * stops and keeps what it has done, which --save then saves).
 * The solver comparison (cli/solve_compare.c) uses the same pieces. */
#ifndef RAD_CLI_SOLVE_WATCH_H
#define RAD_CLI_SOLVE_WATCH_H

#include "radiosity.h"
#include "plot.h"

#include <stdio.h>

typedef struct solve_watch {
    const rad_system *system;
    const char *solver_name;
    int shooting;        /* shots (shooting, importance) rather than rounds */
    int hierarchy;       /* --log adds links, leaves and the oracle's largest error */
    long step_offset;    /* steps done before a resumed run */
    double tolerance;    /* for the time-left estimate */
    double time_budget;  /* 0: none */

    /* --log: rows kept in memory, written whole at the end. */
    FILE *log;
    char *log_buffer;
    size_t log_size;
    const char *log_prefix; /* a first column (the solver's name) in the comparison, or NULL */

    /* --plot: the series drawn (the view error's too, in the comparison). */
    plot_series *series, *view_series;

    /* Comparison: error against a reference solution, overall and as the camera sees it. */
    const double *reference;   /* 3 per element, or NULL */
    const double *view_share;  /* per element, or NULL */
    double stop_error;         /* stop once the error is at most this (0: never) */
    double last_error, last_view_error;
    double error_seconds, view_error_seconds; /* first time at or under `target` (-1: never) */
    long error_steps, view_error_steps;
    double target;

    /* Progress line (stderr is a terminal and not --quiet). */
    int progress;
    double last_draw;
    double history_t[64], history_r[64]; /* (seconds, ln residual) for the time-left estimate */
    int history_count;

    /* Snapshots: called every `snapshot_every` steps; returns nonzero to stop (it failed). */
    int snapshot_every;
    int (*snapshot)(void *user, long step);
    void *snapshot_user;
    int failed; /* a snapshot or an allocation failed: the message is printed */
} solve_watch;

/* The rad_iteration_fn: pass a solve_watch as the user pointer. */
int solve_watch_iteration(void *user, const rad_iteration_event *event);

/* Clears the progress line, if one was drawn. */
void solve_watch_finish(solve_watch *watch);

/* The error of the system's solution against watch->reference (and the view's), updating
 * last_error and last_view_error. */
void solve_watch_measure(solve_watch *watch);

#endif
