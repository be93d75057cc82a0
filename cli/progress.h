/* progress.h - what a long command shows on stderr while it works: a progress bar (the phase,
 * how much is done, the rate and the time left) when stderr is a terminal, nothing when it is
 * not or with --quiet; and warnings, which clear the bar before they print. */
#ifndef RAD_CLI_PROGRESS_H
#define RAD_CLI_PROGRESS_H

#include "radiosity.h"

/* A context like cli_context (exits with 1 when it cannot make one; Ctrl-C cancels the work,
 * interrupt.h) whose progress reports also draw the bar. */
rad_context *cli_context_with_progress(int threads, uint64_t seed, double max_memory_mib,
                                       int quiet);

/* Clears the bar (before printing results, and at the end). */
void cli_progress_clear(void);

/* The progress callback itself, for contexts made elsewhere; `user` is unused. Returns nonzero
 * (stop) after Ctrl-C. */
int cli_progress_report(void *user, const char *phase, double done, double total);

#endif
