/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * series.h -- per-granule quantities of one run (scene_quantity: &fit x, y;
 * &figure x, y), for the numerics and for the binary-collision theory
 * alike, so that one fit or one plot treats both the same way.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SERIES_H
#define TAPER_SERIES_H

#include "scene/scene.h"
#include "taper.h"

#include <stddef.h>

/* What one run produced: arrays of length n, granule k at index k-1. */
typedef struct series_source {
    size_t n;
    const double *theory[TAPER_N_THEORY_QUANTITIES]; /* by TAPER_THEORY_*        */
    const double *obs[TAPER_N_OBSERVABLES];          /* taper_sim_observable; all
                                                        NULL without numerics   */
} series_source;

enum { SERIES_THEORY = 0, SERIES_NUMERICS = 1 };

/* Fills out[k-1], k = 1..n, with quantity q of the theory or the numerics
 * (side); NaN where it does not exist.  -1 for a side without data. */
int series_fill(const series_source *src, int side, scene_quantity q, double *out);

/* Axis label of a quantity ("v_k", "t", ...). */
const char *series_label(scene_quantity q);

#endif
