/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * calibrate.c -- nonlinear least squares over runs of a scene
 * (calibrate.h).
 */
#include "optimise/calibrate.h"

#include "util/text.h"

#include <float.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A residual for a point outside the domain (a trial the library refuses,
 * a run that fails): larger than any a run gives, finite, so that the
 * trust region rejects the step (as src/analysis/fit.c does). */
#define OUT_OF_DOMAIN 1e50

/* A setting within this fraction of its size from a bound is at it. */
#define AT_BOUND 1e-4

/* ---- the setting's scaled variable y and the solver's u ------------------------------ */

typedef struct scaled {
    double size;          /* theta = size * y                                */
    double lo, hi;        /* bounds of y                                     */
} scaled;

static double y_of_u(const scaled *s, double u)
{
    int lo = isfinite(s->lo), hi = isfinite(s->hi);
    if (lo && hi) return s->lo + (s->hi - s->lo) * 0.5 * (1.0 + sin(u));
    if (lo) return s->lo - 1.0 + sqrt(u * u + 1.0);
    if (hi) return s->hi + 1.0 - sqrt(u * u + 1.0);
    return u;
}

static double dy_du(const scaled *s, double u)
{
    int lo = isfinite(s->lo), hi = isfinite(s->hi);
    if (lo && hi) return (s->hi - s->lo) * 0.5 * cos(u);
    if (lo) return u / sqrt(u * u + 1.0);
    if (hi) return -u / sqrt(u * u + 1.0);
    return 1.0;
}

static double u_of_y(const scaled *s, double y)
{
    int lo = isfinite(s->lo), hi = isfinite(s->hi);
    if (lo && hi) {
        double z = 2.0 * (y - s->lo) / (s->hi - s->lo) - 1.0;
        return asin(z > 1 ? 1 : z < -1 ? -1 : z);
    }
    if (lo) {
        double a = y - s->lo + 1.0;
        return sqrt(a * a - 1.0 > 0 ? a * a - 1.0 : 0.0);
    }
    if (hi) {
        double a = s->hi - y + 1.0;
        return sqrt(a * a - 1.0 > 0 ? a * a - 1.0 : 0.0);
    }
    return y;
}

/* ---- the calibration's data and settings --------------------------------------------- */

void calibration_free(calibration *c)
{
    if (!c) return;
    opt_plan_free(&c->plan);
    meas_free(c->data);
    opt_space_free(c->space);
    free(c->data_path);
    free(c->w);
    free(c->reason);
    free(c->value);
    free(c->error);
    free(c->correlation);
    free(c->at_bound);
    free(c->fitted);
    free(c);
}

static void set_error(opt_error *e, const char *keyword, char *message)
{
    free(e->message);
    e->message = message ? message : text_dup("out of memory");
    e->keyword = keyword;
}

/* The data's path as the scene means it: relative to the scene file's
 * folder (as radii_file). */
static char *resolve_path(const scene *sc, const char *path)
{
    const char *sp = scene_path(sc), *slash = strrchr(sp, '/');
    if (path[0] == '/' || !slash || strcmp(sp, "stdin") == 0) return text_dup(path);
    return text_printf("%.*s/%s", (int)(slash - sp), sp, path);
}

