/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * shock_absorber.c -- a granular chain between an impact and a wall: which
 * chain protects the wall best?
 *
 * A steel bead strikes a chain of steel beads at 0.5 m/s; the chain's far
 * end rests against a steel wall, the body to protect, whose force sensor
 * records the blow.  Chains that shrink towards the wall ("forward tapered"
 * chains, arXiv:0905.4512, Sec. I, and the studies it cites) and chains
 * with small beads between the large ones (decorated chains; Doney and
 * Sen, Phys. Rev. Lett. 97, 155502 (2006), who combined both) have been
 * proposed as shock absorbers: the pulse that reaches the wall is weaker
 * and longer than the striker's blow.  This program puts four chains of the
 * same steel against the wall and compares what the sensor sees:
 *
 *   monodisperse       20 beads of 4.76 mm radius
 *   decorated          the same 20 with a bead of 0.2 their radius between
 *                      each pair (39 beads, profile TAPER_DECORATED)
 *   tapered            20 beads shrinking by 4 % of the first per bead
 *                      towards the wall (TAPER_FORWARD_LINEAR, S = 0.04)
 *   tapered decorated  the tapered 20 with a bead of 0.2 their radius
 *                      between each pair (radii given: TAPER_CUSTOM)
 *
 * For each: the wall's peak force and its time (located exactly by CVODE's
 * root finder), the impulse it took, and where the striker's energy went by
 * the end (sent back towards the striker's side, still in the chain).
 * What to look at: the decorated chains cut the peak force below the
 * monodisperse chain's, the tapered ones cut it most, and none of them
 * changes the fact that the wall must stop the momentum it receives: a
 * lower peak comes with a longer push.  In the tapered chains the energy
 * that comes back ends in the heavy first beads, which carry it with more
 * momentum (p = sqrt(2 m E)), so the wall takes more impulse, not less;
 * and a quarter to a half of the striker's energy is still in them at the
 * end (column "chain"), against almost none in the monodisperse chain,
 * which sends the pulse back whole.
 *
 * The checks are the balances an experimenter would trust the record by:
 * energy (kinetic + elastic against the striker's, the library's
 * statistic) and momentum, recomputed here from the final state: the
 * striker's momentum less what the striker and the beads carry at the end
 * is what the wall took, its force integrated over the run.  The program
 * exits non-zero if either fails or a call fails; every return value is
 * checked.
 *
 * Build against an installed libtaper:
 *     cc shock_absorber.c $(pkg-config --cflags --libs taper) \
 *        -Wl,-rpath,$(pkg-config --variable=libdir taper) -lm -o shock_absorber
 */
#include <taper.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define N_LARGE 20        /* large beads in every chain                  */
#define SMALL 0.2         /* radius of a decorating bead, relative        */
#define S 0.04            /* taper: R_k = 1 - S (k - 1) of the large ones */
#define YOUNG 193e9       /* Pa, stainless steel                         */
#define POISSON 0.3
#define DENSITY 8000.0    /* kg/m^3                                      */
#define RADIUS 4.76e-3    /* m, the striker's and the first bead's        */
#define VELOCITY 0.5      /* m/s, the striker's                          */
#define T_END 200.0       /* rescaled: every pulse is back from the wall  */
#define MAX_ENERGY_ERROR 1e-6
#define MAX_MOMENTUM_ERROR 1e-6

static int check_status(taper_status status, const char *funcname, const taper_error *err)
{
    if (status == TAPER_OK) return 0;
    fprintf(stderr, "\nERROR: %s() failed with status %d (%s)%s%s%s\n  %s\n", funcname,
            (int)status, taper_strerror(status), err->field ? ": setting '" : "",
            err->field ? err->field : "", err->field ? "'" : "", err->message);
    return 1;
}

static int check_pointer(const void *pointer, const char *funcname, const taper_error *err)
{
    return pointer ? 0 : check_status(err->status, funcname, err);
}

/* The chains compared: a profile, its parameter and, for the custom one,
 * its radii. */
typedef struct absorber {
    const char *name;
    taper_profile profile;
    size_t n;
    double s;
    const double *pattern;   /* decorated: one period */
    size_t period;
    const double *radii;     /* custom                */
} absorber;

/* What the wall's sensor and the balances say, rescaled. */
typedef struct record {
    double f_peak, t_peak, impulse;
    double e_reflected, e_in_chain, e_initial, energy_error;
    double momentum_error;   /* |p_0 - P(t_end) - J| / p_0, from the state */
    double steps;
} record;

/* Momentum p_0 - P(t_end) that the chain and the striker lost by t_end,
 * from the masses and the final velocities. */
static int momentum_lost(const taper_sim *sim, const taper_chain *chain, double *lost)
{
    taper_error err;
    const size_t n = taper_chain_size(chain);
    const double *m = taper_chain_mass(chain);
    double *v = malloc(n * sizeof *v), xs, vs;
    if (!v) {
        fprintf(stderr, "ERROR: out of memory\n");
        return 1;
    }
    int failed = check_status(taper_sim_state(sim, NULL, v, &err), "taper_sim_state", &err) ||
                 check_status(taper_sim_striker_state(sim, &xs, &vs, &err),
                              "taper_sim_striker_state", &err);
    if (!failed) {
        const double ms = taper_chain_striker_mass(chain);
        double p = ms * vs;
        for (size_t k = 0; k < n; k++) p += m[k] * v[k];
        *lost = ms * 1.0 - p;   /* the striker came in at the unit velocity */
    }
    free(v);
    return failed;
}

static int protect(const absorber *a, record *r)
{
    taper_error err;
    taper_chain_spec *chain_spec = NULL;
    taper_solver_spec *solver_spec = NULL;
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    int retval = 1;

    chain_spec = taper_chain_spec_alloc(&err);
    if (check_pointer(chain_spec, "taper_chain_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_chain_spec_set_profile(chain_spec, a->profile, &err),
                     "taper_chain_spec_set_profile", &err) ||
        check_status(taper_chain_spec_set_n_granules(chain_spec, a->n, &err),
                     "taper_chain_spec_set_n_granules", &err))
        goto cleanup;
    if (a->s > 0 &&
        check_status(taper_chain_spec_set_s(chain_spec, a->s, &err), "taper_chain_spec_set_s", &err))
        goto cleanup;
    if (a->pattern && check_status(taper_chain_spec_set_pattern(chain_spec, a->pattern, a->period, &err),
                                   "taper_chain_spec_set_pattern", &err))
        goto cleanup;
    if (a->radii && check_status(taper_chain_spec_set_radii(chain_spec, a->radii, a->n, &err),
                                 "taper_chain_spec_set_radii", &err))
        goto cleanup;
    /* the wall and the striker: the beads' steel (compliance 1), the
     * striker of the first bead's size */
    if (check_status(taper_chain_spec_set_end(chain_spec, TAPER_RIGHT, TAPER_END_WALL, 1.0, &err),
                     "taper_chain_spec_set_end", &err) ||
        check_status(taper_chain_spec_set_striker(chain_spec, 1.0, 1.0, 1.0, &err),
                     "taper_chain_spec_set_striker", &err))
        goto cleanup;
    chain = taper_chain_alloc(chain_spec, &err);
    if (check_pointer(chain, "taper_chain_alloc", &err)) goto cleanup;

    solver_spec = taper_solver_spec_alloc(&err);
    if (check_pointer(solver_spec, "taper_solver_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_solver_spec_set_t_end(solver_spec, T_END, &err),
                     "taper_solver_spec_set_t_end", &err))
        goto cleanup;
    sim = taper_sim_alloc(chain, solver_spec, &err);
    if (check_pointer(sim, "taper_sim_alloc", &err)) goto cleanup;
    if (check_status(taper_sim_run(sim, &err), "taper_sim_run", &err)) goto cleanup;

    r->f_peak = taper_sim_statistic(sim, TAPER_STAT_WALL_PEAK_FORCE_RIGHT);
    r->t_peak = taper_sim_statistic(sim, TAPER_STAT_WALL_PEAK_TIME_RIGHT);
    r->impulse = taper_sim_statistic(sim, TAPER_STAT_WALL_IMPULSE_RIGHT);
    r->e_initial = taper_sim_statistic(sim, TAPER_STAT_ENERGY_INITIAL);
    r->e_reflected = taper_sim_statistic(sim, TAPER_STAT_ENERGY_REFLECTED);
    r->e_in_chain = taper_sim_statistic(sim, TAPER_STAT_ENERGY_IN_CHAIN);
    r->energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    r->steps = taper_sim_statistic(sim, TAPER_STAT_STEPS);
    double lost;
    if (momentum_lost(sim, chain, &lost)) goto cleanup;
    const double p0 = taper_chain_striker_mass(chain);
    r->momentum_error = fabs(lost - r->impulse) / p0;
    retval = 0;

cleanup:
    taper_sim_free(sim);
    taper_solver_spec_free(solver_spec);
    taper_chain_free(chain);
    taper_chain_spec_free(chain_spec);
    return retval;
}

int main(void)
{
    /* The tapered decorated chain's radii: large bead K = 1 - S (K-1),
     * then a small one of SMALL times it. */
    double tapered_decorated[2 * N_LARGE - 1];
    for (int k = 0; k < 2 * N_LARGE - 1; k++)
        tapered_decorated[k] = (1 - S * (k / 2)) * (k % 2 ? SMALL : 1.0);
    const double pattern[2] = {1.0, SMALL};
    const absorber absorbers[] = {
        {"monodisperse", TAPER_MONODISPERSE, N_LARGE, 0, NULL, 0, NULL},
        {"decorated", TAPER_DECORATED, 2 * N_LARGE - 1, 0, pattern, 2, NULL},
        {"tapered", TAPER_FORWARD_LINEAR, N_LARGE, S, NULL, 0, NULL},
        {"tapered decorated", TAPER_CUSTOM, 2 * N_LARGE - 1, 0, NULL, 0, tapered_decorated},
    };
    const int n_absorbers = sizeof absorbers / sizeof absorbers[0];

    const double force_unit = taper_unit_scale(TAPER_DIM_FORCE, YOUNG, POISSON, DENSITY, RADIUS, VELOCITY);
    const double time_unit = taper_unit_scale(TAPER_DIM_TIME, YOUNG, POISSON, DENSITY, RADIUS, VELOCITY);
    const double impulse_unit = taper_unit_scale(TAPER_DIM_IMPULSE, YOUNG, POISSON, DENSITY, RADIUS,
                                                 VELOCITY);
    if (!isfinite(force_unit * time_unit * impulse_unit)) {
        fprintf(stderr, "ERROR: taper_unit_scale refused the material\n");
        return EXIT_FAILURE;
    }

    printf("# a steel striker (R = %g mm) at %g m/s, a chain of steel beads, a steel wall;\n",
           RADIUS * 1e3, VELOCITY);
    printf("# energy in %% of the striker's, at t = %.0f us\n", T_END * time_unit * 1e6);
    printf("# %-18s %5s %9s %9s %12s %9s %9s %6s %9s %9s\n", "chain", "beads", "F_max [N]",
           "at [us]", "impulse[mNs]", "back [%]", "chain [%]", "steps", "E error", "P error");
    int failed = 0;
    for (int i = 0; i < n_absorbers; i++) {
        record r;
        if (protect(&absorbers[i], &r)) return EXIT_FAILURE;
        printf("  %-18s %5zu %9.2f %9.1f %12.4f %9.1f %9.1f %6.0f %9.2g %9.2g\n", absorbers[i].name,
               absorbers[i].n, r.f_peak * force_unit, r.t_peak * time_unit * 1e6,
               r.impulse * impulse_unit * 1e3, 100 * r.e_reflected / r.e_initial,
               100 * r.e_in_chain / r.e_initial, r.steps, r.energy_error, r.momentum_error);
        if (!(r.energy_error <= MAX_ENERGY_ERROR) || !(r.momentum_error <= MAX_MOMENTUM_ERROR)) {
            fprintf(stderr, "FAIL: %s: energy error %.3g (bound %g), momentum balance %.3g (bound %g)\n",
                    absorbers[i].name, r.energy_error, MAX_ENERGY_ERROR, r.momentum_error,
                    MAX_MOMENTUM_ERROR);
            failed = 1;
        }
    }
    printf("# checks: energy conserved within %g, the wall's impulse equal to the momentum lost "
           "within %g: %s\n", MAX_ENERGY_ERROR, MAX_MOMENTUM_ERROR, failed ? "FAILED" : "all hold");
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
