/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_rk8.c -- method 'rk8': an explicit single-step integrator,
 * Prince and Dormand's 8(7) pair with 13 stages as GSL's rk8pd has it
 * (stepper_rk8_tableau.h), with a continuous extension of order 7 for its
 * roots and outputs, as a stepper (stepper.h).  It integrates the sim's
 * equations under their error weights (equations.c) with events.c's root
 * functions armed, on its own entries of the state (the window's buffer,
 * window_storage.h, or the whole chain's); nothing else.
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
 * - The steps are GSL's rk8pd steps to the bit, computed here on the
 *   state's few entries (each stage one loop, the right-hand side called
 *   directly) rather than through GSL's generic driver.
 * - The steps are the controller's alone: an accepted step is held, and
 *   whatever lies inside it, a root or an output time, is served from the
 *   step's continuous extension (dense output, stepper_rk8_tableau.h) as
 *   CVODE serves them from its interpolant, its own time ahead at the
 *   step's end.  Five more stages, only in a step that has a root or an
 *   output inside, make it of order 7 (error O(h^8), the order of the
 *   pair's error estimate); the step's end is the step's own y1.  So a
 *   run's steps do not depend on its outputs, nor on its roots.
 * - Roots: every slot's value at both ends of an accepted step; a sign
 *   change in the slot's direction is located by the Illinois method on the
 *   dense output (to CVODE's root tolerance, below rtol 1e-11 to a few
 *   ulps of t), the earliest first, and every slot that changed sign up
 *   to it is reported.  The next root of the step is
 *   searched from the last one (not from an output between them), so that
 *   outputs do not move roots.
 * - A step never goes past the stop time (a discontinuity, the end of the
 *   run's phase): it is shortened to end there, and the step-size
 *   controller keeps its own proposal.  A stop set inside a held step ends
 *   the step there, on its dense output.
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
 * h^8); a step is accepted when it is within the tolerance, and the next
 * is proposed for SAFETY^8 (0.33) of it, growth at most 4 and shrinkage
 * at most 5 per step.  The energy drift of a long run grows steeply with
 * the step size (monodisperse N = 1e5 at rtol 1e-10: 1.06e-8 at a safety
 * factor of 0.9, 7.8e-9 at 0.87, 6.3e-9 at 0.85): 0.87 keeps N = 1e6
 * within 1e-7 (docs/design.md, "A single-step method: rk8"). */
#define ERROR_EXPONENT (1.0 / 8.0)
#define SAFETY 0.87
#define GROW_MAX 4.0
#define SHRINK_MAX 0.2
/* Root location: at most this many interpolations per root; below
 * TAPER_REFINE_BELOW_RTOL down to this many ulps of t (rk8_start). */
#define LOCATE_ITERATIONS 100
#define LOCATE_ULPS 4.0

/* The stages: k[0..12] the step's, k[13] y' at its end (the next step's
 * first), k[14..18] the dense output's extra ones. */
#define STEP_STAGES 13
#define END_SLOPE 13
#define ALL_STAGES RK8_DENSE_STAGES

typedef struct rk8_counters {
    long steps;          /* accepted steps                                   */
    long rhs_evals;      /* right-hand sides, the dense output's included    */
    long root_evals;     /* evaluations of the root functions                */
    long err_test_fails; /* rejected steps                                   */
} rk8_counters;

typedef enum rk8_result {
    RK8_REACHED,         /* at tout or at the stop time                      */
    RK8_ROOT,            /* at a root: found[] holds its slots               */
    RK8_WORK,            /* max_steps taken, short of tout                   */
    RK8_FAILED,          /* rk->failure says why                             */
    RK8_STEP_ON          /* (inside: the held step is done, step on)         */
} rk8_result;

/* The step held: accepted, its end not yet reached by the caller's state.
 * Its arrays (y0, y1, the stages) are in the window's layout when it was
 * taken, absolute entries [begin, end) and the tail; the window may lose
 * granules at its back meanwhile (a departure at a root return), and then
 * entry e of the state is entry e + (window's begin - begin) of the held
 * arrays (the tail moves with the end, which stays). */
typedef struct rk8_held {
    int on;
    double t, t_low;         /* its start                                   */
    double h;
    size_t begin, end, dim;  /* its layout                                  */
    int end_slope, dense;    /* k[13], k[14..18] computed                   */
    int grow_crossed;        /* the growth slot crossed in it               */
    int values_fresh;        /* g_ev, g_end hold the slots at s_ev and at the
                                end for the layout and arming now           */
    double s_ev;             /* the last root in it (0: its start): where the
                                search for the next one starts              */
    int next_known;          /* the next root, searched from s_ev: */
    int next_is_root;        /*   none (the end) or at s_next, state y_root */
    double s_next;
    double s_now;            /* where the caller's state is in it           */
    double t_now, t_now_low; /* and its time                                */
} rk8_held;

typedef struct rk8_stepper {
    taper_sim *sim;
    double *state;           /* the state's storage (sim->state.buffer)     */
    size_t dim;              /* the state's entries when the step is taken  */
    size_t capacity;         /* entries of each array below                 */
    double *stages;          /* one block for the stages: */
    double *k[ALL_STAGES];   /* each's entries (k[0] and k[13] trade places) */
    double *y_stage, *err, *w, *y0, *y1, *y_root, *y_trial;
    int f0_valid;            /* k[0] is y' at the state, window layout
                                [f0_begin, f0_end)                          */
    size_t f0_begin, f0_end;
    int g0_valid;            /* g0 holds the slots at the state             */
    size_t slot_capacity;
    double *g0, *g1, *g_ev, *g_end, *g_root, *g_trial; /* `slot_capacity` each */
    int *found_next;
    size_t root_capacity;
    int *directions, *found; /* per root slot: taper_events_directions, and
                                the crossings of a root return              */
    rk8_held held;
    int grow_pending;        /* a held step left early had the growth slot
                                cross: reported at the next step's end      */
    double t, t_low;         /* the stepper's own time (its last step's end) */
    double h, h_last;        /* the controller's proposal; the last step    */
    double root_tol;         /* roots to root_tol (|t| + |h|)               */
    double stop;             /* the stop time set (INFINITY: none)          */
    rk8_counters count;
    const char *failure;
} rk8_stepper;

/* The time of the state last returned, t + low (low: the rounding of the
 * sum of the steps). */
static double rk8_time(const rk8_stepper *rk, double *low)
{
    if (low) *low = rk->held.on ? rk->held.t_now_low : rk->t_low;
    return rk->held.on ? rk->held.t_now : rk->t;
}

/* The window's layout now: absolute entries [begin, end) (and the tail). */
static size_t layout_begin(const rk8_stepper *rk) { return taper_dyn_begin(&rk->sim->dyn); }
static size_t layout_end(const rk8_stepper *rk) { return taper_dyn_end(&rk->sim->dyn); }

/* The state's entries: the window's (with the quadratures' tail) or the
 * whole chain's. */
static size_t state_length(const rk8_stepper *rk)
{
    const taper_sim *sim = rk->sim;
    if (sim->state.window) return taper_window_size(sim->state.window);
    return 2 * sim->n + (sim->model.quadratures ? TAPER_N_QUADRATURES : 0);
}

/* ---- storage, grown with the window --------------------------------------- */
static int grow_array(double **a, size_t n)
{
    double *p = realloc(*a, n * sizeof *p);
    if (!p) return -1;
    *a = p;
    return 0;
}

static int fit_slots(rk8_stepper *rk, size_t slots)
{
    if (slots <= rk->slot_capacity) return 0;
    const size_t c = 2 * slots;
    int *f = realloc(rk->found_next, c * sizeof *f);
    if (f) rk->found_next = f;
    if (!f || grow_array(&rk->g0, c) || grow_array(&rk->g1, c) || grow_array(&rk->g_ev, c) ||
        grow_array(&rk->g_end, c) || grow_array(&rk->g_root, c) || grow_array(&rk->g_trial, c))
        return -1;
    rk->slot_capacity = c;
    return 0;
}

/* Arrays for dim entries (never while a step is held: its arrays stay). */
static int fit(rk8_stepper *rk, size_t dim, size_t slots)
{
    if (dim > rk->capacity) {
        const size_t c = 2 * dim;
        if (grow_array(&rk->stages, ALL_STAGES * c)) return -1;
        for (int i = 0; i < ALL_STAGES; i++) rk->k[i] = rk->stages + (size_t)i * c;
        rk->f0_valid = 0;
        if (grow_array(&rk->y_stage, c) || grow_array(&rk->err, c) || grow_array(&rk->w, c) ||
            grow_array(&rk->y0, c) || grow_array(&rk->y1, c) || grow_array(&rk->y_root, c) ||
            grow_array(&rk->y_trial, c))
            return -1;
        rk->capacity = c;
    }
    if (fit_slots(rk, slots) != 0) return -1;
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
 * rk->err, from y' at the start in rk->k[0]: GSL's rk8pd_apply
 * (ode-initval2/rk8pd.c), operation for operation in the same order, so
 * that a step is GSL's to the bit, on the state's few entries at once:
 * each stage one fused loop with the tableau's constants, the right-hand
 * side called directly. */
static void step(rk8_stepper *rk, const double *restrict y, double t, double h, double *restrict out)
{
    const size_t n = rk->dim;
    double *restrict s = rk->y_stage;
    double *restrict k1 = rk->k[0], *restrict k2 = rk->k[1], *restrict k3 = rk->k[2];
    double *restrict k4 = rk->k[3], *restrict k5 = rk->k[4], *restrict k6 = rk->k[5];
    double *restrict k7 = rk->k[6], *restrict k8 = rk->k[7], *restrict k9 = rk->k[8];
    double *restrict k10 = rk->k[9], *restrict k11 = rk->k[10], *restrict k12 = rk->k[11];
    double *restrict k13 = rk->k[12], *restrict err = rk->err;
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

/* ---- the dense output ------------------------------------------------------- */
/* Whether the held step's arrays are in the window's layout now, and where
 * the state's entries start in them (the window lost `*offset` entries at
 * its back since).  0 if they cannot be read in it (the window moved
 * otherwise: a granule back in it, after which the loop restarts). */
static int held_layout(const rk8_stepper *rk, size_t *offset)
{
    const rk8_held *H = &rk->held;
    const size_t begin = layout_begin(rk);
    if (layout_end(rk) != H->end || begin < H->begin) return 0;
    *offset = begin - H->begin;
    return 1;
}

/* y' at the held step's end (k[13]) and the dense output's extra stages
 * k[14..18], each from the step's start and the stages before it
 * (stepper_rk8_tableau.h).  The right-hand side sees the window as it is
 * now, so this is done in the step's own layout, before any root or
 * output inside the step is returned (the window moves only at those);
 * -1 if the layout has changed since. */
static int dense_stages(rk8_stepper *rk)
{
    rk8_held *H = &rk->held;
    if (H->dense) return 0;
    size_t offset;
    if (!held_layout(rk, &offset) || offset) return -1;
    const size_t n = H->dim;
    if (!H->end_slope) {
        rhs(rk, H->t + H->h, rk->y1, rk->k[END_SLOPE]);
        H->end_slope = 1;
    }
    /* stage 15 + i weighs k_1 and k_6 .. k_(14 + i), the zeros of its row
     * left out: each stage one fused loop, as the step's */
    const double h = H->h, *restrict y0 = rk->y0;
    double *restrict s = rk->y_stage;
    const double *restrict k[ALL_STAGES];
    for (int j = 0; j < ALL_STAGES; j++) k[j] = rk->k[j];
#define D(i, j) rk8_dense_a[i][j] * k[j][e]
    for (size_t e = 0; e < n; e++)
        s[e] = y0[e] + h * (D(0, 0) + D(0, 5) + D(0, 6) + D(0, 7) + D(0, 8) + D(0, 9) + D(0, 10) +
                            D(0, 11) + D(0, 12) + D(0, 13));
    rhs(rk, H->t + rk8_dense_c[0] * h, s, rk->k[14]);
    for (size_t e = 0; e < n; e++)
        s[e] = y0[e] + h * (D(1, 0) + D(1, 5) + D(1, 6) + D(1, 7) + D(1, 8) + D(1, 9) + D(1, 10) +
                            D(1, 11) + D(1, 12) + D(1, 13) + D(1, 14));
    rhs(rk, H->t + rk8_dense_c[1] * h, s, rk->k[15]);
    for (size_t e = 0; e < n; e++)
        s[e] = y0[e] + h * (D(2, 0) + D(2, 5) + D(2, 6) + D(2, 7) + D(2, 8) + D(2, 9) + D(2, 10) +
                            D(2, 11) + D(2, 12) + D(2, 13) + D(2, 14) + D(2, 15));
    rhs(rk, H->t + rk8_dense_c[2] * h, s, rk->k[16]);
    for (size_t e = 0; e < n; e++)
        s[e] = y0[e] + h * (D(3, 0) + D(3, 5) + D(3, 6) + D(3, 7) + D(3, 8) + D(3, 9) + D(3, 10) +
                            D(3, 11) + D(3, 12) + D(3, 13) + D(3, 14) + D(3, 15) + D(3, 16));
    rhs(rk, H->t + rk8_dense_c[3] * h, s, rk->k[17]);
    for (size_t e = 0; e < n; e++)
        s[e] = y0[e] + h * (D(4, 0) + D(4, 5) + D(4, 6) + D(4, 7) + D(4, 8) + D(4, 9) + D(4, 10) +
                            D(4, 11) + D(4, 12) + D(4, 13) + D(4, 14) + D(4, 15) + D(4, 16) + D(4, 17));
    rhs(rk, H->t + rk8_dense_c[4] * h, s, rk->k[18]);
#undef D
    H->dense = 1;
    return 0;
}

/* The dense output's weights b_i(theta), from their coefficients in the
 * Bernstein basis of degree RK8_DENSE_DEGREE (the binomials folded in):
 * values of at most ~10 on [0, 1], so each is good to a few rounding
 * units. */
static void dense_weights(double theta, double b[ALL_STAGES])
{
    const double rest = 1.0 - theta;
    double up[RK8_DENSE_DEGREE + 1], down[RK8_DENSE_DEGREE + 1];
    up[0] = down[0] = 1.0;
    for (int j = 1; j <= RK8_DENSE_DEGREE; j++) up[j] = up[j - 1] * theta, down[j] = down[j - 1] * rest;
    for (int i = 0; i < ALL_STAGES; i++) {
        double sum = 0.0;
        for (int j = 0; j <= RK8_DENSE_DEGREE; j++) sum += rk8_dense_b[i][j] * (up[j] * down[RK8_DENSE_DEGREE - j]);
        b[i] = sum;
    }
}

/* The dense output of the held step at s in [0, h], in the step's layout,
 * into out: y0 + h sum_i b_i(s/h) k_i over the stages it weighs, k_1,
 * k_6 .. k_14 and k_17 .. k_19 (the others' weights are 0:
 * stepper_rk8_tableau.h). */
static void interpolate(const rk8_stepper *rk, double s, double *restrict out)
{
    const rk8_held *H = &rk->held;
    double b[ALL_STAGES];
    dense_weights(s / H->h, b);
    const double h = H->h, *restrict y0 = rk->y0;
    const double *restrict k1 = rk->k[0], *restrict k6 = rk->k[5], *restrict k7 = rk->k[6];
    const double *restrict k8 = rk->k[7], *restrict k9 = rk->k[8], *restrict k10 = rk->k[9];
    const double *restrict k11 = rk->k[10], *restrict k12 = rk->k[11], *restrict k13 = rk->k[12];
    const double *restrict k14 = rk->k[13], *restrict k17 = rk->k[16], *restrict k18 = rk->k[17];
    const double *restrict k19 = rk->k[18];
    for (size_t e = 0; e < H->dim; e++)
        out[e] = y0[e] + h * (b[0] * k1[e] + b[5] * k6[e] + b[6] * k7[e] + b[7] * k8[e] + b[8] * k9[e] +
                              b[9] * k10[e] + b[10] * k11[e] + b[11] * k12[e] + b[12] * k13[e] +
                              b[13] * k14[e] + b[16] * k17[e] + b[17] * k18[e] + b[18] * k19[e]);
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

/* Whether a slot other than the growth slot crosses from a to b. */
static int any_crossing(const rk8_stepper *rk, const double *a, const double *b, size_t slots, size_t grow)
{
    for (size_t i = 0; i < slots; i++)
        if (i != grow && crossing(a[i], b[i], rk->directions[i])) return 1;
    return 0;
}

/* The next root of the held step after s_ev: the earliest crossing of a
 * slot (but the growth slot, which is acted on at the step's end), located
 * by the Illinois method on the dense output to root_tol (|t| + |h|), the
 * slots in turn, each searched only up to the earliest so far.  Sets
 * next_is_root, s_next, y_root (the state there, the step's layout: the
 * far side of the crossing) and found_next (every slot crossed up to it).
 * -1 if the dense output cannot be made (dense_stages). */
static int find_next_root(rk8_stepper *rk, size_t offset)
{
    rk8_held *H = &rk->held;
    taper_sim *sim = rk->sim;
    const size_t slots = taper_events_slots(sim), grow = taper_events_grow_slot(sim);
    if (!H->values_fresh) {
        if (H->s_ev > 0.0) {
            interpolate(rk, H->s_ev, rk->y_trial);
            root_values(rk, rk->y_trial + offset, rk->g_ev);
        } else {
            root_values(rk, rk->y0 + offset, rk->g_ev);
        }
        root_values(rk, rk->y1 + offset, rk->g_end);
        H->values_fresh = 1;
    }
    double far = H->h; /* the earliest crossing so far: its values in g_root */
    memcpy(rk->g_root, rk->g_end, slots * sizeof(double));
    int located = 0;
    const double tol = rk->root_tol * (fabs(H->t) + H->h);
    for (size_t i = 0; i < slots; i++) {
        const int direction = rk->directions[i];
        if (i == grow || !crossing(rk->g_ev[i], rk->g_root[i], direction)) continue;
        if (dense_stages(rk) != 0) return -1;
        taper_bracket br = {H->s_ev, rk->g_ev[i], far, rk->g_root[i], 0};
        for (int it = 0; it < LOCATE_ITERATIONS && br.b - br.a > tol; it++) {
            const double c = taper_bracket_point(&br);
            interpolate(rk, c, rk->y_trial);
            root_values(rk, rk->y_trial + offset, rk->g_trial);
            const double gc = rk->g_trial[i];
            const int crossed = crossing(rk->g_ev[i], gc, direction) != 0;
            taper_bracket_move(&br, c, gc, crossed);
            if (crossed) { /* the new far side: its state and values */
                double *y = rk->y_root, *g = rk->g_root;
                rk->y_root = rk->y_trial, rk->g_root = rk->g_trial;
                rk->y_trial = y, rk->g_trial = g;
                located = 1;
                if (gc == 0.0) break; /* the root itself */
            }
        }
        far = br.b;
    }
    H->next_is_root = far < H->h;
    H->s_next = far;
    for (size_t i = 0; i < slots; i++)
        rk->found_next[i] = i == grow ? 0 : crossing(rk->g_ev[i], rk->g_root[i], rk->directions[i]);
    if (!located) memcpy(rk->y_root, rk->y1, H->dim * sizeof(double)); /* crossings at the end itself */
    H->next_known = 1;
    return 0;
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

/* s into the held step as a time: the step's start plus s, compensated. */
static void held_time(const rk8_held *H, double s, double *t, double *low)
{
    const double sum = H->t + s, s_part = sum - H->t; /* TwoSum(t, s) */
    *t = sum;
    *low = H->t_low + (H->t - (sum - s_part)) + (s - s_part);
}

/* The held step is left: the stepper goes on from the caller's state.
 * At its end that is y1, whose y' (k[13]) is the next step's first stage
 * while the window keeps the step's layout; inside it, the state the
 * stepper returned there. */
static void leave_held(rk8_stepper *rk, int at_end)
{
    rk8_held *H = &rk->held;
    rk->g0_valid = 0;
    if (at_end && H->end_slope) { /* k[13] becomes k[0] */
        double *k = rk->k[0];
        rk->k[0] = rk->k[END_SLOPE], rk->k[END_SLOPE] = k;
        rk->f0_valid = 1, rk->f0_begin = H->begin, rk->f0_end = H->end;
    } else {
        rk->f0_valid = 0;
    }
    if (!at_end) {
        rk->t = H->t_now, rk->t_low = H->t_now_low;
        rk->h_last = rk->t - H->t;
        /* its growth root, if it crossed before here, would not cross
         * again: the window grows at the end of the next step instead */
        rk->grow_pending |= H->grow_crossed;
    }
    H->on = 0;
}

/* Copies entries [offset, offset + dim of the state) of a held array into
 * the state. */
static void deliver(rk8_stepper *rk, double *y, const double *from, size_t offset)
{
    memcpy(y, from + offset, (rk->held.dim - offset) * sizeof *y);
}

/* What the held step answers to an advance towards tout, never past
 * tstop: its next root, an output at tout inside it, its end at a stop
 * time inside it, or its end (RK8_STEP_ON, the state at y1, unless the
 * growth slot crossed in it: then a root there). */
static rk8_result serve_held(rk8_stepper *rk, double *y, double tout, double tstop, int *found)
{
    rk8_held *H = &rk->held;
    const size_t slots = taper_events_slots(rk->sim), grow = taper_events_grow_slot(rk->sim);
    size_t offset;
    if (!held_layout(rk, &offset)) { /* cannot happen: the loop restarts after such moves */
        leave_held(rk, 0);
        return RK8_STEP_ON;
    }
    if (!H->next_known && find_next_root(rk, offset) != 0) {
        leave_held(rk, 0);
        return RK8_STEP_ON;
    }
    const double t_end = rk->t; /* the step's end (the stepper's own time) */
    const double s_event = H->next_is_root ? H->s_next : H->h;
    const double s_stop = tstop - H->t;
    if (tstop < t_end && s_stop <= s_event && tstop <= tout) {
        /* a stop set inside the step since it was taken, before its next
         * root: the step ends there, on its dense output */
        if (dense_stages(rk) != 0) {
            leave_held(rk, 0);
            return RK8_STEP_ON;
        }
        if (s_stop > H->s_now) { /* (else it is where the state is already) */
            interpolate(rk, s_stop, rk->y_trial);
            deliver(rk, y, rk->y_trial, offset);
            H->t_now = tstop, H->t_now_low = 0.0;
        }
        leave_held(rk, 0);
        return RK8_REACHED;
    }
    if (tout < t_end && tout - H->t < s_event) { /* an output inside, before the next root */
        if (dense_stages(rk) != 0) {
            leave_held(rk, 0);
            return RK8_STEP_ON;
        }
        H->s_now = tout - H->t;
        interpolate(rk, H->s_now, rk->y_trial);
        deliver(rk, y, rk->y_trial, offset);
        H->t_now = tout, H->t_now_low = 0.0;
        return RK8_REACHED;
    }
    if (H->next_is_root) { /* the root, inside the step */
        deliver(rk, y, rk->y_root, offset);
        held_time(H, H->s_next, &H->t_now, &H->t_now_low);
        H->s_now = H->s_next;
        memcpy(found, rk->found_next, slots * sizeof *found);
        H->s_ev = H->s_next;
        H->next_known = H->values_fresh = 0;
        return RK8_ROOT;
    }
    /* the end: y1, with the crossings there and the growth slot's */
    deliver(rk, y, rk->y1, offset);
    int n_found = 0;
    for (size_t i = 0; i < slots; i++) {
        found[i] = rk->found_next[i];
        if (i == grow && H->grow_crossed) found[i] = 1;
        n_found += found[i] != 0;
    }
    const int fresh = H->values_fresh; /* the slots at y1, for the window and arming now */
    leave_held(rk, 1);
    if (fresh) {
        double *g = rk->g0;
        rk->g0 = rk->g_end, rk->g_end = g;
        rk->g0_valid = 1;
    }
    return n_found ? RK8_ROOT : RK8_STEP_ON;
}

/* Steps the state y towards tout, taking at most max_steps steps, never
 * past tstop (a discontinuity, the end of a phase); stops at the first
 * root of the slots (taper_events_slots) that changes sign in its
 * direction (+1: from below, -1: from above, 0: either).  found[]: per
 * slot, the sign of its crossing (0: none), set on RK8_ROOT.  The growth
 * slot (taper_events_grow_slot) is not located: its root is reported at
 * the end of the step that holds it.  A tout or a root inside a step does
 * not shorten it: y is the dense output's state there, and the stepper
 * keeps its step; the next call goes on from there (y must be left as
 * returned, but for the window's departures at its back, as CVODE's
 * interpolated output). */
static rk8_result advance_to(rk8_stepper *rk, double *y, double tout, double tstop, long max_steps)
{
    taper_sim *sim = rk->sim;
    rk->failure = NULL;
    /* the caller may have changed the slots' arming since the last call */
    rk->g0_valid = rk->held.values_fresh = 0;
    if (rk->held.on) {
        if (!(rk->held.t_now < tout)) return RK8_REACHED;
        const rk8_result r = serve_held(rk, y, tout, tstop, rk->found);
        if (r != RK8_STEP_ON) return r;
    }
    const size_t slots = taper_events_slots(sim), grow = taper_events_grow_slot(sim);
    if (fit(rk, state_length(rk), slots) != 0) {
        rk->failure = "out of memory";
        return RK8_FAILED;
    }
    /* the caller may have changed the slots, and the window at the end of
     * the last step */
    if (rk->f0_valid && (rk->f0_begin != layout_begin(rk) || rk->f0_end != layout_end(rk))) rk->f0_valid = 0;
    for (long n = 0; n < max_steps; n++) {
        if (!(rk->t < tout) || !(rk->t < tstop)) return RK8_REACHED;
        const int last = rk->t + rk->h >= tstop;
        const double h = last ? tstop - rk->t : rk->h;
        if (!rk->f0_valid) {
            rhs(rk, rk->t, y, rk->k[0]);
            rk->f0_valid = 1, rk->f0_begin = layout_begin(rk), rk->f0_end = layout_end(rk);
        }
        step(rk, y, rk->t, h, rk->y1);
        taper_equations_weights(sim, y, rk->w);
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
        rk->count.steps++;
        rk->h_last = h;
        /* after a step cut short at tstop, the proposal stands */
        if (!last) rk->h = h * fmin(GROW_MAX, SAFETY * pow(fmax(e, 1e-30), -ERROR_EXPONENT));
        if (!rk->g0_valid) root_values(rk, y, rk->g0);
        root_values(rk, rk->y1, rk->g1);
        rk8_held *H = &rk->held;
        const double t_start = rk->t, t_start_low = rk->t_low;
        if (last) set_time(rk, tstop);
        else add_time(rk, h);
        const int crossed = any_crossing(rk, rk->g0, rk->g1, slots, grow);
        const int grows = grow < slots && (rk->grow_pending || crossing(rk->g0[grow], rk->g1[grow], rk->directions[grow]));
        rk->grow_pending = 0;
        if (!crossed && !(tout < rk->t)) { /* nothing inside: the state goes to the end */
            memcpy(y, rk->y1, rk->dim * sizeof *y);
            double *g = rk->g0;
            rk->g0 = rk->g1, rk->g1 = g;
            rk->g0_valid = 1;
            rk->f0_valid = 0;
            if (grows) {
                for (size_t i = 0; i < slots; i++) rk->found[i] = i == grow;
                return RK8_ROOT;
            }
            continue;
        }
        /* a root or an output inside: the step is held, and served from */
        *H = (rk8_held){.on = 1, .t = t_start, .t_low = t_start_low, .h = h, .begin = layout_begin(rk),
                        .end = layout_end(rk), .dim = rk->dim, .grow_crossed = grows, .values_fresh = 1,
                        .t_now = t_start, .t_now_low = t_start_low};
        memcpy(rk->y0, y, rk->dim * sizeof *y);
        memcpy(rk->g_ev, rk->g0, slots * sizeof(double));
        memcpy(rk->g_end, rk->g1, slots * sizeof(double));
        const rk8_result r = serve_held(rk, y, tout, tstop, rk->found);
        if (r != RK8_STEP_ON) return r;
    }
    return RK8_WORK;
}

/* ---- the stepper ------------------------------------------------------------ */
static void rk8_free(taper_stepper *s)
{
    rk8_stepper *rk = (rk8_stepper *)s;
    if (!rk) return;
    free(rk->stages);
    free(rk->y_stage), free(rk->err), free(rk->w), free(rk->y0), free(rk->y1);
    free(rk->y_root), free(rk->y_trial);
    free(rk->g0), free(rk->g1), free(rk->g_ev), free(rk->g_end), free(rk->g_root), free(rk->g_trial);
    free(rk->found_next), free(rk->directions), free(rk->found);
    taper_state *state = &rk->sim->state;
    if (state->buffer == &rk->state) state->buffer = NULL;
    if (state->window) taper_window_detach(state->window, &rk->state);
    else free(rk->state);
    free(rk);
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

/* Root directions and answers for every slot events.c has now; the next
 * root of a held step is searched again with them. */
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
    if (fit_slots(rk, slots) != 0) return taper_fail(err, TAPER_ENOMEM, "cannot allocate %zu root slots", slots);
    taper_events_directions(rk->sim, rk->directions);
    rk->held.next_known = rk->held.values_fresh = 0;
    rk->g0_valid = 0;
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
 * rk8 needs no dense output for it. */
static taper_step_outcome rk8_advance(taper_stepper *s, double tout, double t_end, taper_step *step)
{
    rk8_stepper *rk = (rk8_stepper *)s;
    const double tstop = rk->stop < t_end ? rk->stop : t_end;
    const rk8_result r = advance_to(rk, taper_sim_entries(rk->sim), tout, tstop, taper_stepper_steps_per_call(rk->sim));
    step->t = rk8_time(rk, &step->t_low);
    step->found = r == RK8_ROOT ? rk->found : NULL;
    switch (r) {
    case RK8_REACHED: return TAPER_STEP_REACHED;
    case RK8_ROOT: return TAPER_STEP_ROOT;
    case RK8_WORK: return TAPER_STEP_WORK;
    case RK8_FAILED:
    case RK8_STEP_ON: break;
    }
    return TAPER_STEP_FAILED;
}

/* The end of the last step, where the state returned is inside it (a root,
 * an output), as CVODE's tn. */
static double rk8_reached(const taper_stepper *s) { return ((const rk8_stepper *)s)->t; }
static double rk8_last_step(const taper_stepper *s) { return ((const rk8_stepper *)s)->h_last; }

/* The loop changed the state at sim->t: a step held is given up there (a
 * single-step method needs nothing of it), and the next starts from the
 * state as the loop left it. */
static taper_status rk8_restart(taper_stepper *s, taper_error *err)
{
    (void)err;
    rk8_stepper *rk = (rk8_stepper *)s;
    if (rk->held.on) leave_held(rk, 0);
    rk->f0_valid = rk->g0_valid = 0;
    return TAPER_OK;
}

/* The roots are located already, to root_tol, on the dense output
 * (find_next_root). */
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
