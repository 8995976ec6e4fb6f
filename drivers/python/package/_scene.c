/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _scene.c -- every call of the package that runs a chain is a scene of the
 * driver's scene module (drivers/scenes/scene/scene.h): the same variables,
 * defaults, validation and messages as `taper SCENE.nml`.  Why the package
 * links the scenes' library (taper_scenes) rather than ship the driver and
 * read back its granules.tsv: a keyword, a file's variable and `taper --set`
 * then mean one thing with one default, range, message and unit, with no
 * subprocess, no files written and no second copy of libtaper (the driver
 * links libtaper.so).  The scene costs a call some microseconds, two thirds
 * of taper.theory(n_granules=2) (drivers/bench/python_overheads.py).
 *
 * Keywords: a keyword is a scene variable's one name (scene_var_keyword_at:
 * the key in its group, with the group's name in front where two groups
 * share a key: striker_radius is &striker radius).  Its Python value is
 * converted by the variable's type (scene_type) and set with
 * scene_set_values, which checks it as a file's value is; then
 * scene_validate checks the scene as a whole, the library's settings
 * through the library's setters.  Nothing here knows a variable by name,
 * except numerics, which theory() sets, and progress, which simulate()
 * also takes as a callable (called during the run).  The rows of the
 * keywords are looked up in a dict made once (the table's own lookup
 * compares every name, case-insensitively, as files need).
 *
 * Units: with &material every dimensional input is SI (the scene converts
 * it per run point, scene_lib.c), and results are converted back to the
 * scene's units (&output units) as granules.tsv's are:
 * scene_column_convert for the columns, the dimensions of the library's
 * statistics, and the units of length, velocity, time and force for the
 * samples and the final state.
 *
 * A result keeps its scene (a capsule shared by the results of one scene)
 * so that its echo, the resolved namelist, and its settings are made only
 * when asked for.
 */
#include "_scene.h"

#include "results/pulse.h"
#include "scene/scene.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CAPSULE_NAME "taper._core.scene"

static const char *const call_names[] = {"simulate", "theory", "chain",    "check",
                                         "cite",     "calibrate", "design"};

/* {keyword: row} of the table, made on first use (the GIL held). */
static PyObject *keyword_rows;
static int numerics_row = -1, progress_row = -1;

static int keyword_rows_ready(void)
{
    if (keyword_rows) return 0;
    PyObject *d = PyDict_New();
    for (size_t i = 0; d && i < scene_var_count(); i++)
        if (core_put(d, scene_var_keyword_at(i), PyLong_FromSize_t(i)) < 0) Py_CLEAR(d);
    if (!d) return -1;
    numerics_row = scene_var_keyword("numerics");
    progress_row = scene_var_keyword("progress");
    keyword_rows = d;
    return 0;
}

/* The row of a keyword spelt exactly as its variable, or -1 (no exception). */
static int row_of(PyObject *key)
{
    PyObject *row = PyDict_GetItemWithError(keyword_rows, key);
    if (!row) {
        PyErr_Clear();
        return -1;
    }
    return (int)PyLong_AsLong(row);
}

static void capsule_free(PyObject *capsule)
{
    scene_free(PyCapsule_GetPointer(capsule, CAPSULE_NAME));
}

/* ---- Python values -> scene values ------------------------------------------- */

/* A list, a tuple or an array of one or more dimensions. */
static int is_sequence(PyObject *v)
{
    return PyList_Check(v) || PyTuple_Check(v) || (PyArray_Check(v) && PyArray_NDIM((PyArrayObject *)v) > 0);
}

/* The values of v for variable `row`, by its type: *n values in *out
 * (PyMem_Malloc'd; a string points into v, which outlives them).  0, or -1
 * with TypeError (or InvalidArgumentError for an integer beyond 64 bits). */
