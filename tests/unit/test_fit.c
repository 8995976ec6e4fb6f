/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_fit.c -- least-squares fits (suite 'fit'): exact synthetic data give
 * the parameters back to 1e-10, noisy data give estimates within 3 standard
 * errors whose size falls as 1/sqrt(n), and bad input is an error, never a
 * crash or a print: a bad setting is refused by its setter (naming it, the
 * spec unchanged), bad data by taper_fit.
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
    taper_fit_model model;
    law_fn law;
    double par[3];
    double x0, x1;
    double p;      /* fixed exponent (NaN: fitted) */
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

/* What a fit gave, read through the result's getters (status != TAPER_OK:
 * no result, everything NaN or 0). */
typedef struct outcome {
    taper_status status;
    taper_fit_model model;
    size_t n_params, n_points, n_skipped, iterations;
    double param[3], param_err[3], chi2;
} outcome;

static outcome fit(const taper_fit_spec *spec, const double *x, const double *y, size_t n,
                   taper_error *err)
{
    taper_error local;
    if (!err) err = &local;
    outcome o;
    memset(&o, 0, sizeof o);
    taper_fit_result *r = taper_fit(spec, x, y, n, err);
    o.status = r ? TAPER_OK : err->status;
    if (r) assert_int_equal(err->status, TAPER_OK);
    else assert_int_not_equal(err->status, TAPER_OK);
    o.model = taper_fit_result_model(r);
    o.n_params = taper_fit_result_n_params(r);
    o.n_points = taper_fit_result_n_points(r);
    o.n_skipped = taper_fit_result_n_skipped(r);
    o.iterations = taper_fit_result_iterations(r);
    o.chi2 = taper_fit_result_chi2(r);
    for (size_t j = 0; j < 3; j++) {
        o.param[j] = taper_fit_result_param(r, j);
        o.param_err[j] = taper_fit_result_param_error(r, j);
    }
    taper_fit_result_free(r);
    return o;
}

/* A spec of `model`; fails the test if it cannot be had. */
static taper_fit_spec *spec_of(taper_fit_model model)
{
    taper_error err;
    taper_fit_spec *spec = taper_fit_spec_alloc(model, &err);
    if (!spec) print_error("taper_fit_spec_alloc: %s\n", err.message);
    assert_non_null(spec);
    return spec;
}

static taper_status run(const fit_case *c, const sample *s, outcome *r)
{
    taper_fit_spec *spec = spec_of(c->model);
    taper_error err;
    if (c->model == TAPER_FIT_DIVERGENCE_B || c->model == TAPER_FIT_DIVERGENCE_C)
        assert_int_equal(taper_fit_spec_set_exponent(spec, c->p, &err), TAPER_OK);
    *r = fit(spec, s->x, s->y, s->n, &err);
    if (r->status != TAPER_OK) print_error("fit failed: %s\n", err.message);
    taper_fit_spec_free(spec);
    return r->status;
}

