/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_asymptotic.c -- the large-k laws of src/analysis/asymptotic.c against the exact
 * binary-collision sums and products of taper_theory_compute (suite
 * 'asymptotic').  Nothing here is compared with a transcribed formula alone:
 * each law is recovered from the exact theory (local slopes, exact ratios,
 * converged sums), and each of the paper's printed forms that disagrees is
 * shown to disagree with the same evidence (docs/paper.md).
 */
#include "test_chains.h"
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct exact {
    taper_chain *chain;
    size_t n;
    double *v, *T, *t;
    const double *R, *X0;
} exact;

static exact exact_theory(taper_profile profile, size_t n, double s, double q, double expo)
{
    exact e = {0};
    e.chain = test_chain(profile, n, s, q, expo, NULL);
    e.n = n;
    e.v = malloc(n * sizeof(double));
    e.T = malloc(n * sizeof(double));
    e.t = malloc(n * sizeof(double));
    e.R = taper_chain_radius(e.chain);
    e.X0 = taper_chain_rest_position(e.chain);
    assert_int_equal(taper_theory_compute(e.chain, e.v, NULL, e.T, e.t, NULL), TAPER_OK);
    return e;
}

static void exact_free(exact *e)
{
    free(e->v);
    free(e->T);
    free(e->t);
    taper_chain_free(e->chain);
}

/* Local exponent d ln y / d ln x between indices i and j. */
static double slope(const double *x, const double *y, size_t i, size_t j)
{
    return log(y[j] / y[i]) / log(x[j] / x[i]);
}

static void test_exponents_values(void **state)
{
    (void)state;
    const double expect[] = {-1.5, 1.3, 2.3, 10.0 / 23, -15.0 / 23, 20.0 / 23, -3.0 / 23,
                             -1.5, 2.3, -15.0 / 23};
    for (int law = 0; law < 10; law++)
        assert_double_rel(taper_asymptotic_exponent((taper_law)law, 2.5), expect[law], 1e-15);
    assert_true(isnan(taper_asymptotic_exponent((taper_law)10, 2.5)));
    assert_true(isnan(taper_asymptotic_exponent((taper_law)-1, 2.5)));
    assert_true(isnan(taper_asymptotic_exponent(TAPER_LAW_T_OF_K, 1.0)));
    assert_true(isnan(taper_asymptotic_exponent(TAPER_LAW_T_OF_K, NAN)));
    assert_true(isnan(taper_asymptotic_exponent(TAPER_LAW_T_OF_K, INFINITY)));
}

/* Backward linear, S = 0.9: the local exponents of the exact theory at
 * k ~ 1e5 approach the laws (errors O(1/(Sk))); checked for n = 5/2, 2, 3. */
static void check_backward_linear(double n)
{
    const size_t N = 200002, i = 99999, j = 199999; /* k = 1e5, 2e5 */
    exact e = exact_theory(TAPER_BACKWARD_LINEAR, N, 0.9, 0, n);
    double *k = malloc(N * sizeof(double)), *c = malloc(N * sizeof(double));
    for (size_t m = 0; m < N; m++) k[m] = (double)(m + 1);
    /* pulse speed between the centres of k and k+1 while it crosses k+1 */
    for (size_t m = 0; m + 2 < N; m++) c[m] = (e.X0[m + 1] - e.X0[m]) / e.T[m + 1];
    const double tol = 1e-4;
    assert_double_abs(slope(k, e.v, i, j), taper_asymptotic_exponent(TAPER_LAW_V_OF_K, n), tol);
    assert_double_abs(slope(k, e.T, i, j), taper_asymptotic_exponent(TAPER_LAW_T_RES_OF_K, n), tol);
    assert_double_abs(slope(k, e.t, i, j), taper_asymptotic_exponent(TAPER_LAW_T_OF_K, n), tol);
    assert_double_abs(slope(e.t, k, i, j), taper_asymptotic_exponent(TAPER_LAW_K_OF_T, n), tol);
    assert_double_abs(slope(e.t, e.v, i, j), taper_asymptotic_exponent(TAPER_LAW_V_OF_T, n), tol);
    assert_double_abs(slope(e.t, e.X0, i, j), taper_asymptotic_exponent(TAPER_LAW_X_OF_T, n), tol);
    assert_double_abs(slope(e.t, c, i, j), taper_asymptotic_exponent(TAPER_LAW_C_OF_T, n), tol);
    if (n == 2.5) {
        /* The paper's eq. (31) c ~ t^(-3/20) is not what the exact theory gives. */
        assert_true(fabs(slope(e.t, c, i, j) - (-3.0 / 20.0)) > 0.01);
    }
    free(k);
    free(c);
    exact_free(&e);
}

