/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * dynamics_api.c -- taper_dynamics: the equations taper_sim integrates,
 * eq. (6), over the whole chain (window lo = 1, hi = N), for integrators
 * outside the library (the peers of taper-bench, a user's own).  A thin
 * shell over taper_dyn: the same floating-point operations as the sim's
 * own right-hand side.
 *
 * The paper's chain only: a chain with a wall, a striker, a load, damping
 * or drag is refused (TAPER_EINVAL naming the option).  Its state would
 * not be the documented 2N vector (the sim adds bodies for a striker and
 * walls, and the dissipated energy), and a peer that integrates eq. (6)
 * would silently solve another problem.
 */
#include "dynamics.h"

#include "core/taper_internal.h"

#include <math.h>
#include <stdlib.h>

struct taper_dynamics {
    taper_dyn dyn;
};

taper_dynamics *taper_dynamics_alloc(const taper_chain *chain, taper_error *err)
{
    if (!chain) {
        taper_fail(err, TAPER_EINVAL, "taper_dynamics_alloc: chain is NULL");
        return NULL;
    }
    const char *option = NULL;
    if (taper_chain_end(chain, TAPER_LEFT) == TAPER_END_WALL ||
        taper_chain_end(chain, TAPER_RIGHT) == TAPER_END_WALL)
        option = "end";
    else if (taper_chain_striker_radius(chain) > 0.0)
        option = "striker_radius";
    else if (taper_chain_load(chain) > 0.0)
        option = "load";
    else if (taper_chain_damping(chain) > 0.0)
        option = "damping";
    else if (taper_chain_drag(chain) > 0.0)
        option = "drag";
    else if (taper_chain_piston_duration(chain) > 0.0)
        option = "piston_duration";
    if (option) {
        taper_fail_field(err, TAPER_EINVAL, option,
                         "taper_dynamics_alloc: the chain has the option '%s'; taper_dynamics "
                         "integrates the paper's eq. (6) only (no walls, striker, piston, load or losses)",
                         option);
        return NULL;
    }
    taper_dynamics *d = calloc(1, sizeof *d);
    if (!d || taper_dyn_init(&d->dyn, taper_chain_size(chain), taper_chain_exponent(chain),
                             taper_chain_mass(chain), taper_chain_contact(chain)) != 0) {
        free(d);
        taper_fail(err, TAPER_ENOMEM, "cannot allocate the dynamics of %zu granules",
                   taper_chain_size(chain));
        return NULL;
    }
    /* taper_dyn_init's window is the whole chain: lo = 1, hi = N. */
    taper_ok(err);
    return d;
}

void taper_dynamics_free(taper_dynamics *dyn)
{
    if (!dyn) return;
    taper_dyn_release(&dyn->dyn);
    free(dyn);
}

/* NULL arguments: no crash, and no number that passes for a result (the
 * entry points return nothing to carry TAPER_EINVAL): ydot NaN when it can
 * be written, NaN energies and peak functions. */
void taper_dynamics_rhs(const taper_dynamics *dyn, const double *y, double *ydot)
{
    if (!dyn || !ydot) return;
    if (!y) {
        for (size_t i = 0; i < 2 * dyn->dyn.n; i++) ydot[i] = NAN;
        return;
    }
    taper_dyn_rhs(&dyn->dyn, y, ydot);
}

void taper_dynamics_energy_momentum(const taper_dynamics *dyn, const double *y, double *energy,
                                    double *momentum)
{
    double e = NAN, p = NAN;
    if (dyn && y) taper_dyn_energy_momentum(&dyn->dyn, y, &e, &p);
    if (energy) *energy = e;
    if (momentum) *momentum = p;
}

double taper_dynamics_peak_function(const taper_dynamics *dyn, const double *y, size_t k)
{
    if (!dyn || !y || k < 1 || k > dyn->dyn.n) return NAN;
    return taper_dyn_peak_function(&dyn->dyn, y, k);
}
