/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * window.c -- the policy of the active window of granules (see dynamics.h):
 * it decides, the run loop (solve.c) acts.  Every function here only reads
 * the sim; the loop moves the window (window_flight.c) and restarts the
 * stepper.
 *
 *  grow:      granule hi+1 joins when z_hi reaches the growth threshold.
 *             Its state and Nordsieck history are zero in every vector, which
 *             is exact for a granule at rest: no solver restart.  It joins
 *             at the stepper's internal time (the end of the step holding
 *             the root), so the contact's impulse from the root to there is
 *             neglected: the thresholds keep its force far below the
 *             tolerance, and the window starts with two bodies (the first
 *             contact closes at t = 0+, see taper_window_growth_thresholds).
 *  shrink:    granule lo leaves, after all its observables are known, when
 *             either criterion below holds.  Dropping components leaves the
 *             others' Nordsieck history exact: no restart.
 *  take back: if the gap behind the window closes after all, granule lo-1
 *             returns with its ballistic state; this changes the history of
 *             a component, so the stepper is restarted (rare).
 *
 * Error scales (from the tolerance):
 *     v_eps = REST_FACTOR (rtol v_ref + atol v_scale),
 *     z_eps = REST_FACTOR (rtol z_ref + atol z_scale)
 * (v_ref, z_ref: velocity of granule k+1 and compression z_k at the last pass
 * event, the pulse's largest; v_scale, z_scale: the granule's own binary
 * collision scales that make atol relative, see sim.c).
 *
 * Criterion 1, exact free flight (the clean case, e.g. backward chains): the
 * gaps on both sides of lo are open by more than z_eps and not closing
 * (v_{lo-1} <= v_lo <= v_{lo+1}).  Granule lo then moves at constant velocity
 * for ever unless the window pushes granule lo+1 back into it, which the gap
 * slot watches at compression 0 (gap_watch = 0): take-back is exact.  Under
 * drag it flies as m dv/dt = -drag v has it (window_flight.c,
 * taper_sim_flight), and the gap behind must stay open for ever under both
 * flights (drag_gap_stays_open); with Kuwabara-Kono damping open contacts
 * push nothing, so the flight is free as without it.
 *
 * Criterion 2, at rest within the tolerance (monodisperse chains, the tails
 * of forward chains, the recoiling train of long backward chains): behind the
 * pulse granules are left with velocities and compressions of either sign at
 * the level of the solver's error, or drifting as a block whose relative
 * velocities are at that level, which criterion 1 rejects for ever, so the
 * window would span the whole chain behind the front (O(N^2) cost).  Granule
 * lo may leave, flying ballistically at its velocity, when
 *     |v_lo - v_{lo-1}| <= v_eps  (|v_1| <= v_eps for lo = 1),
 *       or, where the gap behind is open and not closing (z_{lo-1} < 0,
 *       v_{lo-1} <= v_lo), |v_lo - v_{lo+1}| <= v_eps,
 *     z_lo <= z_eps,  z_{lo-1} <= z_eps,
 * i.e. when it is at rest within REST_FACTOR error units relative to the
 * granule behind it, which already flies freely (Galilean invariance: a
 * backward linear chain, S = 0.5, leaves its granules beyond k ~ 4e5 drifting
 * back together at 2.8e-14 with relative velocities of 1e-20 and either sign,
 * and with rest as the reference the window grew by one granule per granule
 * from there on), or relative to the granule ahead when the one behind flies
 * away from it and can never touch it again (behind a pulse of a high
 * exponent granule 1 recoils at a real velocity, -2.9e-7 for monodisperse
 * n = 12, far beyond v_eps, while granule 2 rests with the chain: compared
 * with granule 1 it never left, and the window spanned the chain, 296 to
 * 299 of 300 granules for n = 8 and 11 to 15, at O(N^2) cost), and its contacts are open or
 * compressed by less than
 * REST_FACTOR error units (an open gap exerts no force, whatever its size;
 * requiring |z| small would strand granules whose gaps open at noise-level
 * speed).  Why this is
 * harmless: the gap z_lo it leaves behind is watched
 * with gap_watch = WATCH_FACTOR / REST_FACTOR * z_rest, and the gap slot
 * pushes nothing on either side (dynamics.h), so while lo is out the force
 * neglected there is at most r z_watch^(n-1), a fraction at most
 * (WATCH_FACTOR rtol)^(n-1) (3e-11 for n = 5/2 and the default rtol) of the
 * pulse force r z_ref^(n-1): below what the tolerance resolves, and without
 * a reaction missing anywhere, so momentum is kept exactly.  A
 * compression beyond z_watch (a real signal) takes the granule back exactly
 * as in criterion 1; the factor WATCH_FACTOR / REST_FACTOR = 10 between
 * leaving and returning is the hysteresis that keeps noise from thrashing
 * (each take-back costs a CVodeReInit).  Neighbours that are both out move
 * together at most at v_eps, so out of the window the chain's gaps close by
 * at most z_eps + v_eps t (documented in docs/window.md).  The
 * granule's momentum is kept exactly; the contact energy dropped is at most
 * r z_watch^n / n per granule.
 */
