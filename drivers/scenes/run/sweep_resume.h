/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_resume.h -- a sweep's results on disk, and resuming from them.
 *
 * Each complete run leaves DIR/RUN/scene.hash: a hash of the resolved scene
 * at its point (the text its granules.tsv echoes, the scene's path and
 * taper's version), and the row count and CRC-32 of each result file it
 * wrote (their footers, results/footer.h), then the CPU time the run took
 * (a measurement, not vouched for: runs.tsv's cpu_time[s]).  Running the
 * same sweep again
 * reuses every run whose hash matches and whose files pass their footers
 * and are the ones the hash names; a run whose files were cut, changed or
 * replaced after it ran is computed again (said on stdout), partial runs
 * are redone.  Directories of runs of another sweep, and the sweep-level
 * files of an earlier sweep, are removed first.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SWEEP_RESUME_H
#define TAPER_SWEEP_RESUME_H

#include "run/sweep_queue.h"

/* Removes what an earlier sweep left in &output dir that is not a run of
 * this one (run/outdir.c).  Returns a run_status. */
int sweep_remove_others(sweep *sw);

/* Marks reused (sweep_reuse) each run still to do whose complete result is
 * on disk, made from this scene; removes the temporaries a killed run left
 * in the directories of the runs still to do, and returns how many. */
size_t sweep_find_reusable(sweep *sw);

/* Computes run i and writes its files (granules.tsv, scene.hash).  On any
 * rank; thread-safe.  Free o with run_outcome_free. */
void sweep_compute(sweep *sw, size_t i, run_outcome *o);

#endif
