/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _module.c -- the extension module taper._core: its functions, its
 * exceptions and the names it exports.  The scenes (simulate, theory,
 * chain, run_scene, variables, scene_text) are _scene.c's; the calls that
 * are not scenes (fit, the asymptotic laws, collision_time, version,
 * statuses) and the exceptions' objects are _core.c's; numpy's C-API
 * table, imported by the first function that needs it (core_numpy), is
 * _numpy.c's.
 */
#include "_core.h"

#include "_optimise.h"
#include "_scene.h"

/* Every function below that may meet a numpy object or type (the Python
 * values of a scene's keywords, results as arrays) imports numpy first. */
#define WITH_NUMPY(call) (core_numpy() < 0 ? NULL : (call))

/* ---- the scenes (_scene.c) --------------------------------------------------- */

static PyObject *py_simulate(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return WITH_NUMPY(pyscene_call(PYSCENE_SIMULATE, args, kwargs));
}

static PyObject *py_theory(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return WITH_NUMPY(pyscene_call(PYSCENE_THEORY, args, kwargs));
}

static PyObject *py_chain(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return WITH_NUMPY(pyscene_call(PYSCENE_CHAIN, args, kwargs));
}

static PyObject *py_check(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return WITH_NUMPY(pyscene_call(PYSCENE_CHECK, args, kwargs));
}

static PyObject *py_cite(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    /* The keywords' values are read with numpy's C API (a numpy bool or
     * float is a value too): cite(method="rk8") as a process's first call
     * dereferenced numpy's table before it was imported. */
    if (kwargs && PyDict_Size(kwargs) > 0 && core_numpy() < 0) return NULL;
    return pyscene_call(PYSCENE_CITE, args, kwargs);
}

static PyObject *py_run_scene(PyObject *self, PyObject *arg)
{
    (void)self;
    return WITH_NUMPY(pyscene_run_file(arg));
}

static PyObject *py_variables(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    return pyscene_variables(); /* imports numpy itself if a default is a list */
}

static PyObject *py_scene_swept(PyObject *self, PyObject *args)
{
    (void)self;
    return pyscene_swept(args);
}

static PyObject *py_scene_settings(PyObject *self, PyObject *args)
{
    (void)self;
    return WITH_NUMPY(pyscene_settings(args));
}

static PyObject *py_pulse_speed(PyObject *self, PyObject *args)
{
    (void)self;
    return WITH_NUMPY(pyscene_pulse_speed(args));
}

/* ---- the calls that are not scenes (_core.c) ----------------------------------- */

static PyObject *py_collision_time(PyObject *self, PyObject *args, PyObject *kwargs)
{
    return WITH_NUMPY(core_collision_time(self, args, kwargs));
}

static PyObject *py_asymptotic(PyObject *self, PyObject *args)
{
    return WITH_NUMPY(core_asymptotic(self, args));
}

static PyObject *py_asymptotic_exponent(PyObject *self, PyObject *args)
{
    return WITH_NUMPY(core_asymptotic_exponent(self, args));
}

static PyObject *py_fit(PyObject *self, PyObject *args, PyObject *kwargs)
{
    return WITH_NUMPY(core_fit(self, args, kwargs));
}

/* ---- calibration and design (_optimise.c) --------------------------------------- */

static PyObject *py_calibrate(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return WITH_NUMPY(pyopt_calibrate(args, kwargs));
}

static PyObject *py_design(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return WITH_NUMPY(pyopt_design(args, kwargs));
}

static PyObject *py_scene_text(PyObject *self, PyObject *args)
{
    (void)self;
    return pyscene_text(args);
}

/* ---- names: each walked list of the library as a tuple ---------------------- */

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

/* ---- the module ------------------------------------------------------------- */

