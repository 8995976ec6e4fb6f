/*
 * _core.c -- the compiled half of the Python package `taper`: libtaper
 * through its public header (include/taper.h), written with the CPython C
 * API and the numpy C API.  The pure-Python half (__init__.py, result.py)
 * wraps what this returns into taper.Result objects.
 *
 * Keyword arguments are the scene variables (docs/scene.md) and each maps
 * to the library setter of the same name (taper_chain_spec_set_<name>,
 * taper_solver_spec_set_<name>): the library checks every value, and a
 * refusal becomes taper.InvalidArgumentError (a ValueError) naming
 * taper_error.field.  What the library cannot see (a str where a number
 * belongs, a negative count for a size_t) is a TypeError or ValueError
 * raised here, naming the argument too.
 *
 * Threads: libtaper has no global state, so every call builds its own chain
 * and sim and runs them with the GIL released (Py_BEGIN_ALLOW_THREADS):
 * Python threads run chains in parallel.
 *
 * Ctrl-C: Python's C-level SIGINT handler only records the signal; the
 * Python handler (KeyboardInterrupt) runs when the main thread calls
 * PyErr_CheckSignals, which needs the GIL.  The library calls our monitor
 * after every pulse event, on the thread running the sim; at most every
 * CHECK_INTERVAL seconds the monitor takes the GIL (PyGILState_Ensure),
 * calls PyErr_CheckSignals, and asks the library to stop if it raised.  The
 * run then ends with TAPER_EINTERRUPTED, the partial sim is freed, and the
 * KeyboardInterrupt propagates: no half-built result is returned.  Taking
 * the GIL only every CHECK_INTERVAL keeps threads from contending for it.
 *
 * Nothing is printed: the library's log messages (taper_solver_spec_set_log)
 * are collected and returned (level >= 1 as warnings).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#define NPY_NO_DEPRECATED_API NPY_1_22_API_VERSION
#include <numpy/arrayobject.h>

#include "taper.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "_scene.h"

/* Seconds between two looks at Python's pending signals during a run. */
#define CHECK_INTERVAL 0.05

static PyObject *TaperError;           /* taper.TaperError(Exception)                 */
static PyObject *InvalidArgumentError; /* taper.InvalidArgumentError(TaperError, ValueError) */
static PyObject *SceneError;           /* taper.SceneError(TaperError, ValueError)    */

/* ---- errors ---------------------------------------------------------------- */

/* Short identifiers of the statuses, for Result.status and exceptions. */
static const char *status_id(taper_status s)
{
    switch (s) {
    case TAPER_OK: return "ok";
    case TAPER_EINVAL: return "invalid";
    case TAPER_ENOMEM: return "nomem";
    case TAPER_ERANGE: return "range";
    case TAPER_ESOLVER: return "solver";
    case TAPER_EINTERRUPTED: return "interrupted";
    case TAPER_ELIMIT: return "limit";
    }
    return "unknown";
}

/* Raises cls(text) with the attributes status (identifier), field (str or
 * None) and message (the library's own text). */