static int values_of(size_t row, const char *func, PyObject *v, scene_value **out, size_t *n)
{
    const char *name = scene_var_keyword_at(row);
    scene_type type = scene_var_type(row);
    *out = NULL;
    *n = 0;
    if (type == SCENE_REAL_LIST) {
        PyArrayObject *a = core_real_vector(name, v);
        if (!a) return -1;
        size_t m = (size_t)PyArray_DIM(a, 0);
        const double *x = PyArray_DATA(a);
        scene_value *vals = m ? PyMem_Malloc(m * sizeof *vals) : NULL;
        if (m && !vals) {
            Py_DECREF(a);
            PyErr_NoMemory();
            return -1;
        }
        for (size_t i = 0; i < m; i++) vals[i] = (scene_value){.kind = SCENE_VALUE_REAL, .x = x[i]};
        Py_DECREF(a);
        *out = vals;
        *n = m;
        return 0;
    }
    if (is_sequence(v) && scene_var_takes_list(row)) {
        /* The scene would sweep it; a call runs one chain. */
        PyErr_Format(PyExc_TypeError,
                     "%s() runs one chain: %s takes one value, not a %.50s (a list of values "
                     "is a sweep: give it in a scene file to taper.run_scene, or call %s() once "
                     "per value)", func, name, Py_TYPE(v)->tp_name, func);
        return -1;
    }
    scene_value *val = PyMem_Malloc(sizeof *val);
    if (!val) {
        PyErr_NoMemory();
        return -1;
    }
    memset(val, 0, sizeof *val);
    int rc = -1;
    switch (type) {
    case SCENE_STRING:
    case SCENE_CHOICE:
        val->kind = SCENE_VALUE_STRING;
        rc = core_get_str(name, v, &val->s);
        break;
    case SCENE_REAL:
        val->kind = SCENE_VALUE_REAL;
        rc = core_get_real(name, v, &val->x);
        break;
    case SCENE_INTEGER:
        val->kind = SCENE_VALUE_INTEGER;
        rc = core_get_integer(name, v, LLONG_MIN, LLONG_MAX, &val->i);
        break;
    case SCENE_LOGICAL:
        val->kind = SCENE_VALUE_LOGICAL;
        rc = core_get_bool(name, v, &val->b);
        break;
    case SCENE_REAL_LIST: break; /* above */
    }
    if (rc != 0) {
        PyMem_Free(val);
        return -1;
    }
    *out = val;
    *n = 1;
    return 0;
}

/* ---- diagnostics -> exceptions ------------------------------------------------- */

/* The keyword of the variable a diagnostic names, or NULL. */
static const char *diag_keyword(const scene_diag *d)
{
    int row = d->group[0] ? scene_var_find(d->group, d->key) : scene_var_keyword(d->key);
    return row >= 0 ? scene_var_keyword_at((size_t)row) : NULL;
}

/* InvalidArgumentError from the scene's diagnostics: .field the first's
 * keyword, .message its message; the text every diagnostic, one a line, as
 * "keyword: message". */
static PyObject *raise_diags(const scene *sc)
{
    size_t n = scene_diag_count(sc);
    if (n == 0) return PyErr_NoMemory(); /* an error that could not be recorded */
    PyObject *text = PyUnicode_FromString("");
    for (size_t i = 0; text && i < n; i++) {
        const scene_diag *d = scene_diag_at(sc, i);
        const char *kw = diag_keyword(d);
        PyObject *t = PyUnicode_FromFormat("%U%s%s%s%s", text, i ? "\n" : "", kw ? kw : "",
                                           kw ? ": " : "", d->message);
        Py_DECREF(text);
        text = t;
    }
    size_t more = scene_error_count(sc) - n;
    if (text && more) {
        PyObject *t = PyUnicode_FromFormat("%U\n(%zu more errors)", text, more);
        Py_DECREF(text);
        text = t;
    }
    if (!text) return NULL;
    const scene_diag *first = scene_diag_at(sc, 0);
    core_raise(core_InvalidArgumentError, PyUnicode_AsUTF8(text), TAPER_EINVAL,
               diag_keyword(first), first->message);
    Py_DECREF(text);
    return NULL;
}

/* The reader's diagnostics of a scene file as the driver prints them
 * (FILE:LINE: &group key: message): SceneError. */
static PyObject *raise_file_diags(const scene *sc)
{
    char *diag = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&diag, &len);
    if (!mem) return PyErr_NoMemory();
    scene_print_diags(sc, mem);
    fclose(mem);
    if (diag && len && diag[len - 1] == '\n') diag[len - 1] = '\0'; /* one message */
    if (!diag || !len) {
        free(diag);
        return PyErr_NoMemory();
    }
    core_raise(core_SceneError, diag, TAPER_EINVAL, NULL, diag);
    free(diag);
    return NULL;
}

/* ---- a scene from keywords --------------------------------------------------------- */

static int set_one(scene *sc, size_t row, const char *func, PyObject *value)
{
    scene_value *vals;
    size_t n;
    if (values_of(row, func, value, &vals, &n) != 0) return -1;
    /* An empty list is no list: the default. */
    size_t errors = n ? scene_set_values(sc, scene_var_keyword_at(row), vals, n) : 0;
    PyMem_Free(vals);
    if (errors) {
        raise_diags(sc);
        return -1;
    }
    return 0;
}

