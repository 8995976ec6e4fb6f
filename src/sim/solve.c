/*
 * solve.c -- the simulation object: CVODE set-up, the run loop that hands
 * root returns to events.c and window.c, and the results.
 *
 * The run starts from the impulse (v_1 = 1, everything else at rest and just
 * touching) and ends by itself as soon as every requested observable is
 * known, never at a guessed end time.
 */
#include "sim.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Internal steps per CVode call: the monitor (progress, Ctrl-C) is consulted
 * at least this often.  CVODE's default of 500 would end long chains. */
#define STEPS_PER_CALL 20000L
/* Once every pass time is known, how long (in units of the longest
 * residence time) to wait for the remaining peaks before declaring them
 * absent. */
#define PEAK_GRACE 20.0
#define INITIAL_STEP 1e-4
/* The end of time when no t_max is given (pass times of exponential chains
 * grow like e^{eta k}: 1e30 is reached within a few hundred granules). */
#define NO_TIME_LIMIT 1e300

void taper_solver_spec_init(taper_solver_spec *spec)
{
    if (!spec) return;
    memset(spec, 0, sizeof *spec);
    spec->method = TAPER_ADAMS;
    /* Measured (docs/design.md, "Defaults"): with atol relative to each
     * granule's binary-collision scale, t_pass and v_peak stay within 1.2e-9
     * and 6.7e-9 of a rtol = 1e-13 reference on the five paper profiles up to
     * N = 1000: an 8x margin on the 1e-8 / 1e-7 targets. */
    spec->rtol = 1e-10;
    spec->atol = 1e-13;
    spec->last_granule = 0;
    spec->window = 1;
}

double *taper_sim_data(const taper_sim *sim, N_Vector v)
{
    return sim->window ? taper_window_data(v) : N_VGetArrayPointer(v);
}

/* ---- allocation ------------------------------------------------------ */
static int validate_spec(const taper_chain *chain, const taper_solver_spec *s, taper_error *err)
{
    if (s->method != TAPER_ADAMS && s->method != TAPER_BDF)
        return taper_fail(err, TAPER_EINVAL, "method = %d: use TAPER_ADAMS or TAPER_BDF", s->method);
    if (!(s->rtol > 0.0 && s->rtol < 1.0))
        return taper_fail(err, TAPER_EINVAL, "rtol = %g: must lie in (0, 1)", s->rtol);
    if (s->rtol < 10.0 * DBL_EPSILON)
        return taper_fail(err, TAPER_EINVAL, "rtol = %g is below what double precision resolves "
                          "(use rtol >= %g)", s->rtol, 10.0 * DBL_EPSILON);
    if (!(s->atol > 0.0 && s->atol < 1.0))
        return taper_fail(err, TAPER_EINVAL, "atol = %g: must lie in (0, 1)", s->atol);
    if (s->last_granule > chain->n)
        return taper_fail(err, TAPER_EINVAL, "last_granule = %zu exceeds n_granules = %zu",
                          s->last_granule, chain->n);
    if (s->max_order < 0 || s->max_order > (s->method == TAPER_BDF ? 5 : 12))
        return taper_fail(err, TAPER_EINVAL, "max_order = %d: CVODE allows 1..%d for this method "
                          "(0: default)", s->max_order, s->method == TAPER_BDF ? 5 : 12);
    if (!(s->t_max >= 0.0) || s->max_steps < 0)
        return taper_fail(err, TAPER_EINVAL, "t_max and max_steps must be >= 0 (0: no limit)");
    return TAPER_OK;
}

/* z_k at which granule k+1 joins the window (k = hi).  Two bounds on the
 * neglected force r_k z^(n-1), the smaller threshold wins:
 *  - over the collision: z below a fraction f of the contact's compression
 *    scale z_scale (the binary-collision z_max), f^(n-1) = 1e-40, so over
 *    the collision time the force changes the velocity of granule k+1 by
 *    1e-40 of its binary-collision velocity.  Mass and time scales cancel.
 *    A per-unit-time bound alone fails on long time scales: a backward
 *    exponential chain (q = 0.05) runs at t ~ 1e40 by granule 1300, granules
 *    were pushed unseen and energy was created (energy error 6e3 at
 *    N = 2000; tests/unit/test_window.c, long_backward_exponential).
 *  - per unit time: the force changes the velocity of the lighter of k, k+1
 *    by less than 1e-40 of its binary-collision velocity per unit time.  On
 *    steep forward chains, whose tiny last granules are struck on short
 *    times by a train far from binary collisions, this bound is the smaller
 *    one; joining later there lets the last granule peak within the step
 *    that arms its peak slot (forward exponential q = 0.05, N = 150).
 * The floor keeps root values clear of underflow (exponents n < 1.4). */