static void raise_with(PyObject *cls, const char *text, taper_status status, const char *field,
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

/* The library refused: the exception carries its message, prefixed with the
 * argument at fault unless the message already starts with it. */
static PyObject *raise_library(const taper_error *err)
{
    if (err->status == TAPER_ENOMEM) return PyErr_NoMemory();
    const char *msg = err->message[0] ? err->message : taper_strerror(err->status);
    PyObject *cls = (err->status == TAPER_EINVAL || err->status == TAPER_ERANGE)
                        ? InvalidArgumentError : TaperError;
    if (err->field && strncmp(msg, err->field, strlen(err->field)) != 0) {
        PyObject *text = PyUnicode_FromFormat("%s: %s", err->field, msg);
        if (!text) return NULL;
        raise_with(cls, PyUnicode_AsUTF8(text), err->status, err->field, err->message);
        Py_DECREF(text);
    } else {
        raise_with(cls, msg, err->status, err->field, err->message);
    }
    return NULL;
}

/* ---- settings ------------------------------------------------------------- */

typedef enum kind {
    K_PROFILE, K_METHOD, K_REAL, K_SIZE, K_INT, K_LONG, K_BOOL, K_RADII,
    K_BOUNDARY,  /* "free" or "wall" (taper_boundary_from_name)          */
    K_DISORDER,  /* "radius" or "mass" (taper_disorder_from_name)        */
    K_SEED,      /* an integer in [0, 2^64)                             */
    K_PATTERN,   /* a sequence of reals, like radii                     */
    K_MATERIALS  /* a pair (density, compliance) of sequences of reals  */
} kind;

typedef struct setting {
    const char *name;  /* scene variable = setter suffix */
    int chain;         /* 1: taper_chain_spec, 0: taper_solver_spec */
    kind kind;
} setting;

/* Every setting a call may name.  The names are the library's own
 * (taper_error.field); this table only says which spec holds each and what
 * Python type it takes. */
static const setting settings[] = {
    {"profile", 1, K_PROFILE},   {"n_granules", 1, K_SIZE}, {"s", 1, K_REAL},
    {"q", 1, K_REAL},            {"exponent", 1, K_REAL},   {"radii", 1, K_RADII},
    {"method", 0, K_METHOD},     {"rtol", 0, K_REAL},       {"atol", 0, K_REAL},
    {"window", 0, K_BOOL},       {"last_granule", 0, K_SIZE}, {"max_order", 0, K_INT},
    {"t_max", 0, K_REAL},        {"max_steps", 0, K_LONG},
    /* Beyond the paper (taper.h, issue 15): named as the library's fields. */
    {"left_end", 1, K_BOUNDARY},            {"right_end", 1, K_BOUNDARY},
    {"left_wall_compliance", 1, K_REAL},    {"right_wall_compliance", 1, K_REAL},
    {"striker_radius", 1, K_REAL},          {"striker_density", 1, K_REAL},
    {"striker_compliance", 1, K_REAL},      {"load", 1, K_REAL},
    {"damping", 1, K_REAL},                 {"drag", 1, K_REAL},
    {"pattern", 1, K_PATTERN},              {"materials", 1, K_MATERIALS},
    {"disorder", 1, K_DISORDER},            {"disorder_amplitude", 1, K_REAL},
    {"disorder_seed", 1, K_SEED},
    {"piston_duration", 1, K_REAL},         {"piston_compliance", 1, K_REAL},
    {"t_end", 0, K_REAL},         {"sample_interval", 0, K_REAL},
};
#define N_SETTINGS (sizeof settings / sizeof settings[0])

static PyObject *type_error(const char *name, const char *want, PyObject *value)
{
    PyErr_Format(PyExc_TypeError, "%s must be %s, not %.100s", name, want, Py_TYPE(value)->tp_name);
    return NULL;
}

static int is_bool(PyObject *v)
{
    return PyBool_Check(v) || PyArray_IsScalar(v, Bool);
}

/* A real number: float, int or a numpy scalar; never bool or str. */
static int get_real(const char *name, PyObject *v, double *out)
{
    if (is_bool(v) || PyUnicode_Check(v) || PyBytes_Check(v) || PyComplex_Check(v) ||
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

/* An integer (int or numpy integer, never bool or float) in [lo, hi]. */
static int get_integer(const char *name, PyObject *v, long long lo, long long hi, long long *out)
{
    if (is_bool(v) || !PyIndex_Check(v)) {
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
        if (text) raise_with(InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, name,
                             PyUnicode_AsUTF8(text));
        Py_XDECREF(text);
        return -1;
    }
    *out = x;
    return 0;
}

static int get_bool(const char *name, PyObject *v, int *out)
{
    if (is_bool(v) || (PyIndex_Check(v) && !PyFloat_Check(v))) {
        int t = PyObject_IsTrue(v);
        if (t < 0) return -1;
        *out = t;
        return 0;
    }
    type_error(name, "a bool", v);
    return -1;
}

static int get_str(const char *name, PyObject *v, const char **out)
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
        if (text) raise_with(InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, name,
                             "must not contain NUL characters");
        Py_XDECREF(text);
        return -1;
    }
    *out = s;
    return 0;
}

/* The settings whose library setter takes several values at once
 * (taper_chain_spec_set_end, _set_striker, _set_piston, _set_disorder): collected over
 * all keywords, then set together (apply_pending), so that the order of the
 * keywords does not matter.  given[i]: keyword i of the group was passed. */
typedef struct pending {
    int end_given[TAPER_N_ENDS], end_compliance_given[TAPER_N_ENDS];
    taper_boundary end[TAPER_N_ENDS];
    double end_compliance[TAPER_N_ENDS];
    int striker_given[3];          /* radius, density, compliance */
    double striker[3];
    int piston_given[2];           /* duration, compliance        */
    double piston[2];
    int disorder_given[3];         /* kind, amplitude, seed       */
    taper_disorder disorder;
    double disorder_amplitude;
    uint64_t disorder_seed;
} pending;

/* A real sequence as a contiguous one-dimensional array of doubles (a new
 * reference), or NULL with a TypeError naming `name`: chain settings and
 * the fits' data alike. */
static PyArrayObject *real_vector(const char *name, PyObject *v)
{
    if (PyUnicode_Check(v) || PyBytes_Check(v) || is_bool(v)) {
        type_error(name, "a sequence of real numbers", v);
        return NULL;
    }
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(v, NPY_DOUBLE, 0, 0, NPY_ARRAY_CARRAY_RO);
    if (!a) {
        if (PyErr_ExceptionMatches(PyExc_TypeError) || PyErr_ExceptionMatches(PyExc_ValueError)) {
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

/* The pair (density, compliance) of a materials keyword, each a sequence of
 * reals; NULL, NULL for None (one material). */
static int materials_pair(PyObject *v, PyArrayObject **rho, PyArrayObject **c)
{
    *rho = *c = NULL;
    if (v == Py_None) return 0;
    if (!PySequence_Check(v) || PyUnicode_Check(v) || PySequence_Size(v) != 2) {
        if (PyErr_Occurred()) PyErr_Clear();
        PyErr_Format(PyExc_TypeError,
                     "materials must be a pair (density, compliance) of sequences of real "
                     "numbers, not %.100s", Py_TYPE(v)->tp_name);
        return -1;
    }
    PyObject *first = PySequence_GetItem(v, 0), *second = PySequence_GetItem(v, 1);
    if (first && second) {
        *rho = real_vector("materials density", first);
        if (*rho) *c = real_vector("materials compliance", second);
    }
    Py_XDECREF(first);
    Py_XDECREF(second);
    if (*rho && *c) return 0;
    Py_XDECREF(*rho);
    *rho = NULL;
    return -1;
}

/* The sampler a spec carries between parse_settings and run_specs, which
 * replaces it by collect_sample; never called. */
static int no_sample(const taper_sim *sim, void *user)
{
    (void)sim;
    (void)user;
    return 0;
}

/* Applies one keyword to its spec through the library setter (or records
 * it in *pd for apply_pending). */
static int apply_setting(const setting *st, PyObject *v, taper_chain_spec *cs, taper_solver_spec *ss,
                         Py_ssize_t *n_radii, pending *pd)
{
    taper_error err;
    taper_status rc = TAPER_OK;
    const char *name = st->name;
    switch (st->kind) {
    case K_PROFILE: {
        const char *s;
        taper_profile p;
        if (get_str(name, v, &s) < 0) return -1;
        rc = taper_profile_from_name(s, &p, &err);
        if (rc == TAPER_OK) rc = taper_chain_spec_set_profile(cs, p, &err);
        break;
    }
    case K_METHOD: {
        const char *s;
        taper_method m;
        if (get_str(name, v, &s) < 0) return -1;
        rc = taper_method_from_name(s, &m, &err);
        if (rc == TAPER_OK) rc = taper_solver_spec_set_method(ss, m, &err);
        break;
    }
    case K_REAL: {
        double x;
        if (get_real(name, v, &x) < 0) return -1;
        if (strcmp(name, "left_wall_compliance") == 0 || strcmp(name, "right_wall_compliance") == 0) {
            int e = name[0] == 'l' ? TAPER_LEFT : TAPER_RIGHT;
            pd->end_compliance_given[e] = 1;
            pd->end_compliance[e] = x;
        } else if (strncmp(name, "striker_", 8) == 0) {
            int i = strcmp(name, "striker_radius") == 0 ? 0 : strcmp(name, "striker_density") == 0 ? 1 : 2;
            pd->striker_given[i] = 1;
            pd->striker[i] = x;
        } else if (strncmp(name, "piston_", 7) == 0) {
            int i = strcmp(name, "piston_duration") == 0 ? 0 : 1;
            pd->piston_given[i] = 1;
            pd->piston[i] = x;
        } else if (strcmp(name, "disorder_amplitude") == 0) {
            pd->disorder_given[1] = 1;
            pd->disorder_amplitude = x;
        } else if (strcmp(name, "load") == 0) rc = taper_chain_spec_set_load(cs, x, &err);
        else if (strcmp(name, "damping") == 0) rc = taper_chain_spec_set_damping(cs, x, &err);
        else if (strcmp(name, "drag") == 0) rc = taper_chain_spec_set_drag(cs, x, &err);
        else if (strcmp(name, "s") == 0) rc = taper_chain_spec_set_s(cs, x, &err);
        else if (strcmp(name, "q") == 0) rc = taper_chain_spec_set_q(cs, x, &err);
        else if (strcmp(name, "exponent") == 0) rc = taper_chain_spec_set_exponent(cs, x, &err);
        else if (strcmp(name, "rtol") == 0) rc = taper_solver_spec_set_rtol(ss, x, &err);
        else if (strcmp(name, "atol") == 0) rc = taper_solver_spec_set_atol(ss, x, &err);
        else if (strcmp(name, "t_end") == 0) rc = taper_solver_spec_set_t_end(ss, x, &err);
        else if (strcmp(name, "sample_interval") == 0)
            /* checked and kept here; the run samples through its own
             * collector (run_specs, collect_sample) */
            rc = x == 0.0 ? taper_solver_spec_set_sampler(ss, 0.0, NULL, NULL, &err)
                          : taper_solver_spec_set_sampler(ss, x, no_sample, NULL, &err);
        else rc = taper_solver_spec_set_t_max(ss, x, &err);
        break;
    }
    case K_SIZE: {
        long long x;
        if (get_integer(name, v, 0, (long long)(SIZE_MAX < (unsigned long long)LLONG_MAX ? SIZE_MAX : LLONG_MAX), &x) < 0)
            return -1;
        if (strcmp(name, "n_granules") == 0) rc = taper_chain_spec_set_n_granules(cs, (size_t)x, &err);
        else rc = taper_solver_spec_set_last_granule(ss, (size_t)x, &err);
        break;
    }
    case K_INT: {
        long long x;
        if (get_integer(name, v, INT_MIN, INT_MAX, &x) < 0) return -1;
        rc = taper_solver_spec_set_max_order(ss, (int)x, &err);
        break;
    }
    case K_LONG: {
        long long x;
        if (get_integer(name, v, LONG_MIN, LONG_MAX, &x) < 0) return -1;
        rc = taper_solver_spec_set_max_steps(ss, (long)x, &err);
        break;
    }
    case K_BOOL: {
        int b;
        if (get_bool(name, v, &b) < 0) return -1;
        rc = taper_solver_spec_set_window(ss, b, &err);
        break;
    }
    case K_BOUNDARY: {
        const char *s;
        taper_boundary b;
        if (get_str(name, v, &s) < 0) return -1;
        rc = taper_boundary_from_name(s, &b, &err);
        if (rc == TAPER_OK) {
            int e = name[0] == 'l' ? TAPER_LEFT : TAPER_RIGHT;
            pd->end_given[e] = 1;
            pd->end[e] = b;
        } else {
            err.field = name;  /* the library's from_name names "boundary": the keyword is ours */
        }
        break;
    }
    case K_DISORDER: {
        const char *s;
        taper_disorder d;
        if (get_str(name, v, &s) < 0) return -1;
        rc = taper_disorder_from_name(s, &d, &err);
        if (rc == TAPER_OK) {
            pd->disorder_given[0] = 1;
            pd->disorder = d;
        }
        break;
    }
    case K_SEED: {
        if (is_bool(v) || !PyIndex_Check(v)) {
            type_error(name, "an integer", v);
            return -1;
        }
        PyObject *i = PyNumber_Index(v);
        if (!i) return -1;
        unsigned long long x = PyLong_AsUnsignedLongLong(i);
        Py_DECREF(i);
        if (x == (unsigned long long)-1 && PyErr_Occurred()) {
            PyErr_Clear();
            PyObject *text = PyUnicode_FromFormat("%s = %S is out of range (0 to 2**64 - 1)", name, v);
            if (text) raise_with(InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, name,
                                 PyUnicode_AsUTF8(text));
            Py_XDECREF(text);
            return -1;
        }
        pd->disorder_given[2] = 1;
        pd->disorder_seed = (uint64_t)x;
        break;
    }
    case K_PATTERN: {
        if (v == Py_None) {
            rc = taper_chain_spec_set_pattern(cs, NULL, 0, &err);
            break;
        }
        PyArrayObject *a = real_vector(name, v);
        if (!a) return -1;
        Py_ssize_t n = PyArray_DIM(a, 0);
        rc = taper_chain_spec_set_pattern(cs, n ? (const double *)PyArray_DATA(a) : NULL, (size_t)n,
                                          &err);
        Py_DECREF(a);
        break;
    }
    case K_MATERIALS: {
        PyArrayObject *rho, *c;
        if (materials_pair(v, &rho, &c) < 0) return -1;
        if (!rho) {
            rc = taper_chain_spec_set_materials(cs, NULL, NULL, 0, &err);
            break;
        }
        Py_ssize_t n = PyArray_DIM(rho, 0);
        if (PyArray_DIM(c, 0) != n) {
            Py_DECREF(rho);
            Py_DECREF(c);
            PyObject *text = PyUnicode_FromFormat(
                "materials: density has %zd values, compliance %zd: one of each per granule",
                n, PyArray_DIM(c, 0));
            if (text) raise_with(InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, name,
                                 PyUnicode_AsUTF8(text));
            Py_XDECREF(text);
            return -1;
        }
        rc = taper_chain_spec_set_materials(cs, n ? (const double *)PyArray_DATA(rho) : NULL,
                                            n ? (const double *)PyArray_DATA(c) : NULL, (size_t)n,
                                            &err);
        Py_DECREF(rho);
        Py_DECREF(c);
        break;
    }
    case K_RADII: {
        if (v == Py_None) {
            rc = taper_chain_spec_set_radii(cs, NULL, 0, &err);
            *n_radii = -1;
            break;
        }
        if (PyUnicode_Check(v) || PyBytes_Check(v) || is_bool(v)) {
            type_error(name, "a sequence of real numbers", v);
            return -1;
        }
        PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(v, NPY_DOUBLE, 0, 0, NPY_ARRAY_CARRAY_RO);
        if (!a) {
            if (PyErr_ExceptionMatches(PyExc_TypeError) || PyErr_ExceptionMatches(PyExc_ValueError)) {
                PyErr_Clear();
                type_error(name, "a sequence of real numbers", v);
            }
            return -1;
        }
        if (PyArray_NDIM(a) != 1) {
            Py_DECREF(a);
            PyErr_Format(PyExc_TypeError, "%s must be a one-dimensional sequence of real numbers",
                         name);
            return -1;
        }
        Py_ssize_t n = PyArray_DIM(a, 0);
        rc = taper_chain_spec_set_radii(cs, n ? (const double *)PyArray_DATA(a) : NULL, (size_t)n,
                                        &err);
        Py_DECREF(a);
        *n_radii = n;
        break;
    }
    }
    if (rc != TAPER_OK) {
        /* The library names the field; from_name refusals name it too. */
        raise_library(&err);
        return -1;
    }
    return 0;
}

/* The grouped settings of *pd through their setters, each value not given
 * taken from the spec (its default). */
static int apply_pending(const pending *pd, taper_chain_spec *cs)
{
    taper_error err;
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        if (!pd->end_given[e] && !pd->end_compliance_given[e]) continue;
        taper_boundary b = pd->end_given[e] ? pd->end[e] : taper_chain_spec_end(cs, (taper_end)e);
        double c = pd->end_compliance_given[e] ? pd->end_compliance[e]
                                               : taper_chain_spec_end_compliance(cs, (taper_end)e);
        if (taper_chain_spec_set_end(cs, (taper_end)e, b, c, &err) != TAPER_OK) {
            raise_library(&err);
            return -1;
        }
    }
    if (pd->striker_given[0] || pd->striker_given[1] || pd->striker_given[2]) {
        double r = pd->striker_given[0] ? pd->striker[0] : taper_chain_spec_striker_radius(cs);
        double rho = pd->striker_given[1] ? pd->striker[1] : taper_chain_spec_striker_density(cs);
        double c = pd->striker_given[2] ? pd->striker[2] : taper_chain_spec_striker_compliance(cs);
        if (taper_chain_spec_set_striker(cs, r, rho, c, &err) != TAPER_OK) {
            raise_library(&err);
            return -1;
        }
    }
    if (pd->piston_given[0] || pd->piston_given[1]) {
        double T = pd->piston_given[0] ? pd->piston[0] : taper_chain_spec_piston_duration(cs);
        double c = pd->piston_given[1] ? pd->piston[1] : taper_chain_spec_piston_compliance(cs);
        if (taper_chain_spec_set_piston(cs, T, c, &err) != TAPER_OK) {
            raise_library(&err);
            return -1;
        }
    }
    if (pd->disorder_given[0] || pd->disorder_given[1] || pd->disorder_given[2]) {
        taper_disorder d = pd->disorder_given[0] ? pd->disorder : taper_chain_spec_disorder(cs);
        double a = pd->disorder_given[1] ? pd->disorder_amplitude
                                         : taper_chain_spec_disorder_amplitude(cs);
        uint64_t seed = pd->disorder_given[2] ? pd->disorder_seed : taper_chain_spec_disorder_seed(cs);
        if (taper_chain_spec_set_disorder(cs, d, a, seed, &err) != TAPER_OK) {
            raise_library(&err);
            return -1;
        }
    }
    return 0;
}

/* Reads the keywords into fresh specs (ss may be NULL: chain settings only).
 * An unknown keyword is a TypeError naming it. */
static int parse_settings(PyObject *kwargs, taper_chain_spec *cs, taper_solver_spec *ss,
                          const char *func)
{
    if (!kwargs) return 0;
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    Py_ssize_t n_radii = -1;
    int n_given = 0;
    pending pd;
    memset(&pd, 0, sizeof pd);
    while (PyDict_Next(kwargs, &pos, &key, &value)) {
        const char *k = PyUnicode_AsUTF8(key);
        if (!k) return -1;
        const setting *st = NULL;
        for (size_t i = 0; i < N_SETTINGS; i++)
            if (strcmp(settings[i].name, k) == 0 && (settings[i].chain || ss)) st = &settings[i];
        if (!st) {
            PyErr_Format(PyExc_TypeError, "%s() got an unexpected keyword argument '%s'", func, k);
            return -1;
        }
        if (value == Py_None && st->kind != K_RADII) continue; /* None: the library's default */
        if (apply_setting(st, value, cs, ss, &n_radii, &pd) < 0) return -1;
        if (strcmp(k, "n_granules") == 0) n_given = 1;
    }
    if (apply_pending(&pd, cs) < 0) return -1;
    /* As in a scene: with radii, n_granules may be left out (N = number of
     * radii). */
    if (n_radii > 0 && !n_given) {
        taper_error err;
        if (taper_chain_spec_set_n_granules(cs, (size_t)n_radii, &err) != TAPER_OK) {
            raise_library(&err);
            return -1;
        }
    }
    return 0;
}

/* ---- results -------------------------------------------------------------- */

static PyObject *double_array(const double *src, size_t n)
{
    npy_intp dim = (npy_intp)n;
    PyObject *a = PyArray_SimpleNew(1, &dim, NPY_DOUBLE);
    if (!a) return NULL;
    double *dst = PyArray_DATA((PyArrayObject *)a);
    if (src) memcpy(dst, src, n * sizeof(double));
    else for (size_t i = 0; i < n; i++) dst[i] = NAN;
    return a;
}

static int put(PyObject *dict, const char *key, PyObject *value)
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
    for (size_t i = 0; i < n; i++) kd[i] = (int64_t)(i + 1);
    if (put(cols, "k", k) < 0) return -1;
    if (put(cols, "R", double_array(taper_chain_radius(chain), n)) < 0) return -1;
    if (put(cols, "m", double_array(taper_chain_mass(chain), n)) < 0) return -1;
    if (put(cols, "X0", double_array(taper_chain_rest_position(chain), n)) < 0) return -1;
    return 0;
}

/* The theory's columns as granules.tsv names them: "theory_" and the
 * quantity's taper_theory_quantity_name, mu left out (it has no column;
 * taper.chain() gives it). */
static int theory_columns(PyObject *cols, const double *const *q, size_t n)
{
    for (int i = 0; taper_theory_quantity_name((taper_theory_quantity)i); i++) {
        if (i == TAPER_THEORY_MU) continue;
        char key[64];
        snprintf(key, sizeof key, "theory_%s", taper_theory_quantity_name((taper_theory_quantity)i));
        if (put(cols, key, double_array(q[i], n)) < 0) return -1;
    }
    return 0;
}

/* The chain settings of issue 15 (ends, striker, load, losses, pattern,
 * materials, disorder) into d, from the spec's getters. */
static int beyond_paper_settings(PyObject *d, const taper_chain_spec *cs)
{
    static const char *const end_keys[TAPER_N_ENDS] = {"left_end", "right_end"};
    static const char *const wall_keys[TAPER_N_ENDS] = {"left_wall_compliance",
                                                        "right_wall_compliance"};
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        const char *b = taper_boundary_name(taper_chain_spec_end(cs, (taper_end)e));
        if (put(d, end_keys[e], PyUnicode_FromString(b ? b : "")) < 0 ||
            put(d, wall_keys[e], PyFloat_FromDouble(taper_chain_spec_end_compliance(cs, (taper_end)e))) < 0)
            return -1;
    }
    size_t n_pattern = 0;
    const double *pattern = taper_chain_spec_pattern(cs, &n_pattern);
    const double *rho = NULL, *c = NULL;
    size_t n_materials = taper_chain_spec_materials(cs, &rho, &c);
    const char *disorder = taper_disorder_name(taper_chain_spec_disorder(cs));
    PyObject *materials = Py_None;
    if (n_materials > 0) {
        PyObject *a = double_array(rho, n_materials), *b = double_array(c, n_materials);
        materials = a && b ? PyTuple_Pack(2, a, b) : NULL;
        Py_XDECREF(a);
        Py_XDECREF(b);
        if (!materials) return -1;
    } else {
        Py_INCREF(materials);
    }
    if (put(d, "materials", materials) < 0 ||
        put(d, "striker_radius", PyFloat_FromDouble(taper_chain_spec_striker_radius(cs))) < 0 ||
        put(d, "striker_density", PyFloat_FromDouble(taper_chain_spec_striker_density(cs))) < 0 ||
        put(d, "striker_compliance", PyFloat_FromDouble(taper_chain_spec_striker_compliance(cs))) < 0 ||
        put(d, "piston_duration", PyFloat_FromDouble(taper_chain_spec_piston_duration(cs))) < 0 ||
        put(d, "piston_compliance", PyFloat_FromDouble(taper_chain_spec_piston_compliance(cs))) < 0 ||
        put(d, "load", PyFloat_FromDouble(taper_chain_spec_load(cs))) < 0 ||
        put(d, "damping", PyFloat_FromDouble(taper_chain_spec_damping(cs))) < 0 ||
        put(d, "drag", PyFloat_FromDouble(taper_chain_spec_drag(cs))) < 0 ||
        put(d, "pattern", pattern ? double_array(pattern, n_pattern) : Py_NewRef(Py_None)) < 0 ||
        put(d, "disorder", PyUnicode_FromString(disorder ? disorder : "")) < 0 ||
        put(d, "disorder_amplitude", PyFloat_FromDouble(taper_chain_spec_disorder_amplitude(cs))) < 0 ||
        put(d, "disorder_seed", PyLong_FromUnsignedLongLong(taper_chain_spec_disorder_seed(cs))) < 0)
        return -1;
    return 0;
}

/* The resolved settings (every default filled in), from the specs' getters. */
static PyObject *settings_dict(const taper_chain_spec *cs, const taper_solver_spec *ss)
{
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    const char *profile = taper_profile_name(taper_chain_spec_profile(cs));
    size_t n_radii = 0;
    const double *radii = taper_chain_spec_radii(cs, &n_radii);
    if (put(d, "profile", PyUnicode_FromString(profile ? profile : "")) < 0 ||
        put(d, "n_granules", PyLong_FromSize_t(taper_chain_spec_n_granules(cs))) < 0 ||
        put(d, "s", PyFloat_FromDouble(taper_chain_spec_s(cs))) < 0 ||
        put(d, "q", PyFloat_FromDouble(taper_chain_spec_q(cs))) < 0 ||
        put(d, "exponent", PyFloat_FromDouble(taper_chain_spec_exponent(cs))) < 0 ||
        put(d, "radii", radii ? double_array(radii, n_radii) : Py_NewRef(Py_None)) < 0)
        goto fail;
    if (beyond_paper_settings(d, cs) < 0) goto fail;
    if (ss) {
        const char *method = taper_method_name(taper_solver_spec_method(ss));
        if (put(d, "method", PyUnicode_FromString(method ? method : "")) < 0 ||
            put(d, "rtol", PyFloat_FromDouble(taper_solver_spec_rtol(ss))) < 0 ||
            put(d, "atol", PyFloat_FromDouble(taper_solver_spec_atol(ss))) < 0 ||
            put(d, "window", PyBool_FromLong(taper_solver_spec_window(ss))) < 0 ||
            put(d, "last_granule", PyLong_FromSize_t(taper_solver_spec_last_granule(ss))) < 0 ||
            put(d, "max_order", PyLong_FromLong(taper_solver_spec_max_order(ss))) < 0 ||
            put(d, "t_max", PyFloat_FromDouble(taper_solver_spec_t_max(ss))) < 0 ||
            put(d, "max_steps", PyLong_FromLong(taper_solver_spec_max_steps(ss))) < 0 ||
            put(d, "t_end", PyFloat_FromDouble(taper_solver_spec_t_end(ss))) < 0 ||
            put(d, "sample_interval", PyFloat_FromDouble(taper_solver_spec_sample_interval(ss))) < 0)
            goto fail;
    }
    return d;
fail:
    Py_DECREF(d);
    return NULL;
}

/* What happens during a run, collected without the GIL. */
typedef struct run_ctx {
    double last_check;      /* monotonic seconds of the last signal check   */
    int interrupted;        /* a Python exception is pending in the thread  */
    char **warnings;        /* copies of the level >= 1 log messages        */
    size_t n_warnings, cap;
    size_t n_dropped;       /* warnings lost to a failed allocation         */
    /* samples (sample_interval): times, displacements and velocities (N per
     * sample), contact forces (N + 1 per sample) */
    size_t n_granules, n_samples, samples_cap;
    double *t, *x, *v, *force;
    int samples_failed;     /* out of memory: the run was stopped           */
} run_ctx;

static double monotonic(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int monitor(const taper_progress *progress, void *user)
{
    (void)progress;
    run_ctx *ctx = user;
    if (ctx->interrupted) return 1;
    double now = monotonic();
    if (now - ctx->last_check < CHECK_INTERVAL) return 0;
    ctx->last_check = now;
    PyGILState_STATE g = PyGILState_Ensure();
    /* Runs the Python signal handlers (main thread only); on
     * KeyboardInterrupt the exception stays set in this thread's state
     * until the caller, holding the GIL again, returns NULL. */
    if (PyErr_CheckSignals() < 0) ctx->interrupted = 1;
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

/* The sampler of a run with sample_interval (without the GIL): copies the
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
    if (put(d, "t", double_array(ctx->t, (size_t)s)) < 0) goto fail;
    for (size_t j = 0; j < sizeof parts / sizeof parts[0]; j++) {
        npy_intp dims[2] = {s, parts[j].cols};
        PyObject *a = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
        if (!a) goto fail;
        if (s) memcpy(PyArray_DATA((PyArrayObject *)a), parts[j].src,
                      (size_t)(s * parts[j].cols) * sizeof(double));
        if (put(d, parts[j].key, a) < 0) goto fail;
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
        if (put(d, taper_statistic_name((taper_statistic)i), v) < 0) {
            Py_DECREF(d);
            return NULL;
        }
    }
    return d;
}

/* Builds the chain from cs and either the theory alone (ss NULL) or a full
 * run; returns the dict Result is made from, or NULL with an exception. */
static PyObject *run_specs(const taper_chain_spec *cs, const taper_solver_spec *ss_in)
{
    taper_error err;
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    taper_solver_spec *ss = NULL;
    double *theory[4] = {NULL, NULL, NULL, NULL};
    PyObject *out = NULL, *cols = NULL;
    run_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    taper_status rc = TAPER_OK;

    Py_BEGIN_ALLOW_THREADS
    chain = taper_chain_alloc(cs, &err);
    Py_END_ALLOW_THREADS
    if (!chain) return raise_library(&err);
    size_t n = taper_chain_size(chain);

    if (!(out = PyDict_New()) || !(cols = PyDict_New())) goto fail;
    if (chain_columns(cols, chain) < 0) goto fail;

    if (!ss_in) {
        /* Theory only: taper_theory_compute, no integration. */
        int nomem = 0;
        for (int i = 0; i < 4; i++)
            if (!(theory[i] = malloc((n ? n : 1) * sizeof(double)))) nomem = 1;
        if (nomem) {
            PyErr_NoMemory();
            goto fail;
        }
        Py_BEGIN_ALLOW_THREADS
        rc = taper_theory_compute(chain, theory[0], theory[1], theory[2], theory[3], &err);
        Py_END_ALLOW_THREADS
        if (rc != TAPER_OK) {
            raise_library(&err);
            goto fail;
        }
        if (theory_columns(cols, (const double *const *)theory, n) < 0) goto fail;
        if (put(out, "stats", PyDict_New()) < 0 ||
            put(out, "settings", settings_dict(cs, NULL)) < 0 ||
            put(out, "status", PyUnicode_FromString("ok")) < 0 ||
            put(out, "message", PyUnicode_FromString("")) < 0 ||
            put(out, "warnings", PyList_New(0)) < 0)
            goto fail;
    } else {
        /* A private copy of the solver settings carrying our monitor and log. */
        if (!(ss = taper_solver_spec_alloc(&err))) {
            raise_library(&err);
            goto fail;
        }
        if (taper_solver_spec_set_method(ss, taper_solver_spec_method(ss_in), &err) != TAPER_OK ||
            taper_solver_spec_set_rtol(ss, taper_solver_spec_rtol(ss_in), &err) != TAPER_OK ||
            taper_solver_spec_set_atol(ss, taper_solver_spec_atol(ss_in), &err) != TAPER_OK ||
            taper_solver_spec_set_window(ss, taper_solver_spec_window(ss_in), &err) != TAPER_OK ||
            taper_solver_spec_set_last_granule(ss, taper_solver_spec_last_granule(ss_in), &err) !=
                TAPER_OK ||
            taper_solver_spec_set_max_order(ss, taper_solver_spec_max_order(ss_in), &err) !=
                TAPER_OK ||
            taper_solver_spec_set_t_max(ss, taper_solver_spec_t_max(ss_in), &err) != TAPER_OK ||
            taper_solver_spec_set_max_steps(ss, taper_solver_spec_max_steps(ss_in), &err) !=
                TAPER_OK ||
            taper_solver_spec_set_t_end(ss, taper_solver_spec_t_end(ss_in), &err) != TAPER_OK) {
            raise_library(&err);
            goto fail;
        }
        taper_solver_spec_set_monitor(ss, monitor, &ctx);
        taper_solver_spec_set_log(ss, collect_log, &ctx);
        const double interval = taper_solver_spec_sample_interval(ss_in);
        if (interval > 0.0) {
            ctx.n_granules = n;
            if (taper_solver_spec_set_sampler(ss, interval, collect_sample, &ctx, &err) != TAPER_OK) {
                raise_library(&err);
                goto fail;
            }
        }
        ctx.last_check = monotonic();

        Py_BEGIN_ALLOW_THREADS
        sim = taper_sim_alloc(chain, ss, &err);
        if (sim) rc = taper_sim_run(sim, &err);
        Py_END_ALLOW_THREADS
        if (!sim) {
            raise_library(&err);
            goto fail;
        }
        if (ctx.interrupted) goto fail; /* KeyboardInterrupt (or a handler's exception) is set */
        if (ctx.samples_failed) {
            PyErr_NoMemory();
            goto fail;
        }
        if (rc != TAPER_OK && rc != TAPER_ESOLVER && rc != TAPER_ELIMIT &&
            rc != TAPER_EINTERRUPTED) {
            raise_library(&err);
            goto fail;
        }
        /* The observables under the library's names (granules.tsv's). */
        for (int i = 0; taper_observable_name((taper_observable)i); i++)
            if (put(cols, taper_observable_name((taper_observable)i),
                    double_array(taper_sim_observable(sim, (taper_observable)i), n)) < 0)
                goto fail;
        const double *th[TAPER_N_THEORY_QUANTITIES];
        for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++)
            th[i] = taper_sim_theory(sim, (taper_theory_quantity)i);
        if (theory_columns(cols, th, n) < 0) goto fail;
        /* The state where the run ended. */
        PyObject *x = double_array(NULL, n), *v = double_array(NULL, n);
        if (!x || !v) {
            Py_XDECREF(x);
            Py_XDECREF(v);
            goto fail;
        }
        taper_error serr;
        taper_sim_state(sim, PyArray_DATA((PyArrayObject *)x), PyArray_DATA((PyArrayObject *)v),
                        &serr);
        if (put(out, "x_final", x) < 0 || put(out, "v_final", v) < 0) goto fail;
        if (taper_solver_spec_sample_interval(ss_in) > 0.0 && put(out, "samples", samples_dict(&ctx)) < 0)
            goto fail;
        if (put(out, "stats", stats_dict(sim)) < 0 ||
            put(out, "settings", settings_dict(cs, ss)) < 0 ||
            put(out, "status", PyUnicode_FromString(status_id(rc))) < 0 ||
            put(out, "message", PyUnicode_FromString(rc == TAPER_OK ? "" : err.message)) < 0 ||
            put(out, "warnings", warnings_list(&ctx)) < 0)
            goto fail;
    }
    if (PyDict_SetItemString(out, "columns", cols) < 0) goto fail;
    Py_DECREF(cols);
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(chain);
    for (int i = 0; i < 4; i++) free(theory[i]);
    ctx_free(&ctx);
    return out;
fail:
    Py_XDECREF(out);
    Py_XDECREF(cols);
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(chain);
    for (int i = 0; i < 4; i++) free(theory[i]);
    ctx_free(&ctx);
    return NULL;
}

/* ---- module functions ------------------------------------------------------ */

static int no_positional(PyObject *args, const char *func)
{
    if (PyTuple_GET_SIZE(args) == 0) return 0;
    PyErr_Format(PyExc_TypeError, "%s() takes keyword arguments only (%zd positional given)", func,
                 PyTuple_GET_SIZE(args));
    return -1;
}

static PyObject *py_simulate(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    if (no_positional(args, "simulate") < 0) return NULL;
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    if (!cs) return raise_library(&err);
    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    if (!ss) {
        taper_chain_spec_free(cs);
        return raise_library(&err);
    }
    PyObject *r = NULL;
    if (parse_settings(kwargs, cs, ss, "simulate") == 0) r = run_specs(cs, ss);
    taper_solver_spec_free(ss);
    taper_chain_spec_free(cs);
    return r;
}

static PyObject *py_theory(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    if (no_positional(args, "theory") < 0) return NULL;
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    if (!cs) return raise_library(&err);
    PyObject *r = NULL;
    if (parse_settings(kwargs, cs, NULL, "theory") == 0) r = run_specs(cs, NULL);
    taper_chain_spec_free(cs);
    return r;
}

/* run_scene(path): the driver's own scene reader (drivers/taper/scene,
 * through _scene.c), then one run per value of the swept variable. */
static PyObject *py_run_scene(PyObject *self, PyObject *arg)
{
    (void)self;
    PyObject *bytes = NULL;
    if (!PyUnicode_FSConverter(arg, &bytes)) return NULL;
    const char *path = PyBytes_AS_STRING(bytes);
    pyscene *sc = NULL;
    char *diag = NULL;
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = pyscene_load(path, &sc, &diag);
    Py_END_ALLOW_THREADS
    if (rc != 0) {
        if (rc == -2) PyErr_NoMemory();
        else raise_with(SceneError, diag ? diag : "invalid scene", TAPER_EINVAL, NULL,
                        diag ? diag : "");
        free(diag);
        pyscene_free(sc);
        Py_DECREF(bytes);
        return NULL;
    }
    PyObject *list = PyList_New(0);
    size_t n = list ? pyscene_runs(sc) : 0;
    for (size_t i = 0; list && i < n; i++) {
        taper_error err;
        taper_chain_spec *cs = taper_chain_spec_alloc(&err);
        taper_solver_spec *ss = cs ? taper_solver_spec_alloc(&err) : NULL;
        PyObject *r = NULL;
        if (!cs || !ss) {
            raise_library(&err);
        } else if (pyscene_specs(sc, i, cs, ss, &err) != TAPER_OK) {
            raise_library(&err);
        } else {
            r = run_specs(cs, pyscene_numerics(sc) ? ss : NULL);
            if (r && put(r, "scene", PyUnicode_DecodeFSDefault(path)) < 0) Py_CLEAR(r);
        }
        taper_solver_spec_free(ss);
        taper_chain_spec_free(cs);
        if (!r || PyList_Append(list, r) < 0) {
            Py_XDECREF(r);
            Py_CLEAR(list);
            break;
        }
        Py_DECREF(r);
    }
    pyscene_free(sc);
    Py_DECREF(bytes);
    return list;
}

static PyObject *py_collision_time(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    static char *kw[] = {"mu", "r", "zdot0", "n", NULL};
    PyObject *o[4] = {NULL, NULL, NULL, NULL};
    double x[4] = {0, 0, 0, 2.5};
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OOO|O:collision_time", kw, &o[0], &o[1], &o[2],
                                     &o[3]))
        return NULL;
    for (int i = 0; i < 4; i++)
        if (o[i] && get_real(kw[i], o[i], &x[i]) < 0) return NULL;
    return PyFloat_FromDouble(taper_theory_collision_time(x[0], x[1], x[2], x[3]));
}

