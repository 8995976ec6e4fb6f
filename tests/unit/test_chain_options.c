/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_chain_options.c -- the chain options beyond the paper (suite 'chain'):
 * ends, striker, static load, damping, drag, mixed materials, the
 * decorated profile and disorder (taper.h, "Beyond the paper";
 * docs/physics.md).  Values are computed here from the documented
 * definitions, not read back from the library; the disorder's first values
 * come from an independent implementation of the documented algorithm (the
 * Python line quoted at test_disorder_values); every option at its default
 * leaves the paper's chain bit for bit; every refused value or relation
 * names the setting to change.
 */
#include "test_chains.h"
#include "test_util.h"

#include "chain/chain_impl.h"
#include "taper.h"

#include <ctype.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define RTOL 1e-14

static taper_chain_spec *new_spec(taper_profile profile, size_t n)
{
    taper_error err;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    assert_non_null(spec);
    test_chain_ok(taper_chain_spec_set_profile(spec, profile, &err), &err);
    test_chain_ok(taper_chain_spec_set_n_granules(spec, n, &err), &err);
    return spec;
}

static taper_chain *build(taper_chain_spec *spec)
{
    taper_error err;
    taper_chain *c = taper_chain_alloc(spec, &err);
    if (!c) print_error("cannot build the chain: %s (field %s)\n", err.message,
                        err.field ? err.field : "none");
    assert_non_null(c);
    return c;
}

/* r_k of eq. (7), written out here. */
static double eq7(double a, double b) { return sqrt(2.0 * a * b / (a + b)); }

/* With every option at its default the chain is the paper's, bit for bit:
 * the same arithmetic as before the options existed (R^3, eq. (7) as
 * written), no wall, no striker, no load, no losses, the theory applies. */
static void test_defaults(void **state)
{
    (void)state;
    taper_chain_spec *spec = new_spec(TAPER_BACKWARD_LINEAR, 30);
    taper_error err;
    test_chain_ok(taper_chain_spec_set_s(spec, 0.3, &err), &err);
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        assert_int_equal(taper_chain_spec_end(spec, (taper_end)e), TAPER_END_FREE);
        assert_true(taper_chain_spec_end_compliance(spec, (taper_end)e) == 0.0);
    }
    assert_true(taper_chain_spec_striker_radius(spec) == 0.0);
    assert_true(taper_chain_spec_striker_density(spec) == 1.0);
    assert_true(taper_chain_spec_striker_compliance(spec) == 1.0);
    assert_true(taper_chain_spec_load(spec) == 0.0);
    assert_true(taper_chain_spec_damping(spec) == 0.0);
    assert_true(taper_chain_spec_drag(spec) == 0.0);
    assert_true(taper_chain_spec_disorder_amplitude(spec) == 0.0);
    assert_int_equal(taper_chain_spec_disorder(spec), TAPER_DISORDER_RADIUS);
    assert_true(taper_chain_spec_disorder_seed(spec) == 0);
    size_t p = 9;
    assert_null(taper_chain_spec_pattern(spec, &p));
    assert_int_equal(p, 0);
    const double *rho = (const double *)1, *cc = (const double *)1;
    assert_int_equal(taper_chain_spec_materials(spec, &rho, &cc), 0);
    assert_null(rho);
    assert_null(cc);
    taper_chain *c = build(spec);
    for (size_t k = 1; k <= 30; k++) {
        double R = 1.0 + 0.3 * (double)(k - 1);
        assert_true(taper_chain_radius(c)[k - 1] == R);
        assert_true(taper_chain_mass(c)[k - 1] == R * R * R);
        if (k < 30) {
            double Rn = 1.0 + 0.3 * (double)k;
            assert_true(taper_chain_contact(c)[k - 1] == sqrt(2.0 * R * Rn / (R + Rn)));
        }
    }
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        assert_int_equal(taper_chain_end(c, (taper_end)e), TAPER_END_FREE);
        assert_true(isnan(taper_chain_end_contact(c, (taper_end)e)));
    }
    assert_true(isnan(taper_chain_striker_radius(c)));
    assert_true(isnan(taper_chain_striker_mass(c)));
    assert_true(isnan(taper_chain_striker_contact(c)));
    assert_true(taper_chain_load(c) == 0.0);
    assert_true(taper_chain_damping(c) == 0.0);
    assert_true(taper_chain_drag(c) == 0.0);
    assert_null(taper_chain_theory_note(c));
    taper_chain_free(c);
    taper_chain_spec_free(spec);
    /* NULL objects: neutral values; a NULL spec reads as a fresh one. */
    assert_true(isnan(taper_chain_end_contact(NULL, TAPER_LEFT)));
    assert_true(isnan(taper_chain_load(NULL)));
    assert_true(taper_chain_spec_damping(NULL) == 0.0);
    assert_true(taper_chain_spec_striker_density(NULL) == 1.0);
    assert_int_equal(taper_chain_spec_end(NULL, TAPER_RIGHT), TAPER_END_FREE);
    assert_null(taper_chain_theory_note(NULL));
    assert_int_equal(taper_chain_spec_materials(NULL, NULL, NULL), 0);
}

