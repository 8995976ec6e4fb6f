/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * design.c -- a result of the run optimised over settings (design.h).
 */
#include "optimise/design.h"

#include "util/text.h"

#include <float.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multimin.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
/* What a failed run counts as: worse than any. */
#define OUTSIDE 1e300
/* Points of the coarse grid in all, at most. */
#define MAX_GRID 10000
/* A setting within this fraction of its range from a bound is at it. */
#define AT_BOUND 1e-3

/* ---- the problem ------------------------------------------------------------------------- */

void design_free(design_problem *d)
{
    if (!d) return;
    opt_journal_close(d->pb.journal);
    free(d->pb.journal_message);
    opt_objective_free(&d->objective);
    opt_space_free(d->space);
    free(d->reason);
    free(d->best);
    free(d->at_bound);
    free(d->scan_values);
    free(d->scan_objective);
    free(d->profile_value);
    free(d->profile_objective);
    free(d);
}

design_problem *design_new(const scene *sc, opt_error *e)
{
    const scene_config *cfg = scene_cfg(sc);
    e->message = NULL;
    e->keyword = NULL;
    design_problem *d = calloc(1, sizeof *d);
    if (!d) goto nomem;
    d->sc = sc;
    d->maximise = cfg->design.goal == SCENE_MAXIMISE;
    if (!(d->space = opt_space_new(sc, "design", e))) goto fail;
    char *msg = NULL;
    /* The longest chain the design may try: NAME(k) must exist in all. */
    size_t n = (size_t)scene_setting(cfg, "n_granules");
    for (size_t i = 0; i < d->space->n; i++)
        if (strcmp(scene_var_keyword_at(d->space->p[i].row), "n_granules") == 0)
            n = (size_t)d->space->p[i].lower;
    if (opt_objective_parse(cfg->design.objective, n, &d->objective, &msg) != 0) {
        e->message = msg ? msg : text_dup("out of memory");
        e->keyword = "design_objective";
        goto fail;
    }
    if (cfg->design.method == SCENE_GRID && cfg->design.grid < 2) {
        e->message = text_printf("method = 'grid' runs the grid alone: give grid >= 2 points per "
                                 "setting");
        e->keyword = "design_grid";
        goto fail;
    }
    size_t reals = 0, points = 1;
    for (size_t i = 0; i < d->space->n; i++) reals += !d->space->p[i].integer;
    for (size_t j = 0; j < reals && cfg->design.grid > 1; j++) {
        points *= (size_t)cfg->design.grid;
        if (points > MAX_GRID) {
            e->message = text_printf("%lld points per setting make a grid of more than %d points "
                                     "for %zu real settings: give fewer (1: none)",
                                     cfg->design.grid, MAX_GRID, reals);
            e->keyword = "design_grid";
            goto fail;
        }
    }
    scene_config at;
    scene_config_at(cfg, 0, &at);
    d->unit = d->objective.dim == TAPER_DIM_NUMBER ? NULL : scene_unit_suffix(&at, d->objective.dim);
    d->best = calloc(d->space->n, sizeof *d->best);
    d->at_bound = calloc(d->space->n, sizeof *d->at_bound);
    if (!d->best || !d->at_bound) goto nomem;
    d->best_objective = NAN;
    d->pb = (opt_problem){.space = d->space, .objective = &d->objective};
    return d;
nomem:
    free(e->message);
    e->message = text_dup("out of memory");
    e->keyword = NULL;
fail:
    design_free(d);
    return NULL;
}

/* ---- the optimiser's variables ------------------------------------------------------------ */

/* The real settings varied (their indices), and the integers fixed at the
 * values of the combination being optimised. */
typedef struct search {
    design_problem *d;
    const opt_options *o;
    size_t p;                /* all free settings                             */
    size_t m;                /* the real ones                                 */
    size_t real[64];         /* their indices                                 */
    double point[64];        /* the full point: integers fixed                */
    double h;                /* the gradient's step in w (BFGS)               */
    double step;             /* the simplex's first step in w                 */
    size_t runs;             /* of this optimisation                          */
    size_t max_runs;
    int interrupted;
    double best_f;           /* the lowest value seen (sign applied)          */
    double best[64];
} search;

