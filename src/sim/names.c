/*
 * names.c -- the names of the per-granule observables of a run
 * (taper_observable_name): the column names of granules.tsv, expanded from
 * the one list in taper.h, so that the driver and the bindings keep no list
 * of their own.
 */
#include "taper.h"

#define OBSERVABLE_NAME(constant, name) [constant] = name,
static const char *const observable_names[] = {TAPER_OBSERVABLE_LIST(OBSERVABLE_NAME)};

const char *taper_observable_name(taper_observable which)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)which >= TAPER_N_OBSERVABLES) return NULL;
    return observable_names[which];
}
