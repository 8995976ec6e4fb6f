/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * optimise.h -- a scene that asks for a calibration (&calibrate data) or a
 * design (&design objective), run as the driver runs scenes: progress on
 * stdout, problems on stderr as FILE:LINE: &group key: message, result
 * files in &output dir, the scene at the optimum written and run, and an
 * exit status of run.h:
 *
 *   RUN_COMPLETE       converged (a design's optimum may lie on a bound:
 *                      design.tsv says so)
 *   RUN_NOT_CONVERGED  no answer to trust: iterations or runs exhausted, a
 *                      fitted setting the data do not determine or at its
 *                      bound; the files say why
 *   RUN_PARTIAL        interrupted (SIGINT, SIGTERM, ...): the runs made
 *                      are in DIR/evaluations.tsv, and the same command
 *                      resumes
 *   RUN_INPUT          a problem of the scene's &calibrate or &design keys,
 *                      or of the data (FILE:LINE:COLUMN)
 *   RUN_FAILED         a run failed where nothing could stand in for it
 *                      (the start), or a file could not be written
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPTIMISE_H
#define TAPER_OPTIMISE_H

#include "optimise/evaluate.h"
#include "optimise/options.h"
#include "scene/scene.h"

/* 1: the scene is a calibration or a design (optimise_scene runs it). */
int optimise_wanted(const scene *sc);

/* Runs the calibration or design of a validated scene.  runner: where
 * the batches' runs are computed (options.h; the driver's MPI ranks), NULL
 * for this process's threads (&output threads).  Returns a run_status. */
int optimise_scene(const scene *sc, const opt_runner *runner);

/* The runs of a scene's calibration or design as another process computes
 * them for the one that optimises (an MPI rank other than 0,
 * drivers/taper/optimise_mpi.c): the problem optimise_scene builds, from
 * the same scene and data, without journal, progress or files.  A run is a
 * pure function of its point, so both give the same to the last bit.  NULL
 * if the scene's &calibrate or &design is not valid (optimise_scene says
 * why, where it runs). */
typedef struct optimise_remote optimise_remote;
optimise_remote *optimise_remote_new(const scene *sc);
/* The free settings: values per point. */
size_t optimise_remote_size(const optimise_remote *w);
/* The run at values (opt_evaluate; a signal to this process stops it,
 * OPT_RUN_INTERRUPTED).  Thread-safe. */
void optimise_remote_evaluate(const optimise_remote *w, const double *values, opt_result *r);
void optimise_remote_free(optimise_remote *w);

#endif
