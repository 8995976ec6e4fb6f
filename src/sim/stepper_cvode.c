/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_cvode.c -- methods 'adams' and 'bdf': SUNDIALS CVODE as a stepper
 * (stepper.h).  CVODE integrates the sim's equations (equations.c) through
 * its callbacks, in the window's N_Vector (nvector_window.c) or a serial
 * one of the whole chain, and finds the roots of events.c's functions
 * itself; its clock and the refinement of its roots are
 * stepper_cvode_clock.c's.  Every call that depends on the SUNDIALS
 * version goes through sundials_compat.c.
 */
#include "stepper_cvode_memory.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <stdio.h>
#include <stdlib.h>

/* Adams' default maximum order, and the growth below which the step is
 * kept fixed (see cvode_start). */
#define ADAMS_ORDER 8
#define ADAMS_ETA_FIXED 1.2

/* ---- CVODE callbacks --------------------------------------------------- */
/* The equations (equations.c) on the state's entries. */
static int rhs(double t, N_Vector y, N_Vector ydot, void *user)
{
    const cvode_stepper *cv = user;
    taper_equations_rhs(cv->sim, t, cvode_entries(cv, y), cvode_entries(cv, ydot));
    return 0;
}

/* Banded analytic Jacobian (BDF, whole chain): d(v_k')/dz = +-F'(z)/m_k,
 * d(z_k')/dv = +-1.  The interleaved layout makes it tridiagonal.  Chains
 * with options use CVODE's difference-quotient band Jacobian instead
 * (attach_solvers): damping and drag couple v_k' to v_{k-1}, v_k, v_{k+1}
 * (bandwidth 2). */
static int jacobian(double t, N_Vector yv, N_Vector fy, SUNMatrix J, void *user, N_Vector t1,
                    N_Vector t2, N_Vector t3)
{
    (void)t, (void)fy, (void)t1, (void)t2, (void)t3;
    const cvode_stepper *cv = user;
    const taper_dyn *d = &cv->sim->dyn;
    const double *y = N_VGetArrayPointer(yv);
    SUNMatZero(J);
    for (size_t k = 1; k <= d->n; k++) {
        sunindextype iv = (sunindextype)taper_idx_v(k), iz = (sunindextype)taper_idx_z(k);
        if (k > 1)
            SM_ELEMENT_B(J, iv, iz - 2) = taper_dyn_force_slope(d, k - 1, y[iz - 2]) * d->inv_mass[k - 1];
        if (k < d->n) {
            SM_ELEMENT_B(J, iv, iz) = -taper_dyn_force_slope(d, k, y[iz]) * d->inv_mass[k - 1];
            SM_ELEMENT_B(J, iz, iv + 2) = -1.0;
        }
        SM_ELEMENT_B(J, iz, iv) = 1.0;
    }
    const size_t c = d->carried; /* whole chain: hi = n; as taper_dyn_carry */
    if (c) {
        sunindextype iv = (sunindextype)taper_idx_v(c), iz = (sunindextype)taper_idx_z(c - 1);
        /* v_c' = v_(c-1)': its dependence on z_(c-1) (the carrier's on
         * z_(c-2) is outside the band and left out: Newton's matrix need
         * not be exact) */
        SM_ELEMENT_B(J, iv, iz) = SM_ELEMENT_B(J, iv - 2, iz);
        SM_ELEMENT_B(J, iz, iv) = SM_ELEMENT_B(J, iz, iv - 2) = 0.0;
    }
    return 0;
}

/* Error weights (equations.c).  CVODE calls this before every step: the
 * moment to sum its clock's rounding (stepper_cvode_clock.c). */
static int error_weights(N_Vector yv, N_Vector wv, void *user)
{
    cvode_stepper *cv = user;
    cvode_clock_track(cv);
    taper_equations_weights(cv->sim, cvode_entries(cv, yv), cvode_entries(cv, wv));
    return 0;
}

/* events.c's root functions on the state's entries. */
static int root_functions(double t, N_Vector y, double *g, void *user)
{
    (void)t;
    const cvode_stepper *cv = user;
    taper_events_root_values(cv->sim, cvode_entries(cv, y), g);
    return 0;
}

