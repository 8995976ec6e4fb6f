/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * optimise_mpi.h -- the runs of a calibration or a design on MPI ranks
 * (taper built with -Dmpi, run under mpirun).  Rank 0 runs the optimiser
 * and keeps the journal (evaluations.tsv, .evaluations.cache) alone, as
 * without MPI; each batch the optimiser asks for (the Jacobian's runs, a
 * design's grid, a simplex's or a line search's points) is spread over the
 * threads of every rank, rank 0's included.  The other ranks read the same
 * scene and data, build the same problem (optimise_remote_new) and compute
 * the points rank 0 sends them: a run is a pure function of its point, so
 * the results are those of a serial run to the last bit.
 *
 * Not part of libtaper: compiled into the taper executable only.
 */
#ifndef TAPER_OPTIMISE_MPI_H
#define TAPER_OPTIMISE_MPI_H

#include "optimise/options.h"
#include "scene/scene.h"

/* Rank 0 of several: where a calibration's or design's batches run
 * (optimise_scene's runner).  NULL on the other ranks, on one rank and
 * without MPI. */
const opt_runner *optimise_mpi_runner(void);

/* Rank 0, after a calibration or design scene (run or not): tells the
 * other ranks it is over, and says on stdout how many runs each rank
 * made.  Then mpi_scene_end collects their goodbyes. */
void optimise_mpi_scene_end(void);

/* A rank other than 0, on a calibration or design scene: computes the
 * points rank 0 sends, on &output threads threads (0: its share of the
 * node's cores), until rank 0 says the scene is over.  Then mpi_worker
 * says goodbye.  A signal to this rank stops its runs (they come back
 * interrupted, and rank 0 stops the optimisation). */
void optimise_mpi_serve(const scene *sc);

#endif
