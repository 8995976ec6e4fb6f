/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_chain.c -- chain geometry (suite 'chain').
 *
 * Every profile's radii, masses, contact factors r_k (eq. (7)) and rest
 * positions X0(k) against values computed here by hand from the paper's
 * definitions, X0 against the paper's closed forms (Sec. III A:
 * X0 = S k^2 + 2k(1-S) + S - 2; eq. (42): (2-q)/q ((1-q)^(1-k) - 1)),
 * every setting out of range refused by its setter with the field named
 * and the spec unchanged, every relation refused by taper_chain_spec_check
 * and taper_chain_alloc naming the setting to change, and the messages
 * (never cut silently) of the error machinery.
 */
#include "test_chains.h"
#include "test_util.h"

#include "taper.h"

#include <ctype.h>
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define RTOL 1e-13

static taper_chain *make(taper_profile profile, size_t n, double s, double q)
{
    return test_chain(profile, n, s, q, 2.5, NULL);
}

/* r_k = sqrt(2 a b / (a + b)), written out independently of chain.c. */
static double contact(double a, double b) { return sqrt(2.0 * a * b / (a + b)); }

/* Checks masses, r_k and X0 against the radii R (hand values). */
static void check_derived(const taper_chain *c, const double *R)
{
    size_t n = taper_chain_size(c);
    const double *m = taper_chain_mass(c);
    const double *r = taper_chain_contact(c);
    const double *X0 = taper_chain_rest_position(c);
    double x = 0.0;
    for (size_t i = 0; i < n; i++) {
        assert_double_rel(taper_chain_radius(c)[i], R[i], RTOL);
        assert_double_rel(m[i], R[i] * R[i] * R[i], RTOL);
        assert_double_abs(X0[i], x, RTOL * fmax(1.0, x));
        if (i + 1 < n) {
            assert_double_rel(r[i], contact(R[i], R[i + 1]), RTOL);
            x += R[i] + R[i + 1];
        }
    }
    assert_true(isnan(r[n - 1]));
}

static void test_monodisperse(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_MONODISPERSE, 5, 0, 0);
    const double R[5] = {1, 1, 1, 1, 1};
    check_derived(c, R);
    /* Just-touching unit spheres: centres 2 apart, r_k = 1. */
    assert_double_rel(taper_chain_rest_position(c)[4], 8.0, RTOL);
    assert_double_rel(taper_chain_contact(c)[0], 1.0, RTOL);
    assert_double_rel(taper_chain_exponent(c), 2.5, 0);
    assert_int_equal(taper_chain_profile(c), TAPER_MONODISPERSE);
    taper_chain_free(c);
}

static void test_backward_linear(void **state)
{
    (void)state;
    /* S = 0.5: R = 1, 1.5, 2, 2.5; m = 1, 3.375, 8, 15.625;
     * r_1 = sqrt(2*1.5/2.5) = sqrt(1.2); X0 = 0, 2.5, 6, 10.5. */
    taper_chain *c = make(TAPER_BACKWARD_LINEAR, 4, 0.5, 0);
    const double R[4] = {1, 1.5, 2, 2.5};
    check_derived(c, R);
    const double m[4] = {1, 3.375, 8, 15.625};
    const double X0[4] = {0, 2.5, 6, 10.5};
    for (int i = 0; i < 4; i++) {
        assert_double_rel(taper_chain_mass(c)[i], m[i], RTOL);
        assert_double_abs(taper_chain_rest_position(c)[i], X0[i], 1e-14);
    }
    assert_double_rel(taper_chain_contact(c)[0], sqrt(1.2), RTOL);
    taper_chain_free(c);
}

/* Sec. III A: X0(k) = S k^2 + 2k(1-S) + S - 2 for every k, several S. */
static void test_backward_linear_x0_paper(void **state)
{
    (void)state;
    const double S[] = {0.1, 0.3, 0.9, 2.0};
    for (size_t j = 0; j < sizeof S / sizeof S[0]; j++) {
        taper_chain *c = make(TAPER_BACKWARD_LINEAR, 300, S[j], 0);
        for (size_t k = 1; k <= 300; k++) {
            double kk = (double)k;
            double paper = S[j] * kk * kk + 2.0 * kk * (1.0 - S[j]) + S[j] - 2.0;
            assert_double_abs(taper_chain_rest_position(c)[k - 1], paper, 1e-12 * fmax(1, paper));
        }
        taper_chain_free(c);
    }
}

