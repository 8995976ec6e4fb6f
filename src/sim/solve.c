/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * solve.c -- the run: CVODE set-up and callbacks, and the loop that asks
 * events.c what a root return means and window.c what the window must do,
 * and applies the answers (sim.c moves the window; CVODE is restarted here
 * and nowhere else).  Then the statistics and the end of the run.
 *
 * The run starts from the impulse (v_1 = 1, everything else at rest and just
 * touching; with a striker the striker moves, granule 1 rests) and ends by
 * itself as soon as every requested observable is known, never at a guessed
 * end time, unless the caller asks to go on to t_end.  A sampler is served
 * on the way (sample.c).
 */
#include "sim.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Internal steps per CVode call: the monitor (progress, Ctrl-C) is consulted
 * at least this often.  CVODE's default of 500 would end long chains.
 * Fewer on a wide window (steps_per_call): WORK_PER_CALL granule-steps,
 * about 0.1 s at ~50 ns a granule and step, so that a signal stops a run
 * whose window spans thousands of granules (a loaded or damped chain after
 * the pulse, where no event calls the monitor) within a fraction of a
 * second. */
#define STEPS_PER_CALL 20000L
#define WORK_PER_CALL 2e6
static long steps_per_call(const taper_sim *sim)
{
    const double steps = WORK_PER_CALL / (double)(sim->dyn.hi - sim->dyn.lo + 1);
    return steps >= (double)STEPS_PER_CALL ? STEPS_PER_CALL : steps < 1.0 ? 1 : (long)steps;
}

/* Once every pass time is known, how long (in units of the longest
 * residence time) to wait for the remaining peaks before declaring them
 * absent. */
#define PEAK_GRACE 20.0
#define INITIAL_STEP 1e-4
/* Adams' default maximum order, and the growth below which the step is
 * kept fixed (see setup_cvode). */
#define ADAMS_ORDER 8
#define ADAMS_ETA_FIXED 1.2
/* The end of time when no t_max is given (pass times of exponential chains
 * grow like e^{eta k}: 1e30 is reached within a few hundred granules). */
#define NO_TIME_LIMIT 1e300

/* ---- CVODE callbacks --------------------------------------------------- */
/* The equations (equations.c) on the state's entries. */
static int rhs(double t, N_Vector y, N_Vector ydot, void *user)
{
    const taper_sim *sim = user;
    taper_equations_rhs(sim, t, taper_sim_data(sim, y), taper_sim_data(sim, ydot));
    return 0;
}

