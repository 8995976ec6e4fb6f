/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _core.c -- the compiled half of the Python package `taper`: libtaper
 * through its public header (include/taper.h), written with the CPython C
 * API and the numpy C API.  The pure-Python half (__init__.py, result.py)
 * wraps what this returns into taper.Result objects; the module itself
 * (its functions, exceptions and names) is defined in _module.c.
 *
 * simulate(), theory(), chain() and run_scene() are scenes of the driver's
 * scene module, built and read in _scene.c: the keyword arguments are the
 * scene's variables, checked and converted there.  This file runs what a
 * scene asks for (core_run, core_chain), and holds the calls that are not
 * scenes: fit(), the asymptotic laws, collision_time(), the names.  A value
 * the library refuses becomes taper.InvalidArgumentError (a ValueError)
 * naming taper_error.field; a value of the wrong Python type a TypeError
 * naming the argument.
 *
 * Threads: libtaper has no global state, so every call builds its own chain
 * and sim and runs them with the GIL released (Py_BEGIN_ALLOW_THREADS):
 * Python threads run chains in parallel.
 *
 * Ctrl-C: Python's C-level SIGINT handler only records the signal; the
 * Python handler (KeyboardInterrupt) runs when the main thread calls
 * PyErr_CheckSignals, which needs the GIL.  The library calls our monitor
 * on the thread building the chain or running the sim or the theory (after
 * every pulse event and sample, at least every ~0.05 s of integration, every
 * 65536 granules of the chain and of the theory: taper.h); at most every CHECK_INTERVAL seconds the monitor takes
 * the GIL (PyGILState_Ensure), calls PyErr_CheckSignals, and asks the
 * library to stop if it raised.  The run then ends with TAPER_EINTERRUPTED,
 * the partial sim is freed, and the KeyboardInterrupt propagates: no
 * half-built result is returned.  Taking the GIL only every CHECK_INTERVAL
 * keeps threads from contending for it.
 *
 * Nothing is printed: the library's log messages (taper_solver_spec_set_log)
 * are collected and returned (level >= 1 as warnings).
 */
#include "_core.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Seconds between two looks at Python's pending signals during a run. */
#define CHECK_INTERVAL 0.05
/* Seconds between two calls of a run's progress callable (taper.simulate's
 * progress=): often enough for a bar, rarely enough to cost nothing. */
#define PROGRESS_INTERVAL 0.1

PyObject *core_TaperError, *core_InvalidArgumentError, *core_SceneError;

/* ---- errors ---------------------------------------------------------------- */

static const char *status_id(taper_status s)
{
    const char *name = taper_status_name(s);
    return name ? name : "unknown";
}

void core_raise(PyObject *cls, const char *text, taper_status status, const char *field,
                const char *message)
{
    PyObject *exc = PyObject_CallFunction(cls, "s", text);
    if (!exc) return;
    PyObject *f = field ? PyUnicode_FromString(field) : Py_NewRef(Py_None);
    PyObject *st = PyUnicode_FromString(status_id(status));
    PyObject *m = PyUnicode_FromString(message ? message : "");
    if (f && st && m && PyObject_SetAttrString(exc, "field", f) == 0 &&
        PyObject_SetAttrString(exc, "status", st) == 0 &&
        PyObject_SetAttrString(exc, "message", m) == 0)
        PyErr_SetObject(cls, exc);
    Py_XDECREF(f);
    Py_XDECREF(st);
    Py_XDECREF(m);
    Py_DECREF(exc);
}

/* The exception carries the library's message, prefixed with the argument
 * at fault unless the message already starts with it. */
PyObject *core_raise_library(const taper_error *err)
{
    if (err->status == TAPER_ENOMEM) return PyErr_NoMemory();
    const char *msg = err->message[0] ? err->message : taper_strerror(err->status);
    PyObject *cls = (err->status == TAPER_EINVAL || err->status == TAPER_ERANGE)
                        ? core_InvalidArgumentError : core_TaperError;
    if (err->field && strncmp(msg, err->field, strlen(err->field)) != 0) {
        PyObject *text = PyUnicode_FromFormat("%s: %s", err->field, msg);
        if (!text) return NULL;
        core_raise(cls, PyUnicode_AsUTF8(text), err->status, err->field, err->message);
        Py_DECREF(text);
    } else {
        core_raise(cls, msg, err->status, err->field, err->message);
    }
    return NULL;
}

/* ---- Python values ----------------------------------------------------------- */

static PyObject *type_error(const char *name, const char *want, PyObject *value)
{
    PyErr_Format(PyExc_TypeError, "%s must be %s, not %.100s", name, want, Py_TYPE(value)->tp_name);
    return NULL;
}

int core_is_bool(PyObject *v)
{
    return PyBool_Check(v) || PyArray_IsScalar(v, Bool);
}

int core_get_real(const char *name, PyObject *v, double *out)
{
    if (core_is_bool(v) || PyUnicode_Check(v) || PyBytes_Check(v) || PyComplex_Check(v) ||
        PyArray_IsScalar(v, ComplexFloating) ||
        !(PyFloat_Check(v) || PyLong_Check(v) || PyIndex_Check(v) || PyNumber_Check(v))) {
        type_error(name, "a real number", v);
        return -1;
    }
    double x = PyFloat_AsDouble(v);
    if (x == -1.0 && PyErr_Occurred()) {
        if (PyErr_ExceptionMatches(PyExc_TypeError)) {
            PyErr_Clear();
            type_error(name, "a real number", v);
        }
        return -1;
    }
    *out = x;
    return 0;
}