static void test_exact(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_CASES; i++) {
        const fit_case *c = &cases[i];
        sample s = make_sample(c->law, c->par, c->x0, c->x1, 60, 0.0, NULL);
        outcome r;
        assert_int_equal(run(c, &s, &r), TAPER_OK);
        assert_int_equal(r.model, c->model);
        assert_int_equal(r.n_points, 60);
        assert_int_equal(r.n_params, c->n_fit);
        for (size_t j = 0; j < c->n_fit; j++) assert_double_rel(r.param[j], c->par[j], 1e-10);
        assert_true(r.chi2 < 1e-20);
        /* Linear models take no iterations; nonlinear ones at least one
         * unless the start is already the solution. */
        if (c->model <= TAPER_FIT_EXPONENTIAL) assert_int_equal(r.iterations, 0);
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
        outcome r1, r4;
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
    taper_fit_spec *spec = spec_of(TAPER_FIT_POWER);
    outcome r;
    assert_int_equal(taper_fit_spec_set_index_window(spec, 20, 0, NULL), TAPER_OK);
    r = fit(spec, s.x, s.y, s.n, NULL);
    assert_int_equal(r.status, TAPER_OK);
    assert_int_equal(r.n_points, 80);
    assert_double_rel(r.param[1], 0.8, 1e-12);
    assert_int_equal(taper_fit_spec_set_index_window(spec, 0, 50, NULL), TAPER_OK);
    assert_int_equal(taper_fit_spec_set_x_window(spec, s.x[20], INFINITY, NULL), TAPER_OK);
    r = fit(spec, s.x, s.y, s.n, NULL);
    assert_int_equal(r.status, TAPER_OK);
    assert_int_equal(r.n_points, 30);
    assert_double_rel(r.param[0], 3.0, 1e-12);
    taper_fit_spec_free(spec);
    /* skipped points: NaN, zero and negative y inside the window */
    spec = spec_of(TAPER_FIT_POWER);
    assert_int_equal(taper_fit_spec_set_index_window(spec, 20, 0, NULL), TAPER_OK);
    s.y[30] = NAN;
    s.y[31] = 0.0;
    s.y[32] = -1.0;
    s.x[33] = INFINITY;
    r = fit(spec, s.x, s.y, s.n, NULL);
    assert_int_equal(r.status, TAPER_OK);
    assert_int_equal(r.n_points, 76);
    assert_int_equal(r.n_skipped, 4);
    assert_double_rel(r.param[1], 0.8, 1e-12);
    assert_int_equal(taper_fit_spec_set_skip_invalid(spec, 0, NULL), TAPER_OK);
    taper_error err;
    r = fit(spec, s.x, s.y, s.n, &err);
    assert_int_equal(r.status, TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, NULL, "point 30");
    assert_true(isnan(r.param[0]) && isnan(r.param_err[1]));
    taper_fit_spec_free(spec);
    sample_free(&s);
}

static void expect_einval(const taper_fit_spec *spec, const double *x, const double *y, size_t n,
                          const char *field, const char *needle)
{
    taper_error err = {0};
    assert_null(taper_fit(spec, x, y, n, &err));
    assert_taper_error(err, TAPER_EINVAL, field, needle);
}

/* Bad data and settings that need the data to be judged: refused by
 * taper_fit. */
static void test_bad_input(void **state)
{
    (void)state;
    double x[5] = {1, 2, 3, 4, 5}, y[5] = {1, 2, 3, 4, 5}, flat[5] = {2, 2, 2, 2, 2};
    taper_fit_spec *spec = spec_of(TAPER_FIT_POWER);
    assert_null(taper_fit(NULL, x, y, 5, NULL));
    expect_einval(NULL, x, y, 5, NULL, "NULL");
    expect_einval(spec, NULL, y, 5, NULL, "NULL");
    expect_einval(spec, x, NULL, 5, NULL, "NULL");
    expect_einval(spec, x, y, 2, NULL, "usable points");      /* too few */
    expect_einval(spec, x, y, 0, "index_window", "window");
    expect_einval(spec, flat, y, 5, NULL, "all equal");
    double neg[5] = {-1, -2, 0, 4, 5};
    expect_einval(spec, neg, y, 5, NULL, "usable points");    /* x <= 0 in a log fit */
    assert_int_equal(taper_fit_spec_set_index_window(spec, 4, 0, NULL), TAPER_OK);
    expect_einval(spec, x, y, 5, NULL, "usable points");
    expect_einval(spec, x, y, 4, "index_window", "beyond");   /* begin 4 of 4 points */
    assert_int_equal(taper_fit_spec_set_index_window(spec, 0, 6, NULL), TAPER_OK);
    expect_einval(spec, x, y, 5, "index_window", "beyond the 5 points");
    taper_fit_spec_free(spec);
    spec = spec_of(TAPER_FIT_DIVERGENCE_M);
    expect_einval(spec, x, y, 3, NULL, "usable points");      /* 3 parameters need 4 */
    taper_fit_spec_free(spec);
    spec = spec_of(TAPER_FIT_DIVERGENCE_C);
    expect_einval(spec, flat, y, 5, NULL, "all equal");
    taper_fit_spec_free(spec);
}

