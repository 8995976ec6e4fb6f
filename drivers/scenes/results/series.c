/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * series.c -- per-granule quantities of a run, theory and numerics alike.
 *
 * The pairing follows the binary collision picture: the theory's t_k is the
 * time the pulse passes k (eq. (19)), like the numerics' t_pass(k);
 * granule k leaves its collision with k-1 with velocity v_k at t_{k-1},
 * which is therefore the theory's time of the velocity peak of k.
 */
#include "results/series.h"

#include <math.h>

/* out[k-1] = a[k-2] (0 for k = 1): the value of the previous granule. */
static void shifted(const double *a, size_t n, double *out)
{
    for (size_t i = 0; i < n; i++) out[i] = i == 0 ? 0.0 : a[i - 1];
}

static void copy(const double *a, size_t n, double *out)
{
    for (size_t i = 0; i < n; i++) out[i] = a ? a[i] : NAN;
}

static void fill_theory(const series_source *s, scene_quantity q, double *out)
{
    switch (q) {
    case SCENE_Q_V: copy(s->theory[TAPER_THEORY_V], s->n, out); break;
    case SCENE_Q_T_RES: copy(s->theory[TAPER_THEORY_T_RES], s->n, out); break;
    case SCENE_Q_T: copy(s->theory[TAPER_THEORY_T], s->n, out); break;
    case SCENE_Q_T_REACH:
    case SCENE_Q_T_PEAK: shifted(s->theory[TAPER_THEORY_T], s->n, out); break;
    default: copy(NULL, s->n, out); break;
    }
}

static void fill_numerics(const series_source *s, scene_quantity q, double *out)
{
    switch (q) {
    case SCENE_Q_V: copy(s->obs[TAPER_V_PEAK], s->n, out); break;
    case SCENE_Q_T_RES: copy(s->obs[TAPER_T_RES], s->n, out); break;
    case SCENE_Q_T: copy(s->obs[TAPER_T_PASS], s->n, out); break;
    case SCENE_Q_T_REACH: shifted(s->obs[TAPER_T_PASS], s->n, out); break;
    case SCENE_Q_T_PEAK: copy(s->obs[TAPER_T_PEAK], s->n, out); break;
    default: copy(NULL, s->n, out); break;
    }
}

int series_fill(const series_source *src, int side, scene_quantity q, double *out)
{
    if (side == SERIES_NUMERICS && !src->obs[TAPER_T_PASS]) return -1;
    if (q == SCENE_Q_K) {
        for (size_t i = 0; i < src->n; i++) out[i] = (double)(i + 1);
        return 0;
    }
    if (side == SERIES_THEORY)
        fill_theory(src, q, out);
    else
        fill_numerics(src, q, out);
    return 0;
}

const char *series_label(scene_quantity q)
{
    switch (q) {
    case SCENE_Q_K: return "k";
    case SCENE_Q_V: return "v_k";
    case SCENE_Q_T_RES: return "T_k";
    default: return "t"; /* t, t_reach, t_peak */
    }
}
