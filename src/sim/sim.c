/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sim.c -- the simulation state (see sim.h for who writes what): allocation
 * with the binary collision theory computed once, free, the results'
 * accessors and the log.  The window's extent and the granules out of it
 * are window_flight.c's.
 */
#include "sim.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

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
    if (s->max_order > order && order == 0)
        return taper_fail_field(err, TAPER_EINVAL, "max_order",
                                "max_order = %d: method '%s' has a fixed order (8); give 0",
                                s->max_order, taper_method_name(s->method));
    if (s->max_order > order)
        return taper_fail_field(err, TAPER_EINVAL, "max_order",
                                "max_order = %d: CVODE allows 1..%d for method '%s' (0: default)",
                                s->max_order, order, taper_method_name(s->method));
    return TAPER_OK;
}

static int alloc_arrays(taper_sim *sim)
{
    const size_t n = sim->n, granules = sim->model.granules;
    for (int i = 0; i < TAPER_N_OBSERVABLES; i++) {
        sim->pulse.obs[i] = malloc(n * sizeof(double));
        if (!sim->pulse.obs[i]) return -1;
        for (size_t k = 0; k < n; k++) sim->pulse.obs[i][k] = NAN;
    }
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) {
        sim->theory[i] = malloc(granules * sizeof(double));
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
    if (sim->model.drag > 0.0) {
        sim->out.t_free = calloc(n, sizeof(double));
        sim->out.hand_start = calloc(n, sizeof(double));
        sim->out.hand_length = calloc(n, sizeof(double));
        if (!sim->out.t_free || !sim->out.hand_start || !sim->out.hand_length) return -1;
    }
    if (taper_dyn_init(&sim->dyn, n, sim->exponent, sim->mass, sim->contact) != 0) return -1;
    taper_model_configure(&sim->model, &sim->dyn);
    return 0;
}

/* Binary-collision z_max of a pair of reduced mass mu and factor r met at
 * velocity v: (n mu v^2 / (2 r))^(1/n). */
static double collision_compression(double n, double mu, double r, double v)
{
    return pow(n * mu / (2.0 * r) * v * v, 1.0 / n);
}

/* Where the chain's theory is NaN (a load or losses: the binary collision
 * approximation is elastic and unloaded), the scales come from the same
 * elastic recursion, eq. (9): v_{k+1} = 2 m_k v_k / (m_k + m_{k+1}), granule
 * 1 struck at velocity 1 (by the striker: 2 m_s / (m_s + m_1)).  The pulse
 * is weaker than that with losses; a larger scale only loosens atol, which
 * rtol then governs.  mu gets the reduced masses. */
static void elastic_scales(const taper_sim *sim, double *v, double *mu)
{
    const taper_model *m = &sim->model;
    const double *mass = sim->mass + m->off;
    const size_t N = m->granules;
    v[0] = m->striker ? 2.0 * sim->mass[0] / (sim->mass[0] + mass[0]) : 1.0;
    for (size_t k = 1; k < N; k++) {
        v[k] = 2.0 * mass[k - 1] * v[k - 1] / (mass[k - 1] + mass[k]);
        mu[k - 1] = mass[k - 1] * mass[k] / (mass[k - 1] + mass[k]);
    }
    mu[N - 1] = NAN;
}

/* Eq. (9) drops what granule k keeps after it hits k+1: when k is the
 * heavier, it moves on at (m_k - m_{k+1}) / (m_k + m_{k+1}) v_k.  On a
 * monotone chain that never matters (forward: v_{k+1} is larger and grows;
 * backward: the remainder moves back), but where a light granule is followed
 * by a heavier one the theory's v_{k+1} collapses (each light-to-heavy
 * collision keeps 2 m_light / (m_light + m_heavy) of the velocity) while the
 * heavy granules behind catch up and carry the pulse on.  The dimer 1, 0.01
 * of 100 granules: the theory's v_k is 8.8e-114 at granule 44 and v_k^2 is
 * subnormal from 59; the dynamics carry 0.68 at every heavy granule.
 * Tolerance scales taken from that theory made the absolute tolerance
 * 1e-280 on granules the pulse reaches, and CVODE stopped there (flag -3 at
 * t = 89.84).  So the velocity scale of granule k+1 is at least the largest
 * remainder moving on behind it; on monotone chains the scales are the
 * theory's, unchanged. */
