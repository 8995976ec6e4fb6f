/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_mpi.h -- the runs of a sweep on MPI ranks (taper built with -Dmpi, run
 * under mpirun).  Rank 0 reads the scene, echoes it, prepares the output
 * directory and hands out runs, the dearest first, as ranks ask for work;
 * every rank, rank 0 included, computes runs on its threads and writes
 * their directories; rank 0 prints their messages in sweep order and
 * writes sweep.tsv, runs.tsv, fits, table and figure, byte-identical to a
 * serial sweep.  The other ranks print nothing.  Without mpirun (no MPI
 * launcher in the environment) MPI is not initialised at all: the driver
 * is the serial one.  The library never sees MPI.
 *
 * Not part of libtaper: compiled into the taper executable only.
 */
#ifndef TAPER_SWEEP_MPI_H
#define TAPER_SWEEP_MPI_H

#include "scene/scene.h"

/* Initialises MPI when launched by mpirun/srun; returns this rank (0
 * otherwise).  Ranks other than 0 print nothing from here on. */
int mpi_start(int *argc, char ***argv);
/* This rank (0 without MPI). */
int mpi_rank(void);
/* Rank 0 of several: how a sweep serves the other ranks (sweep_run's
 * options).  NULL on the other ranks and without MPI. */
struct sweep_remote;
const struct sweep_remote *mpi_remote(void);
/* The work of a rank other than 0 on one scene: computes the runs rank 0
 * hands out, until it says stop or a signal stops this rank, then says
 * goodbye.  sc NULL (the scene did not load) or a scene that is not a
 * sweep: nothing to do but that.  Returns RUN_PARTIAL after a signal,
 * RUN_COMPLETE otherwise (rank 0 speaks for the runs). */
int mpi_worker(const scene *sc);
/* Rank 0, after each scene of the command line: waits for every worker to
 * be done with it (a scene that was no sweep, or did not load, included). */
void mpi_scene_end(void);
/* In place of a scene not run after an interruption: every rank walks
 * the scenes of the command line in step (rank 0 collects the goodbyes,
 * the others say it). */
void mpi_scene_skip(void);
/* What a calibration's or design's runs on the ranks (optimise_mpi.c)
 * share with a sweep's: the job, the threads a rank computes on when the
 * scene says &output threads = 0, and the bells (bell.h), set up once for
 * the whole command line.  On rank 0, bell[r] is rank r's bell, rung[r]
 * its rings heard and got[r] its messages received, which every protocol
 * keeps counting (a ring, then one message); on the others, bell[0] is
 * rank 0's.  A rank's own slot, bell[rank], is -1: free for a wake-up of
 * its own threads while it waits.  NULL without MPI or on a single rank. */
typedef struct mpi_link {
    int rank, size;
    unsigned threads_per_rank;
    int *bell;
    unsigned long *rung, *got;
} mpi_link;
mpi_link *mpi_link_get(void);
/* Finalises MPI.  Returns rc. */
int mpi_stop(int rc);

#endif