/* Every option's setter refuses values out of its range with its field
 * named and the spec unchanged. */
#define REFUSED(call, field, needle)                                                    \
    do {                                                                                \
        taper_error err_;                                                               \
        memset(&err_, 0, sizeof err_);                                                  \
        taper_error *err = &err_;                                                       \
        assert_int_equal((call), TAPER_EINVAL);                                         \
        assert_taper_error(err_, TAPER_EINVAL, field, needle);                          \
    } while (0)

static void test_setters_refuse(void **state)
{
    (void)state;
    taper_chain_spec *spec = new_spec(TAPER_MONODISPERSE, 4);
    const double bad[] = {-1.0, NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        REFUSED(taper_chain_spec_set_load(spec, bad[i], err), "load", "load = ");
        REFUSED(taper_chain_spec_set_damping(spec, bad[i], err), "damping", "damping = ");
        REFUSED(taper_chain_spec_set_drag(spec, bad[i], err), "drag", "drag = ");
        REFUSED(taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_WALL, bad[i], err),
                "left_compliance", "compliance");
        REFUSED(taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_WALL, bad[i], err),
                "right_compliance", "compliance");
        REFUSED(taper_chain_spec_set_striker(spec, bad[i], 1, 1, err), "striker_radius",
                "striker_radius = ");
        REFUSED(taper_chain_spec_set_striker(spec, 1, bad[i], 1, err), "striker_density",
                "striker_density = ");
        REFUSED(taper_chain_spec_set_striker(spec, 1, 1, bad[i], err), "striker_compliance",
                "striker_compliance = ");
        REFUSED(taper_chain_spec_set_disorder(spec, TAPER_DISORDER_MASS, bad[i], 1, err),
                "disorder_amplitude", "[0, 1)");
    }
    REFUSED(taper_chain_spec_set_striker(spec, 1, 0, 1, err), "striker_density", "> 0");
    REFUSED(taper_chain_spec_set_disorder(spec, TAPER_DISORDER_RADIUS, 1.0, 1, err),
            "disorder_amplitude", "must stay > 0");
    REFUSED(taper_chain_spec_set_disorder(spec, (taper_disorder)2, 0.1, 1, err), "disorder",
            "no such disorder");
    REFUSED(taper_chain_spec_set_end(spec, (taper_end)2, TAPER_END_WALL, 0, err), "end",
            "unknown end");
    REFUSED(taper_chain_spec_set_end(spec, TAPER_RIGHT, (taper_boundary)5, 0, err), "right",
            "no such right");
    const double zero[2] = {1, 0}, nan2[2] = {1, NAN}, ok2[2] = {1, 0.5};
    REFUSED(taper_chain_spec_set_pattern(spec, zero, 2, err), "pattern", "pattern(2) = 0");
    REFUSED(taper_chain_spec_set_pattern(spec, NULL, 2, err), "pattern", "NULL");
    REFUSED(taper_chain_spec_set_materials(spec, nan2, ok2, 2, err), "densities", "densities(2)");
    REFUSED(taper_chain_spec_set_materials(spec, ok2, zero, 2, err), "compliances",
            "compliances(2)");
    REFUSED(taper_chain_spec_set_materials(spec, ok2, NULL, 2, err), "compliances", "NULL");
    /* Nothing was changed by the refusals. */
    assert_true(taper_chain_spec_load(spec) == 0.0);
    assert_true(taper_chain_spec_damping(spec) == 0.0);
    assert_true(taper_chain_spec_drag(spec) == 0.0);
    assert_true(taper_chain_spec_striker_radius(spec) == 0.0);
    assert_true(taper_chain_spec_disorder_amplitude(spec) == 0.0);
    assert_int_equal(taper_chain_spec_end(spec, TAPER_LEFT), TAPER_END_FREE);
    assert_int_equal(taper_chain_spec_end(spec, TAPER_RIGHT), TAPER_END_FREE);
    assert_null(taper_chain_spec_pattern(spec, NULL));
    assert_int_equal(taper_chain_spec_materials(spec, NULL, NULL), 0);
    /* NULL spec. */
    taper_error err;
    assert_int_equal(taper_chain_spec_set_load(NULL, 1, &err), TAPER_EINVAL);
    assert_null(err.field);
    taper_chain_spec_free(spec);
}

