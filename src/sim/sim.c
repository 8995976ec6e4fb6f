/*
 * sim.c -- the simulation state (see sim.h for who writes what): allocation
 * with the binary collision theory computed once, free, the results'
 * accessors, the log, and the window's extent with the granules that leave
 * it and come back.
 */
#include "sim.h"

#include <cvode/cvode.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

double *taper_sim_data(const taper_sim *sim, N_Vector v)
{
    return sim->cv.window ? taper_window_data(v) : N_VGetArrayPointer(v);
}

void taper_sim_log(const taper_sim *sim, int level, const char *fmt, ...)
{
    if (!sim->spec.log) return;
    char text[TAPER_MESSAGE_SIZE], *message = text;
    va_list ap;
    va_start(ap, fmt);
    int needed = vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (needed < 0) return;
    if ((size_t)needed >= sizeof text) { /* long: format it again, whole */
        message = malloc((size_t)needed + 1);
        if (!message) {
            message = text; /* out of memory: say the rest is missing */
            snprintf(text + sizeof text - 4, 4, "...");
        } else {
            va_start(ap, fmt);
            vsnprintf(message, (size_t)needed + 1, fmt, ap);
            va_end(ap);
        }
    }
    sim->spec.log(level, message, sim->spec.log_data);
    if (message != text) free(message);
}

/* ---- allocation ------------------------------------------------------------ */
/* What the spec's setters could not check: the settings against the chain
 * and the method. */
static taper_status check_spec(const taper_solver_spec *s, size_t n, taper_error *err)
{
    if (s->last_granule > n)
        return taper_fail_field(err, TAPER_EINVAL, "last_granule",
                                "last_granule = %zu exceeds n_granules = %zu", s->last_granule, n);
    const int order = taper_method_max_order(s->method);
    if (s->max_order > order)
        return taper_fail_field(err, TAPER_EINVAL, "max_order",
                                "max_order = %d: CVODE allows 1..%d for method '%s' (0: default)",
                                s->max_order, order, taper_method_name(s->method));
    return TAPER_OK;
}

static int alloc_arrays(taper_sim *sim)
{
    const size_t n = sim->n;
    for (int i = 0; i < TAPER_N_OBSERVABLES; i++) {
        sim->pulse.obs[i] = malloc(n * sizeof(double));
        if (!sim->pulse.obs[i]) return -1;
        for (size_t k = 0; k < n; k++) sim->pulse.obs[i][k] = NAN;
    }
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) {
        sim->theory[i] = malloc(n * sizeof(double));
        if (!sim->theory[i]) return -1;
    }
    sim->out.x_free = calloc(n, sizeof(double));
    sim->out.v_free = calloc(n, sizeof(double));
    sim->out.gap_watch = calloc(n, sizeof(double));
    sim->grow_z = malloc(n * sizeof(double));
    sim->pulse.events = calloc(n, 1);
    sim->v_scale = malloc(n * sizeof(double));
    sim->z_scale = malloc(n * sizeof(double));
    if (!sim->out.x_free || !sim->out.v_free || !sim->out.gap_watch || !sim->grow_z ||
        !sim->pulse.events || !sim->v_scale || !sim->z_scale)
        return -1;
    return taper_dyn_init(&sim->dyn, n, sim->exponent, sim->mass, sim->contact);
}

/* The binary collision theory of the chain, once per run: its v_k and mu_k
 * give the tolerance scales, and the caller reads all four columns through
 * taper_sim_theory.  Velocity and compression scales of granule k: v_k
 * (eq. (9)) and z_max = (n mu_k / (2 r_k) v_k^2)^(1/n), the maximum
 * compression of the collision k, k+1.  Floored so that weights stay
 * finite. */
static taper_status theory_and_scales(taper_sim *sim, taper_error *err)
{
    const size_t n = sim->n;
    const double *mu = sim->theory[TAPER_THEORY_MU];
    taper_status status = taper_theory_compute(sim->chain, sim->theory[TAPER_THEORY_V],
                                               sim->theory[TAPER_THEORY_MU],
                                               sim->theory[TAPER_THEORY_T_RES],
                                               sim->theory[TAPER_THEORY_T], err);
    if (status != TAPER_OK) return status;
    for (size_t k = 0; k < n; k++) sim->v_scale[k] = sim->theory[TAPER_THEORY_V][k];
    /* In place, in this order: z_N uses the floored v_{N-1}. */
    for (size_t k = 1; k <= n; k++) {
        size_t j = k < n ? k : n - 1; /* z_N = x_N: scale of the last contact */
        double v = sim->v_scale[j - 1];
        double z = pow(sim->exponent * mu[j - 1] / (2.0 * sim->contact[j - 1]) * v * v,
                       1.0 / sim->exponent);
        sim->v_scale[k - 1] = fmax(sim->v_scale[k - 1], 1e-280);
        sim->z_scale[k - 1] = isfinite(z) ? fmax(z, 1e-280) : 1.0;
    }
    return TAPER_OK;
}