#include "sim.h"

#include <math.h>

/* Criterion 2: leave within REST_FACTOR error units of rest, come back
 * beyond WATCH_FACTOR units of compression. */
#define REST_FACTOR 100.0
#define WATCH_FACTOR 1000.0
/* ... and leave compressions whose force is below this fraction of rtol
 * times the pulse force (resting_compression). */
#define FORCE_FRACTION 0.01
/* The smallest growth threshold: root values stay clear of underflow. */
#define GROW_FLOOR 1e-290

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
/* The lighter of bodies k, k+1 that can move: a wall (mass 0, extended.c)
 * never does, and its contact's threshold is the granule's. */
static double lighter(const taper_sim *sim, size_t k)
{
    const double a = sim->mass[k - 1], b = sim->mass[k];
    if (!(a > 0.0)) return b;
    if (!(b > 0.0)) return a;
    return fmin(a, b);
}

/* Under a static load F0 the force a contact outside the window would add
 * is F(delta + z) - F0 ~ K z, linear with the stiffness K = (n-1) r
 * delta^(n-2) (the disturbance ahead of a pulse in a precompressed chain is
 * linear, not z^(n-1)).  The same two bounds, for that force: K z below
 * 1e-40 of m v per unit time, and below 1e-40 of the contact's pulse force
 * r z_scale^(n-1).  Only ever lowers the thresholds. */
static void loaded_thresholds(const taper_sim *sim, double *grow_z)
{
    const double n = sim->exponent;
    for (size_t k = 1; k < sim->n; k++) {
        const double r = sim->contact[k - 1], delta = sim->model.delta[k - 1];
        const double stiffness = (n - 1.0) * r * pow(delta, n - 2.0);
        double m = lighter(sim, k);
        double v = fmin(sim->v_scale[k - 1], sim->v_scale[k]);
        double per_time = 1e-40 * m * v / stiffness;
        double per_collision = 1e-40 * r * pow(sim->z_scale[k - 1], n - 1.0) / stiffness;
        double z = fmin(per_time, per_collision);
        if (z < grow_z[k - 1]) grow_z[k - 1] = fmax(z, GROW_FLOOR);
    }
}

/* With Kuwabara-Kono damping a closing contact also pushes with r damping
 * d(s^(n-1))/dt (s = delta + z), whose impulse integrates exactly: from
 * rest to the time a compression z is reached it is r damping (s^(n-1) -
 * delta^(n-1)), i.e. r damping z^(n-1) unloaded and damping K z to first
 * order under a load (K the linear stiffness above; the clipping at zero
 * force only lowers it).  The neglected contact's impulse is therefore
 * bounded by bounding z: that impulse below 1e-40 of m v, the lighter
 * granule's binary-collision momentum (eq. (9)).  The force itself is not
 * small against the elastic one near contact onset (their ratio is damping
 * (n-1) (dz/dt) / z, large while z grows from 0), but what the window
 * neglects is the momentum it would have given granule hi+1, and that is
 * this impulse plus the elastic one the other bounds hold.  Only ever
 * lowers the thresholds; for damping below a unit time the per-unit-time
 * bound is the lower one already. */
static void damped_thresholds(const taper_sim *sim, double *grow_z)
{
    const double n = sim->exponent, damping = sim->model.damping;
    for (size_t k = 1; k < sim->n; k++) {
        const double r = sim->contact[k - 1];
        const double momentum = 1e-40 * lighter(sim, k) * fmin(sim->v_scale[k - 1], sim->v_scale[k]);
        double z;
        if (sim->model.load > 0.0) {
            const double delta = sim->model.delta[k - 1];
            z = momentum / (damping * (n - 1.0) * r * pow(delta, n - 2.0));
        } else {
            z = pow(momentum / (damping * r), 1.0 / (n - 1.0));
        }
        if (z < grow_z[k - 1]) grow_z[k - 1] = fmax(z, GROW_FLOOR);
    }
}

