/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_rk8.c -- method 'rk8': an explicit single-step integrator,
 * Prince and Dormand's 8(7) pair with 13 stages as GSL's rk8pd has it
 * (stepper_rk8_tableau.h), with root finding, as a stepper (stepper.h).
 * It integrates the sim's equations under their error weights
 * (equations.c) with events.c's root functions armed, on its own entries
 * of the state (the window's buffer, window_storage.h, or the whole
 * chain's); nothing else.
 *
 * Why a single-step method: a contact's force has a kink where the contact
 * opens or closes (r z^n for z > 0, 0 otherwise), and every kink costs a
 * multistep method its order, since its history spans the kink; a
 * single-step method starts afresh at every step.  Measured
 * (docs/benchmarks.md, "Who is fastest"): on backward chains rk8 reaches
 * pass-time errors of 4-6e-15 at rtol 1e-14, where CVODE's Adams at its
 * tightest rtol stops at 3-4e-14; from 1e-6 to 1e-12 Adams is the faster.
 *
 * What it shares with CVODE's run: the state vector (the window's or the
 * whole chain's entries, contiguous), the right-hand side, the error
 * weights 1 / (rtol |y_i| + atol scale_i) and the root functions with
 * their directions.  What differs:
 * - The error test is in the max norm of the weighted error estimate.  A
 *   WRMS norm over the window divides the error of the few granules the
 *   pulse moves by the many it does not (taper-bench's rk8-window
 *   experiment, whose scheme this is, settled it).
 * - Roots: every slot's value at both ends of an accepted step; a sign
 *   change in the slot's direction is located by the Illinois method on
 *   fresh rk8pd steps from the step's start (the method has no interpolant,
 *   so every trial state is of order 8), to a few ulps of t.  The step is
 *   then cut at the earliest root, so that at a root return the state is
 *   the state at the root (CVODE's is interpolated there, its internal
 *   time ahead), and every slot that changed sign up to it is reported.
 * - A step never goes past the stop time (a discontinuity, the end of the
 *   run's phase): it is shortened to end there, and the step-size
 *   controller keeps its own proposal.  An output time inside a step (a
 *   sample) does not shorten it (advance_to).
 * - Time is a compensated sum of the steps: t plus a low part (the
 *   rounding of each t += h, Knuth's TwoSum), read as the true time.
 */
#include "illinois.h"
#include "stepper.h"
#include "stepper_rk8_tableau.h"


#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The step-size controller: the error estimate is of order 7 (error ~
 * h^8), safety 0.9, growth at most 4 and shrinkage at most 5 per step. */
#define ERROR_EXPONENT (1.0 / 8.0)
#define SAFETY 0.9
#define GROW_MAX 4.0
#define SHRINK_MAX 0.2
/* Root location: at most this many trial steps per root; below
 * TAPER_REFINE_BELOW_RTOL down to this many ulps of t (rk8_start). */
#define LOCATE_ITERATIONS 100
#define LOCATE_ULPS 4.0
/* The seed's bracket, relative to the step (see locate). */
#define SEED_BRACKET 1e-4

typedef struct rk8_counters {
    long steps;          /* accepted steps                                   */
    long rhs_evals;      /* right-hand sides, root location's included       */
    long root_evals;     /* evaluations of the root functions                */
    long err_test_fails; /* rejected steps                                   */
} rk8_counters;

typedef enum rk8_result {
    RK8_REACHED,         /* at tout                                          */
    RK8_ROOT,            /* at a root: found[] holds its slots               */
    RK8_WORK,            /* max_steps taken, short of tout                   */
    RK8_FAILED           /* rk->failure says why                             */
} rk8_result;

typedef struct rk8_stepper {
    taper_sim *sim;
    double *state;          /* the state's storage (sim->state.buffer)      */
    size_t dim;             /* the current state's entries                  */
    double *k[13];          /* the stages (k[0]: y' at the start), `capacity`
                               entries each, in one block                   */
    double *y_stage, *y1, *y_root, *y_trial, *err, *w, *f1; /* `capacity` each */
    int f0_valid;           /* k[0] is y' at the step's start state        */
    int g0_valid;           /* g0 holds the root functions there           */
    size_t capacity;
    double *g0, *g1, *g_trial; /* `slot_capacity` entries each             */
    int *found_ahead;
    size_t slot_capacity;
    int *directions, *found; /* per root slot: taper_events_directions, and
                               the crossings of a root return              */
    size_t root_capacity;
    /* Output inside a step (see advance_to): the caller holds the state at
     * t_out, the integrator's is y_ahead at t; the step began at y_start,
     * t_start, and found_ahead holds the roots at its end if root_ahead. */
    int ahead, root_ahead;
    double *y_start, *y_ahead, t_start, t_out;
    double t, t_low;        /* the time: t + t_low                          */
    double h, h_last;       /* the controller's proposal; the last step     */
    double root_tol;        /* roots to root_tol (|t| + |h|)                */
    double stop;            /* the stop time set (INFINITY: none)           */
    rk8_counters count;
    const char *failure;
} rk8_stepper;

/* The time of the state last returned, t + low (low: the rounding of the
 * sum of the steps). */
static double rk8_time(const rk8_stepper *rk, double *low)
{
    if (low) *low = rk->ahead ? 0.0 : rk->t_low;
    return rk->ahead ? rk->t_out : rk->t;
}

/* ---- storage, grown with the window --------------------------------------- */
static int grow_array(double **a, size_t n)
{
    double *p = realloc(*a, n * sizeof *p);
    if (!p) return -1;
    *a = p;
    return 0;
}

static int fit(rk8_stepper *rk, size_t dim, size_t slots)
{
    if (dim > rk->capacity) {
        size_t c = 2 * dim;
        double *k = rk->k[0];
        if (grow_array(&k, 13 * c)) return -1;
        for (int i = 0; i < 13; i++) rk->k[i] = k + (size_t)i * c;
        rk->f0_valid = 0;
        if (grow_array(&rk->y1, c) || grow_array(&rk->y_root, c) || grow_array(&rk->y_trial, c) ||
            grow_array(&rk->err, c) || grow_array(&rk->w, c) || grow_array(&rk->y_stage, c) ||
            grow_array(&rk->f1, c) || grow_array(&rk->y_start, c) || grow_array(&rk->y_ahead, c))
            return -1;
        rk->capacity = c;
    }
    if (slots > rk->slot_capacity) {
        size_t c = 2 * slots;
        int *f = realloc(rk->found_ahead, c * sizeof *f);
        if (f) rk->found_ahead = f;
        if (!f || grow_array(&rk->g0, c) || grow_array(&rk->g1, c) || grow_array(&rk->g_trial, c)) return -1;
        rk->slot_capacity = c;
    }
    rk->dim = dim;
    return 0;
}

/* ---- one step -------------------------------------------------------------- */
static void rhs(rk8_stepper *rk, double t, const double *y, double *dydt)
{
    rk->count.rhs_evals++;
    taper_equations_rhs(rk->sim, t, y, dydt);
}

/* One rk8pd step of size h from (t, y) into out, its error estimate into
 * rk->err: GSL's rk8pd_apply (ode-initval2/rk8pd.c), operation for
 * operation in the same order, so that a step is GSL's to the bit, on the
 * state's few entries at once: each stage one fused loop with the
 * tableau's constants, the right-hand side called directly.  y' at the
 * start is computed once per start state (rk->k[0]) and serves every step
 * from it: the retries after a failed error test and the trial steps of
 * root location. */
static void step(rk8_stepper *rk, const double *restrict y, double t, double h, double *restrict out)
{
    const size_t n = rk->dim;
    double *restrict s = rk->y_stage;
    double *restrict k1 = rk->k[0], *restrict k2 = rk->k[1], *restrict k3 = rk->k[2];
    double *restrict k4 = rk->k[3], *restrict k5 = rk->k[4], *restrict k6 = rk->k[5];
    double *restrict k7 = rk->k[6], *restrict k8 = rk->k[7], *restrict k9 = rk->k[8];
    double *restrict k10 = rk->k[9], *restrict k11 = rk->k[10], *restrict k12 = rk->k[11];
    double *restrict k13 = rk->k[12], *restrict err = rk->err;
    if (!rk->f0_valid) {
        rhs(rk, t, y, k1);
        rk->f0_valid = 1;
    }
    for (size_t i = 0; i < n; i++) s[i] = y[i] + RK8_A21 * h * k1[i];
    rhs(rk, t + RK8_C2 * h, s, k2);
    for (size_t i = 0; i < n; i++) s[i] = y[i] + h * (RK8_A31 * k1[i] + RK8_A32 * k2[i]);
    rhs(rk, t + RK8_C3 * h, s, k3);
    for (size_t i = 0; i < n; i++) s[i] = y[i] + h * (RK8_A41 * k1[i] + RK8_A43 * k3[i]);
    rhs(rk, t + RK8_C4 * h, s, k4);
    for (size_t i = 0; i < n; i++) s[i] = y[i] + h * (RK8_A51 * k1[i] + RK8_A53 * k3[i] + RK8_A54 * k4[i]);
    rhs(rk, t + RK8_C5 * h, s, k5);
    for (size_t i = 0; i < n; i++) s[i] = y[i] + h * (RK8_A61 * k1[i] + RK8_A64 * k4[i] + RK8_A65 * k5[i]);
    rhs(rk, t + RK8_C6 * h, s, k6);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A71 * k1[i] + RK8_A74 * k4[i] + RK8_A75 * k5[i] + RK8_A76 * k6[i]);
    rhs(rk, t + RK8_C7 * h, s, k7);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A81 * k1[i] + RK8_A84 * k4[i] + RK8_A85 * k5[i] + RK8_A86 * k6[i] +
                           RK8_A87 * k7[i]);
    rhs(rk, t + RK8_C8 * h, s, k8);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A91 * k1[i] + RK8_A94 * k4[i] + RK8_A95 * k5[i] + RK8_A96 * k6[i] +
                           RK8_A97 * k7[i] + RK8_A98 * k8[i]);
    rhs(rk, t + RK8_C9 * h, s, k9);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A10_1 * k1[i] + RK8_A10_4 * k4[i] + RK8_A10_5 * k5[i] + RK8_A10_6 * k6[i] +
                           RK8_A10_7 * k7[i] + RK8_A10_8 * k8[i] + RK8_A10_9 * k9[i]);
    rhs(rk, t + RK8_C10 * h, s, k10);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A11_1 * k1[i] + RK8_A11_4 * k4[i] + RK8_A11_5 * k5[i] + RK8_A11_6 * k6[i] +
                           RK8_A11_7 * k7[i] + RK8_A11_8 * k8[i] + RK8_A11_9 * k9[i] + RK8_A11_10 * k10[i]);
    rhs(rk, t + RK8_C11 * h, s, k11);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A12_1 * k1[i] + RK8_A12_4 * k4[i] + RK8_A12_5 * k5[i] + RK8_A12_6 * k6[i] +
                           RK8_A12_7 * k7[i] + RK8_A12_8 * k8[i] + RK8_A12_9 * k9[i] + RK8_A12_10 * k10[i] +
                           RK8_A12_11 * k11[i]);
    rhs(rk, t + h, s, k12);
    for (size_t i = 0; i < n; i++)
        s[i] = y[i] + h * (RK8_A13_1 * k1[i] + RK8_A13_4 * k4[i] + RK8_A13_5 * k5[i] + RK8_A13_6 * k6[i] +
                           RK8_A13_7 * k7[i] + RK8_A13_8 * k8[i] + RK8_A13_9 * k9[i] + RK8_A13_10 * k10[i] +
                           RK8_A13_11 * k11[i]);
    rhs(rk, t + h, s, k13);
    for (size_t i = 0; i < n; i++) {
        const double ksum8 = RK8_B1 * k1[i] + RK8_B6 * k6[i] + RK8_B7 * k7[i] + RK8_B8 * k8[i] + RK8_B9 * k9[i] +
                             RK8_B10 * k10[i] + RK8_B11 * k11[i] + RK8_B12 * k12[i] + RK8_B13 * k13[i];
        const double ksum7 = RK8_BHAT1 * k1[i] + RK8_BHAT6 * k6[i] + RK8_BHAT7 * k7[i] + RK8_BHAT8 * k8[i] +
                             RK8_BHAT9 * k9[i] + RK8_BHAT10 * k10[i] + RK8_BHAT11 * k11[i] + RK8_BHAT12 * k12[i];
        out[i] = y[i] + h * ksum8;
        err[i] = h * (ksum7 - ksum8);
    }
}

