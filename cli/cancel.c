/* cancel.c - see cancel.h. */
#include "cancel.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>

/* The one piece of process state a signal handler may touch. */
static atomic_int cancel_requested;

static void on_signal(int sig)
{
    (void)sig;
    atomic_store(&cancel_requested, 1);
}

const atomic_int *cli_cancel_on_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    return &cancel_requested;
}
