/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * evaluate.c -- a run at a point and what the optimisers read of it
 * (evaluate.h).
 */
#include "optimise/evaluate.h"

#include "run/parallel.h"
#include "util/text.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- the objective ------------------------------------------------------------------ */

int opt_objective_parse(const char *text, size_t n_granules, opt_objective *o, char **msg)
{
    memset(o, 0, sizeof *o);
    o->statistic = o->observable = -1;
    *msg = NULL;
    if (!(o->name = text_dup(text))) goto nomem;
    for (int i = 0; taper_statistic_name((taper_statistic)i); i++)
        if (strcmp(taper_statistic_name((taper_statistic)i), text) == 0) {
            o->statistic = i;
            o->dim = taper_statistic_dimension((taper_statistic)i);
            return 0;
        }
    const char *paren = strchr(text, '(');
    if (paren) {
        size_t len = (size_t)(paren - text);
        char *end;
        long k = strtol(paren + 1, &end, 10);
        for (int i = 0; taper_observable_name((taper_observable)i); i++) {
            const char *name = taper_observable_name((taper_observable)i);
            if (strlen(name) != len || strncmp(name, text, len) != 0) continue;
            if (end == paren + 1 || strcmp(end, ")") != 0 || k < 1 || (size_t)k > n_granules) {
                *msg = text_printf("'%s': a granule's %s is %s(k), k = 1 to %zu (n_granules)",
                                   text, name, name, n_granules);
                opt_objective_free(o);
                return -1;
            }
            o->observable = i;
            o->granule = (size_t)k;
            o->dim = taper_observable_dimension((taper_observable)i);
            return 0;
        }
    }
    /* What there is to choose from, for the message. */
    char *list = NULL;
    size_t size = 0;
    FILE *fp = open_memstream(&list, &size);
    for (int i = 0; fp && taper_statistic_name((taper_statistic)i); i++)
        fprintf(fp, "%s%s", i ? ", " : "", taper_statistic_name((taper_statistic)i));
    if (fp) fclose(fp);
    *msg = text_printf("'%s' is not a result of the run: a statistic of granules.tsv's header "
                       "(%s) or a granule's observable, NAME(k) (t_pass, T_res, v_peak, t_peak, "
                       "X_pass)", text, list ? list : "");
    free(list);
    opt_objective_free(o);
    return -1;
nomem:
    *msg = text_printf("out of memory");
    return -1;
}

void opt_objective_free(opt_objective *o)
{
    free(o->name);
    o->name = NULL;
}

/* ---- the plan of a calibration's samples ---------------------------------------------- */