/* The error estimate in units of the tolerance: max_i |err_i| w_i, the
 * weights of the step's start state (as CVODE's, set before each step).
 * Not a number counts as too large. */
static double error_norm(const rk8_stepper *rk)
{
    double e = 0.0;
    for (size_t i = 0; i < rk->dim; i++) {
        double q = fabs(rk->err[i]) * rk->w[i];
        if (!(q <= e)) e = isnan(q) ? INFINITY : q;
    }
    return e;
}

/* ---- roots ----------------------------------------------------------------- */
/* The sign of the crossing from a to b in the slot's direction (+1: up,
 * -1: down), 0 if none.  A value that is exactly 0 at the start crosses
 * nothing: it is the end of an earlier crossing, or a slot at rest (as
 * CVODE, which looks past a zero at the start). */
static int crossing(double a, double b, int direction)
{
    if (a < 0.0 && b >= 0.0 && direction >= 0) return 1;
    if (a > 0.0 && b <= 0.0 && direction <= 0) return -1;
    return 0;
}

static void root_values(rk8_stepper *rk, const double *y, double *g)
{
    rk->count.root_evals++;
    taper_events_root_values(rk->sim, y, g);
}

/* The cubic Hermite interpolant of the step of size h from (y, k[0]) to
 * (y1, f1) at tau, into out. */
