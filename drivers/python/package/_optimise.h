/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * _optimise.h -- the package's calibration and design (_optimise.c): a
 * scene of keywords (_scene.c) with &calibrate or &design, run by the
 * driver's own optimisers (drivers/scenes/optimise), so that Python and
 * `taper SCENE.nml` find the same optimum through the same runs.
 */
#ifndef TAPER_PY_OPTIMISE_H
#define TAPER_PY_OPTIMISE_H

#include "_core.h"

/* calibrate(**kw), design(**kw): the result as a dict (taper/_optimise.py
 * makes it a Calibration or Design), or NULL with an exception:
 * InvalidArgumentError for a problem of the keywords or the data (.field
 * the keyword), TaperError when the optimisation failed,
 * KeyboardInterrupt on Ctrl-C. */
PyObject *pyopt_calibrate(PyObject *args, PyObject *kwargs);
PyObject *pyopt_design(PyObject *args, PyObject *kwargs);

#endif