static void test_backward_linear(void **state)
{
    (void)state;
    check_backward_linear(2.5);
    check_backward_linear(2.0);
    check_backward_linear(3.0);
}

/* Backward exponential: ln A, eta exact per step; t_k = tau (e^(k eta) - 1)
 * and v_k = (1 + t_{k-1}/tau)^-f for every k; position exponent from the
 * local slope of X0 against t; 1 - f/5 for n = 5/2. */
static void check_backward_exponential(double q, double n)
{
    const size_t N = 300;
    exact e = exact_theory(TAPER_BACKWARD_EXPONENTIAL, N, 0, q, n);
    double lnA = taper_asymptotic_lnA(q), eta = taper_asymptotic_eta(q, n);
    double f = taper_asymptotic_f(q, n), tau = taper_asymptotic_timescale(q, n);
    assert_double_rel(lnA, log(taper_asymptotic_A(q)), 1e-12);
    for (size_t k = 1; k < N; k++) {
        assert_double_rel(log(e.v[k - 1] / e.v[k]), lnA, 1e-9);
        if (k + 1 < N) assert_double_rel(log(e.T[k] / e.T[k - 1]), eta, 1e-8);
        assert_double_rel(e.t[k - 1], tau * expm1((double)k * eta), 1e-11);
        double tprev = k == 1 ? 0.0 : e.t[k - 2];
        assert_double_rel(e.v[k - 1], pow(1.0 + tprev / tau, -f), 1e-10);
    }
    /* X ~ t^p.  Exactly, X0(k) + (2-q)/q = (2-q)/q (1-q)^(1-k) (eq. (42))
     * = (2-q)/q (1 + t_{k-1}/tau)^p; and the local slope once e^(k eta) >> 1. */
    double p = taper_asymptotic_position_exponent(q, n), X1 = (2.0 - q) / q;
    for (size_t k = 2; k <= N; k++)
        assert_double_rel(e.X0[k - 1] + X1, X1 * pow(1.0 + e.t[k - 2] / tau, p), 1e-10);
    if (q >= 0.05) assert_double_abs(slope(e.t, e.X0, 200, 298), p, 1e-4);
    assert_double_rel(taper_asymptotic_speed_exponent(q, n), p - 1.0, 1e-14);
    if (n == 2.5) assert_double_rel(p, 1.0 - f / 5.0, 1e-12);
    exact_free(&e);
}

static void test_backward_exponential(void **state)
{
    (void)state;
    const double Q[] = {0.01, 0.05, 0.09, 0.3};
    const double expo[] = {2.5, 1.5, 2.0, 4.0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) check_backward_exponential(Q[i], expo[j]);
}

/* eq. (43) prints X ~ (2-q)/(q(1-q)) e^(-k ln(1-q)); from
 * eq. (42), (1-q)^(1-k) = (1-q) e^(-k ln(1-q)), so the prefactor is
 * (2-q)(1-q)/q.  The exact X0 of the chain decides. */
static void test_position_prefactor(void **state)
{
    (void)state;
    const double q = 0.05;
    exact e = exact_theory(TAPER_BACKWARD_EXPONENTIAL, 400, 0, q, 2.5);
    double k = 400.0, X = e.X0[399] * exp(k * log1p(-q));
    assert_double_rel(X, (2.0 - q) * (1.0 - q) / q, 1e-6);
    assert_true(rel_diff(X, (2.0 - q) / (q * (1.0 - q))) > 0.09);
    exact_free(&e);
}

/* Forward exponential: t_k converges to -M (the exact sum); v(t) law exact;
 * Tables IV and V theory columns; the paper's eq. (57) is off. */