static void hermite(const rk8_stepper *rk, const double *y, double h, double tau, double *out)
{
    const double th = tau / h, u = 1.0 - th;
    const double h00 = (1.0 + 2.0 * th) * u * u, h10 = th * u * u * h;
    const double h01 = th * th * (3.0 - 2.0 * th), h11 = -th * th * u * h;
    for (size_t i = 0; i < rk->dim; i++)
        out[i] = h00 * y[i] + h10 * rk->k[0][i] + h01 * rk->y1[i] + h11 * rk->f1[i];
}

/* Where the interpolant puts slot i's crossing in (0, b]: the Illinois
 * method on the interpolated states, whose root functions cost a fraction
 * of a step each. */
static double seed(rk8_stepper *rk, const double *y, double t, double h, size_t i, int direction,
                   double g_start, double b, double gb)
{
    taper_bracket br = {0.0, g_start, b, gb, 0};
    for (int it = 0; it < LOCATE_ITERATIONS && br.b - br.a > LOCATE_ULPS * DBL_EPSILON * (fabs(t) + br.b); it++) {
        const double c = taper_bracket_point(&br);
        hermite(rk, y, h, c, rk->y_trial);
        root_values(rk, rk->y_trial, rk->g_trial);
        taper_bracket_move(&br, c, rk->g_trial[i], crossing(g_start, rk->g_trial[i], direction) != 0);
    }
    return br.b;
}

