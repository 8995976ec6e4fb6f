/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * pulse.c -- a pulse in a backward-tapered chain, numerics next to theory.
 *
 * Harbola, Rosas, Esposito and Lindenberg (arXiv:0905.4512) consider N
 * granules with radii R_k = 1 + S (k-1) (a "backward" linear taper: each
 * granule is larger and heavier than the one before) and Hertz contacts,
 * n = 5/2.  Granule 1 is kicked with unit velocity.  The binary collision
 * approximation treats the pulse as a sequence of two-body collisions:
 * granule k leaves its collision with velocity v_k, eq. (9), and the pulse
 * passes granule k at t_k = T_1 + ... + T_k, eq. (19).  Here we integrate
 * the full equations of motion, eq. (6), read off when the pulse passes
 * each granule (t_pass) and how fast each granule moves at its first
 * velocity maximum (v_peak), and print them next to the theory.  The
 * passage times agree to about 2 per cent.  The peak velocities lie about
 * a third below the theory's v_k (the real pulse is spread over several
 * granules, which the two-body picture ignores), yet both fall off with the
 * same power of k, approaching the large-k law v ~ k^-3/2, eq. (22), once
 * S k >> 1.
 *
 * The steps are those of a SUNDIALS example: create the objects, set them
 * up, run, read the results and the statistics, free everything; every
 * return value is checked, and the program exits non-zero when a call
 * fails or a passage time strays more than 5 % from the theory or the
 * energy is not conserved.  The settings live in objects the library
 * allocates and are written through setters, which check each value at
 * once and name the setting they refuse (docs/api.md, "Why opaque
 * objects").
 *
 * Build against an installed libtaper:
 *     cc pulse.c $(pkg-config --cflags --libs taper) \
 *        -Wl,-rpath,$(pkg-config --variable=libdir taper) -lm -o pulse
 */
#include <taper.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define N 200    /* granules                 */
#define S 0.1    /* tapering strength        */
#define EXPONENT 2.5 /* Hertz contacts       */
#define MAX_THEORY_DEVIATION 0.05
#define MAX_ENERGY_ERROR 1e-6

/* Check a returned status: on failure print the function, the setting at
 * fault (if one is) and the library's message, and return 1. */
static int check_status(taper_status status, const char *funcname, const taper_error *err)
{
    if (status == TAPER_OK) return 0;
    fprintf(stderr, "\nERROR: %s() failed with status %d (%s)%s%s%s\n  %s\n", funcname,
            (int)status, taper_strerror(status), err->field ? ": setting '" : "",
            err->field ? err->field : "", err->field ? "'" : "", err->message);
    return 1;
}

/* Check a returned pointer: NULL means failure, explained in err. */
static int check_pointer(const void *pointer, const char *funcname, const taper_error *err)
{
    return pointer ? 0 : check_status(err->status, funcname, err);
}

static void print_final_stats(const taper_sim *sim)
{
    printf("#\n# Final statistics:\n");
    for (int i = 0; i < TAPER_N_STATISTICS; i++)
        printf("#   %-16s = %.10g\n", taper_statistic_name((taper_statistic)i),
               taper_sim_statistic(sim, (taper_statistic)i));
}

int main(void)
{
    taper_error err;
    taper_chain_spec *chain_spec = NULL;
    taper_solver_spec *solver_spec = NULL;
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    int retval = EXIT_FAILURE;

    /* 1. The chain: a settings object with the library's defaults, set
     *    one value at a time, then built.  Settings a later version adds
     *    keep their defaults here. */
    chain_spec = taper_chain_spec_alloc(&err);
    if (check_pointer(chain_spec, "taper_chain_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_chain_spec_set_profile(chain_spec, TAPER_BACKWARD_LINEAR, &err),
                     "taper_chain_spec_set_profile", &err))
        goto cleanup;
    if (check_status(taper_chain_spec_set_n_granules(chain_spec, N, &err),
                     "taper_chain_spec_set_n_granules", &err))
        goto cleanup;
    if (check_status(taper_chain_spec_set_s(chain_spec, S, &err), "taper_chain_spec_set_s", &err))
        goto cleanup;
    if (check_status(taper_chain_spec_set_exponent(chain_spec, EXPONENT, &err),
                     "taper_chain_spec_set_exponent", &err))
        goto cleanup;
    chain = taper_chain_alloc(chain_spec, &err);
    if (check_pointer(chain, "taper_chain_alloc", &err)) goto cleanup;

    /* 2. The full dynamics with the library's default solver (Adams,
     *    measured tolerances), set explicitly here to show the setters;
     *    the run ends once every observable is known.  taper_sim_alloc
     *    also computes the binary collision theory of the chain. */
    solver_spec = taper_solver_spec_alloc(&err);
    if (check_pointer(solver_spec, "taper_solver_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_solver_spec_set_method(solver_spec, TAPER_ADAMS, &err),
                     "taper_solver_spec_set_method", &err))
        goto cleanup;
    if (check_status(taper_solver_spec_set_rtol(solver_spec, 1e-10, &err),
                     "taper_solver_spec_set_rtol", &err))
        goto cleanup;
    sim = taper_sim_alloc(chain, solver_spec, &err);
    if (check_pointer(sim, "taper_sim_alloc", &err)) goto cleanup;
    if (check_status(taper_sim_run(sim, &err), "taper_sim_run", &err)) goto cleanup;

    /* 3. Observables and theory: arrays of length N owned by the sim. */
    const double *t_pass = taper_sim_observable(sim, TAPER_T_PASS);
    const double *v_peak = taper_sim_observable(sim, TAPER_V_PEAK);
    const double *t_theory = taper_sim_theory(sim, TAPER_THEORY_T);
    const double *v_theory = taper_sim_theory(sim, TAPER_THEORY_V);
    if (check_pointer(t_pass, "taper_sim_observable", &err) ||
        check_pointer(v_peak, "taper_sim_observable", &err) ||
        check_pointer(t_theory, "taper_sim_theory", &err) ||
        check_pointer(v_theory, "taper_sim_theory", &err))
        goto cleanup;

    printf("# libtaper %s: %s chain, N = %zu, S = %g, n = %g\n", taper_version(),
           taper_profile_name(taper_chain_profile(chain)), taper_chain_size(chain),
           taper_chain_spec_s(chain_spec), taper_chain_exponent(chain));
    printf("# %5s %14s %14s %14s %14s\n", "k", "t_pass", "t_k theory", "v_peak", "v_k theory");
    for (int k = 1; k < N; k += (k < 10 ? 1 : k < 50 ? 10 : 50))
        printf("  %5d %14.8f %14.8f %14.8f %14.8f\n", k, t_pass[k - 1], t_theory[k - 1],
               v_peak[k - 1], v_theory[k - 1]);

    /* 4. The power law v ~ k^-3/2, numerics and theory, over the tail. */
    const int k1 = N / 2, k2 = N - 1;
    const double ln_k = log((double)k2 / k1);
    printf("# slope of ln v over ln k, k = %d..%d: v_peak %.3f, theory %.3f, large-k law %.3f\n",
           k1, k2, log(v_peak[k2 - 1] / v_peak[k1 - 1]) / ln_k,
           log(v_theory[k2 - 1] / v_theory[k1 - 1]) / ln_k,
           taper_asymptotic_exponent(TAPER_LAW_V_OF_K, taper_chain_exponent(chain)));

    /* 5. The statistics of the run, by name. */
    print_final_stats(sim);

    /* 6. The checks: every passage time within MAX_THEORY_DEVIATION of the
     *    theory (measured: 2.1 % at most), energy conserved. */
    double worst = 0;
    for (int k = 1; k < N; k++)
        worst = fmax(worst, fabs(t_pass[k - 1] - t_theory[k - 1]) / t_theory[k - 1]);
    const double energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    printf("# checks: passage times within %.1f %% of the theory (at most %g %%), energy error "
           "%.2g (at most %g): %s\n", 100 * worst, 100 * MAX_THEORY_DEVIATION, energy_error,
           MAX_ENERGY_ERROR,
           worst <= MAX_THEORY_DEVIATION && energy_error <= MAX_ENERGY_ERROR ? "all hold" : "FAILED");
    if (!(worst <= MAX_THEORY_DEVIATION && energy_error <= MAX_ENERGY_ERROR)) goto cleanup;
    retval = EXIT_SUCCESS;

cleanup:
    taper_sim_free(sim);
    taper_solver_spec_free(solver_spec);
    taper_chain_free(chain);
    taper_chain_spec_free(chain_spec);
    return retval;
}
