/*
 * chain_options.c -- the settings of a chain beyond the paper (issue 15;
 * taper.h, "Beyond the paper"): ends, striker, static load, damping, drag,
 * mixed materials, the decorated pattern and disorder.  Each setter checks
 * its values alone and leaves the spec unchanged when it refuses them;
 * chain_options_check states the relations between them.  Every refusal
 * names the setting to change in err->field:
 *   left_end, right_end, left_wall_compliance, right_wall_compliance
 *                                        (taper_chain_spec_set_end),
 *   striker_radius, striker_density, striker_compliance (set_striker),
 *   load, damping, drag, materials, pattern,
 *   disorder, disorder_amplitude         (set_disorder).
 * The physics of each option: docs/physics.md.
 */
#include "chain/chain_impl.h"

#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const boundary_names[TAPER_N_BOUNDARIES] = {
    [TAPER_END_FREE] = "free",
    [TAPER_END_WALL] = "wall",
};

static const char *const disorder_names[TAPER_N_DISORDERS] = {
    [TAPER_DISORDER_RADIUS] = "radius",
    [TAPER_DISORDER_MASS] = "mass",
};

const char *taper_boundary_name(taper_boundary boundary)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)boundary >= TAPER_N_BOUNDARIES) return NULL;
    return boundary_names[boundary];
}

const char *taper_disorder_name(taper_disorder kind)
{
    if ((unsigned)kind >= TAPER_N_DISORDERS) return NULL;
    return disorder_names[kind];
}

/* Case-insensitive lookup of `name` in names[0..count); TAPER_EINVAL naming
 * `field` and listing the names otherwise. */
static taper_status from_name(const char *name, const char *const *names, unsigned count,
                              const char *field, const char *what, unsigned *index,
                              taper_error *err)
{
    if (!name) return taper_fail_field(err, TAPER_EINVAL, field, "%s name is NULL", what);
    for (unsigned i = 0; i < count; i++) {
        if (strcasecmp(name, names[i]) == 0) {
            *index = i;
            return taper_ok(err);
        }
    }
    taper_fail_field(err, TAPER_EINVAL, field, "unknown %s '%s': use", what, name);
    for (unsigned i = 0; i < count; i++) taper_fail_append(err, "%s '%s'", i ? "," : "", names[i]);
    return TAPER_EINVAL;
}

taper_status taper_boundary_from_name(const char *name, taper_boundary *boundary, taper_error *err)
{
    if (!boundary)
        return taper_fail(err, TAPER_EINVAL, "taper_boundary_from_name: boundary is NULL");
    unsigned i = 0;
    taper_status st = from_name(name, boundary_names, TAPER_N_BOUNDARIES, "boundary", "boundary",
                                &i, err);
    if (st == TAPER_OK) *boundary = (taper_boundary)i;
    return st;
}

taper_status taper_disorder_from_name(const char *name, taper_disorder *kind, taper_error *err)
{
    if (!kind) return taper_fail(err, TAPER_EINVAL, "taper_disorder_from_name: kind is NULL");
    unsigned i = 0;
    taper_status st = from_name(name, disorder_names, TAPER_N_DISORDERS, "disorder",
                                "disorder kind", &i, err);
    if (st == TAPER_OK) *kind = (taper_disorder)i;
    return st;
}

void chain_options_default(taper_chain_spec *spec)
{
    spec->pattern = NULL;
    spec->n_pattern = 0;
    spec->disorder = TAPER_DISORDER_RADIUS;
    spec->disorder_amplitude = 0.0;
    spec->disorder_seed = 0;
    spec->density = NULL;
    spec->compliance = NULL;
    spec->n_materials = 0;
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        spec->end[e] = TAPER_END_FREE;
        spec->end_compliance[e] = 0.0;
    }
    spec->striker_radius = 0.0;
    spec->striker_density = 1.0;
    spec->striker_compliance = 1.0;
    spec->load = 0.0;
    spec->damping = 0.0;
    spec->drag = 0.0;
    spec->piston_duration = 0.0;
    spec->piston_compliance = 0.0;
}

void chain_options_free(taper_chain_spec *spec)
{
    free(spec->pattern);
    free(spec->density);
    free(spec->compliance);
}