/* The residuals' factors: noise, weights, or each column's peak. */
static int weights(calibration *c, opt_error *e)
{
    const scene_calibrate_config *k = &scene_cfg(c->sc)->calibrate;
    const measurements *m = c->data;
    if (k->noise.n && k->weights.n) {
        set_error(e, "calibrate_weights", text_printf("give noise or weights, not both (noise "
                  "makes the standard errors absolute; weights only balance the columns)"));
        return -1;
    }
    const scene_reals *given = k->noise.n ? &k->noise : &k->weights;
    const char *key = k->noise.n ? "calibrate_noise" : "calibrate_weights";
    if (given->n && given->n != 1 && given->n != m->n_quantities) {
        set_error(e, key, text_printf("%zu values for %zu fitted columns: give one per column, "
                  "in the data's order, or one for all", given->n, m->n_quantities));
        return -1;
    }
    double factor[MEAS_N_QUANTITIES];
    for (size_t i = 0; i < m->n_quantities; i++) {
        meas_quantity q = m->quantity[i];
        double g = given->n ? given->v[given->n == 1 ? 0 : i] : 1.0;
        if (!k->noise.n && !(m->peak[q] > 0)) {
            set_error(e, "calibrate_data", text_printf("%s: column %s is zero throughout: give "
                      "its noise (&calibrate noise) to fit it", m->path, meas_quantity_name(q)));
            return -1;
        }
        factor[q] = k->noise.n ? 1.0 / g : sqrt(g) / m->peak[q];
    }
    if (!(c->w = malloc(m->n * sizeof *c->w))) return -1;
    for (size_t i = 0; i < m->n; i++) c->w[i] = factor[m->points[i].q];
    c->absolute = k->noise.n > 0;
    return 0;
}

calibration *calibration_new(const scene *sc, opt_error *e)
{
    const scene_config *cfg = scene_cfg(sc);
    e->message = NULL;
    e->keyword = NULL;
    calibration *c = calloc(1, sizeof *c);
    if (!c) goto nomem;
    c->sc = sc;
    c->rtol = scene_setting(cfg, "rtol");
    if (!(c->space = opt_space_new(sc, "calibrate", e))) goto fail;
    if (!(c->data_path = resolve_path(sc, cfg->calibrate.data))) goto nomem;
    char *msg = NULL;
    if (!(c->data = meas_read(c->data_path, cfg->calibrate.columns, &msg))) {
        set_error(e, strncmp(msg ? msg : "", "columns:", 8) == 0 ? "calibrate_columns"
                                                                  : "calibrate_data", msg);
        goto fail;
    }
    if (c->data->si && !cfg->material.on) {
        set_error(e, "calibrate_data", text_printf("%s is in SI units (its header: %s...), and "
                  "the scene has no &material: give &material young, poisson, density, radius, "
                  "velocity, or a table in rescaled units (no units in the header)", c->data_path,
                  meas_quantity_name(c->data->quantity[0])));
        goto fail;
    }
    /* What the data need of the chain and the run, in the data's units. */
    scene_config at;
    scene_config_at(cfg, 0, &at);
    double to_data = 1.0; /* a time as the scene gives it -> the data's unit */
    if (cfg->material.on && !c->data->si) to_data = 1.0 / scene_input_scale(&at, TAPER_DIM_TIME);
    meas_run_limits lim = {
        .n_granules = (size_t)scene_setting(cfg, "n_granules"),
        .wall_left = scene_setting(cfg, "left") == TAPER_END_WALL,
        .wall_right = scene_setting(cfg, "right") == TAPER_END_WALL,
        .t_end = scene_setting(cfg, "t_end") * to_data,
        .t_max = scene_setting(cfg, "t_max") * to_data,
    };
    if (meas_check(c->data, &lim, &msg) != 0) {
        set_error(e, "calibrate_data", msg);
        goto fail;
    }
    if (c->data->n <= c->space->n) {
        set_error(e, "calibrate_data", text_printf("%s: %zu measurements for %zu free settings: "
                  "a fit needs more measurements than settings", c->data_path, c->data->n,
                  c->space->n));
        goto fail;
    }
    if (opt_plan_init(&c->plan, c->data) != 0 || weights(c, e) != 0) goto fail;
    size_t p = c->space->n;
    c->value = calloc(p, sizeof *c->value);
    c->error = calloc(p, sizeof *c->error);
    c->correlation = calloc(p * p, sizeof *c->correlation);
    c->at_bound = calloc(p, sizeof *c->at_bound);
    if (!c->value || !c->error || !c->correlation || !c->at_bound) goto nomem;
    c->jacobian_step = sqrt(c->rtol > DBL_EPSILON ? c->rtol : DBL_EPSILON);
    return c;
nomem:
    set_error(e, NULL, text_printf("out of memory"));
fail:
    if (!e->message) set_error(e, NULL, text_printf("out of memory"));
    calibration_free(c);
    return NULL;
}

