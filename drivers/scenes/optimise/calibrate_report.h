/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * calibrate_report.h -- a calibration's result files:
 *
 *   DIR/calibration.tsv  one row per fitted setting: its value, standard
 *                        error, unit, start and bounds, whether it ended at
 *                        a bound, and its row of the correlation matrix;
 *                        '#' lines: how the fit ended, chi2, dof,
 *                        chi2/dof, how the errors were scaled, iterations,
 *                        runs
 *   DIR/residuals.tsv    one row per measurement: its line in the data,
 *                        time, granule, quantity, measured and fitted
 *                        values, the residual; one gnuplot data block per
 *                        signal (quantity and granule)
 *   DIR/calibration.gp   measured (points) and fitted (lines) signals, a
 *                        panel per quantity -> DIR/calibration.png
 *
 * Every file is written whole or not at all (results/output.h).
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_CALIBRATE_REPORT_H
#define TAPER_OPT_CALIBRATE_REPORT_H

#include "optimise/calibrate.h"

#include <stdio.h>

/* Writes the three files into dir and renders the figure when gnuplot is
 * there, saying what it wrote on out ("! wrote ...").  0, or -1 with *msg
 * (malloc'd). */
int calibration_report(const calibration *c, const char *dir, FILE *out, char **msg);

/* The fitted values, errors and chi2/dof as lines for a terminal. */
void calibration_print(const calibration *c, FILE *out);

#endif