static taper_status null_spec(taper_error *err, const char *function)
{
    return taper_fail(err, TAPER_EINVAL, "%s: spec is NULL", function);
}

static const char *const end_fields[TAPER_N_ENDS] = {"left_end", "right_end"};
static const char *const wall_fields[TAPER_N_ENDS] = {"left_wall_compliance",
                                                      "right_wall_compliance"};

taper_status taper_chain_spec_set_end(taper_chain_spec *spec, taper_end end,
                                      taper_boundary boundary, double compliance, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if ((unsigned)end >= TAPER_N_ENDS)
        return taper_fail_field(err, TAPER_EINVAL, "end",
                                "end = %d: unknown end (TAPER_LEFT or TAPER_RIGHT)", (int)end);
    if (!taper_boundary_name(boundary))
        return taper_fail_field(err, TAPER_EINVAL, end_fields[end],
                                "%s = %d: unknown boundary (use 'free' or 'wall')",
                                end_fields[end], (int)boundary);
    /* c_wall = (1 - nu^2)/E of the wall over granule 1's: 0 is a rigid
     * wall, and no material has a negative one. */
    if (!(compliance >= 0.0) || !isfinite(compliance))
        return taper_fail_field(err, TAPER_EINVAL, wall_fields[end],
                                "%s = %g: a wall's compliance (1 - nu^2)/E relative to granule "
                                "1's must be finite and >= 0 (0: rigid)",
                                wall_fields[end], compliance);
    spec->end[end] = boundary;
    spec->end_compliance[end] = compliance;
    return taper_ok(err);
}

taper_boundary taper_chain_spec_end(const taper_chain_spec *spec, taper_end end)
{
    if (!spec || (unsigned)end >= TAPER_N_ENDS) return (taper_boundary)-1;
    return spec->end[end];
}

double taper_chain_spec_end_compliance(const taper_chain_spec *spec, taper_end end)
{
    if (!spec || (unsigned)end >= TAPER_N_ENDS) return NAN;
    return spec->end_compliance[end];
}

taper_status taper_chain_spec_set_striker(taper_chain_spec *spec, double radius, double density,
                                          double compliance, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    /* Its mass density radius^3 must stay inside the chain's mass range
     * (chain.c); the bound on the radius alone keeps radius^3 finite. */
    if (!(radius >= 0.0 && radius <= 1e100))
        return taper_fail_field(err, TAPER_EINVAL, "striker_radius",
                                "striker_radius = %g: the striker's radius relative to R_1 must "
                                "be finite, >= 0 and <= 1e100 (0: no striker, the impulse "
                                "v_1 = 1)", radius);
    if (!(density > 0.0) || !isfinite(density))
        return taper_fail_field(err, TAPER_EINVAL, "striker_density",
                                "striker_density = %g: the striker's density relative to "
                                "granule 1's must be finite and > 0", density);
    if (!(compliance >= 0.0) || !isfinite(compliance))
        return taper_fail_field(err, TAPER_EINVAL, "striker_compliance",
                                "striker_compliance = %g: the striker's compliance "
                                "(1 - nu^2)/E relative to granule 1's must be finite and >= 0 "
                                "(0: rigid)", compliance);
    spec->striker_radius = radius;
    spec->striker_density = density;
    spec->striker_compliance = compliance;
    return taper_ok(err);
}

double taper_chain_spec_striker_radius(const taper_chain_spec *spec)
{
    return spec ? spec->striker_radius : NAN;
}
double taper_chain_spec_striker_density(const taper_chain_spec *spec)
{
    return spec ? spec->striker_density : NAN;
}
double taper_chain_spec_striker_compliance(const taper_chain_spec *spec)
{
    return spec ? spec->striker_compliance : NAN;
}

taper_status taper_chain_spec_set_piston(taper_chain_spec *spec, double duration,
                                         double compliance, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!(duration >= 0.0))
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "piston_duration = %g: the time the piston pushes must be > 0 "
                                "(infinite: a steady push; 0: no piston)", duration);
    if (!(compliance >= 0.0) || !isfinite(compliance))
        return taper_fail_field(err, TAPER_EINVAL, "piston_compliance",
                                "piston_compliance = %g: the piston's compliance (1 - nu^2)/E "
                                "relative to granule 1's must be finite and >= 0 (0: rigid)",
                                compliance);
    spec->piston_duration = duration;
    spec->piston_compliance = compliance;
    return taper_ok(err);
}