/* ---- the residuals and their Jacobian over runs ------------------------------------------- */

typedef struct fit {
    calibration *c;
    opt_problem pb;
    const opt_options *o;
    size_t n, p;
    scaled *s;
    double *theta;           /* scratch: p                                   */
    double *points;          /* scratch: p points of p values                */
    opt_result *results;     /* scratch: p                                   */
    /* the last f: at u_f, r_f */
    double *u_f, *r_f;
    int have_f;
    /* the last Jacobian in y: at y_j, n x p */
    double *y_j, *J_y;
    int have_j;
    int interrupted;
    char *failure;           /* a run that failed where it had to succeed    */
} fit;

static double summary(const opt_result *r, void *user)
{
    const calibration *c = user;
    if (r->status != OPT_RUN_OK || !r->model) return NAN;
    double chi2 = 0;
    for (size_t i = 0; i < c->data->n; i++) {
        double d = c->w[i] * (r->model[i] - c->data->points[i].value);
        chi2 += d * d;
    }
    return chi2;
}

static void theta_of_y(const fit *f, const double *y, double *theta)
{
    for (size_t i = 0; i < f->p; i++) theta[i] = f->s[i].size * y[i];
}

static void residuals(const fit *f, const opt_result *r, double *out)
{
    const calibration *c = f->c;
    for (size_t i = 0; i < f->n; i++)
        out[i] = r->status == OPT_RUN_OK ? c->w[i] * (r->model[i] - c->data->points[i].value)
                                         : OUT_OF_DOMAIN;
}

/* Runs the points (m of them) and notes an interruption. */
static void run_points(fit *f, size_t m, const double *points, opt_result *r)
{
    if (opt_evaluate_batch(&f->pb, m, points, r)) f->interrupted = 1;
}

static int f_of_u(const gsl_vector *x, void *params, gsl_vector *out)
{
    fit *f = params;
    double y[64];
    for (size_t i = 0; i < f->p; i++) y[i] = y_of_u(&f->s[i], gsl_vector_get(x, i));
    theta_of_y(f, y, f->theta);
    opt_result r;
    run_points(f, 1, f->theta, &r);
    if (f->interrupted) {
        opt_result_free(&r);
        return GSL_EBADFUNC;
    }
    residuals(f, &r, out->data);
    for (size_t i = 0; i < f->p; i++) f->u_f[i] = gsl_vector_get(x, i);
    memcpy(f->r_f, out->data, f->n * sizeof *f->r_f);
    f->have_f = r.status == OPT_RUN_OK;
    if (!f->have_f && !f->failure) /* kept for the message if no step succeeds */
        f->failure = text_dup(r.message ? r.message : "a run failed");
    opt_result_free(&r);
    return GSL_SUCCESS;
}

/* The Jacobian of the residuals in y at y0 (residuals r0 there) into J_y:
 * forward differences, the p runs at once; a step that fails is taken the
 * other way.  0, or -1 (f->interrupted, or f->failure). */