/* A setter that refuses its value names it in err->field and changes
 * nothing: the spec's getters and a fit with it give what they gave. */
#define EXPECT_REFUSED(model_, call, field, needle)                                     \
    do {                                                                                \
        taper_fit_spec *spec = spec_of(model_);                                         \
        double p_ = taper_fit_spec_exponent(spec);                                      \
        outcome before = fit(spec, sx, sy, 40, NULL);                                   \
        taper_error err;                                                                \
        memset(&err, 0, sizeof err);                                                    \
        assert_int_equal((call), TAPER_EINVAL);                                         \
        assert_taper_error(err, TAPER_EINVAL, field, needle);                           \
        assert_int_equal(taper_fit_spec_model(spec), (model_));                         \
        assert_memory_equal(&p_, &(double){taper_fit_spec_exponent(spec)}, sizeof p_); \
        outcome after = fit(spec, sx, sy, 40, NULL);                                    \
        assert_int_equal(before.status, TAPER_OK);                                      \
        assert_memory_equal(&before, &after, sizeof before);                            \
        taper_fit_spec_free(spec);                                                      \
    } while (0)

static void test_setters(void **state)
{
    (void)state;
    /* 40 points of a divergence every model can fit. */
    double sx[40], sy[40];
    const double par[3] = {1.1, 60.0, 0.5};
    for (size_t i = 0; i < 40; i++) {
        sx[i] = 1.0 + (double)i;
        sy[i] = div_c(sx[i], par) * (1.0 + 1e-3 * sin((double)i));
    }
    const taper_fit_model all[] = {TAPER_FIT_POWER, TAPER_FIT_EXPONENTIAL, TAPER_FIT_DIVERGENCE_B,
                                   TAPER_FIT_DIVERGENCE_C, TAPER_FIT_DIVERGENCE_M};
    for (size_t m = 0; m < 5; m++) {
        taper_fit_model model = all[m];
        EXPECT_REFUSED(model, taper_fit_spec_set_exponent(spec, 0.0, &err), "exponent", "p = 0");
        EXPECT_REFUSED(model, taper_fit_spec_set_exponent(spec, -1.5, &err), "exponent", "p = -1.5");
        EXPECT_REFUSED(model, taper_fit_spec_set_exponent(spec, INFINITY, &err), "exponent", "p = inf");
        EXPECT_REFUSED(model, taper_fit_spec_set_index_window(spec, 3, 3, &err), "index_window",
                       "[3, 3)");
        EXPECT_REFUSED(model, taper_fit_spec_set_index_window(spec, 5, 2, &err), "index_window",
                       "empty");
        EXPECT_REFUSED(model, taper_fit_spec_set_x_window(spec, 3, 2, &err), "x_window", "x window");
        EXPECT_REFUSED(model, taper_fit_spec_set_x_window(spec, 0, NAN, &err), "x_window", "x window");
        EXPECT_REFUSED(model, taper_fit_spec_set_x_window(spec, NAN, 1, &err), "x_window", "x window");
        EXPECT_REFUSED(model, taper_fit_spec_set_max_iter(spec, 0, &err), "max_iter", "max_iter");
        EXPECT_REFUSED(model, taper_fit_spec_set_xtol(spec, 0.0, &err), "xtol", "xtol");
        EXPECT_REFUSED(model, taper_fit_spec_set_xtol(spec, 1.0, &err), "xtol", "xtol");
        EXPECT_REFUSED(model, taper_fit_spec_set_xtol(spec, NAN, &err), "xtol", "xtol");
        /* A fitted exponent (NaN) only for divergence_c. */
        if (model != TAPER_FIT_DIVERGENCE_C)
            EXPECT_REFUSED(model, taper_fit_spec_set_exponent(spec, NAN, &err), "exponent",
                           "divergence_c");
    }
    /* Defaults and the exponent getter. */
    taper_fit_spec *spec = spec_of(TAPER_FIT_DIVERGENCE_B);
    assert_int_equal(taper_fit_spec_model(spec), TAPER_FIT_DIVERGENCE_B);
    assert_double_rel(taper_fit_spec_exponent(spec), 1.5, 0);
    assert_int_equal(taper_fit_spec_set_exponent(spec, 2.0, NULL), TAPER_OK);
    assert_double_rel(taper_fit_spec_exponent(spec), 2.0, 0);
    taper_fit_spec_free(spec);
    spec = spec_of(TAPER_FIT_DIVERGENCE_C);
    assert_true(isnan(taper_fit_spec_exponent(spec)));
    outcome r = fit(spec, sx, sy, 40, NULL);
    assert_int_equal(r.n_params, 3);
    assert_int_equal(taper_fit_spec_set_exponent(spec, 0.5, NULL), TAPER_OK);
    r = fit(spec, sx, sy, 40, NULL);
    assert_int_equal(r.n_params, 2);
    assert_double_rel(r.param[2], 0.5, 0);
    assert_double_abs(r.param_err[2], 0.0, 0);   /* a fixed exponent has error 0 */
    assert_int_equal(taper_fit_spec_set_exponent(spec, NAN, NULL), TAPER_OK);
    assert_true(isnan(taper_fit_spec_exponent(spec)));
    /* The other setters accept their ranges, and skip_invalid any int. */
    taper_error err;
    assert_int_equal(taper_fit_spec_set_index_window(spec, 0, 0, &err), TAPER_OK);
    assert_null(err.field);
    assert_int_equal(taper_fit_spec_set_index_window(spec, 7, 8, &err), TAPER_OK);
    assert_int_equal(taper_fit_spec_set_x_window(spec, -INFINITY, INFINITY, &err), TAPER_OK);
    assert_int_equal(taper_fit_spec_set_x_window(spec, 2, 2, &err), TAPER_OK);
    assert_int_equal(taper_fit_spec_set_skip_invalid(spec, 42, &err), TAPER_OK);
    assert_int_equal(taper_fit_spec_set_max_iter(spec, 1, &err), TAPER_OK);
    assert_int_equal(taper_fit_spec_set_xtol(spec, 0.5, &err), TAPER_OK);
    taper_fit_spec_free(spec);
    taper_fit_spec_free(NULL);
    /* Unknown models: no spec, field "model". */
    assert_null(taper_fit_spec_alloc((taper_fit_model)17, &err));
    assert_taper_error(err, TAPER_EINVAL, "model", "17");
    assert_null(taper_fit_spec_alloc((taper_fit_model)-1, &err));
    assert_taper_error(err, TAPER_EINVAL, "model", NULL);
    /* NULL specs. */
    assert_int_equal(taper_fit_spec_set_xtol(NULL, 0.5, &err), TAPER_EINVAL);
    assert_null(err.field);
    assert_true(isnan(taper_fit_spec_exponent(NULL)));
    assert_null(taper_fit_model_name(taper_fit_spec_model(NULL)));
}

