/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * fit.c -- least-squares fits of the paper's laws (power law, exponential,
 * and the finite-x divergences of the forward chains, Sec. IV) in ln y.
 *
 * The three divergence forms are one model, y = a (1 - s x)^(-p), with
 * s = b, 1/C or -1/M: fitting s keeps the domain 1 - s x > 0 a single
 * condition and its covariance maps exactly (at the linear order the
 * covariance is defined at) to that of C or M, se(C) = se(s) / s^2.
 *
 * The library never prints or aborts: every argument GSL checks with
 * GSL_ERROR (n >= p, vector sizes) is checked here first, and the solver's
 * own failures come back as status codes.
 */
#include "core/taper_internal.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <math.h>
#include <stdlib.h>
#include <strings.h>

/* A residual larger than any reachable one: a trial step out of the domain
 * 1 - s x > 0 gets it and is rejected by the trust region. */
#define OUT_OF_DOMAIN 1e100

/* The settings of a fit; every value in its range (the setters see to it). */
struct taper_fit_spec {
    taper_fit_model model;
    double p;             /* exponent of DIVERGENCE_B/_C; NaN: fit it (_C)   */
    size_t index_begin;   /* window in indices [begin, end); end 0: all      */
    size_t index_end;
    double x_min, x_max;  /* window in x (inclusive); -inf, +inf: all        */
    int skip_invalid;     /* 1: skip unusable points; 0: they are an error   */
    size_t max_iter;      /* nonlinear iterations                            */
    double xtol;          /* step tolerance                                  */
};

struct taper_fit_result {
    taper_fit_model model;
    size_t n_params;      /* parameters fitted: 2 or 3                       */
    double param[3];      /* (a, b) | (a, b, p) | (a, C, p) | (a, M, f)       */
    double param_err[3];  /* standard errors                                 */
    size_t n_points;      /* points used                                     */
    size_t n_skipped;     /* points in the window skipped as unusable        */
    double chi2;          /* sum of squared residuals of ln y                */
    size_t iterations;    /* nonlinear iterations (0 for linear fits)        */
};

#define MODEL_NAME(constant, name) [constant] = name,
static const char *const model_names[] = {TAPER_FIT_MODEL_LIST(MODEL_NAME)};

const char *taper_fit_model_name(taper_fit_model model)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)model >= TAPER_N_FIT_MODELS) return NULL;
    return model_names[model];
}

taper_status taper_fit_model_from_name(const char *name, taper_fit_model *model, taper_error *err)
{
    if (!model) return taper_fail(err, TAPER_EINVAL, "taper_fit_model_from_name: model is NULL");
    size_t i = 0;
    taper_status st = taper_name_find(name, model_names, TAPER_N_FIT_MODELS, "model", "fit model",
                                      &i, err);
    if (st == TAPER_OK) *model = (taper_fit_model)i;
    return st;
}

taper_fit_spec *taper_fit_spec_alloc(taper_fit_model model, taper_error *err)
{
    if (!taper_fit_model_name(model)) {
        taper_fail_field(err, TAPER_EINVAL, "model", "fit model = %d: unknown model "
                         "(taper_fit_model has %d values)", (int)model, TAPER_N_FIT_MODELS);
        return NULL;
    }
    taper_fit_spec *spec = malloc(sizeof *spec);
    if (!spec) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a fit spec");
        return NULL;
    }
    spec->model = model;
    spec->p = (model == TAPER_FIT_DIVERGENCE_C) ? NAN : 1.5;
    spec->index_begin = 0;
    spec->index_end = 0;
    spec->x_min = -INFINITY;
    spec->x_max = INFINITY;
    spec->skip_invalid = 1;
    spec->max_iter = 200;
    spec->xtol = 1e-12;
    taper_ok(err);
    return spec;
}

void taper_fit_spec_free(taper_fit_spec *spec) { free(spec); }