/* CVODE's errors and warnings: the last one is kept for the error message
 * of a failed run (whole: the message decides its own length), and each is
 * passed on to the caller's log. */
static void keep_solver_message(const char *message, const char *function, int code, void *user)
{
    cvode_stepper *cv = user;
    const char *format = "%s (CVODE %s, flag %d)";
    int needed = snprintf(NULL, 0, format, message, function, code);
    if (needed < 0) return;
    char *text = malloc((size_t)needed + 1);
    if (text) {
        snprintf(text, (size_t)needed + 1, format, message, function, code);
        free(cv->message);
        cv->message = text;
    }
    taper_sim_log(cv->sim, 1, format, message, function, code);
}

static const char *solver_message(const cvode_stepper *cv) { return cv->message ? cv->message : ""; }

/* ---- memory and state ------------------------------------------------------ */
static void cvode_free(taper_stepper *s)
{
    cvode_stepper *cv = (cvode_stepper *)s;
    if (!cv) return;
    if (cv->mem) CVodeFree(&cv->mem);
    if (cv->nonlinear) SUNNonlinSolFree(cv->nonlinear);
    if (cv->linear) SUNLinSolFree(cv->linear);
    if (cv->band) SUNMatDestroy(cv->band);
    if (cv->y) {
        N_VDestroy(cv->y);
        cv->sim->state.buffer = NULL;
    }
    if (cv->at_root) N_VDestroy(cv->at_root);
    taper_sundials_context_free(&cv->ctx);
    free(cv->message);
    free(cv->roots);
    free(cv);
}

/* The state: a vector of the window (its clones too: CVODE's own vectors
 * follow the window with it), or a serial vector of the whole chain. */
static int make_state(cvode_stepper *cv)
{
    taper_sim *sim = cv->sim;
    cv->window = sim->state.window;
    if (cv->window) {
        cv->y = taper_window_vector_new(cv->window, cv->ctx);
        if (!cv->y) return -1;
        sim->state.buffer = taper_window_vector_buffer(cv->y);
    } else {
        const size_t extra = sim->model.quadratures ? TAPER_N_QUADRATURES : 0;
        cv->y = N_VNew_Serial((sunindextype)(2 * sim->n + extra), cv->ctx);
        if (!cv->y) return -1;
        N_VConst(0.0, cv->y);
        cv->whole = N_VGetArrayPointer(cv->y);
        sim->state.buffer = &cv->whole;
    }
    cv->at_root = N_VClone(cv->y); /* a window vector's clone shares its range */
    return cv->at_root ? 0 : -1;
}

static taper_stepper *cvode_alloc(taper_sim *sim, taper_error *err)
{
    cvode_stepper *cv = calloc(1, sizeof *cv);
    if (!cv) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the CVODE stepper");
        return NULL;
    }
    cv->sim = sim;
    if (taper_sundials_context_new(&cv->ctx) != 0) {
        taper_fail(err, TAPER_ENOMEM, "cannot create the SUNDIALS context");
    } else if (make_state(cv) != 0) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the state");
    } else {
        return (taper_stepper *)cv;
    }
    cvode_free((taper_stepper *)cv);
    return NULL;
}

/* ---- set-up ------------------------------------------------------------ */
static int check(int flag, const char *what, const cvode_stepper *cv, taper_error *err)
{
    if (flag >= 0) return TAPER_OK;
    return taper_fail(err, TAPER_ESOLVER, "CVODE set-up failed in %s (flag %d): %s", what, flag,
                      solver_message(cv));
}

