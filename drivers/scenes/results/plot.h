/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * plot.h -- a scene's figure: DIR/figure.tsv (per-granule data, one gnuplot
 * data block per run), DIR/inset.tsv (the fitted value against the swept
 * variable), DIR/figure.gp (a gnuplot script in the paper's style: theory
 * open circles, numerics filled circles, the inset drawn inside the main
 * panel where it covers no point, as near a corner as can be, as the paper
 * draws its insets) and, with gnuplot installed, DIR/figure.png.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_PLOT_H
#define TAPER_PLOT_H

#include "results/analysis.h"

#include <stddef.h>
#include <stdio.h>

/* Writes figure.tsv, inset.tsv (with an inset) and figure.gp.  0, or -1
 * with *msg (malloc'd). */
int plot_write(const report *r, char **msg);

/* Runs gnuplot on DIR/figure.gp in DIR ($TAPER_GNUPLOT, default gnuplot;
 * "none" skips) into DIR/figure.png, removed first: no earlier picture
 * passes for this one.  0: rendered; 1: gnuplot not available (*msg says
 * how to render later); -1: gnuplot failed, or a stop signal stopped it
 * (*msg; what it left under the picture's name is removed).  *msg is
 * malloc'd. */
int plot_render(const char *dir, char **msg);
/* The same for another script of DIR (spacetime.gp). */
int plot_render_script(const char *dir, const char *script, char **msg);
/* plot_render_script, and what became of the picture said on out: "!
 * wrote DIR/NAME.png", or a note when gnuplot is not available (not an
 * error: the script stays to render later).  0, or -1 with *msg
 * (malloc'd) when gnuplot failed or a signal stopped it. */
int plot_render_reported(const char *dir, const char *script, FILE *out, char **msg);
/* A gnuplot string literal in double quotes ("enhanced" text kept). */
void plot_gp_string(FILE *fp, const char *s);

#endif
