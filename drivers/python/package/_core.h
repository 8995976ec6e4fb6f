/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _core.h -- what _core.c (libtaper's runs, fits and laws; the exceptions;
 * Python values in and out) and _numpy.c (numpy's C API, on demand) give
 * the other C files of the extension:
 * _scene.c (the driver's scene module: keywords, validation, units,
 * settings) and _module.c (the module's table and init).
 *
 * All use the numpy C API: one table of its functions (_numpy.c defines
 * TAPER_CORE_IMPORTS_NUMPY), imported by core_numpy() on the first call that
 * needs it, not when the module is imported: `import taper` does not import
 * numpy (docs/python.md, "Overheads").
 */
#ifndef TAPER_PY_CORE_H
#define TAPER_PY_CORE_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#define NPY_NO_DEPRECATED_API NPY_1_22_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL taper_core_ARRAY_API
#ifndef TAPER_CORE_IMPORTS_NUMPY
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include "taper.h"

#include <stddef.h>

/* numpy's C API ready (imported once, the GIL held): 0, or -1 with the
 * exception set (_numpy.c).  Every function of the module that touches a
 * numpy object or type calls it first. */
int core_numpy(void);

/* taper.TaperError(Exception), taper.InvalidArgumentError(TaperError,
 * ValueError), taper.SceneError(TaperError, ValueError). */
extern PyObject *core_TaperError, *core_InvalidArgumentError, *core_SceneError;

/* Raises cls(text) with the attributes status (taper_status_name), field
 * (str or None) and message. */
void core_raise(PyObject *cls, const char *text, taper_status status, const char *field,
                const char *message);
/* A library refusal: InvalidArgumentError (EINVAL, ERANGE) or TaperError,
 * "field: message"; MemoryError for ENOMEM.  Returns NULL. */
PyObject *core_raise_library(const taper_error *err);

/* Python values for the library, each error a TypeError naming `name`
 * (or InvalidArgumentError for an integer beyond [lo, hi]): a real number
 * (int, float or a numpy number, never bool, str or complex); an integer
 * (never bool or float); a bool (or numpy bool); a str without NUL (the
 * UTF-8 text lives as long as the str); a one-dimensional sequence of reals
 * as a contiguous float64 array (a new reference).  0, or -1 with the
 * exception set. */
int core_is_bool(PyObject *v);
int core_get_real(const char *name, PyObject *v, double *out);
int core_get_integer(const char *name, PyObject *v, long long lo, long long hi, long long *out);
int core_get_bool(const char *name, PyObject *v, int *out);
int core_get_str(const char *name, PyObject *v, const char **out);
PyArrayObject *core_real_vector(const char *name, PyObject *v);

/* A new float64 array of n values (NaN when src is NULL); Ctrl-C looked
 * for every 2 MB of a long one (NULL with KeyboardInterrupt set). */
PyObject *core_double_array(const double *src, size_t n);
/* The same copy into dst: 0, or -1 with the exception set. */
int core_copy_checked(double *dst, const double *src, size_t n);
/* dict[key] = value, the reference to value stolen; -1 when value is NULL. */
int core_put(PyObject *dict, const char *key, PyObject *value);

/* How a run is sampled and watched: every `interval` (rescaled time; 0:
 * never), the samples held in memory refused beyond max_bytes (0: no
 * bound), a time shown in messages or given to `progress` times time_scale
 * with its unit (NULL: rescaled); progress (NULL: none) is called with
 * (granules passed, target granule, t, granules per second of wall time)
 * every PROGRESS_INTERVAL while the run lasts and once when it ends. */
typedef struct core_sampling {
    double interval;
    double max_bytes;
    double time_scale;
    const char *time_unit;
    PyObject *progress;
} core_sampling;

/* One run of libtaper, the GIL released while it computes (Ctrl-C raises
 * KeyboardInterrupt): the chain of cs, and either its binary-collision
 * theory alone (ss NULL) or a sim with the solver settings of ss (which
 * receives the extension's monitor, log and, when sampling, its sampler).
 * Samples that would take more than sampling->max_bytes are refused before
 * the run: InvalidArgumentError naming "interval".  An exception raised by
 * sampling->progress stops the run and propagates, as KeyboardInterrupt
 * does.  Returns a dict in the
 * library's units:
 * "columns" {name: array} (k R m X0, the observables when run, theory_v
 * theory_T theory_t), "stats", "status", "message", "warnings", and for a
 * sim "x_final", "v_final" and with samples "samples" {t, x, v, force};
 * "theory_note".  NULL with an exception. */
PyObject *core_run(const taper_chain_spec *cs, taper_solver_spec *ss,
                   const core_sampling *sampling);
/* The chain of cs alone: "columns" {k R m X0 r mu}, "profile", "exponent",
 * "theory_note", "striker_mass", in the library's units. */
PyObject *core_chain(const taper_chain_spec *cs);

/* The module's functions that are not scenes (_module.c's table). */
PyObject *core_collision_time(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *core_version(PyObject *self, PyObject *unused);
PyObject *core_statuses(PyObject *self, PyObject *unused);
PyObject *core_asymptotic(PyObject *self, PyObject *args);
PyObject *core_asymptotic_exponent(PyObject *self, PyObject *args);
PyObject *core_fit(PyObject *self, PyObject *args, PyObject *kwargs);
const char *core_law_name_i(int i); /* taper_law_name by int, for LAWS */

#endif
