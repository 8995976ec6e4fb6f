/*
 * test_fit.c -- least-squares fits (suite 'fit'): exact synthetic data give
 * the parameters back to 1e-10, noisy data give estimates within 3 standard
 * errors whose size falls as 1/sqrt(n), and bad input is an error, never a
 * crash or a print.
 */
#include "test_util.h"

#include "taper.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <stdlib.h>
#include <string.h>

typedef double (*law_fn)(double x, const double *par);

static double power(double x, const double *c) { return c[0] * pow(x, c[1]); }
static double expo(double x, const double *c) { return c[0] * exp(c[1] * x); }
static double div_b(double x, const double *c) { return c[0] * pow(1.0 - c[1] * x, -c[2]); }
static double div_c(double x, const double *c) { return c[0] * pow(1.0 - x / c[1], -c[2]); }
static double div_m(double x, const double *c) { return c[0] * pow(1.0 + x / c[1], -c[2]); }

typedef struct sample {
    double *x, *y;
    size_t n;
} sample;

/* n points of law on [x0, x1], each multiplied by exp(sigma * N(0,1)). */
static sample make_sample(law_fn law, const double *par, double x0, double x1, size_t n,
                          double sigma, gsl_rng *rng)
{
    sample s = {malloc(n * sizeof(double)), malloc(n * sizeof(double)), n};
    for (size_t i = 0; i < n; i++) {
        s.x[i] = x0 + (x1 - x0) * (double)i / (double)(n - 1);
        s.y[i] = law(s.x[i], par) * (sigma > 0 ? exp(sigma * gsl_ran_gaussian(rng, 1.0)) : 1.0);
    }
    return s;
}

static void sample_free(sample *s)
{
    free(s->x);
    free(s->y);
}

typedef struct fit_case {
    int model;
    law_fn law;
    double par[3];
    double x0, x1;
    double p;      /* spec.p (NaN: fitted) */
    size_t n_fit;  /* parameters checked */
} fit_case;

static const fit_case cases[] = {
    {TAPER_FIT_POWER, power, {2.5, -1.3, 0}, 1.0, 50.0, 0, 2},
    {TAPER_FIT_EXPONENTIAL, expo, {0.7, 0.05, 0}, 0.0, 80.0, 0, 2},
    {TAPER_FIT_DIVERGENCE_B, div_b, {1.2, 0.009, 1.5}, 1.0, 100.0, 1.5, 2},
    {TAPER_FIT_DIVERGENCE_C, div_c, {1.1, 40.0, 15.0 / 23.0}, 0.0, 39.0, 15.0 / 23.0, 2},
    {TAPER_FIT_DIVERGENCE_C, div_c, {1.1, 40.0, 15.0 / 23.0}, 0.0, 39.0, NAN, 3},
    {TAPER_FIT_DIVERGENCE_M, div_m, {0.9, 25.0, 1.15}, 0.0, 500.0, 0, 3},
    {TAPER_FIT_DIVERGENCE_M, div_m, {1.0, -30.0, 1.12}, 0.0, 29.5, 0, 3},
};
#define N_CASES (sizeof cases / sizeof cases[0])

static int run(const fit_case *c, const sample *s, taper_fit_result *r)
{
    taper_fit_spec spec;
    taper_fit_spec_init(&spec, c->model);
    if (c->model == TAPER_FIT_DIVERGENCE_B || c->model == TAPER_FIT_DIVERGENCE_C) spec.p = c->p;
    taper_error err;
    int status = taper_fit(&spec, s->x, s->y, s->n, r, &err);
    if (status != TAPER_OK) print_error("fit failed: %s\n", err.message);
    return status;
}