void taper_window_growth_thresholds(const taper_sim *sim, double *grow_z)
{
    const double power = 1.0 / (sim->exponent - 1.0);
    const double fraction = fmax(pow(1e-40, power), 1e-200);
    for (size_t k = 1; k < sim->n; k++) {
        double m = lighter(sim, k);
        double v = fmin(sim->v_scale[k - 1], sim->v_scale[k]);
        double per_time = pow(1e-40 * m * v / sim->contact[k - 1], power);
        double per_collision = fraction * sim->z_scale[k - 1];
        grow_z[k - 1] = fmax(fmin(per_time, per_collision), GROW_FLOOR);
    }
    /* No threshold for the contact of the body with the impulse: it is in
     * the window from the start (solve.c, setup_stepper).  Starting with that
     * body alone, the first growth root fell inside CVODE's first step
     * (h = 1e-4) and granule 2 joined at its end, at rest, short of the
     * impulse r h^n / n (energy error 1.3e-6 for n = 3/2); for n >= 12 a
     * threshold beyond z = 1e-4 was first crossed inside a second step to
     * t = 1.0001 (a lone ballistic body has no error estimate: the step
     * grew 10^4-fold) and CVODE failed there (flag -4).  A window of two
     * bodies has neither: its error estimate follows the first contact. */
    if (sim->model.load > 0.0) loaded_thresholds(sim, grow_z);
    if (sim->model.damping > 0.0) damped_thresholds(sim, grow_z);
    grow_z[sim->n - 1] = INFINITY; /* nothing beyond the last granule */
}

/* Take back first: the granule returns into the state the growth and the
 * departures are then decided on.  Growing needs no restart: granule hi+1
 * is at rest, its state and Nordsieck history zero in every vector. */
taper_window_plan taper_window_plan_for(const taper_sim *sim, taper_root_report report)
{
    return (taper_window_plan){
        .take_back = report.gap_closed && sim->dyn.lo > 1,
        .grow = report.grow && sim->dyn.hi < sim->dyn.n,
        .shrink = report.passed && sim->state.window != NULL,
    };
}

/* The largest compression a contact may keep when granule j leaves at rest
 * (criterion 2).  Its force r z^(n-1) is dropped from then on (the gap slot
 * pushes nothing, dynamics.h); that is negligible while the force is a
 * fraction below FORCE_FRACTION rtol of the pulse force r z_ref^(n-1), i.e.
 * z <= (FORCE_FRACTION rtol)^(1/(n-1)) z_ref.  For n = 5/2 at rtol <= 1e-10
 * that is looser than z_eps (which then decides); at looser tolerances
 * z_eps = 100 rtol z_ref let monodisperse chains leak momentum at
 * 2.7e-8 per granule at rtol 1e-6 while the gap slot pushed the window's
 * first granule alone (docs/window.md, "The force bound").  Never below one error
 * unit: smaller compressions are noise, indistinguishable from zero. */
static double resting_compression(const taper_sim *sim, size_t j, double z_eps)
{
    const double n = sim->exponent, rtol = sim->spec.rtol;
    const double z_ref = sim->pulse.z_ref;
    const double unit = rtol * fabs(z_ref) + sim->spec.atol * sim->z_scale[j - 1];
    const double z_force = pow(FORCE_FRACTION * rtol, 1.0 / (n - 1.0)) * fabs(z_ref);
    return fmin(z_eps, fmax(unit, z_force));
}

/* How far body k still flies under drag at velocity v: v m_k / drag
 * (taper_sim_flight); a wall (inverse mass 0) rests. */
static double drag_reach(const taper_sim *sim, size_t k, double v)
{
    const double rate = sim->model.drag * sim->dyn.inv_mass[k - 1];
    return v != 0.0 && rate > 0.0 ? v / rate : 0.0;
}

