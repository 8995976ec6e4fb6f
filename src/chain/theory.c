/* SPDX-License-Identifier: GPL-3.0-or-later */
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
 * The options beyond the paper (docs/physics.md, "Theory columns"): a striker is
 * granule 0 of an extended chain, so the columns start from its collision
 * with granule 1 (v_1 = 2 m_s / (m_s + m_1), t_k includes that collision's
 * residence time); materials and disorder only change m_k and r_k, which
 * the recursion reads; walls do not touch the first pass.  A decorated
 * chain is walked as its effective chain (walk_of below), its columns at
 * the large granules.  A static load, losses, and decorated chains whose
 * small granules are not light take the chain out of the approximation:
 * the columns are NaN and chain->theory_note says why.
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

/* The terms of eq. (18) that depend on n alone, computed once per chain:
 * the recursion below adds them in log_collision_time's order, so that
 * each T_k is the same double bit for bit, at a third of the cost (the two
 * lngamma were most of it: 10^7 granules took 1.9 s). */
typedef struct collision_constants {
    double n, half_log_pi, log_half_n, slope, lngamma_a, lngamma_b;
} collision_constants;

static collision_constants constants_of(double n)
{
    return (collision_constants){.n = n, .half_log_pi = 0.5 * log(3.14159265358979323846),
                                 .log_half_n = log(n / 2.0), .slope = 2.0 / n - 1.0,
                                 .lngamma_a = gsl_sf_lngamma(1.0 + 1.0 / n),
                                 .lngamma_b = gsl_sf_lngamma(1.0 / n + 0.5)};
}

static double log_collision_time_of(const collision_constants *c, double log_mu, double log_r,
                                    double log_zdot0)
{
    return c->half_log_pi + (c->log_half_n + log_mu - log_r) / c->n + c->slope * log_zdot0
           + c->lngamma_a - c->lngamma_b;
}

double taper_theory_collision_time(double mu, double r, double zdot0, double n)
{
    if (!(mu > 0.0) || !(r > 0.0) || !(zdot0 > 0.0) || !(n > 1.0) || !isfinite(n))
        return NAN;
    return exp(log_collision_time(log(mu), log(r), log(zdot0), n));
}

/* The setting that moves a chain's theory back into double precision: the
 * radii of a custom chain, the pattern of a decorated one, the length of
 * any other (the first granules are computed either way). */
static const char *range_field(const taper_chain *chain)
{
    if (chain->profile == TAPER_DECORATED) return "pattern";
    return chain->profile == TAPER_CUSTOM ? "radii" : "n_granules";
}

/* The chain the recursion walks.  For every chain but a decorated one it is
 * the chain itself (stride 1).  A decorated chain of period P >= 2 is walked
 * as its effective chain (docs/physics.md, "Decorated chains"): effective
 * granule K is large granule k = (K-1) P + 1 with the small granules up to
 * the next large one; its mass is their sum, and the contacts between large
 * granule K and K+1 act as Hertz springs in series through massless small
 * granules (one force F through all of them): the overlaps z_j = (F/r_j)^(1/(n-1))
 * add up to Z, so F = r_eff Z^(n-1) with
 *     r_eff = (sum_j r_j^(-1/(n-1)))^(-(n-1)).
 * Derived here, not taken from a paper (docs/physics.md says why). */
typedef struct walked {
    const taper_chain *chain;
    size_t stride; /* P, or 1 */
    size_t n;      /* granules walked */
} walked;

static walked walk_of(const taper_chain *chain)
{
    walked w = {chain, 1, chain->n};
    if (chain->pattern_period >= 2) {
        w.stride = chain->pattern_period;
        w.n = (chain->n + w.stride - 1) / w.stride;
    }
    return w;
}

/* The mass of walked granule K (1-based). */
static double walked_mass(const walked *w, size_t K)
{
    const double *m = w->chain->mass;
    size_t first = (K - 1) * w->stride;
    if (w->stride == 1) return m[first];
    double sum = 0.0;
    for (size_t i = first; i < first + w->stride && i < w->chain->n; i++) sum += m[i];
    return sum;
}

/* ln of the contact factor between walked granules K and K+1. */
static double walked_log_contact(const walked *w, size_t K)
{
    const double *r = w->chain->contact;
    size_t first = (K - 1) * w->stride;
    if (w->stride == 1) return log(r[first]);
    double p = 1.0 / (w->chain->exponent - 1.0), sum = 0.0;
    for (size_t i = first; i < first + w->stride; i++) sum += pow(r[i], -p);
    return -(w->chain->exponent - 1.0) * log(sum);
}

