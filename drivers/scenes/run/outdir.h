/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * outdir.h -- an output directory: its lock, and the results earlier runs
 * left in it.
 */
#ifndef TAPER_RUN_OUTDIR_H
#define TAPER_RUN_OUTDIR_H

#include "scene/scene.h"

/* &output dir created and locked for this process (flock on
 * DIR/.taper.lock, held until exit, released by the kernel however the
 * process ends): exclusive (shared != 0: shared, the parts of a sweep
 * computed at once, --part), so that a second taper process writing into
 * the same directory is refused while the first runs, instead of both
 * writing and the last one winning.  A directory this process holds
 * already (a second scene of the same command) is its own: 0.  0, or -1
 * after printing why. */
int outdir_lock(const scene *sc, const char *dir, int shared);

/* Removes what an earlier sweep (or single run) left in the scene's output
 * directory: the sweep-level files (sweep.tsv, runs.tsv, fits, table,
 * figure), and run directories (NAME=VALUE,...) for which in_this_sweep
 * (called with data) is 0.  in_this_sweep NULL: a single run, which keeps
 * its granules files; otherwise those of a single run go too.  Run
 * directories holding other files than a run's are kept, with a warning.
 * RUN_COMPLETE, or RUN_FAILED with a message on stderr. */
int outdir_clean(const scene *sc, int (*in_this_sweep)(const char *name, const void *data),
                 const void *data);

/* Removes the temporaries a killed run (SIGKILL, a power loss) left in a
 * directory it wrote: .NAME.XXXXXX of the names taper writes there
 * (granules.tsv, sensors.tsv, sweep.tsv, ...), nothing else.  The caller
 * holds the directory's lock.  Returns how many were removed. */
size_t outdir_remove_temporaries(const char *dir);

#endif
