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

#include "scene/scene.h"

/* Exit status of the driver, in order of gravity: input error > failure >
 * partial > untrusted > complete (docs/scene.md, "Exit status"). */
enum run_status {
    RUN_COMPLETE = 0, /* every result written                                  */
    RUN_FAILED = 1,   /* library or output failure                             */
    RUN_INPUT = 2,    /* bad input: scene, command line, output directory      */
    RUN_PARTIAL = 3,  /* a run ended early (solver failure, a signal, t_max,
                         max_steps): granules.partial.tsv, no granules.tsv     */
    RUN_UNTRUSTED = 4 /* complete, but energy or momentum conservation worse
                         than &output max_energy_error / max_momentum_error:
                         granules.tsv says "# UNTRUSTED: ..."                  */
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

/* Runs every point of the scene into &output dir.  Returns a run_status. */
int run_scene(const scene *sc);

#endif
