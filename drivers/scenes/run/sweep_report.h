/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_report.h -- the files a sweep writes from its runs' files once
 * every run is done: DIR/sweep.tsv (one column per swept variable, then
 * the columns of granules.tsv, the rows of every run with rows), DIR/runs.tsv
 * (each run's status) and the fits, table and figure.  They are built from
 * the runs' granules.tsv, which hold every number to the last bit (%.17g),
 * so that they do not depend on where a run was computed, or when.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SWEEP_REPORT_H
#define TAPER_SWEEP_REPORT_H

#include "run/sweep_queue.h"

/* sweep.tsv, runs.tsv, then fits, table and figure if the scene asks for
 * them; prints "! wrote ..." for each.  Returns a run_status (RUN_FAILED
 * after printing why). */
int sweep_write_results(sweep *sw);

#endif
