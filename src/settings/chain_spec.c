/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * chain_spec.c -- taper_chain_spec: allocation, and the typed setters and
 * getters of taper.h, each a thin call into the table of settings (every
 * check of a value, its message and its default come from its row).  The
 * relations between settings are src/chain's (taper_chain_spec_check).
 */
#include "settings/settings.h"

#include <math.h>
#include <stdlib.h>

static const setting_row *row(const char *name)
{
    return setting_row_of(name, TAPER_SETTING_CHAIN, NULL);
}

void taper_chain_spec_defaults(struct taper_chain_spec *spec)
{
    setting_defaults(spec, TAPER_SETTING_CHAIN);
}

taper_chain_spec *taper_chain_spec_alloc(taper_error *err)
{
    taper_chain_spec *spec = malloc(sizeof *spec);
    if (!spec) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a chain spec");
        return NULL;
    }
    taper_chain_spec_defaults(spec);
    taper_ok(err);
    return spec;
}

void taper_chain_spec_free(taper_chain_spec *spec)
{
    if (!spec) return;
    setting_free_lists(spec, TAPER_SETTING_CHAIN);
    free(spec);
}

/* One value through its row: checked, then stored. */
static taper_status set(taper_chain_spec *spec, const char *function, const char *name,
                        double value, taper_error *err)
{
    if (!spec) return setting_null_spec(err, function);
    const setting_row *r = row(name);
    taper_status st = setting_check(r, value, err);
    if (st == TAPER_OK) setting_store(spec, r, value);
    return st;
}

/* Several values set together (set_end, set_striker, set_piston): each
 * checked before any is stored, so that a refusal leaves the spec as it
 * was. */
static taper_status set_all(taper_chain_spec *spec, const char *function, size_t n,
                            const char *const *names, const double *values, taper_error *err)
{
    if (!spec) return setting_null_spec(err, function);
    for (size_t i = 0; i < n; i++) {
        taper_status st = setting_check(row(names[i]), values[i], err);
        if (st != TAPER_OK) return st;
    }
    for (size_t i = 0; i < n; i++) setting_store(spec, row(names[i]), values[i]);
    return taper_ok(err);
}

static taper_status set_list(taper_chain_spec *spec, const char *function, const char *name,
                             const double *values, size_t n, taper_error *err)
{
    if (!spec) return setting_null_spec(err, function);
    double *copy;
    taper_status st = setting_copy_list(row(name), values, n, &copy, err);
    if (st == TAPER_OK) setting_put_list(spec, row(name), copy, n);
    return st;
}

static double get(const taper_chain_spec *spec, const char *name)
{
    return setting_value(spec, row(name));
}

/* ---- the paper's chain ----------------------------------------------------- */

taper_status taper_chain_spec_set_profile(taper_chain_spec *spec, taper_profile profile,
                                          taper_error *err)
{
    return set(spec, __func__, "profile", (double)(int)profile, err);
}
taper_status taper_chain_spec_set_n_granules(taper_chain_spec *spec, size_t n, taper_error *err)
{
    return set(spec, __func__, "n_granules", (double)n, err);
}
taper_status taper_chain_spec_set_s(taper_chain_spec *spec, double s, taper_error *err)
{
    return set(spec, __func__, "s", s, err);
}
taper_status taper_chain_spec_set_q(taper_chain_spec *spec, double q, taper_error *err)
{
    return set(spec, __func__, "q", q, err);
}
taper_status taper_chain_spec_set_exponent(taper_chain_spec *spec, double exponent,
                                           taper_error *err)
{
    return set(spec, __func__, "exponent", exponent, err);
}
taper_status taper_chain_spec_set_radii(taper_chain_spec *spec, const double *radii, size_t n,
                                        taper_error *err)
{
    return set_list(spec, __func__, "radii", radii, n, err);
}

taper_profile taper_chain_spec_profile(const taper_chain_spec *spec)
{
    return (taper_profile)get(spec, "profile");
}
size_t taper_chain_spec_n_granules(const taper_chain_spec *spec)
{
    return (size_t)get(spec, "n_granules");
}
double taper_chain_spec_s(const taper_chain_spec *spec) { return get(spec, "s"); }
double taper_chain_spec_q(const taper_chain_spec *spec) { return get(spec, "q"); }
double taper_chain_spec_exponent(const taper_chain_spec *spec) { return get(spec, "exponent"); }
const double *taper_chain_spec_radii(const taper_chain_spec *spec, size_t *n)
{
    return setting_list(spec, row("radii"), n);
}

/* ---- beyond the paper -------------------------------------------------------- */

taper_status taper_chain_spec_set_pattern(taper_chain_spec *spec, const double *pattern, size_t p,
                                          taper_error *err)
{
    return set_list(spec, __func__, "pattern", pattern, p, err);
}
const double *taper_chain_spec_pattern(const taper_chain_spec *spec, size_t *p)
{
    return setting_list(spec, row("pattern"), p);
}

