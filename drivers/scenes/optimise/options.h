/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * options.h -- what a calibration and a design share: how one is run
 * (threads, interruption, journal, progress) and how it ended.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_OPTIONS_H
#define TAPER_OPT_OPTIONS_H

#include <stddef.h>

struct opt_problem;
struct opt_result;

/* Where the runs of a batch are computed when not on this process's
 * threads alone: run(pb, n, values, r, user) fills r[i] with the run at
 * point i (values: n rows of the space's size) exactly as opt_evaluate
 * would (evaluate.h), wherever it computes it.  The driver's MPI ranks
 * (drivers/taper/optimise_mpi.c) are one; run NULL: this process's
 * threads. */
typedef struct opt_runner {
    void (*run)(const struct opt_problem *pb, size_t n, const double *values,
                struct opt_result *r, void *user);
    void *user;
} opt_runner;

/* How an optimisation is run: threads, interruption, journal, progress. */
typedef struct opt_options {
    unsigned threads;                 /* runs at once; 0: one per core         */
    int (*stop)(void *user);          /* polled by every run: non-zero stops   */
    void *stop_user;
    const char *dir;                  /* the journal's directory (evaluations.tsv,
                                         resume); NULL: none                   */
    /* One line per iteration, without '\n'; NULL: quiet. */
    void (*progress)(const char *line, void *user);
    void *progress_user;
    opt_runner runner;                /* the batches' runs; {NULL}: threads    */
} opt_options;

/* How an optimisation ended. */
typedef enum opt_outcome {
    OPT_CONVERGED = 0,      /* an answer                                       */
    OPT_NOT_CONVERGED = 1,  /* iterations or runs exhausted, a setting the
                               data do not determine, or (a calibration) a
                               setting at its bound: reason says which         */
    OPT_INTERRUPTED = 2,    /* stopped by opt_options.stop: resume it          */
    OPT_FAILED = 3          /* a run failed where no other could stand in, a
                               journal could not be written: reason           */
} opt_outcome;

#endif
