/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * evaluate.h -- one run of the scene at a point of the free settings'
 * space, and what an optimiser reads of it: the simulated value at every
 * measured point (a calibration) or one scalar result (a design).
 *
 * A calibration's signals are read at the measured times themselves by
 * the library's sampler (taper_solver_spec_set_sample_times): CVODE's
 * interpolant there, to the integration's own accuracy, with the run's
 * steps unchanged; never a coarser grid interpolated.  Times and values
 * are converted between the table's units (SI or rescaled) and the
 * library's rescaled ones at every run, since a free setting such as
 * Young's modulus changes the units.  The run lasts until the last
 * measured time (t_end) unless the scene asks for longer.
 *
 * A run counts only when it completes and its energy and momentum errors
 * are within &output max_energy_error and max_momentum_error: a point the
 * library refuses, a run that fails, an observable it does not find (nan)
 * and an untrusted run are failures with a message, which the optimisers
 * treat as outside the domain.
 *
 * Batches of points run on threads (the library has no global state: each
 * run is bit-identical to a serial one), and every point computed is
 * remembered in a journal (optimise/journal.h): a point asked for again,
 * in this process or after a restart, is not run again.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_EVALUATE_H
#define TAPER_OPT_EVALUATE_H

#include "optimise/journal.h"
#include "optimise/measurements.h"
#include "optimise/options.h"
#include "optimise/space.h"

#include <stddef.h>

/* A design's objective: a statistic of the run by name, or a granule's
 * observable as NAME(k). */
typedef struct opt_objective {
    char *name;             /* as the scene writes it                         */
    int statistic;          /* a taper_statistic, or -1                        */
    int observable;         /* a taper_observable, or -1                       */
    size_t granule;         /* the observable's granule (1-based)              */
    taper_dimension dim;
} opt_objective;

/* Parses &design objective for a chain of n_granules.  0, or -1 with *msg
 * (malloc'd). */
int opt_objective_parse(const char *text, size_t n_granules, opt_objective *o, char **msg);
void opt_objective_free(opt_objective *o);

/* When a calibration samples its run: the distinct measured times in
 * increasing order (the table's units), and each point's sample. */
typedef struct opt_plan {
    const measurements *data;
    double *times;
    size_t n_times;
    size_t *sample_of;      /* per point; unused for a granules table          */
    size_t *first;          /* the points of sample j: order[first[j] .. first[j+1]) */
    size_t *order;
} opt_plan;

/* The plan of a table.  0, or -1 out of memory. */
int opt_plan_init(opt_plan *plan, const measurements *data);
void opt_plan_free(opt_plan *plan);

typedef enum opt_status {
    OPT_RUN_OK = 0,
    OPT_RUN_FAILED = 1,       /* refused, failed, untrusted, a nan observable */
    OPT_RUN_INTERRUPTED = 2   /* stopped by the problem's stop function       */
} opt_status;

typedef struct opt_problem {
    const opt_space *space;
    const opt_plan *plan;           /* a calibration's, or NULL               */
    const opt_objective *objective; /* a design's, or NULL                    */
    unsigned threads;               /* runs of a batch at once; 0: per core   */
    opt_runner runner;              /* where a batch runs; {NULL}: threads    */
    /* Polled during every run (its monitor and sampler): non-zero stops the
     * runs, which end OPT_RUN_INTERRUPTED.  NULL: never. */
    int (*stop)(void *user);
    void *stop_user;
    opt_journal *journal;           /* remembers every point computed         */
    /* The number a journal records for a result (chi-square, the
     * objective), by the optimiser that asks. */
    double (*summary)(const opt_result *r, void *user);
    void *summary_user;
    size_t computed;                /* runs made by this process              */
    size_t reused;                  /* points found in the journal            */
    char *journal_message;          /* the first failure to write the journal
                                       (malloc'd), or NULL                    */
} opt_problem;

/* The run at values (one per free setting) into *r (allocated; free with
 * opt_result_free): thread-safe, prints nothing. */
void opt_evaluate(const opt_problem *pb, const double *values, opt_result *r);

/* The runs at n points (values: n rows of space->n), those the journal
 * does not have computed (on threads, or by pb->runner) and recorded in
 * the order of the points, wherever they ran.  r[i] is point i's.
 * Returns 1 if a run was interrupted (its r is OPT_RUN_INTERRUPTED), else
 * 0. */
int opt_evaluate_batch(opt_problem *pb, size_t n, const double *values, opt_result *r);

#endif
