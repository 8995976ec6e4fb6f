/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * budget.c -- where the energy went at t_final (taper.h,
 * TAPER_STAT_ENERGY_*), and for chains with options the balances that
 * replace plain conservation:
 *
 *   energy:    E(t) + D(t) = E(0), D the energy dissipated by damping and
 *              drag (an entry of the state integrated under the error
 *              control, equations.c), E
 *              measured from the loaded equilibrium (dynamics.h), so
 *              TAPER_STAT_ENERGY_ERROR = |E + D - E(0)| / E(0);
 *   momentum:  P(t) - P(0) = J_left - J_right + F0 t (free first body)
 *              - F0 t (free last body) - drag sum_k x_k(t), J the walls'
 *              impulses (quadratures of their force beyond F0, plus F0 t)
 *              and the drag's impulse integrated exactly (-drag int v_k dt
 *              = -drag x_k(t), x_k(0) = 0); the F0 t of the two ends
 *              cancel;
 *              TAPER_STAT_MOMENTUM_ERROR is the mismatch relative to the
 *              momentum in motion, as for the paper's chain.
 *
 * Budget: body k carries its kinetic energy and half of the energy of each
 * of its contacts (all of a wall's contact: a wall carries nothing).
 * Contacts whose elastic force is zero (overlap <= 0) are open; they cut
 * the bodies into clusters, each moving freely as a whole (momentum P,
 * mass M, velocity V = P / M) until it meets another.  Energy has left the
 * chain for good when the clusters carrying it can never meet the rest
 * again:
 *   reflected    the clusters at the near end that move back (V < 0), each
 *                at least as fast as the next (V_i <= V_{i+1}, so that none
 *                is caught), without a left wall (or a piston) to send them
 *                back;
 *   transmitted  likewise at the far end: moving forward (V > 0), each at
 *                most as fast as the next (V_{i-1} <= V_i), without a right
 *                wall;
 *   in chain     the rest: clusters still to collide, bodies at rest,
 *                energy pressing on a wall; all of it while the chain is
 *                one cluster, or under a static load (which pushes the end
 *                granules back).
 * So two spheres that separate, the second faster, have both transmitted
 * their energy forward; a pulse reflected from a wall whose granules all
 * move back, none faster than the one before, is all reflected.  The
 * three parts and the dissipated energy add up to E(0) to the tolerance.
 */
#include "sim.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

/* Compression of contact k (bodies k, k+1) at sim->t: the window's state
 * where it holds it, else the difference of displacements. */
static double compression(const taper_sim *sim, const double *y, const double *x, size_t k)
{
    const taper_dyn *d = &sim->dyn;
    if (k + 1 == d->lo) return y[0];
    if (k >= d->lo && k <= d->hi) return taper_dyn_z(d, y, k);
    return x[k - 1] - x[k];
}

double taper_budget_piston_work(const taper_sim *sim, const double *q)
{
    if (!sim->model.piston) return NAN;
    /* u = 1 while it moves, 0 after: W = int F u dt = J(min(t, duration)),
     * J its impulse (no load with a piston: the quadrature is all of it) */
    if (!sim->piston_moving && sim->ran) return sim->piston_work;
    return q ? q[TAPER_QUAD_WALL_LEFT] : 0.0;
}

static int is_wall(const taper_model *m, size_t k)
{
    return (k == 1 && m->wall_left) || (k == m->bodies && m->wall_right);
}

void taper_budget_compute(taper_sim *sim, const double *q)
{
    const taper_model *m = &sim->model;
    taper_run_statistics *s = &sim->stats;
    const size_t n = sim->n, i0 = m->impulse;
    /* A piston has mass 0 (sim.h): E(0) = P(0) = 0 */
    const double e0 = 0.5 * sim->mass[i0 - 1], p0 = sim->mass[i0 - 1];
    s->energy_initial = e0;
    /* the quadrature covers the window; bodies out of it lose to drag
     * exactly what their flight says */
    s->energy_dissipated = (q ? q[TAPER_QUAD_DISSIPATED] : 0.0) + taper_sim_dissipated_out(sim);
    /* the quadratures hold the walls' impulses beyond the static F0 t */
    const double static_impulse = m->load * sim->t;
    s->wall_impulse[TAPER_LEFT] = m->wall_left && q ? q[TAPER_QUAD_WALL_LEFT] + static_impulse : NAN;
    s->wall_impulse[TAPER_RIGHT] = m->wall_right && q ? q[TAPER_QUAD_WALL_RIGHT] + static_impulse : NAN;
    s->energy_transmitted = s->energy_reflected = s->energy_in_chain = NAN;
    s->piston_work = taper_budget_piston_work(sim, q);
    const double *y = taper_sim_entries(sim);
    if (!y) return;
    double *x = malloc(n * sizeof(double)), *v = malloc(n * sizeof(double));
    double *phi = malloc(n * sizeof(double));
    if (!x || !v || !phi) {
        free(x), free(v), free(phi);
        return;
    }
    const taper_dyn *d = &sim->dyn;
    taper_sim_bodies(sim, x, v);
    /* The clusters: body k starts a new one after an open contact (a wall
     * belongs to none: it does not move). */
    size_t nc = 0;
    double *cp = malloc(n * sizeof(double)), *cm = malloc(n * sizeof(double));
    double *ce = malloc(n * sizeof(double));
    if (!cp || !cm || !ce) {
        free(cp), free(cm), free(ce);
        free(x), free(v), free(phi);
        return;
    }
    for (size_t k = 1; k < n; k++) phi[k - 1] = taper_dyn_contact_energy(d, k, compression(sim, y, x, k));
    double total = 0.0, p = 0.0, p_abs = 0.0, drag_impulse = 0.0;
    for (size_t k = 1; k <= n; k++) {
        if (is_wall(m, k)) continue;
        const int open_left = k == 1 || is_wall(m, k - 1) ||
                              taper_dyn_elastic_force(d, k - 1, compression(sim, y, x, k - 1)) <= 0.0;
        if (open_left || nc == 0) {
            cp[nc] = cm[nc] = ce[nc] = 0.0;
            nc++;
        }
        double e = 0.5 * sim->mass[k - 1] * v[k - 1] * v[k - 1];
        if (k > 1) e += (is_wall(m, k - 1) ? 1.0 : 0.5) * phi[k - 2];
        if (k < n) e += (is_wall(m, k + 1) ? 1.0 : 0.5) * phi[k - 1];
        drag_impulse -= m->drag * x[k - 1];
        const double pk = sim->mass[k - 1] * v[k - 1];
        cp[nc - 1] += pk;
        cm[nc - 1] += sim->mass[k - 1];
        ce[nc - 1] += e;
        total += e;
        p += pk;
        p_abs += fabs(pk);
    }
    /* V = P / M.  A static load pushes the end granules back into the
     * chain: under it nothing leaves; nor from one cluster, the whole chain
     * moving together (granule 1 driving the rest before it). */
    double reflected = 0.0, transmitted = 0.0;
    size_t i = 0, j = nc;
    const int apart = nc > 1 && m->load == 0.0;
    if (!m->wall_left && apart)
        for (; i < nc && cm[i] > 0.0 && cp[i] < 0.0 &&
               (i + 1 == nc || cp[i] / cm[i] <= cp[i + 1] / cm[i + 1]); i++)
            reflected += ce[i];
    if (!m->wall_right && apart)
        for (; j > i && cm[j - 1] > 0.0 && cp[j - 1] > 0.0 &&
               (j - 1 == 0 || cp[j - 2] / cm[j - 2] <= cp[j - 1] / cm[j - 1]); j--)
            transmitted += ce[j - 1];
    s->energy_reflected = reflected;
    s->energy_transmitted = transmitted;
    s->energy_in_chain = total - reflected - transmitted;
    free(cp), free(cm), free(ce);
    if (m->piston) {
        /* E + D = E(0) + W, relative to the energy put in (E(0) = 0) */
        const double w = s->piston_work;
        s->energy_error = fabs(total + s->energy_dissipated - e0 - w) / fmax(fmax(e0, w), DBL_MIN);
        double external = drag_impulse + (q ? q[TAPER_QUAD_WALL_LEFT] : 0.0);
        if (q && m->wall_right) external -= q[TAPER_QUAD_WALL_RIGHT];
        s->momentum_error = fabs(p - p0 - external) / fmax(fmax(p0, p_abs), DBL_MIN);
    } else if (m->options) {
        s->energy_error = fabs(total + s->energy_dissipated - e0) / e0;
        /* Each end pushes with F0 t (a free end's load, or a wall's static
         * part) plus a wall's dynamic impulse: the F0 t cancel. */
        double external = drag_impulse;
        if (q && m->wall_left) external += q[TAPER_QUAD_WALL_LEFT];
        if (q && m->wall_right) external -= q[TAPER_QUAD_WALL_RIGHT];
        s->momentum_error = fabs(p - p0 - external) / fmax(p0, p_abs);
    }
    free(x), free(v), free(phi);
}
