/*
 * chain.c -- geometry of a granular chain (paper, Sec. II and the tapering
 * protocols of Secs. III-IV): radii, masses m_k = R_k^3 (uniform density,
 * unit first granule), contact factors r_k (eq. r-prime) and the centres
 * X0(k) of the uncompressed, just-touching chain.
 */
#include "core/taper_internal.h"

#include <ctype.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const profile_names[] = {
    "monodisperse", "backward_linear", "forward_linear",
    "backward_exponential", "forward_exponential", "custom",
};
#define N_PROFILES (sizeof profile_names / sizeof profile_names[0])

/* Masses outside this range leave no room for the dynamics (velocities and
 * times scale with powers of the mass ratio). */
#define MASS_MIN 1e-300
#define MASS_MAX 1e300

const char *taper_profile_name(int profile)
{
    if (profile < 0 || (size_t)profile >= N_PROFILES) return NULL;
    return profile_names[profile];
}

int taper_profile_from_name(const char *name, int *profile)
{
    if (!name || !profile) return TAPER_EINVAL;
    for (size_t i = 0; i < N_PROFILES; i++) {
        if (strcasecmp(name, profile_names[i]) == 0) {
            *profile = (int)i;
            return TAPER_OK;
        }
    }
    return TAPER_EINVAL;
}

void taper_chain_spec_init(taper_chain_spec *spec)
{
    if (!spec) return;
    memset(spec, 0, sizeof *spec);
    spec->profile = TAPER_MONODISPERSE;
    spec->n_granules = 100;
    spec->s = 0.0;
    spec->q = 0.0;
    spec->exponent = 2.5;
    spec->radii = NULL;
}

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

static int validate_parameters(const taper_chain_spec *spec, taper_error *err)
{
    const char *name = taper_profile_name(spec->profile);
    if (!name) return taper_fail(err, TAPER_EINVAL, "unknown profile %d", spec->profile);
    if (spec->n_granules < 2)
        return taper_fail(err, TAPER_EINVAL, "n_granules = %zu: a chain needs at least 2 granules",
                          spec->n_granules);
    /* Four arrays of N doubles: a larger N would overflow n * sizeof(double)
     * in the allocation (and the mass check would loop for ages first). */
    if (spec->n_granules > SIZE_MAX / (4 * sizeof(double)))
        return taper_fail(err, TAPER_EINVAL, "n_granules = %zu: too many granules to allocate",
                          spec->n_granules);
    if (!(spec->exponent > 1.0) || !isfinite(spec->exponent))
        return taper_fail(err, TAPER_EINVAL,
                          "exponent = %g: the contact exponent n must be finite and > 1 (5/2 for Hertz)",
                          spec->exponent);
    switch (spec->profile) {
    case TAPER_BACKWARD_LINEAR:
    case TAPER_FORWARD_LINEAR:
        if (!(spec->s >= 0.0) || !isfinite(spec->s))
            return taper_fail(err, TAPER_EINVAL, "s = %g: %s tapering needs a finite s >= 0",
                              spec->s, name);
        if (spec->profile == TAPER_FORWARD_LINEAR && spec->s > 0.0 &&
            !((double)spec->n_granules < 1.0 + 1.0 / spec->s))
            return taper_fail(err, TAPER_EINVAL,
                              "forward_linear with s = %.17g needs n_granules < 1 + 1/s = %.17g "
                              "(eq. r1-forw): granule %zu would have radius 1 - s (N-1) = %.3g, "
                              "not positive (or lost to rounding); lower n_granules or s",
                              spec->s, 1.0 + 1.0 / spec->s, spec->n_granules,
                              1.0 - spec->s * (double)(spec->n_granules - 1));
        break;
    case TAPER_BACKWARD_EXPONENTIAL:
        if (!(spec->q >= 0.0 && spec->q < 1.0))
            return taper_fail(err, TAPER_EINVAL,
                              "q = %g: backward_exponential tapering needs 0 <= q < 1", spec->q);
        break;
    case TAPER_FORWARD_EXPONENTIAL:
        if (!(spec->q >= 0.0) || !isfinite(spec->q))
            return taper_fail(err, TAPER_EINVAL,
                              "q = %g: forward_exponential tapering needs a finite q >= 0", spec->q);
        break;
    case TAPER_CUSTOM:
        if (!spec->radii)
            return taper_fail(err, TAPER_EINVAL, "custom profile needs radii (n_granules of them)");
        for (size_t k = 1; k <= spec->n_granules; k++) {
            double R = spec->radii[k - 1];
            if (!(R > 0.0) || !isfinite(R))
                return taper_fail(err, TAPER_EINVAL,
                                  "radii(%zu) = %g: every radius must be finite and > 0", k, R);
        }
        if (spec->radii[0] != 1.0)
            return taper_fail(err, TAPER_EINVAL,
                              "radii(1) = %.17g: the first radius is the unit of length and must be 1 "
                              "(divide all radii by it)", spec->radii[0]);
        break;
    default:
        break;
    }
    return TAPER_OK;
}

static int mass_in_range(const taper_chain_spec *spec, size_t k)
{
    double lm = 3.0 * log_radius(spec, k);
    return lm >= log(MASS_MIN) && lm <= log(MASS_MAX);
}

/* Masses must stay representable with room for the dynamics.  The analytic
 * profiles have ln R_k monotonic in k with R_1 = 1 in range, so the first
 * granule out of range is found by bisection: O(log N), not a loop over an
 * absurd N before the allocation can fail (N = 1e12 took hours). */
static int check_mass_range(const taper_chain_spec *spec, taper_error *err)
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
    if (first_bad)
        return taper_fail(err, TAPER_ERANGE,
                          "granule %zu: mass m_k = R_k^3 = exp(%.6g) is outside [%g, %g], "
                          "beyond what double precision can integrate; use at most %zu granules",
                          first_bad, 3.0 * log_radius(spec, first_bad), MASS_MIN, MASS_MAX,
                          first_bad - 1);
    return TAPER_OK;
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
    c->s = spec->s;
    c->q = spec->q;
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

/* r_k = (2 R_k R_{k+1} / (R_k + R_{k+1}))^{1/2}, eq. (r-prime). */
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
    if (validate_parameters(spec, err) != TAPER_OK) return NULL;
    if (check_mass_range(spec, err) != TAPER_OK) return NULL;
    taper_chain *c = chain_new(spec);
    if (!c) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a chain of %zu granules", spec->n_granules);
        return NULL;
    }
    fill_geometry(c, spec);
    if (!isfinite(c->rest[c->n - 1])) {
        taper_fail(err, TAPER_ERANGE, "the chain's length overflows double precision");
        taper_chain_free(c);
        return NULL;
    }
    taper_ok(err);
    return c;
}

size_t taper_chain_size(const taper_chain *chain) { return chain ? chain->n : 0; }
double taper_chain_exponent(const taper_chain *chain) { return chain ? chain->exponent : NAN; }
int taper_chain_profile(const taper_chain *chain) { return chain ? chain->profile : -1; }
const double *taper_chain_radius(const taper_chain *chain) { return chain ? chain->radius : NULL; }
const double *taper_chain_mass(const taper_chain *chain) { return chain ? chain->mass : NULL; }
const double *taper_chain_contact(const taper_chain *chain) { return chain ? chain->contact : NULL; }
const double *taper_chain_rest_position(const taper_chain *chain) { return chain ? chain->rest : NULL; }
