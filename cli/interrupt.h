/* interrupt.h - Ctrl-C: the first SIGINT asks the running command to stop; the library sees it
 * through the progress callback, returns RAD_ERROR_CANCELLED and leaves its results as far as
 * they got, so the command can keep them (solve --save) and exits with 130. A second Ctrl-C
 * (half a second or more after the first; timeout(1) delivers one twice) kills the process at
 * once. SIGTERM keeps its default action: a command must die when told
 * to, even inside a step that reports no progress. */
#ifndef RAD_CLI_INTERRUPT_H
#define RAD_CLI_INTERRUPT_H

/* Exit status of an interrupted command: 128 + SIGINT, what shells report for Ctrl-C. */
#define EXIT_INTERRUPTED 130

/* Installs the handler (once; later calls do nothing). A process started with SIGINT ignored
 * (nohup, a background job of a script) leaves it ignored, as shells expect. */
void cli_interrupt_install(void);

/* Nonzero once Ctrl-C was pressed. */
int cli_interrupted(void);

/* The exit status of an interrupted command: 128 + SIGINT = 130. */
int cli_interrupt_exit_status(void);

#endif
