/*
 * chain_spec.c -- the settings of a chain before it is built: the one list
 * of profile names, the ranges of the single settings (the setters) and the
 * relations between them (taper_chain_spec_check).  Every refusal names the
 * setting to change in err->field, spelt as the setter's suffix.
 */
#include "chain/chain_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const profile_names[TAPER_N_PROFILES] = {
    [TAPER_MONODISPERSE] = "monodisperse",
    [TAPER_BACKWARD_LINEAR] = "backward_linear",
    [TAPER_FORWARD_LINEAR] = "forward_linear",
    [TAPER_BACKWARD_EXPONENTIAL] = "backward_exponential",
    [TAPER_FORWARD_EXPONENTIAL] = "forward_exponential",
    [TAPER_CUSTOM] = "custom",
    [TAPER_DECORATED] = "decorated",
};

const char *taper_profile_name(taper_profile profile)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)profile >= TAPER_N_PROFILES) return NULL;
    return profile_names[profile];
}

taper_status taper_profile_from_name(const char *name, taper_profile *profile, taper_error *err)
{
    if (!profile) return taper_fail(err, TAPER_EINVAL, "taper_profile_from_name: profile is NULL");
    if (!name)
        return taper_fail_field(err, TAPER_EINVAL, "profile", "taper_profile_from_name: name is NULL");
    for (unsigned i = 0; i < TAPER_N_PROFILES; i++) {
        if (strcasecmp(name, profile_names[i]) == 0) {
            *profile = (taper_profile)i;
            return taper_ok(err);
        }
    }
    taper_fail_field(err, TAPER_EINVAL, "profile", "unknown profile '%s': use", name);
    for (unsigned i = 0; i < TAPER_N_PROFILES; i++)
        taper_fail_append(err, "%s '%s'", i ? "," : "", profile_names[i]);
    return TAPER_EINVAL;
}

taper_chain_spec *taper_chain_spec_alloc(taper_error *err)
{
    taper_chain_spec *spec = malloc(sizeof *spec);
    if (!spec) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a chain spec");
        return NULL;
    }
    spec->profile = TAPER_MONODISPERSE;
    spec->n_granules = 100;
    spec->s = 0.0;
    spec->q = 0.0;
    spec->exponent = 2.5;
    spec->radii = NULL;
    spec->n_radii = 0;
    chain_options_default(spec);
    taper_ok(err);
    return spec;
}

void taper_chain_spec_free(taper_chain_spec *spec)
{
    if (!spec) return;
    free(spec->radii);
    chain_options_free(spec);
    free(spec);
}

static taper_status null_spec(taper_error *err, const char *function)
{
    return taper_fail(err, TAPER_EINVAL, "%s: spec is NULL", function);
}

taper_status taper_chain_spec_set_profile(taper_chain_spec *spec, taper_profile profile,
                                          taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!taper_profile_name(profile))
        return taper_fail_field(err, TAPER_EINVAL, "profile",
                                "profile = %d: unknown profile (taper_profile has %d values)",
                                (int)profile, TAPER_N_PROFILES);
    spec->profile = profile;
    return taper_ok(err);
}

taper_status taper_chain_spec_set_n_granules(taper_chain_spec *spec, size_t n, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (n < TAPER_N_GRANULES_MIN || n > TAPER_N_GRANULES_MAX)
        return taper_fail_field(err, TAPER_EINVAL, "n_granules",
                                "n_granules = %zu is out of range [%d, %g]: a chain needs at least "
                                "%d granules", n, TAPER_N_GRANULES_MIN,
                                (double)TAPER_N_GRANULES_MAX, TAPER_N_GRANULES_MIN);
    spec->n_granules = n;
    return taper_ok(err);
}

taper_status taper_chain_spec_set_s(taper_chain_spec *spec, double s, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!(s >= 0.0 && s <= TAPER_S_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "s",
                                "s = %g is out of range [0, %g]: the linear tapering S must be "
                                "finite and >= 0", s, TAPER_S_MAX);
    spec->s = s;
    return taper_ok(err);
}

taper_status taper_chain_spec_set_q(taper_chain_spec *spec, double q, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!(q >= 0.0 && q <= TAPER_Q_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "q",
                                "q = %g is out of range [0, %g]: the exponential tapering q must be "
                                "finite and >= 0 (backward_exponential: < 1)", q, TAPER_Q_MAX);
    spec->q = q;
    return taper_ok(err);
}