int core_get_integer(const char *name, PyObject *v, long long lo, long long hi, long long *out)
{
    if (core_is_bool(v) || !PyIndex_Check(v)) {
        type_error(name, "an integer", v);
        return -1;
    }
    PyObject *i = PyNumber_Index(v);
    if (!i) return -1;
    int overflow = 0;
    long long x = PyLong_AsLongLongAndOverflow(i, &overflow);
    Py_DECREF(i);
    if (x == -1 && PyErr_Occurred()) return -1;
    if (overflow || x < lo || x > hi) {
        PyObject *text = PyUnicode_FromFormat("%s = %S is out of range", name, v);
        if (text) core_raise(core_InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, name,
                             PyUnicode_AsUTF8(text));
        Py_XDECREF(text);
        return -1;
    }
    *out = x;
    return 0;
}

int core_get_bool(const char *name, PyObject *v, int *out)
{
    if (!core_is_bool(v)) {
        type_error(name, "a bool", v);
        return -1;
    }
    int t = PyObject_IsTrue(v);
    if (t < 0) return -1;
    *out = t;
    return 0;
}

int core_get_str(const char *name, PyObject *v, const char **out)
{
    if (!PyUnicode_Check(v)) {
        type_error(name, "a str", v);
        return -1;
    }
    Py_ssize_t size = 0;
    const char *s = PyUnicode_AsUTF8AndSize(v, &size);
    if (!s) return -1;
    if (strlen(s) != (size_t)size) {
        PyObject *text = PyUnicode_FromFormat("%s: must not contain NUL characters", name);
        if (text) core_raise(core_InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, name,
                             "must not contain NUL characters");
        Py_XDECREF(text);
        return -1;
    }
    *out = s;
    return 0;
}

PyArrayObject *core_real_vector(const char *name, PyObject *v)
{
    if (PyUnicode_Check(v) || PyBytes_Check(v) || core_is_bool(v)) {
        type_error(name, "a sequence of real numbers", v);
        return NULL;
    }
    /* numpy reads None in a list as nan: a hole in the caller's data would
     * become a value out of range ("radius nan"), not the None it is. */
    if (PyList_Check(v) || PyTuple_Check(v)) {
        Py_ssize_t n = PySequence_Fast_GET_SIZE(v);
        for (Py_ssize_t i = 0; i < n; i++)
            if (PySequence_Fast_GET_ITEM(v, i) == Py_None) {
                PyErr_Format(PyExc_TypeError, "%s must be a sequence of real numbers, but "
                             "element %zd (from 0) is None", name, i);
                return NULL;
            }
    }
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(v, NPY_DOUBLE, 0, 0, NPY_ARRAY_CARRAY_RO);
    if (!a) {
        if (PyErr_ExceptionMatches(PyExc_TypeError) || PyErr_ExceptionMatches(PyExc_ValueError) ||
            PyErr_ExceptionMatches(PyExc_OverflowError)) {
            PyErr_Clear();
            type_error(name, "a sequence of real numbers", v);
        }
        return NULL;
    }
    if (PyArray_NDIM(a) != 1) {
        Py_DECREF(a);
        PyErr_Format(PyExc_TypeError, "%s must be a one-dimensional sequence of real numbers", name);
        return NULL;
    }
    return a;
}

/* ---- results -------------------------------------------------------------- */

/* Values between two looks at Ctrl-C while a long column is copied with
 * the GIL held: 2 MB, about a millisecond (a column of 10^7 granules, 80 MB
 * written to fresh pages, took 0.05 s and up to 0.2 s on a loaded machine
 * in one piece). */
#define COPY_BLOCK ((size_t)1 << 18)

int core_copy_checked(double *dst, const double *src, size_t n)
{
    for (size_t at = 0; at < n; at += COPY_BLOCK) {
        if (at && PyErr_CheckSignals() < 0) return -1;
        size_t m = n - at < COPY_BLOCK ? n - at : COPY_BLOCK;
        if (src) memcpy(dst + at, src + at, m * sizeof(double));
        else for (size_t i = at; i < at + m; i++) dst[i] = NAN;
    }
    return 0;
}