/* taper_chain_spec_check and taper_chain_alloc refuse the same relation. */
static void expect_relation(taper_chain_spec *spec, const char *field, const char *needle)
{
    taper_error err, err2;
    memset(&err, 0, sizeof err);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, field, needle);
    assert_null(taper_chain_alloc(spec, &err2));
    assert_string_equal(err.message, err2.message);
    taper_chain_spec_free(spec);
}

static void test_relations(void **state)
{
    (void)state;
    taper_error err;
    const double pattern[2] = {1, 0.5}, unit_not_first[2] = {0.5, 1}, rho[3] = {1, 2, 3};
    /* A pattern without the decorated profile, and the reverse. */
    taper_chain_spec *spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_pattern(spec, pattern, 2, &err), &err);
    expect_relation(spec, "pattern", "use profile = 'decorated'");
    expect_relation(new_spec(TAPER_DECORATED, 4), "pattern", "needs a pattern");
    spec = new_spec(TAPER_DECORATED, 4);
    test_chain_ok(taper_chain_spec_set_pattern(spec, unit_not_first, 2, &err), &err);
    expect_relation(spec, "pattern", "pattern(1) = 0.5");
    /* Materials for another N. */
    spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_materials(spec, rho, rho, 3, &err), &err);
    expect_relation(spec, "densities", "3 densities but n_granules = 4");
    /* A wall compliance on a free end. */
    spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_FREE, 0.5, &err), &err);
    expect_relation(spec, "right_compliance", "no effect on a free end");
    /* Striker density or compliance without a striker. */
    spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_striker(spec, 0, 2, 1, &err), &err);
    expect_relation(spec, "striker_radius", "without a striker");
    /* A striker and a left wall. */
    spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_striker(spec, 1, 1, 1, &err), &err);
    test_chain_ok(taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_WALL, 0, &err), &err);
    expect_relation(spec, "left", "remove the striker");
    /* Kuwabara-Kono damping below n = 2 (its force diverges at contact);
     * n = 2 itself is allowed. */
    spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_damping(spec, 0.1, &err), &err);
    test_chain_ok(taper_chain_spec_set_exponent(spec, 1.75, &err), &err);
    expect_relation(spec, "damping", "diverges as a contact closes");
    spec = new_spec(TAPER_MONODISPERSE, 4);
    test_chain_ok(taper_chain_spec_set_damping(spec, 0.1, &err), &err);
    test_chain_ok(taper_chain_spec_set_exponent(spec, 2.0, &err), &err);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_OK);
    taper_chain_spec_free(spec);
    /* s and q still belong to their profiles only. */
    spec = new_spec(TAPER_DECORATED, 4);
    test_chain_ok(taper_chain_spec_set_pattern(spec, pattern, 2, &err), &err);
    test_chain_ok(taper_chain_spec_set_s(spec, 0.1, &err), &err);
    expect_relation(spec, "s", "no effect with profile = 'decorated'");
}