/* Paper's mu_k and r_k of eqs. (23), (24). */
static void test_backward_linear_paper_rk(void **state)
{
    (void)state;
    const double S = 0.7;
    taper_chain *c = make(TAPER_BACKWARD_LINEAR, 50, S, 0);
    for (size_t k = 1; k < 50; k++) {
        double u = S / (1.0 + S * (double)k);
        double rk = sqrt((1.0 + S * (double)k) * (1.0 - u) / (1.0 - u / 2.0));
        assert_double_rel(taper_chain_contact(c)[k - 1], rk, 1e-13);
        /* m_k / m_{k+1} = (1 - S/(1+Sk))^3 (Sec. III A) */
        assert_double_rel(taper_chain_mass(c)[k - 1] / taper_chain_mass(c)[k], pow(1.0 - u, 3), 1e-13);
    }
    taper_chain_free(c);
}

static void test_forward_linear(void **state)
{
    (void)state;
    /* S = 0.2, N = 5 < 1 + 1/S = 6: R = 1, .8, .6, .4, .2. */
    taper_chain *c = make(TAPER_FORWARD_LINEAR, 5, 0.2, 0);
    const double R[5] = {1, 0.8, 0.6, 0.4, 0.2};
    check_derived(c, R);
    const double X0[5] = {0, 1.8, 3.2, 4.2, 4.8};
    for (int i = 0; i < 5; i++)
        assert_double_abs(taper_chain_rest_position(c)[i], X0[i], 1e-14);
    /* eq. (47): R_k / R_{k+1} = 1 + S/(1 - Sk). */
    for (size_t k = 1; k < 5; k++)
        assert_double_rel(R[k - 1] / R[k], 1.0 + 0.2 / (1.0 - 0.2 * (double)k), 1e-14);
    /* X0 = S replaced by -S in the backward closed form: 2(k-1) - S (k-1)^2. */
    taper_chain_free(c);
    c = make(TAPER_FORWARD_LINEAR, 100, 0.0099, 0);
    for (size_t k = 1; k <= 100; k++) {
        double km1 = (double)(k - 1);
        assert_double_abs(taper_chain_rest_position(c)[k - 1], 2.0 * km1 - 0.0099 * km1 * km1, 1e-11);
    }
    taper_chain_free(c);
}

static void test_backward_exponential(void **state)
{
    (void)state;
    /* q = 0.5: R = 1, 2, 4, 8 (R_k = (1-q)^(1-k)); r_1 = sqrt(4/3). */
    taper_chain *c = make(TAPER_BACKWARD_EXPONENTIAL, 4, 0, 0.5);
    const double R[4] = {1, 2, 4, 8};
    check_derived(c, R);
    assert_double_rel(taper_chain_contact(c)[0], sqrt(4.0 / 3.0), RTOL);
    const double X0[4] = {0, 3, 9, 21};
    for (int i = 0; i < 4; i++)
        assert_double_abs(taper_chain_rest_position(c)[i], X0[i], 1e-13);
    taper_chain_free(c);
}

/* eq. (42): X0(k) = (2-q)/q ((1-q)^(-k+1) - 1); eq. (37):
 * r_k = (1-q/2)^(-1/2) (1-q)^(-(k-1)/2). */
static void test_backward_exponential_paper(void **state)
{
    (void)state;
    const double Q[] = {0.01, 0.05, 0.09, 0.3};
    for (size_t j = 0; j < sizeof Q / sizeof Q[0]; j++) {
        double q = Q[j];
        taper_chain *c = make(TAPER_BACKWARD_EXPONENTIAL, 200, 0, q);
        for (size_t k = 1; k <= 200; k++) {
            double km1 = (double)(k - 1);
            double x0 = (2.0 - q) / q * (pow(1.0 - q, -km1) - 1.0);
            assert_double_abs(taper_chain_rest_position(c)[k - 1], x0, 1e-12 * fmax(1, x0));
            assert_double_rel(taper_chain_radius(c)[k - 1], pow(1.0 - q, -km1), 1e-13);
            if (k < 200) {
                double rk = pow(1.0 - q / 2.0, -0.5) * pow(1.0 - q, -km1 / 2.0);
                assert_double_rel(taper_chain_contact(c)[k - 1], rk, 1e-13);
            }
        }
        taper_chain_free(c);
    }
}