static taper_status null_spec(taper_error *err, const char *function)
{
    return taper_fail(err, TAPER_EINVAL, "%s: spec is NULL", function);
}

taper_status taper_fit_spec_set_exponent(taper_fit_spec *spec, double p, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (isnan(p) ? spec->model != TAPER_FIT_DIVERGENCE_C : !(p > 0.0 && isfinite(p)))
        return taper_fail_field(err, TAPER_EINVAL, "exponent",
                                "exponent p = %g: a fixed exponent must be finite and > 0 "
                                "(NaN, fitting it, only for divergence_c)", p);
    spec->p = p;
    return taper_ok(err);
}

taper_status taper_fit_spec_set_index_window(taper_fit_spec *spec, size_t begin, size_t end,
                                             taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (end != 0 && !(begin < end))
        return taper_fail_field(err, TAPER_EINVAL, "index_window",
                                "index window [%zu, %zu) is empty", begin, end);
    spec->index_begin = begin;
    spec->index_end = end;
    return taper_ok(err);
}

taper_status taper_fit_spec_set_x_window(taper_fit_spec *spec, double x_min, double x_max,
                                         taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!(x_min <= x_max))
        return taper_fail_field(err, TAPER_EINVAL, "x_window", "x window [%g, %g] is empty",
                                x_min, x_max);
    spec->x_min = x_min;
    spec->x_max = x_max;
    return taper_ok(err);
}

taper_status taper_fit_spec_set_skip_invalid(taper_fit_spec *spec, int skip, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    spec->skip_invalid = skip != 0;
    return taper_ok(err);
}

taper_status taper_fit_spec_set_max_iter(taper_fit_spec *spec, size_t max_iter, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (max_iter < 1)
        return taper_fail_field(err, TAPER_EINVAL, "max_iter", "max_iter = 0: need at least 1 "
                                "iteration");
    spec->max_iter = max_iter;
    return taper_ok(err);
}

taper_status taper_fit_spec_set_xtol(taper_fit_spec *spec, double xtol, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!(xtol > 0.0 && xtol < 1.0))
        return taper_fail_field(err, TAPER_EINVAL, "xtol", "xtol = %g: need 0 < xtol < 1", xtol);
    spec->xtol = xtol;
    return taper_ok(err);
}

taper_fit_model taper_fit_spec_model(const taper_fit_spec *spec)
{
    return spec ? spec->model : (taper_fit_model)-1;
}
double taper_fit_spec_exponent(const taper_fit_spec *spec) { return spec ? spec->p : NAN; }

/* The usable points of the window: X = x (or ln x for the power law),
 * Y = ln y. */
typedef struct points {
    double *X, *Y;
    size_t n, skipped;
} points;

static int usable(const taper_fit_spec *spec, double x, double y)
{
    if (!isfinite(x) || !isfinite(y) || !(y > 0.0)) return 0;
    return spec->model != TAPER_FIT_POWER || x > 0.0;
}

static int select_points(const taper_fit_spec *spec, const double *x, const double *y, size_t n,
                         points *pt, taper_error *err)
{
    size_t end = spec->index_end ? spec->index_end : n;
    pt->X = malloc((end > spec->index_begin ? end - spec->index_begin : 1) * sizeof(double));
    pt->Y = malloc((end > spec->index_begin ? end - spec->index_begin : 1) * sizeof(double));
    pt->n = pt->skipped = 0;
    if (!pt->X || !pt->Y) return taper_fail(err, TAPER_ENOMEM, "fit: cannot allocate %zu points", n);
    for (size_t i = spec->index_begin; i < end; i++) {
        if (!(x[i] >= spec->x_min && x[i] <= spec->x_max) && !isnan(x[i])) continue;
        if (!usable(spec, x[i], y[i])) {
            if (!spec->skip_invalid)
                return taper_fail(err, TAPER_EINVAL,
                                  "fit: point %zu (x = %g, y = %g) is not finite or not positive "
                                  "where a logarithm is taken", i, x[i], y[i]);
            pt->skipped++;
            continue;
        }
        pt->X[pt->n] = spec->model == TAPER_FIT_POWER ? log(x[i]) : x[i];
        pt->Y[pt->n] = log(y[i]);
        pt->n++;
    }
    return TAPER_OK;
}

