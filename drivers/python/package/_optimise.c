/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _optimise.c -- taper.calibrate() and taper.design() (_optimise.h).
 *
 * The optimiser runs on a thread of its own, its runs on further threads
 * (&output threads), all without the GIL.  The calling thread waits for it
 * and every CHECK_INTERVAL takes the GIL to run Python's signal handlers
 * (PyErr_CheckSignals runs them on the main thread only, which is why the
 * runs' own monitors cannot): Ctrl-C then stops every run at its next
 * event, the optimiser returns, and KeyboardInterrupt propagates.
 */
#include "_optimise.h"

#include "_scene.h"

#include "optimise/calibrate.h"
#include "optimise/design.h"
#include "scene/scene.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CHECK_INTERVAL 0.1 /* seconds between looks for Ctrl-C */

/* ---- the optimiser on its own thread ----------------------------------------------- */

typedef struct job {
    calibration *c;           /* one of the two */
    design_problem *d;
    opt_options o;
    opt_outcome outcome;
    atomic_int stop;          /* set by the waiting thread on Ctrl-C */
    atomic_int done;
} job;

static int stop_requested(void *user) { return atomic_load(&((job *)user)->stop); }

static void *work(void *arg)
{
    job *j = arg;
    if (j->c) {
        j->outcome = calibration_run(j->c, &j->o);
    } else {
        j->outcome = design_run(j->d, &j->o);
        if (j->outcome == OPT_CONVERGED || j->outcome == OPT_NOT_CONVERGED)
            if (design_profiles(j->d, &j->o) == OPT_INTERRUPTED) j->outcome = OPT_INTERRUPTED;
    }
    atomic_store(&j->done, 1);
    return NULL;
}

/* Runs the job, the GIL released; 0, or -1 with KeyboardInterrupt (or a
 * signal handler's exception) set. */
static int run_job(job *j)
{
    j->o.stop = stop_requested;
    j->o.stop_user = j;
    pthread_t tid;
    int interrupted = 0, threaded;
    Py_BEGIN_ALLOW_THREADS
    threaded = pthread_create(&tid, NULL, work, j) == 0;
    Py_END_ALLOW_THREADS
    if (!threaded) {
        /* no thread to be had: here, without Ctrl-C */
        Py_BEGIN_ALLOW_THREADS
        work(j);
        Py_END_ALLOW_THREADS
        return 0;
    }
    while (!atomic_load(&j->done)) {
        Py_BEGIN_ALLOW_THREADS
        struct timespec ts = {.tv_sec = 0, .tv_nsec = (long)(CHECK_INTERVAL * 1e9)};
        for (int k = 0; k < 10 && !atomic_load(&j->done); k++) {
            struct timespec part = {.tv_sec = 0, .tv_nsec = ts.tv_nsec / 10};
            nanosleep(&part, NULL);
        }
        Py_END_ALLOW_THREADS
        if (!interrupted && PyErr_CheckSignals() < 0) {
            interrupted = 1;
            atomic_store(&j->stop, 1);
        }
    }
    Py_BEGIN_ALLOW_THREADS
    pthread_join(tid, NULL);
    Py_END_ALLOW_THREADS
    return interrupted ? -1 : 0;
}

/* ---- results ------------------------------------------------------------------------- */

static const char *outcome_name(opt_outcome o)
{
    switch (o) {
    case OPT_CONVERGED: return "converged";
    case OPT_NOT_CONVERGED: return "not converged";
    case OPT_INTERRUPTED: return "interrupted";
    case OPT_FAILED: return "failed";
    }
    return "?";
}

static PyObject *str_or_none(const char *s)
{
    return s ? PyUnicode_DecodeUTF8(s, (Py_ssize_t)strlen(s), "replace") : Py_NewRef(Py_None);
}

/* The free settings: names, units, bounds, start. */
static int put_space(PyObject *d, const opt_space *s)
{
    PyObject *names = PyList_New(0), *units = PyDict_New(), *bounds = PyDict_New(),
             *start = PyDict_New();
    for (size_t i = 0; names && units && bounds && start && i < s->n; i++) {
        const opt_param *p = &s->p[i];
        PyObject *name = PyUnicode_FromString(p->name);
        if (!name || PyList_Append(names, name) < 0 ||
            core_put(units, p->name, str_or_none(p->unit)) < 0 ||
            core_put(bounds, p->name, Py_BuildValue("(dd)", p->lower, p->upper)) < 0 ||
            core_put(start, p->name, PyFloat_FromDouble(p->start)) < 0) {
            Py_XDECREF(name);
            Py_CLEAR(names);
            break;
        }
        Py_DECREF(name);
    }
    if (!names || !units || !bounds || !start) {
        Py_XDECREF(names);
        Py_XDECREF(units);
        Py_XDECREF(bounds);
        Py_XDECREF(start);
        return -1;
    }
    PyObject *t = PyList_AsTuple(names);
    Py_DECREF(names);
    if (core_put(d, "names", t) < 0 || core_put(d, "units", units) < 0 ||
        core_put(d, "bounds", bounds) < 0 || core_put(d, "start", start) < 0)
        return -1;
    return 0;
}

/* {name: values[i]} */
static PyObject *by_name(const opt_space *s, const double *values)
{
    PyObject *d = PyDict_New();
    for (size_t i = 0; d && i < s->n; i++)
        if (core_put(d, s->p[i].name, PyFloat_FromDouble(values[i])) < 0) Py_CLEAR(d);
    return d;
}

static PyObject *bounds_hit(const opt_space *s, const int *at)
{
    static const char *const words[] = {"", "lower", "upper"};
    PyObject *d = PyDict_New();
    for (size_t i = 0; d && i < s->n; i++)
        if (at[i] && core_put(d, s->p[i].name, PyUnicode_FromString(words[at[i]])) < 0)
            Py_CLEAR(d);
    return d;
}

/* The scene at values, as a namelist (without &calibrate or &design): it
 * reproduces the optimum's run; None if refused. */
static PyObject *scene_at(const opt_space *s, const double *values)
{
    char *msg = NULL, *text = NULL;
    size_t len = 0;
    scene *sc = opt_scene_at(s, values, &msg);
    free(msg);
    if (!sc) return Py_NewRef(Py_None);
    FILE *fp = open_memstream(&text, &len);
    if (fp) {
        scene_write(sc, fp, 0);
        fclose(fp);
    }
    scene_free(sc);
    PyObject *o = text ? PyUnicode_DecodeUTF8(text, (Py_ssize_t)len, "replace") : PyErr_NoMemory();
    free(text);
    return o;
}

/* Every run of the journal: {"status": [...], name: array, ..., key: array}. */
static PyObject *evaluations(const opt_space *s, const opt_journal *j, const char *key)
{
    size_t n = opt_journal_count(j);
    PyObject *d = PyDict_New(), *status = PyList_New((Py_ssize_t)n);
    double *col = malloc((n ? n : 1) * sizeof *col);
    if (!d || !status || !col) goto fail;
    for (size_t r = 0; r < n; r++) {
        PyObject *st = PyUnicode_FromString(opt_journal_result(j, r)->status == 0 ? "ok" : "failed");
        if (!st) goto fail;
        PyList_SET_ITEM(status, (Py_ssize_t)r, st);
    }
    int rc = core_put(d, "status", status);
    status = NULL;
    if (rc < 0) goto fail;
    for (size_t i = 0; i < s->n; i++) {
        for (size_t r = 0; r < n; r++) col[r] = opt_journal_point(j, r)[i];
        if (core_put(d, s->p[i].name, core_double_array(col, n)) < 0) goto fail;
    }
    for (size_t r = 0; r < n; r++) {
        const opt_result *res = opt_journal_result(j, r);
        col[r] = res->status == 0 ? res->objective : NAN;
    }
    if (core_put(d, key, core_double_array(col, n)) < 0) goto fail;
    free(col);
    return d;
fail:
    free(col);
    Py_XDECREF(status);
    Py_XDECREF(d);
    return NULL;
}

/* A problem of the keywords: InvalidArgumentError naming the keyword. */
static PyObject *raise_opt_error(opt_error *e)
{
    core_raise(core_InvalidArgumentError, e->message ? e->message : "out of memory",
               TAPER_EINVAL, e->keyword, e->message ? e->message : "out of memory");
    opt_error_clear(e);
    return NULL;
}

/* The outcomes that leave no result: an exception. */
static int raise_outcome(opt_outcome outcome, const char *reason)
{
    if (outcome != OPT_FAILED) return 0;
    core_raise(core_TaperError, reason ? reason : "failed", TAPER_ESOLVER, NULL,
               reason ? reason : "failed");
    return -1;
}

/* The measurements and the fit at them, point by point. */
static int put_points(PyObject *d, const calibration *c)
{
    const measurements *m = c->data;
    double *t = malloc((m->n ? m->n : 1) * sizeof *t), *g = malloc((m->n ? m->n : 1) * sizeof *g);
    double *v = malloc((m->n ? m->n : 1) * sizeof *v);
    PyObject *q = PyList_New((Py_ssize_t)m->n);
    int rc = -1;
    if (!t || !g || !v || !q) goto out;
    for (size_t i = 0; i < m->n; i++) {
        t[i] = m->points[i].t;
        g[i] = (double)m->points[i].granule;
        v[i] = m->points[i].value;
        PyObject *name = PyUnicode_FromString(meas_quantity_name(m->points[i].q));
        if (!name) goto out;
        PyList_SET_ITEM(q, (Py_ssize_t)i, name);
    }
    if (core_put(d, "t", core_double_array(t, m->n)) < 0 ||
        core_put(d, "granule", core_double_array(g, m->n)) < 0 ||
        core_put(d, "measured", core_double_array(v, m->n)) < 0 ||
        core_put(d, "fitted", core_double_array(c->fitted, m->n)) < 0 ||
        core_put(d, "weight", core_double_array(c->w, m->n)) < 0) goto out;
    rc = core_put(d, "quantity", q);
    q = NULL;
out:
    Py_XDECREF(q);
    free(t);
    free(g);
    free(v);
    return rc;
}

static unsigned threads_of(const scene *sc) { return (unsigned)scene_cfg(sc)->output.threads; }

PyObject *pyopt_calibrate(PyObject *args, PyObject *kwargs)
{
    scene *sc = pyscene_scene(PYSCENE_CALIBRATE, args, kwargs);
    if (!sc) return NULL;
    PyObject *d = NULL;
    if (!scene_cfg(sc)->calibrate.data[0]) {
        PyErr_SetString(PyExc_TypeError, "calibrate() needs data: the file of measurements");
        scene_free(sc);
        return NULL;
    }
    opt_error e;
    calibration *c;
    Py_BEGIN_ALLOW_THREADS
    c = calibration_new(sc, &e);
    Py_END_ALLOW_THREADS
    if (!c) {
        scene_free(sc);
        return raise_opt_error(&e);
    }
    /* a journal in memory, kept to list every run */
    job j = {.c = c, .o = {.threads = threads_of(sc)}};
    if (run_job(&j) != 0 || raise_outcome(j.outcome, c->reason) != 0) goto out;
    if (j.outcome == OPT_INTERRUPTED) { /* stopped without Ctrl-C here: a handler's stop */
        PyErr_SetString(PyExc_KeyboardInterrupt, c->reason ? c->reason : "interrupted");
        goto out;
    }
    const size_t p = c->space->n;
    npy_intp dims[2] = {(npy_intp)p, (npy_intp)p};
    PyObject *corr = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!corr) goto out;
    memcpy(PyArray_DATA((PyArrayObject *)corr), c->correlation, p * p * sizeof(double));
    if (!(d = PyDict_New()) || put_space(d, c->space) < 0 ||
        core_put(d, "values", by_name(c->space, c->value)) < 0 ||
        core_put(d, "errors", by_name(c->space, c->error)) < 0 ||
        core_put(d, "correlation", corr) < 0 ||
        core_put(d, "at_bound", bounds_hit(c->space, c->at_bound)) < 0 ||
        core_put(d, "chi2", PyFloat_FromDouble(c->chi2)) < 0 ||
        core_put(d, "dof", PyLong_FromSize_t(c->dof)) < 0 ||
        core_put(d, "absolute_errors", PyBool_FromLong(c->absolute)) < 0 ||
        core_put(d, "iterations", PyLong_FromSize_t(c->iterations)) < 0 ||
        core_put(d, "runs", PyLong_FromSize_t(c->runs)) < 0 ||
        core_put(d, "outcome", PyUnicode_FromString(outcome_name(j.outcome))) < 0 ||
        core_put(d, "reason", str_or_none(c->reason)) < 0 ||
        core_put(d, "data", str_or_none(c->data_path)) < 0 ||
        core_put(d, "si", PyBool_FromLong(c->data->si)) < 0 ||
        put_points(d, c) < 0 ||
        core_put(d, "scene", scene_at(c->space, c->value)) < 0)
        Py_CLEAR(d);
out:
    calibration_free(c);
    scene_free(sc);
    return d;
}