taper_sim *taper_sim_alloc(const taper_chain *chain, const taper_solver_spec *spec, taper_error *err)
{
    taper_solver_spec defaults;
    if (!chain) {
        taper_fail(err, TAPER_EINVAL, "taper_sim_alloc: chain is NULL");
        return NULL;
    }
    if (!spec) {
        taper_solver_spec_defaults(&defaults);
        spec = &defaults;
    }
    const size_t n = taper_chain_size(chain);
    if (check_spec(spec, n, err) != TAPER_OK) return NULL;
    taper_sim *sim = calloc(1, sizeof *sim);
    if (!sim) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the simulation");
        return NULL;
    }
    sim->chain = chain;
    sim->n = n;
    sim->exponent = taper_chain_exponent(chain);
    sim->mass = taper_chain_mass(chain);
    sim->contact = taper_chain_contact(chain);
    sim->rest = taper_chain_rest_position(chain);
    sim->spec = *spec;
    if (alloc_arrays(sim) != 0) {
        taper_sim_free(sim);
        taper_fail(err, TAPER_ENOMEM, "cannot allocate results for %zu granules", n);
        return NULL;
    }
    if (theory_and_scales(sim, err) != TAPER_OK) {
        taper_sim_free(sim);
        return NULL;
    }
    sim->target = spec->last_granule ? spec->last_granule : n;
    sim->pass_limit = sim->target < n ? sim->target : n - 1;
    taper_pulse *p = &sim->pulse;
    p->next_pass = 1;
    p->next_peak = 2;
    p->obs[TAPER_V_PEAK][0] = 1.0; /* the impulse itself */
    p->obs[TAPER_T_PEAK][0] = 0.0;
    p->v_ref = 1.0;
    p->z_ref = 1.0;
    p->events[0] |= TAPER_EV_PEAK;
    p->pass_slots = TAPER_RING_SLOTS;
    p->peak_slots = TAPER_RING_SLOTS;
    p->arm_all = taper_sundials_roots_see_tiny_values();
    taper_ok(err);
    return sim;
}

void taper_sim_free(taper_sim *sim)
{
    if (!sim) return;
    taper_cvode *cv = &sim->cv;
    if (cv->mem) CVodeFree(&cv->mem);
    if (cv->nonlinear) SUNNonlinSolFree(cv->nonlinear);
    if (cv->linear) SUNLinSolFree(cv->linear);
    if (cv->band) SUNMatDestroy(cv->band);
    if (cv->y) N_VDestroy(cv->y);
    taper_window_free(cv->window);
    taper_sundials_context_free(&cv->ctx);
    free(cv->message);
    free(cv->roots);
    taper_dyn_release(&sim->dyn);
    for (int i = 0; i < TAPER_N_OBSERVABLES; i++) free(sim->pulse.obs[i]);
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) free(sim->theory[i]);
    free(sim->out.x_free);
    free(sim->out.v_free);
    free(sim->out.gap_watch);
    free(sim->grow_z);
    free(sim->pulse.events);
    free(sim->v_scale);
    free(sim->z_scale);
    free(sim);
}

/* ---- the window's extent --------------------------------------------------- */
int taper_sim_move_window(taper_sim *sim, size_t lo, size_t hi, double v_left)
{
    taper_dyn moved = sim->dyn;
    moved.lo = lo;
    moved.hi = hi;
    moved.v_left = v_left;
    if (sim->cv.window &&
        taper_window_set_range(sim->cv.window, taper_dyn_begin(&moved), taper_dyn_end(&moved)) != 0)
        return -1;
    sim->dyn = moved;
    return 0;
}

void taper_sim_release_granule(taper_sim *sim, double watch, int at_rest)
{
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_data(sim, sim->cv.y);
    const size_t j = d->lo;
    const double v = taper_dyn_v(d, y, j);
    const double x = taper_dyn_position(d, y, j);
    taper_out *out = &sim->out;
    out->x_free[j - 1] = x - v * sim->t;
    out->v_free[j - 1] = v;
    out->energy_free += 0.5 * sim->mass[j - 1] * v * v;
    out->momentum_free += sim->mass[j - 1] * v;
    out->gap_watch[j - 1] = watch;
    if (at_rest) out->left_resting++;
    /* Shrinking on the left never needs new buffers: this cannot fail. */
    (void)taper_sim_move_window(sim, j + 1, d->hi, v);
}

static double free_position(const taper_sim *sim, size_t j)
{
    return sim->out.x_free[j - 1] + sim->out.v_free[j - 1] * sim->t;
}