static size_t n_params_of(const taper_fit_spec *spec)
{
    if (spec->model == TAPER_FIT_DIVERGENCE_M) return 3;
    if (spec->model == TAPER_FIT_DIVERGENCE_C && isnan(spec->p)) return 3;
    return 2;
}

/* What the setters cannot check: the arguments, and the index window
 * against the number of points. */
static taper_status validate(const taper_fit_spec *spec, const double *x, const double *y, size_t n,
                             taper_error *err)
{
    if (!spec || !x || !y)
        return taper_fail(err, TAPER_EINVAL, "taper_fit: spec, x and y must not be NULL");
    size_t end = spec->index_end ? spec->index_end : n;
    if (end > n || spec->index_begin >= end)
        return taper_fail_field(err, TAPER_EINVAL, "index_window", "taper_fit: index window "
                                "[%zu, %zu) is empty or beyond the %zu points",
                                spec->index_begin, end, n);
    return TAPER_OK;
}

/* Ordinary least squares Y = c0 + c1 X with standard errors scaled by the
 * residual variance; TAPER_EINVAL when the X values are all equal. */
typedef struct line {
    double c0, c1, se0, se1, chi2;
} line;

static int fit_line(const double *X, const double *Y, size_t n, line *L, taper_error *err)
{
    double mx = 0.0, my = 0.0, sxx = 0.0, sxy = 0.0, chi2 = 0.0;
    for (size_t i = 0; i < n; i++) {
        mx += X[i];
        my += Y[i];
    }
    mx /= (double)n;
    my /= (double)n;
    for (size_t i = 0; i < n; i++) {
        sxx += (X[i] - mx) * (X[i] - mx);
        sxy += (X[i] - mx) * (Y[i] - my);
    }
    if (!(sxx > 0.0) || !isfinite(sxx))
        return taper_fail(err, TAPER_EINVAL, "fit: the %zu x values are all equal (or overflow): "
                          "no slope can be fitted", n);
    L->c1 = sxy / sxx;
    L->c0 = my - L->c1 * mx;
    for (size_t i = 0; i < n; i++) {
        double r = Y[i] - L->c0 - L->c1 * X[i];
        chi2 += r * r;
    }
    double s2 = n > 2 ? chi2 / (double)(n - 2) : NAN;
    L->chi2 = chi2;
    L->se1 = sqrt(s2 / sxx);
    L->se0 = sqrt(s2 * (1.0 / (double)n + mx * mx / sxx));
    return TAPER_OK;
}

/* ---- divergence model  ln y = la - p ln(1 - s x) ------------------------ */

typedef struct model {
    const points *pt;
    double p;       /* fixed exponent (when n_params == 2) */
    size_t np;      /* 2: (la, s); 3: (la, s, p) */
} model;

static double theta_p(const model *m, const gsl_vector *th)
{
    return m->np == 3 ? gsl_vector_get(th, 2) : m->p;
}

static int model_f(const gsl_vector *th, void *data, gsl_vector *f)
{
    const model *m = data;
    double la = gsl_vector_get(th, 0), s = gsl_vector_get(th, 1), p = theta_p(m, th);
    for (size_t i = 0; i < m->pt->n; i++) {
        double u = 1.0 - s * m->pt->X[i];
        double r = u > 0.0 ? la - p * log(u) - m->pt->Y[i] : NAN;
        if (!isfinite(r)) {
            gsl_vector_set_all(f, OUT_OF_DOMAIN);
            return GSL_SUCCESS;
        }
        gsl_vector_set(f, i, r);
    }
    return GSL_SUCCESS;
}

