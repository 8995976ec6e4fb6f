/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * dynamics.h -- the rescaled equations of motion (eq. (6) of arXiv:0905.4512) in
 * difference variables, on a window of granules.
 *
 * State layout (absolute indices into a 2N vector):  v_k at 2(k-1), and
 * z_k = x_k - x_{k+1} at 2(k-1)+1, with x_{N+1} := 0 so that z_N = x_N.
 * Interleaving makes the Jacobian tridiagonal (bandwidth 1).
 *
 * Why compressions, not displacements: the forces depend only on z_k, which
 * stay O(1) (or small) while granules thrown back drift arbitrarily far; in
 * displacement variables z_k = x_k - x_{k+1} would be a difference of large
 * numbers and lose digits, and CVODE's error control would weigh drift, not
 * compression.  Displacements are recovered exactly as x_k = sum_{j>=k} z_j
 * (granules ahead of the window are at rest, x = 0).
 *
 * Window: granules lo..hi are integrated.  Granules > hi are at rest; the
 * contact (hi, hi+1) is left out while z_hi is below a growth threshold (the
 * solver grows the window before it matters).  Granules < lo fly freely; the
 * gap z_{lo-1} is kept in the state (first entry) with the frozen velocity
 * v_left of granule lo-1, so that its closing can be detected (the "gap
 * slot").  It exerts no force on either side: granule lo-1 cannot take the
 * reaction, and a force on lo alone changed the momentum.  The contact
 * joins the equations when lo-1 is taken back, at the root of the gap slot
 * (window_flight.c, window.c).  With the force applied to lo, the CVODE
 * step holding that root integrated a one-sided force from the root to its
 * end, and the state interpolated back to the root carried it: a pulse reflected from a
 * right wall into a free end (t_end) lost 8e-8 of the momentum in one
 * collision (momentum error 1.4e-7, energy 3.0e-7, N = 200, against 2e-12
 * and 4.9e-9 for the whole chain; docs/window.md, "The gap slot pushes
 * nothing").
 */
#ifndef TAPER_DYNAMICS_H
#define TAPER_DYNAMICS_H

#include <stddef.h>

typedef struct taper_dyn {
    size_t n;               /* granules                                     */
    double exponent;        /* n                                            */
    int hertz;              /* exponent == 5/2: z^(3/2) = z sqrt(z), no pow */
    const double *mass;     /* m_k                                          */
    const double *contact;  /* r_k                                          */
    double *inv_mass;       /* 1 / m_k                                      */
    double *rho;            /* r_k^(1/(n-1)), rho_N = 0 (peak function)     */
    size_t lo, hi;          /* integrated granules                          */
    double v_left;          /* velocity of granule lo-1 (lo > 1) at time
                               left_since, frozen without drag             */
    double left_decay;      /* its drag's rate drag / m_(lo-1) (0: none):
                               v = v_left e^(-left_decay (t - left_since)) */
    double left_since;
    /* Beyond the paper (taper.h, "Beyond the paper"; set by the sim after
     * taper_dyn_init, all zero for the paper's chain).  Bodies of zero mass
     * are walls: inverse mass 0, they never move.  general: some option is
     * on and taper_dyn_rhs_general is the right-hand side; the paper's chain
     * keeps taper_dyn_rhs, untouched (the hot path). */
    int general;
    int dissipative;        /* damping > 0 or drag > 0                      */
    double load;            /* F0: static force through every contact, and
                               on a free first and last body               */
    const double *delta;    /* static overlaps, r_k delta_k^(n-1) = F0 (NULL
                               without a load); z is measured from them     */
    double damping;         /* Kuwabara-Kono time (rescaled)               */
    double drag;            /* force -drag v on every body                  */
    int wall_left, wall_right; /* body 1 / body n is a wall                 */
    /* The last body, carried by the one before it (0: none; sim.c,
     * "A light end carried"): it moves with its carrier, v_n = v_(n-1),
     * their contact held at z_(n-1) = 0, once both are in the window. */
    size_t carried;
} taper_dyn;

static inline size_t taper_idx_v(size_t k) { return 2 * (k - 1); }
static inline size_t taper_idx_z(size_t k) { return 2 * (k - 1) + 1; }
/* Absolute index range [begin, end) of the window's state. */
static inline size_t taper_dyn_begin(const taper_dyn *d) { return d->lo > 1 ? taper_idx_z(d->lo - 1) : 0; }
static inline size_t taper_dyn_end(const taper_dyn *d) { return 2 * d->hi; }

/* 0 on success, -1 on allocation failure. */
int taper_dyn_init(taper_dyn *d, size_t n, double exponent, const double *mass,
                   const double *contact);
void taper_dyn_release(taper_dyn *d);

/* Contact force r_k z^(n-1) theta(z) of the pair (k, k+1). */
double taper_dyn_force(const taper_dyn *d, size_t k, double z);

/* dF/dz of the pair (k, k+1): r_k (n-1) z^(n-2) theta(z) (Jacobian). */
double taper_dyn_force_slope(const taper_dyn *d, size_t k, double z);

/* y and ydot point at absolute index taper_dyn_begin(d). */
void taper_dyn_rhs(const taper_dyn *d, const double *y, double *ydot);

/* A carried body (d->carried) takes its carrier's acceleration, and their
 * contact stays where it is (at 0), applied to a right-hand side computed
 * by either function: the carrier feels no force from it (z = 0), so
 * nothing else changes.  Only while both are integrated (the carrier may
 * have left the window behind: then both fly freely, side by side). */
static inline void taper_dyn_carry(const taper_dyn *d, double *ydot)
{
    const size_t c = d->carried, begin = taper_dyn_begin(d);
    if (!c || d->hi != c || d->lo >= c) return;
    ydot[taper_idx_v(c) - begin] = ydot[taper_idx_v(c - 1) - begin];
    ydot[taper_idx_z(c - 1) - begin] = 0.0;
}

/* ---- chains with options (d->general) ------------------------------------
 * Contact k pushes with r_k (s^(n-1) + damping d(s^(n-1))/dt), s = delta_k +
 * z_k, while that is > 0, never pulls (Kuwabara and Kono, Jpn. J. Appl.
 * Phys. 26, 1230 (1987); Brilliantov et al., Phys. Rev. E 53, 5382 (1996)
 * for the form).  The contact (hi, hi+1) outside the window carries the
 * static force F0 (granules ahead are at rest in equilibrium); a free end is
 * pushed by F0; every body feels -drag v. */
double taper_dyn_contact_force(const taper_dyn *d, size_t k, double z, double zdot);
/* The elastic part alone, r_k s^(n-1) theta(s). */
double taper_dyn_elastic_force(const taper_dyn *d, size_t k, double z);
void taper_dyn_rhs_general(const taper_dyn *d, double t, const double *y, double *ydot);
/* Velocity of granule lo-1, out of the window, at time t: constant, or
 * decaying under drag (free flight, sim.h). */
double taper_dyn_v_left(const taper_dyn *d, double t);
/* Energy of contact k measured from the equilibrium,
 * U(delta + z) - U(delta) - F0 z with U(s) = r s^n / n for s > 0: convex,
 * zero at rest; the sum over contacts includes the potential of the loads
 * on free ends (their -F0 z terms telescope to -F0 (x_1 - x_N)). */
double taper_dyn_contact_energy(const taper_dyn *d, size_t k, double z);
/* Total force of contact k (lo - 1 <= k <= hi, k >= 1) in the window state:
 * the gap slot for k = lo - 1 (no force: 0), the static F0 for k = hi. */
double taper_dyn_window_force(const taper_dyn *d, const double *y, size_t k);
/* Acceleration of body k (lo <= k <= hi) in the window state. */
double taper_dyn_acceleration(const taper_dyn *d, const double *y, size_t k);
/* The quadratures of a run with walls or losses: out[0], out[1] the forces
 * of the left and right walls less the static load F0 (whose impulse F0 t
 * is exact: integrated, it would swamp the pulse's share in the error
 * control), out[2] the power dissipated by damping and drag, sum over
 * contacts of (F - F_elastic) dz/dt plus drag sum v^2. */
void taper_dyn_quadrature_rhs(const taper_dyn *d, const double *y, double *out);

/* Velocity and compression of granule k (lo <= k <= hi) in the window state;
 * compression of k = lo - 1 is the boundary gap. */
static inline double taper_dyn_v(const taper_dyn *d, const double *y, size_t k)
{
    return y[taper_idx_v(k) - taper_dyn_begin(d)];
}
static inline double taper_dyn_z(const taper_dyn *d, const double *y, size_t k)
{
    return y[taper_idx_z(k) - taper_dyn_begin(d)];
}

/* Displacement x_k = sum_{j=k}^{hi} z_j for lo <= k <= hi. */
double taper_dyn_position(const taper_dyn *d, const double *y, size_t k);

/* Kinetic plus contact energy and momentum of the window's granules. */
void taper_dyn_energy_momentum(const taper_dyn *d, const double *y, double *energy,
                               double *momentum);

/* Sign of the acceleration of granule k without the division:
 * rho_{k-1} z_{k-1} - rho_k z_k has the sign of F_{k-1} - F_k whenever a
 * contact of k is closed, and unlike the force difference it is never
 * identically zero on an interval (CVODE rejects such root functions). */
double taper_dyn_peak_function(const taper_dyn *d, const double *y, size_t k);
/* The two terms of the peak function of a dissipative chain (d->dissipative),
 * g = left - right: the forces themselves, F_{k-1} and F_k + drag v_k (k's
 * acceleration times m_k; the caller arms it only while v_k > 0, where it
 * cannot vanish on an interval).  Elastic chains, with or without a load,
 * use rho_{k-1} z_{k-1} - rho_k z_k (taper_dyn_peak_function: rho_k delta_k
 * = F0^(1/(n-1)) for every contact, so the load cancels). */
void taper_dyn_peak_terms(const taper_dyn *d, const double *y, size_t k, double *left,
                          double *right);

#endif