/* The time in (0, b] of slot i's crossing (direction `direction`, value
 * g_start at the step's start), searched from the step's start (y, t) to
 * b, where the state is rk->y_root (value gb); on return rk->y_root holds
 * the state at the returned time, on the far side of the crossing.  The
 * Illinois method on fresh steps (order 8 at every trial point), its first
 * two trials SEED_BRACKET of b either side of where the step's cubic
 * Hermite interpolant puts the root (seed): where the interpolant is that
 * close, the search starts from that narrow bracket and ends within a few
 * more steps (3.3 to 5.3 trial steps per event, docs/design.md); where it
 * is not, the trials still narrow the bracket. */
static double locate(rk8_stepper *rk, const double *y, double t, double h, size_t i, int direction,
                     double g_start, double b, double gb)
{
    const double guess = seed(rk, y, t, h, i, direction, g_start, b, gb);
    taper_bracket br = {0.0, g_start, b, gb, 0};
    for (int it = 0; it < LOCATE_ITERATIONS && br.b - br.a > rk->root_tol * (fabs(t) + h); it++) {
        double c = taper_bracket_point(&br);
        if (it < 2) { /* the seed's bracket, where it lies inside (a, b) */
            const double s = guess + (it ? 1.0 : -1.0) * SEED_BRACKET * br.b;
            if (s > br.a && s < br.b) c = s;
        }
        step(rk, y, t, c, rk->y_trial);
        root_values(rk, rk->y_trial, rk->g_trial);
        const double gc = rk->g_trial[i];
        const int far = crossing(g_start, gc, direction) != 0; /* crossed by c */
        taper_bracket_move(&br, c, gc, far);
        if (far) {
            memcpy(rk->y_root, rk->y_trial, rk->dim * sizeof(double));
            if (gc == 0.0) break; /* the root itself */
        }
    }
    return br.b;
}