static int model_df(const gsl_vector *th, void *data, gsl_matrix *J)
{
    const model *m = data;
    double s = gsl_vector_get(th, 1), p = theta_p(m, th);
    for (size_t i = 0; i < m->pt->n; i++) {
        double x = m->pt->X[i], u = 1.0 - s * x;
        gsl_matrix_set(J, i, 0, 1.0);
        gsl_matrix_set(J, i, 1, u > 0.0 ? p * x / u : 0.0);
        if (m->np == 3) gsl_matrix_set(J, i, 2, u > 0.0 ? -log(u) : 0.0);
    }
    return GSL_SUCCESS;
}

static double model_cost(const model *m, double la, double s, double p)
{
    double c = 0.0;
    for (size_t i = 0; i < m->pt->n; i++) {
        double u = 1.0 - s * m->pt->X[i];
        if (!(u > 0.0)) return INFINITY;
        double r = la - p * log(u) - m->pt->Y[i];
        c += r * r;
    }
    return isfinite(c) ? c : INFINITY;
}

/* Linearised start for exponent p: y^(-1/p) = a^(-1/p) (1 - s x) is a line
 * alpha + beta x; exact for exact data.  Returns its cost (INFINITY if the
 * line leaves the domain), filling la and s. */
static double linear_guess(const model *m, double p, double *work, double *la, double *s)
{
    for (size_t i = 0; i < m->pt->n; i++) {
        work[i] = exp(-m->pt->Y[i] / p);
        if (!isfinite(work[i]) || work[i] <= 0.0) return INFINITY;
    }
    line L;
    if (fit_line(m->pt->X, work, m->pt->n, &L, NULL) != TAPER_OK || !(L.c0 > 0.0)) return INFINITY;
    *la = -p * log(L.c0);
    *s = -L.c1 / L.c0;
    return model_cost(m, *la, *s, p);
}

/* Start vector: the linearisation at the fixed p, or the best over a
 * logarithmic scan of p in [0.01, 100] when p is fitted; falls back to the
 * constant y = exp(mean ln y) (s = 0), which is always in the domain. */
static void initial_guess(const model *m, double *work, double th[3])
{
    double best = INFINITY, la, s;
    th[0] = 0.0;
    for (size_t i = 0; i < m->pt->n; i++) th[0] += m->pt->Y[i] / (double)m->pt->n;
    th[1] = 0.0;
    th[2] = m->np == 3 ? 1.0 : m->p;
    if (m->np == 2) {
        if (isfinite(linear_guess(m, m->p, work, &la, &s))) {
            th[0] = la;
            th[1] = s;
        }
        return;
    }
    for (int j = 0; j <= 200; j++) {
        double p = pow(10.0, -2.0 + 0.02 * j);
        double c = linear_guess(m, p, work, &la, &s);
        if (c < best) {
            best = c;
            th[0] = la;
            th[1] = s;
            th[2] = p;
        }
    }
}

/* GSL's convergence measure: max_i |g_i| max(|th_i|, 1) / max(chi2/2, 1).
 * Used to accept a start that no step can improve (exact data). */
static double scaled_gradient(gsl_multifit_nlinear_workspace *w)
{
    gsl_vector *f = gsl_multifit_nlinear_residual(w), *th = gsl_multifit_nlinear_position(w);
    gsl_matrix *J = gsl_multifit_nlinear_jac(w);
    double chi2, gmax = 0.0;
    gsl_blas_ddot(f, f, &chi2);
    for (size_t j = 0; j < J->size2; j++) {
        double g = 0.0;
        for (size_t i = 0; i < J->size1; i++) g += gsl_matrix_get(J, i, j) * gsl_vector_get(f, i);
        gmax = fmax(gmax, fabs(g) * fmax(fabs(gsl_vector_get(th, j)), 1.0));
    }
    return gmax / fmax(0.5 * chi2, 1.0);
}