taper_status taper_chain_spec_set_exponent(taper_chain_spec *spec, double exponent,
                                           taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    /* Below 3/2 the force r z^(n-1) has a slope (n-1) z^(n-2) that grows
     * without bound at contact onset, faster the closer n is to 1, and
     * every contact starts there: CVODE's steps collapse.  Measured with
     * the window (monodisperse N = 100, default tolerances, at f72f424):
     * 187 steps per granule at n = 1.5, 375 at 1.4, 3200 at 1.3, 59000 at
     * 1.2 (granule 17 after 30 s), and n = 1.1 had not passed granule 1
     * after 7.4 million steps (t = 9e-4).  Refused before the run, with
     * what to change (issue 18, item 2). */
    if (!(exponent >= TAPER_EXPONENT_MIN && exponent <= TAPER_EXPONENT_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "exponent",
                                "exponent = %g is out of range [%g, %g]: the contact exponent n "
                                "must be finite, >= %g (below, the force's slope is unbounded at "
                                "contact onset and the integration stalls) and <= %g; 5/2 is "
                                "Hertz", exponent, TAPER_EXPONENT_MIN, TAPER_EXPONENT_MAX,
                                TAPER_EXPONENT_MIN, TAPER_EXPONENT_MAX);
    spec->exponent = exponent;
    return taper_ok(err);
}

taper_status taper_chain_spec_set_radii(taper_chain_spec *spec, const double *radii, size_t n,
                                        taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (n == 0) {
        free(spec->radii);
        spec->radii = NULL;
        spec->n_radii = 0;
        return taper_ok(err);
    }
    if (!radii)
        return taper_fail_field(err, TAPER_EINVAL, "radii", "radii: NULL with n = %zu", n);
    /* More radii than a chain may have granules could never be used, and
     * would only make the copy below absurdly large. */
    if (n > TAPER_N_GRANULES_MAX)
        return taper_fail_field(err, TAPER_EINVAL, "radii",
                                "%zu radii: a chain has at most %g granules", n,
                                (double)TAPER_N_GRANULES_MAX);
    for (size_t k = 1; k <= n; k++) {
        double R = radii[k - 1];
        if (!(R > 0.0) || !isfinite(R))
            return taper_fail_field(err, TAPER_EINVAL, "radii",
                                    "radii(%zu) = %g: every radius must be finite and > 0", k, R);
    }
    double *copy = malloc(n * sizeof *copy);
    if (!copy) return taper_fail(err, TAPER_ENOMEM, "cannot copy %zu radii", n);
    memcpy(copy, radii, n * sizeof *copy);
    free(spec->radii);
    spec->radii = copy;
    spec->n_radii = n;
    return taper_ok(err);
}

taper_profile taper_chain_spec_profile(const taper_chain_spec *spec)
{
    return spec ? spec->profile : (taper_profile)-1;
}
size_t taper_chain_spec_n_granules(const taper_chain_spec *spec) { return spec ? spec->n_granules : 0; }
double taper_chain_spec_s(const taper_chain_spec *spec) { return spec ? spec->s : NAN; }
double taper_chain_spec_q(const taper_chain_spec *spec) { return spec ? spec->q : NAN; }
double taper_chain_spec_exponent(const taper_chain_spec *spec) { return spec ? spec->exponent : NAN; }

const double *taper_chain_spec_radii(const taper_chain_spec *spec, size_t *n)
{
    if (n) *n = spec ? spec->n_radii : 0;
    return spec ? spec->radii : NULL;
}

/* R_N = 1 - S (N-1) must stay positive: N < 1 + 1/S, eq. (46).  The fix is
 * fewer granules or a smaller S; n_granules is named since S is usually the
 * parameter under study. */
static taper_status check_forward_linear(const taper_chain_spec *spec, taper_error *err)
{
    if (spec->s > 0.0 && !((double)spec->n_granules < 1.0 + 1.0 / spec->s))
        return taper_fail_field(err, TAPER_EINVAL, "n_granules",
                                "forward_linear with s = %.17g needs n_granules < 1 + 1/s = %.17g "
                                "(eq. (46)): granule %zu would have radius 1 - s (N-1) = %.3g, "
                                "not positive (or lost to rounding); lower n_granules or s",
                                spec->s, 1.0 + 1.0 / spec->s, spec->n_granules,
                                1.0 - spec->s * (double)(spec->n_granules - 1));
    return TAPER_OK;
}

static taper_status check_custom(const taper_chain_spec *spec, taper_error *err)
{
    if (!spec->radii)
        return taper_fail_field(err, TAPER_EINVAL, "radii",
                                "the custom profile needs radii (n_granules = %zu of them)",
                                spec->n_granules);
    if (spec->n_radii != spec->n_granules)
        return taper_fail_field(err, TAPER_EINVAL, "radii",
                                "%zu radii but n_granules = %zu: the custom profile needs one "
                                "radius per granule", spec->n_radii, spec->n_granules);
    if (spec->radii[0] != 1.0)
        return taper_fail_field(err, TAPER_EINVAL, "radii",
                                "radii(1) = %.17g: the first radius is the unit of length and must "
                                "be 1 (divide all radii by it)", spec->radii[0]);
    return TAPER_OK;
}

static int is_linear(taper_profile p) { return p == TAPER_BACKWARD_LINEAR || p == TAPER_FORWARD_LINEAR; }
static int is_exponential(taper_profile p)
{
    return p == TAPER_BACKWARD_EXPONENTIAL || p == TAPER_FORWARD_EXPONENTIAL;
}

/* Each tapering parameter belongs to its profiles: s to the linear ones, q
 * to the exponential ones.  A tapered profile without its parameter was a
 * monodisperse chain under another name (profile = 'backward_linear' with
 * no s ran R_k = 1 and said nothing), and a parameter given to a profile
 * that does not read it is a mistake the caller should hear of, not a
 * value silently ignored (reported first: it names what the caller
 * wrote).  0 is "not given" (the default).  The one place
 * of this rule: the scene reader, the bindings and the Fortran driver all
 * reach it through taper_chain_spec_check or taper_chain_alloc. */
static taper_status check_parameters(const taper_chain_spec *spec, taper_error *err)
{
    const char *profile = profile_names[spec->profile];
    if (!is_linear(spec->profile) && spec->s != 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "s",
                                "s = %g has no effect with profile = '%s' (only the linear "
                                "profiles use it): leave s at 0 or choose a linear profile",
                                spec->s, profile);
    if (!is_exponential(spec->profile) && spec->q != 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "q",
                                "q = %g has no effect with profile = '%s' (only the exponential "
                                "profiles use it): leave q at 0 or choose an exponential profile",
                                spec->q, profile);
    if (is_linear(spec->profile) && spec->s == 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "s",
                                "profile = '%s' needs its tapering s > 0 (R_k = 1 %s s (k-1)); "
                                "s = 0 is a monodisperse chain: give s > 0, or use profile = "
                                "'monodisperse'",
                                profile, spec->profile == TAPER_BACKWARD_LINEAR ? "+" : "-");
    if (is_exponential(spec->profile) && spec->q == 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "q",
                                "profile = '%s' needs its tapering q > 0 (R_k = (1 %s q)^(1-k)); "
                                "q = 0 is a monodisperse chain: give q > 0, or use profile = "
                                "'monodisperse'",
                                profile, spec->profile == TAPER_BACKWARD_EXPONENTIAL ? "-" : "+");
    return TAPER_OK;
}

taper_status taper_chain_spec_check(const taper_chain_spec *spec, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    taper_status status = check_parameters(spec, err);
    if (status != TAPER_OK) return status;
    switch (spec->profile) {
    case TAPER_FORWARD_LINEAR: status = check_forward_linear(spec, err); break;
    case TAPER_BACKWARD_EXPONENTIAL:
        if (!(spec->q < 1.0))
            status = taper_fail_field(err, TAPER_EINVAL, "q",
                                      "q = %g: backward_exponential tapering needs q < 1 "
                                      "(R_k = (1-q)^(1-k))", spec->q);
        break;
    case TAPER_CUSTOM: status = check_custom(spec, err); break;
    default: break;
    }
    if (status == TAPER_OK) status = chain_options_check(spec, err);
    return status == TAPER_OK ? taper_ok(err) : status;
}