int taper_sim_recall_granule(taper_sim *sim)
{
    const size_t j = sim->dyn.lo - 1;
    taper_out *out = &sim->out;
    const double v = out->v_free[j - 1];
    if (taper_sim_move_window(sim, j, sim->dyn.hi, j > 1 ? out->v_free[j - 2] : 0.0) != 0)
        return -1;
    out->energy_free -= 0.5 * sim->mass[j - 1] * v * v;
    out->momentum_free -= sim->mass[j - 1] * v;
    double *y = taper_sim_data(sim, sim->cv.y);
    y[taper_idx_v(j) - taper_dyn_begin(&sim->dyn)] = v;
    if (j > 1) y[0] = free_position(sim, j - 1) - free_position(sim, j);
    return 0;
}

/* ---- results ---------------------------------------------------------------- */
const double *taper_sim_observable(const taper_sim *sim, taper_observable which)
{
    if (!sim || (int)which < 0 || (int)which >= TAPER_N_OBSERVABLES) return NULL;
    return sim->pulse.obs[which];
}

const double *taper_sim_theory(const taper_sim *sim, taper_theory_quantity which)
{
    if (!sim || (int)which < 0 || (int)which >= TAPER_N_THEORY_QUANTITIES) return NULL;
    return sim->theory[which];
}

static const char *const statistic_names[TAPER_N_STATISTICS] = {
    [TAPER_STAT_STEPS] = "steps",
    [TAPER_STAT_RHS_EVALS] = "rhs_evals",
    [TAPER_STAT_ROOT_EVALS] = "root_evals",
    [TAPER_STAT_JAC_EVALS] = "jac_evals",
    [TAPER_STAT_NONLIN_ITERS] = "nonlin_iters",
    [TAPER_STAT_ERR_TEST_FAILS] = "err_test_fails",
    [TAPER_STAT_WINDOW_CHANGES] = "window_changes",
    [TAPER_STAT_RESTARTS] = "restarts",
    [TAPER_STAT_MAX_WINDOW] = "max_window",
    [TAPER_STAT_GRANULE_REACHED] = "granule_reached",
    [TAPER_STAT_T_FINAL] = "t_final",
    [TAPER_STAT_ENERGY_ERROR] = "energy_error",
    [TAPER_STAT_MOMENTUM_ERROR] = "momentum_error",
    [TAPER_STAT_COMPLETE] = "complete",
};

const char *taper_statistic_name(taper_statistic which)
{
    if ((int)which < 0 || (int)which >= TAPER_N_STATISTICS) return NULL;
    return statistic_names[which];
}

double taper_sim_statistic(const taper_sim *sim, taper_statistic which)
{
    if (!sim) return NAN;
    const taper_run_statistics *s = &sim->stats;
    switch (which) {
    case TAPER_STAT_STEPS: return (double)s->cvode.steps;
    case TAPER_STAT_RHS_EVALS: return (double)s->cvode.rhs_evals;
    case TAPER_STAT_ROOT_EVALS: return (double)s->cvode.root_evals;
    case TAPER_STAT_JAC_EVALS: return (double)s->cvode.jac_evals;
    case TAPER_STAT_NONLIN_ITERS: return (double)s->cvode.nonlin_iters;
    case TAPER_STAT_ERR_TEST_FAILS: return (double)s->cvode.err_test_fails;
    case TAPER_STAT_WINDOW_CHANGES: return (double)s->window_changes;
    case TAPER_STAT_RESTARTS: return (double)s->restarts;
    case TAPER_STAT_MAX_WINDOW: return (double)s->max_window;
    case TAPER_STAT_GRANULE_REACHED: return (double)s->granule_reached;
    case TAPER_STAT_T_FINAL: return s->t_final;
    case TAPER_STAT_ENERGY_ERROR: return s->energy_error;
    case TAPER_STAT_MOMENTUM_ERROR: return s->momentum_error;
    case TAPER_STAT_COMPLETE: return (double)s->complete;
    }
    return NAN;
}

taper_status taper_sim_state(const taper_sim *sim, double *x, double *v, taper_error *err)
{
    if (!sim) return taper_fail(err, TAPER_EINVAL, "taper_sim_state: sim is NULL");
    if (!sim->cv.y) return taper_fail(err, TAPER_EINVAL, "taper_sim_state: the sim has not run");
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_data(sim, sim->cv.y);
    /* From the right: x_k = z_k + x_{k+1} inside the window, O(N) in all. */
    double x_window = 0.0;
    for (size_t k = d->n; k >= 1; k--) {
        double xk = 0.0, vk = 0.0;
        if (k < d->lo) {
            vk = sim->out.v_free[k - 1];
            xk = sim->out.x_free[k - 1] + vk * sim->t;
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
