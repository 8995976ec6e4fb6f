/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * chain.c -- geometry of a granular chain (paper, Sec. II and the tapering
 * protocols of Secs. III-IV): radii, masses m_k = R_k^3 (uniform density,
 * unit first granule), contact factors r_k (eq. (7)) and the centres X0(k)
 * of the uncompressed, just-touching chain; and what the options beyond
 * the paper make of them (docs/physics.md): the decorated profile, disorder,
 * mixed materials (m_k = rho_k R_k^3, r_k 2 c_1 / (c_k + c_{k+1})), the
 * contact factors of walls and of a striker.  With every option at its
 * default the arithmetic is exactly the paper chain's.  The settings are
 * checked in chain_spec_check.c and chain_options.c; this file only adds the
 * limits of double precision.
 */
#include "chain/chain_impl.h"

#include <math.h>
#include <stdlib.h>

/* Masses outside this range leave no room for the dynamics (velocities and
 * times scale with powers of the mass ratio).  They also bound every radius
 * by 1e100, so the chain's length (at most 2 N R_max) stays finite. */
#define MASS_MIN 1e-300
#define MASS_MAX 1e300

/* Granules between two looks at the caller's monitor while a chain is
 * built (taper_chain_alloc_monitored): a few milliseconds of the loops
 * below, so that a signal stops the building of the longest chain within
 * a fraction of a second, as the theory's recursion does. */
#define MONITOR_EVERY 65536

/* The caller's monitor and the chain's length, for its progress. */
typedef struct build_watch {
    taper_monitor_fn monitor; /* NULL: never asked */
    void *user;
    size_t n;
} build_watch;

/* 1 when the monitor, asked at every MONITOR_EVERY-th granule k (not at 0),
 * says stop (progress: granule k of target N, window 0..0 as for the
 * theory). */
