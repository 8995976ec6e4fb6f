/*
 * test_chain.c -- chain geometry (suite 'chain').
 *
 * Every profile's radii, masses, contact factors r_k (eq. r-prime) and rest
 * positions X0(k) against values computed here by hand from the paper's
 * definitions, X0 against the paper's closed forms (Sec. III A:
 * X0 = S k^2 + 2k(1-S) + S - 2; eq. pos-kth: (2-q)/q ((1-q)^(1-k) - 1)),
 * and every invalid parameter rejected with a message.
 */
#include "test_chains.h"
#include "test_util.h"

#include "taper.h"

#include <float.h>
#include <stdint.h>
#include <string.h>

#define RTOL 1e-13

static taper_chain *make(int profile, size_t n, double s, double q)
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

/* Paper's mu_k and r_k of eqs. (mk-ak-linear-1), (mk-ak-linear-2). */
static void test_backward_linear_paper_rk(void **state)
{
    (void)state;
    const double S = 0.7;
    taper_chain *c = make(TAPER_BACKWARD_LINEAR, 50, S, 0);
    for (size_t k = 1; k < 50; k++) {
        double u = S / (1.0 + S * (double)k);
        double rk = sqrt((1.0 + S * (double)k) * (1.0 - u) / (1.0 - u / 2.0));
        assert_double_rel(taper_chain_contact(c)[k - 1], rk, 1e-13);
        /* eq. (ratio-linear): m_k / m_{k+1} = (1 - S/(1+Sk))^3 */
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
    /* eq. (ratio-forw): R_k / R_{k+1} = 1 + S/(1 - Sk). */
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

/* eq. (pos-kth): X0(k) = (2-q)/q ((1-q)^(-k+1) - 1); eq. (ak-binary):
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

static void test_custom(void **state)
{
    (void)state;
    const double R[5] = {1, 3, 0.5, 0.5, 2};
    taper_chain_spec spec;
    taper_chain_spec_init(&spec);
    spec.profile = TAPER_CUSTOM;
    spec.n_granules = 5;
    spec.radii = R;
    spec.exponent = 2.0;
    taper_error err;
    taper_chain *c = taper_chain_alloc(&spec, &err);
    assert_non_null(c);
    check_derived(c, R);
    assert_double_rel(taper_chain_contact(c)[0], sqrt(1.5), RTOL);   /* 2*3/4 */
    assert_double_rel(taper_chain_contact(c)[2], sqrt(0.5), RTOL);   /* equal 0.5, 0.5 */
    assert_double_rel(taper_chain_rest_position(c)[4], 11.0, RTOL);  /* 4+3.5+1+2.5 */
    assert_double_rel(taper_chain_exponent(c), 2.0, 0);
    taper_chain_free(c);
}

/* Expects taper_chain_alloc(spec) to fail with `status` and a message that
 * contains `needle`. */
static void expect_fail(const taper_chain_spec *spec, int status, const char *needle)
{
    taper_error err;
    memset(&err, 0, sizeof err);
    taper_chain *c = taper_chain_alloc(spec, &err);
    assert_null(c);
    assert_int_equal(err.status, status);
    assert_true(strlen(err.message) > 0);
    if (needle && !strstr(err.message, needle)) {
        print_error("message '%s' lacks '%s'\n", err.message, needle);
        fail();
    }
}

static taper_chain_spec spec_of(int profile, size_t n, double s, double q)
{
    taper_chain_spec spec;
    taper_chain_spec_init(&spec);
    spec.profile = profile;
    spec.n_granules = n;
    spec.s = s;
    spec.q = q;
    return spec;
}

static void test_invalid(void **state)
{
    (void)state;
    taper_chain_spec sp;
    assert_null(taper_chain_alloc(NULL, NULL));
    sp = spec_of(TAPER_MONODISPERSE, 1, 0, 0);
    expect_fail(&sp, TAPER_EINVAL, "n_granules");
    sp = spec_of(TAPER_MONODISPERSE, 0, 0, 0);
    expect_fail(&sp, TAPER_EINVAL, "n_granules");
    sp = spec_of(99, 10, 0, 0);
    expect_fail(&sp, TAPER_EINVAL, "profile");
    sp = spec_of(-1, 10, 0, 0);
    expect_fail(&sp, TAPER_EINVAL, "profile");
    /* eq. (r1-forw): N < 1 + 1/S; N = 1 + 1/S exactly makes R_N = 0. */
    sp = spec_of(TAPER_FORWARD_LINEAR, 11, 0.1, 0);
    expect_fail(&sp, TAPER_EINVAL, "1 + 1/s");
    sp = spec_of(TAPER_FORWARD_LINEAR, 200, 0.01, 0);
    expect_fail(&sp, TAPER_EINVAL, "1 + 1/s");
    sp = spec_of(TAPER_FORWARD_LINEAR, 10, NAN, 0);
    expect_fail(&sp, TAPER_EINVAL, "s = nan");
    sp = spec_of(TAPER_BACKWARD_LINEAR, 10, -0.1, 0);
    expect_fail(&sp, TAPER_EINVAL, "s = -0.1");
    sp = spec_of(TAPER_BACKWARD_LINEAR, 10, INFINITY, 0);
    expect_fail(&sp, TAPER_EINVAL, "s = inf");
    const double badq[] = {-0.1, 1.0, 1.5, NAN};
    for (int i = 0; i < 4; i++) {
        sp = spec_of(TAPER_BACKWARD_EXPONENTIAL, 10, 0, badq[i]);
        expect_fail(&sp, TAPER_EINVAL, "q = ");
    }
    sp = spec_of(TAPER_FORWARD_EXPONENTIAL, 10, 0, -0.5);
    expect_fail(&sp, TAPER_EINVAL, "q = ");
    sp = spec_of(TAPER_FORWARD_EXPONENTIAL, 10, 0, NAN);
    expect_fail(&sp, TAPER_EINVAL, "q = ");
    const double badn[] = {1.0, 0.5, -2, NAN, INFINITY};
    for (int i = 0; i < 5; i++) {
        sp = spec_of(TAPER_MONODISPERSE, 10, 0, 0);
        sp.exponent = badn[i];
        expect_fail(&sp, TAPER_EINVAL, "exponent");
    }
}

static void test_invalid_custom(void **state)
{
    (void)state;
    taper_chain_spec sp = spec_of(TAPER_CUSTOM, 3, 0, 0);
    expect_fail(&sp, TAPER_EINVAL, "radii");
    const double zero[3] = {1, 0, 1}, neg[3] = {1, 2, -1}, nan3[3] = {1, NAN, 1},
                 inf3[3] = {1, INFINITY, 1}, first[3] = {2, 2, 2};
    sp.radii = zero;
    expect_fail(&sp, TAPER_EINVAL, "radii(2)");
    sp.radii = neg;
    expect_fail(&sp, TAPER_EINVAL, "radii(3)");
    sp.radii = nan3;
    expect_fail(&sp, TAPER_EINVAL, "radii(2)");
    sp.radii = inf3;
    expect_fail(&sp, TAPER_EINVAL, "radii(2)");
    sp.radii = first;
    expect_fail(&sp, TAPER_EINVAL, "radii(1)");
}

/* Long exponential chains: m_k = (1-q)^(-3(k-1)) passes 1e300 at
 * 3 (k-1) ln 2 > 300 ln 10, i.e. k = 334 for q = 1/2; the message names it. */
static void test_overflow(void **state)
{
    (void)state;
    taper_chain_spec sp = spec_of(TAPER_BACKWARD_EXPONENTIAL, 333, 0, 0.5);
    taper_error err;
    taper_chain *c = taper_chain_alloc(&sp, &err);
    assert_non_null(c);
    taper_chain_free(c);
    sp = spec_of(TAPER_BACKWARD_EXPONENTIAL, 1000, 0, 0.5);
    expect_fail(&sp, TAPER_ERANGE, "granule 334");
    /* Forward: underflow below 1e-300 at the same granule for q = 1. */
    sp = spec_of(TAPER_FORWARD_EXPONENTIAL, 1000, 0, 1.0);
    expect_fail(&sp, TAPER_ERANGE, "granule 334");
    /* A size whose arrays cannot even be addressed. */
    sp = spec_of(TAPER_MONODISPERSE, SIZE_MAX / 2, 0, 0);
    taper_chain *big = taper_chain_alloc(&sp, &err);
    assert_null(big);
    assert_int_not_equal(err.status, TAPER_OK);
}

/* Under AddressSanitizer a huge malloc aborts unless the allocator may
 * return NULL, as the C library's does. */
#if defined(__SANITIZE_ADDRESS__)
#define TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TEST_ASAN 1
#endif
#endif
#ifdef TEST_ASAN
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "allocator_may_return_null=1"; }
#endif

