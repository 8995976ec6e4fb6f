/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * run.h -- the runs of a validated scene: for each value of its sweep (or
 * once) a chain and, unless &solver numerics = .false., a sim whose
 * binary-collision theory the library computed with it (without numerics:
 * taper_theory_compute), computed in parallel; then the result files,
 * fits, table and figure (results/).
 *
 * Not part of libtaper.
 */
#ifndef TAPER_RUN_H
#define TAPER_RUN_H

#include "results/analysis.h"
#include "scene/scene.h"

/* Exit status of the driver, in order of gravity: input error > failure >
 * partial > not converged > some runs failed > untrusted > complete
 * (docs/scene.md, "Exit status"). */
enum run_status {
    RUN_COMPLETE = 0, /* every result written                                  */
    RUN_FAILED = 1,   /* library or output failure                             */
    RUN_INPUT = 2,    /* bad input: scene, command line, output directory      */
    RUN_PARTIAL = 3,  /* a run ended early (solver failure, a signal, t_max,
                         max_steps): granules.partial.tsv, no granules.tsv; or
                         a signal before it started (nothing written) or while
                         its results were written (the file being written and
                         those after it are not; the message says which)    */
    RUN_UNTRUSTED = 4, /* complete, but energy or momentum conservation worse
                         than &output max_energy_error / max_momentum_error:
                         granules.tsv says "# UNTRUSTED: ..."                  */
    RUN_SOME_FAILED = 5, /* a sweep ran every run, but some failed (solver
                         failure, a value the library refused, t_max, ...):
                         sweep.tsv and runs.tsv name them (run/sweep.c)        */
    RUN_NOT_CONVERGED = 6 /* a calibration or design ended without an answer
                         to trust: not converged, a setting the data do not
                         determine, a fitted setting at its bound
                         (optimise/optimise.h)                               */
};

/* The graver of two run_status values. */
int run_worst(int a, int b);

/* Runs a scene without a sweep (runs.swept 0) into &output dir; a sweep is
 * run by sweep_run (run/sweep.c), which calls run_point for each of its
 * runs (run/sweep_resume.c).  Returns a run_status. */
int run_scene(const scene *sc);

/* What one run of a sweep printed: stdout and stderr text (malloc'd, may be
 * NULL), its run_status, and the CPU time it took (NaN: not known). */
typedef struct run_outcome {
    int rc;
    char *out;
    char *log;
    double cpu_seconds; /* on its thread, from its chain to its last file  */
} run_outcome;

/* Computes run `point` of the scene into dir (granules.tsv, or
 * granules.partial.tsv; report.tsv when the scene's fits, table or figure
 * need rows or columns its granules.tsv leaves out): chain, sim, result
 * files; o->cpu_seconds the CPU time of the calling thread meanwhile (a
 * run is computed on one thread).  Prints nothing; its messages name the run (`name`, e.g.
 * "q=0.05,exponent=2.5").  Thread-safe.  Free with run_outcome_free. */
void run_point(const scene *sc, size_t point, const char *dir, const char *name,
               run_outcome *o);
void run_outcome_free(run_outcome *o);

/* What a stop signal that came while a file was written leaves, from the
 * writer's message (out_stopped_message, "DIR/NAME not written:
 * interrupted by a signal"): "interrupted by SIGTERM while writing
 * DIR/NAME: it is not written, nor anything after it; ..." (malloc'd). */
char *run_stopped_writing(const char *msg);

/* Fits, table and figure of a scene from its runs' data: points[i] for run
 * i (runs.n of them), spec and src filled.  Returns a run_status. */
int run_write_reports(const scene *sc, report_point *points);

#endif
