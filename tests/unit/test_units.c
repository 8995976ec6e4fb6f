/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_units.c -- the SI value of the rescaled units, eqs. (4)-(5) of
 * arXiv:0905.4512 with a = sqrt(2) E / (3 (1 - nu^2)) (suite 'chain';
 * docs/physics.md, "Real units").
 *
 * One case computed by hand (steel beads of R = 4.76 mm, E = 193 GPa,
 * nu = 0.3, rho = 8000 kg/m^3 struck at 1 m/s), the dimensional relations
 * between the units, their scaling with the impulse velocity, and the
 * physical check that the units turn Hertz's law for two equal spheres into
 * the rescaled force x^(3/2) of eq. (6).
 */
#include "test_util.h"

#include "taper.h"

#define STEEL 193e9, 0.3, 8000.0, 4.76e-3

/* python3 -c "from math import *; R=4.76e-3; E=193e9; nu=0.3; rho=8000; V=1.0;
 *   a=sqrt(2)*E/(3*(1-nu*nu)); M=4/3*pi*rho*R**3; al=M*V*V/(a*R**3);
 *   L=R*al**0.4; print(repr(M), repr(L), repr(M*V*V/L))"
 * 0.003614094086506307 1.223811492755625e-05 295.3146058768041 */
static void test_hand_case(void **state)
{
    (void)state;
    assert_double_rel(taper_unit_scale(TAPER_DIM_MASS, STEEL, 1.0), 0.003614094086506307, 1e-14);
    assert_double_rel(taper_unit_scale(TAPER_DIM_LENGTH, STEEL, 1.0), 1.223811492755625e-05, 1e-14);
    assert_double_rel(taper_unit_scale(TAPER_DIM_TIME, STEEL, 1.0), 1.223811492755625e-05, 1e-14);
    assert_double_rel(taper_unit_scale(TAPER_DIM_FORCE, STEEL, 1.0), 295.3146058768041, 1e-14);
    assert_double_rel(taper_unit_scale(TAPER_DIM_VELOCITY, STEEL, 1.0), 1.0, 0);
}

/* force length = energy, energy / velocity = impulse = mass velocity =
 * force time, length / time = velocity; length ~ V^(4/5), time ~ V^(-1/5)
 * (alpha ~ V^2, eq. (4)). */
static void test_dimensions(void **state)
{
    (void)state;
    const double V[3] = {0.1, 1.0, 7.3};
    for (int i = 0; i < 3; i++) {
        double L = taper_unit_scale(TAPER_DIM_LENGTH, STEEL, V[i]);
        double T = taper_unit_scale(TAPER_DIM_TIME, STEEL, V[i]);
        double v = taper_unit_scale(TAPER_DIM_VELOCITY, STEEL, V[i]);
        double M = taper_unit_scale(TAPER_DIM_MASS, STEEL, V[i]);
        double F = taper_unit_scale(TAPER_DIM_FORCE, STEEL, V[i]);
        double E = taper_unit_scale(TAPER_DIM_ENERGY, STEEL, V[i]);
        double I = taper_unit_scale(TAPER_DIM_IMPULSE, STEEL, V[i]);
        assert_double_rel(F * L, E, 1e-14);
        assert_double_rel(E / v, I, 1e-14);
        assert_double_rel(M * v, I, 1e-14);
        assert_double_rel(F * T, I, 1e-14);
        assert_double_rel(L / T, v, 1e-14);
        assert_double_rel(v, V[i], 0);
        assert_double_rel(L / taper_unit_scale(TAPER_DIM_LENGTH, STEEL, 1.0), pow(V[i], 0.8), 1e-13);
        assert_double_rel(T / taper_unit_scale(TAPER_DIM_TIME, STEEL, 1.0), pow(V[i], -0.2), 1e-13);
        /* Hertz between two equal spheres: (4/3) E* sqrt(R*) y^(3/2) with
         * E* = E / (2 (1 - nu^2)), R* = R/2; at y = L x it must be F x^(3/2)
         * (eq. (6) with r = 1): F = (4/3) E* sqrt(R/2) L^(3/2). */
        double Estar = 193e9 / (2.0 * (1.0 - 0.09));
        assert_double_rel(F, 4.0 / 3.0 * Estar * sqrt(4.76e-3 / 2.0) * pow(L, 1.5), 1e-13);
    }
}

static void test_names_and_domain(void **state)
{
    (void)state;
    const char *names[] = {"length", "time", "velocity", "mass", "force", "energy", "impulse", "size",
                           "density", "compliance", "drag", "number"};
    const char *units[] = {"m", "s", "m/s", "kg", "N", "J", "N s", "m", "kg/m^3", "1/Pa", "kg/s", "1"};
    int i;
    for (i = 0; taper_dimension_name((taper_dimension)i); i++) {
        assert_true(i < TAPER_N_DIMENSIONS);
        assert_string_equal(taper_dimension_name((taper_dimension)i), names[i]);
        assert_string_equal(taper_dimension_unit((taper_dimension)i), units[i]);
    }
    assert_int_equal(i, TAPER_N_DIMENSIONS);
    assert_null(taper_dimension_unit((taper_dimension)TAPER_N_DIMENSIONS));
    assert_null(taper_dimension_name((taper_dimension)-1));
    /* Out of the physical range: NaN. */
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 0.0, 0.3, 8000, 1e-3, 1)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, 0.5, 8000, 1e-3, 1)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, -1.0, 8000, 1e-3, 1)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, 0.3, -1, 1e-3, 1)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, 0.3, 8000, 0, 1)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, 0.3, 8000, 1e-3, 0)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, INFINITY, 0.3, 8000, 1e-3, 1)));
    assert_true(isnan(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, NAN, 8000, 1e-3, 1)));
    assert_true(isnan(taper_unit_scale((taper_dimension)TAPER_N_DIMENSIONS, 1e9, 0.3, 8000, 1e-3, 1)));
    /* The units of the settings' dimensions: granule 1's density and
     * compliance (1 - nu^2)/E, a drag coefficient's mass / time, and 1. */
    const double E = 193e9, nu = 0.3, rho = 8000, R = 4.76e-3, V = 0.5;
    assert_true(taper_unit_scale(TAPER_DIM_SIZE, E, nu, rho, R, V) == R);
    assert_true(taper_unit_scale(TAPER_DIM_DENSITY, E, nu, rho, R, V) == rho);
    assert_true(taper_unit_scale(TAPER_DIM_COMPLIANCE, E, nu, rho, R, V) == (1 - nu * nu) / E);
    assert_true(taper_unit_scale(TAPER_DIM_NUMBER, E, nu, rho, R, V) == 1.0);
    double drag = taper_unit_scale(TAPER_DIM_DRAG, E, nu, rho, R, V);
    double m_over_t = taper_unit_scale(TAPER_DIM_MASS, E, nu, rho, R, V) /
                      taper_unit_scale(TAPER_DIM_TIME, E, nu, rho, R, V);
    assert_true(fabs(drag - m_over_t) <= 4e-16 * m_over_t);
    /* Auxetic materials (nu < 0) are physical. */
    assert_true(taper_unit_scale(TAPER_DIM_LENGTH, 1e9, -0.5, 8000, 1e-3, 1) > 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_case),
        cmocka_unit_test(test_dimensions),
        cmocka_unit_test(test_names_and_domain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