static void fill_nan(size_t n, double *v, double *mu, double *T, double *t)
{
    for (size_t k = 0; k < n; k++) {
        if (v) v[k] = NAN;
        if (mu) mu[k] = NAN;
        if (T) T[k] = NAN;
        if (t) t[k] = NAN;
    }
}

/* Granules between two looks at the caller's monitor: about 10 ms of the
 * recursion, so that a signal stops the theory of the longest chain within
 * a fraction of a second. */
#define MONITOR_EVERY 65536

taper_status taper_theory_compute(const taper_chain *chain, double *v, double *mu, double *T,
                                  double *t, taper_error *err)
{
    return taper_theory_compute_monitored(chain, v, mu, T, t, NULL, NULL, err);
}

taper_status taper_theory_compute_monitored(const taper_chain *chain, double *v, double *mu,
                                            double *T, double *t, taper_monitor_fn monitor,
                                            void *user, taper_error *err)
{
    if (!chain) return taper_fail(err, TAPER_EINVAL, "taper_theory_compute: chain is NULL");
    if (chain->theory_note[0]) {
        /* Outside the approximation: no column, by design (the note says
         * why), and not an error. */
        fill_nan(chain->n, v, mu, T, t);
        return taper_ok(err);
    }
    const walked w = walk_of(chain);
    /* Granules between the walked ones (the small granules of a decorated
     * chain) have no column of their own. */
    if (w.stride > 1) fill_nan(chain->n, v, mu, T, t);
    const size_t n = w.n;
    const collision_constants cc = constants_of(chain->exponent);
    double log_v = 0.0; /* v_1 = 1 */
    double elapsed = 0.0;
    double m = walked_mass(&w, 1);
    if (w.stride > 1) {
        /* The impulse's energy m_1 / 2, carried by the effective granule:
         * v_1 = (m_1 / M_1)^(1/2), so that the effective chain conserves
         * energy as every binary collision does. */
        log_v = 0.5 * log(chain->mass[0] / m);
    }
    if (chain->striker_mass > 0.0) {
        /* The striker (granule 0, v_0 = 1) hits granule 1 at rest: eq. (8)
         * gives v_1, eq. (18) the collision's residence time, which the
         * times t_k of eq. (19) include. */
        double ms = chain->striker_mass;
        double log_mu = log(ms) - log1p(ms / m);
        elapsed = exp(log_collision_time_of(&cc, log_mu, log(chain->striker_contact), 0.0));
        log_v = log(2.0) - log1p(m / ms);
    }
    for (size_t K = 1; K <= n; K++) {
        size_t out = (K - 1) * w.stride; /* index of walked granule K */
        if (monitor && K % MONITOR_EVERY == 0) {
            /* window 0..0: the theory, not the integration, is calling */
            const taper_progress p = {.granule = out, .target = chain->n, .t = elapsed};
            if (monitor(&p, user)) {
                /* The entry where it stopped is NaN, a reader's end of
                 * what is known; those after it are not written: filling
                 * them would touch every page of the arrays the caller
                 * has not used yet (10^7 granules: 0.1-0.4 s), after the
                 * caller asked to stop at once. */
                if (v) v[out] = NAN;
                if (mu) mu[out] = NAN;
                if (T) T[out] = NAN;
                if (t) t[out] = NAN;
                return taper_fail(err, TAPER_EINTERRUPTED,
                                  "theory: interrupted after granule %zu of %zu", out, chain->n);
            }
        }
        /* A custom chain whose masses go up and down by large factors loses
         * velocity at every step up and at most doubles it at a step down:
         * v_k can leave double precision long before the masses do. */
        double vk = exp(log_v);
        if (!(vk >= DBL_MIN && vk <= DBL_MAX))
            return taper_fail_field(err, TAPER_ERANGE, range_field(chain),
                                    "theory: velocity of granule %zu is exp(%g), outside double "
                                    "precision; use at most %zu granules",
                                    out + 1, log_v, out > 1 ? out : (size_t)1);
        if (v) v[out] = vk;
        if (K == n) {
            if (mu) mu[out] = NAN;
            if (T) T[out] = NAN;
            if (t) t[out] = NAN;
            break;
        }
        double m_next = walked_mass(&w, K + 1);
        double ratio = m_next / m;                    /* m_{k+1} / m_k */
        double log_mu = log(m) - log1p(m / m_next);   /* m_k m_{k+1}/(m_k+m_{k+1}) */
        double log_T = log_collision_time_of(&cc, log_mu, walked_log_contact(&w, K), log_v);
        double Tk = exp(log_T);
        elapsed += Tk;                                /* eq. (19) */
        if (!isfinite(Tk) || !isfinite(elapsed))
            return taper_fail_field(err, TAPER_ERANGE, range_field(chain),
                                    "theory: residence time of granule %zu overflows double "
                                    "precision (ln T = %g); use at most %zu granules",
                                    out + 1, log_T, out + 1);
        if (mu) mu[out] = exp(log_mu);
        if (T) T[out] = Tk;
        if (t) t[out] = elapsed;
        log_v += log(2.0) - log1p(ratio);             /* eq. (8) */
        m = m_next;
    }
    return taper_ok(err);
}