/* The scene of a call's keywords, validated; NULL with an exception.  A
 * callable given for progress goes to *progress (borrowed from kwargs). */
static scene *scene_of(pyscene_kind kind, PyObject *args, PyObject *kwargs, PyObject **progress)
{
    const char *func = call_names[kind];
    *progress = NULL;
    if (PyTuple_GET_SIZE(args) != 0) {
        PyErr_Format(PyExc_TypeError, "%s() takes keyword arguments only (%zd positional given)",
                     func, PyTuple_GET_SIZE(args));
        return NULL;
    }
    if (keyword_rows_ready() < 0) return NULL;
    /* The call's name names the scene in its echo (&output dir = 'out/NAME'). */
    scene *sc = scene_new(func);
    if (!sc) {
        PyErr_NoMemory();
        return NULL;
    }
    scene_keep_samples(sc); /* they go to Result.samples */
    const int numerics = numerics_row;
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    while (kwargs && PyDict_Next(kwargs, &pos, &key, &value)) {
        int row = row_of(key);
        if (row < 0) {
            /* The table's names are case-insensitive for files; a keyword is
             * spelt as its variable is. */
            const char *k = PyUnicode_AsUTF8(key);
            if (!k) goto fail;
            int nocase = scene_var_keyword(k);
            const char *near = nocase >= 0 ? scene_var_keyword_at((size_t)nocase)
                                           : scene_nearest_keyword(k);
            if (near)
                PyErr_Format(PyExc_TypeError, "%s() got an unexpected keyword argument '%s' "
                             "(did you mean '%s'? taper.variables() lists them)", func, k, near);
            else
                PyErr_Format(PyExc_TypeError, "%s() got an unexpected keyword argument '%s' "
                             "(taper.variables() lists them)", func, k);
            goto fail;
        }
        if (kind == PYSCENE_THEORY && row == numerics) {
            PyErr_Format(PyExc_TypeError, "theory() got the keyword argument 'numerics': it is "
                         "the scene with numerics = .false. (simulate(numerics=...) chooses)");
            goto fail;
        }
        if (value == Py_None) continue; /* the default */
        if (row == progress_row && !core_is_bool(value) && PyCallable_Check(value)) {
            *progress = value;
            value = Py_True;
        }
        if (set_one(sc, (size_t)row, func, value) != 0) goto fail;
    }
    if (kind == PYSCENE_THEORY) {
        scene_value off = {.kind = SCENE_VALUE_LOGICAL, .b = 0};
        if (scene_set_values(sc, scene_var_keyword_at((size_t)numerics), &off, 1) != 0) {
            raise_diags(sc);
            goto fail;
        }
    }
    if (scene_validate(sc) != 0) {
        raise_diags(sc);
        goto fail;
    }
    return sc;
fail:
    scene_free(sc);
    return NULL;
}

scene *pyscene_scene(pyscene_kind kind, PyObject *args, PyObject *kwargs)
{
    PyObject *progress; /* an optimisation reports no progress of its runs */
    return scene_of(kind, args, kwargs, &progress);
}

/* ---- results in the scene's units -------------------------------------------------- */

/* The value of variable i at run `point`: a swept variable's value there,
 * else by its type (a real without value, an empty list: None). */
static PyObject *setting_value(const scene *sc, size_t point, size_t i)
{
    const scene_config *cfg = scene_cfg(sc);
    for (size_t k = 0; k < cfg->runs.n_swept; k++)
        if (cfg->runs.swept_row[k] == i) {
            double x = scene_swept_value(cfg, point, k);
            return scene_swept_integer(cfg, k) ? PyLong_FromLongLong((long long)x)
                                               : PyFloat_FromDouble(x);
        }
    size_t n = 0;
    const double *x;
    switch (scene_var_type(i)) {
    case SCENE_STRING:
    case SCENE_CHOICE: {
        const char *s = scene_var_text(sc, i);
        return PyUnicode_DecodeUTF8(s, (Py_ssize_t)strlen(s), "replace");
    }
    case SCENE_INTEGER: return PyLong_FromLongLong(scene_var_integer(sc, i));
    case SCENE_LOGICAL: return PyBool_FromLong((long)scene_var_integer(sc, i));
    case SCENE_REAL:
        x = scene_var_reals(sc, i, &n);
        return n ? PyFloat_FromDouble(x[0]) : Py_NewRef(Py_None);
    case SCENE_REAL_LIST:
        x = scene_var_reals(sc, i, &n);
        if (!n) return Py_NewRef(Py_None);
        /* variables() runs when the package is imported, before numpy is. */
        return core_numpy() < 0 ? NULL : core_double_array(x, n);
    }
    return Py_NewRef(Py_None);
}