static void test_exact(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_CASES; i++) {
        const fit_case *c = &cases[i];
        sample s = make_sample(c->law, c->par, c->x0, c->x1, 60, 0.0, NULL);
        taper_fit_result r;
        assert_int_equal(run(c, &s, &r), TAPER_OK);
        assert_int_equal(r.n_points, 60);
        assert_int_equal(r.n_params, c->n_fit);
        for (size_t j = 0; j < c->n_fit; j++) assert_double_rel(r.param[j], c->par[j], 1e-10);
        assert_true(r.chi2 < 1e-20);
        sample_free(&s);
    }
}

/* Lognormal noise of 1%: every estimate within 3 standard errors, and 4x the
 * points halves the standard error (within 15%). */
static void test_noisy(void **state)
{
    (void)state;
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    for (size_t i = 0; i < N_CASES; i++) {
        const fit_case *c = &cases[i];
        gsl_rng_set(rng, 12345 + i);
        taper_fit_result r1, r4;
        sample s1 = make_sample(c->law, c->par, c->x0, c->x1, 400, 0.01, rng);
        sample s4 = make_sample(c->law, c->par, c->x0, c->x1, 1600, 0.01, rng);
        assert_int_equal(run(c, &s1, &r1), TAPER_OK);
        assert_int_equal(run(c, &s4, &r4), TAPER_OK);
        for (size_t j = 0; j < c->n_fit; j++) {
            assert_true(r1.param_err[j] > 0.0);
            assert_double_abs(r1.param[j], c->par[j], 3.0 * r1.param_err[j]);
            assert_double_abs(r4.param[j], c->par[j], 3.0 * r4.param_err[j]);
            assert_double_rel(r1.param_err[j] / r4.param_err[j], 2.0, 0.15);
        }
        /* chi2 / dof estimates sigma^2 */
        assert_double_rel(r4.chi2 / (double)(r4.n_points - r4.n_params), 1e-4, 0.15);
        sample_free(&s1);
        sample_free(&s4);
    }
    gsl_rng_free(rng);
}

/* Windows: only the selected points count; garbage outside is ignored. */
static void test_windows(void **state)
{
    (void)state;
    const double par[2] = {3.0, 0.8};
    sample s = make_sample(power, par, 1.0, 100.0, 100, 0.0, NULL);
    for (size_t i = 0; i < 20; i++) s.y[i] = 1e6 * (double)(i + 1); /* off the law */
    taper_fit_spec spec;
    taper_fit_spec_init(&spec, TAPER_FIT_POWER);
    taper_fit_result r;
    spec.index_begin = 20;
    assert_int_equal(taper_fit(&spec, s.x, s.y, s.n, &r, NULL), TAPER_OK);
    assert_int_equal(r.n_points, 80);
    assert_double_rel(r.param[1], 0.8, 1e-12);
    spec.index_begin = 0;
    spec.index_end = 50;
    spec.x_min = s.x[20];
    assert_int_equal(taper_fit(&spec, s.x, s.y, s.n, &r, NULL), TAPER_OK);
    assert_int_equal(r.n_points, 30);
    assert_double_rel(r.param[0], 3.0, 1e-12);
    /* skipped points: NaN, zero and negative y inside the window */
    spec = (taper_fit_spec){0};
    taper_fit_spec_init(&spec, TAPER_FIT_POWER);
    spec.index_begin = 20;
    s.y[30] = NAN;
    s.y[31] = 0.0;
    s.y[32] = -1.0;
    s.x[33] = INFINITY;
    assert_int_equal(taper_fit(&spec, s.x, s.y, s.n, &r, NULL), TAPER_OK);
    assert_int_equal(r.n_points, 76);
    assert_int_equal(r.n_skipped, 4);
    assert_double_rel(r.param[1], 0.8, 1e-12);
    spec.skip_invalid = 0;
    taper_error err;
    assert_int_equal(taper_fit(&spec, s.x, s.y, s.n, &r, &err), TAPER_EINVAL);
    assert_non_null(strstr(err.message, "point 30"));
    assert_true(isnan(r.param[0]) && isnan(r.param_err[1]));
    sample_free(&s);
}