PyObject *core_double_array(const double *src, size_t n)
{
    if (n >= COPY_BLOCK && PyErr_CheckSignals() < 0) return NULL;
    npy_intp dim = (npy_intp)n;
    PyObject *a = PyArray_SimpleNew(1, &dim, NPY_DOUBLE);
    if (!a) return NULL;
    if (core_copy_checked(PyArray_DATA((PyArrayObject *)a), src, n) < 0) {
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

int core_put(PyObject *dict, const char *key, PyObject *value)
{
    if (!value) return -1;
    int rc = PyDict_SetItemString(dict, key, value);
    Py_DECREF(value);
    return rc;
}

/* k R m X0 of the chain. */
static int chain_columns(PyObject *cols, const taper_chain *chain)
{
    size_t n = taper_chain_size(chain);
    npy_intp dim = (npy_intp)n;
    PyObject *k = PyArray_SimpleNew(1, &dim, NPY_INT64);
    if (!k) return -1;
    int64_t *kd = PyArray_DATA((PyArrayObject *)k);
    for (size_t i = 0; i < n; i++) {
        if (i % COPY_BLOCK == 0 && i && PyErr_CheckSignals() < 0) {
            Py_DECREF(k);
            return -1;
        }
        kd[i] = (int64_t)(i + 1);
    }
    if (core_put(cols, "k", k) < 0) return -1;
    if (core_put(cols, "R", core_double_array(taper_chain_radius(chain), n)) < 0) return -1;
    if (core_put(cols, "m", core_double_array(taper_chain_mass(chain), n)) < 0) return -1;
    if (core_put(cols, "X0", core_double_array(taper_chain_rest_position(chain), n)) < 0) return -1;
    return 0;
}

/* The theory's columns as granules.tsv names them: "theory_" and the
 * quantity's taper_theory_quantity_name, mu left out (it has no column;
 * taper.chain() gives it).  Where the binary-collision theory does not
 * describe the chain (taper_chain_theory_note) they are NaN, as the
 * driver writes them. */
static int theory_columns(PyObject *cols, const double *const *q, size_t n, int blank)
{
    for (int i = 0; taper_theory_quantity_name((taper_theory_quantity)i); i++) {
        if (i == TAPER_THEORY_MU) continue;
        char key[64];
        snprintf(key, sizeof key, "theory_%s", taper_theory_quantity_name((taper_theory_quantity)i));
        if (core_put(cols, key, core_double_array(blank ? NULL : q[i], n)) < 0) return -1;
    }
    return 0;
}

/* ---- a run ------------------------------------------------------------------ */

/* What happens during a run, collected without the GIL. */
typedef struct run_ctx {
    double last_check;      /* monotonic seconds of the last signal check   */
    int interrupted;        /* a Python exception is pending in the thread  */
    char **warnings;        /* copies of the level >= 1 log messages        */
    size_t n_warnings, cap;
    size_t n_dropped;       /* warnings lost to a failed allocation         */
    /* samples (&sensors interval): times, displacements and velocities (N per
     * sample), contact forces (N + 1 per sample) */
    size_t n_granules, n_samples, samples_cap;
    double *t, *x, *v, *force;
    int samples_failed;     /* out of memory: the run was stopped           */
    /* progress: the callable, when the run started and when it was last
     * called (monotonic seconds), the granule the run ends at, the factor
     * from the library's time to the scene's */
    PyObject *progress;
    double start, last_report;
    size_t target;
    double time_scale;
} run_ctx;

static double monotonic(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Calls ctx->progress(passed, target, t, rate) (the GIL held): rate in
 * granules per second of wall time since the run started.  -1 when it
 * raised (the exception stays set). */
static int report_progress(run_ctx *ctx, size_t passed, double t, double now)
{
    ctx->last_report = now;
    double elapsed = now - ctx->start;
    double rate = elapsed > 0.0 ? (double)passed / elapsed : 0.0;
    PyObject *r = PyObject_CallFunction(ctx->progress, "nndd", (Py_ssize_t)passed,
                                        (Py_ssize_t)ctx->target, t * ctx->time_scale, rate);
    Py_XDECREF(r);
    return r ? 0 : -1;
}

static int monitor(const taper_progress *progress, void *user)
{
    run_ctx *ctx = user;
    if (ctx->interrupted) return 1;
    ctx->target = progress->target;
    double now = monotonic();
    if (now - ctx->last_check < CHECK_INTERVAL) return 0;
    ctx->last_check = now;
    PyGILState_STATE g = PyGILState_Ensure();
    /* Runs the Python signal handlers (main thread only); on
     * KeyboardInterrupt the exception stays set in this thread's state
     * until the caller, holding the GIL again, returns NULL.  So does an
     * exception of the progress callable. */
    if (PyErr_CheckSignals() < 0) ctx->interrupted = 1;
    else if (ctx->progress && now - ctx->last_report >= PROGRESS_INTERVAL &&
             report_progress(ctx, progress->granule, progress->t, now) < 0)
        ctx->interrupted = 1;
    PyGILState_Release(g);
    return ctx->interrupted;
}

static void collect_log(int level, const char *message, void *user)
{
    run_ctx *ctx = user;
    if (level < 1 || !message) return;
    if (ctx->n_warnings == ctx->cap) {
        size_t cap = ctx->cap ? 2 * ctx->cap : 8;
        char **w = realloc(ctx->warnings, cap * sizeof *w);
        if (!w) {
            ctx->n_dropped++;
            return;
        }
        ctx->warnings = w;
        ctx->cap = cap;
    }
    char *copy = strdup(message);
    if (!copy) {
        ctx->n_dropped++;
        return;
    }
    ctx->warnings[ctx->n_warnings++] = copy;
}

static void ctx_free(run_ctx *ctx)
{
    for (size_t i = 0; i < ctx->n_warnings; i++) free(ctx->warnings[i]);
    free(ctx->warnings);
    free(ctx->t);
    free(ctx->x);
    free(ctx->v);
    free(ctx->force);
}

/* The sampler of a run with samples (without the GIL): copies the
 * state and forces at the sample time into growing buffers; stops the run
 * if they cannot grow. */
static int collect_sample(const taper_sim *sim, void *user)
{
    run_ctx *ctx = user;
    const size_t n = ctx->n_granules;
    if (ctx->n_samples == ctx->samples_cap) {
        size_t cap = ctx->samples_cap ? 2 * ctx->samples_cap : 64;
        double *t = realloc(ctx->t, cap * sizeof *t);
        if (t) ctx->t = t;
        double *x = t ? realloc(ctx->x, cap * n * sizeof *x) : NULL;
        if (x) ctx->x = x;
        double *v = x ? realloc(ctx->v, cap * n * sizeof *v) : NULL;
        if (v) ctx->v = v;
        double *f = v ? realloc(ctx->force, cap * (n + 1) * sizeof *f) : NULL;
        if (f) ctx->force = f;
        if (!f) {
            ctx->samples_failed = 1;
            return 1;
        }
        ctx->samples_cap = cap;
    }
    const size_t i = ctx->n_samples++;
    taper_error err;
    ctx->t[i] = taper_sim_time(sim);
    if (taper_sim_state(sim, ctx->x + i * n, ctx->v + i * n, &err) != TAPER_OK)
        for (size_t k = 0; k < n; k++) ctx->x[i * n + k] = ctx->v[i * n + k] = NAN;
    if (taper_sim_forces(sim, ctx->force + i * (n + 1), &err) != TAPER_OK)
        for (size_t k = 0; k <= n; k++) ctx->force[i * (n + 1) + k] = NAN;
    return 0;
}

/* {"t": (S,), "x": (S, N), "v": (S, N), "force": (S, N + 1)} of the samples. */
static PyObject *samples_dict(const run_ctx *ctx)
{
    const npy_intp s = (npy_intp)ctx->n_samples, n = (npy_intp)ctx->n_granules;
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    struct { const char *key; const double *src; npy_intp cols; } parts[] = {
        {"x", ctx->x, n}, {"v", ctx->v, n}, {"force", ctx->force, n + 1}};
    if (core_put(d, "t", core_double_array(ctx->t, (size_t)s)) < 0) goto fail;
    for (size_t j = 0; j < sizeof parts / sizeof parts[0]; j++) {
        npy_intp dims[2] = {s, parts[j].cols};
        PyObject *a = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
        if (!a) goto fail;
        if (s && core_copy_checked(PyArray_DATA((PyArrayObject *)a), parts[j].src,
                                   (size_t)(s * parts[j].cols)) < 0) {
            Py_DECREF(a);
            goto fail;
        }
        if (core_put(d, parts[j].key, a) < 0) goto fail;
    }
    return d;
fail:
    Py_DECREF(d);
    return NULL;
}

static PyObject *warnings_list(const run_ctx *ctx)
{
    PyObject *l = PyList_New(0);
    if (!l) return NULL;
    for (size_t i = 0; i < ctx->n_warnings; i++) {
        PyObject *s = PyUnicode_DecodeUTF8(ctx->warnings[i], (Py_ssize_t)strlen(ctx->warnings[i]),
                                           "replace");
        if (!s || PyList_Append(l, s) < 0) {
            Py_XDECREF(s);
            Py_DECREF(l);
            return NULL;
        }
        Py_DECREF(s);
    }
    if (ctx->n_dropped) {
        PyObject *s = PyUnicode_FromFormat("%zu further warnings lost (out of memory)",
                                           ctx->n_dropped);
        if (!s || PyList_Append(l, s) < 0) {
            Py_XDECREF(s);
            Py_DECREF(l);
            return NULL;
        }
        Py_DECREF(s);
    }
    return l;
}

/* The statistics, by taper_statistic_name: counts as int, times and errors
 * as float, complete as bool. */
static PyObject *stats_dict(const taper_sim *sim)
{
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    for (int i = 0; taper_statistic_name((taper_statistic)i); i++) {
        double x = taper_sim_statistic(sim, (taper_statistic)i);
        PyObject *v;
        if (i == TAPER_STAT_COMPLETE) v = PyBool_FromLong(x != 0);
        else if (i == TAPER_STAT_T_FINAL || i == TAPER_STAT_ENERGY_ERROR ||
                 i == TAPER_STAT_MOMENTUM_ERROR || i >= TAPER_STAT_ENERGY_INITIAL ||
                 !isfinite(x) || x != floor(x) ||
                 fabs(x) > 9.0e15)
            v = PyFloat_FromDouble(x);
        else v = PyLong_FromLongLong((long long)x);
        if (core_put(d, taper_statistic_name((taper_statistic)i), v) < 0) {
            Py_DECREF(d);
            return NULL;
        }
    }
    return d;
}

/* The chain of cs, built without the GIL, Ctrl-C looked for while it is
 * built (taper_chain_alloc_monitored: 10^7 granules take a fraction of a
 * second).  NULL with the exception set: the library's refusal, or
 * KeyboardInterrupt. */
static taper_chain *build_chain(const taper_chain_spec *cs)
{
    run_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.last_check = monotonic();
    taper_error err;
    taper_chain *chain;
    Py_BEGIN_ALLOW_THREADS
    chain = taper_chain_alloc_monitored(cs, monitor, &ctx, &err);
    Py_END_ALLOW_THREADS
    if (!chain && !ctx.interrupted) core_raise_library(&err);
    ctx_free(&ctx);
    return chain;
}

/* Builds the chain from cs and either the theory alone (ss NULL) or a full
 * run (_core.h). */
/* How long a run will last, before it starts: until t_end, and until the
 * pulse has passed the chain, when the binary-collision theory says (eq.
 * (19)); a chain it does not describe (losses, a load) by the
 * monodisperse pulse's 1.19 time units a granule (docs/physics.md,
 * Nesterenko's wave), with room.  The driver estimates its sensors' files
 * the same way (&output max_output). */
static double duration_estimate(const taper_sim *sim, size_t n, const taper_solver_spec *ss)
{
    const double *t = taper_sim_theory(sim, TAPER_THEORY_T);
    double pulse = 1.5 * (double)n;
    for (size_t k = n; k-- > 0;)
        if (t && isfinite(t[k])) {
            pulse = t[k];
            break;
        }
    return fmax(pulse, taper_solver_spec_t_end(ss));
}

/* Samples beyond sampling->max_bytes (3 N + 2 doubles each, to the run's
 * estimated end): InvalidArgumentError naming "interval", before the run. */
static int check_samples_size(const taper_sim *sim, size_t n, const taper_solver_spec *ss,
                              const core_sampling *sampling)
{
    if (sampling->max_bytes <= 0.0) return 0;
    const double duration = duration_estimate(sim, n, ss);
    const double samples = floor(duration / sampling->interval) + 1.0;
    const double bytes = samples * (3.0 * (double)n + 2.0) * sizeof(double);
    if (bytes <= sampling->max_bytes) return 0;
    char text[TAPER_MESSAGE_SIZE];
    snprintf(text, sizeof text,
             "the samples would take about %.2g bytes of memory (%.3g samples of 3 N + 2 "
             "values to t = %.4g%s%s, the pulse's crossing by the binary-collision theory or "
             "t_end), more than max_output = %g: give a longer interval, or raise max_output",
             bytes, samples, duration * sampling->time_scale, sampling->time_unit ? " " : "",
             sampling->time_unit ? sampling->time_unit : "", sampling->max_bytes);
    PyObject *full = PyUnicode_FromFormat("interval: %s", text);
    if (full) core_raise(core_InvalidArgumentError, PyUnicode_AsUTF8(full), TAPER_EINVAL,
                         "interval", text);
    Py_XDECREF(full);
    return -1;
}

PyObject *core_run(const taper_chain_spec *cs, taper_solver_spec *ss,
                   const core_sampling *sampling)
{
    const double interval = sampling ? sampling->interval : 0.0;
    taper_error err;
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    double *theory[TAPER_N_THEORY_QUANTITIES] = {NULL};
    double *columns[TAPER_N_THEORY_QUANTITIES] = {NULL}; /* theory only: cols' arrays */
    PyObject *out = NULL, *cols = NULL;
    run_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    taper_status rc = TAPER_OK;

    if (!(chain = build_chain(cs))) return NULL;
    const size_t n = taper_chain_size(chain);
    const char *note = taper_chain_theory_note(chain);

    /* Ctrl-C between the steps that hold the GIL (each column of 10^7
     * granules a copy of 80 MB: core_double_array looks before each). */
    if (PyErr_CheckSignals() < 0) goto fail;
    if (!(out = PyDict_New()) || !(cols = PyDict_New())) goto fail;
    if (chain_columns(cols, chain) < 0) goto fail;
    if (core_put(out, "theory_note", note ? PyUnicode_FromString(note) : Py_NewRef(Py_None)) < 0)
        goto fail;
    if (PyErr_CheckSignals() < 0) goto fail;

    if (!ss) {
        /* Theory only: taper_theory_compute, no integration, written straight
         * into the columns' arrays (no copy after it, which for 10^7
         * granules held the GIL, and Ctrl-C, for a second); mu has no
         * column. */
        for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) {
            if (i == TAPER_THEORY_MU) {
                if (!(theory[i] = malloc((n ? n : 1) * sizeof(double)))) {
                    PyErr_NoMemory();
                    goto fail;
                }
                continue;
            }
            char key[64];
            snprintf(key, sizeof key, "theory_%s",
                     taper_theory_quantity_name((taper_theory_quantity)i));
            npy_intp dim = (npy_intp)n;
            if (PyErr_CheckSignals() < 0) goto fail;
            PyObject *a = PyArray_SimpleNew(1, &dim, NPY_DOUBLE); /* every entry written below */
            if (core_put(cols, key, a) < 0) goto fail;
            columns[i] = PyArray_DATA((PyArrayObject *)a); /* cols holds it */
        }
        ctx.last_check = monotonic();
        Py_BEGIN_ALLOW_THREADS
        rc = taper_theory_compute_monitored(chain, columns[TAPER_THEORY_V], theory[TAPER_THEORY_MU],
                                            columns[TAPER_THEORY_T_RES], columns[TAPER_THEORY_T],
                                            monitor, &ctx, &err);
        Py_END_ALLOW_THREADS
        if (ctx.interrupted) goto fail; /* KeyboardInterrupt is set */
        if (rc != TAPER_OK) {
            core_raise_library(&err);
            goto fail;
        }
        if (core_put(out, "stats", PyDict_New()) < 0 ||
            core_put(out, "status", PyUnicode_FromString("ok")) < 0 ||
            core_put(out, "message", PyUnicode_FromString("")) < 0 ||
            core_put(out, "warnings", PyList_New(0)) < 0)
            goto fail;
    } else {
        taper_solver_spec_set_monitor(ss, monitor, &ctx);
        taper_solver_spec_set_log(ss, collect_log, &ctx);
        if (interval > 0.0) {
            ctx.n_granules = n;
            if (taper_solver_spec_set_sampler(ss, interval, collect_sample, &ctx, &err) != TAPER_OK) {
                core_raise_library(&err);
                goto fail;
            }
        }
        ctx.last_check = ctx.start = ctx.last_report = monotonic();
        ctx.progress = sampling ? sampling->progress : NULL;
        ctx.time_scale = sampling ? sampling->time_scale : 1.0;
        /* The library's target until its monitor says (taper_progress):
         * passes are timed up to the last contact, granule N - 1. */
        ctx.target = taper_solver_spec_last_granule(ss);
        if (ctx.target == 0 || ctx.target >= n) ctx.target = n - 1;

        Py_BEGIN_ALLOW_THREADS
        sim = taper_sim_alloc(chain, ss, &err); /* its theory asks the monitor too */
        Py_END_ALLOW_THREADS
        if (ctx.interrupted) goto fail; /* KeyboardInterrupt is set */
        if (!sim) {
            core_raise_library(&err);
            goto fail;
        }
        if (interval > 0.0 && check_samples_size(sim, n, ss, sampling) != 0) goto fail;
        Py_BEGIN_ALLOW_THREADS
        rc = taper_sim_run(sim, &err);
        Py_END_ALLOW_THREADS
        if (ctx.interrupted) goto fail; /* KeyboardInterrupt (or a handler's exception) is set */
        if (ctx.samples_failed) {
            PyErr_NoMemory();
            goto fail;
        }
        if (rc != TAPER_OK && rc != TAPER_ESOLVER && rc != TAPER_ELIMIT &&
            rc != TAPER_EINTERRUPTED) {
            core_raise_library(&err);
            goto fail;
        }
        /* The progress callable's last call: where the run ended. */
        if (ctx.progress &&
            report_progress(&ctx, (size_t)taper_sim_statistic(sim, TAPER_STAT_GRANULE_REACHED),
                            taper_sim_statistic(sim, TAPER_STAT_T_FINAL), monotonic()) < 0)
            goto fail;
        /* The observables under the library's names (granules.tsv's). */
        for (int i = 0; taper_observable_name((taper_observable)i); i++)
            if (core_put(cols, taper_observable_name((taper_observable)i),
                         core_double_array(taper_sim_observable(sim, (taper_observable)i), n)) < 0)
                goto fail;
        const double *th[TAPER_N_THEORY_QUANTITIES];
        for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++)
            th[i] = taper_sim_theory(sim, (taper_theory_quantity)i);
        if (theory_columns(cols, th, n, note != NULL) < 0) goto fail;
        /* The state where the run ended. */
        PyObject *x = core_double_array(NULL, n), *v = core_double_array(NULL, n);
        if (!x || !v) {
            Py_XDECREF(x);
            Py_XDECREF(v);
            goto fail;
        }
        taper_error serr;
        taper_sim_state(sim, PyArray_DATA((PyArrayObject *)x), PyArray_DATA((PyArrayObject *)v),
                        &serr);
        if (core_put(out, "x_final", x) < 0 || core_put(out, "v_final", v) < 0) goto fail;
        if (interval > 0.0 && core_put(out, "samples", samples_dict(&ctx)) < 0) goto fail;
        if (core_put(out, "stats", stats_dict(sim)) < 0 ||
            core_put(out, "status", PyUnicode_FromString(status_id(rc))) < 0 ||
            core_put(out, "message", PyUnicode_FromString(rc == TAPER_OK ? "" : err.message)) < 0 ||
            core_put(out, "warnings", warnings_list(&ctx)) < 0)
            goto fail;
    }
    if (PyDict_SetItemString(out, "columns", cols) < 0) goto fail;
    Py_DECREF(cols);
    taper_sim_free(sim);
    taper_chain_free(chain);
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) free(theory[i]);
    ctx_free(&ctx);
    return out;
fail:
    Py_XDECREF(out);
    Py_XDECREF(cols);
    taper_sim_free(sim);
    taper_chain_free(chain);
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) free(theory[i]);
    ctx_free(&ctx);
    return NULL;
}

