/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * names.c -- the names of the enums a setting chooses from (profile,
 * disorder, boundary, method) and of the chain's ends, each expanded from
 * its one list in taper.h, and their lookups (core's taper_name_find: the
 * same message and "did you mean" for all).
 */
#include "settings/settings.h"

#define NAME(constant, name) [constant] = name,

const char *const taper_profile_names[] = {TAPER_PROFILE_LIST(NAME) NULL};
const char *const taper_disorder_names[] = {TAPER_DISORDER_LIST(NAME) NULL};
const char *const taper_boundary_names[] = {TAPER_BOUNDARY_LIST(NAME) NULL};
const char *const taper_method_names[] = {TAPER_METHOD_LIST(NAME) NULL};

/* Unsigned: a negative value of an int-typed enum is out of range too. */
const char *taper_profile_name(taper_profile p)
{
    return (unsigned)p < TAPER_N_PROFILES ? taper_profile_names[p] : NULL;
}
const char *taper_disorder_name(taper_disorder d)
{
    return (unsigned)d < TAPER_N_DISORDERS ? taper_disorder_names[d] : NULL;
}
const char *taper_boundary_name(taper_boundary b)
{
    return (unsigned)b < TAPER_N_BOUNDARIES ? taper_boundary_names[b] : NULL;
}
const char *taper_method_name(taper_method m)
{
    return (unsigned)m < TAPER_N_METHODS ? taper_method_names[m] : NULL;
}

/* The inverses: *out only on success. */
#define FROM_NAME(type, names, count, field, what)                                         \
    taper_status taper_##type##_from_name(const char *name, taper_##type *out,             \
                                          taper_error *err)                                \
    {                                                                                      \
        size_t i = 0;                                                                      \
        if (!out) return taper_fail(err, TAPER_EINVAL, "taper_" #type "_from_name: NULL"); \
        taper_status st = taper_name_find(name, names, count, field, what, &i, err);       \
        if (st == TAPER_OK) *out = (taper_##type)i;                                        \
        return st;                                                                         \
    }
FROM_NAME(profile, taper_profile_names, TAPER_N_PROFILES, "profile", "profile")
FROM_NAME(disorder, taper_disorder_names, TAPER_N_DISORDERS, "disorder", "disorder kind")
FROM_NAME(boundary, taper_boundary_names, TAPER_N_BOUNDARIES, "boundary", "boundary")
FROM_NAME(method, taper_method_names, TAPER_N_METHODS, "method", "method")