typedef struct nl_out {
    double th[3], se[3], chi2;
    size_t iterations;
} nl_out;

/* Runs the trust-region solver from th0 and extracts parameters, chi2 and
 * standard errors.  Workspace and vectors are sized from m, so GSL's size
 * checks cannot fail. */
static int run_solver(const model *m, const double th0[3], const taper_fit_spec *spec, nl_out *out,
                      taper_error *err)
{
    const size_t n = m->pt->n, np = m->np;
    gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
    /* The covariance and start vector are views of stack arrays: a failed
     * gsl_*_alloc would call GSL's error handler (abort) before returning
     * NULL.  The workspace (O(n np) doubles, the size of the points we
     * already hold) is the one allocation left to GSL. */
    double cov_data[9], th_data[3];
    gsl_matrix_view cov_view = gsl_matrix_view_array(cov_data, np, np);
    gsl_vector_view th_view = gsl_vector_view_array(th_data, np);
    gsl_matrix *cov = &cov_view.matrix;
    gsl_vector *th = &th_view.vector;
    gsl_multifit_nlinear_workspace *w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, n, np);
    if (!w) return taper_fail(err, TAPER_ENOMEM, "fit: cannot allocate the nonlinear solver");
    for (size_t j = 0; j < np; j++) gsl_vector_set(th, j, th0[j]);
    gsl_multifit_nlinear_fdf fdf = {model_f, model_df, NULL, n, np, (void *)m, 0, 0, 0};
    int info = 0, status = gsl_multifit_nlinear_init(th, &fdf, w);
    if (status == GSL_SUCCESS)
        status = gsl_multifit_nlinear_driver(spec->max_iter, spec->xtol, 1e-14, 1e-15, NULL, NULL,
                                             &info, w);
    gsl_vector *f = gsl_multifit_nlinear_residual(w);
    gsl_blas_ddot(f, f, &out->chi2);
    if (status != GSL_SUCCESS && !(out->chi2 < OUT_OF_DOMAIN && scaled_gradient(w) < 1e-10))
        status = taper_fail(err, TAPER_ESOLVER, "fit: the nonlinear fit did not converge after %zu "
                            "iterations (%s)", gsl_multifit_nlinear_niter(w), gsl_strerror(status));
    else if (!(out->chi2 < OUT_OF_DOMAIN))
        status = taper_fail(err, TAPER_ESOLVER, "fit: the nonlinear fit left the model's domain");
    else
        status = TAPER_OK;
    if (status == TAPER_OK) {
        gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(w), 0.0, cov);
        double s2 = out->chi2 / (double)(n - np);
        for (size_t j = 0; j < np; j++) {
            out->th[j] = gsl_vector_get(gsl_multifit_nlinear_position(w), j);
            out->se[j] = sqrt(gsl_matrix_get(cov, j, j) * s2);
        }
        out->iterations = gsl_multifit_nlinear_niter(w);
    }
    gsl_multifit_nlinear_free(w);
    return status;
}

/* ---- assembling results -------------------------------------------------- */

static void result_reset(taper_fit_result *r, taper_fit_model which, size_t np)
{
    r->model = which;
    r->n_params = np;
    for (int j = 0; j < 3; j++) r->param[j] = r->param_err[j] = NAN;
    r->n_points = r->n_skipped = 0;
    r->chi2 = NAN;
    r->iterations = 0;
}

static int fit_linear_model(const points *pt, taper_fit_result *r, taper_error *err)
{
    line L;
    int status = fit_line(pt->X, pt->Y, pt->n, &L, err);
    if (status != TAPER_OK) return status;
    r->param[0] = exp(L.c0);
    r->param_err[0] = r->param[0] * L.se0; /* delta method from ln a */
    r->param[1] = L.c1;
    r->param_err[1] = L.se1;
    r->chi2 = L.chi2;
    return TAPER_OK;
}