/* Result getters: NaN past the third parameter; neutral for NULL. */
static void test_result_getters(void **state)
{
    (void)state;
    const double par[2] = {2.0, 0.5};
    sample s = make_sample(power, par, 1.0, 10.0, 10, 0.0, NULL);
    taper_fit_spec *spec = spec_of(TAPER_FIT_POWER);
    taper_fit_result *r = taper_fit(spec, s.x, s.y, s.n, NULL);
    assert_non_null(r);
    assert_int_equal(taper_fit_result_model(r), TAPER_FIT_POWER);
    assert_int_equal(taper_fit_result_n_params(r), 2);
    assert_double_rel(taper_fit_result_param(r, 0), 2.0, 1e-12);
    assert_double_rel(taper_fit_result_param(r, 1), 0.5, 1e-12);
    assert_true(isnan(taper_fit_result_param(r, 2)));       /* a power law has two */
    for (size_t i = 3; i < 6; i++) {
        assert_true(isnan(taper_fit_result_param(r, i)));
        assert_true(isnan(taper_fit_result_param_error(r, i)));
    }
    assert_true(isnan(taper_fit_result_param(r, (size_t)-1)));
    assert_int_equal(taper_fit_result_n_points(r), 10);
    assert_int_equal(taper_fit_result_n_skipped(r), 0);
    assert_int_equal(taper_fit_result_iterations(r), 0);
    assert_true(taper_fit_result_chi2(r) < 1e-20);
    taper_fit_result_free(r);
    taper_fit_result_free(NULL);
    assert_true(isnan(taper_fit_result_param(NULL, 0)));
    assert_true(isnan(taper_fit_result_param_error(NULL, 0)));
    assert_true(isnan(taper_fit_result_chi2(NULL)));
    assert_int_equal(taper_fit_result_n_params(NULL), 0);
    assert_int_equal(taper_fit_result_n_points(NULL), 0);
    assert_null(taper_fit_model_name(taper_fit_result_model(NULL)));
    taper_fit_spec_free(spec);
    sample_free(&s);
}

