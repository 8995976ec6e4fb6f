/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sample.c -- the sampler of taper_solver_spec_set_sampler: the user's
 * function at t_j = j * interval, j = 0, 1, ... (each a product, never a
 * running sum, so that t_j is exactly j * interval whatever the number of
 * samples), or at the caller's times (taper_solver_spec_set_sample_times).
 *
 * How the sim is positioned at t_j without disturbing the integration:
 * solve.c asks the stepper for t_j as an output time (stepper.h, advance).
 * The stepper steps as it would anyway and, once its own time passes t_j,
 * returns the state there, inside its step (CVODE interpolates its
 * Nordsieck history, to its own accuracy; rk8 evaluates its dense output
 * of order 7) without changing its steps; roots before t_j are returned
 * first, so the window at t_j is the one in force then.  The state and
 * sim->t then hold t_j, and every reader (taper_sim_time, _state,
 * _striker_state, _forces) sees the sample time.
 */
#include "sim.h"

#include <math.h>

double taper_sample_next(const taper_sim *sim)
{
    if (!sim->spec.sample_fn) return INFINITY;
    if (sim->spec.sample_times) /* given times (a measurement's), then none */
        return sim->samples_taken < sim->spec.n_sample_times
                   ? sim->spec.sample_times[sim->samples_taken] : INFINITY;
    return (double)sim->samples_taken * sim->spec.sample_interval;
}

int taper_sample_call(taper_sim *sim)
{
    sim->samples_taken++;
    return sim->spec.sample_fn(sim, sim->spec.sample_data);
}