static void trailing_scales(const double *mass, size_t n, double *v_scale)
{
    double trailing = 0.0;
    for (size_t k = 0; k + 1 < n; k++) {
        double remainder = (mass[k] - mass[k + 1]) / (mass[k] + mass[k + 1]) * v_scale[k];
        if (remainder > trailing) trailing = remainder;
        if (trailing > v_scale[k + 1]) v_scale[k + 1] = trailing;
    }
}

/* The binary collision theory of the chain, once per run: its v_k and mu_k
 * give the tolerance scales, and the caller reads all four columns through
 * taper_sim_theory.  Velocity and compression scales of granule k: v_k
 * (eq. (9)) and z_max = (n mu_k / (2 r_k) v_k^2)^(1/n), the maximum
 * compression of the collision k, k+1.  Floored so that weights stay
 * finite.  The bodies at the ends: a striker moves at 1 and meets granule 1
 * (reduced mass m_s m_1 / (m_s + m_1)); a wall contact is met by its end
 * granule at that granule's velocity (reduced mass: the granule's). */
static taper_status theory_and_scales(taper_sim *sim, taper_error *err)
{
    const taper_model *m = &sim->model;
    const size_t n = m->granules, off = m->off;
    const double *mu = sim->theory[TAPER_THEORY_MU];
    taper_status status = taper_theory_compute_monitored(
        sim->chain, sim->theory[TAPER_THEORY_V], sim->theory[TAPER_THEORY_MU],
        sim->theory[TAPER_THEORY_T_RES], sim->theory[TAPER_THEORY_T], sim->spec.monitor,
        sim->spec.monitor_data, err);
    if (status != TAPER_OK) return status;
    double *v_scale = sim->v_scale + off, *z_scale = sim->z_scale + off;
    const double *contact = sim->contact + off;
    /* The theory's columns where it has every one; otherwise (NaN columns
     * for loads and losses, NaN at the small granules of a decorated chain,
     * whose theory is that of the effective chain) the elastic recursion. */
    double *own_mu = NULL;
    int holes = 0;
    for (size_t k = 0; k < n; k++)
        holes |= !isfinite(sim->theory[TAPER_THEORY_V][k]) || (k + 1 < n && !isfinite(mu[k]));
    if (holes) {
        own_mu = malloc(n * sizeof(double));
        if (!own_mu) return taper_fail(err, TAPER_ENOMEM, "cannot allocate the tolerance scales");
        elastic_scales(sim, v_scale, own_mu);
        mu = own_mu;
    } else {
        for (size_t k = 0; k < n; k++) v_scale[k] = sim->theory[TAPER_THEORY_V][k];
    }
    trailing_scales(sim->mass + off, n, v_scale);
    /* In place, in this order: z_N uses the floored v_{N-1}. */
    for (size_t k = 1; k <= n; k++) {
        size_t j = k < n ? k : n - 1; /* z_N = x_N: scale of the last contact */
        double v = v_scale[j - 1];
        double z = pow(sim->exponent * mu[j - 1] / (2.0 * contact[j - 1]) * v * v,
                       1.0 / sim->exponent);
        v_scale[k - 1] = fmax(v_scale[k - 1], 1e-280);
        z_scale[k - 1] = isfinite(z) ? fmax(z, 1e-280) : 1.0;
    }
    const double *mass = sim->mass + off;
    if (m->wall_right) { /* z_N: the wall's compression */
        double z = collision_compression(sim->exponent, mass[n - 1], contact[n - 1], v_scale[n - 1]);
        z_scale[n - 1] = isfinite(z) ? fmax(z, 1e-280) : 1.0;
        sim->v_scale[sim->n - 1] = v_scale[n - 1];
        sim->z_scale[sim->n - 1] = 1.0; /* the wall body has no contact after it */
    }
    if (off) {
        double mu0 = m->striker ? sim->mass[0] * mass[0] / (sim->mass[0] + mass[0]) : mass[0];
        double z = collision_compression(sim->exponent, mu0, sim->contact[0], 1.0);
        sim->v_scale[0] = 1.0;
        sim->z_scale[0] = isfinite(z) ? fmax(z, 1e-280) : 1.0;
    }
    free(own_mu);
    return TAPER_OK;
}

