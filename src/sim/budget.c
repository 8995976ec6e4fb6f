/*
 * budget.c -- where the energy went at t_final (taper.h,
 * TAPER_STAT_ENERGY_*), and for chains with options the balances that
 * replace plain conservation:
 *
 *   energy:    E(t) + D(t) = E(0), D the energy dissipated by damping and
 *              drag (a CVODE quadrature with error control, solve.c), E
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
 * Contacts whose elastic force is zero (overlap <= 0) are open.  The near
 * group runs from body 1 (striker or wall included) to the first open
 * contact, the far group from the last open contact to the last body; the
 * near group's energy is reflected when its momentum is negative (it moves
 * back), the far group's transmitted when its momentum is positive or it
 * ends on a right wall (it presses on it); the rest is in the chain.
 * With no open contact everything is in the chain.  The four parts add up
 * to E(0) to the tolerance.
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
    if (!sim->cv.y) return;
    double *x = malloc(n * sizeof(double)), *v = malloc(n * sizeof(double));
    double *phi = malloc(n * sizeof(double));
    if (!x || !v || !phi) {
        free(x), free(v), free(phi);
        return;
    }
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_data(sim, sim->cv.y);
    taper_sim_bodies(sim, x, v);
    size_t first_open = 0, last_open = 0; /* 0: none */
    for (size_t k = 1; k < n; k++) {
        double z = compression(sim, y, x, k);
        phi[k - 1] = taper_dyn_contact_energy(d, k, z);
        if (taper_dyn_elastic_force(d, k, z) <= 0.0) {
            if (!first_open) first_open = k;
            last_open = k;
        }
    }
    double total = 0.0, near = 0.0, far = 0.0, p_near = 0.0, p_far = 0.0, p = 0.0, p_abs = 0.0;
    double drag_impulse = 0.0;
    for (size_t k = 1; k <= n; k++) {
        double e = 0.0;
        if (!is_wall(m, k)) {
            e = 0.5 * sim->mass[k - 1] * v[k - 1] * v[k - 1];
            if (k > 1) e += (is_wall(m, k - 1) ? 1.0 : 0.5) * phi[k - 2];
            if (k < n) e += (is_wall(m, k + 1) ? 1.0 : 0.5) * phi[k - 1];
            drag_impulse -= m->drag * x[k - 1];
        }
        const double pk = sim->mass[k - 1] * v[k - 1];
        total += e;
        p += pk;
        p_abs += fabs(pk);
        if (first_open && k <= first_open) near += e, p_near += pk;
        if (first_open && k > last_open) far += e, p_far += pk;
    }
    s->energy_reflected = first_open && p_near < 0.0 ? near : 0.0;
    s->energy_transmitted = first_open && (p_far > 0.0 || m->wall_right) ? far : 0.0;
    s->energy_in_chain = total - s->energy_reflected - s->energy_transmitted;
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
