/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * chain_impl.h -- the layout behind taper_chain (a spec's is
 * settings/specs.h).  Private to src/chain (and its unit tests): every
 * other part reads a chain through the getters of taper.h.
 */
#ifndef TAPER_CHAIN_IMPL_H
#define TAPER_CHAIN_IMPL_H

#include "settings/specs.h"

/* Room for the reason the theory does not apply (taper_chain_theory_note). */
#define CHAIN_NOTE_SIZE 320

/* The chain: plain arrays, granule k at index k-1 (see taper.h). */
struct taper_chain {
    size_t n;           /* number of granules N                         */
    taper_profile profile;
    double exponent;    /* contact exponent n                           */
    double *radius;     /* R_k                                          */
    double *mass;       /* m_k = rho_k R_k^3 (times the mass disorder)  */
    double *contact;    /* r_k for the pair (k, k+1); [n-1] = NaN       */
    double *rest;       /* X0(k)                                        */
    taper_boundary end[TAPER_N_ENDS];
    double end_contact[TAPER_N_ENDS];     /* NaN for a free end         */
    double striker_radius, striker_mass, striker_contact; /* NaN: none  */
    double load, damping, drag;
    double piston_duration, piston_contact; /* 0, NaN: no piston          */
    size_t pattern_period;                /* P of a decorated chain; 0  */
    char theory_note[CHAIN_NOTE_SIZE];    /* "" when the theory applies */
};

/* chain_options.c: the relations between the settings beyond the paper
 * (ends, striker, piston, pattern, materials, losses), for
 * taper_chain_spec_check. */
taper_status chain_options_check(const taper_chain_spec *spec, taper_error *err);

/* chain_options.c: the piston of a built chain (its duration and the
 * contact factor of its face with granule 1: a wall's, eq. (7) with the
 * other radius infinite).  Called by chain.c once the radii are known. */
void chain_options_fill_piston(taper_chain *chain, const taper_chain_spec *spec);

/* disorder.c: u_k in [-1, 1) for granule k of the given seed, identical on
 * every machine (docs/physics.md, "Disorder"). */
double chain_disorder_uniform(uint64_t seed, uint64_t k);

/* theory.c: why the binary collision approximation does not describe
 * the chain (written into chain->theory_note), or "" when it does. */
void chain_theory_note(taper_chain *chain);

#endif
