/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * table.h -- the fits of a scene as files and as the paper's tables:
 * DIR/fits.tsv (every fit parameter of every run, theory and numerics),
 * DIR/table.tsv (param theory numerics numerics_stderr paper_theory
 * paper_numerics theory_fit theory_fit_stderr) and the table on stdout in
 * the paper's layout, next to the paper's printed values.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_TABLE_H
#define TAPER_TABLE_H

#include "results/analysis.h"

#include <stdio.h>

/* Write DIR/fits.tsv and DIR/table.tsv.  0, or -1 with *msg (malloc'd). */
int table_write_fits(const report *r, char **msg);
int table_write(const report *r, char **msg);

/* The table as text, the paper's columns next to ours. */
void table_print(const report *r, FILE *fp);

#endif
