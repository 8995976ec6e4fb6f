/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper-reference -- converged pass times of a paper chain, independent of
 * CVODE: extrapolated modified midpoint steps (Gragg-Bulirsch-Stoer) in
 * long double (64-bit mantissa, eps 1.1e-19) with compensated time.
 *
 *   taper-reference PROFILE N S Q [TOL]     (TOL default 1e-17)
 *
 * prints "k t_pass" for k = 1..N-1 with 21 significant digits.  The
 * equations are eq. (6) (motion_rescaled) in the compressions of
 * docs/design.md, with masses and contact factors from libtaper's chain
 * (taper_chain_mass, taper_chain_contact: the same doubles the library
 * integrates), v_1(0) = 1, the rest at rest and just touching.
 *
 * What makes it a reference rather than one more integrator:
 *  - every non-smooth point of the force r z^(n-1) theta(z) (a contact
 *    opening or closing inside the integrated range) ends a step exactly
 *    (root of z_k located on re-integrated partial steps), so no step
 *    straddles a kink, and the extrapolation's order holds;
 *  - a pass, the first upward zero of v_{k+1} - v_k (armed as in
 *    src/sim/events.c: the next granule to pass, or v_k above 1e-6 of the
 *    pulse velocity), is located the same way to ~1e-19 relative;
 *  - time is a compensated sum of the steps (a plain t += H drifts by up
 *    to half an ulp of t per step);
 *  - the granules ahead of the front join once the compression of the last
 *    one reaches z_th = 1e-40 (a neglected force below r 1e-60), 20 orders
 *    below libtaper's threshold; granules behind leave once passed 40
 *    granules ago and separating from the next, and the gap to the last
 *    one that left is watched: should it close, the program fails.
 * Convergence is checked by the caller: two tolerances must agree
 * (tests/unit/reference/make_references.sh).  Exit 1 on bad arguments or a
 * failed run, with a message on stderr.
 */
#include "reference.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: taper-reference PROFILE N S Q [TOL]\n");
        return 1;
    }
    taper_error err;
    taper_profile profile;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    if (!spec || taper_profile_from_name(argv[1], &profile, &err) != TAPER_OK ||
        taper_chain_spec_set_profile(spec, profile, &err) != TAPER_OK ||
        taper_chain_spec_set_n_granules(spec, (size_t)strtoul(argv[2], NULL, 10), &err) != TAPER_OK ||
        taper_chain_spec_set_s(spec, strtod(argv[3], NULL), &err) != TAPER_OK ||
        taper_chain_spec_set_q(spec, strtod(argv[4], NULL), &err) != TAPER_OK) {
        fprintf(stderr, "taper-reference: bad chain %s %s %s %s\n", argv[1], argv[2], argv[3], argv[4]);
        return 1;
    }
    taper_chain *chain = taper_chain_alloc(spec, &err);
    taper_chain_spec_free(spec);
    if (!chain) {
        fprintf(stderr, "taper-reference: %s\n", err.message);
        return 1;
    }
    long double tol = argc > 5 ? strtold(argv[5], NULL) : 1e-17L;
    size_t n = taper_chain_size(chain);
    long double *t = malloc(n * sizeof *t);
    int status = t ? taper_reference_pass_times(chain, tol, t) : -1;
    taper_chain_free(chain);
    if (status != 0) return 1;
    for (size_t k = 1; k < n; k++) printf("%zu %.21Lg\n", k, t[k - 1]);
    free(t);
    return 0;
}
