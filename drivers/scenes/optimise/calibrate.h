/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * calibrate.h -- a scene's settings fitted to measurements (&calibrate):
 * weighted nonlinear least squares over runs of the scene, on GSL's
 * trust-region solver (gsl_multifit_nlinear, Levenberg-Marquardt with
 * More's scaling).
 *
 * Residuals: r_j = w_j (model_j - data_j), the model read from the run at
 * the measured times (evaluate.h), w_j = 1/noise of its column when
 * &calibrate noise is given, else sqrt(weight)/peak of its column (the
 * largest |value| measured there: columns of different units compare as
 * fractions of their peaks).  chi2 = sum r_j^2.
 *
 * Bounds: the solver works in unbounded variables u mapped onto each
 * setting's interval as MINUIT does (F. James and M. Roos, Comput. Phys.
 * Commun. 10 (1975) 343; the MINUIT manual, "Parameter limits"): both
 * bounds y = a + (b - a)(1 + sin u)/2, one bound y = a - 1 + sqrt(u^2 + 1)
 * (or its mirror), each setting first divided by the size of its start.
 *
 * Jacobian: forward differences, computed in parallel, each setting
 * stepped by h = sqrt(rtol) times its size (rtol the scene's &solver
 * rtol): the integration's error, about rtol of each value, is the noise
 * a difference quotient divides by h, so the quotient's error is about
 * rtol/h + h = 2 sqrt(rtol) relative (Press et al., Numerical Recipes, 3rd
 * ed., Sec. 5.7); docs/calibration.md measures it.
 *
 * Uncertainties: C = (J^T J)^-1 at the optimum, J the Jacobian of the
 * residuals in the settings' own units; standard errors sqrt(C_ii), times
 * sqrt(chi2/dof) when the noise is not given (estimated from the scatter,
 * as gnuplot's fit and scipy's curve_fit do), dof = N - p.
 *
 * The fit converges when no setting moves by more than xtol of its value
 * in an iteration, or when no step reduces chi2 any more (GSL_ENOPROG: the
 * optimum to the model's own precision).  A fit that needs more than
 * max_iter iterations, whose Jacobian is singular (a setting the data do
 * not determine) or that ends with a setting at its bound has no answer to
 * trust: calibration_run says so.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_CALIBRATE_H
#define TAPER_OPT_CALIBRATE_H

#include "optimise/evaluate.h"
#include "optimise/measurements.h"
#include "optimise/options.h"
#include "optimise/space.h"
#include "scene/scene.h"

typedef struct calibration {
    const scene *sc;
    opt_space *space;
    measurements *data;
    opt_plan plan;
    char *data_path;        /* as resolved against the scene's folder         */
    double *w;              /* per point: the residual's factor              */
    int absolute;           /* noise given: the standard errors are absolute */
    double rtol;            /* the scene's: the Jacobian's step              */
    /* the result */
    opt_outcome outcome;
    char *reason;           /* how it ended, one line                         */
    double *value;          /* per setting                                    */
    double *error;          /* standard errors; NaN where undetermined        */
    double *correlation;    /* p x p, row-major                               */
    int *at_bound;          /* per setting: 1 lower, 2 upper, 0 neither       */
    double *fitted;         /* the model at the optimum, per point            */
    double chi2;
    size_t dof;
    size_t iterations;
    size_t runs, reused;    /* runs made, and taken from the journal          */
    double jacobian_step;   /* sqrt(rtol): the relative step                  */
} calibration;

/* The calibration of a validated scene with &calibrate data: the data
 * read and checked against the chain, the free settings resolved.  NULL
 * with *e (the key at fault) on any problem. */
calibration *calibration_new(const scene *sc, opt_error *e);
void calibration_free(calibration *c);

/* Fits; the result in c.  Returns c->outcome. */
opt_outcome calibration_run(calibration *c, const opt_options *o);

#endif