static PyObject *names_tuple(const char *(*name)(int))
{
    PyObject *l = PyList_New(0);
    if (!l) return NULL;
    for (int i = 0; name(i); i++) {
        PyObject *s = PyUnicode_FromString(name(i));
        if (!s || PyList_Append(l, s) < 0) {
            Py_XDECREF(s);
            Py_DECREF(l);
            return NULL;
        }
        Py_DECREF(s);
    }
    PyObject *t = PyList_AsTuple(l);
    Py_DECREF(l);
    return t;
}

static const char *profile_name_i(int i) { return taper_profile_name((taper_profile)i); }
static const char *method_name_i(int i) { return taper_method_name((taper_method)i); }
static const char *statistic_name_i(int i) { return taper_statistic_name((taper_statistic)i); }
static const char *observable_name_i(int i) { return taper_observable_name((taper_observable)i); }
static const char *quantity_name_i(int i)
{
    return taper_theory_quantity_name((taper_theory_quantity)i);
}
static const char *fit_model_name_i(int i) { return taper_fit_model_name((taper_fit_model)i); }
static const char *boundary_name_i(int i) { return taper_boundary_name((taper_boundary)i); }
static const char *disorder_name_i(int i) { return taper_disorder_name((taper_disorder)i); }

static PyObject *py_version(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    return PyUnicode_FromString(taper_version());
}

