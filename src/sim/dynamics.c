/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * dynamics.c -- right-hand side of eq. (6) in the variables
 * of dynamics.h.  This is the hot path: no allocation, no pow() for n = 5/2.
 * Chains with options (walls, striker, load, losses) have their own
 * right-hand side, taper_dyn_rhs_general, chosen once by the sim: the
 * paper's chain runs the plain one, unchanged.
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
        /* mass 0: a wall (sim.c), which never moves */
        d->inv_mass[k - 1] = mass[k - 1] > 0.0 ? 1.0 / mass[k - 1] : 0.0;
        d->rho[k - 1] = k < n ? pow(contact[k - 1], 1.0 / (exponent - 1.0)) : 0.0;
    }
    d->lo = 1;
    d->hi = n;
    d->v_left = 0.0;
    d->left_decay = d->left_since = 0.0;
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

/* The gap slot z_{lo-1} (dynamics.h) exerts no force, on either side: the
 * granule out of the window cannot take the reaction. */
void taper_dyn_rhs(const taper_dyn *d, const double *y, double *ydot)
{
    const size_t lo = d->lo, hi = d->hi;
    size_t shift = 0;
    double force_left = 0.0;
    if (lo > 1) { /* boundary gap to the free-flying granule lo-1: watched only */
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
    if (d->general) { /* walls have mass 0; energies from the equilibrium */
        for (size_t k = d->lo; k <= d->hi; k++) {
            double v = taper_dyn_v(d, y, k);
            e += 0.5 * d->mass[k - 1] * v * v;
            p += d->mass[k - 1] * v;
            if (k < d->n) e += taper_dyn_contact_energy(d, k, taper_dyn_z(d, y, k));
        }
        *energy = e; /* the gap slot exerts no force and holds no energy */
        *momentum = p;
        return;
    }
    for (size_t k = d->lo; k <= d->hi; k++) {
        double v = taper_dyn_v(d, y, k), z = taper_dyn_z(d, y, k);
        e += 0.5 * d->mass[k - 1] * v * v;
        p += d->mass[k - 1] * v;
        if (k < d->n && z > 0.0) e += d->contact[k - 1] / d->exponent * pow(z, d->exponent);
    }
    *energy = e; /* the gap slot exerts no force and holds no energy */
    *momentum = p;
}

double taper_dyn_peak_function(const taper_dyn *d, const double *y, size_t k)
{
    if (d->dissipative) {
        double left, right;
        taper_dyn_peak_terms(d, y, k, &left, &right);
        return left - right;
    }
    double left = k > d->lo ? d->rho[k - 2] * taper_dyn_z(d, y, k - 1) : 0.0; /* no gap slot force */
    return left - d->rho[k - 1] * taper_dyn_z(d, y, k);
}

/* ---- chains with options ------------------------------------------------ */
/* Every force below is measured from the static load: Phi = F - F0.  Under a
 * load F0 the forces are F0 plus the pulse's share, and F0 cancels between
 * the two contacts of a granule; computing the totals and subtracting them
 * would leave the rounding of F0 (1e-13 of it, against pulse forces 1e-3 of
 * it for F0 = 1000) in every acceleration: the momentum balance of a loaded
 * chain drifted to 2e-9 at rtol 1e-12.  With Phi a free end's load, the
 * contact outside the window and the state at rest are all exactly 0. */
static double overlap(const taper_dyn *d, size_t k, double z)
{
    return d->delta ? d->delta[k - 1] + z : z;
}

static double power_law(const taper_dyn *d, double s)
{
    return d->hertz ? s * sqrt(s) : pow(s, d->exponent - 1.0);
}

/* r_k s^(n-1) - F0 for s = delta_k + z > 0: F0 ((1 + z/delta)^(n-1) - 1)
 * without cancellation. */
static double elastic_excess(const taper_dyn *d, size_t k, double z)
{
    if (!d->delta) return z > 0.0 ? d->contact[k - 1] * power_law(d, z) : 0.0;
    const double delta = d->delta[k - 1];
    if (!(delta + z > 0.0)) return -d->load;
    return d->load * expm1((d->exponent - 1.0) * log1p(z / delta));
}

/* Phi_k = F_k - F0 with damping: F = r (s^(n-1) + damping (n-1) s^(n-2)
 * dz/dt) while > 0, so Phi >= -F0.  At s = 0 the damping term is its
 * limit from closing contacts: 0 for n > 2, r damping dz/dt for n = 2 (a
 * chain starts just touching with v_1 = 1: there the force must be the one
 * the first step meets, or CVODE fails its error test at t = 0). */
static double excess_force(const taper_dyn *d, size_t k, double z, double zdot)
{
    const double s = overlap(d, k, z);
    if (!(s >= 0.0)) return -d->load;
    double phi = elastic_excess(d, k, z);
    if (d->damping > 0.0) { /* d(s^(n-1))/dt = (n-1) s^(n-2) dz/dt */
        const double s_n2 = d->hertz ? sqrt(s) : pow(s, d->exponent - 2.0);
        phi += d->contact[k - 1] * d->damping * (d->exponent - 1.0) * s_n2 * zdot;
    }
    return phi > -d->load ? phi : -d->load;
}

double taper_dyn_elastic_force(const taper_dyn *d, size_t k, double z)
{
    if (!(overlap(d, k, z) > 0.0)) return 0.0;
    return elastic_excess(d, k, z) + d->load;
}

double taper_dyn_contact_force(const taper_dyn *d, size_t k, double z, double zdot)
{
    if (!(overlap(d, k, z) >= 0.0)) return 0.0;
    return excess_force(d, k, z, zdot) + d->load;
}

double taper_dyn_v_left(const taper_dyn *d, double t)
{
    return d->left_decay > 0.0 ? d->v_left * exp(-d->left_decay * (t - d->left_since)) : d->v_left;
}

void taper_dyn_rhs_general(const taper_dyn *d, double t, const double *y, double *ydot)
{
    const size_t lo = d->lo, hi = d->hi;
    size_t shift = 0;
    double force_left = 0.0; /* a free first body: its load F0, less F0 */
    if (lo > 1) { /* the gap slot: no force (F - F0 = -F0; no departures under a load) */
        force_left = -d->load;
        ydot[0] = taper_dyn_v_left(d, t) - y[1];
        shift = 1;
    }
    const double *yv = y + shift;
    double *fv = ydot + shift;
    for (size_t k = lo, i = 0; k <= hi; k++, i += 2) {
        const double v = yv[i], v_next = k < hi ? yv[i + 2] : 0.0;
        /* Beyond hi: the static contact outside the window, or the load on
         * a free last body: F0 either way, 0 here (a wall body has inverse
         * mass 0). */
        double force = k < hi ? excess_force(d, k, yv[i + 1], v - v_next) : 0.0;
        fv[i] = (force_left - force - d->drag * v) * d->inv_mass[k - 1];
        fv[i + 1] = v - v_next;
        force_left = force;
    }
}

/* (1 + u)^n - 1 - n u without the cancellation of its first terms for
 * small u (the energy of a weak pulse in a strongly loaded chain). */
static double excess_power(double n, double u)
{
    if (fabs(u) < 0.05) {
        double term = n * u, sum = 0.0;
        for (int j = 2; j < 60; j++) {
            term *= (n - j + 1) / j * u;
            sum += term;
            if (fabs(term) <= 1e-18 * fabs(sum)) break;
        }
        return sum;
    }
    return pow(1.0 + u, n) - 1.0 - n * u;
}

double taper_dyn_contact_energy(const taper_dyn *d, size_t k, double z)
{
    const double n = d->exponent, r = d->contact[k - 1];
    if (!d->delta) return z > 0.0 ? r / n * pow(z, n) : 0.0;
    const double delta = d->delta[k - 1], u0 = r * pow(delta, n) / n;
    if (!(delta + z > 0.0)) return -u0 - d->load * z;
    return u0 * excess_power(n, z / delta);
}

/* Phi of contact k (lo - 1 <= k) in the window state: the gap slot (no
 * force: -F0), the window's own, 0 (static) from hi on. */
static double window_excess(const taper_dyn *d, const double *y, size_t k)
{
    if (k + 1 == d->lo) return -d->load;
    if (k >= d->hi) return 0.0;
    return excess_force(d, k, taper_dyn_z(d, y, k), taper_dyn_v(d, y, k) - taper_dyn_v(d, y, k + 1));
}

double taper_dyn_window_force(const taper_dyn *d, const double *y, size_t k)
{
    return window_excess(d, y, k) + d->load;
}

/* Phi on body k from the left (its contact k-1, or a free first body's
 * load: 0) and from the right (contact k, or a free last body's: 0). */
static double excess_left(const taper_dyn *d, const double *y, size_t k)
{
    return k > 1 ? window_excess(d, y, k - 1) : 0.0;
}

static double excess_right(const taper_dyn *d, const double *y, size_t k)
{
    return k < d->n ? window_excess(d, y, k) : 0.0;
}

double taper_dyn_acceleration(const taper_dyn *d, const double *y, size_t k)
{
    if (k < d->lo || k > d->hi) return 0.0;
    return (excess_left(d, y, k) - excess_right(d, y, k) - d->drag * taper_dyn_v(d, y, k)) *
           d->inv_mass[k - 1];
}

void taper_dyn_peak_terms(const taper_dyn *d, const double *y, size_t k, double *left,
                          double *right)
{
    /* the force balance, both sides less F0 (elastic chains use the rho
     * form of taper_dyn_peak_function instead) */
    *left = excess_left(d, y, k);
    *right = excess_right(d, y, k) + d->drag * taper_dyn_v(d, y, k);
}

/* Dissipated power of contact k: (F - F_elastic) dz/dt >= 0 (the clipped
 * force never pulls: where it is 0, -F_elastic dz/dt > 0). */
static double contact_loss(const taper_dyn *d, size_t k, double z, double zdot)
{
    if (!(d->damping > 0.0) || !(overlap(d, k, z) >= 0.0)) return 0.0; /* as excess_force */
    return (excess_force(d, k, z, zdot) - elastic_excess(d, k, z)) * zdot;
}

void taper_dyn_quadrature_rhs(const taper_dyn *d, const double *y, double *out)
{
    const size_t lo = d->lo, hi = d->hi;
    out[0] = out[1] = out[2] = 0.0;
    /* Left wall: body 1, its contact with granule 1 (body 2) in the window;
     * out of it (the gap slot, or further) it pushes nothing: F = 0,
     * F - F0 = -F0. */
    if (d->wall_left) out[0] = lo == 1 && hi >= 2 ? window_excess(d, y, 1) : -d->load;
    /* Right wall: body n; beyond the window its contact is static. */
    if (d->wall_right) out[1] = hi == d->n ? window_excess(d, y, d->n - 1) : 0.0;
    double loss = 0.0; /* the gap slot: no force, no loss */
    for (size_t k = lo; k <= hi; k++) {
        const double v = taper_dyn_v(d, y, k);
        if (k < hi) loss += contact_loss(d, k, taper_dyn_z(d, y, k), v - taper_dyn_v(d, y, k + 1));
        /* a body of inverse mass 0 feels no drag (the rhs), even moving: a piston */
        if (d->inv_mass[k - 1] > 0.0) loss += d->drag * v * v;
    }
    out[2] = loss;
}