double taper_chain_spec_piston_duration(const taper_chain_spec *spec)
{
    return spec ? spec->piston_duration : NAN;
}
double taper_chain_spec_piston_compliance(const taper_chain_spec *spec)
{
    return spec ? spec->piston_compliance : NAN;
}

/* The piston's face is a wall's (chain.c, fill_ends): sqrt(2 R_1) times
 * 2 c_1 / (c_1 + c_piston). */
void chain_options_fill_piston(taper_chain *chain, const taper_chain_spec *spec)
{
    const int on = spec->piston_duration > 0.0;
    const double c1 = spec->compliance ? spec->compliance[0] : 1.0;
    chain->piston_duration = on ? spec->piston_duration : 0.0;
    chain->piston_contact = on ? sqrt(2.0 * chain->radius[0]) * 2.0 / (c1 + spec->piston_compliance)
                               : NAN;
    /* A push of finite duration is no impulse on granule 1 at rest: the
     * pulse it launches is not the binary collision cascade of eq. (9). */
    if (on && !chain->theory_note[0])
        snprintf(chain->theory_note, sizeof chain->theory_note, "%s",
                 "piston: the binary collision approximation of arXiv:0905.4512 starts from an "
                 "impulse on granule 1, not from a push of prescribed velocity");
}

double taper_chain_piston_duration(const taper_chain *chain)
{
    return chain ? chain->piston_duration : NAN;
}
double taper_chain_piston_contact(const taper_chain *chain)
{
    return chain ? chain->piston_contact : NAN;
}

/* Load, damping and drag: one finite value >= 0 each. */
static taper_status set_nonnegative(taper_chain_spec *spec, double *slot, double value,
                                    const char *field, const char *meaning, taper_error *err)
{
    if (!(value >= 0.0) || !isfinite(value))
        return taper_fail_field(err, TAPER_EINVAL, field, "%s = %g: %s must be finite and >= 0",
                                field, value, meaning);
    (void)spec;
    *slot = value;
    return taper_ok(err);
}

taper_status taper_chain_spec_set_load(taper_chain_spec *spec, double f0, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    return set_nonnegative(spec, &spec->load, f0, "load",
                           "the static compressive force F0 (0: none)", err);
}

taper_status taper_chain_spec_set_damping(taper_chain_spec *spec, double damping,
                                          taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    return set_nonnegative(spec, &spec->damping, damping, "damping",
                           "the Kuwabara-Kono damping time (0: elastic contacts)", err);
}

taper_status taper_chain_spec_set_drag(taper_chain_spec *spec, double drag, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    return set_nonnegative(spec, &spec->drag, drag, "drag",
                           "the hydrodynamic friction coefficient (0: none)", err);
}

double taper_chain_spec_load(const taper_chain_spec *spec) { return spec ? spec->load : NAN; }
double taper_chain_spec_damping(const taper_chain_spec *spec) { return spec ? spec->damping : NAN; }
double taper_chain_spec_drag(const taper_chain_spec *spec) { return spec ? spec->drag : NAN; }

/* Copies n values, every one finite and > 0, divided by values[0] when
 * `relative`; names the first bad entry as field(k). */
static taper_status copy_positive(const double *values, size_t n, const char *field,
                                  const char *label, int relative, double **out, taper_error *err)
{
    if (!values) return taper_fail_field(err, TAPER_EINVAL, field, "%s: NULL with n = %zu", label, n);
    if (n > TAPER_N_GRANULES_MAX)
        return taper_fail_field(err, TAPER_EINVAL, field, "%zu %s values: a chain has at most %g "
                                "granules", n, label, (double)TAPER_N_GRANULES_MAX);
    for (size_t k = 1; k <= n; k++) {
        double x = values[k - 1];
        if (!(x > 0.0) || !isfinite(x))
            return taper_fail_field(err, TAPER_EINVAL, field,
                                    "%s(%zu) = %g: every entry must be finite and > 0", label, k, x);
    }
    double *copy = malloc(n * sizeof *copy);
    if (!copy) return taper_fail(err, TAPER_ENOMEM, "cannot copy %zu %s values", n, label);
    for (size_t k = 0; k < n; k++) copy[k] = relative ? values[k] / values[0] : values[k];
    if (relative) copy[0] = 1.0;
    *out = copy;
    return TAPER_OK;
}

