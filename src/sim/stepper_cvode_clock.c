/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_cvode_clock.c -- the CVODE stepper's time: the rounding drift of
 * CVODE's own clock summed exactly (the low part of the time it returns,
 * taper_step.t_low), and a root CVODE returned located again on the step's
 * interpolant (its refine_root).  Both need only CVODE's memory and the
 * stepper's clock fields (stepper_cvode_memory.h).
 */
#include "illinois.h"
#include "stepper_cvode_memory.h"

#include <cvode/cvode.h>

#include <float.h>
#include <math.h>

/* CVODE advances its time by tn += h, rounded to double at every step.  At
 * a fixed h (the step band keeps h for thousands of steps, docs/design.md
 * "Tolerances and defaults") and within a binade of t every step rounds by the same
 * amount, so the errors add up instead of averaging out: monodisperse
 * N = 1000 at rtol 1e-14 drifted by -1.2e-9 (1.1e-12 of t) over 90 000
 * steps, the floor of its pass times (docs/design.md, "Accuracy at
 * tight tolerances").  The state is not affected (the Nordsieck array is
 * scaled by h itself, and the equations do not depend on t), only the
 * time it is labelled with.  Each step's rounding error is recovered
 * exactly (Knuth's TwoSum of the previous tn and h) and summed into
 * t_shift; the error-weight function, which CVODE calls before every step,
 * and the root return call this.  A step whose tn is not tn + h (CVODE
 * clipped it to a stop time) only re-synchronises. */
void cvode_clock_track(cvode_stepper *cv)
{
    long nst = 0;
    double tn = 0.0, h = 0.0;
    if (!cv->mem) return;
    if (CVodeGetNumSteps(cv->mem, &nst) != CV_SUCCESS || nst == cv->nst_seen) return;
    CVodeGetCurrentTime(cv->mem, &tn);
    if (nst == cv->nst_seen + 1 && CVodeGetLastStep(cv->mem, &h) == CV_SUCCESS) {
        const double a = cv->tn_seen, sum = a + h;
        if (sum == tn) {
            const double h_part = sum - a;
            cv->t_shift += (a - (sum - h_part)) + (h - h_part);
        }
    }
    cv->tn_seen = tn;
    cv->nst_seen = nst;
}

/* CVODE's root finder (cvRootfind) stops once its bracket is below
 * ttol = 100 uround (|t| + |h|) and returns the end past the zero: at
 * t ~ 1000 that is 2e-14 of t, above what rtol 1e-14 gives.  The step's
 * own interpolant (CVodeGetDky, the same polynomial CVODE searched) is
 * searched again from a bracket of twice CVODE's tolerance, by the
 * Illinois method, down to two ulps of t.  A bracket without a sign change
 * (the zero at the step's start, a function CVODE saw change sign
 * elsewhere) keeps CVODE's answer. */
#define ROOT_BRACKET (200.0 * DBL_EPSILON)
#define ROOT_ITERATIONS 60

static int sign_of(double g) { return g > 0.0 ? 1 : g < 0.0 ? -1 : 0; }

double cvode_refine_root(taper_stepper *s, taper_root_value g, size_t k, const double **y)
{
    cvode_stepper *cv = (cvode_stepper *)s;
    const taper_sim *sim = cv->sim;
    void *mem = cv->mem;
    N_Vector at = cv->at_root;
    double tn = sim->t, hu = 0.0;
    if (!mem || !at || !(sim->spec.rtol < TAPER_REFINE_BELOW_RTOL) || CVodeGetCurrentTime(mem, &tn) != CV_SUCCESS || CVodeGetLastStep(mem, &hu) != CV_SUCCESS)
        return sim->t;
    const double *data = cvode_entries(cv, at);
    double b = sim->t, gb = g(sim, *y, k);
    double a = fmax(b - ROOT_BRACKET * (fabs(b) + fabs(hu)), tn - fabs(hu));
    if (!(a < b) || CVodeGetDky(mem, a, 0, at) != CV_SUCCESS) return sim->t;
    double ga = g(sim, data, k);
    if (sign_of(ga) * sign_of(gb) >= 0) return sim->t;
    taper_bracket br = {a, ga, b, gb, 0};
    for (int i = 0; i < ROOT_ITERATIONS && br.b - br.a > 2.0 * DBL_EPSILON * fabs(br.b); i++) {
        const double c = taper_bracket_point(&br);
        if (!(c > br.a && c < br.b) || CVodeGetDky(mem, c, 0, at) != CV_SUCCESS) break;
        double gc = g(sim, data, k);
        if (gc == 0.0) {
            br.b = c; /* an exact zero: the root */
            break;
        }
        taper_bracket_move(&br, c, gc, sign_of(gc) == sign_of(br.gb));
    }
    if (CVodeGetDky(mem, br.b, 0, at) != CV_SUCCESS) return sim->t;
    *y = data;
    return br.b;
}
