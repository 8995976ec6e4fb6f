/*
 * chain.c -- geometry of a granular chain (paper, Sec. II and the tapering
 * protocols of Secs. III-IV): radii, masses m_k = R_k^3 (uniform density,
 * unit first granule), contact factors r_k (eq. (7)) and the centres X0(k)
 * of the uncompressed, just-touching chain.  The settings are checked in
 * chain_spec.c; this file only adds the limits of double precision.
 */
#include "chain/chain_impl.h"

#include <math.h>
#include <stdlib.h>

/* Masses outside this range leave no room for the dynamics (velocities and
 * times scale with powers of the mass ratio).  They also bound every radius
 * by 1e100, so the chain's length (at most 2 N R_max) stays finite. */
#define MASS_MIN 1e-300
#define MASS_MAX 1e300

/* ln R_k for the analytic profiles, k = 1..N (ln avoids overflow in the
 * exponential chains before we can name the offending granule). */
static double log_radius(const taper_chain_spec *spec, size_t k)
{
    double km1 = (double)(k - 1);
    switch (spec->profile) {
    case TAPER_BACKWARD_LINEAR: return log1p(spec->s * km1);
    case TAPER_FORWARD_LINEAR: return log1p(-spec->s * km1);
    case TAPER_BACKWARD_EXPONENTIAL: return -km1 * log1p(-spec->q);
    case TAPER_FORWARD_EXPONENTIAL: return -km1 * log1p(spec->q);
    case TAPER_CUSTOM: return log(spec->radii[k - 1]);
    default: return 0.0;
    }
}

static int mass_in_range(const taper_chain_spec *spec, size_t k)
{
    double lm = 3.0 * log_radius(spec, k);
    return lm >= log(MASS_MIN) && lm <= log(MASS_MAX);
}

/* The parameter whose taper makes the masses leave the range. */
static const char *taper_parameter(taper_profile profile)
{
    return (profile == TAPER_BACKWARD_LINEAR || profile == TAPER_FORWARD_LINEAR) ? "s" : "q";
}

/* Masses must stay representable with room for the dynamics.  The analytic
 * profiles have ln R_k monotonic in k with R_1 = 1 in range, so the first
 * granule out of range is found by bisection in O(log N) evaluations. */
static taper_status check_mass_range(const taper_chain_spec *spec, taper_error *err)
{
    size_t first_bad = 0; /* 0: none */
    if (spec->profile == TAPER_CUSTOM) {
        for (size_t k = 1; k <= spec->n_granules && !first_bad; k++)
            if (!mass_in_range(spec, k)) first_bad = k;
    } else if (!mass_in_range(spec, spec->n_granules)) {
        size_t good = 1, bad = spec->n_granules; /* invariant: good in range, bad not */
        while (bad - good > 1) {
            size_t mid = good + (bad - good) / 2;
            if (mass_in_range(spec, mid))
                good = mid;
            else
                bad = mid;
        }
        first_bad = mass_in_range(spec, 1) ? bad : 1;
    }
    if (!first_bad) return TAPER_OK;
    double log_mass = 3.0 * log_radius(spec, first_bad);
    if (spec->profile == TAPER_CUSTOM)
        return taper_fail_field(err, TAPER_ERANGE, "radii",
                                "granule %zu: mass m_k = R_k^3 = exp(%.6g) is outside [%g, %g], "
                                "beyond what double precision can integrate; change radii(%zu)",
                                first_bad, log_mass, MASS_MIN, MASS_MAX, first_bad);
    /* Fewer granules is the change that keeps the chain the user asked for
     * up to where it breaks down: name n_granules, mention the taper. */
    return taper_fail_field(err, TAPER_ERANGE, "n_granules",
                            "granule %zu: mass m_k = R_k^3 = exp(%.6g) is outside [%g, %g], "
                            "beyond what double precision can integrate; use at most %zu granules "
                            "(or a smaller %s)",
                            first_bad, log_mass, MASS_MIN, MASS_MAX, first_bad - 1,
                            taper_parameter(spec->profile));
}

void taper_chain_free(taper_chain *chain)
{
    if (!chain) return;
    free(chain->radius);
    free(chain->mass);
    free(chain->contact);
    free(chain->rest);
    free(chain);
}

static taper_chain *chain_new(const taper_chain_spec *spec)
{
    taper_chain *c = calloc(1, sizeof *c);
    if (!c) return NULL;
    size_t n = spec->n_granules;
    c->n = n;
    c->profile = spec->profile;
    c->exponent = spec->exponent;
    c->radius = malloc(n * sizeof(double));
    c->mass = malloc(n * sizeof(double));
    c->contact = malloc(n * sizeof(double));
    c->rest = malloc(n * sizeof(double));
    if (!c->radius || !c->mass || !c->contact || !c->rest) {
        taper_chain_free(c);
        return NULL;
    }
    return c;
}

/* r_k = (2 R_k R_{k+1} / (R_k + R_{k+1}))^{1/2}, eq. (7). */
static double contact_factor(double a, double b) { return sqrt(2.0 * a * b / (a + b)); }

static void fill_geometry(taper_chain *c, const taper_chain_spec *spec)
{
    for (size_t k = 1; k <= c->n; k++) {
        double R = (spec->profile == TAPER_CUSTOM) ? spec->radii[k - 1]
                   : (spec->profile == TAPER_MONODISPERSE) ? 1.0
                   : exp(log_radius(spec, k));
        /* Linear profiles are exact in floating point without exp/log. */
        if (spec->profile == TAPER_BACKWARD_LINEAR) R = 1.0 + spec->s * (double)(k - 1);
        if (spec->profile == TAPER_FORWARD_LINEAR) R = 1.0 - spec->s * (double)(k - 1);
        c->radius[k - 1] = R;
        c->mass[k - 1] = R * R * R;
    }
    c->rest[0] = 0.0;
    for (size_t k = 1; k < c->n; k++) {
        c->contact[k - 1] = contact_factor(c->radius[k - 1], c->radius[k]);
        c->rest[k] = c->rest[k - 1] + c->radius[k - 1] + c->radius[k];
    }
    c->contact[c->n - 1] = NAN;
}

taper_chain *taper_chain_alloc(const taper_chain_spec *spec, taper_error *err)
{
    if (!spec) {
        taper_fail(err, TAPER_EINVAL, "taper_chain_alloc: spec is NULL");
        return NULL;
    }
    if (taper_chain_spec_check(spec, err) != TAPER_OK) return NULL;
    if (check_mass_range(spec, err) != TAPER_OK) return NULL;
    taper_chain *c = chain_new(spec);
    if (!c) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a chain of %zu granules", spec->n_granules);
        return NULL;
    }
    fill_geometry(c, spec);
    taper_ok(err);
    return c;
}

size_t taper_chain_size(const taper_chain *chain) { return chain ? chain->n : 0; }
double taper_chain_exponent(const taper_chain *chain) { return chain ? chain->exponent : NAN; }
taper_profile taper_chain_profile(const taper_chain *chain)
{
    return chain ? chain->profile : (taper_profile)-1;
}
const double *taper_chain_radius(const taper_chain *chain) { return chain ? chain->radius : NULL; }
const double *taper_chain_mass(const taper_chain *chain) { return chain ? chain->mass : NULL; }
const double *taper_chain_contact(const taper_chain *chain) { return chain ? chain->contact : NULL; }
const double *taper_chain_rest_position(const taper_chain *chain) { return chain ? chain->rest : NULL; }
