/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * rk8.h -- method 'rk8': GSL's rk8pd with root finding on a state of
 * contiguous entries whose length may change between calls (the window).
 * A leaf of src/sim (rk8.c): solve.c drives it as it drives CVODE, with
 * the sim's equations, error weights and root functions as callbacks.
 */
#ifndef TAPER_RK8_H
#define TAPER_RK8_H

#include <stddef.h>

/* f = y' at (t, y); 0, or non-zero on failure. */
typedef int (*taper_rk8_rhs)(double t, const double *y, double *f, void *user);
/* w_i = 1 / (rtol |y_i| + atol scale_i): the step is accepted if
 * max_i |error_i| w_i <= 1. */
typedef void (*taper_rk8_weights)(const double *y, double *w, void *user);
/* The root functions' values at y (as many as the `slots` of the call). */
typedef void (*taper_rk8_roots)(const double *y, double *g, void *user);

typedef struct taper_rk8 taper_rk8;

typedef struct taper_rk8_counters {
    long steps;          /* accepted steps                                   */
    long rhs_evals;      /* right-hand sides, root location's included       */
    long root_evals;     /* evaluations of the root functions                */
    long err_test_fails; /* rejected steps                                   */
} taper_rk8_counters;

typedef enum taper_rk8_result {
    TAPER_RK8_REACHED,   /* at tout                                          */
    TAPER_RK8_ROOT,      /* at a root: found[] holds its slots               */
    TAPER_RK8_WORK,      /* max_steps taken, short of tout                   */
    TAPER_RK8_FAILED     /* see taper_rk8_failure                            */
} taper_rk8_result;

/* h0: the first step tried.  Time starts at 0.  NULL when out of memory. */
taper_rk8 *taper_rk8_alloc(taper_rk8_rhs rhs, taper_rk8_weights weights, taper_rk8_roots roots,
                           void *user, double h0);
void taper_rk8_free(taper_rk8 *rk);

/* Steps y (dim entries, overwritten) towards tout, taking at most
 * max_steps steps, never past tstop (>= tout: a discontinuity, the end of
 * a phase); stops at the first root of the `slots` root functions that
 * changes sign in its direction (+1: from below, -1: from above, 0:
 * either).  found[]: per slot, the sign of its crossing (0: none), set on
 * TAPER_RK8_ROOT.  Slot `unlocated` (none if >= slots) is not located: its
 * root is reported at the end of the step that holds it (or at an earlier
 * root of another slot in that step, if already crossed there).
 * A tout inside a step does not shorten it: y is the state at tout (a
 * fresh step from the step's start), and the integrator keeps its own
 * state ahead; the next call goes on from there (y must be left as
 * returned, as CVODE's interpolated output). */
taper_rk8_result taper_rk8_advance(taper_rk8 *rk, double *y, size_t dim, const int *directions,
                                   size_t slots, size_t unlocated, int *found, double tout,
                                   double tstop, long max_steps);

/* The time of the state last returned, t + low (low: the rounding of the
 * sum of the steps). */
double taper_rk8_time(const taper_rk8 *rk, double *low);
void taper_rk8_set_time(taper_rk8 *rk, double t);
/* Roots are located to rel (|t| + |h|), h the step holding them; at
 * least (and by default) 4 ulps. */
void taper_rk8_set_root_tolerance(taper_rk8 *rk, double rel);
/* The last accepted step (cut at a root: up to the root). */
double taper_rk8_last_step(const taper_rk8 *rk);
taper_rk8_counters taper_rk8_get_counters(const taper_rk8 *rk);
/* Why the last call failed ("" if it did not). */
const char *taper_rk8_failure(const taper_rk8 *rk);

#endif