static void expect_einval(const taper_fit_spec *spec, const double *x, const double *y, size_t n,
                          const char *needle)
{
    taper_fit_result r;
    taper_error err = {0};
    assert_int_equal(taper_fit(spec, x, y, n, &r, &err), TAPER_EINVAL);
    assert_int_equal(err.status, TAPER_EINVAL);
    if (!strstr(err.message, needle)) {
        print_error("message '%s' lacks '%s'\n", err.message, needle);
        fail();
    }
}

static void test_bad_input(void **state)
{
    (void)state;
    double x[5] = {1, 2, 3, 4, 5}, y[5] = {1, 2, 3, 4, 5}, flat[5] = {2, 2, 2, 2, 2};
    taper_fit_spec spec;
    taper_fit_result r;
    taper_fit_spec_init(&spec, TAPER_FIT_POWER);
    assert_int_equal(taper_fit(NULL, x, y, 5, &r, NULL), TAPER_EINVAL);
    expect_einval(&spec, NULL, y, 5, "NULL");
    assert_int_equal(taper_fit(&spec, x, y, 5, NULL, NULL), TAPER_EINVAL);
    expect_einval(&spec, x, y, 2, "usable points");      /* too few */
    expect_einval(&spec, x, y, 0, "window");
    expect_einval(&spec, flat, y, 5, "all equal");
    double neg[5] = {-1, -2, 0, 4, 5};
    expect_einval(&spec, neg, y, 5, "usable points");    /* x <= 0 in a log fit */
    spec.index_begin = 4;
    expect_einval(&spec, x, y, 5, "usable points");
    spec.index_end = 3;
    expect_einval(&spec, x, y, 5, "window");
    taper_fit_spec_init(&spec, TAPER_FIT_EXPONENTIAL);
    spec.x_min = 3;
    spec.x_max = 2;
    expect_einval(&spec, x, y, 5, "x window");
    spec.x_max = NAN;
    expect_einval(&spec, x, y, 5, "x window");
    taper_fit_spec_init(&spec, 17);
    expect_einval(&spec, x, y, 5, "model");
    taper_fit_spec_init(&spec, TAPER_FIT_DIVERGENCE_B);
    spec.p = 0.0;
    expect_einval(&spec, x, y, 5, "exponent");
    spec.p = INFINITY;
    expect_einval(&spec, x, y, 5, "exponent");
    taper_fit_spec_init(&spec, TAPER_FIT_DIVERGENCE_M);
    expect_einval(&spec, x, y, 3, "usable points");      /* 3 parameters need 4 */
    spec.xtol = 0.0;
    expect_einval(&spec, x, y, 5, "xtol");
    taper_fit_spec_init(&spec, TAPER_FIT_DIVERGENCE_M);
    spec.max_iter = 0;
    expect_einval(&spec, x, y, 5, "max_iter");
    taper_fit_spec_init(&spec, TAPER_FIT_DIVERGENCE_C);
    expect_einval(&spec, flat, y, 5, "all equal");
}

/* A pure power law has no finite M: one iteration cannot converge. */
static void test_no_convergence(void **state)
{
    (void)state;
    const double par[2] = {1.0, -1.0};
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    sample s = make_sample(power, par, 1.0, 1000.0, 200, 0.05, rng);
    taper_fit_spec spec;
    taper_fit_spec_init(&spec, TAPER_FIT_DIVERGENCE_M);
    spec.max_iter = 1;
    taper_fit_result r;
    taper_error err;
    assert_int_equal(taper_fit(&spec, s.x, s.y, s.n, &r, &err), TAPER_ESOLVER);
    assert_non_null(strstr(err.message, "converge"));
    assert_true(isnan(r.param[0]));
    sample_free(&s);
    gsl_rng_free(rng);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact),
        cmocka_unit_test(test_noisy),
        cmocka_unit_test(test_windows),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_no_convergence),
    };
    return cmocka_run_group_tests_name("fit", tests, NULL, NULL);
}
