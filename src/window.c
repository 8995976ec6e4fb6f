/*
 * window.c -- the active window of granules (see dynamics.h).
 *
 *  grow:      granule hi+1 joins when z_hi reaches the growth threshold.
 *             Its state and Nordsieck history are zero in every vector, which
 *             is exact for a granule at rest: no solver restart.
 *  shrink:    granule lo leaves when its motion is free flight for ever: the
 *             gaps on both sides are open and not closing (velocities ordered),
 *             and all its observables are known.  Dropping components leaves
 *             the others' Nordsieck history exact: no restart.
 *  take back: if the gap behind the window closes after all, granule lo-1
 *             returns with its ballistic state; this changes the history of
 *             a component, so CVODE is re-initialised (rare).
 */
#include "sim.h"

#include <math.h>

/* A gap must be open by more than this (in units of R_1) before the granule
 * behind it may leave; avoids leaving and returning at once. */
#define GAP_MIN 1e-9

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

static int can_leave(const taper_sim *sim, const double *y, size_t j)
{
    const taper_dyn *d = &sim->dyn;
    if (j + 2 >= d->hi || j >= sim->next_pass || j >= sim->next_peak) return 0;
    double v = taper_dyn_v(d, y, j), v_next = taper_dyn_v(d, y, j + 1);
    if (!(taper_dyn_z(d, y, j) < -GAP_MIN) || !(v <= v_next)) return 0;
    if (j > 1 && (!(y[0] < -GAP_MIN) || !(d->v_left <= v))) return 0;
    return 1;
}

static void leave(taper_sim *sim, const double *y, size_t j)
{
    taper_dyn *d = &sim->dyn;
    double v = taper_dyn_v(d, y, j);
    double x = taper_dyn_position(d, y, j);
    sim->x_free[j - 1] = x - v * sim->t;
    sim->v_free[j - 1] = v;
    sim->energy_free += 0.5 * d->mass[j - 1] * v * v;
    sim->momentum_free += d->mass[j - 1] * v;
    d->v_left = v;
    d->lo = j + 1;
}

int taper_window_shrink(taper_sim *sim, taper_error *err)
{
    if (!sim->window) return TAPER_OK;
    size_t lo = sim->dyn.lo;
    /* y's data pointer follows the window's begin: re-read after each drop */
    while (can_leave(sim, taper_sim_data(sim, sim->y), sim->dyn.lo)) {
        leave(sim, taper_sim_data(sim, sim->y), sim->dyn.lo);
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
    double *y = taper_sim_data(sim, sim->y);
    y[taper_idx_v(j) - taper_dyn_begin(d)] = v;
    if (j > 1) y[0] = free_position(sim, j - 1) - free_position(sim, j);
    return taper_solver_restart(sim, err);
}