static PyMethodDef methods[] = {
    {"simulate", (PyCFunction)(void (*)(void))py_simulate, METH_VARARGS | METH_KEYWORDS,
     "simulate(**variables) -> dict: the scene of the keywords, validated; its chain "
     "integrated (GIL released); columns, statistics, samples and status in its units."},
    {"theory", (PyCFunction)(void (*)(void))py_theory, METH_VARARGS | METH_KEYWORDS,
     "theory(**variables) -> dict: the scene with numerics = .false.: the binary collision "
     "columns alone."},
    {"chain", (PyCFunction)(void (*)(void))py_chain, METH_VARARGS | METH_KEYWORDS,
     "chain(**variables) -> dict: the scene's chain: columns k R m X0 r mu, no theory times, "
     "no integration."},
    {"cite", (PyCFunction)(void (*)(void))py_cite, METH_VARARGS | METH_KEYWORDS,
     "cite(**variables) -> str: BibTeX for what the scene's run uses (taper --cite)."},
    {"check", (PyCFunction)(void (*)(void))py_check, METH_VARARGS | METH_KEYWORDS,
     "check(**variables) -> None: the scene of the keywords validated, nothing run (the "
     "errors of simulate())."},
    {"run_scene", py_run_scene, METH_O,
     "run_scene(path) -> list of dict: the scene read by the driver's reader, one run per "
     "point of its sweep."},
    {"variables", py_variables, METH_NOARGS,
     "variables() -> tuple of dict: every scene variable (the keywords), from the scene's "
     "table."},
    {"calibrate", (PyCFunction)(void (*)(void))py_calibrate, METH_VARARGS | METH_KEYWORDS,
     "calibrate(**variables) -> dict: the scene's &calibrate: its free settings fitted to "
     "its data by the driver's optimiser (GIL released, runs on threads)."},
    {"design", (PyCFunction)(void (*)(void))py_design, METH_VARARGS | METH_KEYWORDS,
     "design(**variables) -> dict: the scene's &design: its objective optimised over its "
     "free settings by the driver's optimiser."},
    {"scene_text", py_scene_text, METH_VARARGS,
     "scene_text(scene, point) -> str: the resolved scene of a result, as a namelist (the "
     "driver's echo)."},
    {"scene_swept", py_scene_swept, METH_VARARGS,
     "scene_swept(scene, point) -> (name, [(variable, value), ...]): the run of a sweep as "
     "the driver names it and runs.tsv's swept columns."},
    {"scene_settings", py_scene_settings, METH_VARARGS,
     "scene_settings(scene, point) -> dict: every variable of a result's scene by its name, "
     "at its point."},
    {"pulse_speed", py_pulse_speed, METH_VARARGS,
     "pulse_speed(X, t, k) -> float: the pulse's speed over the last tenth of the granules "
     "passed, as granules.tsv's header has it (drivers/scenes/results/pulse.h)."},
    {"collision_time", (PyCFunction)(void (*)(void))py_collision_time, METH_VARARGS | METH_KEYWORDS,
     "collision_time(mu, r, zdot0, n=2.5) -> float: residence time of one binary collision, "
     "eq. (18)."},
    {"asymptotic", py_asymptotic, METH_VARARGS,
     "asymptotic(name, x[, n]) -> float: taper_asymptotic_<name>."},
    {"asymptotic_exponent", py_asymptotic_exponent, METH_VARARGS,
     "asymptotic_exponent(law, n) -> float: the exponent of a law named as in LAWS."},
    {"fit", (PyCFunction)(void (*)(void))py_fit, METH_VARARGS | METH_KEYWORDS,
     "fit(x, y, *, model, exponent, index_window, x_window, skip_invalid, max_iter, xtol) -> "
     "dict: taper_fit, each keyword passed to the fit setter of its name."},
    {"version", core_version, METH_NOARGS, "version() -> str: the version of libtaper linked in."},
    {"statuses", core_statuses, METH_NOARGS, "{identifier: (code, description)} of taper_status."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "taper._core",
                                    "libtaper, compiled in (see the package taper).", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__core(void)
{
    PyObject *m = PyModule_Create(&module);
    if (!m) return NULL;
    core_TaperError = PyErr_NewExceptionWithDoc(
        "taper.TaperError",
        "A libtaper failure: .status (identifier), .field (the argument at fault, or None), "
        ".message (the library's message).",
        NULL, NULL);
    PyObject *bases = core_TaperError ? PyTuple_Pack(2, core_TaperError, PyExc_ValueError) : NULL;
    if (bases) {
        core_InvalidArgumentError = PyErr_NewExceptionWithDoc(
            "taper.InvalidArgumentError",
            "A value the scene or the library refused; .field names the keyword (the scene "
            "variable), .message is the scene's or the library's message.",
            bases, NULL);
        core_SceneError = PyErr_NewExceptionWithDoc(
            "taper.SceneError", "A scene file the driver's reader rejects (its diagnostics).",
            bases, NULL);
        Py_DECREF(bases);
    }
    if (!core_TaperError || !core_InvalidArgumentError || !core_SceneError ||
        PyModule_AddObject(m, "TaperError", Py_NewRef(core_TaperError)) < 0 ||
        PyModule_AddObject(m, "InvalidArgumentError", Py_NewRef(core_InvalidArgumentError)) < 0 ||
        PyModule_AddObject(m, "SceneError", Py_NewRef(core_SceneError)) < 0 ||
        PyModule_AddObject(m, "PROFILES", names_tuple(profile_name_i)) < 0 ||
        PyModule_AddObject(m, "METHODS", names_tuple(method_name_i)) < 0 ||
        PyModule_AddObject(m, "STATISTICS", names_tuple(statistic_name_i)) < 0 ||
        PyModule_AddObject(m, "OBSERVABLES", names_tuple(observable_name_i)) < 0 ||
        PyModule_AddObject(m, "THEORY_QUANTITIES", names_tuple(quantity_name_i)) < 0 ||
        PyModule_AddObject(m, "LAWS", names_tuple(core_law_name_i)) < 0 ||
        PyModule_AddObject(m, "FIT_MODELS", names_tuple(fit_model_name_i)) < 0 ||
        PyModule_AddObject(m, "BOUNDARIES", names_tuple(boundary_name_i)) < 0 ||
        PyModule_AddObject(m, "DISORDERS", names_tuple(disorder_name_i)) < 0 ||
        PyModule_AddObject(m, "COLUMNS", pyscene_columns(0)) < 0 ||
        PyModule_AddObject(m, "THEORY_COLUMNS", pyscene_columns(1)) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