static void growth_thresholds(taper_sim *sim)
{
    const taper_chain *c = sim->chain;
    const double power = 1.0 / (c->exponent - 1.0);
    const double fraction = fmax(pow(1e-40, power), 1e-200);
    for (size_t k = 1; k < c->n; k++) {
        double m = fmin(c->mass[k - 1], c->mass[k]);
        double v = fmin(sim->v_scale[k - 1], sim->v_scale[k]);
        double per_time = pow(1e-40 * m * v / c->contact[k - 1], power);
        double per_collision = fraction * sim->z_scale[k - 1];
        sim->grow_z[k - 1] = fmax(fmin(per_time, per_collision), 1e-290);
    }
    sim->grow_z[c->n - 1] = INFINITY; /* nothing beyond the last granule */
}

static int alloc_arrays(taper_sim *sim)
{
    size_t n = sim->chain->n;
    for (int i = 0; i < TAPER_N_OBSERVABLES; i++) {
        sim->obs[i] = malloc(n * sizeof(double));
        if (!sim->obs[i]) return -1;
        for (size_t k = 0; k < n; k++) sim->obs[i][k] = NAN;
    }
    sim->x_free = calloc(n, sizeof(double));
    sim->v_free = calloc(n, sizeof(double));
    sim->gap_watch = calloc(n, sizeof(double));
    sim->grow_z = malloc(n * sizeof(double));
    sim->events = calloc(n, 1);
    if (!sim->grow_z || !sim->events) return -1;
    sim->v_scale = malloc(n * sizeof(double));
    sim->z_scale = malloc(n * sizeof(double));
    if (!sim->x_free || !sim->v_free || !sim->gap_watch || !sim->v_scale || !sim->z_scale) return -1;
    return taper_dyn_init(&sim->dyn, n, sim->chain->exponent, sim->chain->mass, sim->chain->contact);
}

/* Velocity and compression scales of granule k from the binary collision
 * approximation: v_k (eq. recv) and z_max = (n mu_k / (2 r_k) v_k^2)^(1/n)
 * (the maximum compression of the collision k, k+1).  Floored so that
 * weights stay finite. */
static int tolerance_scales(taper_sim *sim, taper_error *err)
{
    const taper_chain *c = sim->chain;
    const size_t n = c->n;
    double *mu = malloc(n * sizeof(double));
    if (!mu) return taper_fail(err, TAPER_ENOMEM, "cannot allocate tolerance scales");
    int status = taper_theory_compute(c, sim->v_scale, mu, NULL, NULL, err);
    for (size_t k = 1; status == TAPER_OK && k <= n; k++) {
        size_t j = k < n ? k : n - 1; /* z_N = x_N: scale of the last contact */
        double v = sim->v_scale[j - 1];
        double z = pow(c->exponent * mu[j - 1] / (2.0 * c->contact[j - 1]) * v * v, 1.0 / c->exponent);
        sim->v_scale[k - 1] = fmax(sim->v_scale[k - 1], 1e-280);
        sim->z_scale[k - 1] = isfinite(z) ? fmax(z, 1e-280) : 1.0;
    }
    free(mu);
    return status;
}