static void test_forward_exponential(void **state)
{
    (void)state;
    /* q = 1: R = 1, 1/2, 1/4; r_1 = sqrt(2/3); X0 = 0, 1.5, 2.25. */
    taper_chain *c = make(TAPER_FORWARD_EXPONENTIAL, 3, 0, 1.0);
    const double R[3] = {1, 0.5, 0.25};
    check_derived(c, R);
    assert_double_rel(taper_chain_contact(c)[0], sqrt(2.0 / 3.0), RTOL);
    assert_double_abs(taper_chain_rest_position(c)[2], 2.25, 1e-15);
    taper_chain_free(c);
    /* q = 0.03, N = 150: (1+q)^(1-k), X0 = (2+q)/q (1 - (1+q)^(1-k)). */
    c = make(TAPER_FORWARD_EXPONENTIAL, 150, 0, 0.03);
    for (size_t k = 1; k <= 150; k++) {
        double km1 = (double)(k - 1);
        assert_double_rel(taper_chain_radius(c)[k - 1], pow(1.03, -km1), 1e-13);
        double x0 = (2.0 + 0.03) / 0.03 * (1.0 - pow(1.03, -km1));
        assert_double_abs(taper_chain_rest_position(c)[k - 1], x0, 1e-12 * fmax(1, x0));
    }
    taper_chain_free(c);
}

/* A spec of the given settings; fails the test if a setter refuses one. */
static taper_chain_spec *spec_of(taper_profile profile, size_t n, double s, double q)
{
    taper_error err;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    assert_non_null(spec);
    test_chain_ok(taper_chain_spec_set_profile(spec, profile, &err), &err);
    test_chain_ok(taper_chain_spec_set_n_granules(spec, n, &err), &err);
    test_chain_ok(taper_chain_spec_set_s(spec, s, &err), &err);
    test_chain_ok(taper_chain_spec_set_q(spec, q, &err), &err);
    return spec;
}