/* Under drag both granules of the gap behind j fly as v e^(-s/tau) once j
 * leaves (tau = m / drag, different for different masses), so "not closing
 * now" (v_back <= v) is not "never closing": the lighter one stops sooner.
 * The gap is z_back + a tau_a (1 - e^(-s/tau_a)) - b tau_b (1 - e^(-s/tau_b))
 * (a = v_back, b = v); its rate a e^(-s/tau_a) - b e^(-s/tau_b) changes
 * sign at most once, and from a - b <= 0 only upward, so the gap is
 * largest at s = 0 or s = oo: it stays open for ever iff its limit
 * z_back + a tau_a - b tau_b is open too.  Exact free flight again, as
 * criterion 1 needs.  Without drag: always (constant velocities). */
static int drag_gap_stays_open(const taper_sim *sim, size_t j, double z_back, double v_back, double v,
                               double z_eps_back)
{
    if (!(sim->model.drag > 0.0) || j == 1) return 1;
    return z_back + drag_reach(sim, j - 1, v_back) - drag_reach(sim, j, v) < -z_eps_back;
}

/* Whether granule lo may leave now, and how (criteria 1 and 2 above). */
taper_departure taper_window_departure(const taper_sim *sim)
{
    const taper_departure stays = {TAPER_STAYS, 0.0};
    /* Under a load a granule behind the pulse is neither in free flight
     * nor at rest in a way the gap slot can follow (its contacts keep
     * pushing about the loaded equilibrium): none leaves, the window only
     * grows (exact, at the cost of integrating the chain behind the
     * pulse).  Kuwabara-Kono damping never pulls, so with open contacts a
     * granule flies freely and both criteria hold as for the paper's
     * chain; the damping part of a compression left at rest (criterion 2)
     * has the impulse r damping z^(n-1) while it closes, a fixed multiple
     * of the elastic force bound below. */
    if (!sim->state.window || !sim->model.free_flight) return stays;
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_entries(sim);
    const size_t j = d->lo;
    if (j + 2 >= d->hi || j >= sim->pulse.next_pass || j >= sim->pulse.next_peak) return stays;
    /* A moving piston stays: its stop sets its velocity in the state
     * (solve.c); once stopped it is a wall at rest and may leave. */
    if (j == 1 && sim->piston_moving) return stays;
    const double v = taper_dyn_v(d, y, j), v_next = taper_dyn_v(d, y, j + 1);
    const double z = taper_dyn_z(d, y, j);
    const double z_back = j > 1 ? y[0] : -INFINITY; /* gap z_{j-1} */
    const double v_back = j > 1 ? taper_dyn_v_left(d, sim->t) : -INFINITY;
    const double rtol = sim->spec.rtol, atol = sim->spec.atol;
    const double v_ref = sim->pulse.v_ref, z_ref = sim->pulse.z_ref;
    const double v_eps = REST_FACTOR * (rtol * fabs(v_ref) + atol * sim->v_scale[j - 1]);
    const double z_eps = REST_FACTOR * (rtol * fabs(z_ref) + atol * sim->z_scale[j - 1]);
    const double z_eps_back = j > 1 ? REST_FACTOR * (rtol * fabs(z_ref) + atol * sim->z_scale[j - 2]) : 0.0;
    /* Criterion 1: gaps open beyond the tolerance's compression and not
     * closing (under drag: not for ever, drag_gap_stays_open). */
    if (z < -z_eps && v <= v_next && z_back < -z_eps_back && v_back <= v &&
        drag_gap_stays_open(sim, j, z_back, v_back, v, z_eps_back))
        return (taper_departure){TAPER_LEAVES_FREE, 0.0};
    /* Criterion 2: at rest within the tolerance, relative to the granule
     * behind (which left before and flies freely; rest itself for j = 1),
     * or relative to the granule ahead where the one behind flies away and
     * the two never meet again (a recoil far above v_eps, then rest);
     * open gaps of any size are harmless (no force), only compressions are
     * bounded, so that the one-sided force they leave is below the
     * tolerance. */
    const double v_rest = j > 1 ? v_back : 0.0;
    const int behind_apart = j > 1 && z_back < 0.0 && v_back <= v;
    const int resting = fabs(v - v_rest) <= v_eps || (behind_apart && fabs(v - v_next) <= v_eps);
    const double z_rest = resting_compression(sim, j, z_eps);
    if (resting && z <= z_rest && z_back <= z_rest)
        return (taper_departure){TAPER_LEAVES_AT_REST, WATCH_FACTOR / REST_FACTOR * z_rest};
    return stays;
}