static int attach_solvers(cvode_stepper *cv, taper_error *err)
{
    const taper_sim *sim = cv->sim;
    if (sim->spec.method == TAPER_ADAMS) {
        /* Non-stiff: fixed-point iteration needs no Jacobian at all.  On
         * the window, SUNDIALS' iteration fused over its entries
         * (stepper_cvode_corrector.c); on the whole chain, SUNDIALS'. */
        cv->nonlinear = cv->window ? cvode_corrector_new(cv->y, rhs, &cv->corrector_rhs_evals, cv->ctx)
                                   : SUNNonlinSol_FixedPoint(cv->y, 0, cv->ctx);
        if (!cv->nonlinear) return taper_fail(err, TAPER_ENOMEM, "cannot create the fixed-point solver");
        return check(CVodeSetNonlinearSolver(cv->mem, cv->nonlinear), "CVodeSetNonlinearSolver", cv, err);
    }
    sunindextype n = (sunindextype)(2 * sim->n + (sim->model.quadratures ? TAPER_N_QUADRATURES : 0));
    const sunindextype band = sim->model.options ? 2 : 1;
    cv->band = SUNBandMatrix(n, band, band, cv->ctx);
    if (!cv->band) return taper_fail(err, TAPER_ENOMEM, "cannot create the band matrix");
    cv->linear = SUNLinSol_Band(cv->y, cv->band, cv->ctx);
    if (!cv->linear) return taper_fail(err, TAPER_ENOMEM, "cannot create the band solver");
    int status = check(CVodeSetLinearSolver(cv->mem, cv->linear, cv->band), "CVodeSetLinearSolver", cv, err);
    if (status != TAPER_OK || sim->model.options) return status;
    return check(CVodeSetJacFn(cv->mem, jacobian), "CVodeSetJacFn", cv, err);
}

/* (Re-)declares the root functions to CVODE: their number changes when
 * events.c enlarges its rings.  Called at the start and after a root
 * return, where CVODE re-evaluates every root function before it looks for
 * the next root (cvRcheck2), so none is compared with a stale value. */
static taper_status cvode_arm_roots(taper_stepper *s, taper_error *err)
{
    cvode_stepper *cv = (cvode_stepper *)s;
    const size_t slots = taper_events_slots(cv->sim);
    if (slots > cv->roots_size) {
        int *roots = realloc(cv->roots, 2 * slots * sizeof *roots);
        if (!roots) return taper_fail(err, TAPER_ENOMEM, "cannot allocate %zu root slots", slots);
        cv->roots = roots;
        cv->roots_size = 2 * slots;
    }
    taper_events_directions(cv->sim, cv->roots);
    int status = check(CVodeRootInit(cv->mem, (int)slots, root_functions), "CVodeRootInit", cv, err);
    if (!status) status = check(CVodeSetRootDirection(cv->mem, cv->roots), "CVodeSetRootDirection", cv, err);
    if (!status) status = check(CVodeSetNoInactiveRootWarn(cv->mem), "CVodeSetNoInactiveRootWarn", cv, err);
    return (taper_status)status;
}

