/*
 * theory.c -- the binary collision approximation (paper, Sec. II).
 *
 * Each collision is a two-body problem: granule k arrives with v_k and meets
 * granule k+1 at rest.  Momentum and energy give eq. (8), whose product is
 * eq. (9); the relative coordinate z_k obeys eq. (12), a particle of mass
 * mu_k in the potential (r_k/n) z^n, whose half-period to maximum
 * compression is the residence time T_k of eq. (18); their sum is the time
 * t_k of eq. (19).  Equation numbers are those printed in arXiv:0905.4512.
 * Everything is computed in logarithms so that long exponential chains fail
 * with a named granule instead of overflowing in an intermediate product.
 *
 * The options of issue 15 (docs/physics.md, "Theory columns"): a striker is
 * granule 0 of an extended chain, so the columns start from its collision
 * with granule 1 (v_1 = 2 m_s / (m_s + m_1), t_k includes that collision's
 * residence time); materials and disorder only change m_k and r_k, which
 * the recursion reads; walls do not touch the first pass.  A static load
 * and losses take the chain out of the approximation: the columns are NaN
 * and chain->theory_note says why.
 */
#include "chain/chain_impl.h"

#include <float.h>
#include <gsl/gsl_sf_gamma.h>
#include <math.h>
#include <stdio.h>

/* ln of eq. (18).  lngamma on (1, 2] never raises a GSL error. */
static double log_collision_time(double log_mu, double log_r, double log_zdot0, double n)
{
    return 0.5 * log(3.14159265358979323846) + (log(n / 2.0) + log_mu - log_r) / n
           + (2.0 / n - 1.0) * log_zdot0
           + gsl_sf_lngamma(1.0 + 1.0 / n) - gsl_sf_lngamma(1.0 / n + 0.5);
}

double taper_theory_collision_time(double mu, double r, double zdot0, double n)
{
    if (!(mu > 0.0) || !(r > 0.0) || !(zdot0 > 0.0) || !(n > 1.0) || !isfinite(n))
        return NAN;
    return exp(log_collision_time(log(mu), log(r), log(zdot0), n));
}

/* The setting that moves a chain's theory back into double precision: the
 * radii of a custom chain, the length of any other (the first granules are
 * computed either way). */
static const char *range_field(const taper_chain *chain)
{
    return chain->profile == TAPER_CUSTOM ? "radii" : "n_granules";
}

taper_status taper_theory_compute(const taper_chain *chain, double *v, double *mu, double *T,
                                  double *t, taper_error *err)
{
    if (!chain) return taper_fail(err, TAPER_EINVAL, "taper_theory_compute: chain is NULL");
    const size_t n = chain->n;
    const double *m = chain->mass;
    if (chain->theory_note[0]) {
        /* Outside the approximation: no column, by design (the note says
         * why), and not an error. */
        for (size_t k = 0; k < n; k++) {
            if (v) v[k] = NAN;
            if (mu) mu[k] = NAN;
            if (T) T[k] = NAN;
            if (t) t[k] = NAN;
        }
        return taper_ok(err);
    }
    double log_v = 0.0; /* v_1 = 1 */
    double elapsed = 0.0;
    if (chain->striker_mass > 0.0) {
        /* The striker (granule 0, v_0 = 1) hits granule 1 at rest: eq. (8)
         * gives v_1, eq. (18) the collision's residence time, which the
         * times t_k of eq. (19) include. */
        double ms = chain->striker_mass;
        double log_mu = log(ms) - log1p(ms / m[0]);
        elapsed = exp(log_collision_time(log_mu, log(chain->striker_contact), 0.0,
                                         chain->exponent));
        log_v = log(2.0) - log1p(m[0] / ms);
    }
    for (size_t k = 1; k <= n; k++) {
        /* A custom chain whose masses go up and down by large factors loses
         * velocity at every step up and at most doubles it at a step down:
         * v_k can leave double precision long before the masses do. */
        double vk = exp(log_v);
        if (!(vk >= DBL_MIN && vk <= DBL_MAX))
            return taper_fail_field(err, TAPER_ERANGE, range_field(chain),
                                    "theory: velocity of granule %zu is exp(%g), outside double "
                                    "precision", k, log_v);
        if (v) v[k - 1] = vk;
        if (k == n) break;
        double ratio = m[k] / m[k - 1];          /* m_{k+1} / m_k */
        double log_mu = log(m[k - 1]) - log1p(m[k - 1] / m[k]); /* m_k m_{k+1}/(m_k+m_{k+1}) */
        double log_T = log_collision_time(log_mu, log(chain->contact[k - 1]), log_v,
                                          chain->exponent);
        double Tk = exp(log_T);
        elapsed += Tk;                            /* eq. (19) */
        if (!isfinite(Tk) || !isfinite(elapsed))
            return taper_fail_field(err, TAPER_ERANGE, range_field(chain),
                                    "theory: residence time of granule %zu overflows double "
                                    "precision (ln T = %g)", k, log_T);
        if (mu) mu[k - 1] = exp(log_mu);
        if (T) T[k - 1] = Tk;
        if (t) t[k - 1] = elapsed;
        log_v += log(2.0) - log1p(ratio);        /* eq. (8) */
    }
    if (mu) mu[n - 1] = NAN;
    if (T) T[n - 1] = NAN;
    if (t) t[n - 1] = NAN;
    return taper_ok(err);
}

static const char *const quantity_names[TAPER_N_THEORY_QUANTITIES] = {
    [TAPER_THEORY_V] = "v",
    [TAPER_THEORY_MU] = "mu",
    [TAPER_THEORY_T_RES] = "T",
    [TAPER_THEORY_T] = "t",
};

const char *taper_theory_quantity_name(taper_theory_quantity which)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)which >= TAPER_N_THEORY_QUANTITIES) return NULL;
    return quantity_names[which];
}

void chain_theory_note(taper_chain *chain)
{
    const char *why = NULL;
    if (chain->load > 0.0)
        why = "precompression: the binary collision approximation of arXiv:0905.4512 is for "
              "chains at rest and just touching, not under a static load";
    else if (chain->damping > 0.0 || chain->drag > 0.0)
        why = "dissipation: the binary collision approximation of arXiv:0905.4512 is elastic";
    snprintf(chain->theory_note, sizeof chain->theory_note, "%s", why ? why : "");
}
