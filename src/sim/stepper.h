/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper.h -- the integrators of a run as steppers: one file each, the
 * same few operations, chosen by the method (steppers.c, one row per
 * method), as REBOUND's integrator_*.c.  The loop (solve.c) drives any of
 * them and never asks which one runs:
 *
 *   alloc, start   the stepper and the state's storage, then the start at
 *                  t = 0 from the state the loop set, root functions armed
 *                  (arm_roots again when their number changes);
 *   advance        towards an output time, stopping at the first root, or
 *                  at the stop time (set_stop); where its own state has
 *                  got to (reached, last_step);
 *   restart        after the loop changed the state (a granule taken back,
 *                  the piston stopped): a history no longer holds;
 *   refine_root    an event's zero located again inside the last step;
 *   counters, describe_failure, free.
 *
 * A stepper integrates equations.c's right-hand side under its error
 * weights, with events.c's root functions (taper_events_slots of them, in
 * taper_events_directions) armed, on the state of sim->state; it calls
 * nothing above those.  Its failures are its own: it reports an outcome
 * (taper_step_outcome) and says why in its own words (describe_failure,
 * and err where it is set up or restarted).
 * Only solve.c and the stepper files include this header
 * (tests/regression/layering.py).
 *
 * The steppers: stepper_cvode.c (CVODE's Adams and BDF, multistep, with
 * CVODE's root finding; its clock and its roots located again on its
 * interpolant in stepper_cvode_clock.c), stepper_rk8.c (GSL's rk8pd,
 * single step, with its own root location).  A new one is a file that
 * defines a taper_stepper_type and a row of steppers.c's table, its method
 * a row of the settings' table (TAPER_METHOD_LIST).
 */
#ifndef TAPER_STEPPER_H
#define TAPER_STEPPER_H

#include "sim.h"

/* Steps per advance at most: the loop's monitor (progress, Ctrl-C) is
 * consulted at least this often.  (CVODE's default of 500 would end long
 * chains.)  Fewer on a wide window: TAPER_STEPPER_WORK_PER_CALL
 * granule-steps, about 0.05 s at ~50 ns a granule and step, so that a
 * signal stops a run whose window spans thousands of granules (a loaded or
 * damped chain after the pulse, where no event calls the monitor) within a
 * fifth of a second on a loaded machine (at 2e6 the process's CPU time from
 * the signal to the stop reached 0.13 s, tests/bindings/python/
 * test_interrupt.py).  The returns cost nothing measurable: callgrind counts
 * 13.66e9 instructions either way for 800 loaded granules to t = 400. */
#define TAPER_STEPPER_STEPS_PER_CALL 20000L
#define TAPER_STEPPER_WORK_PER_CALL 1e6
static inline long taper_stepper_steps_per_call(const taper_sim *sim)
{
    const double steps = TAPER_STEPPER_WORK_PER_CALL / (double)(sim->dyn.hi - sim->dyn.lo + 1);
    return steps >= (double)TAPER_STEPPER_STEPS_PER_CALL ? TAPER_STEPPER_STEPS_PER_CALL
           : steps < 1.0                                 ? 1
                                                         : (long)steps;
}
/* The first step tried: an explicit one, since an estimate from the output
 * time would use an unbounded one. */
#define TAPER_STEPPER_FIRST_STEP 1e-4
/* Below this rtol roots are located to a few ulps of t (CVODE's by its
 * refine_root, rk8's by its own search); above it the integration error of
 * an event time (~10-100 rtol) dwarfs CVODE's root tolerance of 100 uround
 * (|t| + |h|), and the search (~10 interpolations per event, 8 % of a
 * default monodisperse run's instructions) buys nothing. */
#define TAPER_REFINE_BELOW_RTOL 1e-11

typedef enum taper_step_outcome {
    TAPER_STEP_REACHED, /* at tout, or at the stop time if that came first  */
    TAPER_STEP_ROOT,    /* at a root: taper_step.found says whose           */
    TAPER_STEP_WORK,    /* taper_stepper_steps_per_call steps taken, short
                           of tout                                          */
    TAPER_STEP_FAILED   /* describe_failure says why                        */
} taper_step_outcome;

/* Where an advance ended: the state's entries (sim->state) hold the state
 * at t. */
