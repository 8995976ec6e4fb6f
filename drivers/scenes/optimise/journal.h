/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * journal.h -- every run a calibration or a design makes, remembered: in
 * memory, so that a point asked for again is not run again, and in DIR
 * (when given), so that an interrupted optimisation resumes.
 *
 *   DIR/evaluations.tsv       one row per run, in the order made: its
 *                             number, status, the free settings' values and
 *                             the optimiser's number for it (chi-square, the
 *                             objective); a failed run's message on a '#'
 *                             line after its row.  Written as runs end.
 *   DIR/.evaluations.cache    the same runs to the last bit (hex floats),
 *                             a calibration's simulated values too, under a
 *                             key of the scene, the data and taper's version
 *
 * The optimisers are deterministic, so the same command after an
 * interruption asks for the same points in the same order: each found in
 * the cache is taken from it, and the optimisation goes on from where it
 * stopped, to the same result.  A cache of another key (the scene or the
 * data changed) is started afresh.  A line cut short by a kill is ignored.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_JOURNAL_H
#define TAPER_OPT_JOURNAL_H

#include "optimise/space.h"

#include <stddef.h>
#include <stdint.h>

/* What one run gave. */
typedef struct opt_result {
    int status;             /* opt_status (evaluate.h)                        */
    char *message;          /* why it failed (malloc'd), or NULL              */
    double objective;       /* a design's objective                           */
    double *model;          /* a calibration's simulated values (malloc'd)    */
    size_t n_model;
    int reused;             /* 1: from the journal, not run here              */
} opt_result;

void opt_result_free(opt_result *r);
/* A deep copy of src into *dst.  0, or -1 out of memory. */
int opt_result_copy(opt_result *dst, const opt_result *src);

typedef struct opt_journal opt_journal;

/* A journal of the runs of space.  dir NULL: in memory only.  key: what
 * the runs depend on (opt_journal_key).  summary_name: the header of the
 * optimiser's column ("chi2", "wall_peak_force_right[N]").  n_model: the
 * simulated values per run (0 for a design).  *resumed: the runs taken
 * from an earlier, interrupted attempt.  NULL with *msg on failure. */
opt_journal *opt_journal_open(const char *dir, const char *key, const opt_space *space,
                              const char *summary_name, size_t n_model, size_t *resumed,
                              char **msg);
void opt_journal_close(opt_journal *j);

/* The run at values, if there was one (NULL otherwise). */
const opt_result *opt_journal_find(const opt_journal *j, const double *values);
/* Records a run made at values, its summary for evaluations.tsv.  0, or
 * -1 with *msg (a write failed; the run is still remembered in memory). */
int opt_journal_add(opt_journal *j, const double *values, const opt_result *r, double summary,
                    char **msg);
/* Runs recorded, earlier attempts' included. */
size_t opt_journal_count(const opt_journal *j);
/* Run i (0 <= i < count, in the order recorded): its point, and what it
 * gave. */
const double *opt_journal_point(const opt_journal *j, size_t i);
const opt_result *opt_journal_result(const opt_journal *j, size_t i);

/* A key of what the runs depend on: the scene's echo, the bytes of the
 * file at data_path (NULL: none) and taper's version, as hex.  malloc'd. */
char *opt_journal_key(const char *scene_text, const char *data_path);

#endif