static double theta_of_w(const opt_param *q, double w)
{
    double s = sin(0.5 * PI * w);
    return q->lower + (q->upper - q->lower) * s * s;
}

static double w_of_theta(const opt_param *q, double theta)
{
    double z = (theta - q->lower) / (q->upper - q->lower);
    z = z < 0 ? 0 : z > 1 ? 1 : z;
    return 2.0 / PI * asin(sqrt(z));
}

static void point_of(search *s, const double *w, double *point)
{
    memcpy(point, s->point, s->p * sizeof *point);
    for (size_t j = 0; j < s->m; j++)
        point[s->real[j]] = theta_of_w(&s->d->space->p[s->real[j]], w[j]);
}

/* The objective, sign applied for minimising, at k points; +inf-like for
 * failed runs.  Keeps the best. */
static void values_at(search *s, size_t k, const double *points, double *f)
{
    opt_result *r = calloc(k, sizeof *r);
    if (!r) {
        for (size_t i = 0; i < k; i++) f[i] = OUTSIDE;
        return;
    }
    if (opt_evaluate_batch(&s->d->pb, k, points, r)) s->interrupted = 1;
    for (size_t i = 0; i < k; i++) {
        f[i] = OUTSIDE;
        if (r[i].status == OPT_RUN_OK) {
            f[i] = s->d->maximise ? -r[i].objective : r[i].objective;
            if (f[i] < s->best_f) {
                s->best_f = f[i];
                memcpy(s->best, points + i * s->p, s->p * sizeof *s->best);
            }
        }
        opt_result_free(&r[i]);
    }
    free(r);
    s->runs += k;
}

static double f_of_w(const gsl_vector *x, void *params)
{
    search *s = params;
    double point[64], f;
    point_of(s, x->data, point);
    values_at(s, 1, point, &f);
    return s->interrupted ? GSL_NAN : f;
}

/* The gradient by forward differences, its m runs at once (and the point
 * itself, which the optimiser has usually just run: the journal has it). */
static void fdf_of_w(const gsl_vector *x, void *params, double *f, gsl_vector *g)
{
    search *s = params;
    double points[65 * 64], fs[65], w[64];
    const size_t m = s->m, p = s->p;
    point_of(s, x->data, points);
    double h[64];
    for (size_t j = 0; j < m; j++) {
        memcpy(w, x->data, m * sizeof *w);
        h[j] = s->h;
        w[j] += h[j];
        point_of(s, w, points + (j + 1) * p);
    }
    values_at(s, m + 1, points, fs);
    *f = s->interrupted ? GSL_NAN : fs[0];
    for (size_t j = 0; g && j < m; j++)
        gsl_vector_set(g, j, fs[j + 1] >= OUTSIDE || fs[0] >= OUTSIDE ? 0.0 : (fs[j + 1] - fs[0]) / h[j]);
}

static void df_of_w(const gsl_vector *x, void *params, gsl_vector *g)
{
    double f;
    fdf_of_w(x, params, &f, g);
}

static void say(const search *s, const char *fmt, ...) TEXT_PRINTF(2, 3);
static void say(const search *s, const char *fmt, ...)
{
    if (!s->o->progress) return;
    va_list ap;
    va_start(ap, fmt);
    char *line = text_vprintf(fmt, ap);
    va_end(ap);
    if (line) s->o->progress(line, s->o->progress_user);
    free(line);
}

static void say_point(const search *s, size_t iter, double f, double size)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp) return;
    const design_problem *d = s->d;
    fprintf(fp, "iteration %zu: %s = %.8g%s%s", iter, d->objective.name,
            d->maximise ? -f : f, d->unit ? " " : "", d->unit ? d->unit : "");
    for (size_t i = 0; i < s->p; i++) fprintf(fp, ", %s = %.8g", d->space->p[i].name, s->best[i]);
    fprintf(fp, " (size %.2g, %zu runs)", size, s->runs);
    fclose(fp);
    say(s, "%s", text);
    free(text);
}

