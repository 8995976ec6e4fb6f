/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * pulse.c -- the pulse's speed (pulse.h).
 */
#include "results/pulse.h"

#include <math.h>

static int64_t granule(const int64_t *k, size_t i) { return k ? k[i] : (int64_t)i + 1; }

double pulse_speed(const double *X, const double *t, const int64_t *k, size_t n)
{
    if (!X || !t) return NAN;
    size_t i1 = n;
    while (i1 > 0 && !(isfinite(X[i1 - 1]) && isfinite(t[i1 - 1]))) i1--;
    if (i1 == 0) return NAN;
    i1--; /* the last granule passed */
    const int64_t reached = granule(k, i1);
    const int64_t from = reached - (reached / 10 > 1 ? reached / 10 : 1);
    size_t i0 = 0;
    while (i0 < i1 && !(granule(k, i0) >= from && isfinite(X[i0]) && isfinite(t[i0]))) i0++;
    if (i0 == i1) return NAN;
    const double dt = t[i1] - t[i0];
    return dt != 0.0 ? (X[i1] - X[i0]) / dt : NAN;
}