taper_status taper_chain_spec_set_pattern(taper_chain_spec *spec, const double *pattern, size_t p,
                                          taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    double *copy = NULL;
    if (p > 0) {
        taper_status st = copy_positive(pattern, p, "pattern", "pattern", 0, &copy, err);
        if (st != TAPER_OK) return st;
    }
    free(spec->pattern);
    spec->pattern = copy;
    spec->n_pattern = p;
    return taper_ok(err);
}

const double *taper_chain_spec_pattern(const taper_chain_spec *spec, size_t *p)
{
    if (p) *p = spec ? spec->n_pattern : 0;
    return spec ? spec->pattern : NULL;
}

taper_status taper_chain_spec_set_materials(taper_chain_spec *spec, const double *density,
                                            const double *compliance, size_t n, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    double *rho = NULL, *c = NULL;
    if (n > 0) {
        taper_status st = copy_positive(density, n, "materials", "density", 1, &rho, err);
        if (st != TAPER_OK) return st;
        st = copy_positive(compliance, n, "materials", "compliance", 1, &c, err);
        if (st != TAPER_OK) {
            free(rho);
            return st;
        }
    }
    free(spec->density);
    free(spec->compliance);
    spec->density = rho;
    spec->compliance = c;
    spec->n_materials = n;
    return taper_ok(err);
}

size_t taper_chain_spec_materials(const taper_chain_spec *spec, const double **density,
                                  const double **compliance)
{
    if (density) *density = spec ? spec->density : NULL;
    if (compliance) *compliance = spec ? spec->compliance : NULL;
    return spec ? spec->n_materials : 0;
}

taper_status taper_chain_spec_set_disorder(taper_chain_spec *spec, taper_disorder kind,
                                           double amplitude, uint64_t seed, taper_error *err)
{
    if (!spec) return null_spec(err, __func__);
    if (!taper_disorder_name(kind))
        return taper_fail_field(err, TAPER_EINVAL, "disorder",
                                "disorder = %d: unknown kind (use 'radius' or 'mass')", (int)kind);
    /* 1 + a u with u in [-1, 1) stays > 0 only for a < 1. */
    if (!(amplitude >= 0.0 && amplitude < 1.0))
        return taper_fail_field(err, TAPER_EINVAL, "disorder_amplitude",
                                "disorder_amplitude = %g: the relative perturbation must be in "
                                "[0, 1) so that every factor 1 + a u_k stays > 0 (0: none)",
                                amplitude);
    spec->disorder = kind;
    spec->disorder_amplitude = amplitude;
    spec->disorder_seed = seed;
    return taper_ok(err);
}

taper_disorder taper_chain_spec_disorder(const taper_chain_spec *spec)
{
    return spec ? spec->disorder : (taper_disorder)-1;
}
double taper_chain_spec_disorder_amplitude(const taper_chain_spec *spec)
{
    return spec ? spec->disorder_amplitude : NAN;
}
uint64_t taper_chain_spec_disorder_seed(const taper_chain_spec *spec)
{
    return spec ? spec->disorder_seed : 0;
}

/* The pattern belongs to the decorated profile as radii to the custom one:
 * neither without the other, and its first radius is the unit. */
static taper_status check_pattern(const taper_chain_spec *spec, taper_error *err)
{
    const char *profile = taper_profile_name(spec->profile);
    if (spec->profile != TAPER_DECORATED && spec->pattern)
        return taper_fail_field(err, TAPER_EINVAL, "pattern",
                                "a pattern has no effect with profile = '%s' (only 'decorated' "
                                "reads it): remove the pattern or use profile = 'decorated'",
                                profile);
    if (spec->profile == TAPER_DECORATED && !spec->pattern)
        return taper_fail_field(err, TAPER_EINVAL, "pattern",
                                "profile = 'decorated' needs a pattern: the radii of one period, "
                                "starting with 1 (e.g. 1, 0.5 for large and small granules in "
                                "turn)");
    if (spec->profile == TAPER_DECORATED && spec->pattern[0] != 1.0)
        return taper_fail_field(err, TAPER_EINVAL, "pattern",
                                "pattern(1) = %.17g: the first radius is the unit of length and "
                                "must be 1 (divide the pattern by it)", spec->pattern[0]);
    return TAPER_OK;
}

