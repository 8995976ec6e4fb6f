/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_chains.h -- building chains in tests: one helper that asserts the
 * chain was built and shows the library's message when it was not.
 */
#ifndef TAPER_TEST_CHAINS_H
#define TAPER_TEST_CHAINS_H

#include "taper.h"
#include "test_util.h"

/* Fails the test, with the library's message, unless status is TAPER_OK. */
static inline void test_chain_ok(taper_status status, const taper_error *err)
{
    if (status != TAPER_OK) {
        print_error("cannot build the chain: %s (field %s)\n", err->message,
                    err->field ? err->field : "none");
        fail();
    }
}

/* A chain of `profile` with tapering s or q and contact exponent n (radii:
 * n_granules of them for TAPER_CUSTOM, else NULL); fails the test if it
 * cannot be built.  Only the profile's own parameter is set (s for the
 * linear profiles, q for the exponential ones): the library refuses the
 * other one when it is not 0, so callers may pass one value for both. */
static inline taper_chain *test_chain(taper_profile profile, size_t n_granules, double s, double q,
                                      double exponent, const double *radii)
{
    taper_error err;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    assert_non_null(spec);
    test_chain_ok(taper_chain_spec_set_profile(spec, profile, &err), &err);
    test_chain_ok(taper_chain_spec_set_n_granules(spec, n_granules, &err), &err);
    if (profile == TAPER_BACKWARD_LINEAR || profile == TAPER_FORWARD_LINEAR)
        test_chain_ok(taper_chain_spec_set_s(spec, s, &err), &err);
    if (profile == TAPER_BACKWARD_EXPONENTIAL || profile == TAPER_FORWARD_EXPONENTIAL)
        test_chain_ok(taper_chain_spec_set_q(spec, q, &err), &err);
    test_chain_ok(taper_chain_spec_set_exponent(spec, exponent, &err), &err);
    if (radii) test_chain_ok(taper_chain_spec_set_radii(spec, radii, n_granules, &err), &err);
    taper_chain *c = taper_chain_alloc(spec, &err);
    taper_chain_spec_free(spec);
    if (!c) print_error("cannot build the chain: %s\n", err.message);
    assert_non_null(c);
    return c;
}

#endif