/* A collision shorter than the resolution of its own time cannot be
 * integrated: t + h == t inside it, and the pass times from there on are
 * equal to rounding.  The binary collision theory gives both sides of that
 * comparison before the run: the residence time T_k of eq. (18) and the
 * time t_k of eq. (19).  Measured (docs/robustness.md, "The stress
 * matrix"): forward linear at its last valid S (N = 10: T_9 = 0.18 eps
 * t_9; N = 100: 4e-3 eps t_99) and forward exponential q = 1000, N = 10
 * (1.5e-9) stopped with CVODE flag -4 after warnings "t + h = t" whatever
 * the method; smoother forward tapers below the limit (q = 0.4 and 0.5 at
 * N = 100, q = 0.1 at N = 1000: 4e-3 down to 8e-39) completed with pass
 * times out of order, values that cannot be trusted.  So the run is refused
 * where T_k < eps t_k for a granule whose pass it times, naming the number
 * of granules that can be resolved.  Chains without a theory (loads,
 * losses: NaN columns) are not checked, nor the granules of a non-monotone
 * chain beyond where the theory loses the pulse (trailing_scales). */
static taper_status check_time_resolution(const taper_sim *sim, taper_error *err)
{
    const double *T = sim->theory[TAPER_THEORY_T_RES], *t = sim->theory[TAPER_THEORY_T];
    const double *v = sim->theory[TAPER_THEORY_V], *v_scale = sim->v_scale + sim->model.off;
    const size_t timed = sim->pass_limit - sim->model.off; /* contacts 1 .. timed */
    for (size_t k = 1; k <= timed; k++) {
        /* From the first granule where the theory has lost the pulse
         * (trailing_scales raised its velocity scale) on, T_k and t_k are
         * not the chain's: below n = 2 eq. (18)'s T ~ v^((2-n)/n) shrinks
         * with the theory's vanishing v_k (the dimer 1, 0.7 at n = 3/2:
         * T_723 = 3e-15 at t = 15 where the heavy granules carry the
         * pulse at order 1). */
        if (v_scale[k - 1] > v[k - 1]) break;
        if (sim->dyn.carried && k + 1 == sim->model.granules) break; /* never a collision */
        if (!(T[k - 1] < DBL_EPSILON * t[k - 1])) continue; /* NaN: no theory */
        const taper_profile profile = taper_chain_profile(sim->chain);
        const char *field = profile == TAPER_CUSTOM ? "radii" : profile == TAPER_DECORATED ? "pattern" : "n_granules";
        const char *taper = profile == TAPER_FORWARD_LINEAR ? ", or a smaller s"
                            : profile == TAPER_FORWARD_EXPONENTIAL ? ", or a smaller q" : "";
        return taper_fail_field(err, TAPER_ERANGE, field,
                                "the collision of granules %zu and %zu lasts T_%zu = %.3g (binary "
                                "collision theory, eqs. (18) and (19) of arXiv:0905.4512), less than "
                                "the resolution of double precision at its time t_%zu = %.6g (%.3g): "
                                "its pass cannot be told from the one before and the integration "
                                "cannot step through it; use at most %zu granules%s",
                                k, k + 1, k, T[k - 1], k, t[k - 1], DBL_EPSILON * t[k - 1], k, taper);
    }
    return TAPER_OK;
}

/* Drag relaxes a granule's velocity in m_k / drag.  Where that is much
 * shorter than a collision (tau = (mu_1 / r_1)^(1/n), eq. (18)'s time at
 * unit velocity up to a factor of order one), the equations are stiff:
 * Adams, whose corrector is a fixed-point iteration, and rk8, an explicit
 * method, step at the relaxation time for as long as the overdamped pulse
 * creeps on; BDF steps with the creep.  A note, not a refusal: the run is
 * correct, only slower.  (Where the creep's energy falls below rtol E(0)
 * while the window holds it, the run ends there: "the pulse has left the
 * chain", solve.c; whole-chain BDF follows a creeping front further.) */
