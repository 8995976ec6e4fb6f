/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * outdir.h -- earlier results in an output directory.
 */
#ifndef TAPER_RUN_OUTDIR_H
#define TAPER_RUN_OUTDIR_H

#include "scene/scene.h"

/* Removes what an earlier sweep (or single run) left in the scene's output
 * directory: the sweep-level files (sweep.tsv, runs.tsv, fits, table,
 * figure), and run directories (NAME=VALUE,...) for which in_this_sweep
 * (called with data) is 0.  in_this_sweep NULL: a single run, which keeps
 * its granules files; otherwise those of a single run go too.  Run
 * directories holding other files than a run's are kept, with a warning.
 * RUN_COMPLETE, or RUN_FAILED with a message on stderr. */
int outdir_clean(const scene *sc, int (*in_this_sweep)(const char *name, const void *data),
                 const void *data);

/* Removes the temporaries a killed run left in its directory
 * (.granules.tsv.XXXXXX and the like). */
void outdir_remove_temporaries(const char *dir);

#endif