taper_sim *taper_sim_alloc(const taper_chain *chain, const taper_solver_spec *spec, taper_error *err)
{
    taper_solver_spec defaults;
    if (!chain) {
        taper_fail(err, TAPER_EINVAL, "taper_sim_alloc: chain is NULL");
        return NULL;
    }
    if (!spec) {
        taper_solver_spec_init(&defaults);
        spec = &defaults;
    }
    if (validate_spec(chain, spec, err) != TAPER_OK) return NULL;
    taper_sim *sim = calloc(1, sizeof *sim);
    if (!sim) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the simulation");
        return NULL;
    }
    sim->chain = chain;
    sim->spec = *spec;
    if (alloc_arrays(sim) != 0) {
        taper_sim_free(sim);
        taper_fail(err, TAPER_ENOMEM, "cannot allocate results for %zu granules", chain->n);
        return NULL;
    }
    if (tolerance_scales(sim, err) != TAPER_OK) {
        taper_sim_free(sim);
        return NULL;
    }
    sim->target = spec->last_granule ? spec->last_granule : chain->n;
    sim->pass_limit = sim->target < chain->n ? sim->target : chain->n - 1;
    sim->next_pass = 1;
    sim->next_peak = 2;
    sim->obs[TAPER_V_PEAK][0] = 1.0; /* the impulse itself */
    sim->obs[TAPER_T_PEAK][0] = 0.0;
    sim->v_ref = 1.0;
    sim->z_ref = 1.0;
    growth_thresholds(sim);
    sim->events[0] |= TAPER_EV_PEAK;
    taper_ok(err);
    return sim;
}

void taper_sim_free(taper_sim *sim)
{
    if (!sim) return;
    if (sim->cvode) CVodeFree(&sim->cvode);
    if (sim->nonlinear) SUNNonlinSolFree(sim->nonlinear);
    if (sim->linear) SUNLinSolFree(sim->linear);
    if (sim->band) SUNMatDestroy(sim->band);
    if (sim->y) N_VDestroy(sim->y);
    taper_window_free(sim->window);
    taper_sundials_context_free(&sim->ctx);
    taper_dyn_release(&sim->dyn);
    for (int i = 0; i < TAPER_N_OBSERVABLES; i++) free(sim->obs[i]);
    free(sim->x_free);
    free(sim->v_free);
    free(sim->gap_watch);
    free(sim->grow_z);
    free(sim->events);
    free(sim->v_scale);
    free(sim->z_scale);
    free(sim);
}

/* ---- CVODE callbacks --------------------------------------------------- */
static int rhs(double t, N_Vector y, N_Vector ydot, void *user)
{
    (void)t;
    const taper_sim *sim = user;
    taper_dyn_rhs(&sim->dyn, taper_sim_data(sim, y), taper_sim_data(sim, ydot));
    return 0;
}

/* Banded analytic Jacobian (BDF, whole chain): d(v_k')/dz = +-F'(z)/m_k,
 * d(z_k')/dv = +-1.  The interleaved layout makes it tridiagonal. */
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
    return 0;
}

/* Error weights 1 / (rtol |y_i| + atol scale_i) over the window, the scale
 * being the granule's pulse velocity or maximum compression (see sim.h). */
static int error_weights(N_Vector yv, N_Vector wv, void *user)
{
    const taper_sim *sim = user;
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_data(sim, yv);
    double *w = taper_sim_data(sim, wv);
    const double rtol = sim->spec.rtol, atol = sim->spec.atol;
    size_t i = 0;
    if (d->lo > 1) { /* the gap behind the window */
        w[0] = 1.0 / (rtol * fabs(y[0]) + atol * sim->z_scale[d->lo - 2]);
        i = 1;
    }
    for (size_t k = d->lo; k <= d->hi; k++, i += 2) {
        w[i] = 1.0 / (rtol * fabs(y[i]) + atol * sim->v_scale[k - 1]);
        w[i + 1] = 1.0 / (rtol * fabs(y[i + 1]) + atol * sim->z_scale[k - 1]);
    }
    return 0;
}

