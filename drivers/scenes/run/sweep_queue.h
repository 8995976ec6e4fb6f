/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_queue.h -- the runs of a sweep and who computes which: one item per
 * run (its name, directory, estimated cost and state), handed out the
 * dearest first to the threads of every rank, their outcomes recorded as
 * they come back.
 *
 * The items are read by the other parts of a sweep (resume, printing,
 * result files); their state changes only through these functions, under
 * the queue's lock.  An item that is DONE no longer changes: its outcome
 * may be read without the lock.  Every rank builds the same items in the
 * same order (sweep_open touches no file), so that a run is named by its
 * index between ranks.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SWEEP_QUEUE_H
#define TAPER_SWEEP_QUEUE_H

#include "run/run.h"
#include "scene/scene.h"

#include <pthread.h>
#include <stddef.h>

enum sweep_state { SWEEP_TODO = 0, SWEEP_RUNNING = 1, SWEEP_DONE = 2 };

typedef struct sweep_item {
    char *name;          /* q=0.05,exponent=2.5                        */
    char *dir;           /* DIR/name                                    */
    double cost;         /* estimate: the granules the pulse crosses    */
    int state;           /* enum sweep_state                            */
    int reused;          /* its result was on disk                      */
    int elsewhere;       /* another part's run (--part)                 */
    run_outcome outcome; /* rc, and the text it printed                 */
} sweep_item;

typedef struct sweep {
    const scene *sc;
    const scene_config *cfg;
    size_t n;
    sweep_item *items;
    size_t *order;       /* dearest first                               */
    size_t next;         /* into order                                  */
    pthread_mutex_t lock;
    pthread_cond_t cond; /* broadcast at each change of state           */
    size_t done, running, reused, failed, untrusted, computed;
    double cost_done, cost_todo;
} sweep;

/* A run whose rows are in sweep.tsv: complete, trusted or not. */
static inline int sweep_has_rows(int rc) { return rc == RUN_COMPLETE || rc == RUN_UNTRUSTED; }

/* The sweep's runs as every rank sees them (names, directories, order),
 * every one to do.  NULL: out of memory. */
sweep *sweep_open(const scene *sc);
void sweep_close(sweep *sw);
size_t sweep_size(const sweep *sw);

/* Before any run is handed out.  Part `part` of `parts` (--part): the
 * runs at positions part-1, part-1+parts, ... of the dearest-first order
 * are this part's, the others are done elsewhere. */
void sweep_deal(sweep *sw, size_t part, size_t parts);
/* Run i is done already, its result on disk (resume): rc RUN_COMPLETE or
 * RUN_UNTRUSTED, and the CPU time its computation took (its scene.hash;
 * NaN: not recorded). */
void sweep_reuse(sweep *sw, size_t i, int rc, double cpu_seconds);

/* The next run to compute (dearest first), or SIZE_MAX when none is left
 * or the sweep was interrupted.  Thread-safe. */
size_t sweep_next(sweep *sw);
/* Records the outcome of run i (takes its texts).  Thread-safe. */
void sweep_done(sweep *sw, size_t i, run_outcome *o);
/* 1 once nothing more will change: every run done, or none left to hand
 * out (or the sweep interrupted) and none running.  Otherwise waits for
 * the next change of state, or `seconds` at most (a signal cannot wake
 * it), and returns 0. */
int sweep_wait(sweep *sw, double seconds);

#endif