static taper_status cvode_start(taper_stepper *s, taper_error *err)
{
    cvode_stepper *cv = (cvode_stepper *)s;
    const taper_sim *sim = cv->sim;
    cv->mem = CVodeCreate(sim->spec.method == TAPER_BDF ? CV_BDF : CV_ADAMS, cv->ctx);
    if (!cv->mem) return taper_fail(err, TAPER_ENOMEM, "cannot create CVODE");
    void *mem = cv->mem;
    cv->messages.fn = keep_solver_message;
    cv->messages.user = cv;
    int status = TAPER_OK;
    if (!status) status = check(taper_sundials_capture_errors(mem, &cv->messages), "error handler", cv, err);
    if (!status) status = check(CVodeInit(mem, rhs, 0.0, cv->y), "CVodeInit", cv, err);
    if (!status) status = check(CVodeWFtolerances(mem, error_weights), "CVodeWFtolerances", cv, err);
    if (!status) status = check(CVodeSetUserData(mem, cv), "CVodeSetUserData", cv, err);
    if (!status) status = check(CVodeSetMaxNumSteps(mem, TAPER_STEPPER_STEPS_PER_CALL), "CVodeSetMaxNumSteps", cv, err);
    /* An explicit first step: CVODE's estimate would use the (unbounded) tout. */
    if (!status) status = check(CVodeSetInitStep(mem, TAPER_STEPPER_FIRST_STEP), "CVodeSetInitStep", cv, err);
    if (!status) status = cvode_arm_roots(s, err);
    /* "t + h = t": the pulse of a steep forward chain crosses its last,
     * lightest granules faster than double precision resolves t (finding C,
     * docs/robustness.md; the affected values end up nan and are counted in
     * the log).  Once says it; CVODE's default repeated it ten times. */
    if (!status) status = check(CVodeSetMaxHnilWarns(mem, 1), "CVodeSetMaxHnilWarns", cv, err);
    /* Adams: max order 8 and a step that changes once it may grow by 1.2
     * (CVODE's default keeps h until it may grow by 1.5).  At order q the
     * error goes like h^(q+1): a 1.5x growth needs an error 1.5^(q+1)
     * times below the tolerance (38x at q = 8), so with the default band
     * a higher order buys no longer steps; together they take monodisperse
     * chains from 63 to 31 steps per granule at rtol 1e-10 (errors 3.6e-10
     * instead of 7.1e-10), backward linear from 86 to 75 (contact openings:
     * 12-23 % of steps fail the error test there).  docs/benchmarks.md,
     * "Steps per granule".
     * The band is (0, 1.2): CVODE (6.4.1 cvSetEta) keeps h while the
     * suggested ratio 1/(6 dsm)^(1/(q+1)) is below 1.2, and shrinks it only
     * on a failed error test (dsm > 1), so h may sit anywhere in a range of
     * 1.2 * 6^(1/9) = 1.46 at q = 8.  On a steady solitary wave it stays
     * at the last value the start-up chose: 29.5-35.5 steps per granule over
     * rtol 0.8-1.2e-10, yet within ~7 % in CPU time, because the longer
     * steps need a second fixed-point iteration on every step (dsm > 0.1,
     * the nonlinear tolerance) and the shorter ones on 70 %.  A narrow band
     * (0.97, 1.03) settles robustly and removes the monodisperse phase
     * drift, but loses accuracy on backward exponential chains (t_pass up to
     * 2.6e-8 at N = 200): not adopted.  docs/benchmarks.md, "The step
     * band's level". */
    int order = sim->spec.max_order ? sim->spec.max_order : (sim->spec.method == TAPER_ADAMS ? ADAMS_ORDER : 5);
    if (!status) status = check(CVodeSetMaxOrd(mem, order), "CVodeSetMaxOrd", cv, err);
    if (!status && sim->spec.method == TAPER_ADAMS)
        status = check(CVodeSetEtaFixedStepBounds(mem, 0.0, ADAMS_ETA_FIXED), "CVodeSetEtaFixedStepBounds", cv, err);
    if (!status) status = attach_solvers(cv, err);
    return (taper_status)status;
}

/* ---- the steps ---------------------------------------------------------- */
static void cvode_set_stop(taper_stepper *s, double t_stop)
{
    /* (a stop time behind tn is refused, and CVODE says so in the log) */
    const cvode_stepper *cv = (const cvode_stepper *)s;
    if (cv->mem) CVodeSetStopTime(cv->mem, t_stop);
}

/* CVode in its normal mode: CVODE steps past tout as it would anyway and
 * returns its interpolant there; t_end is no stop of CVODE's (a stop time
 * costs a multistep method its step size): the loop sets those. */
static taper_step_outcome cvode_advance(taper_stepper *s, double tout, double t_end, taper_step *step)
{
    (void)t_end;
    cvode_stepper *cv = (cvode_stepper *)s;
    cv->failed = NULL;
    step->t = cv->sim->t; /* (where CVode returns before it sets it) */
    /* the window may have grown since the last advance */
    CVodeSetMaxNumSteps(cv->mem, taper_stepper_steps_per_call(cv->sim));
    cv->flag = CVode(cv->mem, tout, cv->y, &step->t, CV_NORMAL);
    step->found = NULL;
    if (cv->flag == CV_ROOT_RETURN) {
        if (CVodeGetRootInfo(cv->mem, cv->roots) < 0) {
            cv->failed = "CVodeGetRootInfo";
            step->t_low = cv->t_shift;
            return TAPER_STEP_FAILED;
        }
        cvode_clock_track(cv); /* the step holding the root */
        step->found = cv->roots;
    }
    step->t_low = cv->t_shift;
    switch (cv->flag) {
    case CV_SUCCESS:
    case CV_TSTOP_RETURN: return TAPER_STEP_REACHED;
    case CV_ROOT_RETURN: return TAPER_STEP_ROOT;
    case CV_TOO_MUCH_WORK: return TAPER_STEP_WORK;
    default: break;
    }
    return TAPER_STEP_FAILED;
}