/* The one list of model names, and its inverse. */
static void test_model_names(void **state)
{
    (void)state;
    const char *names[] = {"power", "exponential", "divergence_b", "divergence_c", "divergence_m"};
    size_t count = 0;
    for (unsigned i = 0; taper_fit_model_name((taper_fit_model)i); i++) {
        assert_string_equal(taper_fit_model_name((taper_fit_model)i), names[i]);
        taper_fit_model m = (taper_fit_model)-1;
        taper_error err;
        assert_int_equal(taper_fit_model_from_name(names[i], &m, &err), TAPER_OK);
        assert_int_equal(m, i);
        assert_null(err.field);
        count++;
    }
    assert_int_equal(count, TAPER_N_FIT_MODELS);
    taper_fit_model m = TAPER_FIT_POWER;
    assert_int_equal(taper_fit_model_from_name("Divergence_C", &m, NULL), TAPER_OK);
    assert_int_equal(m, TAPER_FIT_DIVERGENCE_C);
    taper_error err;
    assert_int_equal(taper_fit_model_from_name("linear", &m, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "model", "'linear'");
    assert_non_null(strstr(err.message, "'divergence_m'"));
    assert_int_equal(m, TAPER_FIT_DIVERGENCE_C);
    assert_int_equal(taper_fit_model_from_name(NULL, &m, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "model", NULL);
    assert_int_equal(taper_fit_model_from_name("power", NULL, &err), TAPER_EINVAL);
    assert_null(taper_fit_model_name((taper_fit_model)TAPER_N_FIT_MODELS));
    assert_null(taper_fit_model_name((taper_fit_model)-1));
}

/* A pure power law has no finite M: one iteration cannot converge. */
static void test_no_convergence(void **state)
{
    (void)state;
    const double par[2] = {1.0, -1.0};
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    sample s = make_sample(power, par, 1.0, 1000.0, 200, 0.05, rng);
    taper_fit_spec *spec = spec_of(TAPER_FIT_DIVERGENCE_M);
    assert_int_equal(taper_fit_spec_set_max_iter(spec, 1, NULL), TAPER_OK);
    taper_error err;
    assert_null(taper_fit(spec, s.x, s.y, s.n, &err));
    assert_taper_error(err, TAPER_ESOLVER, NULL, "converge");
    taper_fit_spec_free(spec);
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
        cmocka_unit_test(test_setters),
        cmocka_unit_test(test_result_getters),
        cmocka_unit_test(test_model_names),
        cmocka_unit_test(test_no_convergence),
    };
    return cmocka_run_group_tests_name("fit", tests, NULL, NULL);
}