static int jacobian_y(fit *f, const double *y0, const double *r0, double *J)
{
    const size_t n = f->n, p = f->p;
    double h[64], y[64];
    for (size_t i = 0; i < p; i++) {
        h[i] = f->c->jacobian_step * fmax(fabs(y0[i]), 1.0);
        /* inside the bounds: away from the nearer one */
        if (y0[i] + h[i] > f->s[i].hi) h[i] = -h[i];
        memcpy(y, y0, p * sizeof *y);
        y[i] += h[i];
        theta_of_y(f, y, f->points + i * p);
    }
    run_points(f, p, f->points, f->results);
    double *r = malloc(n * sizeof *r);
    int rc = r ? 0 : -1;
    for (size_t i = 0; rc == 0 && i < p; i++) {
        if (f->interrupted) {
            rc = -1;
            break;
        }
        if (f->results[i].status != OPT_RUN_OK && y0[i] - h[i] >= f->s[i].lo) {
            /* the other side */
            opt_result_free(&f->results[i]);
            h[i] = -h[i];
            memcpy(y, y0, p * sizeof *y);
            y[i] += h[i];
            theta_of_y(f, y, f->points + i * p);
            run_points(f, 1, f->points + i * p, &f->results[i]);
        }
        if (f->interrupted) {
            rc = -1;
            break;
        }
        if (f->results[i].status != OPT_RUN_OK) {
            free(f->failure);
            f->failure = text_printf("the Jacobian's step in %s from %.17g: %s",
                                     f->c->space->p[i].name, f->s[i].size * y0[i],
                                     f->results[i].message ? f->results[i].message : "failed");
            rc = -1;
            break;
        }
        residuals(f, &f->results[i], r);
        for (size_t j = 0; j < n; j++) J[j * p + i] = (r[j] - r0[j]) / h[i];
    }
    for (size_t i = 0; i < p; i++) opt_result_free(&f->results[i]);
    free(r);
    if (rc == 0) {
        memcpy(f->y_j, y0, p * sizeof *y0);
        f->have_j = 1;
    }
    return rc;
}

static int df_of_u(const gsl_vector *x, void *params, gsl_matrix *J)
{
    fit *f = params;
    const size_t p = f->p, n = f->n;
    double y0[64];
    for (size_t i = 0; i < p; i++) y0[i] = y_of_u(&f->s[i], gsl_vector_get(x, i));
    int same = f->have_f;
    for (size_t i = 0; same && i < p; i++) same = f->u_f[i] == gsl_vector_get(x, i);
    if (!same) { /* the residuals here: GSL asks after f at the same x, so rarely */
        gsl_vector_view r = gsl_vector_view_array(f->r_f, n);
        if (f_of_u(x, f, &r.vector) != GSL_SUCCESS) return GSL_EBADFUNC;
        if (!f->have_f) return GSL_EBADFUNC;
    }
    if (jacobian_y(f, y0, f->r_f, f->J_y) != 0) return GSL_EBADFUNC;
    for (size_t i = 0; i < p; i++) {
        double d = dy_du(&f->s[i], gsl_vector_get(x, i));
        for (size_t j = 0; j < n; j++) gsl_matrix_set(J, j, i, f->J_y[j * p + i] * d);
    }
    return GSL_SUCCESS;
}

/* ---- the fit ---------------------------------------------------------------------------- */

static void set_reason(calibration *c, opt_outcome outcome, char *reason)
{
    free(c->reason);
    c->reason = reason ? reason : text_dup("out of memory");
    c->outcome = outcome;
}

static void progress(const fit *f, size_t iter, double chi2, const double *theta)
{
    if (!f->o->progress) return;
    char *line = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&line, &len);
    if (!fp) return;
    fprintf(fp, "iteration %zu: chi2 = %.6g", iter, chi2);
    for (size_t i = 0; i < f->p; i++) fprintf(fp, ", %s = %.8g", f->c->space->p[i].name, theta[i]);
    fprintf(fp, " (%zu runs)", f->pb.computed + f->pb.reused);
    fclose(fp);
    f->o->progress(line, f->o->progress_user);
    free(line);
}

