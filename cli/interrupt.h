/* interrupt.h - Ctrl-C: the first SIGINT (or SIGTERM) asks the running command to stop; the
 * library sees it through the progress callback, returns RAD_ERROR_CANCELLED and leaves its
 * results as far as they got, so the command can keep them (solve --save) and exits with 130
 * (143 for SIGTERM). A second Ctrl-C kills the process at once. */
#ifndef RAD_CLI_INTERRUPT_H
#define RAD_CLI_INTERRUPT_H

/* Exit status of an interrupted command: 128 + SIGINT, what shells report for Ctrl-C. */
#define EXIT_INTERRUPTED 130

/* Installs the handlers (once; later calls do nothing). */
void cli_interrupt_install(void);

/* Nonzero once Ctrl-C was pressed (or SIGTERM arrived). */
int cli_interrupted(void);

/* The exit status of an interrupted command: 128 + the signal (130 for Ctrl-C). */
int cli_interrupt_exit_status(void);

#endif
