/*
 * test_chains.h -- building chains in tests: one helper that asserts the
 * chain was built and shows the library's message when it was not.
 */
#ifndef TAPER_TEST_CHAINS_H
#define TAPER_TEST_CHAINS_H

#include "taper.h"
#include "test_util.h"

/* A chain of `profile` with tapering s or q and contact exponent n (radii
 * for TAPER_CUSTOM, else NULL); fails the test if it cannot be built. */
static inline taper_chain *test_chain(int profile, size_t n_granules, double s, double q,
                                      double exponent, const double *radii)
{
    taper_chain_spec spec;
    taper_chain_spec_init(&spec);
    spec.profile = profile;
    spec.n_granules = n_granules;
    spec.s = s;
    spec.q = q;
    spec.exponent = exponent;
    spec.radii = radii;
    taper_error err;
    taper_chain *c = taper_chain_alloc(&spec, &err);
    if (!c) print_error("cannot build the chain: %s\n", err.message);
    assert_non_null(c);
    return c;
}

#endif