/* Addressable but absurd sizes: the allocation fails at once with
 * TAPER_ENOMEM (the mass-range check once looped over all N granules
 * first: hours for N = 1e12).  8e12 bytes per array exceed any machine and
 * Linux's overcommit heuristic, so malloc reliably says no. */
static void test_absurd_size(void **state)
{
    (void)state;
    const int profiles[] = {TAPER_MONODISPERSE, TAPER_BACKWARD_LINEAR, TAPER_FORWARD_EXPONENTIAL};
    for (size_t i = 0; i < 3; i++) {
        taper_chain_spec sp = spec_of(profiles[i], (size_t)1e12, 1e-9, 1e-15);
        taper_error err;
        taper_chain *c = taper_chain_alloc(&sp, &err);
        assert_null(c);
        assert_int_equal(err.status, TAPER_ENOMEM);
        assert_non_null(strstr(err.message, "allocate"));
    }
    /* Out of mass range long before the end: named in O(log N) steps. */
    taper_chain_spec sp = spec_of(TAPER_BACKWARD_EXPONENTIAL, (size_t)1e15, 0, 0.5);
    expect_fail(&sp, TAPER_ERANGE, "granule 334");
}

static void test_names(void **state)
{
    (void)state;
    int p = -1;
    assert_string_equal(taper_profile_name(TAPER_BACKWARD_LINEAR), "backward_linear");
    assert_int_equal(taper_profile_from_name("Forward_Exponential", &p), TAPER_OK);
    assert_int_equal(p, TAPER_FORWARD_EXPONENTIAL);
    assert_int_equal(taper_profile_from_name("conical", &p), TAPER_EINVAL);
    assert_null(taper_profile_name(6));
    assert_int_equal(taper_chain_size(NULL), 0);
    assert_null(taper_chain_radius(NULL));
    taper_chain_free(NULL);
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
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_invalid_custom),
        cmocka_unit_test(test_overflow),
        cmocka_unit_test(test_absurd_size),
        cmocka_unit_test(test_names),
    };
    return cmocka_run_group_tests_name("chain", tests, NULL, NULL);
}