static double cvode_reached(const taper_stepper *s)
{
    const cvode_stepper *cv = (const cvode_stepper *)s;
    double tn = cv->sim->t;
    if (cv->mem) CVodeGetCurrentTime(cv->mem, &tn);
    return tn;
}

static double cvode_last_step(const taper_stepper *s)
{
    const cvode_stepper *cv = (const cvode_stepper *)s;
    double h = 0.0;
    if (cv->mem) CVodeGetLastStep(cv->mem, &h);
    return h;
}

/* CVODE's counters since its last (re-)initialisation. */
static taper_step_counters read_counters(const cvode_stepper *cv)
{
    taper_step_counters c = {0};
    void *mem = cv->mem;
    if (!mem) return c;
    CVodeGetNumSteps(mem, &c.steps);
    CVodeGetNumRhsEvals(mem, &c.rhs_evals);
    c.rhs_evals += cv->corrector_rhs_evals;
    CVodeGetNumGEvals(mem, &c.root_evals);
    if (cv->linear) CVodeGetNumJacEvals(mem, &c.jac_evals);
    CVodeGetNumNonlinSolvIters(mem, &c.nonlin_iters);
    CVodeGetNumErrTestFails(mem, &c.err_test_fails);
    return c;
}

/* CVodeReInit resets CVODE's counters: the run keeps the sum of those of
 * earlier restarts. */
static taper_step_counters cvode_counters(const taper_stepper *s)
{
    const cvode_stepper *cv = (const cvode_stepper *)s;
    taper_step_counters a = read_counters(cv);
    const taper_step_counters b = cv->before_restart;
    a.steps += b.steps;
    a.rhs_evals += b.rhs_evals;
    a.root_evals += b.root_evals;
    a.jac_evals += b.jac_evals;
    a.nonlin_iters += b.nonlin_iters;
    a.err_test_fails += b.err_test_fails;
    return a;
}

/* Re-initialises CVODE at the current state: a fresh history, and a first
 * step of a hundredth of the usual (the change is a kink). */
static taper_status cvode_restart(taper_stepper *s, taper_error *err)
{
    cvode_stepper *cv = (cvode_stepper *)s;
    const taper_sim *sim = cv->sim;
    cv->before_restart = cvode_counters(s);
    if (CVodeReInit(cv->mem, sim->t, cv->y) != CV_SUCCESS)
        return taper_fail(err, TAPER_ESOLVER, "cannot restart CVODE at t = %.17g: %s", sim->t,
                          solver_message(cv));
    cv->tn_seen = sim->t; /* CVODE's counters start again from 0 */
    cv->nst_seen = 0;
    cv->corrector_rhs_evals = 0;
    CVodeSetInitStep(cv->mem, TAPER_STEPPER_FIRST_STEP * 1e-2);
    return TAPER_OK;
}

static int cvode_sees_tiny_sign_changes(const taper_stepper *s)
{
    (void)s;
    return taper_sundials_roots_see_tiny_values();
}

static void cvode_describe_failure(const taper_stepper *s, taper_error *err, taper_status status)
{
    const cvode_stepper *cv = (const cvode_stepper *)s;
    if (cv->failed) taper_fail(err, status, "%s failed", cv->failed);
    else taper_fail(err, status, "CVODE failed (flag %d: %s)", cv->flag, solver_message(cv));
}

const taper_stepper_type taper_stepper_cvode = {
    .alloc = cvode_alloc,
    .start = cvode_start,
    .arm_roots = cvode_arm_roots,
    .set_stop = cvode_set_stop,
    .advance = cvode_advance,
    .reached = cvode_reached,
    .last_step = cvode_last_step,
    .restart = cvode_restart,
    .refine_root = cvode_refine_root,
    .sees_tiny_sign_changes = cvode_sees_tiny_sign_changes,
    .counters = cvode_counters,
    .describe_failure = cvode_describe_failure,
    .free = cvode_free,
};