/* Every variable by its keyword, at run `point`. */
static PyObject *settings_of(const scene *sc, size_t point)
{
    PyObject *d = PyDict_New();
    for (size_t i = 0; d && i < scene_var_count(); i++)
        if (core_put(d, scene_var_keyword_at(i), setting_value(sc, point, i)) < 0) Py_CLEAR(d);
    return d;
}

/* d[name] *= scale for a float array or a float (a new object). */
static int scale_item(PyObject *d, const char *name, double scale)
{
    PyObject *v = PyDict_GetItemString(d, name);
    if (!v || scale == 1.0) return 0;
    if (PyArray_Check(v)) {
        PyArrayObject *a = (PyArrayObject *)v;
        double *x = PyArray_DATA(a);
        for (npy_intp j = 0, n = PyArray_SIZE(a); j < n; j++) x[j] *= scale;
        return 0;
    }
    double x = PyFloat_AsDouble(v);
    if (x == -1.0 && PyErr_Occurred()) return -1;
    return core_put(d, name, PyFloat_FromDouble(x * scale));
}

/* units[name] = the SI unit of dim, when the results are in SI and dim is
 * not a pure number. */
static int put_unit(PyObject *units, const scene_config *at, const char *name,
                    taper_dimension dim)
{
    const char *u = dim == TAPER_DIM_NUMBER ? NULL : scene_unit_suffix(at, dim);
    return u ? core_put(units, name, PyUnicode_FromString(u)) : 0;
}

/* The rows of granules k = 1, 1 + every, ..., and the last (&output
 * every), as the driver writes them. */
static PyObject *thin_rows(PyObject *column, size_t every)
{
    PyArrayObject *a = (PyArrayObject *)column;
    npy_intp n = PyArray_DIM(a, 0), m = 0;
    npy_intp dim = n ? (n - 1) / (npy_intp)every + 1 + ((n - 1) % (npy_intp)every != 0) : 0;
    PyObject *index = PyArray_SimpleNew(1, &dim, NPY_INTP);
    if (!index) return NULL;
    npy_intp *ix = PyArray_DATA((PyArrayObject *)index);
    for (npy_intp k = 1; k <= n; k++)
        if ((size_t)(k - 1) % every == 0 || k == n) ix[m++] = k - 1;
    PyObject *thin = PyArray_TakeFrom(a, index, 0, NULL, NPY_RAISE);
    Py_DECREF(index);
    return thin;
}

/* stats["pulse_speed"] of a run (results/pulse.h), from its whole columns
 * converted to the scene's units, as granules.tsv's header has it. */
static int add_pulse_speed(PyObject *d, PyObject *raw, const scene_config *at, PyObject *units)
{
    PyObject *stats = PyDict_GetItemString(d, "stats");
    PyObject *x = PyDict_GetItemString(raw, taper_observable_name(TAPER_X_PASS));
    PyObject *t = PyDict_GetItemString(raw, taper_observable_name(TAPER_T_PASS));
    if (!stats || !x || !t) return 0; /* the theory alone */
    const double v = pulse_speed(PyArray_DATA((PyArrayObject *)x), PyArray_DATA((PyArrayObject *)t),
                                 NULL, (size_t)PyArray_DIM((PyArrayObject *)x, 0));
    if (core_put(stats, PULSE_SPEED_NAME, PyFloat_FromDouble(v)) < 0) return -1;
    return put_unit(units, at, PULSE_SPEED_NAME, TAPER_DIM_VELOCITY);
}

/* Granules converted between two looks at Ctrl-C. */
#define CONVERT_BLOCK ((size_t)1 << 18)

/* The columns of a run as granules.tsv has them (&output columns, every),
 * in its order, converted to the scene's units. */