/* R_k = pattern[(k-1) mod P]; masses, r_k and X0 from those radii. */
static void test_decorated(void **state)
{
    (void)state;
    taper_error err;
    const double pattern[3] = {1, 0.25, 0.5};
    taper_chain_spec *spec = new_spec(TAPER_DECORATED, 7);
    test_chain_ok(taper_chain_spec_set_pattern(spec, pattern, 3, &err), &err);
    size_t p = 0;
    const double *got = taper_chain_spec_pattern(spec, &p);
    assert_int_equal(p, 3);
    assert_true(got != pattern && got[1] == 0.25);
    taper_chain *c = build(spec);
    const double R[7] = {1, 0.25, 0.5, 1, 0.25, 0.5, 1};
    double x = 0.0;
    for (int i = 0; i < 7; i++) {
        assert_true(taper_chain_radius(c)[i] == R[i]);
        assert_true(taper_chain_mass(c)[i] == R[i] * R[i] * R[i]);
        assert_double_abs(taper_chain_rest_position(c)[i], x, 1e-15);
        if (i < 6) {
            assert_double_rel(taper_chain_contact(c)[i], eq7(R[i], R[i + 1]), RTOL);
            x += R[i] + R[i + 1];
        }
    }
    assert_int_equal(taper_chain_profile(c), TAPER_DECORATED);
    assert_string_equal(taper_profile_name(TAPER_DECORATED), "decorated");
    taper_chain_free(c);
    /* A pattern whose masses leave double precision: named. */
    const double huge[2] = {1, 1e120};
    test_chain_ok(taper_chain_spec_set_pattern(spec, huge, 2, &err), &err);
    assert_null(taper_chain_alloc(spec, &err));
    assert_taper_error(err, TAPER_ERANGE, "pattern", "pattern(2)");
    /* Removed with NULL, 0. */
    test_chain_ok(taper_chain_spec_set_pattern(spec, NULL, 0, &err), &err);
    assert_null(taper_chain_spec_pattern(spec, &p));
    assert_int_equal(p, 0);
    taper_chain_spec_free(spec);
}

/* The first values of the documented algorithm (docs/physics.md,
 * "Disorder"), computed independently with Python's arbitrary-precision
 * integers:
 *
 *   python3 -c "
 *   M=2**64
 *   def u(seed,k):
 *       z=(seed+k*0x9E3779B97F4A7C15)%M
 *       z=((z^(z>>30))*0xBF58476D1CE4E5B9)%M
 *       z=((z^(z>>27))*0x94D049BB133111EB)%M
 *       z=z^(z>>31)
 *       return 2*((z>>11)/2**53)-1
 *   print([repr(u(42,k)) for k in range(2,6)])"
 *
 * gives -0.6801792142461598, -0.4427977394897227, -0.31161856695272494,
 * -0.9239396629195076.  SplitMix64's published first output from seed 0
 * (Vigna's splitmix64.c) is 0xE220A8397B1DCDAF: u(0, 1) = 2 (that >> 11)
 * 2^-53 - 1 = 0.7666216164272852. */
static void test_disorder_values(void **state)
{
    (void)state;
    const double want42[4] = {-0.6801792142461598, -0.4427977394897227, -0.31161856695272494,
                              -0.9239396629195076};
    for (int k = 2; k <= 5; k++) assert_true(chain_disorder_uniform(42, (uint64_t)k) == want42[k - 2]);
    assert_true(chain_disorder_uniform(0, 1) == 2.0 * (double)(UINT64_C(0xE220A8397B1DCDAF) >> 11) * 0x1.0p-53 - 1.0);
    assert_true(chain_disorder_uniform(0, 1) == 0.7666216164272852);
    /* Through the chain: R_k = 1 (1 + a u_k) for k >= 2, granule 1 the unit. */
    taper_error err;
    taper_chain_spec *spec = new_spec(TAPER_MONODISPERSE, 5);
    test_chain_ok(taper_chain_spec_set_disorder(spec, TAPER_DISORDER_RADIUS, 0.2, 42, &err), &err);
    assert_true(taper_chain_spec_disorder_seed(spec) == 42);
    taper_chain *c = build(spec);
    assert_true(taper_chain_radius(c)[0] == 1.0);
    for (int k = 2; k <= 5; k++) {
        double R = 1.0 + 0.2 * want42[k - 2];
        assert_true(taper_chain_radius(c)[k - 1] == R);
        assert_true(taper_chain_mass(c)[k - 1] == R * R * R);
    }
    assert_double_rel(taper_chain_contact(c)[0], eq7(1.0, 1.0 + 0.2 * want42[0]), RTOL);
    assert_null(taper_chain_theory_note(c)); /* just another chain */
    taper_chain_free(c);
    taper_chain_spec_free(spec);
}

