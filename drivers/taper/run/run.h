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
 * partial > complete. */
enum run_status {
    RUN_COMPLETE = 0, /* every result written                                  */
    RUN_FAILED = 1,   /* library or output failure                             */
    RUN_INPUT = 2,    /* bad input: scene, command line, output directory      */
    RUN_PARTIAL = 3,  /* a run ended early (solver failure, Ctrl-C, t_max,
                         max_steps): granules.partial.tsv, no granules.tsv     */
    RUN_SOME_FAILED = 4 /* a sweep ran every run, but some failed (solver
                         failure, a value the library refused, t_max, ...):
                         sweep.tsv and runs.tsv name them (run/sweep.c)        */
};

/* Order of gravity: input error > failure > partial > some failed >
 * complete.  The graver of a and b. */
int run_worst(int a, int b);

/* Ctrl-C ends the runs partial, keeping what was found; a second Ctrl-C
 * kills the process as usual. */
void run_install_sigint(void);

/* Runs every point of the scene into &output dir.  Returns a run_status.
 * A sweep (runs.n > 1) is run by run/sweep.c. */
int run_scene(const scene *sc);

/* 1 once Ctrl-C (or another stop signal) asked the runs to stop. */
int run_interrupted(void);

/* What one run of a sweep printed: stdout and stderr text (malloc'd, may be
 * NULL), and its run_status. */
typedef struct run_outcome {
    int rc;
    char *out;
    char *log;
} run_outcome;

/* Computes run `point` of the scene into dir (granules.tsv, or
 * granules.partial.tsv): chain, sim, result file.  Prints nothing; its
 * messages name the run (`name`, e.g. "q=0.05,exponent=2.5").  Thread-safe.
 * Free the outcome with run_outcome_free. */
void run_point(const scene *sc, size_t point, const char *dir, const char *name,
               run_outcome *o);
void run_outcome_free(run_outcome *o);

/* Fits, table and figure of a scene from its runs' data: points[i] for run
 * i (runs.n of them), spec and src filled.  Returns a run_status. */
int run_write_reports(const scene *sc, report_point *points);

#endif
