/*
 * series.c -- per-granule quantities of a run, theory and numerics alike.
 *
 * The pairing follows the binary collision picture: the theory's t_k is the
 * time the pulse passes k (eq. totaltime), like the numerics' t_pass(k);
 * granule k leaves its collision with k-1 with velocity v_k at t_{k-1},
 * which is therefore the theory's time of the velocity peak of k.
 */
#include "results/series.h"

#include <math.h>
#include <string.h>

/* out[k-1] = a[k-2] (0 for k = 1): the value of the previous granule. */
static void shifted(const double *a, size_t n, double *out)
{
    for (size_t i = 0; i < n; i++) out[i] = i == 0 ? 0.0 : a[i - 1];
}

static void copy(const double *a, size_t n, double *out)
{
    for (size_t i = 0; i < n; i++) out[i] = a ? a[i] : NAN;
}

static int fill_theory(const series_source *s, const char *q, double *out)
{
    if (strcmp(q, "v") == 0) copy(s->theory_v, s->n, out);
    else if (strcmp(q, "T_res") == 0) copy(s->theory_T, s->n, out);
    else if (strcmp(q, "t") == 0) copy(s->theory_t, s->n, out);
    else if (strcmp(q, "t_reach") == 0 || strcmp(q, "t_peak") == 0) shifted(s->theory_t, s->n, out);
    else return -1;
    return 0;
}

static int fill_numerics(const series_source *s, const char *q, double *out)
{
    if (!s->obs[TAPER_T_PASS]) return -1;
    if (strcmp(q, "v") == 0) copy(s->obs[TAPER_V_PEAK], s->n, out);
    else if (strcmp(q, "T_res") == 0) copy(s->obs[TAPER_T_RES], s->n, out);
    else if (strcmp(q, "t") == 0) copy(s->obs[TAPER_T_PASS], s->n, out);
    else if (strcmp(q, "t_reach") == 0) shifted(s->obs[TAPER_T_PASS], s->n, out);
    else if (strcmp(q, "t_peak") == 0) copy(s->obs[TAPER_T_PEAK], s->n, out);
    else return -1;
    return 0;
}

int series_fill(const series_source *src, int side, const char *quantity, double *out)
{
    if (strcmp(quantity, "k") == 0) {
        for (size_t i = 0; i < src->n; i++) out[i] = (double)(i + 1);
        return side == SERIES_NUMERICS && !src->obs[TAPER_T_PASS] ? -1 : 0;
    }
    return side == SERIES_THEORY ? fill_theory(src, quantity, out)
                                 : fill_numerics(src, quantity, out);
}

const char *series_label(const char *quantity)
{
    static const char *const labels[][2] = {
        {"k", "k"}, {"v", "v_k"}, {"T_res", "T_k"}, {"t", "t"}, {"t_reach", "t"}, {"t_peak", "t"},
    };
    for (size_t i = 0; i < sizeof labels / sizeof labels[0]; i++)
        if (strcmp(labels[i][0], quantity) == 0) return labels[i][1];
    return "";
}