/* The same seed gives granule k the same factor whatever N and whatever
 * the profile; other seeds other factors; mass disorder leaves radii. */
static void test_disorder_properties(void **state)
{
    (void)state;
    taper_error err;
    taper_chain_spec *spec = new_spec(TAPER_BACKWARD_LINEAR, 40);
    test_chain_ok(taper_chain_spec_set_s(spec, 0.1, &err), &err);
    test_chain_ok(taper_chain_spec_set_disorder(spec, TAPER_DISORDER_RADIUS, 0.3, 7, &err), &err);
    taper_chain *long_chain = build(spec);
    test_chain_ok(taper_chain_spec_set_n_granules(spec, 10, &err), &err);
    taper_chain *short_chain = build(spec);
    for (int i = 0; i < 10; i++)
        assert_true(taper_chain_radius(long_chain)[i] == taper_chain_radius(short_chain)[i]);
    /* The factor is the profile's radius times 1 + a u_k. */
    for (int k = 2; k <= 40; k++) {
        double ratio = taper_chain_radius(long_chain)[k - 1] / (1.0 + 0.1 * (k - 1));
        assert_double_rel(ratio, 1.0 + 0.3 * chain_disorder_uniform(7, (uint64_t)k), 1e-15);
        assert_true(ratio >= 0.7 && ratio < 1.3);
    }
    test_chain_ok(taper_chain_spec_set_n_granules(spec, 40, &err), &err);
    test_chain_ok(taper_chain_spec_set_disorder(spec, TAPER_DISORDER_RADIUS, 0.3, 8, &err), &err);
    taper_chain *other = build(spec);
    int differ = 0;
    for (int i = 1; i < 40; i++)
        differ += taper_chain_radius(other)[i] != taper_chain_radius(long_chain)[i];
    assert_int_equal(differ, 39);
    /* Mass disorder: radii, contacts and X0 of the profile, masses scaled. */
    test_chain_ok(taper_chain_spec_set_disorder(spec, TAPER_DISORDER_MASS, 0.3, 7, &err), &err);
    taper_chain *massy = build(spec);
    for (int k = 1; k <= 40; k++) {
        double R = 1.0 + 0.1 * (k - 1);
        assert_true(taper_chain_radius(massy)[k - 1] == R);
        double f = k == 1 ? 1.0 : 1.0 + 0.3 * chain_disorder_uniform(7, (uint64_t)k);
        assert_double_rel(taper_chain_mass(massy)[k - 1], R * R * R * f, 1e-15);
    }
    taper_chain_free(long_chain);
    taper_chain_free(short_chain);
    taper_chain_free(other);
    taper_chain_free(massy);
    taper_chain_spec_free(spec);
}

/* m_k = rho_k R_k^3 and r_k 2 c_1 / (c_k + c_{k+1}), with densities and
 * compliances taken relative to granule 1's (steel, brass, PTFE-like
 * numbers in SI: only their ratios matter). */
