/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_cvode_memory.h -- the CVODE stepper's memory, shared by its files:
 * stepper_cvode.c (set-up, CVODE's callbacks, the stepper's operations),
 * stepper_cvode_clock.c (CVODE's clock, and its roots located again on
 * its interpolant) and stepper_cvode_corrector.c (the Adams corrector on
 * the window).  Private to them: the rest of the run sees a
 * taper_stepper (stepper.h) and no SUNDIALS type.
 */
#ifndef TAPER_STEPPER_CVODE_MEMORY_H
#define TAPER_STEPPER_CVODE_MEMORY_H

#include "nvector_window.h"
#include "stepper.h"
#include "sundials_compat.h"

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

typedef struct cvode_stepper {
    taper_sim *sim;
    SUNContext ctx;
    void *mem;
    N_Vector y;             /* the state (sim->state's storage)             */
    taper_window *window;   /* the state's window (NULL: a serial vector of
                               the whole chain, whose data is `whole`)      */
    double *whole;
    SUNMatrix band;
    SUNLinearSolver linear;
    SUNNonlinearSolver nonlinear;
    taper_solver_messages messages;
    char *message;          /* CVODE's last message (NULL: none yet)        */
    int flag;               /* the last CVode call's, for describe_failure  */
    const char *failed;     /* a call other than CVode that failed          */
    taper_step_counters before_restart; /* summed over earlier restarts     */
    int *roots;             /* CVodeSetRootDirection's array, then
                               CVodeGetRootInfo's answer: roots_size slots  */
    size_t roots_size;
    N_Vector at_root;       /* the state at a refined root                  */
    /* CVODE's time drifts: it advances tn += h rounded to double, and at a
     * fixed h each step rounds the same way (stepper_cvode_clock.c).  The
     * rounding errors summed exactly: true time = CVODE's time + t_shift. */
    double t_shift;
    double tn_seen;         /* CVODE's tn and step count when last tracked  */
    long nst_seen;
    /* Right-hand sides the window's corrector evaluated since CVODE's last
     * (re-)initialisation: CVODE's nfe does not count them. */
    long corrector_rhs_evals;
} cvode_stepper;

/* Pointer to the entry at absolute index taper_dyn_begin of one of the
 * stepper's vectors (y, CVODE's own). */
static inline double *cvode_entries(const cvode_stepper *cv, N_Vector v)
{
    return cv->window ? taper_window_data(v) : N_VGetArrayPointer(v);
}

/* ---- stepper_cvode_clock.c ------------------------------------------------- */
/* Sums the rounding of CVODE's clock over the steps taken since the last
 * call into t_shift (called before every step, from the error weights,
 * and at each root return). */
void cvode_clock_track(cvode_stepper *cv);
/* The CVODE stepper's refine_root (stepper.h). */
double cvode_refine_root(taper_stepper *s, taper_root_value g, size_t k, const double **y);

/* ---- stepper_cvode_corrector.c --------------------------------------------- */
/* CVODE's right-hand side (CVRhsFn). */
typedef int (*cvode_rhs_fn)(double t, N_Vector y, N_Vector ydot, void *user);
/* The fixed-point corrector of Adams steps on window vectors like y
 * (nvector_window.h): SUNDIALS' fixed-point iteration, fused.  rhs is the
 * right-hand side CVODE was given; each evaluation made here is counted in
 * *rhs_evals.  NULL on allocation failure. */
SUNNonlinearSolver cvode_corrector_new(N_Vector y, cvode_rhs_fn rhs, long *rhs_evals, SUNContext ctx);

#endif