PyObject *core_chain(const taper_chain_spec *cs)
{
    taper_error err;
    taper_chain *chain = build_chain(cs);
    if (!chain) return NULL;
    size_t n = taper_chain_size(chain);
    PyObject *out = PyDict_New(), *cols = PyDict_New(), *mu = NULL;
    if (!out || !cols) goto fail;
    if (chain_columns(cols, chain) < 0) goto fail;
    if (core_put(cols, "r", core_double_array(taper_chain_contact(chain), n)) < 0) goto fail;
    if (!(mu = core_double_array(NULL, n))) goto fail;
    taper_status rc;
    run_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.last_check = monotonic();
    Py_BEGIN_ALLOW_THREADS
    rc = taper_theory_compute_monitored(chain, NULL, PyArray_DATA((PyArrayObject *)mu), NULL, NULL,
                                        monitor, &ctx, &err);
    Py_END_ALLOW_THREADS
    if (ctx.interrupted) goto fail; /* KeyboardInterrupt is set */
    if (rc != TAPER_OK) {
        core_raise_library(&err);
        goto fail;
    }
    if (core_put(cols, "mu", mu) < 0) {
        mu = NULL;
        goto fail;
    }
    mu = NULL;
    const char *profile = taper_profile_name(taper_chain_profile(chain));
    const char *note = taper_chain_theory_note(chain);
    if (core_put(out, "columns", Py_NewRef(cols)) < 0 ||
        core_put(out, "profile", PyUnicode_FromString(profile ? profile : "")) < 0 ||
        core_put(out, "exponent", PyFloat_FromDouble(taper_chain_exponent(chain))) < 0 ||
        core_put(out, "theory_note", note ? PyUnicode_FromString(note) : Py_NewRef(Py_None)) < 0 ||
        core_put(out, "striker_mass", PyFloat_FromDouble(taper_chain_striker_mass(chain))) < 0)
        goto fail;
    Py_DECREF(cols);
    taper_chain_free(chain);
    return out;
fail:
    Py_XDECREF(mu);
    Py_XDECREF(cols);
    Py_XDECREF(out);
    taper_chain_free(chain);
    return NULL;
}