static int stop_asked(const build_watch *w, size_t k)
{
    if (!w->monitor || k == 0 || k % MONITOR_EVERY != 0) return 0;
    const taper_progress p = {.granule = k, .target = w->n};
    return w->monitor(&p, w->user) != 0;
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
    case TAPER_DECORATED: return log(spec->pattern[(k - 1) % spec->n_pattern]);
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

static taper_status interrupted(size_t k, size_t n, taper_error *err)
{
    return taper_fail(err, TAPER_EINTERRUPTED, "chain: interrupted at granule %zu of %zu", k, n);
}

/* Masses must stay representable with room for the dynamics.  The analytic
 * profiles have ln R_k monotonic in k with R_1 = 1 in range, so the first
 * granule out of range is found by bisection in O(log N) evaluations. */
static taper_status check_mass_range(const taper_chain_spec *spec, const build_watch *w,
                                     taper_error *err)
{
    size_t first_bad = 0; /* 0: none */
    if (spec->profile == TAPER_CUSTOM) {
        for (size_t k = 1; k <= spec->n_granules && !first_bad; k++) {
            if (stop_asked(w, k)) return interrupted(k, spec->n_granules, err);
            if (!mass_in_range(spec, k)) first_bad = k;
        }
    } else if (spec->profile == TAPER_DECORATED) {
        /* Periodic: the first period holds every radius there is. */
        for (size_t k = 1; k <= spec->n_granules && k <= spec->n_pattern && !first_bad; k++)
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
    if (spec->profile == TAPER_DECORATED)
        return taper_fail_field(err, TAPER_ERANGE, "pattern",
                                "granule %zu: mass m_k = R_k^3 = exp(%.6g) is outside [%g, %g], "
                                "beyond what double precision can integrate; change pattern(%zu)",
                                first_bad, log_mass, MASS_MIN, MASS_MAX, first_bad);
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

/* The radius of granule k of the profile alone. */
static double profile_radius(const taper_chain_spec *spec, size_t k)
{
    /* Linear profiles are exact in floating point without exp/log. */
    switch (spec->profile) {
    case TAPER_MONODISPERSE: return 1.0;
    case TAPER_BACKWARD_LINEAR: return 1.0 + spec->s * (double)(k - 1);
    case TAPER_FORWARD_LINEAR: return 1.0 - spec->s * (double)(k - 1);
    case TAPER_CUSTOM: return spec->radii[k - 1];
    case TAPER_DECORATED: return spec->pattern[(k - 1) % spec->n_pattern];
    default: return exp(log_radius(spec, k));
    }
}

/* 1 + a u_k for granule k >= 2 (granule 1 stays the unit), or 1 when the
 * disorder is off or acts on the other quantity. */
static double disorder_factor(const taper_chain_spec *spec, taper_disorder kind, size_t k)
{
    if (spec->disorder_amplitude == 0.0 || spec->disorder != kind || k < 2) return 1.0;
    return 1.0 + spec->disorder_amplitude * chain_disorder_uniform(spec->disorder_seed, k);
}

/* Relative compliance c_k of granule k (c_1 = 1). */
static double compliance_of(const taper_chain_spec *spec, size_t k)
{
    return spec->compliance ? spec->compliance[k - 1] : 1.0;
}

/* Hertz between materials of compliances a and b, relative to the pair of
 * two granules of granule 1's material: 1/E* = c_a + c_b, so the factor is
 * 2 c_1 / (c_a + c_b) with c_1 = 1. */
static double material_factor(double a, double b) { return 2.0 / (a + b); }

/* Radii and masses of granules first..last. */
static void fill_masses(taper_chain *c, const taper_chain_spec *spec, size_t first, size_t last)
{
    int disordered = spec->disorder_amplitude > 0.0;
    for (size_t k = first; k <= last; k++) {
        double R = profile_radius(spec, k);
        if (disordered) R *= disorder_factor(spec, TAPER_DISORDER_RADIUS, k);
        c->radius[k - 1] = R;
        c->mass[k - 1] = R * R * R;
        if (spec->density) c->mass[k - 1] *= spec->density[k - 1];
        if (disordered) c->mass[k - 1] *= disorder_factor(spec, TAPER_DISORDER_MASS, k);
    }
}

/* Contact factors of the pairs (k, k+1) and rest positions X0(k+1), k =
 * first..last (< N), the radii known. */
static void fill_contacts(taper_chain *c, const taper_chain_spec *spec, size_t first, size_t last)
{
    for (size_t k = first; k <= last; k++) {
        c->contact[k - 1] = contact_factor(c->radius[k - 1], c->radius[k]);
        if (spec->compliance)
            c->contact[k - 1] *= material_factor(spec->compliance[k - 1], spec->compliance[k]);
        c->rest[k] = c->rest[k - 1] + c->radius[k - 1] + c->radius[k];
    }
}

/* In blocks of MONITOR_EVERY granules, the monitor asked between them:
 * 0, or the granule where it said stop. */
static size_t fill_geometry(taper_chain *c, const taper_chain_spec *spec, const build_watch *w)
{
    const size_t n = c->n;
    for (size_t first = 1; first <= n; first += MONITOR_EVERY) {
        if (stop_asked(w, first - 1)) return first - 1;
        fill_masses(c, spec, first, n - first < MONITOR_EVERY ? n : first + MONITOR_EVERY - 1);
    }
    c->rest[0] = 0.0;
    for (size_t first = 1; first < n; first += MONITOR_EVERY) {
        if (stop_asked(w, first - 1)) return first - 1;
        fill_contacts(c, spec, first, n - 1 - first < MONITOR_EVERY ? n - 1 : first + MONITOR_EVERY - 1);
    }
    c->contact[n - 1] = NAN;
    return 0;
}

/* Walls and striker (NaN where absent); a wall is eq. (7) with the other
 * radius infinite: sqrt(2 R_k). */
static void fill_ends(taper_chain *c, const taper_chain_spec *spec)
{
    const size_t end_granule[TAPER_N_ENDS] = {1, c->n};
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        size_t k = end_granule[e];
        c->end[e] = spec->end[e];
        c->end_contact[e] = spec->end[e] == TAPER_END_WALL
                                ? sqrt(2.0 * c->radius[k - 1])
                                      * material_factor(compliance_of(spec, k),
                                                        spec->end_compliance[e])
                                : NAN;
    }
    double Rs = spec->striker_radius;
    c->striker_radius = Rs > 0.0 ? Rs : NAN;
    c->striker_mass = Rs > 0.0 ? spec->striker_density * Rs * Rs * Rs : NAN;
    c->striker_contact = Rs > 0.0 ? contact_factor(Rs, c->radius[0])
                                        * material_factor(spec->striker_compliance,
                                                          compliance_of(spec, 1))
                                  : NAN;
    c->load = spec->load;
    c->damping = spec->damping;
    c->drag = spec->drag;
    c->pattern_period = spec->profile == TAPER_DECORATED ? spec->n_pattern : 0;
}

/* Densities, mass disorder and the striker move masses away from R^3: the
 * limits of check_mass_range, checked on the built values. */
static taper_status check_final_masses(const taper_chain *c, const taper_chain_spec *spec,
                                       const build_watch *w, taper_error *err)
{
    if (spec->striker_radius > 0.0
        && !(c->striker_mass >= MASS_MIN && c->striker_mass <= MASS_MAX))
        return taper_fail_field(err, TAPER_ERANGE, "striker_radius",
                                "striker mass density radius^3 = %g is outside [%g, %g], beyond "
                                "what double precision can integrate; change the striker",
                                c->striker_mass, MASS_MIN, MASS_MAX);
    if (!spec->density && !(spec->disorder_amplitude > 0.0)) return TAPER_OK;
    for (size_t k = 1; k <= c->n; k++) {
        if (stop_asked(w, k)) return interrupted(k, c->n, err);
        double m = c->mass[k - 1];
        if (!(m >= MASS_MIN && m <= MASS_MAX))
            return taper_fail_field(err, TAPER_ERANGE, spec->density ? "densities" : "disorder_amplitude",
                                    "granule %zu: mass %g is outside [%g, %g], beyond what double "
                                    "precision can integrate; change its density or the disorder",
                                    k, m, MASS_MIN, MASS_MAX);
    }
    return TAPER_OK;
}

taper_chain *taper_chain_alloc(const taper_chain_spec *spec, taper_error *err)
{
    return taper_chain_alloc_monitored(spec, NULL, NULL, err);
}

taper_chain *taper_chain_alloc_monitored(const taper_chain_spec *spec, taper_monitor_fn monitor,
                                         void *user, taper_error *err)
{
    if (!spec) {
        taper_fail(err, TAPER_EINVAL, "taper_chain_alloc: spec is NULL");
        return NULL;
    }
    if (taper_chain_spec_check(spec, err) != TAPER_OK) return NULL;
    const build_watch w = {monitor, user, spec->n_granules};
    if (check_mass_range(spec, &w, err) != TAPER_OK) return NULL;
    taper_chain *c = chain_new(spec);
    if (!c) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a chain of %zu granules", spec->n_granules);
        return NULL;
    }
    const size_t stopped = fill_geometry(c, spec, &w);
    if (stopped) {
        taper_chain_free(c);
        interrupted(stopped, spec->n_granules, err);
        return NULL;
    }
    fill_ends(c, spec);
    if (check_final_masses(c, spec, &w, err) != TAPER_OK) {
        taper_chain_free(c);
        return NULL;
    }
    chain_theory_note(c);
    chain_options_fill_piston(c, spec); /* after the note: a piston sets its own */
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

taper_boundary taper_chain_end(const taper_chain *chain, taper_end end)
{
    if (!chain || (unsigned)end >= TAPER_N_ENDS) return (taper_boundary)-1;
    return chain->end[end];
}
double taper_chain_end_contact(const taper_chain *chain, taper_end end)
{
    if (!chain || (unsigned)end >= TAPER_N_ENDS) return NAN;
    return chain->end_contact[end];
}
double taper_chain_striker_radius(const taper_chain *chain) { return chain ? chain->striker_radius : NAN; }
double taper_chain_striker_mass(const taper_chain *chain) { return chain ? chain->striker_mass : NAN; }
double taper_chain_striker_contact(const taper_chain *chain) { return chain ? chain->striker_contact : NAN; }
double taper_chain_load(const taper_chain *chain) { return chain ? chain->load : NAN; }
double taper_chain_damping(const taper_chain *chain) { return chain ? chain->damping : NAN; }
double taper_chain_drag(const taper_chain *chain) { return chain ? chain->drag : NAN; }
const char *taper_chain_theory_note(const taper_chain *chain)
{
    if (!chain) return NULL;
    return chain->theory_note[0] ? chain->theory_note : NULL;
}