/* The roots of an accepted step of size h from (t, y) to rk->y1 (values
 * rk->g0, rk->g1): the earliest crossing's time tau (h if none), with
 * rk->y_root the state there and found[] every slot that crossed up to
 * it.  Returns the number of slots found. */
static size_t find_roots(rk8_stepper *rk, const double *y, double t, double h, const int *directions,
                         size_t slots, size_t unlocated, int *found, double *tau)
{
    *tau = h;
    memcpy(rk->y_root, rk->y1, rk->dim * sizeof(double));
    const double *g_end = rk->g1;
    int located = 0, have_f1 = 0;
    for (size_t i = 0; i < slots; i++) {
        if (!crossing(rk->g0[i], g_end[i], directions[i])) continue;
        located = 1;
        if (i == unlocated) continue; /* reported where the step ends */
        if (!have_f1) { /* the interpolant's end slope */
            rhs(rk, t + h, rk->y1, rk->f1);
            have_f1 = 1;
        }
        /* crossed before the earliest root so far: that is earlier */
        *tau = locate(rk, y, t, h, i, directions[i], rk->g0[i], *tau, g_end[i]);
        root_values(rk, rk->y_root, rk->g_trial);
        memcpy(rk->g1, rk->g_trial, slots * sizeof(double));
        g_end = rk->g1;
    }
    size_t n = 0;
    for (size_t i = 0; i < slots; i++) {
        found[i] = located ? crossing(rk->g0[i], rk->g1[i], directions[i]) : 0;
        n += found[i] != 0;
    }
    return n;
}

/* ---- the run --------------------------------------------------------------- */
static void add_time(rk8_stepper *rk, double h)
{
    const double s = rk->t + h, h_part = s - rk->t; /* TwoSum(t, h) */
    rk->t_low += (rk->t - (s - h_part)) + (h - h_part);
    rk->t = s;
}

static void set_time(rk8_stepper *rk, double t)
{
    rk->t = t;
    rk->t_low = 0.0;
}

/* The state at time `at` inside the step held ahead: a fresh step from
 * its start (whose y' rk->k[0] still holds). */
static int output_inside(rk8_stepper *rk, double at, double *y)
{
    step(rk, rk->y_start, rk->t_start, at - rk->t_start, y);
    return 0;
}

/* Leaves the step held ahead: the caller's state becomes the integrator's. */
static void catch_up(rk8_stepper *rk, double *y)
{
    memcpy(y, rk->y_ahead, rk->dim * sizeof *y);
    rk->ahead = 0;
    rk->f0_valid = 0;
}

