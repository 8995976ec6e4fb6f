/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * granules.h -- the result files of a run: DIR/granules.tsv (or
 * granules.partial.tsv for a run that ended early) with the resolved scene
 * and the run's statistics as '#' lines.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_GRANULES_H
#define TAPER_GRANULES_H

#include "scene/scene.h"
#include "taper.h"

#include <stddef.h>

/* What one run produced. */
typedef struct granules_run {
    const scene *sc;            /* echoed at its sweep point               */
    size_t point;
    const taper_chain *chain;
    const taper_sim *sim;       /* NULL without numerics                   */
    const double *theory[TAPER_N_THEORY_QUANTITIES]; /* by TAPER_THEORY_*  */
    taper_status status;        /* of taper_sim_run (TAPER_OK without)     */
    const char *message;        /* its message, for a partial result       */
    const char *untrusted;      /* why it is not to be trusted, or NULL    */
    const char *theory_note;    /* taper_chain_theory_note: why the theory
                                   columns are NaN, or NULL                */
    scene_config at;            /* the scene at `point` (scene_config_at):
                                   its units                               */
} granules_run;

/* Writes DIR/granules.tsv (partial: DIR/granules.partial.tsv), removing
 * the other one (a stale result must not pass for this one).  Prints
 * nothing (the runs of a sweep: run/sweep_print.c prints in the order of
 * the sweep).  0, or -1 with *msg (malloc'd). */
int granules_save(const char *dir, const granules_run *run, int partial, char **msg);

#endif
