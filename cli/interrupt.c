/* interrupt.c - Ctrl-C asks the running command to stop (see interrupt.h). */
#include "interrupt.h"

#include <signal.h>
#include <string.h>

static volatile sig_atomic_t interrupted; /* the signal number, 0 before any */
static int installed;

/* The first signal sets the flag; the next one takes the default action (the process ends). */
static void on_signal(int signal_number) {
    interrupted = signal_number;
    struct sigaction default_action;
    memset(&default_action, 0, sizeof default_action);
    default_action.sa_handler = SIG_DFL;
    sigemptyset(&default_action.sa_mask);
    sigaction(signal_number, &default_action, NULL);
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