/* Steps y (dim entries, overwritten) towards tout, taking at most
 * max_steps steps, never past tstop (>= tout: a discontinuity, the end of
 * a phase); stops at the first root of the `slots` root functions that
 * changes sign in its direction (+1: from below, -1: from above, 0:
 * either).  found[]: per slot, the sign of its crossing (0: none), set on
 * RK8_ROOT.  Slot `unlocated` (none if >= slots) is not located: its root
 * is reported at the end of the step that holds it (or at an earlier root
 * of another slot in that step, if already crossed there).  A tout inside
 * a step does not shorten it: y is the state at tout (a fresh step from
 * the step's start), and the stepper keeps its own state ahead; the next
 * call goes on from there (y must be left as returned, as CVODE's
 * interpolated output). */
static rk8_result advance_to(rk8_stepper *rk, double *y, size_t dim, const int *directions,
                             size_t slots, size_t unlocated, int *found, double tout,
                             double tstop, long max_steps)
{
    rk->failure = NULL;
    if (rk->ahead && dim != rk->dim) { /* (the window moved: cannot happen) go on from y */
        rk->ahead = 0;
        set_time(rk, rk->t_out);
    }
    if (rk->ahead) {
        if (tout < rk->t && tout <= tstop) { /* another output inside the step held */
            if (output_inside(rk, tout, y) != 0) goto rhs_failed;
            rk->t_out = tout;
            return RK8_REACHED;
        }
        if (tstop < rk->t) { /* a stop inside it, before its roots: the step ends there */
            if (output_inside(rk, tstop, y) != 0) goto rhs_failed;
            rk->ahead = 0;
            rk->f0_valid = 0;
            set_time(rk, tstop);
            rk->h_last = tstop - rk->t_start;
            return RK8_REACHED;
        }
        catch_up(rk, y);
        if (rk->root_ahead) {
            memcpy(found, rk->found_ahead, slots * sizeof *found);
            return RK8_ROOT;
        }
    }
    rk->f0_valid = rk->g0_valid = 0; /* the caller may have changed y and the slots */
    if (fit(rk, dim, slots) != 0) {
        rk->failure = "out of memory";
        return RK8_FAILED;
    }
    for (long n = 0; n < max_steps; n++) {
        if (!(rk->t < tout)) return RK8_REACHED;
        const int last = rk->t + rk->h >= tstop;
        const double h = last ? tstop - rk->t : rk->h;
        step(rk, y, rk->t, h, rk->y1);
        taper_equations_weights(rk->sim, y, rk->w);
        const double e = error_norm(rk);
        if (!(e <= 1.0)) {
            rk->count.err_test_fails++;
            rk->h = h * fmax(SHRINK_MAX, SAFETY * pow(e, -ERROR_EXPONENT));
            if (!(rk->h > 8.0 * DBL_EPSILON * fabs(rk->t))) {
                rk->failure = "the step size fell below the resolution of t (t + h = t)";
                return RK8_FAILED;
            }
            continue;
        }
        if (!rk->g0_valid) root_values(rk, y, rk->g0);
        root_values(rk, rk->y1, rk->g1);
        double tau = h;
        const size_t n_found = find_roots(rk, y, rk->t, h, directions, slots, unlocated, found, &tau);
        rk->count.steps++;
        rk->h_last = tau;
        /* after a root or a step cut short at tstop, the proposal stands */
        if (!n_found && !last) rk->h = h * fmin(GROW_MAX, SAFETY * pow(fmax(e, 1e-30), -ERROR_EXPONENT));
        const double t_start = rk->t;
        const int reaches_stop = last && !n_found;
        if (reaches_stop) set_time(rk, tstop);
        else add_time(rk, tau);
        if (tout < rk->t) {
            /* tout (a sample) falls inside the step: the step is kept, as
             * if no one had asked (the run's steps do not depend on the
             * samples), and the caller gets the state at tout */
            memcpy(rk->y_start, y, dim * sizeof *y);
            memcpy(rk->y_ahead, n_found ? rk->y_root : rk->y1, dim * sizeof *y);
            rk->t_start = t_start;
            rk->root_ahead = n_found != 0;
            if (n_found) memcpy(rk->found_ahead, found, slots * sizeof *found);
            rk->ahead = 1;
            rk->t_out = tout;
            if (output_inside(rk, tout, y) != 0) goto rhs_failed;
            return RK8_REACHED;
        }
        memcpy(y, n_found ? rk->y_root : rk->y1, dim * sizeof *y);
        rk->f0_valid = 0;
        if (n_found) return RK8_ROOT;
        /* the step's end is the next one's start: its root values too */
        double *g = rk->g0;
        rk->g0 = rk->g1, rk->g1 = g;
        rk->g0_valid = 1;
    }
    return RK8_WORK;
rhs_failed:
    rk->failure = "the right-hand side failed";
    return RK8_FAILED;
}

