/*
 * names.c -- the names of the per-granule observables of a run
 * (taper_observable_name): the column names of granules.tsv, stated once
 * here so that the driver and the bindings keep no list of their own.
 */
#include "taper.h"

static const char *const observable_names[TAPER_N_OBSERVABLES] = {
    [TAPER_T_PASS] = "t_pass",
    [TAPER_T_RES] = "T_res",
    [TAPER_V_PEAK] = "v_peak",
    [TAPER_T_PEAK] = "t_peak",
    [TAPER_X_PASS] = "X_pass",
};

const char *taper_observable_name(taper_observable which)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)which >= TAPER_N_OBSERVABLES) return NULL;
    return observable_names[which];
}
