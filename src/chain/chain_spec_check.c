/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * chain_spec_check.c -- the relations between the settings of a chain of the
 * paper's model (taper_chain_spec_check): what makes one setting's value
 * wrong for another's.  Each single value is checked against its row of
 * the table of settings when it is set (src/settings).  Every refusal names
 * the setting to change in err->field, by its name in that table.
 */
#include "chain/chain_impl.h"

#include <math.h>

static taper_status null_spec(taper_error *err, const char *function)
{
    return taper_fail(err, TAPER_EINVAL, "%s: spec is NULL", function);
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
 * to the exponential ones.  A parameter given to a profile that does not
 * read it is a mistake the caller should hear of, not a value silently
 * ignored.  0 is the default, and with its own profile the monodisperse
 * chain, the limit s -> 0 (q -> 0) of the taper: R_k = 1, and the theory
 * the monodisperse one (the recursion of eqs. (9), (18), (19) reads the
 * masses, so the limit is its value there, no 0/0), the natural baseline of
 * a sweep over s or q.  (A tapered profile whose parameter was never given
 * is the scene's to refuse, which knows what was given.)  The one place of
 * this rule: the scene reader, the bindings and the Fortran driver all
 * reach it through taper_chain_spec_check or taper_chain_alloc. */
static taper_status check_parameters(const taper_chain_spec *spec, taper_error *err)
{
    const char *profile = taper_profile_name(spec->profile);
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