static void test_custom(void **state)
{
    (void)state;
    double R[5] = {1, 3, 0.5, 0.5, 2};
    taper_chain_spec *spec = spec_of(TAPER_CUSTOM, 5, 0, 0);
    taper_error err;
    assert_int_equal(taper_chain_spec_set_radii(spec, R, 5, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_exponent(spec, 2.0, &err), TAPER_OK);
    /* The spec holds its own copy of the radii... */
    const double R0 = R[1];
    R[1] = 99.0;
    size_t n_radii = 0;
    const double *held = taper_chain_spec_radii(spec, &n_radii);
    assert_int_equal(n_radii, 5);
    assert_double_rel(held[1], R0, 0);
    R[1] = R0;
    taper_chain *c = taper_chain_alloc(spec, &err);
    assert_non_null(c);
    assert_int_equal(err.status, TAPER_OK);
    assert_null(err.field);
    assert_string_equal(err.message, "");
    /* ... and the chain of the spec: freeing the spec leaves it intact. */
    taper_chain_spec_free(spec);
    check_derived(c, R);
    assert_double_rel(taper_chain_contact(c)[0], sqrt(1.5), RTOL);   /* 2*3/4 */
    assert_double_rel(taper_chain_contact(c)[2], sqrt(0.5), RTOL);   /* equal 0.5, 0.5 */
    assert_double_rel(taper_chain_rest_position(c)[4], 11.0, RTOL);  /* 4+3.5+1+2.5 */
    assert_double_rel(taper_chain_exponent(c), 2.0, 0);
    assert_int_equal(taper_chain_profile(c), TAPER_CUSTOM);
    taper_chain_free(c);
}

static void test_spec_defaults(void **state)
{
    (void)state;
    taper_error err;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    assert_non_null(spec);
    assert_int_equal(err.status, TAPER_OK);
    assert_int_equal(taper_chain_spec_profile(spec), TAPER_MONODISPERSE);
    assert_int_equal(taper_chain_spec_n_granules(spec), 100);
    assert_double_abs(taper_chain_spec_s(spec), 0.0, 0);
    assert_double_abs(taper_chain_spec_q(spec), 0.0, 0);
    assert_double_rel(taper_chain_spec_exponent(spec), 2.5, 0);
    size_t n = 7;
    assert_null(taper_chain_spec_radii(spec, &n));
    assert_int_equal(n, 0);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_OK);
    /* Radii set, then removed with NULL, 0. */
    const double R[3] = {1, 2, 3};
    assert_int_equal(taper_chain_spec_set_radii(spec, R, 3, &err), TAPER_OK);
    assert_non_null(taper_chain_spec_radii(spec, &n));
    assert_int_equal(n, 3);
    assert_int_equal(taper_chain_spec_set_radii(spec, NULL, 0, &err), TAPER_OK);
    assert_null(taper_chain_spec_radii(spec, &n));
    assert_int_equal(n, 0);
    /* The extremes of every range are allowed. */
    assert_int_equal(taper_chain_spec_set_n_granules(spec, TAPER_N_GRANULES_MIN, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, TAPER_N_GRANULES_MAX, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_s(spec, 0.0, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_s(spec, TAPER_S_MAX, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_q(spec, 0.0, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_q(spec, TAPER_Q_MAX, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_exponent(spec, TAPER_EXPONENT_MAX, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_exponent(spec, TAPER_EXPONENT_MIN, &err), TAPER_OK);
    taper_chain_spec_free(spec);
    taper_chain_spec_free(NULL);
    /* NULL specs: refused by every function that takes one; getters read a
     * NULL spec as a fresh one (the defaults). */
    assert_int_equal(taper_chain_spec_set_s(NULL, 0.1, &err), TAPER_EINVAL);
    assert_null(err.field);
    assert_int_equal(taper_chain_spec_check(NULL, &err), TAPER_EINVAL);
    assert_null(taper_chain_alloc(NULL, &err));
    assert_int_equal(err.status, TAPER_EINVAL);
    assert_null(taper_chain_alloc(NULL, NULL));
    assert_int_equal(taper_chain_spec_n_granules(NULL), 100);
    assert_true(taper_chain_spec_s(NULL) == 0.0);
    assert_true(taper_chain_spec_exponent(NULL) == 2.5);
    assert_int_equal(taper_chain_spec_profile(NULL), TAPER_MONODISPERSE);
    size_t n_radii = 9;
    assert_null(taper_chain_spec_radii(NULL, &n_radii));
    assert_int_equal(n_radii, 0);
}

/* Every setting of a spec, to see that a refused value changed none. */
typedef struct snapshot {
    taper_profile profile;
    size_t n, n_radii;
    double s, q, exponent;
    const double *radii;
} snapshot;

static snapshot snap(const taper_chain_spec *spec)
{
    snapshot x;
    x.profile = taper_chain_spec_profile(spec);
    x.n = taper_chain_spec_n_granules(spec);
    x.s = taper_chain_spec_s(spec);
    x.q = taper_chain_spec_q(spec);
    x.exponent = taper_chain_spec_exponent(spec);
    x.radii = taper_chain_spec_radii(spec, &x.n_radii);
    return x;
}

static void assert_unchanged(const taper_chain_spec *spec, const snapshot *before)
{
    snapshot now = snap(spec);
    assert_int_equal(now.profile, before->profile);
    assert_int_equal(now.n, before->n);
    assert_true(now.s == before->s);
    assert_true(now.q == before->q);
    assert_true(now.exponent == before->exponent);
    assert_ptr_equal(now.radii, before->radii);
    assert_int_equal(now.n_radii, before->n_radii);
}

/* A spec with every setting away from its default and radii set, so that a
 * setter that wrote anything would show. */
static taper_chain_spec *busy_spec(void)
{
    taper_chain_spec *spec = spec_of(TAPER_BACKWARD_LINEAR, 7, 0.25, 0.125);
    const double R[2] = {1, 2};
    taper_error err;
    test_chain_ok(taper_chain_spec_set_exponent(spec, 3.5, &err), &err);
    test_chain_ok(taper_chain_spec_set_radii(spec, R, 2, &err), &err);
    return spec;
}

#define EXPECT_REFUSED(call, field, needle)                                             \
    do {                                                                                \
        taper_chain_spec *spec = busy_spec();                                           \
        snapshot before = snap(spec);                                                   \
        taper_error err;                                                                \
        memset(&err, 0, sizeof err);                                                    \
        taper_status st = (call);                                                       \
        assert_int_equal(st, TAPER_EINVAL);                                             \
        assert_taper_error(err, TAPER_EINVAL, field, needle);                           \
        assert_unchanged(spec, &before);                                                \
        taper_chain_spec_free(spec);                                                    \
    } while (0)

static void test_setters_refuse(void **state)
{
    (void)state;
    const size_t badn[] = {0, 1, TAPER_N_GRANULES_MAX + 1, (size_t)1e12, SIZE_MAX / 2, SIZE_MAX};
    for (size_t i = 0; i < sizeof badn / sizeof badn[0]; i++)
        EXPECT_REFUSED(taper_chain_spec_set_n_granules(spec, badn[i], &err), "n_granules",
                       "n_granules = ");
    EXPECT_REFUSED(taper_chain_spec_set_profile(spec, (taper_profile)99, &err), "profile", "99");
    EXPECT_REFUSED(taper_chain_spec_set_profile(spec, (taper_profile)-1, &err), "profile", "-1");
    EXPECT_REFUSED(taper_chain_spec_set_profile(spec, (taper_profile)TAPER_N_PROFILES, &err),
                   "profile", "no such profile");
    EXPECT_REFUSED(taper_chain_spec_set_s(spec, NAN, &err), "s", "s = nan");
    EXPECT_REFUSED(taper_chain_spec_set_s(spec, -0.1, &err), "s", "s = -0.1");
    EXPECT_REFUSED(taper_chain_spec_set_s(spec, INFINITY, &err), "s", "s = inf");
    EXPECT_REFUSED(taper_chain_spec_set_s(spec, nextafter(TAPER_S_MAX, 2e3), &err), "s",
                   "out of range [0, 1000]");
    const double badq[] = {-0.1, -INFINITY, INFINITY, NAN, 1001.0};
    for (size_t i = 0; i < sizeof badq / sizeof badq[0]; i++)
        EXPECT_REFUSED(taper_chain_spec_set_q(spec, badq[i], &err), "q", "q = ");
    /* 1.01 to 1.4: the integration stalled or took hours
     * (n = 1.01 hung, 1.1 ran to t = 1e300, 1.2 took 7 million steps);
     * refused before the run, saying why and what to give. */
    const double badexp[] = {1.0, 1.01, 1.1, 1.2, 1.4, nextafter(1.5, 0.0), 0.5, -2, NAN, INFINITY, 20.5};
    for (size_t i = 0; i < sizeof badexp / sizeof badexp[0]; i++)
        EXPECT_REFUSED(taper_chain_spec_set_exponent(spec, badexp[i], &err), "exponent",
                       "exponent = ");
    EXPECT_REFUSED(taper_chain_spec_set_exponent(spec, 25, &err), "exponent", "[1.5, 20]");
    EXPECT_REFUSED(taper_chain_spec_set_exponent(spec, 1.2, &err), "exponent",
                   "below 3/2 the force's slope (n-1) z^(n-2) is unbounded at contact onset");
    const double zero[3] = {1, 0, 1}, neg[3] = {1, 2, -1}, nan3[3] = {1, NAN, 1},
                 inf3[3] = {1, INFINITY, 1};
    EXPECT_REFUSED(taper_chain_spec_set_radii(spec, zero, 3, &err), "radii", "radii(2)");
    EXPECT_REFUSED(taper_chain_spec_set_radii(spec, neg, 3, &err), "radii", "radii(3)");
    EXPECT_REFUSED(taper_chain_spec_set_radii(spec, nan3, 3, &err), "radii", "radii(2)");
    EXPECT_REFUSED(taper_chain_spec_set_radii(spec, inf3, 3, &err), "radii", "radii(2)");
    EXPECT_REFUSED(taper_chain_spec_set_radii(spec, NULL, 3, &err), "radii", "NULL");
    /* More radii than any chain has granules: refused before they are read. */
    EXPECT_REFUSED(taper_chain_spec_set_radii(spec, zero, (size_t)TAPER_N_GRANULES_MAX + 1, &err),
                   "radii", "at most");
}

/* taper_chain_spec_check and taper_chain_alloc refuse the same relations
 * with the same status, field and message. */
static void expect_relation(taper_chain_spec *spec, const char *field, const char *needle)
{
    taper_error err, err2;
    memset(&err, 0, sizeof err);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, field, needle);
    assert_null(taper_chain_alloc(spec, &err2));
    assert_taper_error(err2, TAPER_EINVAL, field, needle);
    assert_string_equal(err.message, err2.message);
    taper_chain_spec_free(spec);
}

static void test_relations(void **state)
{
    (void)state;
    /* eq. (46): N < 1 + 1/S; N = 1 + 1/S exactly makes R_N = 0.  Fixed by
     * fewer granules (named) or a smaller s (said). */
    expect_relation(spec_of(TAPER_FORWARD_LINEAR, 11, 0.1, 0), "n_granules", "n_granules < 1 + 1/s = 11");
    expect_relation(spec_of(TAPER_FORWARD_LINEAR, 200, 0.01, 0), "n_granules", "lower n_granules or s");
    expect_relation(spec_of(TAPER_FORWARD_LINEAR, 3, TAPER_S_MAX, 0), "n_granules", "1 + 1/s");
    /* q < 1 only for backward_exponential. */
    const double badq[] = {1.0, 1.5, TAPER_Q_MAX};
    for (int i = 0; i < 3; i++)
        expect_relation(spec_of(TAPER_BACKWARD_EXPONENTIAL, 10, 0, badq[i]), "q", "q < 1");
    /* Custom: radii needed, one per granule, the first 1. */
    expect_relation(spec_of(TAPER_CUSTOM, 3, 0, 0), "radii", "needs radii");
    const double two[2] = {1, 2}, first[3] = {2, 2, 2};
    taper_error err;
    taper_chain_spec *sp = spec_of(TAPER_CUSTOM, 3, 0, 0);
    test_chain_ok(taper_chain_spec_set_radii(sp, two, 2, &err), &err);
    expect_relation(sp, "radii", "2 radii but n_granules = 3");
    sp = spec_of(TAPER_CUSTOM, 3, 0, 0);
    test_chain_ok(taper_chain_spec_set_radii(sp, first, 3, &err), &err);
    expect_relation(sp, "radii", "radii(1)");
    /* Valid relations: TAPER_OK, field NULL, empty message, even after a
     * failure left them set. */
    sp = spec_of(TAPER_FORWARD_LINEAR, 10, 0.1, 0);
    err.status = TAPER_EINVAL;
    err.field = "q";
    strcpy(err.message, "stale");
    assert_int_equal(taper_chain_spec_check(sp, &err), TAPER_OK);
    assert_int_equal(err.status, TAPER_OK);
    assert_null(err.field);
    assert_string_equal(err.message, "");
    taper_chain *c = taper_chain_alloc(sp, NULL);
    assert_non_null(c);
    taper_chain_free(c);
    taper_chain_spec_free(sp);
    /* s belongs to the linear profiles, q to the exponential ones: a
     * parameter on a profile that does not read it was silently ignored;
     * refused, naming the parameter. */
    expect_relation(spec_of(TAPER_MONODISPERSE, 5, 0.1, 0), "s", "no effect with profile = 'monodisperse'");
    expect_relation(spec_of(TAPER_BACKWARD_EXPONENTIAL, 5, 500.0, 0.5), "s", "no effect");
    expect_relation(spec_of(TAPER_MONODISPERSE, 5, 0, 0.1), "q", "no effect with profile = 'monodisperse'");
    expect_relation(spec_of(TAPER_BACKWARD_LINEAR, 5, 0.5, 5.0), "q", "no effect");
    expect_relation(spec_of(TAPER_CUSTOM, 5, 0.5, 0), "s", "no effect with profile = 'custom'");
    c = test_chain(TAPER_MONODISPERSE, 5, 0, 0, 2.5, NULL);
    taper_chain_free(c);
}

/* s = 0 and q = 0 with their own profiles: the limit of the taper, the
 * monodisperse chain, radii, masses and the theory's columns equal to it
 * bit for bit (the baseline of a sweep over s or q). */
static void test_taper_limit(void **state)
{
    (void)state;
    enum { N = 40 };
    const taper_profile tapered[] = {TAPER_BACKWARD_LINEAR, TAPER_FORWARD_LINEAR,
                                     TAPER_BACKWARD_EXPONENTIAL, TAPER_FORWARD_EXPONENTIAL};
    taper_chain *mono = test_chain(TAPER_MONODISPERSE, N, 0, 0, 2.5, NULL);
    double v0[N], t0[N], v[N], t[N];
    assert_int_equal(taper_theory_compute(mono, v0, NULL, NULL, t0, NULL), TAPER_OK);
    for (int i = 0; i < 4; i++) {
        taper_chain *c = test_chain(tapered[i], N, 0, 0, 2.5, NULL);
        taper_error err;
        assert_int_equal(taper_theory_compute(c, v, NULL, NULL, t, &err), TAPER_OK);
        for (size_t k = 0; k < N; k++) {
            assert_true(taper_chain_radius(c)[k] == 1.0);
            assert_true(taper_chain_mass(c)[k] == taper_chain_mass(mono)[k]);
            assert_true(v[k] == v0[k]);
            assert_true(k + 1 == N ? isnan(t[k]) && isnan(t0[k]) : t[k] == t0[k]);
        }
        /* the monodisperse collision: T = eq. (18) with mu = 1/2, r of two
         * unit spheres, zdot0 = 1 */
        assert_true(fabs(t[0] - taper_theory_collision_time(0.5, taper_chain_contact(c)[0], 1.0, 2.5)) <
                    1e-15 * t[0]);
        taper_chain_free(c);
    }
    taper_chain_free(mono);
}

/* Long exponential chains: m_k = (1-q)^(-3(k-1)) passes 1e300 at
 * 3 (k-1) ln 2 > 300 ln 10, i.e. k = 334 for q = 1/2; the message names it
 * and the number of granules that fits, and the field is n_granules. */
static void expect_range(taper_chain_spec *spec, const char *field, const char *needle)
{
    taper_error err;
    memset(&err, 0, sizeof err);
    assert_null(taper_chain_alloc(spec, &err));
    assert_taper_error(err, TAPER_ERANGE, field, needle);
    taper_chain_spec_free(spec);
}

static void test_overflow(void **state)
{
    (void)state;
    taper_chain_spec *sp = spec_of(TAPER_BACKWARD_EXPONENTIAL, 333, 0, 0.5);
    taper_error err;
    taper_chain *c = taper_chain_alloc(sp, &err);
    assert_non_null(c);
    taper_chain_free(c);
    taper_chain_spec_free(sp);
    expect_range(spec_of(TAPER_BACKWARD_EXPONENTIAL, 1000, 0, 0.5), "n_granules", "granule 334");
    expect_range(spec_of(TAPER_BACKWARD_EXPONENTIAL, 1000, 0, 0.5), "n_granules",
                 "use at most 333 granules (or a smaller q)");
    /* Forward: underflow below 1e-300 at the same granule for q = 1. */
    expect_range(spec_of(TAPER_FORWARD_EXPONENTIAL, 1000, 0, 1.0), "n_granules", "granule 334");
    /* A custom chain: the radius at fault is named. */
    const double R[4] = {1, 2, 1e101, 3};
    sp = spec_of(TAPER_CUSTOM, 4, 0, 0);
    test_chain_ok(taper_chain_spec_set_radii(sp, R, 4, &err), &err);
    expect_range(sp, "radii", "radii(3)");
}

/* The largest chain allowed, out of mass range long before its end: the
 * first granule out of range is found by bisection in O(log N) steps
 * (the mass-range check once looped over all N granules first). */
static void test_largest_size(void **state)
{
    (void)state;
    expect_range(spec_of(TAPER_BACKWARD_EXPONENTIAL, TAPER_N_GRANULES_MAX, 0, 0.5), "n_granules",
                 "granule 334");
    /* m_k = 1001^(-3(k-1)) < 1e-300 first at 3 (k-1) ln 1001 > 300 ln 10:
     * k = 35. */
    expect_range(spec_of(TAPER_FORWARD_EXPONENTIAL, TAPER_N_GRANULES_MAX, 0, TAPER_Q_MAX),
                 "n_granules", "granule 35:");
}

static void test_names(void **state)
{
    (void)state;
    /* The one list: every profile round-trips, in any case. */
    size_t count = 0;
    for (unsigned i = 0; taper_profile_name((taper_profile)i); i++) {
        const char *name = taper_profile_name((taper_profile)i);
        taper_profile p = (taper_profile)-1;
        taper_error err;
        assert_int_equal(taper_profile_from_name(name, &p, &err), TAPER_OK);
        assert_int_equal(p, i);
        assert_int_equal(err.status, TAPER_OK);
        assert_null(err.field);
        char upper[64];
        size_t j = 0;
        for (; name[j] && j + 1 < sizeof upper; j++) upper[j] = (char)toupper((unsigned char)name[j]);
        upper[j] = '\0';
        p = (taper_profile)-1;
        assert_int_equal(taper_profile_from_name(upper, &p, NULL), TAPER_OK);
        assert_int_equal(p, i);
        count++;
    }
    assert_int_equal(count, TAPER_N_PROFILES);
    assert_string_equal(taper_profile_name(TAPER_BACKWARD_LINEAR), "backward_linear");
    assert_string_equal(taper_profile_name(TAPER_CUSTOM), "custom");
    assert_null(taper_profile_name((taper_profile)-1));
    assert_null(taper_profile_name((taper_profile)TAPER_N_PROFILES));
    /* Unknown names: TAPER_EINVAL, field "profile", the names listed, the
     * output untouched. */
    taper_profile p = TAPER_FORWARD_LINEAR;
    taper_error err;
    assert_int_equal(taper_profile_from_name("conical", &p, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "profile", "'conical'");
    assert_non_null(strstr(err.message, "'monodisperse'"));
    assert_non_null(strstr(err.message, "'custom'"));
    assert_int_equal(p, TAPER_FORWARD_LINEAR);
    assert_int_equal(taper_profile_from_name("", &p, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "profile", NULL);
    assert_int_equal(taper_profile_from_name(NULL, &p, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "profile", NULL);
    assert_int_equal(taper_profile_from_name("custom", NULL, &err), TAPER_EINVAL);
    assert_int_equal(taper_chain_size(NULL), 0);
    assert_null(taper_chain_radius(NULL));
    assert_null(taper_profile_name(taper_chain_profile(NULL)));
    taper_chain_free(NULL);
}

/* A message longer than taper_error's buffer ends in "...": here the
 * unknown name itself (3000 characters) does not fit, and a name of 470
 * leaves the list of profiles appended after it no room. */
static void test_long_message(void **state)
{
    (void)state;
    const size_t lengths[] = {3000, 470, TAPER_MESSAGE_SIZE};
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
        char *name = malloc(lengths[i] + 1);
        assert_non_null(name);
        memset(name, 'x', lengths[i]);
        name[lengths[i]] = '\0';
        taper_profile p;
        taper_error err;
        assert_int_equal(taper_profile_from_name(name, &p, &err), TAPER_EINVAL);
        assert_taper_error(err, TAPER_EINVAL, "profile", "unknown profile 'xxx");
        size_t len = strlen(err.message);
        assert_int_equal(len, TAPER_MESSAGE_SIZE - 1);
        assert_string_equal(err.message + len - 3, "...");
        free(name);
    }
    /* A message that fits is not marked. */
    taper_profile p;
    taper_error err;
    assert_int_equal(taper_profile_from_name("xx", &p, &err), TAPER_EINVAL);
    assert_null(strstr(err.message, "..."));
    /* The last profile of the list, in full. */
    assert_string_equal(err.message + strlen(err.message) - 12, "'decorated')");
}

static void test_strerror(void **state)
{
    (void)state;
    const taper_status all[] = {TAPER_OK, TAPER_EINVAL, TAPER_ENOMEM, TAPER_ERANGE,
                                TAPER_ESOLVER, TAPER_EINTERRUPTED, TAPER_ELIMIT};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
        const char *text = taper_strerror(all[i]);
        assert_non_null(text);
        assert_string_not_equal(text, "unknown status");
        for (size_t j = 0; j < i; j++) assert_string_not_equal(text, taper_strerror(all[j]));
    }
    assert_string_equal(taper_strerror(TAPER_EINVAL), "invalid argument");
    assert_string_equal(taper_strerror((taper_status)7), "unknown status");
    assert_string_equal(taper_strerror((taper_status)-1), "unknown status");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_monodisperse),
        cmocka_unit_test(test_backward_linear),
        cmocka_unit_test(test_backward_linear_x0_paper),
        cmocka_unit_test(test_backward_linear_paper_rk),
        cmocka_unit_test(test_forward_linear),
        cmocka_unit_test(test_backward_exponential),
        cmocka_unit_test(test_backward_exponential_paper),
        cmocka_unit_test(test_forward_exponential),
        cmocka_unit_test(test_custom),
        cmocka_unit_test(test_spec_defaults),
        cmocka_unit_test(test_setters_refuse),
        cmocka_unit_test(test_relations),
        cmocka_unit_test(test_taper_limit),
        cmocka_unit_test(test_overflow),
        cmocka_unit_test(test_largest_size),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_long_message),
        cmocka_unit_test(test_strerror),
    };
    return cmocka_run_group_tests_name("chain", tests, NULL, NULL);
}
