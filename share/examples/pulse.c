/*
 * pulse.c -- a pulse in a backward-tapered chain, numerics next to theory.
 *
 * Harbola, Rosas, Esposito and Lindenberg consider N granules with radii
 * R_k = 1 + S (k-1) (a "backward" linear taper: each granule is larger and
 * heavier than the one before) and Hertz contacts, n = 5/2.  Granule 1 is
 * kicked with unit velocity.  The binary collision approximation treats the
 * pulse as a sequence of two-body collisions: granule k leaves its
 * collision with velocity v_k, and the pulse passes granule k at
 * t_k = T_1 + ... + T_k.  Here we integrate the full equations of motion,
 * read off when the pulse passes each granule (t_pass) and how fast each
 * granule moves at its first velocity maximum (v_peak), and print them next
 * to the theory.  The passage times agree to about 2 per cent.  The peak
 * velocities lie about a third below the theory's v_k (the real pulse is
 * spread over several granules, which the two-body picture ignores), yet
 * both fall off with the same power of k, approaching the large-k law
 * v ~ k^-3/2 once S k >> 1 (paper, Sec. III A).
 *
 * Build against an installed libtaper:
 *     cc pulse.c $(pkg-config --cflags --libs taper) -o pulse
 */
#include <taper.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define N 200    /* granules                 */
#define S 0.1    /* tapering strength        */

/* Reports a failure of the library with its message and ends the program. */
static void die(const char *what, const taper_error *err)
{
    fprintf(stderr, "pulse: %s: %s (%s)\n", what, err->message, taper_strerror(err->status));
    exit(EXIT_FAILURE);
}

int main(void)
{
    taper_error err;

    /* 1. The chain.  Start from the defaults so that fields added in later
     *    versions of the library get sensible values. */
    taper_chain_spec chain_spec;
    taper_chain_spec_init(&chain_spec);
    chain_spec.profile = TAPER_BACKWARD_LINEAR;
    chain_spec.n_granules = N;
    chain_spec.s = S;
    chain_spec.exponent = 2.5;
    taper_chain *chain = taper_chain_alloc(&chain_spec, &err);
    if (!chain) die("chain", &err);

    /* 2. The binary collision approximation: v_k and t_k for every k. */
    static double v_theory[N], t_theory[N];
    if (taper_theory_compute(chain, v_theory, NULL, NULL, t_theory, &err) != TAPER_OK)
        die("theory", &err);

    /* 3. The full dynamics with the library's default solver (Adams,
     *    measured tolerances); the run ends once every observable is known. */
    taper_solver_spec solver_spec;
    taper_solver_spec_init(&solver_spec);
    taper_sim *sim = taper_sim_alloc(chain, &solver_spec, &err);
    if (!sim) die("simulation", &err);
    if (taper_sim_run(sim, &err) != TAPER_OK) die("run", &err);

    /* 4. Observables: arrays of length N owned by the sim. */
    const double *t_pass = taper_sim_observable(sim, TAPER_T_PASS);
    const double *v_peak = taper_sim_observable(sim, TAPER_V_PEAK);
    taper_stats stats;
    taper_sim_stats(sim, &stats);

    printf("# libtaper %s: backward linear chain, N = %d, S = %g, n = %g\n", taper_version(), N, S,
           taper_chain_exponent(chain));
    printf("# %5s %14s %14s %14s %14s\n", "k", "t_pass", "t_k theory", "v_peak", "v_k theory");
    for (int k = 1; k < N; k += (k < 10 ? 1 : k < 50 ? 10 : 50))
        printf("  %5d %14.8f %14.8f %14.8f %14.8f\n", k, t_pass[k - 1], t_theory[k - 1],
               v_peak[k - 1], v_theory[k - 1]);
    printf("# %ld steps, energy conserved to %.1e, pulse reached granule %zu at t = %g\n",
           stats.steps, stats.energy_error, stats.granule_reached, stats.t_final);

    /* 5. The power law v ~ k^-3/2, numerics and theory, over the tail. */
    const int k1 = N / 2, k2 = N - 1;
    double ln_k = log((double)k2 / k1);
    printf("# slope of ln v over ln k, k = %d..%d: v_peak %.3f, theory %.3f, large-k law %.3f\n",
           k1, k2, log(v_peak[k2 - 1] / v_peak[k1 - 1]) / ln_k,
           log(v_theory[k2 - 1] / v_theory[k1 - 1]) / ln_k,
           taper_asymptotic_exponent(TAPER_LAW_V_OF_K, chain_spec.exponent));

    taper_sim_free(sim);
    taper_chain_free(chain);
    return EXIT_SUCCESS;
}
