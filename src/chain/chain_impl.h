/*
 * chain_impl.h -- the layouts behind taper_chain_spec and taper_chain.
 * Private to src/chain (and its unit tests): every other part reads a chain
 * through the getters of taper.h.
 */
#ifndef TAPER_CHAIN_IMPL_H
#define TAPER_CHAIN_IMPL_H

#include "core/taper_internal.h"

/* Settings of a chain; every value in its range (the setters see to it). */
struct taper_chain_spec {
    taper_profile profile;
    size_t n_granules;  /* N                                             */
    double s, q;        /* tapering parameters                            */
    double exponent;    /* contact exponent n                             */
    double *radii;      /* owned copy, n_radii of them; NULL: none        */
    size_t n_radii;
};

/* The chain: plain arrays, granule k at index k-1 (see taper.h). */
struct taper_chain {
    size_t n;           /* number of granules N                         */
    taper_profile profile;
    double exponent;    /* contact exponent n                           */
    double *radius;     /* R_k                                          */
    double *mass;       /* m_k = R_k^3                                  */
    double *contact;    /* r_k for the pair (k, k+1); [n-1] = NaN       */
    double *rest;       /* X0(k)                                        */
};

#endif