static void check_forward_exponential(double q, double n)
{
    const size_t N = q > 0.1 ? 500 : 1500; /* masses stay above 1e-300 */
    exact e = exact_theory(TAPER_FORWARD_EXPONENTIAL, N, 0, q, n);
    double M = taper_asymptotic_M(q, n), f = taper_asymptotic_f(-q, n);
    assert_true(M < 0.0);
    /* t_k = -M (1 - e^(k eta)) -> -M: the exact sum converges to -M. */
    double eta = taper_asymptotic_eta(-q, n);
    assert_double_rel(e.t[N - 2], -M * -expm1((double)(N - 1) * eta), 1e-11);
    assert_true(e.t[N - 2] / -M > 1.0 - 1e-6);
    for (size_t k = 1; k < N; k++) {
        double tprev = k == 1 ? 0.0 : e.t[k - 2];
        /* 1 + t/M loses digits to cancellation as t -> -M: stop at 1e-4 */
        if (1.0 + tprev / M > 1e-4) assert_double_rel(e.v[k - 1], pow(1.0 + tprev / M, -f), 1e-9);
        assert_double_rel(log(e.v[k] / e.v[k - 1]), -taper_asymptotic_lnA(-q), 1e-9);
    }
    exact_free(&e);
}

static void test_forward_exponential(void **state)
{
    (void)state;
    const double Q[] = {0.01, 0.03, 0.06, 0.5};
    const double expo[] = {2.5, 2.0, 3.0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 3; j++) check_forward_exponential(Q[i], expo[j]);
}

/* Paper's eq. (57), transcribed only to show that it is wrong. */
static double paper_M(double q)
{
    double eta = taper_asymptotic_eta(-q, 2.5);
    return 2.0 * sqrt(M_PI) / (5.0 * eta) * tgamma(1.4) / tgamma(0.9)
           * pow(1.25 * sqrt(1.0 - q / 2.0) / (1.0 + pow(1.0 + q, 3)), 0.4);
}

static void test_paper_M(void **state)
{
    (void)state;
    for (int i = 1; i <= 6; i++) {
        double q = 0.01 * i, M = taper_asymptotic_M(q, 2.5);
        /* The paper's M is ~ 0.4 of the true divergence time ... */
        double ratio = paper_M(q) / M;
        assert_true(ratio > 0.38 && ratio < 0.41);
        /* ... and the continuum estimate T_1/eta(-q) with the right r_1
         * agrees to O(eta): (e^eta - 1)/eta = 1 + eta/2. */
        double eta = taper_asymptotic_eta(-q, 2.5);
        double T1 = taper_theory_collision_time(1.0 / (1.0 + pow(1.0 + q, 3)),
                                                1.0 / sqrt(1.0 + q / 2.0), 1.0, 2.5);
        assert_double_rel(M, T1 / eta / (1.0 + eta / 2.0), eta * eta);
    }
}

/* Forward linear: the exact sum over the longest chain (S = 1/m, N = m)
 * against C (error O(S^2)), C0 (O(S)), and the paper's C0 with (1 + 1/S). */
static double exact_divergence_time(double S, double n, size_t N)
{
    exact e = exact_theory(TAPER_FORWARD_LINEAR, N, S, 0, n);
    double t = e.t[N - 2];
    exact_free(&e);
    return t;
}

static void test_forward_linear_C(void **state)
{
    (void)state;
    const double expo[] = {2.5, 2.0, 3.0, 1.5};
    for (int j = 0; j < 4; j++) {
        for (size_t m = 100; m <= 3200; m *= 2) {
            double S = 1.0 / (double)m, n = expo[j];
            double t = exact_divergence_time(S, n, m);
            assert_double_rel(t, taper_asymptotic_C(S, n), 6.0 * S * S);
            assert_true(rel_diff(t, taper_asymptotic_C0(S, n)) < 0.9 * S); /* |c1| < 0.8 */
            if (n == 2.5) {
                double paper_C0 = taper_asymptotic_C0(S, n) * (1.0 + S);
                /* off by -(1 - 57/130) S = -0.56 S instead of O(S^2) */
                assert_double_abs(t / paper_C0 - 1.0, -(1.0 - 57.0 / 130.0) * S, 6.0 * S * S);
            }
        }
    }
}

