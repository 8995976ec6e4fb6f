/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * interrupt.c -- the signals that stop a taper process (interrupt.h).
 */
#include "run/interrupt.h"

#include "results/output.h"

#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

/* The signal that stopped the runs: this process's first (the handler),
 * or one another MPI rank received (interrupt_from_rank), whichever came
 * first.  Lock-free, so both may set it. */
static atomic_int interrupted;
static volatile sig_atomic_t received;     /* this process's first signal    */
static volatile sig_atomic_t sender;       /* the process that sent it (0: unknown) */
static volatile sig_atomic_t on_rank = -1; /* interrupted by that rank's signal */
static long launcher;                      /* interrupt_set_launcher's process, and its name */
static char launcher_name[32];

static const int stop_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGXCPU};
#define N_STOP_SIGNALS (sizeof stop_signals / sizeof stop_signals[0])

static void on_signal(int sig, siginfo_t *info, void *context)
{
    (void)context;
    if (!received) { /* the first: stop the runs (unless another rank's did) */
        received = sig;
        sender = info && info->si_code == SI_USER ? (sig_atomic_t)info->si_pid : 0;
        int none = 0;
        atomic_compare_exchange_strong(&interrupted, &none, sig);
        return;
    }
    out_signal_cleanup();
    signal(sig, SIG_DFL);
    raise(sig);
}

static int stopped(void) { return atomic_load(&interrupted); }

void interrupt_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = on_signal;
    sa.sa_flags = SA_SIGINFO;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < N_STOP_SIGNALS; i++) sigaddset(&sa.sa_mask, stop_signals[i]);
    for (size_t i = 0; i < N_STOP_SIGNALS; i++) {
        struct sigaction old;
        /* SIGHUP ignored by the parent (nohup) stays ignored.  SIGINT is
         * ignored in the background jobs of a shell script, yet `kill -INT`
         * there is meant: it is handled all the same. */
        if (stop_signals[i] == SIGHUP && sigaction(SIGHUP, NULL, &old) == 0 &&
            old.sa_handler == SIG_IGN)
            continue;
        sigaction(stop_signals[i], &sa, NULL);
    }
    /* A write beyond `ulimit -f` fails with EFBIG (reported, its temporary
     * file removed) instead of killing the process. */
    signal(SIGXFSZ, SIG_IGN);
    /* The writers stop between rows at a signal that comes while they
     * write a complete result (results/output.h). */
    out_set_stop_check(stopped);
}

int interrupt_signal(void) { return atomic_load(&interrupted); }

void interrupt_from_rank(int sig, int rank)
{
    int none = 0;
    on_rank = rank;
    if (!atomic_compare_exchange_strong(&interrupted, &none, sig)) on_rank = -1;
}

void interrupt_set_launcher(long pid, const char *name)
{
    launcher = pid;
    snprintf(launcher_name, sizeof launcher_name, "%s", name);
}

static const char *signal_name(int sig)
{
    switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGXCPU: return "SIGXCPU";
    default: return "a signal";
    }
}

void interrupt_describe(char *buf, size_t size)
{
    int n = snprintf(buf, size, "%s", signal_name(atomic_load(&interrupted)));
    if (n < 0 || (size_t)n >= size) return;
    if (on_rank >= 0)
        snprintf(buf + n, size - (size_t)n, " to rank %d", (int)on_rank);
    else if (launcher && sender == launcher)
        snprintf(buf + n, size - (size_t)n, " from %s", launcher_name);
}
