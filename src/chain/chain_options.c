/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * chain_options.c -- the chain beyond the paper (taper.h, "Beyond the
 * paper"): the relations between its settings (chain_options_check: ends,
 * striker, piston, pattern, materials, losses), each refusal naming the
 * setting to change by its name in the table of settings, and the piston
 * of a built chain.  The physics of each option: docs/physics.md.
 */
#include "chain/chain_impl.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const wall_fields[TAPER_N_ENDS] = {"left_compliance", "right_compliance"};

/* The piston's face is a wall's (chain.c, fill_ends): sqrt(2 R_1) times
 * 2 c_1 / (c_1 + c_piston). */
void chain_options_fill_piston(taper_chain *chain, const taper_chain_spec *spec)
{
    const int on = spec->piston_duration > 0.0;
    const double c1 = spec->compliance ? spec->compliance[0] : 1.0;
    chain->piston_duration = on ? spec->piston_duration : 0.0;
    chain->piston_contact = on ? sqrt(2.0 * chain->radius[0]) * 2.0 / (c1 + spec->piston_compliance)
                               : NAN;
    /* A push of finite duration is no impulse on granule 1 at rest: the
     * pulse it launches is not the binary collision cascade of eq. (9). */
    if (on && !chain->theory_note[0])
        snprintf(chain->theory_note, sizeof chain->theory_note, "%s",
                 "piston: the binary collision approximation of arXiv:0905.4512 starts from an "
                 "impulse on granule 1, not from a push of prescribed velocity");
}

double taper_chain_piston_duration(const taper_chain *chain)
{
    return chain ? chain->piston_duration : NAN;
}
double taper_chain_piston_contact(const taper_chain *chain)
{
    return chain ? chain->piston_contact : NAN;
}

/* The pattern belongs to the decorated profile as radii to the custom one:
 * neither without the other, and its first radius is the unit. */
static taper_status check_pattern(const taper_chain_spec *spec, taper_error *err)
{
    const char *profile = taper_profile_name(spec->profile);
    if (spec->profile != TAPER_DECORATED && spec->pattern)
        return taper_fail_field(err, TAPER_EINVAL, "pattern",
                                "a pattern has no effect with profile = '%s' (only 'decorated' "
                                "reads it): remove the pattern or use profile = 'decorated'",
                                profile);
    if (spec->profile == TAPER_DECORATED && !spec->pattern)
        return taper_fail_field(err, TAPER_EINVAL, "pattern",
                                "profile = 'decorated' needs a pattern: the radii of one period, "
                                "starting with 1 (e.g. 1, 0.5 for large and small granules in "
                                "turn)");
    if (spec->profile == TAPER_DECORATED && spec->pattern[0] != 1.0)
        return taper_fail_field(err, TAPER_EINVAL, "pattern",
                                "pattern(1) = %.17g: the first radius is the unit of length and "
                                "must be 1 (divide the pattern by it)", spec->pattern[0]);
    return TAPER_OK;
}

taper_status chain_options_check(const taper_chain_spec *spec, taper_error *err)
{
    taper_status st = check_pattern(spec, err);
    if (st != TAPER_OK) return st;
    /* A mixed chain needs both lists, one entry per granule. */
    if (!spec->density != !spec->compliance)
        return taper_fail_field(err, TAPER_EINVAL, spec->density ? "compliances" : "densities",
                                "a mixed chain needs densities and compliances, one of each "
                                "per granule: %s are missing",
                                spec->density ? "compliances" : "densities");
    if (spec->density && spec->n_density != spec->n_granules)
        return taper_fail_field(err, TAPER_EINVAL, "densities",
                                "%zu densities but n_granules = %zu: give one per granule",
                                spec->n_density, spec->n_granules);
    if (spec->compliance && spec->n_compliance != spec->n_granules)
        return taper_fail_field(err, TAPER_EINVAL, "compliances",
                                "%zu compliances but n_granules = %zu: give one per granule",
                                spec->n_compliance, spec->n_granules);
    for (int e = 0; e < TAPER_N_ENDS; e++)
        if (spec->end[e] == TAPER_END_FREE && spec->end_compliance[e] != 0.0)
            return taper_fail_field(err, TAPER_EINVAL, wall_fields[e],
                                    "%s = %g has no effect on a free end: leave it at 0 or make "
                                    "the %s end a wall", wall_fields[e], spec->end_compliance[e],
                                    e == TAPER_LEFT ? "left" : "right");
    if (spec->striker_radius == 0.0 && (spec->striker_density != 1.0 || spec->striker_compliance != 1.0))
        return taper_fail_field(err, TAPER_EINVAL, "striker_radius",
                                "striker_density = %g and striker_compliance = %g have no effect "
                                "without a striker: give striker_radius > 0 or leave them at 1",
                                spec->striker_density, spec->striker_compliance);
    /* The striker hits granule 1 from the left: a wall cannot be there too. */
    if (spec->striker_radius > 0.0 && spec->end[TAPER_LEFT] == TAPER_END_WALL)
        return taper_fail_field(err, TAPER_EINVAL, "left",
                                "a left wall and a striker exclude each other (the striker comes "
                                "from the left end): make the left end 'free' or remove the "
                                "striker (striker_radius = 0)");
    /* The piston pushes granule 1 from the left, as a striker or a left
     * wall would be there; under a load its face would hold granule 1 by
     * a static overlap, a case the piston's model does not cover. */
    if (spec->piston_duration == 0.0 && spec->piston_compliance != 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "piston_compliance",
                                "piston_compliance = %g has no effect without a piston: give "
                                "piston_duration > 0 or leave it at 0", spec->piston_compliance);
    if (spec->piston_duration > 0.0 && spec->striker_radius > 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "a piston and a striker exclude each other (both push granule 1 "
                                "from the left): remove one (piston_duration = 0 or "
                                "striker_radius = 0)");
    if (spec->piston_duration > 0.0 && spec->end[TAPER_LEFT] == TAPER_END_WALL)
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "a piston and a left wall exclude each other (the piston is the "
                                "left end): make the left end 'free' or remove the piston "
                                "(piston_duration = 0)");
    if (spec->piston_duration > 0.0 && spec->load > 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "a piston under a static load is not modelled (the piston starts "
                                "just touching granule 1 of a chain at rest): set load = 0 or "
                                "remove the piston");
    /* The Kuwabara-Kono force damping r (n-1) z^(n-2) dz/dt diverges as a
     * contact closes when n < 2 (z^(n-2) -> oo at z -> 0+): no finite force
     * law to integrate.  Refused here, before any run, naming what to change, as
     * taper_sim_alloc does. */
    if (spec->damping > 0.0 && spec->exponent < 2.0)
        return taper_fail_field(err, TAPER_EINVAL, "damping",
                                "damping = %g with exponent n = %g: the Kuwabara-Kono force "
                                "damping (n-1) z^(n-2) dz/dt diverges as a contact closes for "
                                "n < 2; use n >= 2 or drag for losses", spec->damping,
                                spec->exponent);
    return TAPER_OK;
}