static void test_materials(void **state)
{
    (void)state;
    taper_error err;
    const double rho[4] = {7800, 8500, 2200, 7800};
    const double c[4] = {(1 - 0.09) / 200e9, (1 - 0.1156) / 100e9, (1 - 0.2116) / 0.5e9,
                         (1 - 0.09) / 200e9};
    taper_chain_spec *spec = new_spec(TAPER_BACKWARD_LINEAR, 4);
    test_chain_ok(taper_chain_spec_set_s(spec, 0.5, &err), &err);
    test_chain_ok(taper_chain_spec_set_materials(spec, rho, c, 4, &err), &err);
    const double *rd, *cd;
    assert_int_equal(taper_chain_spec_materials(spec, &rd, &cd), 4);
    assert_true(rd[0] == 1.0 && cd[0] == 1.0);
    assert_double_rel(rd[2], 2200.0 / 7800.0, RTOL);
    taper_chain *ch = build(spec);
    const double R[4] = {1, 1.5, 2, 2.5};
    for (int i = 0; i < 4; i++)
        assert_double_rel(taper_chain_mass(ch)[i], rho[i] / rho[0] * R[i] * R[i] * R[i], RTOL);
    for (int i = 0; i < 3; i++) {
        /* Hertz: 1/E* = c_k + c_{k+1}; the paper's pair has 1/E* = 2 c_1. */
        double want = eq7(R[i], R[i + 1]) * 2.0 * c[0] / (c[i] + c[i + 1]);
        assert_double_rel(taper_chain_contact(ch)[i], want, RTOL);
    }
    assert_null(taper_chain_theory_note(ch));
    taper_chain_free(ch);
    /* One material given explicitly is the default chain, exactly. */
    const double ones[4] = {3, 3, 3, 3};
    test_chain_ok(taper_chain_spec_set_materials(spec, ones, ones, 4, &err), &err);
    ch = build(spec);
    taper_chain *plain = test_chain(TAPER_BACKWARD_LINEAR, 4, 0.5, 0, 2.5, NULL);
    assert_memory_equal(taper_chain_mass(ch), taper_chain_mass(plain), 4 * sizeof(double));
    assert_memory_equal(taper_chain_contact(ch), taper_chain_contact(plain), 3 * sizeof(double));
    taper_chain_free(ch);
    taper_chain_free(plain);
    /* Masses out of range through the density: named. */
    const double heavy[4] = {1, 1, 1e301, 1};
    test_chain_ok(taper_chain_spec_set_materials(spec, heavy, ones, 4, &err), &err);
    assert_null(taper_chain_alloc(spec, &err));
    assert_taper_error(err, TAPER_ERANGE, "densities", "granule 3");
    taper_chain_spec_free(spec);
}

/* Walls: sqrt(2 R_k) 2 c_1 / (c_k + c_wall); striker: mass rho R^3,
 * contact eq. (7) with R_1 times 2 c_1 / (c_s + c_1). */
static void test_walls_and_striker(void **state)
{
    (void)state;
    taper_error err;
    const double rho[3] = {1, 1, 2}, c[3] = {1, 1, 0.5};
    taper_chain_spec *spec = new_spec(TAPER_BACKWARD_LINEAR, 3);
    test_chain_ok(taper_chain_spec_set_s(spec, 1.0, &err), &err); /* R = 1, 2, 3 */
    test_chain_ok(taper_chain_spec_set_materials(spec, rho, c, 3, &err), &err);
    test_chain_ok(taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_WALL, 0.0, &err), &err);
    test_chain_ok(taper_chain_spec_set_striker(spec, 2.0, 0.5, 3.0, &err), &err);
    assert_int_equal(taper_chain_spec_end(spec, TAPER_RIGHT), TAPER_END_WALL);
    taper_chain *ch = build(spec);
    assert_int_equal(taper_chain_end(ch, TAPER_LEFT), TAPER_END_FREE);
    assert_int_equal(taper_chain_end(ch, TAPER_RIGHT), TAPER_END_WALL);
    assert_true(isnan(taper_chain_end_contact(ch, TAPER_LEFT)));
    /* Rigid wall against granule 3 (R = 3, c = 0.5): sqrt(6) 2 / 0.5. */
    assert_double_rel(taper_chain_end_contact(ch, TAPER_RIGHT), sqrt(6.0) * 4.0, RTOL);
    assert_double_rel(taper_chain_striker_radius(ch), 2.0, 0);
    assert_double_rel(taper_chain_striker_mass(ch), 0.5 * 8.0, RTOL);
    assert_double_rel(taper_chain_striker_contact(ch), eq7(2.0, 1.0) * 2.0 / (3.0 + 1.0), RTOL);
    assert_null(taper_chain_theory_note(ch));
    taper_chain_free(ch);
    taper_chain_spec_free(spec);
    /* A left wall of granule 1's material: sqrt(2) 2/(1+1) = sqrt(2). */
    spec = new_spec(TAPER_MONODISPERSE, 3);
    test_chain_ok(taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_WALL, 1.0, &err), &err);
    ch = build(spec);
    assert_double_rel(taper_chain_end_contact(ch, TAPER_LEFT), sqrt(2.0), RTOL);
    assert_double_rel(taper_chain_spec_end_compliance(spec, TAPER_LEFT), 1.0, 0);
    taper_chain_free(ch);
    taper_chain_spec_free(spec);
}

