/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * design.h -- a scalar result of the run minimised or maximised over
 * settings within bounds (&design), on GSL's multimin: the Nelder-Mead
 * simplex (nmsimplex2, no derivatives) or BFGS (vector_bfgs2, the gradient
 * by forward differences).
 *
 * Bounds: each real setting theta in [lower, upper] is
 * theta = lower + (upper - lower) sin^2(pi w / 2) of an unbounded w, so
 * every point the optimiser tries is inside, and an optimum on a bound is
 * reached (w = 0 or 1) as well as one inside.  The simplex starts at the
 * start and 0.2 in w along each setting; its n + 1 first runs are made at
 * once, in parallel, as are a gradient's.  A run that fails counts as
 * +inf (outside the domain).  The optimiser has converged when the simplex
 * (Nelder-Mead) or the last step (BFGS) is smaller than &design tolerance
 * in w, about that fraction of each setting's range (dtheta/dw <=
 * (pi/2)(upper - lower)).
 *
 * Integer settings (n_granules) are scanned: every value from lower to
 * upper, the real ones optimised at each (or, without real ones, every
 * combination run at once); the best wins.
 *
 * After the optimum: the objective along each setting through it,
 * profile_points runs from lower to upper (design_profiles), all at once.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_DESIGN_H
#define TAPER_OPT_DESIGN_H

#include "optimise/evaluate.h"
#include "optimise/options.h"
#include "optimise/space.h"

typedef struct design_problem {
    const scene *sc;
    opt_space *space;
    opt_objective objective;
    const char *unit;        /* the objective's unit (SI), or NULL          */
    int maximise;
    opt_problem pb;          /* the runs, and their journal                 */
    /* the result */
    opt_outcome outcome;
    char *reason;
    double *best;            /* the free settings at the optimum            */
    double best_objective;
    int *at_bound;           /* 1 lower, 2 upper, 0 neither                  */
    size_t iterations;
    size_t runs, reused;     /* the optimiser's runs (profiles not counted)  */
    /* integer settings scanned: one optimum per combination */
    size_t n_scan;
    double *scan_values;     /* n_scan x p                                   */
    double *scan_objective;
    /* the profiles through the optimum (design_profiles) */
    size_t profile_points;   /* per setting                                  */
    double *profile_value;   /* p x points                                   */
    double *profile_objective; /* NaN where a run failed                     */
    size_t profile_runs;
} design_problem;

/* The design of a validated scene with &design objective.  NULL with *e
 * on a problem of its keys. */
design_problem *design_new(const scene *sc, opt_error *e);
void design_free(design_problem *d);

/* Optimises; the result in d.  Returns d->outcome. */
opt_outcome design_run(design_problem *d, const opt_options *o);

/* The profiles through d->best (after design_run).  OPT_CONVERGED, or
 * OPT_INTERRUPTED. */
opt_outcome design_profiles(design_problem *d, const opt_options *o);

#endif