static PyObject *py_setting_names(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    PyObject *t = PyTuple_New((Py_ssize_t)N_SETTINGS);
    if (!t) return NULL;
    for (size_t i = 0; i < N_SETTINGS; i++) {
        PyObject *s = PyUnicode_FromString(settings[i].name);
        if (!s) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, (Py_ssize_t)i, s);
    }
    return t;
}

/* status identifier -> (code, taper_strerror text), for read_granules. */
static PyObject *py_statuses(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    for (int s = TAPER_OK; s <= TAPER_ELIMIT; s++)
        if (put(d, status_id((taper_status)s), Py_BuildValue("(is)", s, taper_strerror((taper_status)s))) < 0) {
            Py_DECREF(d);
            return NULL;
        }
    return d;
}

/* ---- the chain alone ---------------------------------------------------------- */

/* chain(**chain_settings): the geometry the library builds (k R m X0, the
 * contact factors r_k) and the reduced masses mu_k of its theory. */
static PyObject *py_chain(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    if (no_positional(args, "chain") < 0) return NULL;
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    if (!cs) return raise_library(&err);
    if (parse_settings(kwargs, cs, NULL, "chain") < 0) {
        taper_chain_spec_free(cs);
        return NULL;
    }
    taper_chain *chain;
    Py_BEGIN_ALLOW_THREADS
    chain = taper_chain_alloc(cs, &err);
    Py_END_ALLOW_THREADS
    if (!chain) {
        taper_chain_spec_free(cs);
        return raise_library(&err);
    }
    size_t n = taper_chain_size(chain);
    PyObject *out = PyDict_New(), *cols = PyDict_New(), *mu = NULL;
    if (!out || !cols) goto fail;
    if (chain_columns(cols, chain) < 0) goto fail;
    if (put(cols, "r", double_array(taper_chain_contact(chain), n)) < 0) goto fail;
    if (!(mu = double_array(NULL, n))) goto fail;
    taper_status rc;
    Py_BEGIN_ALLOW_THREADS
    rc = taper_theory_compute(chain, NULL, PyArray_DATA((PyArrayObject *)mu), NULL, NULL, &err);
    Py_END_ALLOW_THREADS
    if (rc != TAPER_OK) {
        raise_library(&err);
        goto fail;
    }
    if (put(cols, "mu", mu) < 0) {
        mu = NULL;
        goto fail;
    }
    mu = NULL;
    const char *profile = taper_profile_name(taper_chain_profile(chain));
    if (put(out, "columns", Py_NewRef(cols)) < 0 ||
        put(out, "settings", settings_dict(cs, NULL)) < 0 ||
        put(out, "profile", PyUnicode_FromString(profile ? profile : "")) < 0 ||
        put(out, "exponent", PyFloat_FromDouble(taper_chain_exponent(chain))) < 0 ||
        put(out, "theory_note", taper_chain_theory_note(chain)
                                    ? PyUnicode_FromString(taper_chain_theory_note(chain))
                                    : Py_NewRef(Py_None)) < 0 ||
        put(out, "striker_mass", PyFloat_FromDouble(taper_chain_striker_mass(chain))) < 0)
        goto fail;
    Py_DECREF(cols);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    return out;
fail:
    Py_XDECREF(mu);
    Py_XDECREF(cols);
    Py_XDECREF(out);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    return NULL;
}

