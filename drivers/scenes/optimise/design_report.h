/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * design_report.h -- a design's result files:
 *
 *   DIR/design.tsv   one row per free setting: its value at the optimum,
 *                    unit, start, bounds, whether the optimum is on a
 *                    bound; '#' lines: the objective there, the outcome,
 *                    method, runs
 *   DIR/scan.tsv     with integer settings: the optimum of each
 *                    combination scanned
 *   DIR/profile.tsv  the objective along each setting through the optimum
 *                    (one gnuplot data block per setting)
 *   DIR/design.gp    those profiles, a panel per setting, the optimum
 *                    marked -> DIR/design.png
 *
 * (DIR/evaluations.tsv, every run, is the journal's: optimise/journal.h.)
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_DESIGN_REPORT_H
#define TAPER_OPT_DESIGN_REPORT_H

#include "optimise/design.h"

#include <stdio.h>

/* Writes the files into dir, renders the figure when gnuplot is there,
 * and says what it wrote on out.  0, or -1 with *msg (malloc'd). */
int design_report(const design_problem *d, const char *dir, FILE *out, char **msg);

/* The optimum as lines for a terminal. */
void design_print(const design_problem *d, FILE *out);

#endif