static void advise_on_stiff_drag(const taper_sim *sim)
{
    const taper_model *m = &sim->model;
    if (!(m->drag > 0.0) || sim->spec.method == TAPER_BDF || m->granules < 2) return;
    const double *mass = sim->mass + m->off;
    double m_min = INFINITY;
    for (size_t k = 0; k < m->granules; k++) m_min = fmin(m_min, mass[k]);
    const double mu = mass[0] * mass[1] / (mass[0] + mass[1]);
    const double tau = pow(mu / sim->contact[m->off], 1.0 / sim->exponent);
    const double ratio = tau * m->drag / m_min;
    if (ratio > 10.0)
        taper_sim_log(sim, 1,
                      "drag = %g relaxes the lightest granule's velocity in m/drag = %.3g, %.0f times "
                      "faster than a collision ((mu/r)^(1/n) = %.3g): the equations are stiff, and "
                      "method '%s' steps at that relaxation time while the pulse creeps on; method = "
                      "'bdf' steps with the creep (CVODE BDF, implicit)",
                      m->drag, m_min / m->drag, ratio, tau, taper_method_name(sim->spec.method));
}

/* Below n = 2 on a chain that gets much lighter toward its end (a steep
 * forward taper), the precursor sets the light end moving long before the
 * pulse arrives, as a block: its weakly compressed contacts, whose force
 * r z^(n-1) is stiff without bound as z -> 0, vibrate at Adams' stability
 * limit and rattle like a gas, and the chatter of compressions below what
 * atol resolves decides the step (docs/robustness.md, "Below n = 2 on steep
 * forward tapers").  The cost is not a property of the chain alone (the
 * steps to t = 1 of forward exponential q = 0.1, N = 100, n = 3/2 change
 * 4.6x when rtol changes by 10 %), so the run is not refused; the caller is
 * told how to bound it.  The rule is inexact on purpose: the largest drop
 * of mass from a granule to a lighter one anywhere ahead of it, at least
 * LIGHT_END_DROP (measured with taper at the default tolerances: forward
 * exponential q = 0.05, N = 60, n = 3/2, a drop of 7e3: 4e5 steps, 3 s;
 * q = 0.1, N = 30: 6e3, 8e4 steps; q = 0.1, N = 50: 2.4e6, 7.3e6 steps,
 * 18 s; q = 0.1, N = 100: 7e12, 2.5e7 steps and more). */
#define LIGHT_END_DROP 1e5

static void advise_on_slow_light_end(const taper_sim *sim)
{
    const taper_model *m = &sim->model;
    if (!(sim->exponent < 2.0)) return;
    const double *mass = sim->mass + m->off;
    double heaviest = 0.0, drop = 1.0;
    size_t at = 0;
    for (size_t k = 0; k < m->granules; k++) {
        heaviest = fmax(heaviest, mass[k]);
        if (heaviest / mass[k] > drop) drop = heaviest / mass[k], at = k + 1;
    }
    if (drop >= LIGHT_END_DROP)
        taper_sim_log(sim, 1,
                      "contact exponent n = %g below 2 on a chain whose granule %zu is %.2g times "
                      "lighter than a granule before it: the precursor sets the light end moving "
                      "long before the pulse arrives, and its weakly compressed contacts (force "
                      "r z^(n-1), stiff without bound as z -> 0) vibrate and rattle, which can cost "
                      "millions of steps per unit time (forward exponential q = 0.1, 100 granules, "
                      "n = 3/2: 2.5e7 steps at the default tolerances).  The run is slow, not "
                      "wrong: bound it with t_max or max_steps, which stop it with the "
                      "observables found so far",
                      sim->exponent, at, drop);
}

