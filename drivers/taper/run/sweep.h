/*
 * sweep.h -- the runs of a sweep (a scene whose variables take lists):
 * one directory per run, DIR/NAME=VALUE[,NAME=VALUE...] (scene_point_name),
 * computed on threads and, under MPI, on other ranks (run/mpi.c), the
 * dearest first; DIR/sweep.tsv (one column per swept variable, then the
 * columns of granules.tsv), DIR/runs.tsv (each run's status), fits, table
 * and figure from the runs' files.
 *
 *  - Faults: a run that fails (solver failure, a value the library refuses,
 *    t_max ...) does not end the sweep; sweep.tsv and runs.tsv name it, and
 *    the exit status is RUN_SOME_FAILED.
 *  - Resume: each complete run leaves DIR/RUN/scene.hash, a hash of the
 *    resolved scene at its point (the text its granules.tsv echoes, the
 *    scene's path and taper's version).  Running the same sweep again
 *    reuses every run whose granules.tsv and hash are on disk and match;
 *    partial runs are redone.  Directories of runs of another sweep, and
 *    the sweep-level files of an earlier sweep, are removed first.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SWEEP_H
#define TAPER_SWEEP_H

#include "scene/scene.h"

#include <stddef.h>

typedef struct sweep sweep;

/* Runs the sweep of a validated scene (runs.swept) into &output dir.
 * Returns a run_status. */
int sweep_run(const scene *sc);

/* Only part `part` of `parts` (1 <= part <= parts) of the sweep's runs:
 * the runs in the order of their estimated cost, dealt out in turn, so
 * that every part gets a share of the dear ones (taper --part I/N; a job
 * array without MPI, docs/cluster.md).  A part writes its runs'
 * directories, not sweep.tsv; the same command without --part then
 * reuses every run the parts completed and writes sweep.tsv, fits, table
 * and figure (the merge).  Call before sweep_run. */
void sweep_set_part(size_t part, size_t parts);

/* ---- for run/mpi.c ------------------------------------------------------ */

/* Other ranks that compute runs (MPI).  Rank 0 calls serve() between waits
 * (answer requests with sweep_next, deliver results with sweep_done; never
 * blocks), finish() once the sweep hands out nothing more (releases every
 * worker; blocks until they have all said goodbye). */
typedef struct sweep_remote {
    void (*serve)(sweep *sw, void *ctx);
    void (*finish)(sweep *sw, void *ctx);
    unsigned ranks;        /* processes in all, this one included         */
    unsigned threads;      /* threads of a rank for &output threads = 0    */
    void *ctx;
} sweep_remote;

/* Installed by the driver before sweep_run (NULL: none). */
void sweep_set_remote(const sweep_remote *remote);

/* The sweep's runs as every rank sees them (names, directories, order):
 * sweep_open builds them without touching the disk. */
sweep *sweep_open(const scene *sc);
void sweep_close(sweep *sw);
size_t sweep_size(const sweep *sw);
/* The next run to compute (dearest first), or SIZE_MAX when none is left
 * or the sweep was interrupted.  Thread-safe. */
size_t sweep_next(sweep *sw);
/* Computes run i and writes its files (granules.tsv, scene.hash).  On any
 * rank; thread-safe.  Free o with run_outcome_free. */
struct run_outcome;
void sweep_compute(sweep *sw, size_t i, struct run_outcome *o);
/* Records the outcome of run i (takes its texts).  Thread-safe. */
void sweep_done(sweep *sw, size_t i, struct run_outcome *o);

#endif
