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
                         max_steps): granules.partial.tsv, no granules.tsv     */
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

/* SIGINT, SIGTERM, SIGHUP and SIGXCPU end the runs partial, keeping what
 * was found; a second one while results are written removes the temporary
 * file and kills the process by that signal.  SIGHUP ignored by the parent
 * (nohup) stays ignored. */
void run_install_signals(void);
/* The number of the first such signal received, 0 if none. */
int run_interrupted(void);
/* Stops the runs as that signal does: signal sig received by MPI rank
 * `rank` (drivers/taper/sweep_mpi.c), which stops the whole sweep. */
void run_interrupt(int sig, int rank);
/* Process pid (named `name`) launched this one and stops it on the user's
 * behalf: mpirun sends SIGTERM to every rank when it gets Ctrl-C, SIGINT,
 * SIGTERM or SIGHUP itself.  Messages then say "interrupted by SIGTERM
 * from mpirun", not the signal the user sent, which only mpirun saw. */
void run_signal_source(long pid, const char *name);

/* Runs a scene without a sweep (runs.swept 0) into &output dir; a sweep is
 * run by sweep_run (run/sweep.c), which calls run_point for each of its
 * runs (run/sweep_resume.c).  Returns a run_status. */
int run_scene(const scene *sc);

/* &output dir created and locked for this process (flock on
 * DIR/.taper.lock, held until exit): exclusive (shared != 0: shared, the
 * parts of a sweep computed at once, --part) so that a second run into the
 * same directory is refused while the first runs.  0, or -1 after printing
 * why. */
int run_lock_dir(const scene *sc, const char *dir, int shared);

/* What one run of a sweep printed: stdout and stderr text (malloc'd, may be
 * NULL), and its run_status. */
typedef struct run_outcome {
    int rc;
    char *out;
    char *log;
} run_outcome;

/* Computes run `point` of the scene into dir (granules.tsv, or
 * granules.partial.tsv; report.tsv when the scene's fits, table or figure
 * need rows or columns its granules.tsv leaves out): chain, sim, result
 * files.  Prints nothing; its messages name the run (`name`, e.g.
 * "q=0.05,exponent=2.5").  Thread-safe.  Free with run_outcome_free. */
void run_point(const scene *sc, size_t point, const char *dir, const char *name,
               run_outcome *o);
void run_outcome_free(run_outcome *o);

/* Fits, table and figure of a scene from its runs' data: points[i] for run
 * i (runs.n of them), spec and src filled.  Returns a run_status. */
int run_write_reports(const scene *sc, report_point *points);

#endif