static int shape_columns(PyObject *d, const scene_config *at, PyObject *units)
{
    PyObject *raw = PyDict_GetItemString(d, "columns");
    PyObject *x0 = raw ? PyDict_GetItemString(raw, scene_column_name(SCENE_COL_X0)) : NULL;
    if (!raw || !x0) {
        PyErr_SetString(PyExc_SystemError, "a run without the columns of its chain");
        return -1;
    }
    const int si = scene_unit_suffix(at, TAPER_DIM_LENGTH) != NULL;
    const size_t n = (size_t)PyArray_DIM((PyArrayObject *)x0, 0);
    /* X_pass = X0 + x_k converts with the rest positions in R_1. */
    double *rest = si ? malloc((n ? n : 1) * sizeof *rest) : NULL;
    if (si && !rest) {
        PyErr_NoMemory();
        return -1;
    }
    if (rest && core_copy_checked(rest, PyArray_DATA((PyArrayObject *)x0), n) < 0) {
        free(rest);
        return -1;
    }
    PyObject *cols = PyDict_New();
    for (int c = 0; cols && c < SCENE_N_COLUMNS; c++) {
        const char *name = scene_column_name((scene_column)c);
        PyObject *a = PyDict_GetItemString(raw, name);
        if (!a) continue;
        /* in blocks, Ctrl-C looked for between them (the GIL is held) */
        double *values = PyArray_DATA((PyArrayObject *)a);
        for (size_t from = 0; si && c != SCENE_COL_K && from < n; from += CONVERT_BLOCK) {
            if (from && PyErr_CheckSignals() < 0) {
                Py_CLEAR(cols);
                break;
            }
            scene_column_convert(at, (scene_column)c, values + from, rest + from,
                                 n - from < CONVERT_BLOCK ? n - from : CONVERT_BLOCK);
        }
        if (!cols) break;
        if (!(at->output.column_set & (1u << c))) continue; /* converted for the speed */
        PyObject *kept = at->output.every > 1 ? thin_rows(a, (size_t)at->output.every)
                                              : Py_NewRef(a);
        if (core_put(cols, name, kept) < 0 ||
            put_unit(units, at, name, scene_column_dimension((scene_column)c)) < 0)
            Py_CLEAR(cols);
    }
    free(rest);
    if (cols && add_pulse_speed(d, raw, at, units) < 0) Py_CLEAR(cols);
    return cols ? core_put(d, "columns", cols) : -1;
}

/* The statistics, the final state and the samples in the scene's units. */
static int convert_run(PyObject *d, const scene_config *at, PyObject *units)
{
    PyObject *stats = PyDict_GetItemString(d, "stats");
    for (int i = 0; stats && taper_statistic_name((taper_statistic)i); i++) {
        const char *name = taper_statistic_name((taper_statistic)i);
        taper_dimension dim = taper_statistic_dimension((taper_statistic)i);
        if (dim == TAPER_DIM_NUMBER || !PyDict_GetItemString(stats, name)) continue;
        if (scale_item(stats, name, scene_unit(at, dim)) < 0 || put_unit(units, at, name, dim) < 0)
            return -1;
    }
    static const struct {
        const char *name;
        taper_dimension dim;
    } state[] = {{"x_final", TAPER_DIM_LENGTH}, {"v_final", TAPER_DIM_VELOCITY}},
      samples[] = {{"t", TAPER_DIM_TIME}, {"x", TAPER_DIM_LENGTH}, {"v", TAPER_DIM_VELOCITY},
                   {"force", TAPER_DIM_FORCE}};
    for (size_t j = 0; j < sizeof state / sizeof state[0]; j++) {
        if (!PyDict_GetItemString(d, state[j].name)) continue;
        if (scale_item(d, state[j].name, scene_unit(at, state[j].dim)) < 0 ||
            put_unit(units, at, state[j].name, state[j].dim) < 0)
            return -1;
    }
    PyObject *smp = PyDict_GetItemString(d, "samples");
    for (size_t j = 0; smp && j < sizeof samples / sizeof samples[0]; j++)
        if (scale_item(smp, samples[j].name, scene_unit(at, samples[j].dim)) < 0 ||
            put_unit(units, at, samples[j].name, samples[j].dim) < 0)
            return -1;
    return 0;
}

/* What every result of a scene carries: its scene and point (for the echo
 * and the settings, made when asked for: pyscene_text, pyscene_settings),
 * the units, where it came from. */
static int add_scene(PyObject *d, PyObject *capsule, PyObject *source, size_t point,
                     PyObject *units)
{
    if (core_put(d, "units", Py_NewRef(units)) < 0 ||
        core_put(d, "scene", Py_NewRef(capsule)) < 0 ||
        core_put(d, "point", PyLong_FromSize_t(point)) < 0 ||
        core_put(d, "source", Py_NewRef(source)) < 0)
        return -1;
    return 0;
}

/* Run `point` of a validated scene with the driver's specs: its chain, and
 * its sim unless it asks for the theory alone, sampled at its &sensors
 * interval, watched by `progress` (NULL: none). */
