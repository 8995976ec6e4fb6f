/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep.h -- the runs of a sweep (a scene whose variables take lists):
 * one directory per run, DIR/NAME=VALUE[,NAME=VALUE...] (scene_point_name),
 * computed on threads and, under MPI, on other ranks (drivers/taper/sweep_mpi.c), the
 * dearest first (run/sweep_queue.h); DIR/sweep.tsv, DIR/runs.tsv, fits,
 * table and figure from the runs' files (run/sweep_report.h).
 *
 *  - Faults: a run that fails (solver failure, a value the library refuses,
 *    t_max ...) does not end the sweep; sweep.tsv and runs.tsv name it, and
 *    the exit status is RUN_SOME_FAILED.
 *  - Resume: running the same sweep again reuses every run whose complete
 *    result is on disk, made from the same scene (run/sweep_resume.h).
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SWEEP_H
#define TAPER_SWEEP_H

#include "run/sweep_queue.h"
#include "scene/scene.h"

#include <stddef.h>

/* Other ranks that compute runs (MPI, run/mpi.c).  sweep_run calls
 * serve() once per sweep, on a thread of its own while this rank's
 * threads compute: it hands runs out as the other ranks ask
 * (sweep_next), records their outcomes (sweep_done), answers "none left"
 * once sweep_next has no more, and returns when every other rank has said
 * it is done with the scene.  sw NULL: the sweep did not start (nothing
 * to hand out); called on this thread then. */
typedef struct sweep_remote {
    void (*serve)(sweep *sw, void *ctx);
    unsigned ranks;        /* processes in all, this one included         */
    unsigned threads;      /* threads of a rank for &output threads = 0    */
    int main_thread;       /* serve() must run on the thread that started
                              MPI (MPI_THREAD_FUNNELED): the runs' messages
                              are printed once it returns                   */
    void *ctx;
} sweep_remote;

typedef struct sweep_options {
    /* Only part `part` of `parts` (1 <= part <= parts) of the sweep's runs;
     * parts 0: all of them.  The runs in the order of their estimated
     * cost, dealt out in turn, so that every part gets a share of the dear
     * ones (taper --part I/N; a job array without MPI, docs/cluster.md).  A
     * part writes its runs' directories, not sweep.tsv; the same command
     * without --part then reuses every run the parts completed and writes
     * sweep.tsv, fits, table and figure (the merge). */
    size_t part, parts;
    const sweep_remote *remote; /* NULL: no other ranks                   */
} sweep_options;

/* Runs the sweep of a validated scene (runs.swept) into &output dir.
 * Returns a run_status. */
int sweep_run(const scene *sc, const sweep_options *options);

#endif
