/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * units.c -- the SI value of the rescaled units of eq. (5) of
 * arXiv:0905.4512 for Hertz contacts (n = 5/2); docs/physics.md, "Real
 * units".
 *
 * Eq. (4): alpha = M_1 V^2 / (a R_1^(n+1/2)), with M_1 = (4/3) pi rho R_1^3
 * the mass of granule 1 and a the constant of the potential (a/n) r'_k
 * z^n.  Hertz's force between two spheres of one material is
 * (4/3) E* sqrt(R*) z^(3/2) with 1/E* = 2 (1 - nu^2)/E and
 * R* = R_k R_{k+1}/(R_k + R_{k+1}) (Landau and Lifshitz, Theory of
 * Elasticity, Sec. 9); written as a r'_k z^(3/2) with r'_k of eq. (7),
 * r'_k = sqrt(2 R*), it gives a = (4/3) E* / sqrt(2) = sqrt(2) E / (3 (1 - nu^2)).
 * Eq. (5): y = R_1 alpha^(1/n) x and tau = (R_1/V) alpha^(1/n) t; the other
 * units follow: velocity V, mass M_1, force M_1 V^2 / (R_1 alpha^(1/n)),
 * energy M_1 V^2, impulse M_1 V, a drag coefficient mass / time.  Sizes
 * (radii, rest positions) are in units of R_1, the paper's convention.  Densities
 * and compliances are relative to granule 1's: their units are rho_1 and
 * c_1 = (1 - nu^2)/E.
 */
#include "core/taper_internal.h"

#include <math.h>

#define DIMENSION_NAME(constant, name, unit) [constant] = name,
#define DIMENSION_UNIT(constant, name, unit) [constant] = unit,
static const char *const dimension_names[] = {TAPER_DIMENSION_LIST(DIMENSION_NAME)};
static const char *const dimension_units[] = {TAPER_DIMENSION_LIST(DIMENSION_UNIT)};

const char *taper_dimension_name(taper_dimension dim)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)dim >= TAPER_N_DIMENSIONS) return NULL;
    return dimension_names[dim];
}

const char *taper_dimension_unit(taper_dimension dim)
{
    if ((unsigned)dim >= TAPER_N_DIMENSIONS) return NULL;
    return dimension_units[dim];
}

static int positive(double x) { return x > 0.0 && isfinite(x); }

double taper_unit_scale(taper_dimension dim, double young, double poisson, double density,
                        double radius, double velocity)
{
    if (!taper_dimension_name(dim)) return NAN;
    if (!positive(young) || !positive(density) || !positive(radius) || !positive(velocity)
        || !(poisson > -1.0 && poisson < 0.5))
        return NAN;
    const double pi = 3.14159265358979323846;
    const double n = 2.5;
    double a = sqrt(2.0) * young / (3.0 * (1.0 - poisson * poisson));
    double mass = 4.0 / 3.0 * pi * density * radius * radius * radius;
    double alpha = mass * velocity * velocity / (a * pow(radius, n + 0.5)); /* eq. (4) */
    double length = radius * pow(alpha, 1.0 / n);                         /* eq. (5) */
    switch (dim) {
    case TAPER_DIM_LENGTH: return length;
    case TAPER_DIM_TIME: return length / velocity;
    case TAPER_DIM_VELOCITY: return velocity;
    case TAPER_DIM_MASS: return mass;
    case TAPER_DIM_FORCE: return mass * velocity * velocity / length;
    case TAPER_DIM_ENERGY: return mass * velocity * velocity;
    case TAPER_DIM_IMPULSE: return mass * velocity;
    case TAPER_DIM_SIZE: return radius;
    case TAPER_DIM_DENSITY: return density;
    case TAPER_DIM_COMPLIANCE: return (1.0 - poisson * poisson) / young;
    case TAPER_DIM_DRAG: return mass * velocity / length; /* mass / time */
    case TAPER_DIM_NUMBER: return 1.0;
    }
    return NAN;
}