/* ---- the stepper ------------------------------------------------------------ */
static void rk8_free(taper_stepper *s)
{
    rk8_stepper *rk = (rk8_stepper *)s;
    if (!rk) return;
    free(rk->k[0]);
    free(rk->y_stage), free(rk->y1), free(rk->y_root), free(rk->y_trial), free(rk->err), free(rk->w);
    free(rk->f1);
    free(rk->g0), free(rk->g1), free(rk->g_trial), free(rk->found_ahead);
    free(rk->y_start), free(rk->y_ahead);
    free(rk->directions), free(rk->found);
    taper_state *state = &rk->sim->state;
    if (state->buffer == &rk->state) state->buffer = NULL;
    if (state->window) taper_window_detach(state->window, &rk->state);
    else free(rk->state);
    free(rk);
}

/* The state's entries: the window's (with the quadratures' tail) or the
 * whole chain's. */
static size_t state_length(const rk8_stepper *rk)
{
    const taper_sim *sim = rk->sim;
    if (sim->state.window) return taper_window_size(sim->state.window);
    return 2 * sim->n + (sim->model.quadratures ? TAPER_N_QUADRATURES : 0);
}

static taper_stepper *rk8_alloc(taper_sim *sim, taper_error *err)
{
    rk8_stepper *rk = calloc(1, sizeof *rk);
    if (!rk) {
        taper_fail(err, TAPER_ENOMEM, "cannot create the rk8 integrator");
        return NULL;
    }
    rk->sim = sim;
    rk->h = TAPER_STEPPER_FIRST_STEP;
    rk->root_tol = LOCATE_ULPS * DBL_EPSILON;
    rk->stop = INFINITY;
    const int made = sim->state.window ? taper_window_attach(sim->state.window, &rk->state)
                                       : (rk->state = calloc(state_length(rk), sizeof(double))) ? 0 : -1;
    if (made != 0) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the state");
        rk8_free((taper_stepper *)rk);
        return NULL;
    }
    sim->state.buffer = &rk->state;
    return (taper_stepper *)rk;
}

/* Root directions and answers for every slot events.c has now. */
static taper_status rk8_arm_roots(taper_stepper *s, taper_error *err)
{
    rk8_stepper *rk = (rk8_stepper *)s;
    const size_t slots = taper_events_slots(rk->sim);
    if (slots > rk->root_capacity) {
        const size_t c = 2 * slots;
        int *d = realloc(rk->directions, c * sizeof *d);
        if (d) rk->directions = d;
        int *f = d ? realloc(rk->found, c * sizeof *f) : NULL;
        if (f) rk->found = f;
        if (!f) return taper_fail(err, TAPER_ENOMEM, "cannot allocate %zu root slots", slots);
        rk->root_capacity = c;
    }
    taper_events_directions(rk->sim, rk->directions);
    return TAPER_OK;
}

/* Roots as CVODE locates them: to 100 uround (|t| + |h|) (cvRootfind's
 * ttol), and below rtol TAPER_REFINE_BELOW_RTOL, where that would dwarf
 * the integration error, to a few ulps (where CVODE's are refined). */