/* A static load and losses: stored, and the theory does not apply (the
 * note says why). */
static void test_load_and_losses(void **state)
{
    (void)state;
    taper_error err;
    struct { int which; const char *needle; } cases[] = {
        {0, "precompression"}, {1, "dissipation"}, {2, "dissipation"}};
    for (size_t i = 0; i < 3; i++) {
        taper_chain_spec *spec = new_spec(TAPER_MONODISPERSE, 5);
        if (cases[i].which == 0) test_chain_ok(taper_chain_spec_set_load(spec, 0.01, &err), &err);
        if (cases[i].which == 1) test_chain_ok(taper_chain_spec_set_damping(spec, 0.1, &err), &err);
        if (cases[i].which == 2) test_chain_ok(taper_chain_spec_set_drag(spec, 0.2, &err), &err);
        taper_chain *ch = build(spec);
        assert_true(taper_chain_load(ch) == (cases[i].which == 0 ? 0.01 : 0.0));
        assert_true(taper_chain_damping(ch) == (cases[i].which == 1 ? 0.1 : 0.0));
        assert_true(taper_chain_drag(ch) == (cases[i].which == 2 ? 0.2 : 0.0));
        const char *note = taper_chain_theory_note(ch);
        assert_non_null(note);
        assert_non_null(strstr(note, cases[i].needle));
        taper_chain_free(ch);
        taper_chain_spec_free(spec);
    }
}

/* The name lists of the two new enums round-trip, in any case. */
static void test_names(void **state)
{
    (void)state;
    const char *boundaries[] = {"free", "wall"}, *kinds[] = {"radius", "mass"};
    for (int i = 0; i < 2; i++) {
        assert_string_equal(taper_boundary_name((taper_boundary)i), boundaries[i]);
        assert_string_equal(taper_disorder_name((taper_disorder)i), kinds[i]);
        char upper[16];
        size_t j = 0;
        for (; boundaries[i][j]; j++) upper[j] = (char)toupper((unsigned char)boundaries[i][j]);
        upper[j] = '\0';
        taper_boundary b = (taper_boundary)-1;
        assert_int_equal(taper_boundary_from_name(upper, &b, NULL), TAPER_OK);
        assert_int_equal(b, i);
        taper_disorder d = (taper_disorder)-1;
        assert_int_equal(taper_disorder_from_name(kinds[i], &d, NULL), TAPER_OK);
        assert_int_equal(d, i);
    }
    assert_null(taper_boundary_name((taper_boundary)TAPER_N_BOUNDARIES));
    assert_null(taper_boundary_name((taper_boundary)-1));
    assert_null(taper_disorder_name((taper_disorder)TAPER_N_DISORDERS));
    taper_error err;
    taper_boundary b = TAPER_END_WALL;
    assert_int_equal(taper_boundary_from_name("spring", &b, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "boundary", "'free', 'wall'");
    assert_int_equal(b, TAPER_END_WALL);
    taper_disorder d = TAPER_DISORDER_MASS;
    assert_int_equal(taper_disorder_from_name(NULL, &d, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "disorder", NULL);
    assert_int_equal(taper_disorder_from_name("density", &d, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "disorder", "'radius', 'mass'");
    assert_int_equal(taper_disorder_from_name("mass", NULL, &err), TAPER_EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_setters_refuse),
        cmocka_unit_test(test_relations),
        cmocka_unit_test(test_decorated),
        cmocka_unit_test(test_disorder_values),
        cmocka_unit_test(test_disorder_properties),
        cmocka_unit_test(test_materials),
        cmocka_unit_test(test_walls_and_striker),
        cmocka_unit_test(test_load_and_losses),
        cmocka_unit_test(test_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