/* ---- module functions that are not scenes ------------------------------------ */

PyObject *core_collision_time(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    static char *kw[] = {"mu", "r", "zdot0", "n", NULL};
    PyObject *o[4] = {NULL, NULL, NULL, NULL};
    double x[4] = {0, 0, 0, 2.5};
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OOO|O:collision_time", kw, &o[0], &o[1], &o[2],
                                     &o[3]))
        return NULL;
    for (int i = 0; i < 4; i++)
        if (o[i] && core_get_real(kw[i], o[i], &x[i]) < 0) return NULL;
    return PyFloat_FromDouble(taper_theory_collision_time(x[0], x[1], x[2], x[3]));
}

PyObject *core_version(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    return PyUnicode_FromString(taper_version());
}

/* status identifier -> (code, taper_strerror text), for read_granules. */
PyObject *core_statuses(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    for (int s = TAPER_OK; s <= TAPER_ELIMIT; s++)
        if (core_put(d, status_id((taper_status)s), Py_BuildValue("(is)", s, taper_strerror((taper_status)s))) < 0) {
            Py_DECREF(d);
            return NULL;
        }
    return d;
}

/* ---- asymptotic laws ---------------------------------------------------------- */

/* A name of a walked list (taper_X_name) -> its enum value, or an
 * core_InvalidArgumentError naming `what` and listing the names. */
