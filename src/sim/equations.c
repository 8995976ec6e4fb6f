/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * equations.c -- the equations every stepper of the run integrates, on the
 * state's entries (the window's, from absolute index taper_dyn_begin, or
 * the whole chain's): the right-hand side and the error weights.  Every
 * stepper calls these (stepper.h), so that all integrate one system under
 * one tolerance.
 */
#include "sim.h"

#include <math.h>

void taper_equations_rhs(const taper_sim *sim, double t, const double *y, double *f)
{
    const taper_dyn *d = &sim->dyn;
    if (!sim->model.options) { /* the paper's chain: the plain right-hand side */
        taper_dyn_rhs(d, y, f);
        taper_dyn_carry(d, f);
        return;
    }
    taper_dyn_rhs_general(d, t, y, f);
    taper_dyn_carry(d, f);
    if (!sim->model.quadratures) return;
    /* With walls or losses the state ends with TAPER_N_QUADRATURES entries
     * after the window's (the window's tail, window_storage.h; after the
     * 2 bodies entries of the whole chain): the wall impulses and the
     * dissipated energy, integrated with the motion and under its error
     * control, so that E + D = E(0) holds to the tolerance (budget.c).
     * They are entries of the state, not a stepper's quadratures: CVODE
     * itself has none (CVODES has; the build links CVODE). */
    double *q = f + (taper_dyn_end(d) - taper_dyn_begin(d));
    taper_dyn_quadrature_rhs(d, y, q);
    /* departed granules' drag loss, fading out of the quadrature
     * (window_flight.c) */
    if (sim->out.n_handing) q[TAPER_QUAD_DISSIPATED] += taper_sim_handover_power(sim, t);
}

/* 1 / (rtol |y_i| + atol scale_i) over the window, the scale being the
 * granule's pulse velocity or maximum compression (see sim.h). */
void taper_equations_weights(const taper_sim *sim, const double *y, double *w)
{
    const taper_dyn *d = &sim->dyn;
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
    if (sim->model.quadratures) { /* impulses on the scale of P(0), D of E(0) */
        const double m0 = sim->model.scale_mass;
        w[i + TAPER_QUAD_WALL_LEFT] = 1.0 / (rtol * fabs(y[i + TAPER_QUAD_WALL_LEFT]) + atol * m0);
        w[i + TAPER_QUAD_WALL_RIGHT] = 1.0 / (rtol * fabs(y[i + TAPER_QUAD_WALL_RIGHT]) + atol * m0);
        w[i + TAPER_QUAD_DISSIPATED] = 1.0 / (rtol * fabs(y[i + TAPER_QUAD_DISSIPATED]) + atol * 0.5 * m0);
    }
}