static int by_time(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int opt_plan_init(opt_plan *plan, const measurements *data)
{
    memset(plan, 0, sizeof *plan);
    plan->data = data;
    if (data->form == MEAS_GRANULES) return 0;
    size_t n = data->n;
    plan->times = malloc(n * sizeof *plan->times);
    plan->sample_of = malloc(n * sizeof *plan->sample_of);
    plan->order = malloc(n * sizeof *plan->order);
    if (!plan->times || !plan->sample_of || !plan->order) goto nomem;
    for (size_t i = 0; i < n; i++) plan->times[i] = data->points[i].t;
    qsort(plan->times, n, sizeof *plan->times, by_time);
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (m == 0 || plan->times[i] != plan->times[m - 1]) plan->times[m++] = plan->times[i];
    plan->n_times = m;
    if (!(plan->first = calloc(m + 1, sizeof *plan->first))) goto nomem;
    for (size_t i = 0; i < n; i++) {
        const double *at = bsearch(&data->points[i].t, plan->times, m, sizeof *plan->times, by_time);
        plan->sample_of[i] = (size_t)(at - plan->times);
        plan->first[plan->sample_of[i] + 1]++;
    }
    for (size_t j = 0; j < m; j++) plan->first[j + 1] += plan->first[j];
    size_t *fill = malloc((m + 1) * sizeof *fill);
    if (!fill) goto nomem;
    memcpy(fill, plan->first, (m + 1) * sizeof *fill);
    for (size_t i = 0; i < n; i++) plan->order[fill[plan->sample_of[i]]++] = i;
    free(fill);
    return 0;
nomem:
    opt_plan_free(plan);
    return -1;
}

void opt_plan_free(opt_plan *plan)
{
    free(plan->times);
    free(plan->sample_of);
    free(plan->first);
    free(plan->order);
    memset(plan, 0, sizeof *plan);
}

/* ---- one run ----------------------------------------------------------------------------- */

/* What the sampler reads, and where it puts it. */
typedef struct sampling {
    const opt_problem *pb;
    double *model;              /* per data point                            */
    double unit[MEAS_N_QUANTITIES]; /* rescaled -> the table's units          */
    size_t n;                   /* granules                                  */
    double *x, *v, *f;          /* the state at a sample: N, N, N + 1         */
    size_t taken;
    int stopped;
    char why[sizeof(((taper_error *)0)->message)];
} sampling;

static int stop_requested(const opt_problem *pb) { return pb->stop && pb->stop(pb->stop_user); }

static int monitor(const taper_progress *p, void *user)
{
    (void)p;
    return stop_requested(user);
}

static double sensor_value(const sampling *s, const meas_point *p)
{
    size_t k = p->granule;
    switch (p->q) {
    case MEAS_X: return s->x[k - 1];
    case MEAS_V: return s->v[k - 1];
    case MEAS_F_LEFT: return s->f[k - 1];
    case MEAS_F_RIGHT: return s->f[k];
    case MEAS_FORCE: return 0.5 * (s->f[k - 1] + s->f[k]);
    case MEAS_WALL_LEFT: return s->f[0];
    case MEAS_WALL_RIGHT: return s->f[s->n];
    default: return NAN;
    }
}

static int sample(const taper_sim *sim, void *user)
{
    sampling *s = user;
    const opt_plan *plan = s->pb->plan;
    taper_error e;
    if (taper_sim_state(sim, s->x, s->v, &e) != TAPER_OK || taper_sim_forces(sim, s->f, &e) != TAPER_OK) {
        snprintf(s->why, sizeof s->why, "%s", e.message);
        s->stopped = 1;
        return 1;
    }
    size_t j = s->taken++;
    for (size_t o = plan->first[j]; o < plan->first[j + 1]; o++) {
        size_t i = plan->order[o];
        const meas_point *p = &plan->data->points[i];
        s->model[i] = sensor_value(s, p) * s->unit[p->q];
    }
    return stop_requested(s->pb);
}

static void fail(opt_result *r, int status, const char *fmt, ...) TEXT_PRINTF(3, 4);
static void fail(opt_result *r, int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    free(r->message);
    r->message = text_vprintf(fmt, ap);
    va_end(ap);
    r->status = status;
}

/* The run's conservation within the scene's bounds (&output), as the
 * driver's granules.tsv requires of a trusted result. */
static int trusted(const taper_sim *sim, const scene_config *at, opt_result *r)
{
    double e = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    double p = taper_sim_statistic(sim, TAPER_STAT_MOMENTUM_ERROR);
    if (!(e <= at->output.max_energy_error)) {
        fail(r, OPT_RUN_FAILED, "untrusted: energy error %.2e exceeds &output max_energy_error "
             "= %g (a smaller rtol keeps it small)", e, at->output.max_energy_error);
        return 0;
    }
    if (!(p <= at->output.max_momentum_error)) {
        fail(r, OPT_RUN_FAILED, "untrusted: momentum error %.2e exceeds &output "
             "max_momentum_error = %g", p, at->output.max_momentum_error);
        return 0;
    }
    return 1;
}

/* Observable `o` of granule k in the units of `units`'s configuration
 * (X_pass: X0 R_1 + x unit_length). */
static double observable(const taper_sim *sim, const taper_chain *chain, const scene_config *units,
                         int o, size_t k)
{
    double x = taper_sim_observable(sim, (taper_observable)o)[k - 1];
    if (o == TAPER_X_PASS) {
        double rest = taper_chain_rest_position(chain)[k - 1];
        scene_column_convert(units, SCENE_COL_X_PASS, &x, &rest, 1);
        return x;
    }
    return x * scene_unit(units, taper_observable_dimension((taper_observable)o));
}

/* The calibration's reading of a run: samples (set up before the run) or
 * observables (after it). */
static void read_granules(const opt_problem *pb, const taper_sim *sim, const taper_chain *chain,
                          const scene_config *units, opt_result *r)
{
    const measurements *m = pb->plan->data;
    for (size_t i = 0; i < m->n; i++) {
        const meas_point *p = &m->points[i];
        int o = meas_quantity_observable(p->q);
        r->model[i] = observable(sim, chain, units, o, p->granule);
        if (isnan(r->model[i])) {
            fail(r, OPT_RUN_FAILED, "granule %zu has no %s in this run (nan: the pulse never "
                 "made it; data line %d)", p->granule, meas_quantity_name(p->q), p->line);
            return;
        }
    }
}

void opt_evaluate(const opt_problem *pb, const double *values, opt_result *r)
{
    memset(r, 0, sizeof *r);
    r->objective = NAN;
    char *msg = NULL;
    scene *sc = opt_scene_at(pb->space, values, &msg);
    if (!sc) {
        fail(r, OPT_RUN_FAILED, "refused: %s", msg ? msg : "out of memory");
        free(msg);
        return;
    }
    scene_config at, units;
    scene_config_at(scene_cfg(sc), 0, &at);
    /* The table's units: SI when it says so, whatever &output units. */
    units = at;
    const measurements *data = pb->plan ? pb->plan->data : NULL;
    if (data) units.output.units = data->si ? SCENE_UNITS_SI : SCENE_UNITS_RESCALED;
    taper_error err;
    taper_chain_spec *cs = scene_chain_spec(&at, 0, &err);
    taper_chain *chain = cs ? taper_chain_alloc(cs, &err) : NULL;
    taper_solver_spec *ss = chain ? scene_solver_spec(&at, &err) : NULL;
    taper_sim *sim = NULL;
    sampling s = {.pb = pb};
    double *times = NULL;
    if (!ss) {
        fail(r, OPT_RUN_FAILED, "refused: %s", err.message);
        goto out;
    }
    taper_solver_spec_set_monitor(ss, monitor, (void *)pb);
    taper_solver_spec_set_log(ss, NULL, NULL);
    s.n = taper_chain_size(chain);
    if (data) {
        r->n_model = data->n;
        if (!(r->model = calloc(data->n, sizeof *r->model))) goto nomem;
        s.model = r->model;
    }
    if (data && data->form != MEAS_GRANULES) {
        const opt_plan *plan = pb->plan;
        double unit_t = scene_unit(&units, TAPER_DIM_TIME);
        for (int q = 0; q < MEAS_N_QUANTITIES; q++)
            s.unit[q] = scene_unit(&units, meas_quantity_dimension((meas_quantity)q));
        s.x = malloc(s.n * sizeof *s.x);
        s.v = malloc(s.n * sizeof *s.v);
        s.f = malloc((s.n + 1) * sizeof *s.f);
        times = malloc(plan->n_times * sizeof *times);
        if (!s.x || !s.v || !s.f || !times) goto nomem;
        for (size_t j = 0; j < plan->n_times; j++) {
            times[j] = plan->times[j] / unit_t;
            if (j && !(times[j] > times[j - 1])) times[j] = nextafter(times[j - 1], INFINITY);
        }
        /* On until the last measured time at least. */
        double t_end = taper_solver_spec_t_end(ss), last = times[plan->n_times - 1];
        if (last > t_end && taper_solver_spec_set_t_end(ss, last, &err) != TAPER_OK) {
            fail(r, OPT_RUN_FAILED, "%s", err.message);
            goto out;
        }
        if (taper_solver_spec_set_sample_times(ss, times, plan->n_times, sample, &s, &err) !=
            TAPER_OK) {
            fail(r, OPT_RUN_FAILED, "%s", err.message);
            goto out;
        }
    }
    if (!(sim = taper_sim_alloc(chain, ss, &err))) {
        fail(r, OPT_RUN_FAILED, "refused: %s", err.message);
        goto out;
    }
    taper_status st = taper_sim_run(sim, &err);
    if (s.stopped && !stop_requested(pb)) {
        fail(r, OPT_RUN_FAILED, "sampling: %s", s.why);
        goto out;
    }
    if (st == TAPER_EINTERRUPTED && stop_requested(pb)) {
        fail(r, OPT_RUN_INTERRUPTED, "interrupted");
        goto out;
    }
    if (st != TAPER_OK) {
        fail(r, OPT_RUN_FAILED, "%s", err.message);
        goto out;
    }
    if (!trusted(sim, &at, r)) goto out;
    if (data && data->form != MEAS_GRANULES && s.taken < pb->plan->n_times) {
        fail(r, OPT_RUN_FAILED, "the run ended at t = %g (rescaled) before the measured time %g",
             taper_sim_statistic(sim, TAPER_STAT_T_FINAL), pb->plan->times[s.taken]);
        goto out;
    }
    if (data && data->form == MEAS_GRANULES) read_granules(pb, sim, chain, &units, r);
    if (pb->objective) {
        const opt_objective *o = pb->objective;
        r->objective = o->statistic >= 0
                           ? taper_sim_statistic(sim, (taper_statistic)o->statistic) *
                                 scene_unit(&at, o->dim)
                           : observable(sim, chain, &at, o->observable, o->granule);
        if (isnan(r->objective))
            fail(r, OPT_RUN_FAILED, "%s is nan in this run (the run did not find it: a wall the "
                 "pulse never reached needs t_end)", o->name);
    }
    goto out;
nomem:
    fail(r, OPT_RUN_FAILED, "out of memory");
out:
    if (r->status != OPT_RUN_OK) {
        free(r->model);
        r->model = NULL;
        r->n_model = 0;
    }
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    free(times);
    free(s.x);
    free(s.v);
    free(s.f);
    scene_free(sc);
}

/* ---- batches ---------------------------------------------------------------------------- */

typedef struct batch {
    const opt_problem *pb;
    const double *values;
    size_t p;
    size_t *todo;
    opt_result *r;
} batch;

static void compute(size_t i, void *data)
{
    batch *b = data;
    size_t k = b->todo[i];
    opt_evaluate(b->pb, b->values + k * b->p, &b->r[k]);
}

/* The m points todo of values, by pb->runner: gathered into rows of their
 * own, and their results put back in place. */
static void run_elsewhere(const opt_problem *pb, size_t m, const double *values, const size_t *todo,
                          opt_result *r)
{
    const size_t p = pb->space->n;
    double *rows = malloc(m * (p ? p : 1) * sizeof *rows);
    opt_result *got = calloc(m, sizeof *got);
    if (!rows || !got) {
        for (size_t t = 0; t < m; t++) fail(&r[todo[t]], OPT_RUN_FAILED, "out of memory");
        free(rows);
        free(got);
        return;
    }
    for (size_t t = 0; t < m; t++) memcpy(rows + t * p, values + todo[t] * p, p * sizeof *rows);
    pb->runner.run(pb, m, rows, got, pb->runner.user);
    for (size_t t = 0; t < m; t++) r[todo[t]] = got[t]; /* moved, not copied */
    free(rows);
    free(got);
}

int opt_evaluate_batch(opt_problem *pb, size_t n, const double *values, opt_result *r)
{
    const size_t p = pb->space->n;
    size_t *todo = malloc((n ? n : 1) * sizeof *todo), m = 0;
    size_t *twin = malloc((n ? n : 1) * sizeof *twin); /* a point given earlier in the batch */
    int interrupted = 0;
    memset(r, 0, n * sizeof *r);
    if (!todo || !twin) {
        for (size_t i = 0; i < n; i++) fail(&r[i], OPT_RUN_FAILED, "out of memory");
        free(todo);
        free(twin);
        return 0;
    }
    for (size_t i = 0; i < n; i++) {
        const opt_result *known = opt_journal_find(pb->journal, values + i * p);
        twin[i] = SIZE_MAX;
        for (size_t j = 0; !known && j < m && twin[i] == SIZE_MAX; j++)
            if (memcmp(values + todo[j] * p, values + i * p, p * sizeof *values) == 0)
                twin[i] = todo[j];
        if (known) {
            if (opt_result_copy(&r[i], known) != 0) fail(&r[i], OPT_RUN_FAILED, "out of memory");
            r[i].reused = 1;
            pb->reused++;
        } else if (twin[i] == SIZE_MAX) {
            todo[m++] = i;
        }
    }
    batch b = {.pb = pb, .values = values, .p = p, .todo = todo, .r = r};
    if (m && pb->runner.run)
        run_elsewhere(pb, m, values, todo, r);
    else if (m)
        parallel_for(m, pb->threads, compute, &b);
    for (size_t t = 0; t < m; t++) {
        opt_result *res = &r[todo[t]];
        if (res->status == OPT_RUN_INTERRUPTED) {
            interrupted = 1;
            continue;
        }
        pb->computed++;
        double summary = pb->summary ? pb->summary(res, pb->summary_user) : res->objective;
        char *msg = NULL;
        if (pb->journal && opt_journal_add(pb->journal, values + todo[t] * p, res, summary, &msg) != 0 &&
            !pb->journal_message) {
            /* The run stands; its record is lost, and the optimiser says so. */
            pb->journal_message = msg;
            msg = NULL;
        }
        free(msg);
    }
    for (size_t i = 0; i < n; i++)
        if (twin[i] != SIZE_MAX) {
            if (opt_result_copy(&r[i], &r[twin[i]]) != 0) fail(&r[i], OPT_RUN_FAILED, "out of memory");
            r[i].reused = 1;
        }
    free(todo);
    free(twin);
    return interrupted;
}