static int fit_divergence(const taper_fit_spec *spec, const points *pt, taper_fit_result *r,
                          taper_error *err)
{
    model m = {pt, spec->p, r->n_params};
    double *work = malloc(pt->n * sizeof(double)), th0[3];
    if (!work) return taper_fail(err, TAPER_ENOMEM, "fit: cannot allocate %zu points", pt->n);
    line L;
    int status = fit_line(pt->X, pt->Y, pt->n, &L, err); /* x must vary */
    if (status == TAPER_OK) initial_guess(&m, work, th0);
    free(work);
    nl_out o;
    if (status == TAPER_OK) status = run_solver(&m, th0, spec, &o, err);
    if (status != TAPER_OK) return status;
    double s = o.th[1];
    r->param[0] = exp(o.th[0]);
    r->param_err[0] = r->param[0] * o.se[0];
    r->param[2] = m.np == 3 ? o.th[2] : spec->p;
    r->param_err[2] = m.np == 3 ? o.se[2] : 0.0;
    if (spec->model == TAPER_FIT_DIVERGENCE_B) {
        r->param[1] = s;
        r->param_err[1] = o.se[1];
    } else { /* C = 1/s, M = -1/s; se = se(s)/s^2 */
        r->param[1] = (spec->model == TAPER_FIT_DIVERGENCE_C ? 1.0 : -1.0) / s;
        r->param_err[1] = o.se[1] / (s * s);
    }
    r->chi2 = o.chi2;
    r->iterations = o.iterations;
    return TAPER_OK;
}

taper_fit_result *taper_fit(const taper_fit_spec *spec, const double *x, const double *y,
                            size_t n, taper_error *err)
{
    if (validate(spec, x, y, n, err) != TAPER_OK) return NULL;
    taper_fit_result *result = malloc(sizeof *result);
    if (!result) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a fit result");
        return NULL;
    }
    size_t np = n_params_of(spec);
    result_reset(result, spec->model, np);
    points pt = {0};
    int status = select_points(spec, x, y, n, &pt, err);
    if (status == TAPER_OK && pt.n < np + 1)
        status = taper_fail(err, TAPER_EINVAL, "fit: %zu usable points in the window (%zu skipped); "
                            "%zu parameters need at least %zu", pt.n, pt.skipped, np, np + 1);
    if (status == TAPER_OK) {
        result->n_points = pt.n;
        result->n_skipped = pt.skipped;
        status = (spec->model <= TAPER_FIT_EXPONENTIAL) ? fit_linear_model(&pt, result, err)
                                                        : fit_divergence(spec, &pt, result, err);
    }
    free(pt.X);
    free(pt.Y);
    if (status != TAPER_OK) {
        free(result);
        return NULL;
    }
    taper_ok(err);
    return result;
}

void taper_fit_result_free(taper_fit_result *result) { free(result); }

taper_fit_model taper_fit_result_model(const taper_fit_result *result)
{
    return result ? result->model : (taper_fit_model)-1;
}
size_t taper_fit_result_n_params(const taper_fit_result *result)
{
    return result ? result->n_params : 0;
}
double taper_fit_result_param(const taper_fit_result *result, size_t i)
{
    return result && i < 3 ? result->param[i] : NAN;
}
double taper_fit_result_param_error(const taper_fit_result *result, size_t i)
{
    return result && i < 3 ? result->param_err[i] : NAN;
}
size_t taper_fit_result_n_points(const taper_fit_result *result)
{
    return result ? result->n_points : 0;
}
size_t taper_fit_result_n_skipped(const taper_fit_result *result)
{
    return result ? result->n_skipped : 0;
}
double taper_fit_result_chi2(const taper_fit_result *result) { return result ? result->chi2 : NAN; }
size_t taper_fit_result_iterations(const taper_fit_result *result)
{
    return result ? result->iterations : 0;
}
