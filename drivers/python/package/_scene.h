/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _scene.h -- the Python package's scenes (_scene.c): where the extension
 * meets the driver's scene module (drivers/scenes/scene, linked in from the
 * static library taper_scenes).  simulate(), theory() and chain() build a
 * scene from their keywords, run_scene() reads one from a file; either is
 * validated by the driver's reader and its points run by core_run
 * (_core.c), the results converted to the scene's units.
 */
#ifndef TAPER_PY_SCENE_H
#define TAPER_PY_SCENE_H

#include "_core.h"

typedef enum pyscene_kind {
    PYSCENE_SIMULATE = 0, /* the scene's one run                          */
    PYSCENE_THEORY = 1,   /* the same with numerics = .false.             */
    PYSCENE_CHAIN = 2,    /* its chain alone                              */
    PYSCENE_CHECK = 3,    /* validated only: None (taper_from_radii)      */
    PYSCENE_CITE = 4,     /* what to cite, as BibTeX (taper --cite)       */
    PYSCENE_CALIBRATE = 5, /* its &calibrate (_optimise.c)                */
    PYSCENE_DESIGN = 6    /* its &design (_optimise.c)                    */
} pyscene_kind;

/* simulate(**kw), theory(**kw), chain(**kw): the dict a Result (Chain) is
 * made from, or NULL with TypeError (an unknown keyword, a value of the
 * wrong Python type), InvalidArgumentError (a value the scene or the
 * library refuses: .field the keyword) or another exception.  The keyword
 * progress may be a callable (simulate: called during the run, _core.h's
 * core_sampling), which the scene holds as progress = .true..  check(**kw):
 * None once the scene is valid. */
PyObject *pyscene_call(pyscene_kind kind, PyObject *args, PyObject *kwargs);
/* The validated scene of a call's keywords (named after the call kind in
 * its echo), or NULL with TypeError or InvalidArgumentError as
 * pyscene_call raises them.  Free with scene_free. */
struct scene;
struct scene *pyscene_scene(pyscene_kind kind, PyObject *args, PyObject *kwargs);
/* run_scene(path): one dict per point of the scene's sweep; SceneError
 * with the reader's diagnostics for an invalid scene. */
PyObject *pyscene_run_file(PyObject *path);
/* variables(): one dict per scene variable, in the table's order. */
PyObject *pyscene_variables(void);
/* scene_swept(scene, point): (the run's name, [(swept variable, value),
 * ...]) as the driver names the run's directory and runs.tsv's columns. */
PyObject *pyscene_swept(PyObject *args);
/* scene_text(scene, point): the echo of a result's scene at its point. */
PyObject *pyscene_text(PyObject *args);
/* scene_settings(scene, point): {keyword: value} of every variable of a
 * result's scene at its point (Result.settings, built when first read). */
PyObject *pyscene_settings(PyObject *args);
/* The names of granules.tsv's columns in their order; theory_only: those
 * a run without numerics has. */
PyObject *pyscene_columns(int theory_only);
/* pulse_speed(X, t, k): the pulse's speed over the last tenth of the
 * granules passed (results/pulse.h), from float64 arrays X and t and the
 * int64 granule numbers k of their rows. */
PyObject *pyscene_pulse_speed(PyObject *args);

#endif
