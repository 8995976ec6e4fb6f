/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_print.h -- what a sweep prints while it runs: each run's messages
 * in the order of the sweep, as soon as every run before it is done (the
 * same text whatever the threads and ranks), and a progress line.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SWEEP_PRINT_H
#define TAPER_SWEEP_PRINT_H

#include "run/sweep_queue.h"

typedef struct sweep_printer {
    size_t committed;    /* runs 0..committed-1 printed                    */
    int show;            /* a progress line                                */
    double every;        /* seconds between lines: 0.25 on a terminal;
                            under mpirun, which hides the terminal from
                            the ranks, a line of its own every 10 s         */
    int on_screen;
    double start, last;
    unsigned ranks, threads;
} sweep_printer;

/* progress: &output progress; remote: other ranks compute runs too (a
 * progress line even without a terminal). */
void sweep_print_start(sweep_printer *p, int progress, int remote, unsigned ranks,
                       unsigned threads);
/* Prints the runs that are done and have every earlier run done. */
void sweep_print_ready(sweep_printer *p, sweep *sw);
/* The progress line, if due (force: now). */
void sweep_print_progress(sweep_printer *p, sweep *sw, int force);
/* Removes the progress line from the terminal. */
void sweep_print_clear(sweep_printer *p);
/* After an interruption: what the runs done after the first one missing
 * printed. */
void sweep_print_rest(const sweep_printer *p, const sweep *sw);

#endif