static taper_status rk8_start(taper_stepper *s, taper_error *err)
{
    rk8_stepper *rk = (rk8_stepper *)s;
    if (!(rk->sim->spec.rtol < TAPER_REFINE_BELOW_RTOL)) rk->root_tol = 100.0 * DBL_EPSILON;
    return rk8_arm_roots(s, err);
}

static void rk8_set_stop(taper_stepper *s, double t_stop) { ((rk8_stepper *)s)->stop = t_stop; }

/* A single step is as cheap to cut as to take: no step goes past the end
 * of the run's phase either.  The growth root is not located: CVODE too
 * grows the window at the end of the step that holds it (solve.c), and
 * rk8 saves the ~5 trial steps a located root costs. */
static taper_step_outcome rk8_advance(taper_stepper *s, double tout, double t_end, taper_step *step)
{
    rk8_stepper *rk = (rk8_stepper *)s;
    taper_sim *sim = rk->sim;
    const double tstop = rk->stop < t_end ? rk->stop : t_end;
    const rk8_result r = advance_to(rk, taper_sim_entries(sim), state_length(rk), rk->directions,
                                    taper_events_slots(sim), taper_events_grow_slot(sim), rk->found,
                                    tout, tstop, TAPER_STEPPER_STEPS_PER_CALL);
    step->t = rk8_time(rk, &step->t_low);
    step->found = r == RK8_ROOT ? rk->found : NULL;
    switch (r) {
    case RK8_REACHED: return TAPER_STEP_REACHED;
    case RK8_ROOT: return TAPER_STEP_ROOT;
    case RK8_WORK: return TAPER_STEP_WORK;
    case RK8_FAILED: break;
    }
    return TAPER_STEP_FAILED;
}

/* The state returned is the stepper's own (a root, a stop) or inside the
 * step held ahead, where a stop may still end that step: its time. */
static double rk8_reached(const taper_stepper *s) { return rk8_time((const rk8_stepper *)s, NULL); }
static double rk8_last_step(const taper_stepper *s) { return ((const rk8_stepper *)s)->h_last; }

/* A single-step method starts afresh at every step: nothing to forget. */
static taper_status rk8_restart(taper_stepper *s, taper_error *err)
{
    (void)s, (void)err;
    return TAPER_OK;
}

/* The roots are located already, on order-8 trial steps (locate). */
static double rk8_refine_root(taper_stepper *s, taper_root_value g, size_t k, const double **y)
{
    (void)g, (void)k, (void)y;
    return ((rk8_stepper *)s)->sim->t;
}

/* crossing() compares signs, never a product. */
static int rk8_sees_tiny_sign_changes(const taper_stepper *s)
{
    (void)s;
    return 1;
}

static taper_step_counters rk8_run_counters(const taper_stepper *s)
{
    const rk8_counters r = ((const rk8_stepper *)s)->count;
    return (taper_step_counters){.steps = r.steps, .rhs_evals = r.rhs_evals, .root_evals = r.root_evals,
                                 .err_test_fails = r.err_test_fails};
}

static void rk8_describe_failure(const taper_stepper *s, taper_error *err, taper_status status)
{
    const rk8_stepper *rk = (const rk8_stepper *)s;
    taper_fail(err, status, "rk8 failed: %s", rk->failure ? rk->failure : "");
}

const taper_stepper_type taper_stepper_rk8 = {
    .alloc = rk8_alloc,
    .start = rk8_start,
    .arm_roots = rk8_arm_roots,
    .set_stop = rk8_set_stop,
    .advance = rk8_advance,
    .reached = rk8_reached,
    .last_step = rk8_last_step,
    .restart = rk8_restart,
    .refine_root = rk8_refine_root,
    .sees_tiny_sign_changes = rk8_sees_tiny_sign_changes,
    .counters = rk8_run_counters,
    .describe_failure = rk8_describe_failure,
    .free = rk8_free,
};