static PyObject *run_point(PyObject *capsule, const scene *sc, size_t point, PyObject *source,
                           PyObject *progress)
{
    scene_config at;
    scene_config_at(scene_cfg(sc), point, &at);
    taper_error err;
    taper_chain_spec *cs = scene_chain_spec(&at, 0, &err);
    if (!cs) return core_raise_library(&err);
    taper_solver_spec *ss = NULL;
    if (at.solver.numerics && !(ss = scene_solver_spec(&at, &err))) {
        taper_chain_spec_free(cs);
        return core_raise_library(&err);
    }
    const char *seconds = scene_unit_suffix(&at, TAPER_DIM_TIME);
    core_sampling sampling = {.interval = ss ? scene_sample_interval(&at) : 0.0,
                              .max_bytes = at.output.max_output,
                              .time_scale = scene_unit(&at, TAPER_DIM_TIME),
                              .time_unit = seconds,
                              .progress = progress};
    PyObject *d = core_run(cs, ss, &sampling);
    taper_solver_spec_free(ss);
    taper_chain_spec_free(cs);
    PyObject *units = d ? PyDict_New() : NULL;
    if (units && shape_columns(d, &at, units) == 0 && convert_run(d, &at, units) == 0 &&
        add_scene(d, capsule, source, point, units) == 0) {
        Py_DECREF(units);
        return d;
    }
    Py_XDECREF(units);
    Py_XDECREF(d);
    return NULL;
}

/* The chain of a validated scene, its sizes and masses in the scene's
 * units (the contact factors r_k stay relative to granule 1's). */
static PyObject *chain_of(PyObject *capsule, const scene *sc, PyObject *source)
{
    scene_config at;
    scene_config_at(scene_cfg(sc), 0, &at);
    taper_error err;
    taper_chain_spec *cs = scene_chain_spec(&at, 0, &err);
    if (!cs) return core_raise_library(&err);
    PyObject *d = core_chain(cs);
    taper_chain_spec_free(cs);
    PyObject *units = d ? PyDict_New() : NULL;
    PyObject *cols = d ? PyDict_GetItemString(d, "columns") : NULL;
    if (!units || !cols) goto fail;
    if (scene_unit_suffix(&at, TAPER_DIM_LENGTH)) {
        static const scene_column sized[] = {SCENE_COL_R, SCENE_COL_M, SCENE_COL_X0};
        for (size_t j = 0; j < sizeof sized / sizeof sized[0]; j++) {
            const char *name = scene_column_name(sized[j]);
            PyArrayObject *a = (PyArrayObject *)PyDict_GetItemString(cols, name);
            scene_column_convert(&at, sized[j], PyArray_DATA(a), NULL, (size_t)PyArray_DIM(a, 0));
            if (put_unit(units, &at, name, scene_column_dimension(sized[j])) < 0) goto fail;
        }
        double mass = scene_unit(&at, TAPER_DIM_MASS);
        if (scale_item(cols, "mu", mass) < 0 || scale_item(d, "striker_mass", mass) < 0 ||
            put_unit(units, &at, "mu", TAPER_DIM_MASS) < 0 ||
            put_unit(units, &at, "striker_mass", TAPER_DIM_MASS) < 0)
            goto fail;
    }
    if (add_scene(d, capsule, source, 0, units) < 0) goto fail;
    Py_DECREF(units);
    return d;
fail:
    Py_XDECREF(units);
    Py_XDECREF(d);
    return NULL;
}

/* The BibTeX of taper --cite for the scene, as str; frees sc. */
static PyObject *citations_of(scene *sc)
{
    char *text = NULL;
    size_t size = 0;
    FILE *fp = open_memstream(&text, &size);
    unsigned works = 0;
    int failed = !fp || scene_cite_mark(sc, &works) != 0 || scene_write_citations(works, fp) != 0;
    if (fp) failed |= fclose(fp) != 0;
    scene_free(sc);
    PyObject *str = failed ? PyErr_NoMemory() : PyUnicode_FromStringAndSize(text, (Py_ssize_t)size);
    free(text);
    return str;
}

PyObject *pyscene_call(pyscene_kind kind, PyObject *args, PyObject *kwargs)
{
    PyObject *progress;
    scene *sc = scene_of(kind, args, kwargs, &progress);
    if (!sc) return NULL;
    if (kind == PYSCENE_CHECK) {
        scene_free(sc);
        Py_RETURN_NONE;
    }
    if (kind == PYSCENE_CITE) return citations_of(sc);
    PyObject *capsule = PyCapsule_New(sc, CAPSULE_NAME, capsule_free);
    if (!capsule) {
        scene_free(sc);
        return NULL;
    }
    PyObject *source = PyUnicode_FromString(call_names[kind]), *d = NULL;
    if (source)
        d = kind == PYSCENE_CHAIN ? chain_of(capsule, sc, source)
                                  : run_point(capsule, sc, 0, source, progress);
    Py_XDECREF(source);
    Py_DECREF(capsule);
    return d;
}

