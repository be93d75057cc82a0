/* interrupt.c - Ctrl-C asks the running command to stop (see interrupt.h). */
#include "interrupt.h"

#include <signal.h>
#include <string.h>
#include <time.h>

/* A second SIGINT this soon after the first is the same Ctrl-C delivered twice (timeout(1),
 * for one, signals both the command and its process group), not a second press. */
#define REPEAT_SECONDS 0.5

static volatile sig_atomic_t interrupted; /* the signal number, 0 before any */
static struct timespec first_time;        /* when the first one came */
static int installed;

static double seconds_since(const struct timespec *then) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now); /* async-signal-safe */
    return (double)(now.tv_sec - then->tv_sec) + 1e-9 * (double)(now.tv_nsec - then->tv_nsec);
}

/* The first signal sets the flag; a later one takes the default action (the process ends). */
static void on_signal(int signal_number) {
    if (!interrupted) {
        clock_gettime(CLOCK_MONOTONIC, &first_time);
        interrupted = signal_number;
        return;
    }
    if (seconds_since(&first_time) < REPEAT_SECONDS) return;
    struct sigaction default_action;
    memset(&default_action, 0, sizeof default_action);
    default_action.sa_handler = SIG_DFL;
    sigemptyset(&default_action.sa_mask);
    sigaction(signal_number, &default_action, NULL);
    raise(signal_number);
}

void cli_interrupt_install(void) {
    if (installed) return;
    installed = 1;
    /* Started with Ctrl-C ignored (nohup, a background job of a script): keep it ignored. */
    struct sigaction current;
    if (sigaction(SIGINT, NULL, &current) == 0 && current.sa_handler == SIG_IGN) return;
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, NULL);
}

int cli_interrupted(void) { return interrupted != 0; }

int cli_interrupt_exit_status(void) { return 128 + (interrupted ? interrupted : SIGINT); }