/* Standard errors and correlations from the Jacobian in y at the optimum. */
static void uncertainties(fit *f, const double *y)
{
    calibration *c = f->c;
    const size_t n = f->n, p = f->p;
    gsl_matrix *J = gsl_matrix_alloc(n, p), *C = gsl_matrix_alloc(p, p);
    if (!J || !C) goto out;
    for (size_t j = 0; j < n; j++)
        for (size_t i = 0; i < p; i++) gsl_matrix_set(J, j, i, f->J_y[j * p + i]);
    /* A column that the others give to within the Jacobian's own error
     * (about its step, sqrt(rtol), relative) is no information: GSL's
     * pivoted QR drops it (variance 0), and the setting is undetermined. */
    gsl_multifit_nlinear_covar(J, 10.0 * c->jacobian_step, C);
    double scale = c->absolute ? 1.0 : c->chi2 / (double)c->dof;
    for (size_t i = 0; i < p; i++) {
        double v = gsl_matrix_get(C, i, i);
        /* dropped: the data do not determine that setting */
        c->error[i] = v > 0 ? sqrt(v * scale) * fabs(f->s[i].size) : NAN;
    }
    for (size_t i = 0; i < p; i++)
        for (size_t k = 0; k < p; k++) {
            double vi = gsl_matrix_get(C, i, i), vk = gsl_matrix_get(C, k, k);
            c->correlation[i * p + k] = vi > 0 && vk > 0 ? gsl_matrix_get(C, i, k) / sqrt(vi * vk)
                                                         : NAN;
        }
    (void)y;
out:
    gsl_matrix_free(J);
    gsl_matrix_free(C);
}

/* The end: values, chi2, the fitted model, errors, bounds. */
static void conclude(fit *f, const double *u, int converged, const char *how)
{
    calibration *c = f->c;
    const size_t n = f->n, p = f->p;
    double y[64];
    for (size_t i = 0; i < p; i++) y[i] = y_of_u(&f->s[i], u[i]);
    theta_of_y(f, y, c->value);
    opt_result r;
    run_points(f, 1, c->value, &r);
    if (f->interrupted || r.status != OPT_RUN_OK) {
        set_reason(c, f->interrupted ? OPT_INTERRUPTED : OPT_FAILED,
                   text_printf("the run at the optimum: %s", r.message ? r.message : "failed"));
        opt_result_free(&r);
        return;
    }
    double *res = malloc(n * sizeof *res);
    c->fitted = r.model;
    r.model = NULL;
    opt_result_free(&r);
    if (!res) {
        set_reason(c, OPT_FAILED, text_printf("out of memory"));
        return;
    }
    c->chi2 = 0;
    for (size_t j = 0; j < n; j++) {
        res[j] = c->w[j] * (c->fitted[j] - c->data->points[j].value);
        c->chi2 += res[j] * res[j];
    }
    c->dof = n - p;
    int same = f->have_j;
    for (size_t i = 0; same && i < p; i++) same = f->y_j[i] == y[i];
    if (!same && jacobian_y(f, y, res, f->J_y) != 0) {
        free(res);
        set_reason(c, f->interrupted ? OPT_INTERRUPTED : OPT_FAILED,
                   text_printf("the Jacobian at the optimum: %s",
                               f->failure ? f->failure : "interrupted"));
        return;
    }
    free(res);
    uncertainties(f, y);
    /* How it ended, worst first. */
    char *bound = NULL, *undetermined = NULL;
    for (size_t i = 0; i < p; i++) {
        const scaled *s = &f->s[i];
        double room = AT_BOUND * fmax(fabs(y[i]), 1.0);
        if (isfinite(s->lo) && y[i] - s->lo <= room) c->at_bound[i] = 1;
        if (isfinite(s->hi) && s->hi - y[i] <= room) c->at_bound[i] = 2;
        if (c->at_bound[i] && !bound)
            bound = text_printf("%s = %.8g is at its %s bound %.8g: the data want it beyond "
                                "(widen the bound, or fix the setting)", c->space->p[i].name,
                                c->value[i], c->at_bound[i] == 1 ? "lower" : "upper",
                                c->at_bound[i] == 1 ? c->space->p[i].lower : c->space->p[i].upper);
        if (isnan(c->error[i]) && !undetermined)
            undetermined = text_printf("the data do not determine %s (its column of the "
                                       "Jacobian depends on the others'): fix it, or measure "
                                       "what it changes", c->space->p[i].name);
    }
    if (!converged)
        set_reason(c, OPT_NOT_CONVERGED, text_printf("%s", how));
    else if (bound)
        set_reason(c, OPT_NOT_CONVERGED, text_printf("%s", bound));
    else if (undetermined)
        set_reason(c, OPT_NOT_CONVERGED, text_printf("%s", undetermined));
    else
        set_reason(c, OPT_CONVERGED, text_printf("%s", how));
    free(bound);
    free(undetermined);
}

