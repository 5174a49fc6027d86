/* SIGTERM and SIGINT as a request to stop (rs_core_interrupt, interrupt.f90): what a scheduler
   sends at a job's time limit, and Ctrl-C. The handler only notes the signal; the time loop
   looks at it after each step, flushes what it has, marks the file 'interrupted' and exits
   with 128 + the signal (docs/user/output.md). A second SIGINT stops at once. */
#include <signal.h>
#include <string.h>

static volatile sig_atomic_t requested = 0;

static void note_signal(int signal_number)
{
    if (requested == SIGINT && signal_number == SIGINT) {
        /* Ctrl-C twice: the user does not want to wait for the flush. */
        signal(SIGINT, SIG_DFL);
        raise(SIGINT);
        return;
    }
    requested = signal_number;
}

/* Install the handler for SIGTERM and SIGINT (after PETSc's initialization, which installs
   its own, aborting one). Returns 0 on success. */
int rs_install_interrupt_handlers(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = note_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    if (sigaction(SIGTERM, &action, NULL) != 0) return 1;
    if (sigaction(SIGINT, &action, NULL) != 0) return 1;
    return 0;
}

/* The signal that asked to stop, 0 if none. */
int rs_interrupt_signal(void) { return (int)requested; }