static int enum_from_name(const char *(*name)(int), const char *what, PyObject *v, int *out)
{
    const char *s;
    if (core_get_str(what, v, &s) < 0) return -1;
    for (int i = 0; name(i); i++)
        if (strcmp(name(i), s) == 0) {
            *out = i;
            return 0;
        }
    PyObject *text = PyUnicode_FromFormat("%s: unknown %s '%s': use", what, what, s);
    for (int i = 0; text && name(i); i++) {
        PyObject *t = PyUnicode_FromFormat("%U%s '%s'", text, i ? "," : "", name(i));
        Py_DECREF(text);
        text = t;
    }
    if (text) core_raise(core_InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, what,
                         PyUnicode_AsUTF8(text) + strlen(what) + 2);
    Py_XDECREF(text);
    return -1;
}

const char *core_law_name_i(int i) { return taper_law_name((taper_law)i); }

/* The functions of taper.h's "Asymptotic laws" by their suffix, with the
 * names of their arguments (for TypeErrors).  Each returns NaN outside its
 * domain; the wrappers in asymptotic.py say so. */
typedef struct asym_fn {
    const char *name;
    const char *args[2]; /* args[1] NULL: one argument */
    double (*f1)(double);
    double (*f2)(double, double);
} asym_fn;

static const asym_fn asym_fns[] = {
    {"A", {"q", NULL}, taper_asymptotic_A, NULL},
    {"lnA", {"q", NULL}, taper_asymptotic_lnA, NULL},
    {"forward_linear_b", {"S", NULL}, taper_asymptotic_forward_linear_b, NULL},
    {"eta", {"q", "n"}, NULL, taper_asymptotic_eta},
    {"f", {"q", "n"}, NULL, taper_asymptotic_f},
    {"position_exponent", {"q", "n"}, NULL, taper_asymptotic_position_exponent},
    {"speed_exponent", {"q", "n"}, NULL, taper_asymptotic_speed_exponent},
    {"timescale", {"q", "n"}, NULL, taper_asymptotic_timescale},
    {"M", {"q", "n"}, NULL, taper_asymptotic_M},
    {"C0", {"S", "n"}, NULL, taper_asymptotic_C0},
    {"C", {"S", "n"}, NULL, taper_asymptotic_C},
};