/* Nelder-Mead from w0: 0 converged, 1 out of runs, 2 interrupted, 3 the
 * solver failed. */
static int nelder_mead(search *s, const double *w0, double tolerance, size_t *iterations)
{
    const size_t m = s->m, p = s->p;
    gsl_vector *x = gsl_vector_alloc(m), *step = gsl_vector_alloc(m);
    gsl_multimin_fminimizer *min = gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, m);
    if (!x || !step || !min) {
        gsl_vector_free(x);
        gsl_vector_free(step);
        gsl_multimin_fminimizer_free(min);
        return 3;
    }
    /* The first simplex, all at once (nmsimplex2 runs x0, then x0 + step_i
     * e_i: the same points, found in the journal). */
    double points[65 * 64], fs[65], w[64];
    point_of(s, w0, points);
    for (size_t j = 0; j < m; j++) {
        memcpy(w, w0, m * sizeof *w);
        w[j] += s->step;
        point_of(s, w, points + (j + 1) * p);
    }
    values_at(s, m + 1, points, fs);
    s->runs -= m + 1; /* counted again as nmsimplex2 asks for them */
    for (size_t j = 0; j < m; j++) {
        gsl_vector_set(x, j, w0[j]);
        gsl_vector_set(step, j, s->step);
    }
    gsl_multimin_function fn = {.f = f_of_w, .n = m, .params = s};
    int rc = 1;
    if (!s->interrupted && gsl_multimin_fminimizer_set(min, &fn, x, step) != GSL_SUCCESS) rc = 3;
    size_t iter = 0;
    while (rc == 1 && !s->interrupted && s->runs < s->max_runs) {
        int status = gsl_multimin_fminimizer_iterate(min);
        if (s->interrupted) break;
        iter++;
        double size = gsl_multimin_fminimizer_size(min);
        say_point(s, iter, min->fval, size);
        if (status != GSL_SUCCESS) {
            rc = 3;
            break;
        }
        if (gsl_multimin_test_size(size, tolerance) == GSL_SUCCESS) rc = 0;
    }
    if (s->interrupted) rc = 2;
    *iterations += iter;
    gsl_multimin_fminimizer_free(min);
    gsl_vector_free(x);
    gsl_vector_free(step);
    return rc;
}

/* BFGS from w0: as nelder_mead. */
static int bfgs(search *s, const double *w0, double tolerance, size_t *iterations)
{
    const size_t m = s->m;
    gsl_vector *x = gsl_vector_alloc(m), *prev = gsl_vector_alloc(m);
    gsl_multimin_fdfminimizer *min =
        gsl_multimin_fdfminimizer_alloc(gsl_multimin_fdfminimizer_vector_bfgs2, m);
    if (!x || !prev || !min) {
        gsl_vector_free(x);
        gsl_vector_free(prev);
        gsl_multimin_fdfminimizer_free(min);
        return 3;
    }
    for (size_t j = 0; j < m; j++) gsl_vector_set(x, j, w0[j]);
    gsl_multimin_function_fdf fn = {.f = f_of_w, .df = df_of_w, .fdf = fdf_of_w, .n = m,
                                    .params = s};
    int rc = 1;
    /* first step 0.1 in w; line search tolerance 0.1 (GSL's advice) */
    if (gsl_multimin_fdfminimizer_set(min, &fn, x, 0.1, 0.1) != GSL_SUCCESS) rc = 3;
    size_t iter = 0;
    while (rc == 1 && !s->interrupted && s->runs < s->max_runs) {
        gsl_vector_memcpy(prev, min->x);
        int status = gsl_multimin_fdfminimizer_iterate(min);
        if (s->interrupted) break;
        iter++;
        double moved = 0;
        for (size_t j = 0; j < m; j++)
            moved = fmax(moved, fabs(gsl_vector_get(min->x, j) - gsl_vector_get(prev, j)));
        say_point(s, iter, min->f, moved);
        /* No step lowers the objective: the optimum to the runs' precision. */
        if (status == GSL_ENOPROG || moved < tolerance) rc = 0;
        else if (status != GSL_SUCCESS) rc = 3;
    }
    if (s->interrupted) rc = 2;
    *iterations += iter;
    gsl_multimin_fdfminimizer_free(min);
    gsl_vector_free(x);
    gsl_vector_free(prev);
    return rc;
}