/* A light end carried.  The last granule of a free end far lighter than
 * the one before it (a forward taper cut near its tip: forward linear
 * s = 0.0101010101, N = 100 ends on a granule 1e-24 times the mass of
 * granule 99) cannot bounce off it: pushed by an acceleration a that
 * changes slowly against its own contact's period, it rides on it, its
 * compression (m_N a / r)^(1/(n-1)) following a adiabatically.  Integrated,
 * CVODE resolves that contact's short period and the chatter that its
 * error excites (1.45e6 steps for t = 51.420..51.425 of a run to t = 77),
 * while nothing it does reaches the rest of the chain: its reaction
 * changes the carrier's acceleration by m_N / m_(N-1) of itself.  So it is
 * carried: v_N = v_(N-1), the contact held at z_(N-1) = 0 (dynamics.h,
 * taper_dyn_carry), the limit m_N / m_(N-1) -> 0 of the chain's motion.
 * In that limit the carrier, whose front pushes nothing, never
 * decelerates (no wall, load or loss), so the rider never leaves; the
 * paper's pass of the carrier, v_N surpassing v_(N-1), is where the
 * rider's compression starts to shrink, at the carrier's largest
 * acceleration, which is where its compression behind is largest: the pass
 * of granule N-2 (events.c).  The rider's velocity peak is the carrier's.
 * How far the finite mass is from the limit: as the push ends the rider
 * leaves its carrier faster by about (m_N / m_(N-1))^(2/(3n-4)) of the
 * velocity (a scaling of the rider's equation, exponent 4/7 at n = 5/2;
 * measured on 11 equal granules and a light 12th: 0.94, 1.05, 1.16 times
 * it at mass ratios 1e-9, 1e-12, 1e-15; test dynamics/light_end_carried),
 * and the pass times move by as much: the rider is carried where that is
 * below rtol.  Contact exponents below 2 are left out (their force is
 * stiff without bound at small compressions; advise_on_slow_light_end). */
static size_t light_end_carried(const taper_sim *sim)
{
    const taper_model *m = &sim->model;
    if (m->granules < 3 || m->wall_right || m->load != 0.0 || m->damping != 0.0 || m->drag != 0.0 ||
        !(sim->exponent >= 2.0))
        return 0;
    const size_t last = m->bodies;
    const double ratio = sim->mass[last - 1] / sim->mass[last - 2];
    return pow(ratio, 2.0 / (3.0 * sim->exponent - 4.0)) <= sim->spec.rtol ? last : 0;
}

/* The pulse before the run: the body with the impulse (granule 1, or the
 * striker) has its velocity peak at t = 0 and every body before it (a left
 * wall) its events done; the walls have no impulse yet and no peak force
 * (NaN until the pulse reaches one); the rings of pending events start at
 * their fixed size. */
static void pulse_init(taper_sim *sim)
{
    const taper_model *m = &sim->model;
    taper_pulse *p = &sim->pulse;
    const size_t i0 = m->impulse;
    p->next_pass = i0;
    p->next_peak = i0 + 1;
    p->obs[TAPER_V_PEAK][i0 - 1] = 1.0; /* the impulse itself */
    p->obs[TAPER_T_PEAK][i0 - 1] = 0.0;
    p->v_ref = 1.0;
    p->z_ref = 1.0;
    for (size_t k = 1; k <= i0; k++) p->events[k - 1] |= TAPER_EV_PEAK | (k < i0 ? TAPER_EV_PASS : 0u);
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        sim->walls.peak_force[e] = sim->walls.peak_time[e] = NAN;
        sim->stats.wall_impulse[e] = NAN;
    }
    if (m->wall_left) sim->stats.wall_impulse[TAPER_LEFT] = 0.0;
    if (m->wall_right) sim->stats.wall_impulse[TAPER_RIGHT] = 0.0;
    /* (how they grow depends on the stepper's root finder: taper_events_arm,
     * when the run starts) */
    p->pass_slots = TAPER_RING_SLOTS;
    p->peak_slots = TAPER_RING_SLOTS;
}

/* Between the set-up's passes over the whole chain of a long chain the
 * monitor is asked too (window 0..0, as during the theory, and like it only
 * for chains of TAPER_LONG_CHAIN granules or more), so that the set-up of a
 * long chain stops at once (10^6 granules: each pass some 10 ms). */
static taper_status go_on(const taper_sim *sim, const char *step, taper_error *err)
{
    if (!sim->spec.monitor || sim->n < TAPER_LONG_CHAIN) return TAPER_OK;
    const taper_progress p = {.target = sim->model.granules};
    if (!sim->spec.monitor(&p, sim->spec.monitor_data)) return TAPER_OK;
    return taper_fail(err, TAPER_EINTERRUPTED, "interrupted while the run was set up (%s)", step);
}