static double *quadrature_entries(const taper_sim *sim, N_Vector v)
{
    return taper_sim_data(sim, v) + (taper_dyn_end(&sim->dyn) - taper_dyn_begin(&sim->dyn));
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
    const taper_sim *sim = user;
    const taper_dyn *d = &sim->dyn;
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
 * moment to sum its clock's rounding (clock.c). */
static int error_weights(N_Vector yv, N_Vector wv, void *user)
{
    taper_sim *sim = user;
    taper_clock_track(sim);
    taper_equations_weights(sim, taper_sim_data(sim, yv), taper_sim_data(sim, wv));
    return 0;
}

/* CVODE's errors and warnings: the last one is kept for the error message
 * of a failed run (whole: the message decides its own length), and each is
 * passed on to the caller's log. */
static void keep_solver_message(const char *message, const char *function, int code, void *user)
{
    taper_sim *sim = user;
    const char *format = "%s (CVODE %s, flag %d)";
    int needed = snprintf(NULL, 0, format, message, function, code);
    if (needed < 0) return;
    char *text = malloc((size_t)needed + 1);
    if (text) {
        snprintf(text, (size_t)needed + 1, format, message, function, code);
        free(sim->cv.message);
        sim->cv.message = text;
    }
    taper_sim_log(sim, 1, format, message, function, code);
}

static const char *solver_message(const taper_sim *sim)
{
    return sim->cv.message ? sim->cv.message : "";
}

/* ---- set-up ------------------------------------------------------------ */
static int make_state(taper_sim *sim)
{
    taper_cvode *cv = &sim->cv;
    const size_t extra = sim->model.quadratures ? TAPER_N_QUADRATURES : 0;
    if (sim->spec.window && sim->spec.method != TAPER_BDF) { /* BDF: a banded Jacobian */
        cv->window = taper_window_alloc_tail(0, 2, 64, extra); /* the quadratures ride along */
        if (!cv->window) return -1;
        cv->y = taper_window_vector_new(cv->window, cv->ctx);
        if (!cv->y) return -1;
        /* The body with the impulse and the next one are in the window
         * from the start (with a left wall, the wall behind them too): their
         * contact closes at t = 0+ in every chain, so holding it out would
         * only delay it.  A growth root is acted on at the end of CVODE's
         * step, not at the root (the new granule's state and history are
         * zero at CVODE's internal time tn): a first contact joining at its
         * growth root lost the impulse r h^n / n of the whole first step
         * (h = 1e-4), an energy error of 1.3e-6 for n = 3/2 and 1.2e-8 for
         * n = 2 at any rtol (the whole chain: 2.5e-9 and 1.6e-9 at rtol
         * 1e-12).  Under a load the same holds for the linear K h^2 / 2. */
        const size_t i0 = sim->model.impulse;
        const size_t hi = i0 < sim->n ? i0 + 1 : i0;
        if (taper_sim_move_window(sim, 1, hi, 0.0) != 0) return -1;
    } else {
        cv->y = N_VNew_Serial((sunindextype)(2 * sim->n + extra), cv->ctx);
        if (!cv->y) return -1;
        N_VConst(0.0, cv->y);
        if (taper_sim_move_window(sim, 1, sim->n, 0.0) != 0) return -1;
    }
    sim->stats.max_window = sim->dyn.hi - sim->dyn.lo + 1;
    cv->at_root = N_VClone(cv->y); /* a window vector's clone shares its range */
    if (!cv->at_root) return -1;
    /* v_1 = 1: the impulse (on the striker, or on granule 1 before a wall) */
    taper_sim_data(sim, cv->y)[taper_idx_v(sim->model.impulse)] = 1.0;
    return 0;
}

static int check(int flag, const char *what, const taper_sim *sim, taper_error *err)
{
    if (flag >= 0) return TAPER_OK;
    return taper_fail(err, TAPER_ESOLVER, "CVODE set-up failed in %s (flag %d): %s", what, flag,
                      solver_message(sim));
}

static int attach_solvers(taper_sim *sim, taper_error *err)
{
    taper_cvode *cv = &sim->cv;
    if (sim->spec.method == TAPER_ADAMS) {
        /* Non-stiff: fixed-point iteration needs no Jacobian at all. */
        cv->nonlinear = SUNNonlinSol_FixedPoint(cv->y, 0, cv->ctx);
        if (!cv->nonlinear) return taper_fail(err, TAPER_ENOMEM, "cannot create the fixed-point solver");
        return check(CVodeSetNonlinearSolver(cv->mem, cv->nonlinear), "CVodeSetNonlinearSolver", sim, err);
    }
    sunindextype n = (sunindextype)(2 * sim->n + (sim->model.quadratures ? TAPER_N_QUADRATURES : 0));
    const sunindextype band = sim->model.options ? 2 : 1;
    cv->band = SUNBandMatrix(n, band, band, cv->ctx);
    if (!cv->band) return taper_fail(err, TAPER_ENOMEM, "cannot create the band matrix");
    cv->linear = SUNLinSol_Band(cv->y, cv->band, cv->ctx);
    if (!cv->linear) return taper_fail(err, TAPER_ENOMEM, "cannot create the band solver");
    int status = check(CVodeSetLinearSolver(cv->mem, cv->linear, cv->band), "CVodeSetLinearSolver", sim, err);
    if (status != TAPER_OK || sim->model.options) return status;
    return check(CVodeSetJacFn(cv->mem, jacobian), "CVodeSetJacFn", sim, err);
}

/* (Re-)declares the root functions to CVODE: their number changes when
 * events.c enlarges its rings.  Called at the start and after a root
 * return, where CVODE re-evaluates every root function before it looks for
 * the next root (cvRcheck2), so none is compared with a stale value. */
static int init_roots(taper_sim *sim, taper_error *err)
{
    taper_cvode *cv = &sim->cv;
    const size_t slots = taper_events_slots(sim);
    /* room for twice the slots: rk8 keeps the directions in the second half */
    if (2 * slots > cv->roots_size) {
        int *roots = realloc(cv->roots, 4 * slots * sizeof *roots);
        if (!roots) return taper_fail(err, TAPER_ENOMEM, "cannot allocate %zu root slots", slots);
        cv->roots = roots;
        cv->roots_size = 4 * slots;
    }
    taper_events_directions(sim, cv->roots);
    if (cv->rk8) { /* rk8 reads the directions behind the slots' answers */
        memcpy(cv->roots + slots, cv->roots, slots * sizeof *cv->roots);
        return TAPER_OK;
    }
    int status = check(CVodeRootInit(cv->mem, (int)slots, taper_events_root_function), "CVodeRootInit", sim, err);
    if (!status) status = check(CVodeSetRootDirection(cv->mem, cv->roots), "CVodeSetRootDirection", sim, err);
    if (!status) status = check(CVodeSetNoInactiveRootWarn(cv->mem), "CVodeSetNoInactiveRootWarn", sim, err);
    return status;
}

/* The quadratures at sim->t: the state's last entries; NULL without. */
static const double *quadratures_now(const taper_sim *sim)
{
    if (!sim->model.quadratures || !sim->cv.y) return NULL;
    return quadrature_entries(sim, sim->cv.y);
}

/* ---- method 'rk8' (rk8.c): the sim's equations and roots as its callbacks ---- */
static int rk8_rhs(double t, const double *y, double *f, void *user)
{
    taper_equations_rhs(user, t, y, f);
    return 0;
}

static void rk8_weights(const double *y, double *w, void *user) { taper_equations_weights(user, y, w); }
static void rk8_roots(const double *y, double *g, void *user) { taper_events_root_values(user, y, g); }

/* The state's entries: the window's (with the quadratures' tail) or the
 * whole chain's. */
static size_t state_length(const taper_sim *sim)
{
    return sim->cv.window ? taper_window_length(sim->cv.y) : (size_t)N_VGetLength(sim->cv.y);
}

static int setup_rk8(taper_sim *sim, taper_error *err)
{
    sim->cv.rk8 = taper_rk8_alloc(rk8_rhs, rk8_weights, rk8_roots, sim, INITIAL_STEP);
    if (!sim->cv.rk8) return taper_fail(err, TAPER_ENOMEM, "cannot create the rk8 integrator");
    /* Roots as CVODE locates them: to 100 uround (|t| + |h|) (cvRootfind's
     * ttol), and below rtol 1e-11, where that would dwarf the integration
     * error, to a few ulps (clock.c refines CVODE's there). */
    if (!(sim->spec.rtol < TAPER_REFINE_BELOW_RTOL)) taper_rk8_set_root_tolerance(sim->cv.rk8, 100.0 * DBL_EPSILON);
    return init_roots(sim, err);
}

/* The state, then the integrator: CVODE, or rk8 in its place. */
static int setup_integrator(taper_sim *sim, taper_error *err)
{
    taper_cvode *cv = &sim->cv;
    taper_window_growth_thresholds(sim, sim->grow_z);
    if (taper_sundials_context_new(&cv->ctx) != 0)
        return taper_fail(err, TAPER_ENOMEM, "cannot create the SUNDIALS context");
    if (make_state(sim) != 0) return taper_fail(err, TAPER_ENOMEM, "cannot allocate the state");
    if (sim->spec.method == TAPER_RK8) return setup_rk8(sim, err);
    cv->mem = CVodeCreate(sim->spec.method == TAPER_BDF ? CV_BDF : CV_ADAMS, cv->ctx);
    if (!cv->mem) return taper_fail(err, TAPER_ENOMEM, "cannot create CVODE");
    void *mem = cv->mem;
    cv->messages.fn = keep_solver_message;
    cv->messages.user = sim;
    int status = TAPER_OK;
    if (!status) status = check(taper_sundials_capture_errors(mem, &cv->messages), "error handler", sim, err);
    if (!status)
        status = check(CVodeInit(mem, rhs, 0.0, cv->y), "CVodeInit", sim, err);
    if (!status) status = check(CVodeWFtolerances(mem, error_weights), "CVodeWFtolerances", sim, err);
    if (!status) status = check(CVodeSetUserData(mem, sim), "CVodeSetUserData", sim, err);
    if (!status) status = check(CVodeSetMaxNumSteps(mem, steps_per_call(sim)), "CVodeSetMaxNumSteps", sim, err);
    /* An explicit first step: CVODE's estimate would use the (unbounded) tout. */
    if (!status) status = check(CVodeSetInitStep(mem, INITIAL_STEP), "CVodeSetInitStep", sim, err);
    if (!status) status = init_roots(sim, err);
    /* "t + h = t": the pulse of a steep forward chain crosses its last,
     * lightest granules faster than double precision resolves t (finding C,
     * docs/robustness.md; the affected values end up nan and are counted in
     * the log).  Once says it; CVODE's default repeated it ten times. */
    if (!status) status = check(CVodeSetMaxHnilWarns(mem, 1), "CVodeSetMaxHnilWarns", sim, err);
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
    if (!status) status = check(CVodeSetMaxOrd(mem, order), "CVodeSetMaxOrd", sim, err);
    if (!status && sim->spec.method == TAPER_ADAMS)
        status = check(CVodeSetEtaFixedStepBounds(mem, 0.0, ADAMS_ETA_FIXED), "CVodeSetEtaFixedStepBounds", sim, err);
    if (!status) status = attach_solvers(sim, err);
    return status;
}

/* ---- counters ------------------------------------------------------------ */
/* CVODE's counters since its last (re-)initialisation. */
static taper_cvode_counters read_counters(const taper_sim *sim)
{
    taper_cvode_counters c = {0};
    void *mem = sim->cv.mem;
    if (sim->cv.rk8) {
        const taper_rk8_counters r = taper_rk8_get_counters(sim->cv.rk8);
        c.steps = r.steps, c.rhs_evals = r.rhs_evals, c.root_evals = r.root_evals;
        c.err_test_fails = r.err_test_fails;
        return c;
    }
    if (!mem) return c;
    CVodeGetNumSteps(mem, &c.steps);
    CVodeGetNumRhsEvals(mem, &c.rhs_evals);
    CVodeGetNumGEvals(mem, &c.root_evals);
    if (sim->cv.linear) CVodeGetNumJacEvals(mem, &c.jac_evals);
    CVodeGetNumNonlinSolvIters(mem, &c.nonlin_iters);
    CVodeGetNumErrTestFails(mem, &c.err_test_fails);
    return c;
}

static taper_cvode_counters add_counters(taper_cvode_counters a, taper_cvode_counters b)
{
    a.steps += b.steps;
    a.rhs_evals += b.rhs_evals;
    a.root_evals += b.root_evals;
    a.jac_evals += b.jac_evals;
    a.nonlin_iters += b.nonlin_iters;
    a.err_test_fails += b.err_test_fails;
    return a;
}

/* The run's counters so far, over every restart. */
static taper_cvode_counters total_counters(const taper_sim *sim)
{
    return add_counters(read_counters(sim), sim->cv.before_restart);
}

/* ---- why a run stops early -------------------------------------------------- */
typedef enum stop_reason {
    STOP_INTERRUPTED,    /* the monitor asked                                */
    STOP_MAX_STEPS,      /* spec max_steps                                    */
    STOP_T_MAX,          /* spec t_max                                        */
    STOP_END_OF_TIME,    /* NO_TIME_LIMIT without a t_max                     */
    STOP_SOLVER,         /* CVODE failed                                      */
    STOP_ROOT_INFO,      /* CVodeGetRootInfo failed                           */
    STOP_WINDOW_MEMORY,  /* the window could not grow                         */
    STOP_RESTART         /* CVodeReInit failed                                */
} stop_reason;

static taper_status stop_status(stop_reason why)
{
    switch (why) {
    case STOP_INTERRUPTED: return TAPER_EINTERRUPTED;
    case STOP_MAX_STEPS:
    case STOP_T_MAX:
    case STOP_END_OF_TIME: return TAPER_ELIMIT;
    case STOP_WINDOW_MEMORY: return TAPER_ENOMEM;
    case STOP_SOLVER:
    case STOP_ROOT_INFO:
    case STOP_RESTART: break;
    }
    return TAPER_ESOLVER;
}

/* What a user can change when a run stops early. */
static const char *advice(stop_reason why)
{
    switch (why) {
    case STOP_INTERRUPTED: return "";
    case STOP_MAX_STEPS: return "; raise max_steps (0: no limit)";
    case STOP_END_OF_TIME:
        return "; the pulse cannot cross this chain in finite double-precision time: fewer "
               "granules or a weaker taper";
    case STOP_T_MAX: return "; raise t_max (0: no limit)";
    default: break;
    }
    return "; try a looser rtol, method 'bdf' (strongly forward-tapered chains, whose lightest "
           "granules collide on tiny time scales), or fewer granules";
}

/* The granule that body k is (0 for a body before granule 1). */
static size_t granule_of(const taper_sim *sim, size_t k)
{
    return k > sim->model.off ? k - sim->model.off : 0;
}

/* Ends the run early: the reason, where the pulse was, what to change.
 * flag: CVODE's flag for STOP_SOLVER. */
static taper_status stop(const taper_sim *sim, taper_error *err, stop_reason why, int flag)
{
    const taper_status status = stop_status(why);
    switch (why) {
    case STOP_WINDOW_MEMORY:
        /* not a stop of the integration: nothing to keep or advise */
        return taper_fail(err, status, "cannot enlarge the active window to %zu granules",
                          sim->dyn.hi - sim->dyn.lo + 2);
    case STOP_RESTART:
        return taper_fail(err, status, "cannot restart CVODE at t = %.17g: %s", sim->t,
                          solver_message(sim));
    case STOP_INTERRUPTED: taper_fail(err, status, "interrupted"); break;
    case STOP_MAX_STEPS: taper_fail(err, status, "max_steps reached"); break;
    case STOP_T_MAX: taper_fail(err, status, "t_max reached"); break;
    case STOP_END_OF_TIME: taper_fail(err, status, "time 1e300 reached (no t_max given)"); break;
    case STOP_ROOT_INFO: taper_fail(err, status, "CVodeGetRootInfo failed"); break;
    case STOP_SOLVER:
        if (sim->cv.rk8) taper_fail(err, status, "rk8 failed: %s", taper_rk8_failure(sim->cv.rk8));
        else taper_fail(err, status, "CVODE failed (flag %d: %s)", flag, solver_message(sim));
        break;
    }
    taper_fail_append(err, " at t = %.17g with the pulse past granule %zu of %zu "
                           "(observables found so far are kept)%s",
                      sim->t, granule_of(sim, sim->pulse.next_pass - 1),
                      granule_of(sim, sim->pass_limit), advice(why));
    return status;
}

/* ---- applying the window's decisions ------------------------------------------ */
static void window_changed(taper_sim *sim)
{
    sim->stats.window_changes++;
    size_t size = sim->dyn.hi - sim->dyn.lo + 1;
    if (size > sim->stats.max_window) sim->stats.max_window = size;
    if (sim->cv.mem) CVodeSetMaxNumSteps(sim->cv.mem, steps_per_call(sim));
}

/* Re-initialises CVODE at the current state; the counters so far are kept. */
static taper_status restart(taper_sim *sim, taper_error *err)
{
    if (sim->cv.rk8) { /* a single-step method starts afresh at every step */
        sim->stats.restarts++;
        return TAPER_OK;
    }
    sim->cv.before_restart = total_counters(sim);
    if (CVodeReInit(sim->cv.mem, sim->t, sim->cv.y) != CV_SUCCESS) return stop(sim, err, STOP_RESTART, 0);
    sim->cv.tn_seen = sim->t; /* CVODE's counters start again from 0 */
    sim->cv.nst_seen = 0;
    CVodeSetInitStep(sim->cv.mem, INITIAL_STEP * 1e-2);
    sim->stats.restarts++;
    return TAPER_OK;
}

/* Whether the gap slot's gap, z_{lo-1}, is already at its watch: the root
 * that watches it needs a sign change, and after a take-back starts from
 * the state CVODE has then. */
static int gap_already_closed(const taper_sim *sim)
{
    const size_t lo = sim->dyn.lo;
    if (lo <= 1) return 0;
    const double *y = taper_sim_data(sim, sim->cv.y);
    return y[0] - sim->out.gap_watch[lo - 2] >= 0.0;
}

/* Granule lo-1 returns; and so does every one behind whose gap has closed
 * too by then.  A take-back comes at the end of the step holding its root,
 * and within that step the returning granule may already have closed the
 * next gap: at n = 12 behind a rigid wall the reflected pulse comes back
 * as a Newton's cradle, one granule flying at -1 at a time, and granule 775
 * of 1000, back in the window with its gap to 774 already closed, flew
 * through the resting 774 unseen (a compression of 2157 by t = 3649,
 * energy error 1.7e39). */
static taper_status take_back(taper_sim *sim, taper_error *err)
{
    do {
        if (taper_sim_recall_granule(sim) != 0) return stop(sim, err, STOP_WINDOW_MEMORY, 0);
        window_changed(sim);
        taper_sim_log(sim, 0, "granule %zu rejoins the window at t = %.17g (its gap closed)",
                      granule_of(sim, sim->dyn.lo), sim->t);
    } while (gap_already_closed(sim));
    return restart(sim, err);
}

static taper_status grow(taper_sim *sim, taper_error *err)
{
    const taper_dyn *d = &sim->dyn;
    if (taper_sim_move_window(sim, d->lo, d->hi + 1, d->v_left) != 0)
        return stop(sim, err, STOP_WINDOW_MEMORY, 0);
    window_changed(sim);
    return TAPER_OK;
}

static taper_status shrink(taper_sim *sim, taper_error *err)
{
    const size_t lo = sim->dyn.lo;
    double tn = sim->t, h = 0.0;
    if (sim->cv.rk8) { /* rk8's state is at its time */
        h = taper_rk8_last_step(sim->cv.rk8);
    } else {
        CVodeGetCurrentTime(sim->cv.mem, &tn);
        CVodeGetLastStep(sim->cv.mem, &h);
    }
    taper_status status = TAPER_OK;
    for (taper_departure d; !status && (d = taper_window_departure(sim)).kind != TAPER_STAYS;)
        if (taper_sim_release_granule(sim, d.watch, d.kind == TAPER_LEAVES_AT_REST, tn, h) != 0)
            status = taper_fail(err, TAPER_ENOMEM, "cannot allocate the drag's handovers");
    if (sim->dyn.lo != lo) window_changed(sim);
    return status;
}

/* ---- the piston's stop ------------------------------------------------------ */
/* The piston's velocity jumps from 1 to 0 at t = duration: a discontinuity
 * of the right-hand side that no step may straddle (the error control would
 * smear it over the steps around it).  CVODE stops there exactly
 * (CVodeSetStopTime), the piston's velocity is set to 0 in the state, and
 * CVODE restarts from that state with a fresh history.  The piston never
 * leaves the window while it moves (window.c), so its velocity is always
 * the state's. */
static int piston_stop_pending(const taper_sim *sim)
{
    return sim->piston_moving && isfinite(sim->model.piston_duration);
}

/* The stop time a phase of the run asked for (grace, t_end): kept, so that
 * it can be set again after the piston's stop replaced it. */
static void set_stop_time(taper_sim *sim, double t)
{
    sim->phase_stop = t;
    /* rk8 never steps past the time it is asked for */
    if (!piston_stop_pending(sim) && sim->cv.mem) CVodeSetStopTime(sim->cv.mem, t);
}

static taper_status stop_piston(taper_sim *sim, taper_error *err)
{
    double *y = taper_sim_data(sim, sim->cv.y);
    sim->piston_work = quadrature_entries(sim, sim->cv.y)[TAPER_QUAD_WALL_LEFT];
    taper_events_piston_stopped(sim);
    y[taper_idx_v(1) - taper_dyn_begin(&sim->dyn)] = 0.0; /* lo == 1 (window.c) */
    sim->piston_moving = 0;
    taper_sim_log(sim, 0, "the piston stops at t = %.17g (work done: %.17g)", sim->t,
                  sim->piston_work);
    taper_status status = restart(sim, err);
    /* CVODE 6.4 keeps a reached stop time through CVodeReInit and then
     * refuses to start from it (flag -22): the phase's, or none. */
    if (!status && sim->cv.mem)
        CVodeSetStopTime(sim->cv.mem, sim->phase_stop > sim->t ? sim->phase_stop : NO_TIME_LIMIT);
    return status;
}

/* ---- the run -------------------------------------------------------------- */
static int call_monitor(const taper_sim *sim)
{
    if (!sim->spec.monitor) return 0;
    const size_t N = sim->model.granules;
    const size_t lo = granule_of(sim, sim->dyn.lo), hi = granule_of(sim, sim->dyn.hi);
    taper_progress p = {
        .granule = granule_of(sim, sim->pulse.next_pass - 1),
        .target = granule_of(sim, sim->pass_limit), .t = sim->t,
        .steps = total_counters(sim).steps, .window_lo = lo ? lo : 1,
        .window_hi = hi > N ? N : hi ? hi : 1,
    };
    return sim->spec.monitor(&p, sim->spec.monitor_data);
}

static taper_status handle_roots(taper_sim *sim, taper_error *err)
{
    /* (rk8 has filled the slots' answers already) */
    if (sim->cv.mem && CVodeGetRootInfo(sim->cv.mem, sim->cv.roots) < 0)
        return stop(sim, err, STOP_ROOT_INFO, 0);
    taper_clock_track(sim); /* the step holding the root */
    const taper_root_report report = taper_events_record(sim, sim->cv.roots);
    const taper_window_plan plan = taper_window_plan_for(sim, report);
    taper_status status = TAPER_OK;
    if (plan.take_back) status = take_back(sim, err);
    if (!status && plan.grow) status = grow(sim, err);
    if (!status && taper_events_fit_rings(sim)) status = (taper_status)init_roots(sim, err);
    if (!status && report.passed) {
        if (plan.shrink) status = shrink(sim, err);
        if (!status && call_monitor(sim)) status = stop(sim, err, STOP_INTERRUPTED, 0);
    }
    return status;
}

/* The time after which missing peaks are declared absent. */
/* The longest residence time so far is the scale: in forward chains the
 * last granules are tiny and passed in 1e-3 time units (even out of order),
 * while the train behind keeps pushing them for times of order the first
 * residence times.  Called once per run: O(N) is fine. */
static double grace_time(const taper_sim *sim)
{
    const double *tp = sim->pulse.obs[TAPER_T_PASS];
    double longest = 0.0;
    for (size_t k = 1; k <= sim->pass_limit; k++)
        longest = fmax(longest, tp[k - 1] - (k > 1 ? tp[k - 2] : 0.0));
    return sim->t + PEAK_GRACE * fmax(longest, 1e-3);
}

/* One call of the integrator towards target (never past stop_at),
 * answering in CVODE's flags: CVODE itself (whose stop time is set), or
 * rk8, which returns at target (a state computed inside its step, as
 * CVODE's interpolation), at a root, or after STEPS_PER_CALL steps, its
 * roots' answers already in sim->cv.roots. */
static int integrator_call(taper_sim *sim, double target, double stop_at, double *t)
{
    taper_cvode *cv = &sim->cv;
    if (!cv->rk8) return CVode(cv->mem, target, cv->y, t, CV_NORMAL);
    const size_t slots = taper_events_slots(sim);
    /* The growth root is not located: CVODE too grows the window at the end
     * of the step that holds it (make_state), and rk8 saves the ~5 trial
     * steps a located root costs. */
    const taper_rk8_result r = taper_rk8_advance(cv->rk8, taper_sim_data(sim, cv->y), state_length(sim),
                                                 cv->roots + slots, slots, taper_events_grow_slot(sim),
                                                 cv->roots, target, stop_at, steps_per_call(sim));
    *t = taper_rk8_time(cv->rk8, &cv->t_shift);
    switch (r) {
    case TAPER_RK8_REACHED: return CV_TSTOP_RETURN;
    case TAPER_RK8_ROOT: return CV_ROOT_RETURN;
    case TAPER_RK8_WORK: return CV_TOO_MUCH_WORK;
    case TAPER_RK8_FAILED: break;
    }
    return CV_ERR_FAILURE;
}

/* One call of CVode towards tout, stopping on the way at the next sample
 * time (sample.c) and calling the sampler there.  *reached: CVODE got to
 * tout (or its stop time) itself.  Without a sampler this is the plain
 * call. */
static taper_status advance(taper_sim *sim, double tout, int *reached, taper_error *err)
{
    const double t_sample = taper_sample_next(sim);
    double t = sim->t, target = t_sample < tout ? t_sample : tout;
    const int piston_first = piston_stop_pending(sim) && sim->model.piston_duration <= target;
    if (piston_first) target = sim->model.piston_duration;
    if (piston_stop_pending(sim) && sim->cv.mem) { /* CVODE's stop: the piston's or the phase's, the first */
        double tn = t, stop_at = sim->model.piston_duration;
        CVodeGetCurrentTime(sim->cv.mem, &tn);
        if (sim->phase_stop > tn && sim->phase_stop < stop_at) stop_at = sim->phase_stop;
        CVodeSetStopTime(sim->cv.mem, stop_at);
    }
    /* rk8's stop: the piston's, or the phase's end (tout) */
    const double stop_at = piston_stop_pending(sim) && sim->model.piston_duration < tout
                               ? sim->model.piston_duration : tout;
    int flag = integrator_call(sim, target, stop_at, &t);
    sim->t = t;
    *reached = 0;
    if (piston_first && (flag == CV_SUCCESS || flag == CV_TSTOP_RETURN) && t >= target) {
        taper_status status = stop_piston(sim, err);
        /* a sample or tout at the stop time: served below, from the
         * stopped state (CVODE would refuse a call for tout = t now) */
        if (status != TAPER_OK || (t < t_sample && t < tout)) return status;
    }
    if (flag == CV_ROOT_RETURN) return handle_roots(sim, err);
    if (flag == CV_TOO_MUCH_WORK) {
        if (call_monitor(sim)) return stop(sim, err, STOP_INTERRUPTED, 0);
        return TAPER_OK;
    }
    if (flag == CV_SUCCESS || flag == CV_TSTOP_RETURN) {
        /* after a sample the monitor too: a sampled run past the pulse
         * has no events, and its calls end at samples, not at the steps'
         * limit */
        if (t >= t_sample && (taper_sample_call(sim) || call_monitor(sim)))
            return stop(sim, err, STOP_INTERRUPTED, 0);
        *reached = t >= tout; /* a stop time of an earlier phase is no arrival */
        return TAPER_OK;
    }
    return stop(sim, err, STOP_SOLVER, flag);
}

static taper_status step_once(taper_sim *sim, double tout, int grace, taper_error *err)
{
    int reached;
    taper_status status = advance(sim, tout, &reached, err);
    if (status != TAPER_OK || !reached) return status;
    if (grace) return TAPER_OK; /* remaining peaks do not exist */
    return stop(sim, err, sim->spec.t_max > 0.0 ? STOP_T_MAX : STOP_END_OF_TIME, 0);
}

/* After the observables: on to t_end (taper_solver_spec_set_t_end), within
 * t_max. */
static taper_status continue_to_end(taper_sim *sim, taper_error *err)
{
    const double t_end = sim->spec.t_end;
    if (!(t_end > sim->t)) return TAPER_OK;
    const double limit = sim->spec.t_max > 0.0 ? sim->spec.t_max : NO_TIME_LIMIT;
    const double tout = t_end < limit ? t_end : limit;
    /* CVODE may have stepped past tout already (the last root lay inside
     * its step): it then interpolates, and a stop time behind it would be
     * refused. */
    double tn = sim->t;
    if (sim->cv.mem) CVodeGetCurrentTime(sim->cv.mem, &tn);
    if (tout > tn) set_stop_time(sim, tout);
    for (int reached = 0; !reached;) {
        if (sim->spec.max_steps > 0 && total_counters(sim).steps >= sim->spec.max_steps)
            return stop(sim, err, STOP_MAX_STEPS, 0);
        taper_status status = advance(sim, tout, &reached, err);
        if (status != TAPER_OK) return status;
    }
    return tout < t_end ? stop(sim, err, STOP_T_MAX, 0) : TAPER_OK;
}

/* Drag takes momentum out of the chain (contact forces and damping only
 * move it along), so a pulse under strong drag dies into an overdamped
 * front that creeps on ever slower, and the passes still to come come ever
 * later, of motion below what the tolerance resolves (a monodisperse chain
 * of 100 at drag 100: every granule at rest within rtol by t = 1.85e6,
 * 28 passed; the front, followed on with BDF, passed granule 99 at
 * t = 4.1e7; Adams had passed 11 by t = 1.2e5 after 1.6e7 steps).  The
 * pulse is absorbed once every body moves slower than one unit of the
 * tolerance at the impulse's velocity, rtol v_1 + atol v_scale (v_1 = 1,
 * the impulse, striker or piston velocity of eq. (5)'s units): the run
 * ends there, complete, the passes it never reached NaN, and the log says
 * so.  Bodies ahead of the window never moved; those behind it fly under
 * drag and slow down on their own, and sim.c keeps the time after which
 * every one of them is that slow (quiet_after). */
static int absorbed_by_drag(const taper_sim *sim)
{
    if (!(sim->model.drag > 0.0) || sim->piston_moving || sim->t < sim->out.quiet_after) return 0;
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_data(sim, sim->cv.y);
    /* from the front, where the pulse is: a moving run answers at once */
    for (size_t k = d->hi; k >= d->lo; k--)
        if (fabs(taper_dyn_v(d, y, k)) > sim->spec.rtol + sim->spec.atol * sim->v_scale[k - 1]) return 0;
    return 1;
}

/* The longest residence time so far (at least 1e-3): the time scale on
 * which the pulse makes progress. */
/* A pulse can leave the chain before it has passed every granule: a heavy
 * granule sends it back, or damping absorbs it, and the passes still to
 * come are of motion below what the tolerance resolves (a chain of radii 1,
 * 1e-3, 1e3, 1e-3, 1e3, 1 reflects all but 2e-9 of the energy at granule
 * 3, then the light granule 4 rattles between the heavy ones for ever).
 * The budget's "in chain" is the energy that can still be exchanged
 * (budget.c): once it is below rtol E(0), nothing the run resolves is left
 * to happen.  Checked only when the run has stalled, PEAK_GRACE longest
 * residence times without a pass: the budget walks the whole chain. */
typedef struct progress_watch {
    size_t next_pass;  /* passes seen so far                          */
    double longest;    /* the longest residence time among them       */
    double since, interval;
} progress_watch;

/* The longest residence time so far, kept as a running maximum over the
 * passes found since the last look (a rescan of every pass at each new one
 * would cost O(N^2) on a long chain). */
static void watch_passes(const taper_sim *sim, progress_watch *w)
{
    const double *tp = sim->pulse.obs[TAPER_T_PASS];
    for (size_t k = w->next_pass > 1 ? w->next_pass : 1;
         k < sim->pulse.next_pass && k <= sim->pass_limit; k++)
        if (isfinite(tp[k - 1]))
            w->longest = fmax(w->longest,
                              tp[k - 1] - (k > 1 && isfinite(tp[k - 2]) ? tp[k - 2] : 0.0));
    w->next_pass = sim->pulse.next_pass;
    w->since = sim->t;
    w->interval = PEAK_GRACE * w->longest;
}

static int pulse_has_left(taper_sim *sim, progress_watch *w)
{
    if (sim->pulse.next_pass != w->next_pass) {
        watch_passes(sim, w);
        return 0;
    }
    if (sim->t - w->since < w->interval) return 0;
    w->since = sim->t; /* the next look after another interval */
    taper_budget_compute(sim, quadratures_now(sim));
    const double left = sim->stats.energy_in_chain, e0 = sim->stats.energy_initial;
    return isfinite(left) && left <= sim->spec.rtol * e0;
}

static taper_status integrate(taper_sim *sim, taper_error *err)
{
    double tout = sim->spec.t_max > 0.0 ? sim->spec.t_max : NO_TIME_LIMIT;
    int grace = 0, absorbed = 0, left = 0;
    progress_watch watch = {.next_pass = 0, .longest = 1e-3};
    watch_passes(sim, &watch);
    while (!taper_events_complete(sim) || !taper_events_walls_settled(sim)) {
        if (sim->spec.max_steps > 0 && total_counters(sim).steps >= sim->spec.max_steps)
            return stop(sim, err, STOP_MAX_STEPS, 0);
        if (!grace && taper_events_passes_complete(sim)) {
            grace = 1;
            double tg = grace_time(sim);
            if (tg < tout) tout = tg;
            set_stop_time(sim, tout);
        }
        double t_before = sim->t;
        taper_status status = step_once(sim, tout, grace, err);
        if (status != TAPER_OK) return status;
        if (grace && sim->t >= tout && sim->t > t_before) break;
        if ((absorbed = absorbed_by_drag(sim))) break;
        if ((left = pulse_has_left(sim, &watch))) break;
    }
    const size_t next_peak = sim->pulse.next_peak;
    if (!taper_events_walls_settled(sim)) /* the grace time ended it (a steady piston) */
        taper_sim_log(sim, 1,
                      "the right wall still pushes at t = %.6g, %g times the longest residence "
                      "time after the last pass: its peak force, time and impulse are those of "
                      "the run so far, not of its whole contact",
                      sim->t, PEAK_GRACE);
    if (left) {
        const size_t next_pass = sim->pulse.next_pass;
        taper_sim_log(sim, 1,
                      "the pulse has left the chain: at t = %.6g the energy that can still be "
                      "exchanged is %.2g of the initial, below rtol (%.1e): reflected %.6g, "
                      "transmitted %.6g; from granule %zu on no pass and from granule %zu on "
                      "no velocity maximum (nan)",
                      sim->t, sim->stats.energy_in_chain / sim->stats.energy_initial,
                      sim->spec.rtol, sim->stats.energy_reflected, sim->stats.energy_transmitted,
                      granule_of(sim, next_pass <= sim->pass_limit ? next_pass : sim->pass_limit + 1),
                      granule_of(sim, next_peak));
    } else if (absorbed) {
        const size_t next_pass = sim->pulse.next_pass;
        taper_sim_log(sim, 1,
                      "the pulse was absorbed by drag: at t = %.6g every granule moves slower than "
                      "rtol + atol v_scale (%.1e of the impulse's velocity); from granule %zu on "
                      "no pass and from granule %zu on no velocity maximum (nan)",
                      sim->t, sim->spec.rtol,
                      granule_of(sim, next_pass <= sim->pass_limit ? next_pass : sim->pass_limit + 1),
                      granule_of(sim, next_peak));
    } else if (next_peak <= sim->target) {
        size_t missing = 0;
        for (size_t k = next_peak; k <= sim->target; k++)
            missing += isnan(sim->pulse.obs[TAPER_T_PEAK][k - 1]);
        taper_sim_log(sim, 1,
                      "%zu of granules %zu..%zu reached no forward velocity maximum within %g "
                      "times the longest residence time after the last pass (the run ended at "
                      "t = %.6g): their v_peak is nan",
                      missing, granule_of(sim, next_peak), granule_of(sim, sim->target),
                      PEAK_GRACE, sim->t);
    }
    taper_status status = continue_to_end(sim, err);
    /* A wall the pulse never reached has no peak: said, never 0. */
    static const char *const sides[TAPER_N_ENDS] = {"left", "right"};
    for (int e = 0; status == TAPER_OK && e < TAPER_N_ENDS; e++) {
        const int wall = e == TAPER_LEFT ? sim->model.wall_left && !sim->model.piston
                                         : sim->model.wall_right;
        if (wall && isnan(sim->walls.peak_force[e]))
            taper_sim_log(sim, 1,
                          "the %s wall felt no force before the run ended at t = %.6g: its peak "
                          "force and time are nan (give t_end to follow the pulse there)",
                          sides[e], sim->t);
    }
    return status;
}

/* Smallest residence time, relative to t_pass, that the pass times resolve.
 * CVODE locates a root to within 100 uround (|t| + |h|) (cvRootfind's
 * ttol), whatever rtol, so a difference of two pass times carries up to
 * 200 uround t_pass of root-finding error; T_res is kept while that is
 * below 1 % of it.  The integration error of T_res is relative to T_res
 * itself, not to t_pass: both pass times share the error accumulated
 * before them.  Measured (docs/design.md): forward exponential q = 0.05,
 * N = 1000, against rtol 1e-13, the T_res error is ~1e-14 t_pass / T_res
 * (7e-4 at T_res ~ 1e-12 t_pass); monodisperse at rtol 1e-6 to N = 20000,
 * T_res ~ 6e-5 t_pass is good to 7e-5 (twice the t_pass error). */
#define PASS_TIME_RESOLUTION (2e4 * DBL_EPSILON)

/* Residence times T_res(k) = t_pass(k) - t_pass(k-1), NaN where they are
 * not a residence: below the pass times' resolution (the last, tiny
 * granules of forward chains are passed within 1e-15 t of each other: a
 * difference that is noise), or negative, where
 * granule k is passed before granule k-1 (below n = 2 the precursor moves
 * the chain's end as a block and its last granule may be passed first; the
 * light end of a steep forward taper, small granules of decorated and mixed
 * chains too).  A negative "residence" would
 * read as a measurement (it did, in a partial file).  The counts
 * go to the log (report_untimed). */
typedef struct residence_report {
    size_t unresolved, out_of_order;
    size_t first_out_of_order;  /* granule, 0: none */
} residence_report;

static residence_report residence_times(taper_sim *sim)
{
    /* granule k of the chain: t_pass(0) = 0 even after a striker */
    const double *tp = sim->pulse.obs[TAPER_T_PASS] + sim->model.off;
    double *tr = sim->pulse.obs[TAPER_T_RES] + sim->model.off;
    residence_report r = {0, 0, 0};
    for (size_t k = 1; k <= sim->model.granules; k++) {
        double before = k > 1 ? tp[k - 2] : 0.0, T = tp[k - 1] - before;
        if (fabs(T) < PASS_TIME_RESOLUTION * fabs(tp[k - 1])) {
            T = NAN;
            r.unresolved++;
        } else if (T < 0.0) {
            T = NAN;
            if (!r.out_of_order++) r.first_out_of_order = k;
        }
        tr[k - 1] = T;
    }
    return r;
}

/* What the caller's log should know about values left NaN on purpose. */
static void report_untimed(const taper_sim *sim, residence_report residences)
{
    const size_t passes = sim->pulse.untimed_passes, peaks = sim->pulse.untimed_peaks;
    if (passes || peaks)
        taper_sim_log(sim, 1,
                      "%zu pass time%s and %zu peak%s happened before their root functions "
                      "were armed (light granules overtaking in the precursor of a steeply "
                      "tapered chain): written as nan, not guessed",
                      passes, passes == 1 ? "" : "s", peaks, peaks == 1 ? "" : "s");
    if (residences.unresolved)
        taper_sim_log(sim, 1,
                      "%zu residence time%s below the resolution of the pass times "
                      "(%.1e t, set by CVODE's root finder): written as nan",
                      residences.unresolved, residences.unresolved == 1 ? " is" : "s are",
                      PASS_TIME_RESOLUTION);
    if (residences.out_of_order)
        taper_sim_log(sim, 1,
                      "%zu granule%s passed before the granule ahead of %s (first: "
                      "granule %zu): the pulse is no longer a sequence of passes there "
                      "(light granules overtaken within the pulse: small granules of a "
                      "decorated or mixed chain, the precursor below n = 2, the light end of "
                      "a steep forward taper); their residence times are written as nan, "
                      "their pass times kept",
                      residences.out_of_order, residences.out_of_order == 1 ? " was" : "s were",
                      residences.out_of_order == 1 ? "it" : "them", residences.first_out_of_order);
}

/* Energy error beyond which the caller is told that the far end of the
 * chain is not what the tolerance suggests.  The error of a long run is a
 * drift, not noise: the energy error grows with the granules crossed, and
 * the pulse's amplitude and speed follow it (monodisperse, 10^6 granules:
 * v_peak off by half the energy error at the end, t_pass by a twentieth;
 * docs/benchmarks.md, "Long chains at looser tolerances"). */
#define ENERGY_DRIFT_WARNING 1e-3

static void warn_of_drift(const taper_sim *sim)
{
    const double e = sim->stats.energy_error;
    if (e > ENERGY_DRIFT_WARNING)
        taper_sim_log(sim, 1,
                      "energy error %.1e at t = %.6g: the integration has drifted, and values far "
                      "along the chain carry errors up to that size (v_peak about half of it); "
                      "a smaller rtol reduces it",
                      e, sim->stats.t_final);
}

static void finish(taper_sim *sim, taper_status status)
{
    report_untimed(sim, residence_times(sim));
    taper_run_statistics *s = &sim->stats;
    s->cvode = total_counters(sim);
    s->granule_reached = granule_of(sim, sim->pulse.next_pass - 1); /* a granule, not a body */
    s->t_final = sim->t;
    s->complete = status == TAPER_OK;
    const taper_dyn *d = &sim->dyn;
    const double *y = sim->cv.y ? taper_sim_data(sim, sim->cv.y) : NULL;
    double e = 0.0, p = 0.0, p_abs = 0.0;
    if (y) taper_dyn_energy_momentum(d, y, &e, &p);
    e += sim->out.energy_free;
    p += sim->out.momentum_free;
    for (size_t k = 1; y && k <= sim->n; k++) {
        double v = 0.0;
        if (k < d->lo) taper_sim_flight(sim, k, sim->t, NULL, &v);
        else if (k <= d->hi) v = taper_dyn_v(d, y, k);
        p_abs += sim->mass[k - 1] * fabs(v);
    }
    /* (a piston's run: budget.c replaces both with the work's balance) */
    const double m0 = sim->mass[sim->model.impulse - 1], e0 = 0.5 * m0, p0 = m0;
    s->energy_error = fabs(e - e0) / e0;
    /* Relative to the momentum in motion: in backward chains granules carry
     * momenta far above P0 in opposite directions. */
    s->momentum_error = fabs(p - p0) / fmax(p0, p_abs);
    taper_budget_compute(sim, quadratures_now(sim));
    warn_of_drift(sim);
}

taper_status taper_sim_run(taper_sim *sim, taper_error *err)
{
    if (!sim) return taper_fail(err, TAPER_EINVAL, "taper_sim_run: sim is NULL");
    if (sim->ran) return taper_fail(err, TAPER_EINVAL, "taper_sim_run: this sim has already run");
    sim->ran = 1;
    sim->piston_moving = sim->model.piston;
    sim->phase_stop = 0.0;
    taper_status status = setup_integrator(sim, err);
    /* the sampler's first call: the initial state, t = 0 */
    if (status == TAPER_OK && taper_sample_next(sim) == 0.0 && taper_sample_call(sim))
        status = stop(sim, err, STOP_INTERRUPTED, 0);
    if (status == TAPER_OK) status = integrate(sim, err);
    finish(sim, status);
    if (status == TAPER_OK) taper_ok(err);
    return status;
}
