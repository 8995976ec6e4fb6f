/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * names.c -- the names of the per-granule observables of a run
 * (taper_observable_name): the column names of granules.tsv, expanded from
 * the one list in taper.h, so that the driver and the bindings keep no list
 * of their own.
 */
#include "taper.h"

#define OBSERVABLE_NAME(constant, name, dimension) [constant] = name,
#define OBSERVABLE_DIMENSION(constant, name, dimension) [constant] = TAPER_DIM_##dimension,
static const char *const observable_names[] = {TAPER_OBSERVABLE_LIST(OBSERVABLE_NAME)};
static const taper_dimension observable_dimensions[] = {TAPER_OBSERVABLE_LIST(OBSERVABLE_DIMENSION)};

taper_dimension taper_observable_dimension(taper_observable which)
{
    return (unsigned)which < TAPER_N_OBSERVABLES ? observable_dimensions[which] : TAPER_DIM_NUMBER;
}

const char *taper_observable_name(taper_observable which)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)which >= TAPER_N_OBSERVABLES) return NULL;
    return observable_names[which];
}