/* The coarse grid of the real settings (k points each, lower to upper)
 * and (with_start) the start, all at once: s->best is the best of them. */
static void grid(search *s, size_t k, int with_start)
{
    const size_t m = s->m, p = s->p;
    size_t n = 1;
    for (size_t j = 0; j < m; j++) n *= k;
    if (k < 2) n = 0;
    double *points = malloc((n + 1) * p * sizeof *points), *f = malloc((n + 1) * sizeof *f);
    if (!points || !f) {
        free(points);
        free(f);
        return;
    }
    memcpy(points, s->point, p * sizeof *points);
    for (size_t j = 0; j < m; j++) points[s->real[j]] = s->d->space->p[s->real[j]].start;
    for (size_t g = 0; g < n; g++) {
        double *x = points + (g + 1) * p;
        memcpy(x, s->point, p * sizeof *x);
        size_t c = g;
        for (size_t j = m; j-- > 0;) {
            const opt_param *q = &s->d->space->p[s->real[j]];
            x[s->real[j]] = q->lower + (q->upper - q->lower) * (double)(c % k) / (double)(k - 1);
            c /= k;
        }
    }
    for (size_t g = with_start ? 0 : 1; g < n + 1 && !s->interrupted; g += 256)
        values_at(s, n + 1 - g < 256 ? n + 1 - g : 256, points + g * p, f + g);
    free(points);
    free(f);
}

/* ---- the design --------------------------------------------------------------------------- */

static void set_reason(design_problem *d, opt_outcome outcome, char *reason)
{
    free(d->reason);
    d->reason = reason ? reason : text_dup("out of memory");
    d->outcome = outcome;
}

static double summary(const opt_result *r, void *user)
{
    (void)user;
    return r->objective;
}

/* The integer settings' combinations: how many, and combination c's
 * values into point. */
static size_t combinations(const design_problem *d)
{
    size_t n = 1;
    for (size_t i = 0; i < d->space->n; i++)
        if (d->space->p[i].integer) n *= (size_t)(d->space->p[i].upper - d->space->p[i].lower) + 1;
    return n;
}

static void combination(const design_problem *d, size_t c, double *point)
{
    for (size_t i = d->space->n; i-- > 0;) {
        const opt_param *q = &d->space->p[i];
        if (!q->integer) continue;
        size_t span = (size_t)(q->upper - q->lower) + 1;
        point[i] = q->lower + (double)(c % span);
        c /= span;
    }
}