/* ---- asymptotic laws ---------------------------------------------------------- */

/* A name of a walked list (taper_X_name) -> its enum value, or an
 * InvalidArgumentError naming `what` and listing the names. */
static int enum_from_name(const char *(*name)(int), const char *what, PyObject *v, int *out)
{
    const char *s;
    if (get_str(what, v, &s) < 0) return -1;
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
    if (text) raise_with(InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, what,
                         PyUnicode_AsUTF8(text) + strlen(what) + 2);
    Py_XDECREF(text);
    return -1;
}

static const char *law_name_i(int i) { return taper_law_name((taper_law)i); }

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
static PyObject *py_asymptotic(PyObject *self, PyObject *args)
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
        if (get_real(fn->args[0], a, &x) < 0) return NULL;
        if (b && get_real(fn->args[1], b, &y) < 0) return NULL;
        return PyFloat_FromDouble(fn->f2 ? fn->f2(x, y) : fn->f1(x));
    }
    PyErr_Format(PyExc_ValueError, "no asymptotic function '%s'", name);
    return NULL;
}

/* asymptotic_exponent(law, n) -> float: taper_asymptotic_exponent, the law
 * given by its taper_law_name. */
static PyObject *py_asymptotic_exponent(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *law, *n_obj;
    int code;
    double n;
    if (!PyArg_ParseTuple(args, "OO:exponent", &law, &n_obj)) return NULL;
    if (enum_from_name(law_name_i, "law", law, &code) < 0) return NULL;
    if (get_real("n", n_obj, &n) < 0) return NULL;
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
        if (get_real("exponent", exponent, &p) < 0) return -1;
        rc = taper_fit_spec_set_exponent(spec, p, &err);
    }
    if (rc == TAPER_OK && index_window && index_window != Py_None) {
        PyObject *b, *e;
        long long begin, end = 0;
        if (get_pair("index_window", index_window, &b, &e) < 0) return -1;
        long long hi = (long long)(SIZE_MAX < (unsigned long long)LLONG_MAX ? SIZE_MAX : LLONG_MAX);
        if (get_integer("index_window", b, 0, hi, &begin) < 0) return -1;
        if (e != Py_None && get_integer("index_window", e, 0, hi, &end) < 0) return -1;
        rc = taper_fit_spec_set_index_window(spec, (size_t)begin, (size_t)end, &err);
    }
    if (rc == TAPER_OK && x_window && x_window != Py_None) {
        PyObject *lo, *hi;
        double x_min = -INFINITY, x_max = INFINITY;
        if (get_pair("x_window", x_window, &lo, &hi) < 0) return -1;
        if (lo != Py_None && get_real("x_window", lo, &x_min) < 0) return -1;
        if (hi != Py_None && get_real("x_window", hi, &x_max) < 0) return -1;
        rc = taper_fit_spec_set_x_window(spec, x_min, x_max, &err);
    }
    if (rc == TAPER_OK && skip_invalid && skip_invalid != Py_None) {
        int b;
        if (get_bool("skip_invalid", skip_invalid, &b) < 0) return -1;
        rc = taper_fit_spec_set_skip_invalid(spec, b, &err);
    }
    if (rc == TAPER_OK && max_iter && max_iter != Py_None) {
        long long m;
        long long hi = (long long)(SIZE_MAX < (unsigned long long)LLONG_MAX ? SIZE_MAX : LLONG_MAX);
        if (get_integer("max_iter", max_iter, 0, hi, &m) < 0) return -1;
        rc = taper_fit_spec_set_max_iter(spec, (size_t)m, &err);
    }
    if (rc == TAPER_OK && xtol && xtol != Py_None) {
        double t;
        if (get_real("xtol", xtol, &t) < 0) return -1;
        rc = taper_fit_spec_set_xtol(spec, t, &err);
    }
    if (rc != TAPER_OK) {
        raise_library(&err);
        return -1;
    }
    return 0;
}