PyObject *pyopt_design(PyObject *args, PyObject *kwargs)
{
    scene *sc = pyscene_scene(PYSCENE_DESIGN, args, kwargs);
    if (!sc) return NULL;
    PyObject *d = NULL;
    if (!scene_cfg(sc)->design.objective[0]) {
        PyErr_SetString(PyExc_TypeError, "design() needs an objective: a result of the run");
        scene_free(sc);
        return NULL;
    }
    opt_error e;
    design_problem *dp;
    Py_BEGIN_ALLOW_THREADS
    dp = design_new(sc, &e);
    Py_END_ALLOW_THREADS
    if (!dp) {
        scene_free(sc);
        return raise_opt_error(&e);
    }
    job j = {.d = dp, .o = {.threads = threads_of(sc)}};
    if (run_job(&j) != 0 || raise_outcome(j.outcome, dp->reason) != 0) goto out;
    if (j.outcome == OPT_INTERRUPTED) {
        PyErr_SetString(PyExc_KeyboardInterrupt, dp->reason ? dp->reason : "interrupted");
        goto out;
    }
    PyObject *profiles = PyDict_New();
    const size_t m = dp->profile_points;
    for (size_t i = 0; profiles && m && i < dp->space->n; i++)
        if (core_put(profiles, dp->space->p[i].name,
                     Py_BuildValue("(NN)", core_double_array(dp->profile_value + i * m, m),
                                   core_double_array(dp->profile_objective + i * m, m))) < 0)
            Py_CLEAR(profiles);
    if (!profiles || !(d = PyDict_New()) || core_put(d, "profiles", profiles) < 0) {
        if (!d) Py_XDECREF(profiles);
        Py_CLEAR(d);
        goto out;
    }
    if (put_space(d, dp->space) < 0 ||
        core_put(d, "values", by_name(dp->space, dp->best)) < 0 ||
        core_put(d, "objective", PyFloat_FromDouble(dp->best_objective)) < 0 ||
        core_put(d, "objective_name", PyUnicode_FromString(dp->objective.name)) < 0 ||
        core_put(d, "objective_unit", str_or_none(dp->unit)) < 0 ||
        core_put(d, "goal", PyUnicode_FromString(dp->maximise ? "maximise" : "minimise")) < 0 ||
        core_put(d, "at_bound", bounds_hit(dp->space, dp->at_bound)) < 0 ||
        core_put(d, "iterations", PyLong_FromSize_t(dp->iterations)) < 0 ||
        core_put(d, "runs", PyLong_FromSize_t(dp->runs)) < 0 ||
        core_put(d, "profile_runs", PyLong_FromSize_t(dp->profile_runs)) < 0 ||
        core_put(d, "outcome", PyUnicode_FromString(outcome_name(j.outcome))) < 0 ||
        core_put(d, "reason", str_or_none(dp->reason)) < 0 ||
        core_put(d, "evaluations", evaluations(dp->space, dp->pb.journal, dp->objective.name)) < 0 ||
        core_put(d, "scene", scene_at(dp->space, dp->best)) < 0)
        Py_CLEAR(d);
out:
    design_free(dp);
    scene_free(sc);
    return d;
}
