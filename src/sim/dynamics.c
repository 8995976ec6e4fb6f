/*
 * dynamics.c -- right-hand side of eq. (6) in the variables
 * of dynamics.h.  This is the hot path: no allocation, no pow() for n = 5/2.
 */
#include "dynamics.h"

#include <math.h>
#include <stdlib.h>

int taper_dyn_init(taper_dyn *d, size_t n, double exponent, const double *mass,
                   const double *contact)
{
    d->n = n;
    d->exponent = exponent;
    d->hertz = exponent == 2.5;
    d->mass = mass;
    d->contact = contact;
    d->inv_mass = malloc(n * sizeof(double));
    d->rho = malloc(n * sizeof(double));
    if (!d->inv_mass || !d->rho) {
        taper_dyn_release(d);
        return -1;
    }
    for (size_t k = 1; k <= n; k++) {
        d->inv_mass[k - 1] = 1.0 / mass[k - 1];
        d->rho[k - 1] = k < n ? pow(contact[k - 1], 1.0 / (exponent - 1.0)) : 0.0;
    }
    d->lo = 1;
    d->hi = n;
    d->v_left = 0.0;
    return 0;
}

void taper_dyn_release(taper_dyn *d)
{
    free(d->inv_mass);
    free(d->rho);
    d->inv_mass = d->rho = NULL;
}

double taper_dyn_force(const taper_dyn *d, size_t k, double z)
{
    if (!(z > 0.0)) return 0.0;
    double p = d->hertz ? z * sqrt(z) : pow(z, d->exponent - 1.0);
    return d->contact[k - 1] * p;
}

double taper_dyn_force_slope(const taper_dyn *d, size_t k, double z)
{
    if (!(z > 0.0)) return 0.0;
    double p = d->hertz ? 1.5 * sqrt(z) : (d->exponent - 1.0) * pow(z, d->exponent - 2.0);
    return d->contact[k - 1] * p;
}

void taper_dyn_rhs(const taper_dyn *d, const double *y, double *ydot)
{
    const size_t lo = d->lo, hi = d->hi;
    size_t shift = 0;
    double force_left = 0.0;
    if (lo > 1) { /* boundary gap to the free-flying granule lo-1 */
        force_left = taper_dyn_force(d, lo - 1, y[0]);
        ydot[0] = d->v_left - y[1];
        shift = 1;
    }
    const double *yv = y + shift;
    double *fv = ydot + shift;
    for (size_t k = lo, i = 0; k <= hi; k++, i += 2) {
        /* The contact (hi, hi+1) is outside the window (see dynamics.h). */
        double force = k < hi ? taper_dyn_force(d, k, yv[i + 1]) : 0.0;
        double v_next = k < hi ? yv[i + 2] : 0.0;
        fv[i] = (force_left - force) * d->inv_mass[k - 1];
        fv[i + 1] = yv[i] - v_next;
        force_left = force;
    }
}

double taper_dyn_position(const taper_dyn *d, const double *y, size_t k)
{
    double x = 0.0;
    for (size_t j = d->hi; j >= k; j--) x += taper_dyn_z(d, y, j);
    return x;
}

void taper_dyn_energy_momentum(const taper_dyn *d, const double *y, double *energy,
                               double *momentum)
{
    double e = 0.0, p = 0.0;
    for (size_t k = d->lo; k <= d->hi; k++) {
        double v = taper_dyn_v(d, y, k), z = taper_dyn_z(d, y, k);
        e += 0.5 * d->mass[k - 1] * v * v;
        p += d->mass[k - 1] * v;
        if (k < d->n && z > 0.0) e += d->contact[k - 1] / d->exponent * pow(z, d->exponent);
    }
    if (d->lo > 1) {
        double z = y[0];
        if (z > 0.0) e += d->contact[d->lo - 2] / d->exponent * pow(z, d->exponent);
    }
    *energy = e;
    *momentum = p;
}

double taper_dyn_peak_function(const taper_dyn *d, const double *y, size_t k)
{
    double left = k > 1 ? d->rho[k - 2] * taper_dyn_z(d, y, k - 1) : 0.0;
    return left - d->rho[k - 1] * taper_dyn_z(d, y, k);
}