PyObject *pyscene_run_file(PyObject *arg)
{
    PyObject *bytes = NULL;
    if (!PyUnicode_FSConverter(arg, &bytes)) return NULL;
    const char *path = PyBytes_AS_STRING(bytes);
    scene *sc = scene_new(path);
    if (!sc) {
        Py_DECREF(bytes);
        return PyErr_NoMemory();
    }
    size_t errors;
    Py_BEGIN_ALLOW_THREADS
    errors = scene_load(sc);
    if (!errors) errors = scene_validate(sc);
    Py_END_ALLOW_THREADS
    if (errors) {
        raise_file_diags(sc);
        scene_free(sc);
        Py_DECREF(bytes);
        return NULL;
    }
    PyObject *capsule = PyCapsule_New(sc, CAPSULE_NAME, capsule_free);
    if (!capsule) scene_free(sc);
    PyObject *source = capsule ? PyUnicode_DecodeFSDefault(path) : NULL;
    PyObject *list = source ? PyList_New(0) : NULL;
    size_t n = scene_cfg(sc)->runs.n;
    for (size_t i = 0; list && i < n; i++) {
        PyObject *r = run_point(capsule, sc, i, source, NULL);
        if (!r || PyList_Append(list, r) < 0) Py_CLEAR(list);
        Py_XDECREF(r);
    }
    Py_XDECREF(source);
    Py_XDECREF(capsule);
    Py_DECREF(bytes);
    return list;
}

/* The scene and point of (capsule, point) arguments, or NULL. */
static const scene *scene_point(PyObject *args, const char *format, Py_ssize_t *point)
{
    PyObject *capsule;
    if (!PyArg_ParseTuple(args, format, &capsule, point)) return NULL;
    const scene *sc = PyCapsule_GetPointer(capsule, CAPSULE_NAME);
    if (!sc) return NULL;
    if (*point < 0 || (size_t)*point >= scene_cfg(sc)->runs.n) {
        PyErr_Format(PyExc_IndexError, "the scene has %zu runs", scene_cfg(sc)->runs.n);
        return NULL;
    }
    return sc;
}

PyObject *pyscene_settings(PyObject *args)
{
    Py_ssize_t point;
    const scene *sc = scene_point(args, "On:scene_settings", &point);
    return sc ? settings_of(sc, (size_t)point) : NULL;
}

PyObject *pyscene_swept(PyObject *args)
{
    Py_ssize_t point;
    const scene *sc = scene_point(args, "On:scene_swept", &point);
    if (!sc) return NULL;
    const scene_config *cfg = scene_cfg(sc);
    char *name = scene_point_name(cfg, (size_t)point);
    if (!name) return PyErr_NoMemory();
    PyObject *values = PyList_New(0);
    for (size_t k = 0; values && k < cfg->runs.n_swept; k++) {
        PyObject *pair = Py_BuildValue("(sd)", scene_swept_name(cfg, k),
                                       scene_swept_value(cfg, (size_t)point, k));
        if (!pair || PyList_Append(values, pair) < 0) Py_CLEAR(values);
        Py_XDECREF(pair);
    }
    PyObject *out = values ? Py_BuildValue("(sN)", name, values) : NULL;
    free(name);
    return out;
}

PyObject *pyscene_text(PyObject *args)
{
    Py_ssize_t point;
    const scene *sc = scene_point(args, "On:scene_text", &point);
    if (!sc) return NULL;
    char *text = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&text, &len);
    if (!mem) return PyErr_NoMemory();
    scene_write_point(sc, mem, (size_t)point);
    fclose(mem);
    PyObject *s = text ? PyUnicode_DecodeUTF8(text, (Py_ssize_t)len, "replace") : PyErr_NoMemory();
    free(text);
    return s;
}

/* ---- the table --------------------------------------------------------------------- */

/* The type's word as docs/scene.md writes it. */
static const char *type_word(scene_type t)
{
    static const char *const words[] = {
        [SCENE_STRING] = "string", [SCENE_REAL] = "real",           [SCENE_INTEGER] = "integer",
        [SCENE_LOGICAL] = "logical", [SCENE_REAL_LIST] = "real list", [SCENE_CHOICE] = "choice"};
    return (unsigned)t < sizeof words / sizeof words[0] ? words[t] : "";
}

