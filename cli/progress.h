/* progress.h - what a long command shows on stderr while it works: a progress bar (the phase,
 * how much is done, the rate and the time left) when stderr is a terminal; when it is not (a
 * batch job, a log file), one line per stage ("radiosity: [mesh] ...") and a progress line
 * every few seconds of long work instead; nothing but warnings and errors with --quiet.
 * Warnings clear the bar before they print. */
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

/* Batch feedback (stderr not a terminal, not --quiet; nothing otherwise): one line
 * "radiosity: [STAGE] what", e.g. "radiosity: [mesh] 8 surfaces, 40 patches, 2527 elements,
 * 0.41 s". The square brackets tell these lines from errors and notes. */
void cli_stage(const char *stage, const char *format, ...) __attribute__((format(printf, 2, 3)));

/* The stage lines of the shared steps: the mesh of a new system, and a finished solve. */
void cli_stage_mesh(const rad_system *system, double seconds);
void cli_stage_solve(const rad_solve_options *solve, const rad_solve_report *report);

/* How a solve ended, in the words every command prints: "converged", "converged (tail rule)"
 * (the hierarchical solver's tail rule ended it, RAD_STOP_TAIL: every link passed the oracle
 * at the radiosities it was refined with) or "not converged". */
const char *cli_solve_outcome(const rad_solve_report *report);
/* The report's residual as text in `out` ("not measured" when a step was cut short). */
const char *cli_residual_text(char *out, size_t size, const rad_solve_report *report);

#endif
