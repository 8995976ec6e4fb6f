/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * interrupt.h -- the signals that stop a taper process, and the state they
 * leave: process-wide by nature (a signal reaches the process, not a run),
 * so kept here, apart from the runs that read it.
 *
 * SIGINT (Ctrl-C), SIGTERM (`timeout`, `kill`, batch queues at their time
 * limit), SIGHUP (the terminal closed) and SIGXCPU (a CPU-time limit) stop
 * the runs, each phase at its next look (docs/scene.md, "Signals, time
 * limits and batch queues"): the library's monitor during the theory and
 * the integration, the writers between rows, the sweep between runs.  The
 * first one is recorded and read with interrupt_signal(); a second one
 * while results are written removes the temporary files being written
 * (results/output.h) and ends the process by that signal's default action.
 * SIGHUP ignored by the parent (nohup) stays ignored.  SIGXFSZ (a file-size
 * limit, `ulimit -f`) is ignored, so that a write beyond the limit fails
 * with EFBIG and is reported like a full disk instead of killing the
 * process with its temporary file left behind.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_RUN_INTERRUPT_H
#define TAPER_RUN_INTERRUPT_H

#include <stddef.h>

/* Installs the handlers (once, before any run). */
void interrupt_install(void);

/* The number of the first stop signal, 0 if none: received by this
 * process, or by another MPI rank (interrupt_from_rank). */
int interrupt_signal(void);

/* Stops the runs as that signal does: signal sig received by MPI rank
 * `rank` (drivers/taper/sweep_mpi.c), which stops the whole sweep. */
void interrupt_from_rank(int sig, int rank);

/* Process pid (named `name`) launched this one and stops it on the user's
 * behalf: mpirun sends SIGTERM to every rank when it gets Ctrl-C, SIGINT,
 * SIGTERM or SIGHUP itself.  Messages then say "interrupted by SIGTERM
 * from mpirun", not the signal the user sent, which only mpirun saw. */
void interrupt_set_launcher(long pid, const char *name);

/* "SIGTERM", "SIGTERM from mpirun" (the launcher stopping the ranks),
 * "SIGINT to rank 2" (another rank's signal stopping the sweep). */
void interrupt_describe(char *buf, size_t size);

#endif