/* The chain's own checks (taper_chain_alloc: damping needs n >= 2, ...) are
 * done; here those of the solver settings against this chain, then the
 * bodies, the result arrays, the theory and tolerance scales, and the
 * time-resolution check, which needs the theory. */
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
    sim->spec = *spec;
    sim->exponent = taper_chain_exponent(chain);
    if (taper_model_init(&sim->model, chain) != 0) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the bodies of %zu granules", n);
        goto fail;
    }
    const taper_model *m = &sim->model;
    sim->n = m->bodies;
    sim->mass = m->mass;
    sim->contact = m->contact;
    sim->rest = m->rest;
    if (go_on(sim, "the bodies", err) != TAPER_OK) goto fail;
    if (alloc_arrays(sim) != 0) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate results for %zu granules", n);
        goto fail;
    }
    if (go_on(sim, "the arrays", err) != TAPER_OK) goto fail;
    if (theory_and_scales(sim, err) != TAPER_OK) goto fail;
    if (go_on(sim, "the tolerance scales", err) != TAPER_OK) goto fail;
    const size_t target = spec->last_granule ? spec->last_granule : n;
    sim->target = target + m->off;
    sim->pass_limit = (target < n ? target : n - 1) + m->off;
    sim->dyn.carried = light_end_carried(sim);
    if (check_time_resolution(sim, err) != TAPER_OK) goto fail;
    if (go_on(sim, "the time resolution", err) != TAPER_OK) goto fail;
    if (sim->dyn.carried) /* a warning: two observables are the limit's */
        taper_sim_log(sim, 1,
                      "granule %zu, %.3g times the mass of granule %zu, rides on it and is "
                      "carried, as in the limit of a vanishing mass: granule %zu is passed when "
                      "granule %zu is, granule %zu peaks with %zu (docs/design.md, \"A light end "
                      "carried\")",
                      m->granules, sim->mass[sim->dyn.carried - 1] / sim->mass[sim->dyn.carried - 2],
                      m->granules - 1, m->granules - 1, m->granules - 2, m->granules, m->granules - 1);
    advise_on_stiff_drag(sim);
    advise_on_slow_light_end(sim);
    pulse_init(sim);
    taper_ok(err);
    return sim;
fail:
    taper_sim_free(sim);
    return NULL;
}

void taper_sim_free(taper_sim *sim)
{
    if (!sim) return;
    /* the stepper first: the state's buffers are registered with the window */
    if (sim->stepper.memory) sim->stepper.release(sim->stepper.memory);
    taper_window_free(sim->state.window);
    taper_dyn_release(&sim->dyn);
    taper_model_release(&sim->model);
    for (int i = 0; i < TAPER_N_OBSERVABLES; i++) free(sim->pulse.obs[i]);
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) free(sim->theory[i]);
    free(sim->out.x_free);
    free(sim->out.v_free);
    free(sim->out.gap_watch);
    free(sim->out.t_free);
    free(sim->out.hand_start);
    free(sim->out.hand_length);
    free(sim->out.handing);
    free(sim->grow_z);
    free(sim->pulse.events);
    free(sim->v_scale);
    free(sim->z_scale);
    free(sim);
}

/* ---- results ---------------------------------------------------------------- */
const double *taper_sim_observable(const taper_sim *sim, taper_observable which)
{
    if (!sim || (int)which < 0 || (int)which >= TAPER_N_OBSERVABLES) return NULL;
    return sim->pulse.obs[which] + sim->model.off;
}

const double *taper_sim_theory(const taper_sim *sim, taper_theory_quantity which)
{
    if (!sim || (int)which < 0 || (int)which >= TAPER_N_THEORY_QUANTITIES) return NULL;
    return sim->theory[which];
}