/* fit(x, y, *, model, exponent, index_window, x_window, skip_invalid,
 * max_iter, xtol) -> dict: taper_fit with each keyword passed to the fit
 * setter of its name. */
static PyObject *py_fit(PyObject *self, PyObject *args, PyObject *kwargs)
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
        if (get_str("model", model, &s) < 0) return NULL;
        if (taper_fit_model_from_name(s, &code, &err) != TAPER_OK) return raise_library(&err);
    }
    PyArrayObject *x = real_vector("x", xo);
    if (!x) return NULL;
    PyArrayObject *y = real_vector("y", yo);
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
        if (text) raise_with(InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL, "y",
                             PyUnicode_AsUTF8(text) + 3);
        Py_XDECREF(text);
        goto done;
    }
    if (!(spec = taper_fit_spec_alloc(code, &err))) {
        raise_library(&err);
        goto done;
    }
    if (fit_settings(spec, exponent, index_window, x_window, skip_invalid, max_iter, xtol) < 0)
        goto done;
    Py_BEGIN_ALLOW_THREADS
    res = taper_fit(spec, PyArray_DATA(x), PyArray_DATA(y), (size_t)n, &err);
    Py_END_ALLOW_THREADS
    if (!res) {
        raise_library(&err);
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
            put(out, "model", PyUnicode_FromString(mname ? mname : "")) < 0 ||
            put(out, "params", double_array(p, shown)) < 0 ||
            put(out, "errors", double_array(e, shown)) < 0 ||
            put(out, "n_params", PyLong_FromSize_t(np)) < 0 ||
            put(out, "n_points", PyLong_FromSize_t(taper_fit_result_n_points(res))) < 0 ||
            put(out, "n_skipped", PyLong_FromSize_t(taper_fit_result_n_skipped(res))) < 0 ||
            put(out, "chi2", PyFloat_FromDouble(taper_fit_result_chi2(res))) < 0 ||
            put(out, "iterations", PyLong_FromSize_t(taper_fit_result_iterations(res))) < 0)
            Py_CLEAR(out);
    }