/* Divergence laws of the forward linear chain in the range 0.05 < R < 0.5
 * (S = 1e-4, N = 9999): v ~ R^-3/2, C - t ~ R^(23/10), v ~ (1 - t/C)^-15/23. */
static void test_forward_linear_laws(void **state)
{
    (void)state;
    const double S = 1e-4, n = 2.5;
    const size_t N = 9999, i = 5000, j = 9000; /* R = 0.5 ... 0.1 */
    exact e = exact_theory(TAPER_FORWARD_LINEAR, N, S, 0, n);
    double C = e.t[N - 2];
    double *Rk = malloc(N * sizeof(double)), *rem = malloc(N * sizeof(double)),
           *tau = malloc(N * sizeof(double));
    for (size_t m = 0; m + 1 < N; m++) {
        Rk[m] = 1.0 - S * ((double)m + 1.5);   /* midpoint: C - t_k ~ R_{k+1/2}^b1 */
        rem[m] = C - e.t[m];
        tau[m] = 1.0 - (m ? e.t[m - 1] : 0.0) / C; /* 1 - t/C when the pulse reaches k */
    }
    double vR[2] = {e.v[i] * pow(e.R[i], 1.5), e.v[j] * pow(e.R[j], 1.5)};
    assert_double_rel(vR[0], vR[1], 2e-3); /* v R^(3/2) constant */
    assert_double_abs(slope(Rk, rem, i, j), taper_asymptotic_exponent(TAPER_LAW_FWD_T_OF_K, n), 2e-3);
    assert_double_abs(slope(tau, e.v, i, j), taper_asymptotic_exponent(TAPER_LAW_FWD_V_OF_T, n), 2e-3);
    assert_double_rel(C, taper_asymptotic_C(S, n), 1e-7);
    assert_double_rel(taper_asymptotic_forward_linear_b(S), 1.0 / (1.0 + 1.0 / S), 1e-15);
    free(Rk);
    free(rem);
    free(tau);
    exact_free(&e);
}

static void test_domains(void **state)
{
    (void)state;
    assert_true(isnan(taper_asymptotic_A(1.0)));
    assert_true(isnan(taper_asymptotic_A(NAN)));
    assert_true(isnan(taper_asymptotic_lnA(2.0)));
    assert_double_rel(taper_asymptotic_A(0.0), 1.0, 0);
    assert_true(isnan(taper_asymptotic_eta(0.1, 1.0)));
    assert_true(isnan(taper_asymptotic_f(0.0, 2.5)));
    assert_true(isnan(taper_asymptotic_position_exponent(-0.1, 2.5)));
    assert_true(isnan(taper_asymptotic_position_exponent(1.0, 2.5)));
    assert_true(isnan(taper_asymptotic_timescale(0.0, 2.5)));
    assert_true(isnan(taper_asymptotic_M(0.0, 2.5)));
    assert_true(isnan(taper_asymptotic_M(-0.1, 2.5)));
    assert_true(isnan(taper_asymptotic_M(INFINITY, 2.5)));
    assert_true(isnan(taper_asymptotic_C0(0.0, 2.5)));
    assert_true(isnan(taper_asymptotic_C(1.0, 2.5)));
    assert_true(isnan(taper_asymptotic_C(0.1, 0.5)));
    assert_true(isnan(taper_asymptotic_forward_linear_b(NAN)));
    /* the paper's n = 5/2 constants */
    assert_double_rel(taper_asymptotic_C0(0.01, 2.5) * 0.01,
                      10.0 * sqrt(M_PI) / 23.0 * pow(0.625, 0.4) * tgamma(1.4) / tgamma(0.9), 1e-14);
    assert_double_rel(taper_asymptotic_eta(0.03, 2.5),
                      log(pow(taper_asymptotic_A(0.03), 0.2) / 0.97), 1e-12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exponents_values),
        cmocka_unit_test(test_backward_linear),
        cmocka_unit_test(test_backward_exponential),
        cmocka_unit_test(test_position_prefactor),
        cmocka_unit_test(test_forward_exponential),
        cmocka_unit_test(test_paper_M),
        cmocka_unit_test(test_forward_linear_C),
        cmocka_unit_test(test_forward_linear_laws),
        cmocka_unit_test(test_domains),
    };
    return cmocka_run_group_tests_name("asymptotic", tests, NULL, NULL);
}