opt_outcome calibration_run(calibration *c, const opt_options *o)
{
    const size_t n = c->data->n, p = c->space->n;
    const scene_calibrate_config *k = &scene_cfg(c->sc)->calibrate;
    fit f = {.c = c, .o = o, .n = n, .p = p};
    f.pb = (opt_problem){.space = c->space, .plan = &c->plan, .threads = o->threads,
                         .runner = o->runner,
                         .stop = o->stop, .stop_user = o->stop_user, .summary = summary,
                         .summary_user = c};
    gsl_multifit_nlinear_workspace *w = NULL;
    gsl_vector *u0 = NULL;
    char *key = NULL, *msg = NULL;
    size_t resumed = 0;
    f.s = calloc(p, sizeof *f.s);
    f.theta = malloc(p * sizeof *f.theta);
    f.points = malloc(p * p * sizeof *f.points);
    f.results = calloc(p, sizeof *f.results);
    f.u_f = malloc(p * sizeof *f.u_f);
    f.r_f = malloc(n * sizeof *f.r_f);
    f.y_j = malloc(p * sizeof *f.y_j);
    f.J_y = malloc(n * p * sizeof *f.J_y);
    u0 = gsl_vector_alloc(p);
    if (!f.s || !f.theta || !f.points || !f.results || !f.u_f || !f.r_f || !f.y_j || !f.J_y || !u0) {
        set_reason(c, OPT_FAILED, text_printf("out of memory"));
        goto out;
    }
    /* The journal: every run, and a restart resumes. */
    char *echo = NULL;
    size_t echo_len = 0;
    FILE *fp = open_memstream(&echo, &echo_len);
    if (fp) {
        scene_write(c->sc, fp, 0);
        fclose(fp);
    }
    key = echo ? opt_journal_key(echo, c->data_path) : NULL;
    free(echo);
    f.pb.journal = key ? opt_journal_open(o->dir, key, c->space, "chi2", n, &resumed, &msg) : NULL;
    if (!f.pb.journal) {
        set_reason(c, OPT_FAILED, msg ? msg : text_printf("out of memory"));
        msg = NULL;
        goto out;
    }
    if (resumed && o->progress) {
        char *line = text_printf("resuming: %zu runs of an interrupted calibration are reused",
                                 resumed);
        if (line) o->progress(line, o->progress_user);
        free(line);
    }
    for (size_t i = 0; i < p; i++) {
        const opt_param *q = &c->space->p[i];
        double size = fabs(q->start);
        if (!(size > 0)) size = isfinite(q->upper - q->lower) ? q->upper - q->lower : 1.0;
        f.s[i] = (scaled){.size = size, .lo = q->lower / size, .hi = q->upper / size};
        double y = q->start / size;
        if ((isfinite(f.s[i].lo) && y <= f.s[i].lo) || (isfinite(f.s[i].hi) && y >= f.s[i].hi)) {
            set_reason(c, OPT_FAILED, text_printf("%s starts at its bound %.8g: start inside the "
                       "bounds", q->name, q->start));
            goto out;
        }
        gsl_vector_set(u0, i, u_of_y(&f.s[i], y));
    }
    gsl_multifit_nlinear_parameters params = gsl_multifit_nlinear_default_parameters();
    params.trs = gsl_multifit_nlinear_trs_lm;
    params.scale = gsl_multifit_nlinear_scale_more;
    params.solver = gsl_multifit_nlinear_solver_qr;
    gsl_multifit_nlinear_fdf fdf = {.f = f_of_u, .df = df_of_u, .fvv = NULL, .n = n, .p = p,
                                    .params = &f};
    /* n > p is checked by calibration_new: GSL's own checks cannot fail. */
    if (!(w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &params, n, p))) {
        set_reason(c, OPT_FAILED, text_printf("out of memory"));
        goto out;
    }
    int status = gsl_multifit_nlinear_init(u0, &fdf, w);
    if (status != GSL_SUCCESS || !f.have_f) {
        set_reason(c, f.interrupted ? OPT_INTERRUPTED : OPT_FAILED,
                   text_printf("the run at the start: %s",
                               f.failure ? f.failure : f.interrupted ? "interrupted" : gsl_strerror(status)));
        goto out;
    }
    free(f.failure);
    f.failure = NULL;
    double y_prev[64], y_now[64];
    for (size_t i = 0; i < p; i++) y_prev[i] = y_of_u(&f.s[i], gsl_vector_get(w->x, i));
    {
        double theta[64], chi2;
        theta_of_y(&f, y_prev, theta);
        gsl_blas_ddot(w->f, w->f, &chi2);
        progress(&f, 0, chi2, theta);
    }
    int converged = 0;
    const char *how = NULL;
    char *how_text = NULL;
    size_t iter = 0;
    while (iter < (size_t)k->max_iter) {
        status = gsl_multifit_nlinear_iterate(w);
        if (f.interrupted) break;
        if (status == GSL_ENOPROG) {
            converged = 1;
            how = "no step reduces chi-square further (the optimum to the model's precision)";
            break;
        }
        if (status != GSL_SUCCESS) break;
        iter++;
        int small = 1;
        for (size_t i = 0; i < p; i++) {
            y_now[i] = y_of_u(&f.s[i], gsl_vector_get(w->x, i));
            if (fabs(y_now[i] - y_prev[i]) > k->xtol * (fabs(y_now[i]) + k->xtol)) small = 0;
        }
        double theta[64], chi2;
        theta_of_y(&f, y_now, theta);
        gsl_blas_ddot(w->f, w->f, &chi2);
        progress(&f, iter, chi2, theta);
        memcpy(y_prev, y_now, p * sizeof *y_now);
        if (small) {
            converged = 1;
            how_text = text_printf("no setting moved by more than xtol = %g of its value", k->xtol);
            how = how_text;
            break;
        }
    }
    c->iterations = iter;
    if (f.interrupted) {
        set_reason(c, OPT_INTERRUPTED, text_printf("interrupted after %zu iterations; the same "
                   "command resumes (its runs are in evaluations.tsv)", iter));
    } else if (status != GSL_SUCCESS && !converged) {
        set_reason(c, OPT_FAILED, text_printf("the trust region stopped: %s%s%s",
                   gsl_strerror(status), f.failure ? ": " : "", f.failure ? f.failure : ""));
    } else {
        double u[64];
        for (size_t i = 0; i < p; i++) u[i] = gsl_vector_get(w->x, i);
        char *not_yet = converged ? NULL : text_printf("not converged in max_iter = %lld "
                                                       "iterations (raise it, or start nearer)",
                                                       k->max_iter);
        conclude(&f, u, converged, converged ? how : not_yet);
        free(not_yet);
    }
    free(how_text);
out:
    c->runs = f.pb.computed;
    c->reused = f.pb.reused;
    if (f.pb.journal_message && c->outcome != OPT_INTERRUPTED)
        set_reason(c, OPT_FAILED, text_printf("%s", f.pb.journal_message));
    free(f.pb.journal_message);
    opt_journal_close(f.pb.journal);
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(u0);
    free(key);
    free(msg);
    free(f.s);
    free(f.theta);
    free(f.points);
    free(f.results);
    free(f.u_f);
    free(f.r_f);
    free(f.y_j);
    free(f.J_y);
    free(f.failure);
    return c->outcome;
}