static PyObject *names_of(const char *const *names)
{
    if (!names) return Py_NewRef(Py_None);
    Py_ssize_t n = 0;
    while (names[n]) n++;
    PyObject *t = PyTuple_New(n);
    for (Py_ssize_t j = 0; t && j < n; j++) {
        PyObject *s = PyUnicode_FromString(names[j]);
        if (!s) Py_CLEAR(t);
        else PyTuple_SET_ITEM(t, j, s);
    }
    return t;
}

PyObject *pyscene_variables(void)
{
    static const char *const checkers[] = {[SCENE_OWN] = "scene", [SCENE_LIB_CHAIN] = "chain",
                                           [SCENE_LIB_SOLVER] = "solver", [SCENE_LIB_FIT] = "fit"};
    scene *sc = scene_new(call_names[PYSCENE_SIMULATE]); /* the defaults of simulate() */
    if (!sc) return PyErr_NoMemory();
    size_t n = scene_var_count();
    PyObject *all = PyTuple_New((Py_ssize_t)n);
    for (size_t i = 0; all && i < n; i++) {
        scene_var_about about;
        scene_var_describe(i, &about);
        char *range = scene_var_range(i);
        PyObject *d = range ? PyDict_New() : NULL;
        const char *unit = about.unit;
        if (!d || core_put(d, "name", PyUnicode_FromString(scene_var_keyword_at(i))) < 0 ||
            core_put(d, "group", PyUnicode_FromString(scene_var_group(i))) < 0 ||
            core_put(d, "key", PyUnicode_FromString(scene_var_name(i))) < 0 ||
            core_put(d, "type", PyUnicode_FromString(type_word(scene_var_type(i)))) < 0 ||
            core_put(d, "sweep", PyBool_FromLong(scene_var_takes_list(i))) < 0 ||
            core_put(d, "default", setting_value(sc, 0, i)) < 0 ||
            core_put(d, "unit", unit ? PyUnicode_FromString(unit) : Py_NewRef(Py_None)) < 0 ||
            core_put(d, "range", PyUnicode_FromString(range)) < 0 ||
            core_put(d, "choices", names_of(about.choices)) < 0 ||
            core_put(d, "description", PyUnicode_FromString(about.description)) < 0 ||
            core_put(d, "beyond_paper", PyBool_FromLong(about.beyond_paper)) < 0 ||
            core_put(d, "checked_by", PyUnicode_FromString(checkers[about.checked_by])) < 0) {
            Py_XDECREF(d);
            Py_CLEAR(all);
        } else {
            PyTuple_SET_ITEM(all, (Py_ssize_t)i, d);
        }
        free(range);
    }
    scene_free(sc);
    return all;
}

PyObject *pyscene_columns(int theory_only)
{
    PyObject *l = PyList_New(0);
    for (int c = 0; l && c < SCENE_N_COLUMNS; c++) {
        if (theory_only && scene_column_numerics((scene_column)c)) continue;
        PyObject *s = PyUnicode_FromString(scene_column_name((scene_column)c));
        if (!s || PyList_Append(l, s) < 0) Py_CLEAR(l);
        Py_XDECREF(s);
    }
    PyObject *t = l ? PyList_AsTuple(l) : NULL;
    Py_XDECREF(l);
    return t;
}

PyObject *pyscene_pulse_speed(PyObject *args)
{
    PyObject *xo, *to, *ko;
    if (!PyArg_ParseTuple(args, "OOO:pulse_speed", &xo, &to, &ko)) return NULL;
    PyArrayObject *x = (PyArrayObject *)PyArray_FROMANY(xo, NPY_DOUBLE, 1, 1, NPY_ARRAY_CARRAY_RO);
    PyArrayObject *t = x ? (PyArrayObject *)PyArray_FROMANY(to, NPY_DOUBLE, 1, 1, NPY_ARRAY_CARRAY_RO)
                         : NULL;
    PyArrayObject *k = t ? (PyArrayObject *)PyArray_FROMANY(ko, NPY_INT64, 1, 1, NPY_ARRAY_CARRAY_RO)
                         : NULL;
    PyObject *out = NULL;
    if (k && (PyArray_DIM(t, 0) != PyArray_DIM(x, 0) || PyArray_DIM(k, 0) != PyArray_DIM(x, 0)))
        PyErr_SetString(PyExc_ValueError, "pulse_speed: X, t and k differ in length");
    else if (k)
        out = PyFloat_FromDouble(pulse_speed(PyArray_DATA(x), PyArray_DATA(t),
                                             PyArray_DATA(k), (size_t)PyArray_DIM(x, 0)));
    Py_XDECREF(x);
    Py_XDECREF(t);
    Py_XDECREF(k);
    return out;
}
