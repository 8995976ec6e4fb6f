/*
 * window.c -- the active window of granules (see dynamics.h).
 *
 *  grow:      granule hi+1 joins when z_hi reaches the growth threshold.
 *             Its state and Nordsieck history are zero in every vector, which
 *             is exact for a granule at rest: no solver restart.
 *  shrink:    granule lo leaves, after all its observables are known, when
 *             either criterion below holds.  Dropping components leaves the
 *             others' Nordsieck history exact: no restart.
 *  take back: if the gap behind the window closes after all, granule lo-1
 *             returns with its ballistic state; this changes the history of
 *             a component, so CVODE is re-initialised (rare).
 *
 * Error scales (from the tolerance):
 *     v_eps = REST_FACTOR (rtol v_ref + atol v_scale),
 *     z_eps = REST_FACTOR (rtol z_ref + atol z_scale)
 * (v_ref, z_ref: velocity of granule k+1 and compression z_k at the last pass
 * event, the pulse's largest; v_scale, z_scale: the granule's own binary
 * collision scales that make atol relative, see solve.c).
 *
 * Criterion 1, exact free flight (the clean case, e.g. backward chains): the
 * gaps on both sides of lo are open by more than z_eps and not closing
 * (v_{lo-1} <= v_lo <= v_{lo+1}).  Granule lo then moves at constant velocity
 * for ever unless the window pushes granule lo+1 back into it, which the gap
 * slot watches at compression 0 (gap_watch = 0): take-back is exact.
 *
 * Criterion 2, at rest within the tolerance (monodisperse chains, the tails
 * of forward chains, the recoiling train of long backward chains): behind the
 * pulse granules are left with velocities and compressions of either sign at
 * the level of the solver's error, or drifting as a block whose relative
 * velocities are at that level, which criterion 1 rejects for ever, so the
 * window would span the whole chain behind the front (O(N^2) cost).  Granule
 * lo may leave, flying ballistically at its velocity, when
 *     |v_lo - v_{lo-1}| <= v_eps  (|v_1| <= v_eps for lo = 1),
 *     z_lo <= z_eps,  z_{lo-1} <= z_eps,
 * i.e. when it is at rest within REST_FACTOR error units relative to the
 * granule behind it, which already flies freely (Galilean invariance: a
 * backward linear chain, S = 0.5, leaves its granules beyond k ~ 4e5 drifting
 * back together at 2.8e-14 with relative velocities of 1e-20 and either sign,
 * and with rest as the reference the window grew by one granule per granule
 * from there on), and its contacts are open or compressed by less than
 * REST_FACTOR error units (an open gap exerts no force, whatever its size;
 * requiring |z| small would strand granules whose gaps open at noise-level
 * speed).  Why this is
 * harmless: the gap z_lo it leaves behind is watched
 * with gap_watch = WATCH_FACTOR / REST_FACTOR * z_eps, so while lo is out the
 * one-sided force the window feels from it is at most r z_watch^(n-1), a
 * fraction (WATCH_FACTOR rtol)^(n-1) (3e-11 for n = 5/2 and the default rtol)
 * of the pulse force r z_ref^(n-1): below what the tolerance resolves.  A
 * compression beyond z_watch (a real signal) takes the granule back exactly
 * as in criterion 1; the factor WATCH_FACTOR / REST_FACTOR = 10 between
 * leaving and returning is the hysteresis that keeps noise from thrashing
 * (each take-back costs a CVodeReInit).  Neighbours that are both out move
 * together at most at v_eps, so out of the window the chain's gaps close by
 * at most z_eps + v_eps t (documented in docs/window.md).  The
 * granule's momentum is kept exactly; the contact energy dropped is at most
 * r z_eps^n / n per granule.
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

static int apply_range(taper_sim *sim, taper_error *err)
{
    if (taper_window_set_range(sim->window, taper_dyn_begin(&sim->dyn), taper_dyn_end(&sim->dyn)) != 0)
        return taper_fail(err, TAPER_ENOMEM, "cannot enlarge the active window to %zu granules",
                          sim->dyn.hi - sim->dyn.lo + 1);
    sim->stats.window_changes++;
    size_t size = sim->dyn.hi - sim->dyn.lo + 1;
    if (size > sim->stats.max_window) sim->stats.max_window = size;
    return TAPER_OK;
}

int taper_window_grow(taper_sim *sim, taper_error *err)
{
    if (sim->dyn.hi >= sim->dyn.n) return TAPER_OK;
    sim->dyn.hi++;
    return apply_range(sim, err);
}

/* The largest compression a contact may keep when granule j leaves at rest
 * (criterion 2).  The window goes on feeling its force r z^(n-1) without the
 * reaction on the departed granule: momentum leaks unless that force is a
 * fraction below FORCE_FRACTION rtol of the pulse force r z_ref^(n-1), i.e.
 * z <= (FORCE_FRACTION rtol)^(1/(n-1)) z_ref.  For n = 5/2 at rtol <= 1e-10
 * that is looser than z_eps (which then decides); at looser tolerances
 * z_eps = 100 rtol z_ref let monodisperse chains leak momentum at
 * 2.7e-8 per granule at rtol 1e-6 (docs/window.md).  Never below one error
 * unit: smaller compressions are noise, indistinguishable from zero. */
