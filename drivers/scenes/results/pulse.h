/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * pulse.h -- the pulse's speed, a result of a run computed from its
 * columns in the units they are written in: one definition for the
 * granules.tsv header (and so runs.tsv) and the Python package's
 * Result.pulse_speed().
 *
 * Not a statistic of the library (taper_statistic): X_pass is a rest
 * position in R_1 plus a displacement in the unit of length (taper.h), so
 * a speed in rescaled units has no single SI scale; computed from the
 * columns after their conversion (scene_column_convert) it is exact in
 * either.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_PULSE_H
#define TAPER_PULSE_H

#include <stddef.h>
#include <stdint.h>

/* The statistic's name in granules.tsv's header, runs.tsv and Result.stats. */
#define PULSE_SPEED_NAME "pulse_speed"

/* The pulse's mean speed over the last tenth of the granules it passed:
 * (X(k1) - X(k0)) / (t(k1) - t(k0)), k1 the last granule whose X and t are
 * both known (finite), k0 the first such granule from k1 - max(1, k1 / 10)
 * on (integer division): where a tapered chain has settled into its
 * asymptotic law.  X and t hold the rows of the granules k[0..n) (NULL:
 * 1..n); X_pass and t_pass for a run, the rest positions X0 and the
 * theory's t_k (eq. (19)) for the theory alone.  NaN with fewer than two
 * such granules, or equal times. */
double pulse_speed(const double *X, const double *t, const int64_t *k, size_t n);

#endif
