/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * events.c -- pulse events located exactly by the stepper's root finder
 * (CVODE's, rk8's: stepper.h), on the root functions defined here.  Writes
 * only sim->pulse (the rings, the references, the observables); tells the
 * run loop what a root return asks of the window (taper_root_report) and
 * leaves the window to it.
 *
 *  pass(k): g = v_{k+1} - v_k crosses zero upward (the pulse passes k);
 *  peak(k): the acceleration of k changes sign downward while v_k > 0,
 *           g = rho_{k-1} z_{k-1} - rho_k z_k (see dynamics.h);
 *  grow:    z_hi - threshold reaches zero (the front reaches hi+1);
 *  gap:     the gap z_{lo-1} behind the window closes: its compression
 *           crosses gap_watch[lo-1] upward (0 after an exact free-flight
 *           departure, a noise-proof threshold after a departure at rest;
 *           see window.c).
 *
 * Only the granules of a ring of pass slots and a ring of peak slots that
 * follow the front are watched, never N: granules ahead of the window are
 * at rest and those behind it have every event known, so only window
 * granules can have an event.  The stepper sees each ring as two root
 * functions, the next granule's and the largest (smallest) of the others'
 * ("the stepper's root functions", below).
 *
 * A slot is armed only while its granule moves at a velocity above
 * ARM_FRACTION of the pulse velocity v_ref (arm_velocity); otherwise it
 * returns a fixed non-zero value of the "nothing happened yet" sign.  Below
 * that, the precursor's signs are no pulse event, and with SUNDIALS 6.4.1
 * (glo*ghi < 0, fixed upstream in 6.5) they would also underflow.  In the
 * precursor of a Hertzian chain v_k > v_{k+1} and the acceleration is
 * positive, so arming late misses no crossing of the pulse; the pass slot
 * of the next granule the pulse must pass is always armed, because at the
 * event that makes it next its velocity equals the pulse velocity.
 *
 * Where the root finder compares signs (rk8's; CVODE's from SUNDIALS 6.5,
 * or the bundled 6.4.1 with our backport) and the contact exponent is at
 * least 2 (pulse.arm_all, taper_events_arm), every event is armed from the
 * start of the pulse: the rings grow (at root returns,
 * taper_events_fit_rings) to cover every window granule whose event is
 * unknown, so their size is bounded by the window's (7-8 slots each on
 * paper chains), and an event several granules ahead of the lowest unknown
 * one is seen (the light granules of steep forward chains, passed out of
 * order within 1e-12 t).  With Debian's 6.4.1 (no fix) the rings stay at
 * TAPER_RING_SLOTS (today's behaviour, byte-identical): events beyond the
 * ring are found only as jumps when the ring reaches them (nan, counted in
 * the log).  So do exponents below 2: their force z^(n-1) is strong at tiny
 * compressions, and the precursor far ahead overtakes (v_{k+1} > v_k at
 * velocities above ARM_FRACTION v_ref) and reverses long before the pulse
 * arrives; a grown ring took that for passes (backward linear S = 0.5,
 * N = 1000, n = 3/2: 7-9 pass times nan).  With Debian's 6.4.1 the pass
 * time of such chains is the first crossing once the granule is within 3
 * of the lowest unknown; with a root finder that compares signs it is a
 * leading pass (below).
 *
 * Leading passes (n < 2, pulse.lead).  The paper's pass, v_{k+1}
 * surpassing v_k, is the pulse moving on from k to k+1: at that moment k
 * carries the pulse's front, no granule behind it moves faster.  The
 * precursor's crossings are far ahead of the pulse, at velocities 1e-17 to
 * 1e-11 of it (forward exponential q = 0.05, N = 60, n = 3/2: from t = 4e-8
 * on, where the pulse arrives at t ~ 10).  So below n = 2 the pass
 * of k is the first time that v_{k+1} >= v_k >= v_j for every window
 * granule j < k (docs/design.md, "The pass time below n = 2"), the zero
 * crossing upward of
 *     g = min(v_{k+1} - v_k, v_k - max_{lo <= j < k} v_j),
 * continuous, never identically zero, and equal to v_{k+1} - v_k near the
 * root wherever the pulse moves granule by granule (its second term is then
 * of the pulse's size).  No arming threshold is needed: every window
 * granule whose pass is unknown has a slot.  On the light end of a steep
 * forward taper, which the precursor has set moving as a block, these are
 * the granules the front crosses (passes out of order by up to 1e-3 of t
 * there), where the first crossing within a ring of 3 had left 5 of 59 nan.
 *
 * Either way a granule at rest is unarmed: its functions would be exactly
 * zero, which CVODE takes for a root at every step.
 *
 * Walls (one slot each after the gap slot): the largest force of a wall is
 * where its force stops growing, dF/dt crossing zero downward while the
 * contact pushes.  Elastic contacts: F = r s^(n-1) grows with the
 * compression s, so the function is the rate of compression dz/dt; with
 * Kuwabara-Kono damping dF/dt = r (n-1) s^(n-2) [dz/dt + damping ((n-2)
 * (dz/dt)^2 / s + d^2z/dt^2)], whose bracket is the function.  Every
 * maximum is a root; the largest is kept (walls.peak_force).  The function
 * is +1 while the contact does not push, so the contact's opening is a jump
 * upward from the falling force's negative rate: the right wall's slot is
 * watched both ways, and the run stops there, at the end of the wall's
 * first contact (taper_events_walls_settled), its impulse the contact's
 * whole impulse.
 *
 * Chains with damping or drag: the acceleration of k is no longer
 * F_{k-1} - F_k over m_k, and the peak function is the force balance itself,
 * F_{k-1} - F_k - drag v_k (taper_dyn_peak_terms); armed only while v_k > 0,
 * where drag keeps it off zero even with both contacts open.
 */
#include "sim.h"

#include <float.h>
#include <math.h>

#define ARM_FRACTION 1e-6

/* Velocity above which a granule's slots are armed, in both modes.  Not
 * only an underflow guard: ahead of the pulse, v_{k+1} - v_k and the
 * acceleration can change sign at velocities that are no pulse event.
 * Backward linear S = 0.5, N = 10 with contact exponent 3/2 (a force
 * z^(1/2), strong at tiny compressions): the precursor of granule 9
 * overtakes it at t = 0.004 with v ~ 1e-13, long before the pulse passes
 * at t = 25; forward exponential q = 0.05, N = 100 at max order 9: a noise
 * "peak" of granule 6 at v = 2e-38.  Armed at any v > 0, as they once were, these
 * were taken for the pass and the peak. */
static double arm_velocity(const taper_sim *sim) { return ARM_FRACTION * sim->pulse.v_ref; }

static double velocity(const taper_sim *sim, const double *y, size_t k)
{
    const taper_dyn *d = &sim->dyn;
    return k <= d->hi ? taper_dyn_v(d, y, k) : 0.0;
}

/* A genuine root has g ~ 0 at the returned time; a slot armed while its
 * event had already happened jumps from the "nothing yet" value to one of the
 * other sign, which CVODE also reports.  Relative size of |g| that tells
 * them apart (CVODE locates roots to ~1e-14 in time). */
#define GENUINE_ROOT 1e-3

static int known(const taper_sim *sim, size_t k, unsigned bit) { return sim->pulse.events[k - 1] & bit; }

/* A carried body and its carrier (sim.c, "A light end carried") move as
 * one: v_c - v_(c-1) and the rider's peak function are identically zero.
 * Their events are those of the granules the limit gives them
 * (carry_pass, record_peak, carry_untimed). */
static int carrier(const taper_sim *sim, size_t k) { return sim->dyn.carried && k + 1 == sim->dyn.carried; }

static int pass_armed(const taper_sim *sim, const double *y, size_t k)
{
    if (k > sim->pass_limit || k > sim->dyn.hi || known(sim, k, TAPER_EV_PASS) || carrier(sim, k)) return 0;
    return sim->pulse.lead || k == sim->pulse.next_pass || velocity(sim, y, k) > arm_velocity(sim);
}

/* Leading passes: the fastest window granule behind k, lo..k-1 (*which:
 * its index; -INFINITY and 0 for k = lo). */
static double fastest_behind(const taper_sim *sim, const double *y, size_t k, size_t *which)
{
    const taper_dyn *d = &sim->dyn;
    double v = -INFINITY;
    *which = 0;
    for (size_t j = d->lo; j < k && j <= d->hi; j++)
        if (taper_dyn_v(d, y, j) > v) v = taper_dyn_v(d, y, j), *which = j;
    return v;
}

/* The leading pass function of k, given the fastest velocity behind it. */
static double lead_value(double v, double v_next, double behind) { return fmin(v_next - v, v - behind); }

/* The pass function's value: v_{k+1} - v_k, or the leading pass's. */
static double pass_value(const taper_sim *sim, const double *y, size_t k)
{
    if (!sim->pulse.lead) return velocity(sim, y, k + 1) - velocity(sim, y, k);
    size_t j;
    return lead_value(velocity(sim, y, k), velocity(sim, y, k + 1), fastest_behind(sim, y, k, &j));
}

static double pass_function(const taper_sim *sim, const double *y, size_t k)
{
    if (!pass_armed(sim, y, k)) return -1.0;
    return pass_value(sim, y, k);
}

static int peak_armed(const taper_sim *sim, const double *y, size_t k)
{
    if (k > sim->target || k > sim->dyn.hi || known(sim, k, TAPER_EV_PEAK) || k == sim->dyn.carried) return 0;
    return velocity(sim, y, k) > arm_velocity(sim);
}

static double peak_function(const taper_sim *sim, const double *y, size_t k)
{
    if (!peak_armed(sim, y, k)) return 1.0;
    return taper_dyn_peak_function(&sim->dyn, y, k);
}

/* ---- the stepper's root functions ------------------------------------------
 * The rings watch every pending event of the window (8 passes and 7 peaks
 * on a monodisperse chain), but the stepper sees six root functions and
 * one per wall, never one per granule:
 *
 *   SLOT_PASS, SLOT_PEAK  the pass of next_pass, the peak of next_peak:
 *                         the event the pulse brings next, which is the
 *                         root of nearly every root return;
 *   SLOT_PASSES_AHEAD     the largest pass function of the ring's other
 *                         granules (next_pass + 1 ...), -1 if none;
 *   SLOT_PEAKS_AHEAD      the smallest peak function of the ring's others;
 *   SLOT_GROW, SLOT_GAP, then one per wall (SLOT_WALLS).
 *
 * Why a group loses no root.  A root finder that watches functions through
 * a step (CVODE's cvRootfind, rk8's) compares each function's sign at the
 * step's ends and, where one differs, narrows the bracket to the earliest
 * change of sign; a function that changes sign and back within one step is
 * not seen (CVODE's documented contract).  After every root return each
 * watched pass function is negative (events.c records the granules that
 * crossed, and advance_rings marks as known, untimed, any armed one that is
 * not negative; a known or unarmed granule's function is the constant -1).
 * So the group's largest value is negative at a step's start and is
 * positive (or zero) at a time exactly when some member's is: the group
 * changes sign in a step exactly when some member does, and the earliest
 * time at which any member has crossed is the earliest time at which the
 * group has: the root finder stops where it would have stopped with one
 * function per granule, and the members that crossed there are those whose
 * function is >= 0 in the state returned (taper_events_record).  The peak
 * group is the same with the signs reversed.  Near the root the group is
 * the crossing member's own function (the others are below it), so the
 * root is located as precisely.
 *
 * What it saves: CVODE's root finder loops over every function at every
 * step (three times: signs, activity, the copy of the values) and at every
 * iteration of its search; 17 functions cost it ~1000 instructions per
 * step on monodisperse chains, and the values' sweep another ~500
 * (CHANGELOG.md: six and one per wall instead of 17). */
enum {
    SLOT_PASS,
    SLOT_PASSES_AHEAD,
    SLOT_PEAK,
    SLOT_PEAKS_AHEAD,
    SLOT_GROW,
    SLOT_GAP,
    SLOT_WALLS
};

/* The rings' functions, the next granule's in g[SLOT_PASS] and
 * g[SLOT_PEAK], the others' largest (passes) and smallest (peaks) in the
 * groups: the values of pass_function and peak_function, computed in one
 * sweep without their per-granule look-ups (CVODE calls the root function
 * once per step and ~10 times per located root). */
static void ring_values(const taper_sim *sim, const double *y, double *g)
{
    const taper_dyn *d = &sim->dyn;
    const taper_pulse *p = &sim->pulse;
    const unsigned char *events = p->events;
    const size_t begin = taper_dyn_begin(d), hi = d->hi, carried = d->carried;
    const double v_armed = arm_velocity(sim);
    /* granule k >= lo: v_k = y[2 k - 2 - begin], z_k = y[2 k - 1 - begin]
     * (taper_idx_v, taper_idx_z), the window's granules only: lo <=
     * next_pass, next_peak (dynamics.h) */
    const size_t last_pass = hi < sim->pass_limit ? hi : sim->pass_limit;
    const size_t end_pass = p->next_pass + p->pass_slots; /* the ring: next_pass .. end_pass - 1 */
    double next = -1.0, ahead = -1.0;
    if (p->lead) { /* one sweep: the fastest behind each granule */
        double behind = -INFINITY;
        for (size_t k = d->lo; k < p->next_pass && k <= hi; k++) behind = fmax(behind, y[2 * k - 2 - begin]);
        for (size_t k = p->next_pass; k < end_pass && k <= last_pass; k++) {
            const double vk = y[2 * k - 2 - begin];
            if (!(events[k - 1] & TAPER_EV_PASS)) {
                const double gk = lead_value(vk, k < hi ? y[2 * k - begin] : 0.0, behind);
                if (k == p->next_pass) next = gk;
                else if (gk > ahead) ahead = gk;
            }
            behind = fmax(behind, vk);
        }
    } else if (p->next_pass <= last_pass) {
        const size_t first = p->next_pass, stop = end_pass < last_pass + 1 ? end_pass : last_pass + 1;
        const double *v = y + (2 * first - 2 - begin); /* v_k, k = first, first + 1, ... */
        if (!(events[first - 1] & TAPER_EV_PASS) && first + 1 != carried)
            next = (first < hi ? v[2] : 0.0) - v[0];
        for (size_t k = first + 1; k < stop; k++) {
            v += 2;
            if (!(*v > v_armed) || (events[k - 1] & TAPER_EV_PASS) || k + 1 == carried) continue;
            const double gk = (k < hi ? v[2] : 0.0) - *v;
            if (gk > ahead) ahead = gk;
        }
    }
    g[SLOT_PASS] = next;
    g[SLOT_PASSES_AHEAD] = ahead;
    const size_t last_peak = hi < sim->target ? hi : sim->target;
    const size_t end_peak = p->next_peak + p->peak_slots;
    const size_t stop = end_peak < last_peak + 1 ? end_peak : last_peak + 1;
    next = ahead = 1.0;
    /* v_k; z_k is v[1], z_{k-1} v[-1] (the window's entries only) */
    const double *v = p->next_peak < stop ? y + (2 * p->next_peak - 2 - begin) : y;
    for (size_t k = p->next_peak; k < stop; k++, v += 2) {
        if (!(*v > v_armed) || (events[k - 1] & TAPER_EV_PEAK) || k == carried) continue;
        double gk;
        if (d->dissipative) {
            gk = taper_dyn_peak_function(d, y, k);
        } else {
            const double left = k > 1 ? d->rho[k - 2] * v[-1] : 0.0;
            gk = left - d->rho[k - 1] * v[1];
        }
        if (k == p->next_peak) next = gk;
        else if (gk < ahead) ahead = gk;
    }
    g[SLOT_PEAK] = next;
    g[SLOT_PEAKS_AHEAD] = ahead;
}

/* CVODE returns a root within 100 uround (|t| + |h|) of the true zero
 * (cvRootfind's ttol); a genuine root's function value is at most its rate
 * of change times that, with a margin. */
#define ROOT_TIME_RESOLUTION (1e3 * DBL_EPSILON)

/* Velocity of granule j >= lo - 1: the free-flying neighbour behind the
 * window, a window granule, or at rest ahead of it. */
static double velocity_from_behind(const taper_sim *sim, const double *y, size_t j)
{
    return j + 1 == sim->dyn.lo ? taper_dyn_v_left(&sim->dyn, sim->t) : velocity(sim, y, j);
}

/* Whether the peak function's value at a root is a genuine zero: small
 * against its present terms, or against their binary-collision size (the
 * last granule peaks as its only contact opens, where both terms vanish),
 * or against what the root's location in time resolves: late in long
 * chains (t > ~5e4 collision times, monodisperse N >= 1e5) the last
 * granule's root is off zero by |dg/dt| 2e-14 t, above 1e-9 of the
 * typical value, and its peak was taken for one that happened before its
 * slot was armed. */
static int genuine_peak_root(const taper_sim *sim, const double *y, size_t k)
{
    const taper_dyn *d = &sim->dyn;
    if (d->dissipative) { /* forces: against their sizes and the contact's force scale */
        double l, r;
        taper_dyn_peak_terms(d, y, k, &l, &r);
        double scale = d->contact[k - 1] * pow(sim->z_scale[k - 1], sim->exponent - 1.0);
        double g = fabs(l - r);
        return g <= GENUINE_ROOT * (fabs(l) + fabs(r)) || g <= 1e-9 * (isfinite(scale) ? scale : 0.0);
    }
    /* the terms of taper_dyn_peak_function: the gap slot (k = lo > 1)
     * pushes nothing */
    const int behind = k > d->lo;
    double left = behind ? d->rho[k - 2] * taper_dyn_z(d, y, k - 1) : 0.0;
    double right = d->rho[k - 1] * taper_dyn_z(d, y, k);
    double typical = (k > 1 ? d->rho[k - 2] * sim->z_scale[k - 2] : 0.0) + d->rho[k - 1] * sim->z_scale[k - 1];
    double v = velocity(sim, y, k), v_next = velocity(sim, y, k + 1);
    double rate = (behind ? d->rho[k - 2] * (velocity_from_behind(sim, y, k - 1) - v) : 0.0) -
                  d->rho[k - 1] * (v - v_next); /* dg/dt: dz_j/dt = v_j - v_{j+1} */
    double g = fabs(left - right);
    return g <= GENUINE_ROOT * (fabs(left) + fabs(right)) || g <= 1e-9 * typical ||
           g <= ROOT_TIME_RESOLUTION * fabs(rate) * fabs(sim->t);
}

/* A wall's contact: k (bodies k, k+1) and the granule's body g, and
 * whether the window holds it (a left wall's while the wall is in the
 * window: let go, it is the gap slot, which pushes nothing; a right wall's
 * once the window reaches it). */
static int wall_contact(const taper_sim *sim, int end, size_t *k, size_t *g)
{
    const taper_dyn *d = &sim->dyn;
    if (end == TAPER_LEFT) {
        *k = 1, *g = 2;
        return d->lo == 1 && d->hi >= 2;
    }
    *k = d->n - 1, *g = d->n - 1;
    return d->hi == d->n;
}

/* The wall's dF/dt up to a positive factor while its contact pushes, +1
 * otherwise (see the top of this file). */
static double wall_rate(const taper_sim *sim, const double *y, int end)
{
    const taper_dyn *d = &sim->dyn;
    size_t k, g;
    if (!wall_contact(sim, end, &k, &g)) return 1.0;
    const double sign = end == TAPER_LEFT ? -1.0 : 1.0; /* dz/dt = sign v_g: the wall rests */
    const double z = taper_dyn_z(d, y, k);
    double zdot = sign * taper_dyn_v(d, y, g);
    if (end == TAPER_LEFT && sim->piston_moving) zdot += taper_dyn_v(d, y, 1); /* it moves */
    if (!(taper_dyn_contact_force(d, k, z, zdot) > 0.0)) return 1.0;
    double rate = zdot;
    if (d->damping > 0.0) {
        const double s = (d->delta ? d->delta[k - 1] : 0.0) + z;
        const double zddot = sign * taper_dyn_acceleration(d, y, g);
        const double curvature = s > 0.0 ? (d->exponent - 2.0) * zdot * zdot / s : 0.0;
        rate += d->damping * (curvature + zddot);
    }
    /* Exactly 0: the granule rests against the wall (a loaded chain before
     * the pulse, a granule that has just joined the window), where CVODE
     * would take the function for a root at every step (flag -22): no
     * maximum there.  A genuine maximum only passes through 0. */
    return rate != 0.0 ? rate : 1.0;
}

static void record_wall(taper_sim *sim, const double *y, int end)
{
    size_t k, g;
    if (!wall_contact(sim, end, &k, &g)) return;
    const double force = taper_dyn_window_force(&sim->dyn, y, k);
    if (isnan(sim->walls.peak_force[end]) || force > sim->walls.peak_force[end]) {
        sim->walls.peak_force[end] = force;
        sim->walls.peak_time[end] = taper_sim_true_time(sim, sim->t);
    }
}

void taper_events_root_values(const taper_sim *sim, const double *y, double *g)
{
    const taper_dyn *d = &sim->dyn;
    ring_values(sim, y, g);
    /* The growth needs no location in time: the granule joins where the
     * stepper's step ends (solve.c, grow), with its zero state and history.
     * So its function stops at 0 once z_hi reaches the threshold: a root
     * finder that sees a function go from negative to exactly 0 at the
     * step's end reports a root there without searching (CVODE's
     * cvRootfind: a zero at thi, no sign change; rk8's crossing: b >= 0),
     * where a sign change cost CVODE ~8 evaluations of the interpolant and
     * of every root function.  The growth that follows makes the function
     * negative again (the new granule's compression is 0): it is never 0
     * at a step's start, which CVODE would take for a root there. */
    const double grow = d->hi < d->n ? taper_dyn_z(d, y, d->hi) - sim->grow_z[d->hi - 1] : -1.0;
    g[SLOT_GROW] = grow < 0.0 ? grow : 0.0;
    g[SLOT_GAP] = d->lo > 1 ? y[0] - sim->out.gap_watch[d->lo - 2] : -1.0;
    size_t slot = SLOT_WALLS;
    if (sim->model.wall_left) g[slot++] = wall_rate(sim, y, TAPER_LEFT);
    if (sim->model.wall_right) g[slot] = wall_rate(sim, y, TAPER_RIGHT);
}

static size_t wall_slots(const taper_sim *sim)
{
    return (size_t)(sim->model.wall_left != 0) + (size_t)(sim->model.wall_right != 0);
}

/* Rings that grow need a precursor without crossings, as the Hertzian one
 * (above); below n = 2 the force z^(n-1) is strong at tiny compressions and
 * the precursor overtakes long before the pulse: there a pass is a crossing
 * of the granule that leads ("leading passes"), which the precursor's
 * crossings are not.  Either needs a root finder that compares signs. */
void taper_events_arm(taper_sim *sim, int sees_tiny_sign_changes)
{
    sim->pulse.arm_all = sim->exponent >= 2.0 && sees_tiny_sign_changes;
    sim->pulse.lead = sim->exponent < 2.0 && sees_tiny_sign_changes;
}

size_t taper_events_grow_slot(const taper_sim *sim)
{
    (void)sim;
    return SLOT_GROW;
}

size_t taper_events_slots(const taper_sim *sim) { return SLOT_WALLS + wall_slots(sim); }

void taper_events_directions(const taper_sim *sim, int *directions)
{
    for (size_t i = 0; i < taper_events_slots(sim); i++) directions[i] = 1;
    directions[SLOT_PEAK] = directions[SLOT_PEAKS_AHEAD] = -1;
    for (size_t i = 0; i < wall_slots(sim); i++) directions[SLOT_WALLS + i] = -1;
    /* the right wall's both ways: a peak down, the contact's opening up
     * (and a minimum of its force while it pushes, which only returns to
     * the caller) */
    if (sim->model.wall_right) directions[SLOT_WALLS + wall_slots(sim) - 1] = 0;
}

/* Slots a ring needs so that granules first..last all have one. */
static size_t ring_needed(size_t first, size_t last) { return last >= first ? last - first + 1 : 1; }

/* A ring grows to what it needs (a handful of re-inits per run: the
 * window's size settles within the first granules). */
static int fit_ring(size_t *slots, size_t needed)
{
    if (needed <= *slots) return 0;
    *slots = needed;
    return 1;
}

int taper_events_fit_rings(taper_sim *sim)
{
    taper_pulse *p = &sim->pulse;
    if (!p->arm_all && !p->lead) return 0; /* leading passes: the pass ring only */
    /* Granules ahead of hi are at rest: no event until a root return grows
     * the window.  Granule hi keeps its slots (its back contact may open
     * before the front reaches hi+1: a peak as the contact opens). */
    const size_t hi = sim->dyn.hi, slots = taper_events_slots(sim);
    fit_ring(&p->pass_slots, ring_needed(p->next_pass, hi < sim->pass_limit ? hi : sim->pass_limit));
    if (p->arm_all) fit_ring(&p->peak_slots, ring_needed(p->next_peak, hi < sim->target ? hi : sim->target));
    /* (a ring's granules beyond the next are one root function, however
     * many: the stepper's functions stay as they were) */
    return taper_events_slots(sim) != slots;
}

/* Acceleration of granule k as the equations of motion have it (0 ahead
 * of the window; the contact (hi, hi+1) is not integrated and the gap slot
 * pushes nothing, dynamics.h): taper_dyn_acceleration, which is the
 * right-hand side's own force law for the paper's chain too (no load, no
 * losses), so the two cannot disagree. */
static double acceleration(const taper_sim *sim, const double *y, size_t k)
{
    return taper_dyn_acceleration(&sim->dyn, y, k);
}

/* Whether the pass function's value at a root is a genuine zero: small
 * against the velocities, or, where every root is armed from the start
 * (no slot can jump), against what the root's location in time resolves.
 * The last, lightest granules of steep forward chains are passed within
 * 1e-12 t of each other: q = 0.3, N = 100, granule 98 at t = 3.47 has
 * |g| = 1.5e-3 of its velocity 137 at the root CVODE returns, with
 * dg/dt ~ 1e11. */
static int genuine_pass_root(const taper_sim *sim, const double *y, size_t k)
{
    double g = fabs(pass_value(sim, y, k));
    if (g <= GENUINE_ROOT * fmax(fabs(velocity(sim, y, k)), fabs(velocity(sim, y, k + 1)))) return 1;
    double rate = fabs(acceleration(sim, y, k + 1) - acceleration(sim, y, k));
    if (sim->pulse.lead) { /* or the rate of the second term, v_k - v_j */
        size_t j;
        fastest_behind(sim, y, k, &j);
        if (j) rate = fmax(rate, fabs(acceleration(sim, y, k) - acceleration(sim, y, j)));
    }
    return (sim->pulse.arm_all || sim->pulse.lead) && g <= ROOT_TIME_RESOLUTION * rate * fabs(sim->t);
}

/* The root functions' values for the stepper's refine_root: pass_value
 * above. */

static double peak_value(const taper_sim *sim, const double *y, size_t k)
{
    return taper_dyn_peak_function(&sim->dyn, y, k);
}

/* The carrier's pass (granule k+1) is granule k's (sim.c, "A light end carried"),
 * at the same time, where the carrier is in y. */
static void carry_pass(taper_sim *sim, const double *y, size_t k)
{
    const size_t c = k + 1;
    if (!carrier(sim, c) || c > sim->pass_limit || known(sim, c, TAPER_EV_PASS)) return;
    sim->pulse.events[c - 1] |= TAPER_EV_PASS;
    sim->pulse.obs[TAPER_T_PASS][c - 1] = sim->pulse.obs[TAPER_T_PASS][k - 1];
    sim->pulse.obs[TAPER_X_PASS][c - 1] = sim->rest[c - 1] + taper_dyn_position(&sim->dyn, y, c);
}

/* The observables of an event are those of the state at its zero as the
 * stepper locates it (`where`: to a few ulps of t below
 * TAPER_REFINE_BELOW_RTOL, CVODE's on its interpolant), at the true time
 * (taper_sim_true_time); y, the state the stepper returned, decides only
 * whether the root is genuine. */
static void record_pass(taper_sim *sim, const double *y, size_t k, taper_root_locator where)
{
    const taper_dyn *d = &sim->dyn;
    sim->pulse.events[k - 1] |= TAPER_EV_PASS;
    if (!genuine_pass_root(sim, y, k)) {
        sim->pulse.untimed_passes++; /* passed before its slot was armed */
        return;
    }
    const double t = where.refine(where.stepper, pass_value, k, &y);
    sim->pulse.obs[TAPER_T_PASS][k - 1] = taper_sim_true_time(sim, t);
    sim->pulse.obs[TAPER_X_PASS][k - 1] = sim->rest[k - 1] + taper_dyn_position(d, y, k);
    carry_pass(sim, y, k);
    double v = velocity(sim, y, k + 1);
    if (v > 0.0) sim->pulse.v_ref = v;
    double z = taper_dyn_z(d, y, k);
    if (z > 0.0) sim->pulse.z_ref = z;
}

static void record_peak(taper_sim *sim, const double *y, size_t k, taper_root_locator where)
{
    double v = velocity(sim, y, k);
    if (!(v > 0.0)) return; /* a maximum while moving backwards is no pulse peak */
    sim->pulse.events[k - 1] |= TAPER_EV_PEAK;
    if (!genuine_peak_root(sim, y, k)) {
        sim->pulse.untimed_peaks++; /* peaked before its slot was armed */
        return;
    }
    const double t = where.refine(where.stepper, peak_value, k, &y);
    sim->pulse.obs[TAPER_V_PEAK][k - 1] = velocity(sim, y, k);
    sim->pulse.obs[TAPER_T_PEAK][k - 1] = taper_sim_true_time(sim, t);
    if (carrier(sim, k) && k + 1 <= sim->target && !known(sim, k + 1, TAPER_EV_PEAK)) {
        /* the rider peaks with its carrier */
        sim->pulse.events[k] |= TAPER_EV_PEAK;
        sim->pulse.obs[TAPER_V_PEAK][k] = sim->pulse.obs[TAPER_V_PEAK][k - 1];
        sim->pulse.obs[TAPER_T_PEAK][k] = sim->pulse.obs[TAPER_T_PEAK][k - 1];
    }
}

/* A carried pair's events follow those they are given (above) when these
 * were found untimed: untimed too, so that the run does not wait for them. */
static int carry_untimed(taper_sim *sim)
{
    const size_t c = sim->dyn.carried;
    int moved = 0;
    if (!c) return 0;
    if (c - 1 <= sim->pass_limit && known(sim, c - 2, TAPER_EV_PASS) && !known(sim, c - 1, TAPER_EV_PASS)) {
        sim->pulse.events[c - 2] |= TAPER_EV_PASS;
        sim->pulse.untimed_passes++;
        moved = 1;
    }
    if (c <= sim->target && known(sim, c - 1, TAPER_EV_PEAK) && !known(sim, c, TAPER_EV_PEAK)) {
        sim->pulse.events[c - 1] |= TAPER_EV_PEAK;
        sim->pulse.untimed_peaks++;
        moved = 1;
    }
    return moved;
}

/* Moves the rings past known events.  A granule that enters a ring with its
 * event already behind it (v_{k+1} > v_k, or decelerating while moving
 * forward, while armed) can never produce a sign change: it is marked known
 * and untimed rather than waited for for ever (steep forward chains, where
 * light granules overtake in the precursor). */
static void advance_rings(taper_sim *sim, const double *y)
{
    for (int moved = 1; moved;) {
        moved = carry_untimed(sim);
        while (sim->pulse.next_pass <= sim->pass_limit && known(sim, sim->pulse.next_pass, TAPER_EV_PASS))
            sim->pulse.next_pass++;
        while (sim->pulse.next_peak <= sim->target && known(sim, sim->pulse.next_peak, TAPER_EV_PEAK))
            sim->pulse.next_peak++;
        /* (leading passes: the fastest behind, swept along, not searched
         * again for each granule) */
        size_t j;
        double behind = sim->pulse.lead ? fastest_behind(sim, y, sim->pulse.next_pass, &j) : 0.0;
        for (size_t k = sim->pulse.next_pass; k < sim->pulse.next_pass + sim->pulse.pass_slots; k++) {
            const int armed = pass_armed(sim, y, k);
            const double g = !armed ? -1.0
                             : sim->pulse.lead ? lead_value(velocity(sim, y, k), velocity(sim, y, k + 1), behind)
                                               : pass_function(sim, y, k);
            if (sim->pulse.lead && k >= sim->dyn.lo && k <= sim->dyn.hi) behind = fmax(behind, velocity(sim, y, k));
            if (armed && g > 0.0) {
                sim->pulse.events[k - 1] |= TAPER_EV_PASS;
                sim->pulse.untimed_passes++;
                moved = 1;
            }
        }
        for (size_t k = sim->pulse.next_peak; k < sim->pulse.next_peak + sim->pulse.peak_slots; k++)
            if (peak_armed(sim, y, k) && peak_function(sim, y, k) < 0.0) {
                sim->pulse.events[k - 1] |= TAPER_EV_PEAK;
                sim->pulse.untimed_peaks++;
                moved = 1;
            }
    }
}

/* Marks, for the root return being recorded, of the granules of a group
 * whose event the return holds (pulse.events' own bits are TAPER_EV_*). */
#define FOUND_PASS 4u
#define FOUND_PEAK 8u

/* The granules of the ahead groups whose function has crossed in the state
 * y the stepper returned (>= 0 for a pass, <= 0 for a peak: "Why a group
 * loses no root" above), marked before any event is recorded: recording
 * one moves v_ref, which arms others. */
static void mark_crossed(taper_sim *sim, const double *y, const int *roots_found)
{
    taper_pulse *p = &sim->pulse;
    if (roots_found[SLOT_PASSES_AHEAD] > 0)
        for (size_t k = p->next_pass + 1; k < p->next_pass + p->pass_slots && k <= sim->pass_limit; k++)
            if (pass_armed(sim, y, k) && pass_function(sim, y, k) >= 0.0) p->events[k - 1] |= FOUND_PASS;
    if (roots_found[SLOT_PEAKS_AHEAD] < 0)
        for (size_t k = p->next_peak + 1; k < p->next_peak + p->peak_slots && k <= sim->target; k++)
            if (peak_armed(sim, y, k) && peak_function(sim, y, k) <= 0.0) p->events[k - 1] |= FOUND_PEAK;
}

taper_root_report taper_events_record(taper_sim *sim, const int *roots_found, taper_root_locator where)
{
    const double *y = taper_sim_entries(sim);
    taper_pulse *p = &sim->pulse;
    const size_t passed_before = p->next_pass;
    mark_crossed(sim, y, roots_found);
    /* Granules in increasing order, the next first, as the ring was when
     * the stepper evaluated the functions. */
    const size_t next_pass = p->next_pass, next_peak = p->next_peak;
    if (roots_found[SLOT_PASS] > 0 && next_pass <= sim->pass_limit) record_pass(sim, y, next_pass, where);
    for (size_t k = next_pass + 1; k < next_pass + p->pass_slots && k <= sim->pass_limit; k++)
        if (p->events[k - 1] & FOUND_PASS) {
            p->events[k - 1] &= (unsigned char)~FOUND_PASS;
            record_pass(sim, y, k, where);
        }
    if (roots_found[SLOT_PEAK] < 0 && next_peak <= sim->target) record_peak(sim, y, next_peak, where);
    for (size_t k = next_peak + 1; k < next_peak + p->peak_slots && k <= sim->target; k++)
        if (p->events[k - 1] & FOUND_PEAK) {
            p->events[k - 1] &= (unsigned char)~FOUND_PEAK;
            record_peak(sim, y, k, where);
        }
    advance_rings(sim, y);
    size_t slot = SLOT_WALLS;
    if (sim->model.wall_left && roots_found[slot++] < 0) record_wall(sim, y, TAPER_LEFT);
    if (sim->model.wall_right && roots_found[slot] < 0) record_wall(sim, y, TAPER_RIGHT);
    return (taper_root_report){
        .grow = roots_found[SLOT_GROW] > 0,
        .gap_closed = roots_found[SLOT_GAP] > 0,
        .passed = p->next_pass != passed_before,
    };
}

void taper_events_piston_stopped(taper_sim *sim)
{
    const double *y = taper_sim_entries(sim);
    /* v_2 - v_1 jumps to v_2 > 0 when v_1 did not reach 1: the pass */
    if (sim->pulse.next_pass == 1 && !known(sim, 1, TAPER_EV_PASS)) {
        sim->pulse.events[0] |= TAPER_EV_PASS;
        sim->pulse.obs[TAPER_T_PASS][0] = taper_sim_true_time(sim, sim->t);
        sim->pulse.obs[TAPER_X_PASS][0] = sim->rest[0] + taper_dyn_position(&sim->dyn, y, 1);
        if (velocity(sim, y, 2) > 0.0) sim->pulse.v_ref = velocity(sim, y, 2);
        if (taper_dyn_z(&sim->dyn, y, 1) > 0.0) sim->pulse.z_ref = taper_dyn_z(&sim->dyn, y, 1);
        carry_pass(sim, y, 1);
    }
    record_wall(sim, y, TAPER_LEFT); /* its force stops growing here */
    advance_rings(sim, y);
}

int taper_events_passes_complete(const taper_sim *sim) { return sim->pulse.next_pass > sim->pass_limit; }

/* The pulse always reaches a right wall (it is the end of the chain): its
 * first contact is over once a maximum is recorded and the contact has
 * opened (its force is zero), so that the wall's peak force, its time and
 * its impulse are those of the whole contact (the opening is a root of its
 * slot: the run stops there).  Under a static load the contact never
 * opens: there the force back below half its rise over the load ends it. */
int taper_events_walls_settled(const taper_sim *sim)
{
    if (!sim->model.wall_right) return 1;
    const double peak = sim->walls.peak_force[TAPER_RIGHT];
    if (isnan(peak)) return 0;
    size_t k, g;
    if (!wall_contact(sim, TAPER_RIGHT, &k, &g)) return 1;
    const double force = taper_dyn_window_force(&sim->dyn, taper_sim_entries(sim), k);
    const double rest = sim->model.load;
    if (rest > 0.0) return force <= rest + 0.5 * (peak - rest);
    return !(force > 0.0);
}

int taper_events_complete(const taper_sim *sim)
{
    return taper_events_passes_complete(sim) && sim->pulse.next_peak > sim->target;
}
