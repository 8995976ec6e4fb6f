/*
 * taper_internal.h -- declarations shared by the library's modules.
 * Not installed.  Symbols declared here have hidden visibility in libtaper.so
 * but are reachable from the driver and the tests through the static core.
 */
#ifndef TAPER_INTERNAL_H
#define TAPER_INTERNAL_H

#include "taper.h"

#include <stdarg.h>

#if defined(__GNUC__) || defined(__clang__)
#define TAPER_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define TAPER_PRINTF(a, b)
#endif

/* Records status and a formatted message in err (if non-NULL); returns status. */
int taper_fail(taper_error *err, int status, const char *fmt, ...) TAPER_PRINTF(3, 4);
/* Clears err to TAPER_OK with an empty message; returns TAPER_OK. */
int taper_ok(taper_error *err);

/* The chain: plain arrays, granule k at index k-1 (see taper.h). */
struct taper_chain {
    size_t n;          /* number of granules N                         */
    int profile;
    double s, q;       /* tapering parameters as given                 */
    double exponent;   /* contact exponent n                           */
    double *radius;    /* R_k                                          */
    double *mass;      /* m_k = R_k^3                                  */
    double *contact;   /* r_k for the pair (k, k+1); [n-1] = NaN       */
    double *rest;      /* X0(k)                                        */
};

#endif