opt_outcome design_run(design_problem *d, const opt_options *o)
{
    const scene_config *cfg = scene_cfg(d->sc);
    const size_t p = d->space->n;
    char *msg = NULL, *key = NULL, *echo = NULL;
    size_t resumed = 0, echo_len = 0;
    d->pb.threads = o->threads;
    d->pb.runner = o->runner;
    d->pb.stop = o->stop;
    d->pb.stop_user = o->stop_user;
    d->pb.summary = summary;
    FILE *fp = open_memstream(&echo, &echo_len);
    if (fp) {
        scene_write(d->sc, fp, 0);
        fclose(fp);
    }
    key = echo ? opt_journal_key(echo, NULL) : NULL;
    free(echo);
    char *column = text_printf("%s%s%s%s", d->objective.name, d->unit ? "[" : "",
                               d->unit ? d->unit : "", d->unit ? "]" : "");
    d->pb.journal = key && column ? opt_journal_open(o->dir, key, d->space, column, 0, &resumed, &msg)
                                  : NULL;
    free(key);
    free(column);
    if (!d->pb.journal) {
        set_reason(d, OPT_FAILED, msg ? msg : text_printf("out of memory"));
        return d->outcome;
    }
    search s = {.d = d, .o = o, .p = p, .best_f = INFINITY};
    if (resumed) say(&s, "resuming: %zu runs of an interrupted design are reused", resumed);
    for (size_t i = 0; i < p; i++)
        if (!d->space->p[i].integer) s.real[s.m++] = i;
    s.h = sqrt(fmax(scene_setting(cfg, "rtol"), DBL_EPSILON));
    /* The simplex's first step in w: half the coarse grid's spacing (about
     * a quarter of a grid cell in the setting near the middle of its
     * range), from 0.05 to 0.2. */
    s.step = cfg->design.grid > 1 ? 0.5 / (double)(cfg->design.grid - 1) : 0.2;
    s.step = s.step < 0.05 ? 0.05 : s.step > 0.2 ? 0.2 : s.step;
    const size_t n_comb = combinations(d);
    d->n_scan = s.m && n_comb > 1 ? n_comb : 0;
    if (n_comb > 1) {
        d->scan_values = malloc(n_comb * p * sizeof *d->scan_values);
        d->scan_objective = malloc(n_comb * sizeof *d->scan_objective);
        if (!d->scan_values || !d->scan_objective) {
            set_reason(d, OPT_FAILED, text_printf("out of memory"));
            return d->outcome;
        }
        d->n_scan = n_comb;
    }
    double w0[64];
    int worst = 0; /* 0 converged, 1 out of runs, 2 interrupted, 3 failed */
    if (s.m == 0) {
        /* Integers alone: every combination, at once. */
        double *points = malloc(n_comb * p * sizeof *points);
        double *f = malloc(n_comb * sizeof *f);
        if (!points || !f) {
            free(points);
            free(f);
            set_reason(d, OPT_FAILED, text_printf("out of memory"));
            return d->outcome;
        }
        for (size_t c = 0; c < n_comb; c++) combination(d, c, points + c * p);
        /* In slices, so that the opt_result array stays small. */
        for (size_t c = 0; c < n_comb && !s.interrupted; c += 64) {
            size_t k = n_comb - c < 64 ? n_comb - c : 64;
            values_at(&s, k, points + c * p, f + c);
        }
        for (size_t c = 0; c < n_comb; c++) {
            memcpy(d->scan_values + c * p, points + c * p, p * sizeof *points);
            d->scan_objective[c] = f[c] >= OUTSIDE ? NAN : d->maximise ? -f[c] : f[c];
        }
        free(points);
        free(f);
        if (s.interrupted) worst = 2;
    }
    for (size_t c = 0; s.m && c < n_comb && worst != 2; c++) {
        for (size_t i = 0; i < p; i++) s.point[i] = d->space->p[i].start;
        combination(d, c, s.point);
        s.max_runs = s.runs + (size_t)cfg->design.max_runs;
        double before = s.best_f, best_here[64];
        memcpy(best_here, s.best, sizeof best_here);
        s.best_f = INFINITY;
        /* The basin: the best of the coarse grid and the start. */
        grid(&s, (size_t)cfg->design.grid, cfg->design.method != SCENE_GRID);
        if (s.interrupted) {
            worst = 2;
            break;
        }
        for (size_t j = 0; j < s.m; j++) {
            const opt_param *q = &d->space->p[s.real[j]];
            w0[j] = w_of_theta(q, isinf(s.best_f) ? q->start : s.best[s.real[j]]);
        }
        int rc = cfg->design.method == SCENE_GRID ? 0
                 : cfg->design.method == SCENE_BFGS
                     ? bfgs(&s, w0, cfg->design.tolerance, &d->iterations)
                     : nelder_mead(&s, w0, cfg->design.tolerance, &d->iterations);
        if (n_comb > 1) {
            memcpy(d->scan_values + c * p, s.best, p * sizeof *s.best);
            d->scan_objective[c] = isinf(s.best_f) ? NAN : d->maximise ? -s.best_f : s.best_f;
            say(&s, "scan %zu of %zu: %s = %.8g", c + 1, n_comb, d->objective.name,
                d->scan_objective[c]);
        }
        if (!(s.best_f < before)) { /* an earlier combination stays the best */
            s.best_f = before;
            memcpy(s.best, best_here, sizeof best_here);
        }
        if (rc > worst) worst = rc;
    }
    d->runs = d->pb.computed;
    d->reused = d->pb.reused;
    if (worst == 2) {
        set_reason(d, OPT_INTERRUPTED, text_printf("interrupted after %zu runs; the same command "
                   "resumes (its runs are in evaluations.tsv)", s.runs));
        return d->outcome;
    }
    if (isinf(s.best_f)) {
        set_reason(d, OPT_FAILED, text_printf("no run succeeded: every point tried failed (see "
                   "evaluations.tsv)"));
        return d->outcome;
    }
    memcpy(d->best, s.best, p * sizeof *d->best);
    d->best_objective = d->maximise ? -s.best_f : s.best_f;
    for (size_t i = 0; i < p; i++) {
        const opt_param *q = &d->space->p[i];
        double room = AT_BOUND * (q->upper - q->lower);
        if (d->best[i] - q->lower <= room) d->at_bound[i] = 1;
        else if (q->upper - d->best[i] <= room) d->at_bound[i] = 2;
    }
    const char *method = cfg->design.method == SCENE_BFGS ? "BFGS" : "Nelder-Mead";
    const size_t per = (size_t)cfg->design.grid;
    if (worst == 3)
        set_reason(d, OPT_NOT_CONVERGED, text_printf("%s stopped without converging (GSL "
                   "refused a step): the best run so far is reported", method));
    else if (worst == 1)
        set_reason(d, OPT_NOT_CONVERGED, text_printf("not converged in max_runs = %lld runs "
                   "(raise it, or the tolerance)", cfg->design.max_runs));
    else if (s.m == 0)
        set_reason(d, OPT_CONVERGED, text_printf("every combination of the integer settings run"));
    else if (cfg->design.method == SCENE_GRID)
        set_reason(d, OPT_CONVERGED, text_printf("the grid of %zu points per setting run (its best "
                   "point: the answer to within a grid cell)", per));
    else
        set_reason(d, OPT_CONVERGED, text_printf("%s: the %s shrank below tolerance = %g of each "
                   "setting's range", method, cfg->design.method == SCENE_BFGS ? "step" : "simplex",
                   cfg->design.tolerance));
    if (d->pb.journal_message) set_reason(d, OPT_FAILED, text_printf("%s", d->pb.journal_message));
    return d->outcome;
}