#define QUANTITY_NAME(constant, name, dimension) [constant] = name,
#define QUANTITY_DIMENSION(constant, name, dimension) [constant] = TAPER_DIM_##dimension,
static const char *const quantity_names[] = {TAPER_THEORY_QUANTITY_LIST(QUANTITY_NAME)};
static const taper_dimension quantity_dimensions[] = {TAPER_THEORY_QUANTITY_LIST(QUANTITY_DIMENSION)};

taper_dimension taper_theory_quantity_dimension(taper_theory_quantity which)
{
    return (unsigned)which < TAPER_N_THEORY_QUANTITIES ? quantity_dimensions[which]
                                                        : TAPER_DIM_NUMBER;
}

const char *taper_theory_quantity_name(taper_theory_quantity which)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)which >= TAPER_N_THEORY_QUANTITIES) return NULL;
    return quantity_names[which];
}

/* The effective chain of a decorated chain holds while the small granules
 * are light against the large ones.  Measured against the numerics
 * (docs/physics.md, "Decorated chains"): up to a small radius of 0.45 the
 * large granules settle to one velocity, as the effective chain's equal
 * granules say, and the time per period is 2.5 % (radius 0.1) to 3.2 %
 * (0.45) longer than the numerics', against 2.5 % for the binary collision
 * approximation of a monodisperse chain.  From radius 0.46 on the pulse
 * keeps losing velocity to the small granules (at 1/2 by 0.6 % every 20
 * periods), which no chain of equal effective granules describes.  The
 * limit is the mass ratio of radius 0.45 in one material. */
#define DECORATED_MASS_RATIO_MAX (0.45 * 0.45 * 0.45)

/* The first small granule heavier than the limit, 0 if none. */
static size_t heavy_small_granule(const taper_chain *chain)
{
    size_t P = chain->pattern_period;
    for (size_t k = 1; k <= chain->n; k++) {
        size_t large = k - (k - 1) % P;
        if (k != large && !(chain->mass[k - 1] <= DECORATED_MASS_RATIO_MAX * chain->mass[large - 1]))
            return k;
    }
    return 0;
}

void chain_theory_note(taper_chain *chain)
{
    chain->theory_note[0] = '\0';
    if (chain->load > 0.0) {
        snprintf(chain->theory_note, sizeof chain->theory_note, "%s",
                 "precompression: the binary collision approximation of arXiv:0905.4512 is for "
                 "chains at rest and just touching, not under a static load");
        return;
    }
    if (chain->damping > 0.0 || chain->drag > 0.0) {
        snprintf(chain->theory_note, sizeof chain->theory_note, "%s",
                 "dissipation: the binary collision approximation of arXiv:0905.4512 is elastic");
        return;
    }
    if (chain->pattern_period >= 2) {
        size_t k = heavy_small_granule(chain);
        if (k) {
            size_t large = k - (k - 1) % chain->pattern_period;
            snprintf(chain->theory_note, sizeof chain->theory_note,
                     "decorated chain: granule %zu has mass %.3g, more than 0.45^3 = %.4g of "
                     "the large granule %zu before it (%.3g); the effective chain of "
                     "docs/physics.md needs small granules between large ones", k,
                     chain->mass[k - 1], DECORATED_MASS_RATIO_MAX, large,
                     chain->mass[large - 1]);
        }
    }
}
