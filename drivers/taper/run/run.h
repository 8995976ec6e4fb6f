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
 * partial > complete. */
enum run_status {
    RUN_COMPLETE = 0, /* every result written                                  */
    RUN_FAILED = 1,   /* library or output failure                             */
    RUN_INPUT = 2,    /* bad input: scene, command line, output directory      */
    RUN_PARTIAL = 3   /* a run ended early (solver failure, Ctrl-C, t_max,
                         max_steps): granules.partial.tsv, no granules.tsv     */
};

/* Ctrl-C ends the runs partial, keeping what was found; a second Ctrl-C
 * kills the process as usual. */
void run_install_sigint(void);

/* Runs every point of the scene into &output dir.  Returns a run_status. */
int run_scene(const scene *sc);

#endif