/* asymptotic(name, x[, n]) -> float: taper_asymptotic_<name>(x[, n]). */
PyObject *core_asymptotic(PyObject *self, PyObject *args)
{
    (void)self;
    const char *name;
    PyObject *a = NULL, *b = NULL;
    if (!PyArg_ParseTuple(args, "sO|O:asymptotic", &name, &a, &b)) return NULL;
    for (size_t i = 0; i < sizeof asym_fns / sizeof asym_fns[0]; i++) {
        const asym_fn *fn = &asym_fns[i];
        if (strcmp(fn->name, name) != 0) continue;
        double x, y = 2.5;
        if ((fn->args[1] == NULL) != (b == NULL)) {
            PyErr_Format(PyExc_TypeError, "%s() takes %d arguments", name, fn->args[1] ? 2 : 1);
            return NULL;
        }
        if (core_get_real(fn->args[0], a, &x) < 0) return NULL;
        if (b && core_get_real(fn->args[1], b, &y) < 0) return NULL;
        return PyFloat_FromDouble(fn->f2 ? fn->f2(x, y) : fn->f1(x));
    }
    PyErr_Format(PyExc_ValueError, "no asymptotic function '%s'", name);
    return NULL;
}

/* asymptotic_exponent(law, n) -> float: taper_asymptotic_exponent, the law
 * given by its taper_law_name. */
PyObject *core_asymptotic_exponent(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *law, *n_obj;
    int code;
    double n;
    if (!PyArg_ParseTuple(args, "OO:exponent", &law, &n_obj)) return NULL;
    if (enum_from_name(core_law_name_i, "law", law, &code) < 0) return NULL;
    if (core_get_real("n", n_obj, &n) < 0) return NULL;
    return PyFloat_FromDouble(taper_asymptotic_exponent((taper_law)code, n));
}

/* ---- fits ------------------------------------------------------------------ */

/* A pair (tuple or list of two) for the two-valued setters. */
static int get_pair(const char *name, PyObject *v, PyObject **first, PyObject **second)
{
    if (!(PyTuple_Check(v) || PyList_Check(v)) || PySequence_Size(v) != 2) {
        PyErr_Format(PyExc_TypeError, "%s must be a pair (a tuple of two values), not %.100s",
                     name, Py_TYPE(v)->tp_name);
        return -1;
    }
    *first = PySequence_Fast_GET_ITEM(v, 0);
    *second = PySequence_Fast_GET_ITEM(v, 1);
    return 0;
}

