/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * extended.c -- the chain the sim integrates: the chain's N granules with the
 * bodies the options beyond the paper put at its ends (taper.h, "Beyond the
 * paper").  A leaf of src/sim (layering in sim.h).
 *
 * Why extra bodies rather than special cases in every formula: a striker
 * is a granule like the others (its mass, its eq. (7) contact with granule
 * 1, initial velocity 1 while granule 1 rests), and a wall is a body that
 * never moves (mass 0 here, inverse mass 0 in dynamics.c) whose contact
 * with the end granule is the Hertz contact with a half-space.  The state
 * layout of dynamics.h then covers them unchanged: with a right wall body
 * at x = 0, z_N = x_N - x_wall = x_N is the wall's compression, as the
 * paper's convention x_{N+1} := 0 already has it, and a left wall let go
 * by the window (exact free flight at velocity 0) is the window's gap slot
 * with v_left = 0.  Events, the window and the tolerance scales work on
 * body indices; the sim publishes granules 1..N as bodies 1+off..N+off.
 */
#include "extended.h"

#include <math.h>
#include <stdlib.h>

static int any_option(const taper_model *m)
{
    return m->striker || m->wall_left || m->wall_right || m->load > 0.0 || m->damping > 0.0 ||
           m->drag > 0.0 || m->piston;
}

int taper_model_init(taper_model *m, const taper_chain *chain)
{
    const size_t N = taper_chain_size(chain);
    const double *mass = taper_chain_mass(chain), *contact = taper_chain_contact(chain);
    const double *rest = taper_chain_rest_position(chain), *radius = taper_chain_radius(chain);
    const double n = taper_chain_exponent(chain);
    *m = (taper_model){0};
    m->granules = N;
    m->striker = taper_chain_striker_radius(chain) > 0.0;
    m->wall_left = taper_chain_end(chain, TAPER_LEFT) == TAPER_END_WALL;
    m->wall_right = taper_chain_end(chain, TAPER_RIGHT) == TAPER_END_WALL;
    m->piston = taper_chain_piston_duration(chain) > 0.0;
    m->piston_duration = m->piston ? taper_chain_piston_duration(chain) : 0.0;
    if (m->piston) m->wall_left = 1; /* a moving left wall (sim.h) */
    const double load = taper_chain_load(chain), damping = taper_chain_damping(chain);
    const double drag = taper_chain_drag(chain);
    m->load = load > 0.0 ? load : 0.0;
    m->damping = damping > 0.0 ? damping : 0.0;
    m->drag = drag > 0.0 ? drag : 0.0;
    m->options = any_option(m);
    /* Kuwabara-Kono damping never pulls: a body whose contacts are open
     * flies freely, as in the paper's chain; under drag it flies as
     * m dv/dt = -drag v has it, in closed form (taper_sim_flight). */
    m->free_flight = !(m->load > 0.0);
    m->quadratures = m->wall_left || m->wall_right || m->damping > 0.0 || m->drag > 0.0;
    m->off = (m->striker || m->wall_left) ? 1 : 0;
    m->bodies = m->off + N + (m->wall_right ? 1 : 0);
    /* A left wall rests; granule 1 carries the impulse.  A striker carries
     * it itself (body 1), and so does a piston (its velocity 1; inverse
     * mass 0 keeps it, solve.c stops it at its duration). */
    m->impulse = m->wall_left && !m->piston ? 2 : 1;
    const size_t nb = m->bodies;
    m->mass = malloc(nb * sizeof(double));
    m->contact = malloc(nb * sizeof(double));
    m->rest = malloc(nb * sizeof(double));
    if (!m->mass || !m->contact || !m->rest) return -1;
    for (size_t k = 1; k <= N; k++) {
        m->mass[m->off + k - 1] = mass[k - 1];
        m->contact[m->off + k - 1] = contact[k - 1]; /* [N-1] NaN: no contact after N */
        m->rest[m->off + k - 1] = rest[k - 1];
    }
    if (m->striker) {
        const double Rs = taper_chain_striker_radius(chain);
        m->mass[0] = taper_chain_striker_mass(chain);
        m->contact[0] = taper_chain_striker_contact(chain);
        m->rest[0] = -(Rs + radius[0]);
    } else if (m->wall_left) {
        m->mass[0] = 0.0;
        m->contact[0] = m->piston ? taper_chain_piston_contact(chain)
                                  : taper_chain_end_contact(chain, TAPER_LEFT);
        m->rest[0] = -radius[0]; /* the wall's (the piston's face at t = 0) plane */
    }
    m->scale_mass = m->piston ? m->mass[1] : m->mass[m->impulse - 1];
    if (m->wall_right) {
        m->contact[nb - 2] = taper_chain_end_contact(chain, TAPER_RIGHT);
        m->mass[nb - 1] = 0.0;
        m->contact[nb - 1] = NAN;
        m->rest[nb - 1] = rest[N - 1] + radius[N - 1];
    }
    if (m->load > 0.0) {
        m->delta = malloc(nb * sizeof(double));
        if (!m->delta) return -1;
        /* r_k delta_k^(n-1) = F0 for every contact, walls with their own r */
        for (size_t k = 1; k <= nb; k++)
            m->delta[k - 1] = k < nb ? pow(m->load / m->contact[k - 1], 1.0 / (n - 1.0)) : 0.0;
        /* Centres of the loaded equilibrium, granule 1 kept at X0(1) = 0:
         * every contact is shorter by its overlap (X_pass = rest + x with x
         * measured from this equilibrium). */
        double shift = 0.0;
        for (size_t k = m->off + 2; k <= nb; k++) {
            shift += m->delta[k - 2];
            m->rest[k - 1] -= shift;
        }
        if (m->off) m->rest[0] += m->delta[0];
    }
    return 0;
}

void taper_model_release(taper_model *m)
{
    free(m->mass);
    free(m->contact);
    free(m->rest);
    free(m->delta);
    m->mass = m->contact = m->rest = m->delta = NULL;
}

void taper_model_configure(const taper_model *m, taper_dyn *d)
{
    d->general = m->options;
    d->dissipative = m->damping > 0.0 || m->drag > 0.0;
    d->load = m->load;
    d->delta = m->delta;
    d->damping = m->damping;
    d->drag = m->drag;
    d->wall_left = m->wall_left;
    d->wall_right = m->wall_right;
}