taper_status taper_chain_spec_set_disorder(taper_chain_spec *spec, taper_disorder kind,
                                           double amplitude, uint64_t seed, taper_error *err)
{
    if (!spec) return setting_null_spec(err, __func__);
    /* The seed is checked as the integer it is: a double could round a
     * seed just above the range into it. */
    const taper_setting *s = &row("seed")->info;
    if (seed > (uint64_t)s->max)
        return taper_fail_field(err, TAPER_EINVAL, s->name, "seed = %llu is out of range [0, "
                                "%.0f]: %s", (unsigned long long)seed, s->max, s->bounds_reason);
    static const char *const names[] = {"disorder", "disorder_amplitude"};
    const double values[] = {(double)(int)kind, amplitude};
    taper_status st = set_all(spec, __func__, 2, names, values, err);
    if (st == TAPER_OK) spec->disorder_seed = seed;
    return st;
}
taper_disorder taper_chain_spec_disorder(const taper_chain_spec *spec)
{
    return (taper_disorder)get(spec, "disorder");
}
double taper_chain_spec_disorder_amplitude(const taper_chain_spec *spec)
{
    return get(spec, "disorder_amplitude");
}
uint64_t taper_chain_spec_disorder_seed(const taper_chain_spec *spec)
{
    return spec ? spec->disorder_seed : (uint64_t)row("seed")->info.default_value;
}

taper_status taper_chain_spec_set_materials(taper_chain_spec *spec, const double *density,
                                            const double *compliance, size_t n, taper_error *err)
{
    if (!spec) return setting_null_spec(err, __func__);
    double *rho, *c;
    taper_status st = setting_copy_list(row("densities"), density, n, &rho, err);
    if (st != TAPER_OK) return st;
    st = setting_copy_list(row("compliances"), compliance, n, &c, err);
    if (st != TAPER_OK) {
        free(rho);
        return st;
    }
    setting_put_list(spec, row("densities"), rho, n);
    setting_put_list(spec, row("compliances"), c, n);
    return taper_ok(err);
}
size_t taper_chain_spec_materials(const taper_chain_spec *spec, const double **density,
                                  const double **compliance)
{
    size_t n_rho, n_c;
    const double *rho = setting_list(spec, row("densities"), &n_rho);
    const double *c = setting_list(spec, row("compliances"), &n_c);
    /* Both or neither: a spec with one alone is refused by the check. */
    int both = rho && c && n_rho == n_c;
    if (density) *density = both ? rho : NULL;
    if (compliance) *compliance = both ? c : NULL;
    return both ? n_rho : 0;
}

static const char *const end_names[TAPER_N_ENDS] = {"left", "right"};
static const char *const wall_names[TAPER_N_ENDS] = {"left_compliance", "right_compliance"};

taper_status taper_chain_spec_set_end(taper_chain_spec *spec, taper_end end,
                                      taper_boundary boundary, double compliance, taper_error *err)
{
    if ((unsigned)end >= TAPER_N_ENDS)
        return taper_fail_field(err, TAPER_EINVAL, "end", "end = %d: unknown end (TAPER_LEFT or TAPER_RIGHT)",
                          (int)end);
    const char *names[] = {end_names[end], wall_names[end]};
    const double values[] = {(double)(int)boundary, compliance};
    return set_all(spec, __func__, 2, names, values, err);
}
taper_boundary taper_chain_spec_end(const taper_chain_spec *spec, taper_end end)
{
    return (unsigned)end < TAPER_N_ENDS ? (taper_boundary)get(spec, end_names[end])
                                        : (taper_boundary)-1;
}
double taper_chain_spec_end_compliance(const taper_chain_spec *spec, taper_end end)
{
    return (unsigned)end < TAPER_N_ENDS ? get(spec, wall_names[end]) : NAN;
}

taper_status taper_chain_spec_set_striker(taper_chain_spec *spec, double radius, double density,
                                          double compliance, taper_error *err)
{
    static const char *const names[] = {"striker_radius", "striker_density",
                                        "striker_compliance"};
    const double values[] = {radius, density, compliance};
    return set_all(spec, __func__, 3, names, values, err);
}
double taper_chain_spec_striker_radius(const taper_chain_spec *spec)
{
    return get(spec, "striker_radius");
}
double taper_chain_spec_striker_density(const taper_chain_spec *spec)
{
    return get(spec, "striker_density");
}
double taper_chain_spec_striker_compliance(const taper_chain_spec *spec)
{
    return get(spec, "striker_compliance");
}

taper_status taper_chain_spec_set_piston(taper_chain_spec *spec, double duration,
                                         double compliance, taper_error *err)
{
    static const char *const names[] = {"piston_duration", "piston_compliance"};
    const double values[] = {duration, compliance};
    return set_all(spec, __func__, 2, names, values, err);
}
double taper_chain_spec_piston_duration(const taper_chain_spec *spec)
{
    return get(spec, "piston_duration");
}
double taper_chain_spec_piston_compliance(const taper_chain_spec *spec)
{
    return get(spec, "piston_compliance");
}

taper_status taper_chain_spec_set_load(taper_chain_spec *spec, double f0, taper_error *err)
{
    return set(spec, __func__, "load", f0, err);
}
taper_status taper_chain_spec_set_damping(taper_chain_spec *spec, double damping,
                                          taper_error *err)
{
    return set(spec, __func__, "damping", damping, err);
}
taper_status taper_chain_spec_set_drag(taper_chain_spec *spec, double drag, taper_error *err)
{
    return set(spec, __func__, "drag", drag, err);
}
double taper_chain_spec_load(const taper_chain_spec *spec) { return get(spec, "load"); }
double taper_chain_spec_damping(const taper_chain_spec *spec) { return get(spec, "damping"); }
double taper_chain_spec_drag(const taper_chain_spec *spec) { return get(spec, "drag"); }