#define STATISTIC_NAME(constant, name, dimension) [constant] = name,
#define STATISTIC_DIMENSION(constant, name, dimension) [constant] = TAPER_DIM_##dimension,
static const char *const statistic_names[] = {TAPER_STATISTIC_LIST(STATISTIC_NAME)};
static const taper_dimension statistic_dimensions[] = {TAPER_STATISTIC_LIST(STATISTIC_DIMENSION)};

taper_dimension taper_statistic_dimension(taper_statistic which)
{
    return (unsigned)which < TAPER_N_STATISTICS ? statistic_dimensions[which] : TAPER_DIM_NUMBER;
}

const char *taper_statistic_name(taper_statistic which)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    return (unsigned)which < TAPER_N_STATISTICS ? statistic_names[which] : NULL;
}

double taper_sim_statistic(const taper_sim *sim, taper_statistic which)
{
    if (!sim) return NAN;
    const taper_run_statistics *s = &sim->stats;
    switch (which) {
    case TAPER_STAT_STEPS: return (double)s->counters.steps;
    case TAPER_STAT_RHS_EVALS: return (double)s->counters.rhs_evals;
    case TAPER_STAT_ROOT_EVALS: return (double)s->counters.root_evals;
    case TAPER_STAT_JAC_EVALS: return (double)s->counters.jac_evals;
    case TAPER_STAT_NONLIN_ITERS: return (double)s->counters.nonlin_iters;
    case TAPER_STAT_ERR_TEST_FAILS: return (double)s->counters.err_test_fails;
    case TAPER_STAT_WINDOW_CHANGES: return (double)s->window_changes;
    case TAPER_STAT_RESTARTS: return (double)s->restarts;
    case TAPER_STAT_MAX_WINDOW: return (double)s->max_window;
    case TAPER_STAT_GRANULE_REACHED: return (double)s->granule_reached;
    case TAPER_STAT_T_FINAL: return s->t_final;
    case TAPER_STAT_ENERGY_ERROR: return s->energy_error;
    case TAPER_STAT_MOMENTUM_ERROR: return s->momentum_error;
    case TAPER_STAT_COMPLETE: return (double)s->complete;
    case TAPER_STAT_ENERGY_INITIAL: return s->energy_initial;
    case TAPER_STAT_ENERGY_DISSIPATED: return s->energy_dissipated;
    case TAPER_STAT_ENERGY_TRANSMITTED: return s->energy_transmitted;
    case TAPER_STAT_ENERGY_REFLECTED: return s->energy_reflected;
    case TAPER_STAT_ENERGY_IN_CHAIN: return s->energy_in_chain;
    case TAPER_STAT_WALL_PEAK_FORCE_LEFT: return sim->walls.peak_force[TAPER_LEFT];
    case TAPER_STAT_WALL_PEAK_TIME_LEFT: return sim->walls.peak_time[TAPER_LEFT];
    case TAPER_STAT_WALL_IMPULSE_LEFT: return s->wall_impulse[TAPER_LEFT];
    case TAPER_STAT_WALL_PEAK_FORCE_RIGHT: return sim->walls.peak_force[TAPER_RIGHT];
    case TAPER_STAT_WALL_PEAK_TIME_RIGHT: return sim->walls.peak_time[TAPER_RIGHT];
    case TAPER_STAT_WALL_IMPULSE_RIGHT: return s->wall_impulse[TAPER_RIGHT];
    }
    return NAN;
}

/* A body out of the window flies in closed form from where and when it left
 * (taper_out; window_flight.c releases it). */
void taper_sim_flight(const taper_sim *sim, size_t j, double t, double *x, double *v)
{
    const taper_out *out = &sim->out;
    const double v0 = out->v_free[j - 1];
    const double tau = out->t_free ? taper_sim_drag_time(sim, j) : INFINITY;
    if (!isfinite(tau)) { /* constant velocity (as ever without drag) */
        if (v) *v = v0;
        if (x) *x = out->x_free[j - 1] + v0 * t;
        return;
    }
    const double s = t - out->t_free[j - 1];
    if (v) *v = v0 * exp(-s / tau);
    if (x) *x = out->x_free[j - 1] - v0 * tau * expm1(-s / tau);
}

/* Displacements and velocities of bodies first..first+count-1 into x[0..count)
 * and v[0..count) (either may be NULL).  From the right: x_k = z_k + x_{k+1}
 * inside the window, O(bodies) in all. */