typedef struct taper_step {
    double t;          /* on the stepper's clock                            */
    double t_low;      /* that clock's low part: the true time is t + t_low */
    const int *found;  /* TAPER_STEP_ROOT: per root slot the sign of its
                          crossing (+1 up, -1 down, 0 none); the stepper's */
} taper_step;

typedef struct taper_stepper taper_stepper; /* a stepper's own memory */

typedef struct taper_stepper_type {
    /* The stepper and the state's storage, all zero: the buffers of
     * sim->state.window where the loop made one, else the whole chain's
     * 2 n entries and the quadratures; sets sim->state.buffer.  NULL when
     * it cannot (err says why; what was made is freed). */
    taper_stepper *(*alloc)(taper_sim *sim, taper_error *err);
    /* Starts at t = 0 from the state the loop set (the impulse), the root
     * functions armed. */
    taper_status (*start)(taper_stepper *s, taper_error *err);
    /* The root functions changed in number (events.c's rings grew): armed
     * again for the next advance. */
    taper_status (*arm_roots)(taper_stepper *s, taper_error *err);
    /* No step goes past t_stop (a discontinuity, the end of a phase of the
     * run) until another is set; the stepper ends a step there exactly. */
    void (*set_stop)(taper_stepper *s, double t_stop);
    /* Steps towards tout and leaves the state at tout, at the stop time or
     * at the first root on the way, whichever comes first, or short of
     * them after taper_stepper_steps_per_call steps.  An output time inside
     * a step need not end the step: the state is then the stepper's
     * account of it there (CVODE's interpolant, rk8's dense output of order
     * 7) and the next advance goes on from where the stepper
     * is.  t_end, the end of the run's phase (>= tout), bounds the outputs
     * to come: a stepper may end its steps there as at a stop time. */
    taper_step_outcome (*advance)(taper_stepper *s, double tout, double t_end, taper_step *step);
    /* How far the stepper's own state has gone: the end of its last step,
     * where the state returned is inside it (CVODE's tn), else the time
     * returned.  A stop time before it cannot be set. */
    double (*reached)(const taper_stepper *s);
    /* The size of the last step (up to the root where it was cut there). */
    double (*last_step)(const taper_stepper *s);
    /* The loop changed the state at sim->t (a granule came back, the
     * piston stopped): the stepper goes on from there with nothing of the
     * steps before that the change made wrong (a multistep method's
     * history; a single-step method starts afresh at every step anyway).
     * On failure err says why. */
    taper_status (*restart)(taper_stepper *s, taper_error *err);
    /* The zero of g(k), a root the last advance returned at sim->t,
     * located again to a few ulps of t on the stepper's own account of the
     * step that holds it (its interpolant): returns its time on the
     * stepper's clock and points *y at the state there.  A stepper that
     * locates its roots that closely in advance, or where rtol >=
     * TAPER_REFINE_BELOW_RTOL, returns sim->t and leaves *y. */
    double (*refine_root)(taper_stepper *s, taper_root_value g, size_t k, const double **y);
    /* Whether the root finder sees a sign change between two tiny values
     * whose product underflows (taper_events_arm). */
    int (*sees_tiny_sign_changes)(const taper_stepper *s);
    /* The run's counters so far, over every restart. */
    taper_step_counters (*counters)(const taper_stepper *s);
    /* Why the last advance failed (TAPER_STEP_FAILED), in the stepper's
     * words, written by taper_fail(err, status, ...).  (Set-up and restart
     * write err themselves.) */
    void (*describe_failure)(const taper_stepper *s, taper_error *err, taper_status status);
    void (*free)(taper_stepper *s);
} taper_stepper_type;

/* The row of a method: its stepper, and whether the stepper integrates on
 * the active window when the spec asks for one (CVODE's BDF solves with
 * a band Jacobian of the whole chain). */
typedef struct taper_stepper_row {
    const taper_stepper_type *type;
    int on_window;
} taper_stepper_row;

/* steppers.c: the method's row; NULL for a value outside TAPER_METHOD_LIST. */
const taper_stepper_row *taper_stepper_of(taper_method method);

/* The steppers (each defined in its own file). */
extern const taper_stepper_type taper_stepper_cvode;
extern const taper_stepper_type taper_stepper_rk8;

#endif