done:
    taper_fit_result_free(res);
    taper_fit_spec_free(spec);
    Py_DECREF(x);
    Py_DECREF(y);
    return out;
}

static PyMethodDef methods[] = {
    {"simulate", (PyCFunction)(void (*)(void))py_simulate, METH_VARARGS | METH_KEYWORDS,
     "simulate(**settings) -> dict: build the chain, integrate it (GIL released), return its "
     "columns, statistics and status."},
    {"theory", (PyCFunction)(void (*)(void))py_theory, METH_VARARGS | METH_KEYWORDS,
     "theory(**chain_settings) -> dict: the binary collision columns alone."},
    {"run_scene", py_run_scene, METH_O,
     "run_scene(path) -> list of dict: the scene read by the driver's reader, one run per "
     "swept value."},
    {"collision_time", (PyCFunction)(void (*)(void))py_collision_time, METH_VARARGS | METH_KEYWORDS,
     "collision_time(mu, r, zdot0, n=2.5) -> float: residence time of one binary collision, "
     "eq. (18)."},
    {"chain", (PyCFunction)(void (*)(void))py_chain, METH_VARARGS | METH_KEYWORDS,
     "chain(**chain_settings) -> dict: the chain's columns k R m X0 r mu, no theory times, no "
     "integration."},
    {"asymptotic", py_asymptotic, METH_VARARGS,
     "asymptotic(name, x[, n]) -> float: taper_asymptotic_<name>."},
    {"asymptotic_exponent", py_asymptotic_exponent, METH_VARARGS,
     "asymptotic_exponent(law, n) -> float: the exponent of a law named as in LAWS."},
    {"fit", (PyCFunction)(void (*)(void))py_fit, METH_VARARGS | METH_KEYWORDS,
     "fit(x, y, *, model, exponent, index_window, x_window, skip_invalid, max_iter, xtol) -> "
     "dict: taper_fit, each keyword passed to the fit setter of its name."},
    {"version", py_version, METH_NOARGS, "version() -> str: the version of libtaper linked in."},
    {"setting_names", py_setting_names, METH_NOARGS, "The keyword arguments simulate() takes."},
    {"statuses", py_statuses, METH_NOARGS, "{identifier: (code, description)} of taper_status."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "taper._core",
                                    "libtaper, compiled in (see the package taper).", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__core(void)
{
    import_array();
    PyObject *m = PyModule_Create(&module);
    if (!m) return NULL;
    TaperError = PyErr_NewExceptionWithDoc(
        "taper.TaperError",
        "A libtaper failure: .status (identifier), .field (the argument at fault, or None), "
        ".message (the library's message).",
        NULL, NULL);
    PyObject *bases = TaperError ? PyTuple_Pack(2, TaperError, PyExc_ValueError) : NULL;
    if (bases) {
        InvalidArgumentError = PyErr_NewExceptionWithDoc(
            "taper.InvalidArgumentError",
            "A value the library refused; .field names the argument (taper_error.field).", bases,
            NULL);
        SceneError = PyErr_NewExceptionWithDoc(
            "taper.SceneError", "A scene file the driver's reader rejects (its diagnostics).",
            bases, NULL);
        Py_DECREF(bases);
    }
    if (!TaperError || !InvalidArgumentError || !SceneError ||
        PyModule_AddObject(m, "TaperError", Py_NewRef(TaperError)) < 0 ||
        PyModule_AddObject(m, "InvalidArgumentError", Py_NewRef(InvalidArgumentError)) < 0 ||
        PyModule_AddObject(m, "SceneError", Py_NewRef(SceneError)) < 0 ||
        PyModule_AddObject(m, "PROFILES", names_tuple(profile_name_i)) < 0 ||
        PyModule_AddObject(m, "METHODS", names_tuple(method_name_i)) < 0 ||
        PyModule_AddObject(m, "STATISTICS", names_tuple(statistic_name_i)) < 0 ||
        PyModule_AddObject(m, "OBSERVABLES", names_tuple(observable_name_i)) < 0 ||
        PyModule_AddObject(m, "THEORY_QUANTITIES", names_tuple(quantity_name_i)) < 0 ||
        PyModule_AddObject(m, "LAWS", names_tuple(law_name_i)) < 0 ||
        PyModule_AddObject(m, "FIT_MODELS", names_tuple(fit_model_name_i)) < 0 ||
        PyModule_AddObject(m, "BOUNDARIES", names_tuple(boundary_name_i)) < 0 ||
        PyModule_AddObject(m, "DISORDERS", names_tuple(disorder_name_i)) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