static void body_states(const taper_sim *sim, double *x, double *v, size_t first, size_t count)
{
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_entries(sim);
    double x_window = 0.0;
    for (size_t k = d->n; k >= 1; k--) {
        double xk = 0.0, vk = 0.0;
        if (k < d->lo) {
            taper_sim_flight(sim, k, sim->t, &xk, &vk);
        } else if (k <= d->hi) {
            vk = taper_dyn_v(d, y, k);
            x_window += taper_dyn_z(d, y, k);
            xk = x_window;
        }
        if (k >= first && k < first + count) {
            if (x) x[k - first] = xk;
            if (v) v[k - first] = vk;
        }
    }
}

void taper_sim_bodies(const taper_sim *sim, double *x, double *v)
{
    body_states(sim, x, v, 1, sim->n);
}

static taper_status check_ran(const taper_sim *sim, const char *what, taper_error *err)
{
    if (!sim) return taper_fail(err, TAPER_EINVAL, "%s: sim is NULL", what);
    if (!taper_sim_entries(sim)) return taper_fail(err, TAPER_EINVAL, "%s: the sim has not run", what);
    return TAPER_OK;
}

taper_status taper_sim_state(const taper_sim *sim, double *x, double *v, taper_error *err)
{
    taper_status status = check_ran(sim, "taper_sim_state", err);
    if (status != TAPER_OK) return status;
    body_states(sim, x, v, 1 + sim->model.off, sim->model.granules);
    return taper_ok(err);
}

double taper_sim_time(const taper_sim *sim) { return sim ? sim->t : NAN; }

double taper_sim_piston_work(const taper_sim *sim)
{
    if (!sim || !sim->model.piston || !taper_sim_entries(sim)) return NAN;
    return sim->stats.piston_work;
}

taper_status taper_sim_striker_state(const taper_sim *sim, double *x, double *v, taper_error *err)
{
    taper_status status = check_ran(sim, "taper_sim_striker_state", err);
    if (status != TAPER_OK) return status;
    if (!sim->model.striker)
        return taper_fail_field(err, TAPER_EINVAL, "striker_radius",
                                "taper_sim_striker_state: the chain has no striker");
    body_states(sim, x, v, 1, 1);
    return taper_ok(err);
}

/* Force of contact k (bodies k, k+1) at sim->t: the window's own state
 * where it has it, the static F0 ahead of it, and behind it, the gap slot
 * included, the contact law on the bodies' positions (x and v of every
 * body; the integration neglects these contacts, window.c). */
static double contact_force_now(const taper_sim *sim, const double *x, const double *v, size_t k)
{
    const taper_dyn *d = &sim->dyn;
    if (k >= d->lo) return taper_dyn_window_force(d, taper_sim_entries(sim), k);
    return taper_dyn_contact_force(d, k, x[k - 1] - x[k], v[k - 1] - v[k]);
}

taper_status taper_sim_forces(const taper_sim *sim, double *force, taper_error *err)
{
    taper_status status = check_ran(sim, "taper_sim_forces", err);
    if (status != TAPER_OK) return status;
    if (!force) return taper_fail(err, TAPER_EINVAL, "taper_sim_forces: force is NULL");
    const taper_model *m = &sim->model;
    double *x = malloc(sim->n * sizeof(double)), *v = malloc(sim->n * sizeof(double));
    if (!x || !v) {
        free(x);
        free(v);
        return taper_fail(err, TAPER_ENOMEM, "taper_sim_forces: cannot allocate %zu bodies", sim->n);
    }
    taper_sim_bodies(sim, x, v);
    const size_t N = m->granules, off = m->off;
    /* force[k] is the contact of bodies k + off, k + off + 1; the ends: the
     * striker's or the wall's contact, else the load on a free end. */
    force[0] = off ? contact_force_now(sim, x, v, 1) : m->load;
    for (size_t k = 1; k < N; k++) force[k] = contact_force_now(sim, x, v, k + off);
    force[N] = m->wall_right ? contact_force_now(sim, x, v, N + off) : m->load;
    free(x);
    free(v);
    return taper_ok(err);
}