static double resting_compression(const taper_sim *sim, size_t j, double z_eps)
{
    const double n = sim->chain->exponent, rtol = sim->spec.rtol;
    const double unit = rtol * fabs(sim->z_ref) + sim->spec.atol * sim->z_scale[j - 1];
    const double z_force = pow(FORCE_FRACTION * rtol, 1.0 / (n - 1.0)) * fabs(sim->z_ref);
    return fmin(z_eps, fmax(unit, z_force));
}

/* How granule j may leave: 0 not at all, 1 exact free flight, 2 at rest
 * within the tolerance (criteria 1 and 2 above). */
static int can_leave(const taper_sim *sim, const double *y, size_t j, double *watch)
{
    const taper_dyn *d = &sim->dyn;
    if (j + 2 >= d->hi || j >= sim->next_pass || j >= sim->next_peak) return 0;
    const double v = taper_dyn_v(d, y, j), v_next = taper_dyn_v(d, y, j + 1);
    const double z = taper_dyn_z(d, y, j);
    const double z_back = j > 1 ? y[0] : -INFINITY; /* gap z_{j-1} */
    const double v_back = j > 1 ? d->v_left : -INFINITY;
    const double rtol = sim->spec.rtol, atol = sim->spec.atol;
    const double v_eps = REST_FACTOR * (rtol * fabs(sim->v_ref) + atol * sim->v_scale[j - 1]);
    const double z_eps = REST_FACTOR * (rtol * fabs(sim->z_ref) + atol * sim->z_scale[j - 1]);
    const double z_eps_back = j > 1 ? REST_FACTOR * (rtol * fabs(sim->z_ref) + atol * sim->z_scale[j - 2]) : 0.0;
    /* Criterion 1: gaps open beyond the tolerance's compression and not closing. */
    if (z < -z_eps && v <= v_next && z_back < -z_eps_back && v_back <= v) {
        *watch = 0.0;
        return 1;
    }
    /* Criterion 2: at rest within the tolerance, relative to the granule
     * behind (which left before and flies freely; rest itself for j = 1);
     * open gaps of any size are harmless (no force), only compressions are
     * bounded, so that the one-sided force they leave is below the
     * tolerance. */
    const double v_rest = j > 1 ? v_back : 0.0;
    const double z_rest = resting_compression(sim, j, z_eps);
    if (fabs(v - v_rest) <= v_eps && z <= z_rest && z_back <= z_rest) {
        *watch = WATCH_FACTOR / REST_FACTOR * z_rest;
        return 2;
    }
    return 0;
}

static void leave(taper_sim *sim, const double *y, size_t j, double watch)
{
    taper_dyn *d = &sim->dyn;
    double v = taper_dyn_v(d, y, j);
    double x = taper_dyn_position(d, y, j);
    sim->x_free[j - 1] = x - v * sim->t;
    sim->v_free[j - 1] = v;
    sim->energy_free += 0.5 * d->mass[j - 1] * v * v;
    sim->momentum_free += d->mass[j - 1] * v;
    sim->gap_watch[j - 1] = watch;
    d->v_left = v;
    d->lo = j + 1;
}

int taper_window_shrink(taper_sim *sim, taper_error *err)
{
    if (!sim->window) return TAPER_OK;
    size_t lo = sim->dyn.lo;
    /* y's data pointer follows the window's begin: re-read after each drop */
    double watch = 0.0;
    int how;
    while ((how = can_leave(sim, taper_sim_data(sim, sim->y), sim->dyn.lo, &watch)) != 0) {
        if (how == 2) sim->left_resting++;
        leave(sim, taper_sim_data(sim, sim->y), sim->dyn.lo, watch);
        sim->window->begin = taper_dyn_begin(&sim->dyn); /* shrinking needs no copy */
    }
    if (sim->dyn.lo != lo) return apply_range(sim, err);
    return TAPER_OK;
}

static double free_position(const taper_sim *sim, size_t j)
{
    return sim->x_free[j - 1] + sim->v_free[j - 1] * sim->t;
}

int taper_window_take_back(taper_sim *sim, taper_error *err)
{
    taper_dyn *d = &sim->dyn;
    if (d->lo <= 1) return TAPER_OK;
    size_t j = d->lo - 1;
    double v = sim->v_free[j - 1];
    sim->energy_free -= 0.5 * d->mass[j - 1] * v * v;
    sim->momentum_free -= d->mass[j - 1] * v;
    d->lo = j;
    d->v_left = j > 1 ? sim->v_free[j - 2] : 0.0;
    int status = apply_range(sim, err);
    if (status != TAPER_OK) return status;
    taper_sim_log(sim, 0, "granule %zu rejoins the window at t = %.17g (its gap closed)", j, sim->t);
    double *y = taper_sim_data(sim, sim->y);
    y[taper_idx_v(j) - taper_dyn_begin(d)] = v;
    if (j > 1) y[0] = free_position(sim, j - 1) - free_position(sim, j);
    return taper_solver_restart(sim, err);
}