static int fit_settings(taper_fit_spec *spec, PyObject *exponent, PyObject *index_window,
                        PyObject *x_window, PyObject *skip_invalid, PyObject *max_iter,
                        PyObject *xtol)
{
    taper_error err;
    taper_status rc = TAPER_OK;
    if (exponent && exponent != Py_None) {
        double p;
        if (core_get_real("exponent", exponent, &p) < 0) return -1;
        rc = taper_fit_spec_set_exponent(spec, p, &err);
    }
    if (rc == TAPER_OK && index_window && index_window != Py_None) {
        PyObject *b, *e;
        long long begin, end = 0;
        if (get_pair("index_window", index_window, &b, &e) < 0) return -1;
        long long hi = (long long)(SIZE_MAX < (unsigned long long)LLONG_MAX ? SIZE_MAX : LLONG_MAX);
        if (core_get_integer("index_window", b, 0, hi, &begin) < 0) return -1;
        if (e != Py_None && core_get_integer("index_window", e, 0, hi, &end) < 0) return -1;
        rc = taper_fit_spec_set_index_window(spec, (size_t)begin, (size_t)end, &err);
    }
    if (rc == TAPER_OK && x_window && x_window != Py_None) {
        PyObject *lo, *hi;
        double x_min = -INFINITY, x_max = INFINITY;
        if (get_pair("x_window", x_window, &lo, &hi) < 0) return -1;
        if (lo != Py_None && core_get_real("x_window", lo, &x_min) < 0) return -1;
        if (hi != Py_None && core_get_real("x_window", hi, &x_max) < 0) return -1;
        rc = taper_fit_spec_set_x_window(spec, x_min, x_max, &err);
    }
    if (rc == TAPER_OK && skip_invalid && skip_invalid != Py_None) {
        int b;
        if (core_get_bool("skip_invalid", skip_invalid, &b) < 0) return -1;
        rc = taper_fit_spec_set_skip_invalid(spec, b, &err);
    }
    if (rc == TAPER_OK && max_iter && max_iter != Py_None) {
        long long m;
        long long hi = (long long)(SIZE_MAX < (unsigned long long)LLONG_MAX ? SIZE_MAX : LLONG_MAX);
        if (core_get_integer("max_iter", max_iter, 0, hi, &m) < 0) return -1;
        rc = taper_fit_spec_set_max_iter(spec, (size_t)m, &err);
    }
    if (rc == TAPER_OK && xtol && xtol != Py_None) {
        double t;
        if (core_get_real("xtol", xtol, &t) < 0) return -1;
        rc = taper_fit_spec_set_xtol(spec, t, &err);
    }
    if (rc != TAPER_OK) {
        core_raise_library(&err);
        return -1;
    }
    return 0;
}

/* fit(x, y, *, model, exponent, index_window, x_window, skip_invalid,
 * max_iter, xtol) -> dict: taper_fit with each keyword passed to the fit
 * setter of its name. */
PyObject *core_fit(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    static char *kw[] = {"x", "y", "model", "exponent", "index_window", "x_window",
                         "skip_invalid", "max_iter", "xtol", NULL};
    PyObject *xo, *yo, *model = NULL, *exponent = NULL, *index_window = NULL, *x_window = NULL,
                       *skip_invalid = NULL, *max_iter = NULL, *xtol = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OO|$OOOOOOO:fit", kw, &xo, &yo, &model,
                                     &exponent, &index_window, &x_window, &skip_invalid,
                                     &max_iter, &xtol))
        return NULL;
    taper_error err;
    taper_fit_model code = TAPER_FIT_POWER;
    if (model && model != Py_None) {
        const char *s;
        if (core_get_str("model", model, &s) < 0) return NULL;
        if (taper_fit_model_from_name(s, &code, &err) != TAPER_OK) return core_raise_library(&err);
    }
    PyArrayObject *x = core_real_vector("x", xo);
    if (!x) return NULL;
    PyArrayObject *y = core_real_vector("y", yo);
    if (!y) {
        Py_DECREF(x);
        return NULL;
    }
    PyObject *out = NULL;
    taper_fit_result *res = NULL;
    taper_fit_spec *spec = NULL;
    npy_intp n = PyArray_DIM(x, 0);
    if (PyArray_DIM(y, 0) != n) {
        PyObject *text = PyUnicode_FromFormat("y: %zd values, x has %zd: they must pair up",
                                              (Py_ssize_t)PyArray_DIM(y, 0), (Py_ssize_t)n);
        if (text) core_raise(core_InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, "y",
                             PyUnicode_AsUTF8(text) + 3);
        Py_XDECREF(text);
        goto done;
    }
    if (!(spec = taper_fit_spec_alloc(code, &err))) {
        core_raise_library(&err);
        goto done;
    }
    if (fit_settings(spec, exponent, index_window, x_window, skip_invalid, max_iter, xtol) < 0)
        goto done;
    Py_BEGIN_ALLOW_THREADS
    res = taper_fit(spec, PyArray_DATA(x), PyArray_DATA(y), (size_t)n, &err);
    Py_END_ALLOW_THREADS
    if (!res) {
        core_raise_library(&err);
        goto done;
    }
    {
        /* The exponent slot (parameter 2) is reported whenever the model has
         * one, fixed (error 0) or fitted. */
        size_t np = taper_fit_result_n_params(res);
        size_t shown = isnan(taper_fit_result_param(res, 2)) ? np : 3;
        double p[3], e[3];
        for (size_t i = 0; i < shown; i++) {
            p[i] = taper_fit_result_param(res, i);
            e[i] = taper_fit_result_param_error(res, i);
        }
        const char *mname = taper_fit_model_name(taper_fit_result_model(res));
        if (!(out = PyDict_New()) ||
            core_put(out, "model", PyUnicode_FromString(mname ? mname : "")) < 0 ||
            core_put(out, "params", core_double_array(p, shown)) < 0 ||
            core_put(out, "errors", core_double_array(e, shown)) < 0 ||
            core_put(out, "n_params", PyLong_FromSize_t(np)) < 0 ||
            core_put(out, "n_points", PyLong_FromSize_t(taper_fit_result_n_points(res))) < 0 ||
            core_put(out, "n_skipped", PyLong_FromSize_t(taper_fit_result_n_skipped(res))) < 0 ||
            core_put(out, "chi2", PyFloat_FromDouble(taper_fit_result_chi2(res))) < 0 ||
            core_put(out, "iterations", PyLong_FromSize_t(taper_fit_result_iterations(res))) < 0)
            Py_CLEAR(out);
    }
done:
    taper_fit_result_free(res);
    taper_fit_spec_free(spec);
    Py_DECREF(x);
    Py_DECREF(y);
    return out;
}