taper_status chain_options_check(const taper_chain_spec *spec, taper_error *err)
{
    taper_status st = check_pattern(spec, err);
    if (st != TAPER_OK) return st;
    if (spec->density && spec->n_materials != spec->n_granules)
        return taper_fail_field(err, TAPER_EINVAL, "materials",
                                "%zu materials but n_granules = %zu: give one density and one "
                                "compliance per granule", spec->n_materials, spec->n_granules);
    for (int e = 0; e < TAPER_N_ENDS; e++)
        if (spec->end[e] == TAPER_END_FREE && spec->end_compliance[e] != 0.0)
            return taper_fail_field(err, TAPER_EINVAL, wall_fields[e],
                                    "%s = %g has no effect on a free end: leave it at 0 or make "
                                    "the %s end a wall", wall_fields[e], spec->end_compliance[e],
                                    e == TAPER_LEFT ? "left" : "right");
    if (spec->striker_radius == 0.0 && (spec->striker_density != 1.0 || spec->striker_compliance != 1.0))
        return taper_fail_field(err, TAPER_EINVAL, "striker_radius",
                                "striker_density = %g and striker_compliance = %g have no effect "
                                "without a striker: give striker_radius > 0 or leave them at 1",
                                spec->striker_density, spec->striker_compliance);
    /* The striker hits granule 1 from the left: a wall cannot be there too. */
    if (spec->striker_radius > 0.0 && spec->end[TAPER_LEFT] == TAPER_END_WALL)
        return taper_fail_field(err, TAPER_EINVAL, "left_end",
                                "a left wall and a striker exclude each other (the striker comes "
                                "from the left end): make left_end 'free' or remove the striker "
                                "(striker_radius = 0)");
    /* The piston pushes granule 1 from the left, as a striker or a left
     * wall would be there; under a load its face would hold granule 1 by
     * a static overlap, a case the piston's model does not cover. */
    if (spec->piston_duration == 0.0 && spec->piston_compliance != 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "piston_compliance",
                                "piston_compliance = %g has no effect without a piston: give "
                                "piston_duration > 0 or leave it at 0", spec->piston_compliance);
    if (spec->piston_duration > 0.0 && spec->striker_radius > 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "a piston and a striker exclude each other (both push granule 1 "
                                "from the left): remove one (piston_duration = 0 or "
                                "striker_radius = 0)");
    if (spec->piston_duration > 0.0 && spec->end[TAPER_LEFT] == TAPER_END_WALL)
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "a piston and a left wall exclude each other (the piston is the "
                                "left end): make left_end 'free' or remove the piston "
                                "(piston_duration = 0)");
    if (spec->piston_duration > 0.0 && spec->load > 0.0)
        return taper_fail_field(err, TAPER_EINVAL, "piston_duration",
                                "a piston under a static load is not modelled (the piston starts "
                                "just touching granule 1 of a chain at rest): set load = 0 or "
                                "remove the piston");
    /* The Kuwabara-Kono force damping r (n-1) z^(n-2) dz/dt diverges as a
     * contact closes when n < 2 (z^(n-2) -> oo at z -> 0+): no finite force
     * law to integrate.  Refused here, before any run (issue 18: refuse
     * before the run, naming what to change), as taper_sim_alloc does. */
    if (spec->damping > 0.0 && spec->exponent < 2.0)
        return taper_fail_field(err, TAPER_EINVAL, "damping",
                                "damping = %g with exponent n = %g: the Kuwabara-Kono force "
                                "damping (n-1) z^(n-2) dz/dt diverges as a contact closes for "
                                "n < 2; use n >= 2 or drag for losses", spec->damping,
                                spec->exponent);
    return TAPER_OK;
}