opt_outcome design_profiles(design_problem *d, const opt_options *o)
{
    const size_t p = d->space->n;
    const size_t points = (size_t)scene_cfg(d->sc)->design.profile_points;
    d->pb.threads = o->threads;
    d->pb.runner = o->runner;
    d->pb.stop = o->stop;
    d->pb.stop_user = o->stop_user;
    if (points == 0) return OPT_CONVERGED;
    size_t before = d->pb.computed;
    d->profile_points = points;
    d->profile_value = malloc(p * points * sizeof *d->profile_value);
    d->profile_objective = malloc(p * points * sizeof *d->profile_objective);
    double *at = malloc(points * p * sizeof *at);
    opt_result *r = calloc(points, sizeof *r);
    opt_outcome outcome = OPT_CONVERGED;
    if (!d->profile_value || !d->profile_objective || !at || !r) {
        outcome = OPT_FAILED;
        goto out;
    }
    for (size_t i = 0; i < p && outcome == OPT_CONVERGED; i++) {
        const opt_param *q = &d->space->p[i];
        for (size_t k = 0; k < points; k++) {
            double x = points > 1 ? q->lower + (q->upper - q->lower) * (double)k / (double)(points - 1)
                                  : d->best[i];
            if (q->integer) x = round(x);
            memcpy(at + k * p, d->best, p * sizeof *at);
            at[k * p + i] = x;
            d->profile_value[i * points + k] = x;
        }
        if (opt_evaluate_batch(&d->pb, points, at, r)) outcome = OPT_INTERRUPTED;
        for (size_t k = 0; k < points; k++) {
            d->profile_objective[i * points + k] = r[k].status == OPT_RUN_OK ? r[k].objective : NAN;
            opt_result_free(&r[k]);
        }
    }
out:
    d->profile_runs = d->pb.computed - before;
    free(at);
    free(r);
    return outcome;
}