void taper_sim_log(const taper_sim *sim, int level, const char *fmt, ...)
{
    if (!sim->spec.log) return;
    char text[TAPER_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    sim->spec.log(level, text, sim->spec.log_data);
}

/* CVODE's errors and warnings: kept for the error message of a failed run
 * and passed on to the caller's log. */
static void keep_solver_message(const char *message, void *user)
{
    taper_sim *sim = user;
    strncpy(sim->solver_message, message, sizeof sim->solver_message - 1);
    taper_sim_log(sim, 1, "%s", message);
}

/* ---- set-up ------------------------------------------------------------ */
static int make_state(taper_sim *sim)
{
    taper_dyn *d = &sim->dyn;
    if (sim->spec.window && sim->spec.method == TAPER_ADAMS) {
        d->lo = d->hi = 1; /* only granule 1 moves; contact (1,2) joins at once */
        sim->window = taper_window_alloc(0, 2, 64);
        if (!sim->window) return -1;
        sim->y = taper_window_vector_new(sim->window, sim->ctx);
    } else {
        d->lo = 1;
        d->hi = d->n;
        sim->y = N_VNew_Serial((sunindextype)(2 * d->n), sim->ctx);
        if (sim->y) N_VConst(0.0, sim->y);
    }
    if (!sim->y) return -1;
    sim->stats.max_window = d->hi - d->lo + 1;
    taper_sim_data(sim, sim->y)[0] = 1.0; /* v_1 = 1: the impulse */
    return 0;
}

static int check(int flag, const char *what, taper_sim *sim, taper_error *err)
{
    if (flag >= 0) return TAPER_OK;
    return taper_fail(err, TAPER_ESOLVER, "CVODE set-up failed in %s (flag %d): %s", what, flag,
                      sim->solver_message);
}

static int attach_solvers(taper_sim *sim, taper_error *err)
{
    void *cv = sim->cvode;
    if (sim->spec.method == TAPER_ADAMS) {
        /* Non-stiff: fixed-point iteration needs no Jacobian at all. */
        sim->nonlinear = SUNNonlinSol_FixedPoint(sim->y, 0, sim->ctx);
        if (!sim->nonlinear) return taper_fail(err, TAPER_ENOMEM, "cannot create the fixed-point solver");
        return check(CVodeSetNonlinearSolver(cv, sim->nonlinear), "CVodeSetNonlinearSolver", sim, err);
    }
    sunindextype n = (sunindextype)(2 * sim->dyn.n);
    sim->band = SUNBandMatrix(n, 1, 1, sim->ctx);
    if (!sim->band) return taper_fail(err, TAPER_ENOMEM, "cannot create the band matrix");
    sim->linear = SUNLinSol_Band(sim->y, sim->band, sim->ctx);
    if (!sim->linear) return taper_fail(err, TAPER_ENOMEM, "cannot create the band solver");
    int status = check(CVodeSetLinearSolver(cv, sim->linear, sim->band), "CVodeSetLinearSolver", sim, err);
    if (status != TAPER_OK) return status;
    return check(CVodeSetJacFn(cv, jacobian), "CVodeSetJacFn", sim, err);
}

static int setup_cvode(taper_sim *sim, taper_error *err)
{
    if (taper_sundials_context_new(&sim->ctx) != 0)
        return taper_fail(err, TAPER_ENOMEM, "cannot create the SUNDIALS context");
    if (make_state(sim) != 0) return taper_fail(err, TAPER_ENOMEM, "cannot allocate the state");
    sim->cvode = CVodeCreate(sim->spec.method == TAPER_BDF ? CV_BDF : CV_ADAMS, sim->ctx);
    if (!sim->cvode) return taper_fail(err, TAPER_ENOMEM, "cannot create CVODE");
    void *cv = sim->cvode;
    sim->messages.fn = keep_solver_message;
    sim->messages.user = sim;
    int directions[TAPER_N_SLOTS];
    taper_events_directions(directions);
    int status = TAPER_OK;
    if (!status) status = check(taper_sundials_capture_errors(cv, &sim->messages), "error handler", sim, err);
    if (!status) status = check(CVodeInit(cv, rhs, 0.0, sim->y), "CVodeInit", sim, err);
    if (!status) status = check(CVodeWFtolerances(cv, error_weights), "CVodeWFtolerances", sim, err);
    if (!status) status = check(CVodeSetUserData(cv, sim), "CVodeSetUserData", sim, err);
    if (!status) status = check(CVodeSetMaxNumSteps(cv, STEPS_PER_CALL), "CVodeSetMaxNumSteps", sim, err);
    /* An explicit first step: CVODE's estimate would use the (unbounded) tout. */
    if (!status) status = check(CVodeSetInitStep(cv, INITIAL_STEP), "CVodeSetInitStep", sim, err);
    if (!status) status = check(CVodeRootInit(cv, TAPER_N_SLOTS, taper_events_root_function), "CVodeRootInit", sim, err);
    if (!status) status = check(CVodeSetRootDirection(cv, directions), "CVodeSetRootDirection", sim, err);
    if (!status) status = check(CVodeSetNoInactiveRootWarn(cv), "CVodeSetNoInactiveRootWarn", sim, err);
    /* "t + h = t": the pulse of a steep forward chain crosses its last,
     * lightest granules faster than double precision resolves t (finding C,
     * docs/robustness.md; the affected values end up nan and are counted in
     * the log).  Once says it; CVODE's default repeated it ten times. */
    if (!status) status = check(CVodeSetMaxHnilWarns(cv, 1), "CVodeSetMaxHnilWarns", sim, err);
    /* Adams above order 6 buys few steps here (the force is only C^1 at
     * contact onset) and each step costs O(q^2) vector operations. */
    int order = sim->spec.max_order ? sim->spec.max_order : (sim->spec.method == TAPER_ADAMS ? 6 : 5);
    if (!status) status = check(CVodeSetMaxOrd(cv, order), "CVodeSetMaxOrd", sim, err);
    if (!status) status = attach_solvers(sim, err);
    return status;
}

/* ---- counters ------------------------------------------------------------ */
static void read_counters(const taper_sim *sim, long c[6])
{
    long v = 0;
    memset(c, 0, 6 * sizeof(long));
    if (!sim->cvode) return;
    CVodeGetNumSteps(sim->cvode, &v), c[0] = v;
    CVodeGetNumRhsEvals(sim->cvode, &v), c[1] = v;
    CVodeGetNumGEvals(sim->cvode, &v), c[2] = v;
    if (sim->linear) CVodeGetNumJacEvals(sim->cvode, &v), c[3] = v;
    CVodeGetNumNonlinSolvIters(sim->cvode, &v), c[4] = v;
    CVodeGetNumErrTestFails(sim->cvode, &v), c[5] = v;
}

static long total_steps(const taper_sim *sim)
{
    long c[6];
    read_counters(sim, c);
    return c[0] + sim->counters_before_restart[0];
}

int taper_solver_restart(taper_sim *sim, taper_error *err)
{
    long c[6];
    read_counters(sim, c);
    for (int i = 0; i < 6; i++) sim->counters_before_restart[i] += c[i];
    if (CVodeReInit(sim->cvode, sim->t, sim->y) != CV_SUCCESS)
        return taper_fail(err, TAPER_ESOLVER, "cannot restart CVODE at t = %.17g: %s", sim->t,
                          sim->solver_message);
    CVodeSetInitStep(sim->cvode, INITIAL_STEP * 1e-2);
    sim->stats.restarts++;
    return TAPER_OK;
}

/* ---- the run -------------------------------------------------------------- */
static int call_monitor(taper_sim *sim)
{
    if (!sim->spec.monitor) return 0;
    taper_progress p = {
        .granule = sim->next_pass - 1, .target = sim->pass_limit, .t = sim->t,
        .steps = total_steps(sim), .window_lo = sim->dyn.lo, .window_hi = sim->dyn.hi,
    };
    return sim->spec.monitor(&p, sim->spec.monitor_data);
}

/* What a user can change when a run stops early. */
static const char *advice(int status, const char *why)
{
    if (status == TAPER_EINTERRUPTED) return "";
    if (strstr(why, "max_steps")) return "; raise max_steps (0: no limit)";
    if (strstr(why, "1e300"))
        return "; the pulse cannot cross this chain in finite double-precision time: fewer "
               "granules or a weaker taper";
    if (strstr(why, "t_max")) return "; raise t_max (0: no limit)";
    return "; try a looser rtol, method 'bdf' (strongly forward-tapered chains, whose lightest "
           "granules collide on tiny time scales), or fewer granules";
}

static int stop(taper_sim *sim, taper_error *err, int status, const char *why)
{
    return taper_fail(err, status,
                      "%s at t = %.17g with the pulse past granule %zu of %zu "
                      "(observables found so far are kept)%s",
                      why, sim->t, sim->next_pass - 1, sim->pass_limit, advice(status, why));
}

static int handle_roots(taper_sim *sim, taper_error *err)
{
    int roots[TAPER_N_SLOTS], grow = 0, gap_closed = 0;
    if (CVodeGetRootInfo(sim->cvode, roots) < 0) return stop(sim, err, TAPER_ESOLVER, "CVodeGetRootInfo failed");
    size_t passed_before = sim->next_pass;
    taper_events_record(sim, roots, &grow, &gap_closed);
    int status = TAPER_OK;
    if (gap_closed) status = taper_window_take_back(sim, err);
    if (!status && grow) status = taper_window_grow(sim, err);
    if (!status && sim->next_pass != passed_before) {
        status = taper_window_shrink(sim, err);
        if (!status && call_monitor(sim)) status = stop(sim, err, TAPER_EINTERRUPTED, "interrupted");
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
    const double *tp = sim->obs[TAPER_T_PASS];
    double longest = 0.0;
    for (size_t k = 1; k <= sim->pass_limit; k++)
        longest = fmax(longest, tp[k - 1] - (k > 1 ? tp[k - 2] : 0.0));
    return sim->t + PEAK_GRACE * fmax(longest, 1e-3);
}

static int step_once(taper_sim *sim, double *tout, int *grace, taper_error *err)
{
    double t = sim->t;
    int flag = CVode(sim->cvode, *tout, sim->y, &t, CV_NORMAL);
    sim->t = t;
    if (flag == CV_ROOT_RETURN) return handle_roots(sim, err);
    if (flag == CV_TOO_MUCH_WORK) {
        if (call_monitor(sim)) return stop(sim, err, TAPER_EINTERRUPTED, "interrupted");
        return TAPER_OK;
    }
    if (flag == CV_SUCCESS || flag == CV_TSTOP_RETURN) {
        if (*grace) return TAPER_OK; /* remaining peaks do not exist */
        return stop(sim, err, TAPER_ELIMIT,
                    sim->spec.t_max > 0.0 ? "t_max reached" : "time 1e300 reached (no t_max given)");
    }
    char why[600];
    snprintf(why, sizeof why, "CVODE failed (flag %d: %s)", flag, sim->solver_message);
    return stop(sim, err, TAPER_ESOLVER, why);
}

static int integrate(taper_sim *sim, taper_error *err)
{
    double tout = sim->spec.t_max > 0.0 ? sim->spec.t_max : NO_TIME_LIMIT;
    int grace = 0;
    while (!taper_events_complete(sim)) {
        if (sim->spec.max_steps > 0 && total_steps(sim) >= sim->spec.max_steps)
            return stop(sim, err, TAPER_ELIMIT, "max_steps reached");
        if (!grace && taper_events_passes_complete(sim)) {
            grace = 1;
            double tg = grace_time(sim);
            if (tg < tout) tout = tg;
            CVodeSetStopTime(sim->cvode, tout);
        }
        double t_before = sim->t;
        int status = step_once(sim, &tout, &grace, err);
        if (status != TAPER_OK) return status;
        if (grace && sim->t >= tout && sim->t > t_before) break;
    }
    if (sim->next_peak <= sim->target) {
        size_t missing = 0;
        for (size_t k = sim->next_peak; k <= sim->target; k++)
            missing += isnan(sim->obs[TAPER_T_PEAK][k - 1]);
        taper_sim_log(sim, 1,
                      "%zu of granules %zu..%zu reached no forward velocity maximum within %g "
                      "times the longest residence time after the last pass (the run ended at "
                      "t = %.6g): their v_peak is nan",
                      missing, sim->next_peak, sim->target, PEAK_GRACE, sim->t);
    }
    return TAPER_OK;
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

/* T_res(k) = t_pass(k) - t_pass(k-1), unless the difference is below what
 * the pass times resolve (the last, tiny granules of forward chains are
 * passed within 1e-15 t of each other): then NaN, not a number that is
 * noise. */
static size_t residence_times(taper_sim *sim)
{
    const double *tp = sim->obs[TAPER_T_PASS];
    double *tr = sim->obs[TAPER_T_RES];
    size_t unresolved = 0;
    for (size_t k = 1; k <= sim->chain->n; k++) {
        double before = k > 1 ? tp[k - 2] : 0.0, T = tp[k - 1] - before;
        if (fabs(T) < PASS_TIME_RESOLUTION * fabs(tp[k - 1])) {
            T = NAN;
            unresolved++;
        }
        tr[k - 1] = T;
    }
    return unresolved;
}

/* What the caller's log should know about values left NaN on purpose. */
static void report_untimed(const taper_sim *sim, size_t unresolved_residences)
{
    if (sim->untimed_passes || sim->untimed_peaks)
        taper_sim_log(sim, 1,
                      "%zu pass times and %zu peaks happened before their root functions were "
                      "armed (light granules overtaking in the precursor of a steeply tapered "
                      "chain): written as nan, not guessed",
                      sim->untimed_passes, sim->untimed_peaks);
    if (unresolved_residences)
        taper_sim_log(sim, 1,
                      "%zu residence times are below the resolution of the pass times "
                      "(%.1e t, set by CVODE's root finder): written as nan",
                      unresolved_residences, PASS_TIME_RESOLUTION);
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

static void finish(taper_sim *sim, int status)
{
    const taper_chain *c = sim->chain;
    report_untimed(sim, residence_times(sim));
    long cnt[6];
    read_counters(sim, cnt);
    for (int i = 0; i < 6; i++) cnt[i] += sim->counters_before_restart[i];
    taper_stats *s = &sim->stats;
    s->steps = cnt[0], s->rhs_evals = cnt[1], s->root_evals = cnt[2], s->jac_evals = cnt[3];
    s->nonlin_iters = cnt[4], s->err_test_fails = cnt[5];
    s->granule_reached = sim->next_pass - 1;
    s->t_final = sim->t;
    s->complete = status == TAPER_OK;
    double e = 0.0, p = 0.0, p_abs = 0.0;
    if (sim->y) taper_dyn_energy_momentum(&sim->dyn, taper_sim_data(sim, sim->y), &e, &p);
    e += sim->energy_free;
    p += sim->momentum_free;
    for (size_t k = 1; sim->y && k <= c->n; k++) {
        double v = k < sim->dyn.lo ? sim->v_free[k - 1]
                   : k <= sim->dyn.hi ? taper_dyn_v(&sim->dyn, taper_sim_data(sim, sim->y), k) : 0.0;
        p_abs += c->mass[k - 1] * fabs(v);
    }
    const double e0 = 0.5 * c->mass[0], p0 = c->mass[0];
    s->energy_error = fabs(e - e0) / e0;
    /* Relative to the momentum in motion: in backward chains granules carry
     * momenta far above P0 in opposite directions. */
    s->momentum_error = fabs(p - p0) / fmax(p0, p_abs);
    warn_of_drift(sim);
}

int taper_sim_run(taper_sim *sim, taper_error *err)
{
    if (!sim) return taper_fail(err, TAPER_EINVAL, "taper_sim_run: sim is NULL");
    if (sim->ran) return taper_fail(err, TAPER_EINVAL, "taper_sim_run: this sim has already run");
    sim->ran = 1;
    int status = setup_cvode(sim, err);
    if (status == TAPER_OK) status = integrate(sim, err);
    finish(sim, status);
    if (status == TAPER_OK) taper_ok(err);
    return status;
}

/* ---- results ------------------------------------------------------------ */
const double *taper_sim_observable(const taper_sim *sim, int which)
{
    if (!sim || which < 0 || which >= TAPER_N_OBSERVABLES) return NULL;
    return sim->obs[which];
}

void taper_sim_stats(const taper_sim *sim, taper_stats *stats)
{
    if (sim && stats) *stats = sim->stats;
}

int taper_sim_state(const taper_sim *sim, double *x, double *v, taper_error *err)
{
    if (!sim) return taper_fail(err, TAPER_EINVAL, "taper_sim_state: sim is NULL");
    if (!sim->y) return taper_fail(err, TAPER_EINVAL, "taper_sim_state: the sim has not run");
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_data(sim, sim->y);
    /* From the right: x_k = z_k + x_{k+1} inside the window, O(N) in all. */
    double x_window = 0.0;
    for (size_t k = d->n; k >= 1; k--) {
        double xk = 0.0, vk = 0.0;
        if (k < d->lo) {
            vk = sim->v_free[k - 1];
            xk = sim->x_free[k - 1] + vk * sim->t;
        } else if (k <= d->hi) {
            vk = taper_dyn_v(d, y, k);
            x_window += taper_dyn_z(d, y, k);
            xk = x_window;
        }
        if (x) x[k - 1] = xk;
        if (v) v[k - 1] = vk;
    }
    return taper_ok(err);
}
