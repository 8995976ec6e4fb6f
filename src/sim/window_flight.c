/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * window_flight.c -- the window's edges: its extent (taper_sim_move_window,
 * the only code that moves it), the granules that leave it behind the
 * pulse into flight in closed form (free, or under drag with the handover
 * of their drag loss from the dissipation quadrature to the closed form)
 * and come back when their gap closes.  Where and when a granule may
 * leave or must come back is window.c's decision; the loop (solve.c) acts
 * on it through these.  Calls nothing else in src/sim but the window's
 * storage (window_storage.c).
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>

/* ---- the window's extent --------------------------------------------------- */
int taper_sim_move_window(taper_sim *sim, size_t lo, size_t hi, double v_left)
{
    taper_dyn moved = sim->dyn;
    /* a carried body joins with its carrier (both at rest then) */
    if (moved.carried && hi + 1 == moved.carried) hi++;
    moved.lo = lo;
    moved.hi = hi;
    moved.v_left = v_left;
    /* Under drag v_left is granule lo-1's velocity when it left, decaying
     * from then on (taper_dyn_v_left); a wall (inverse mass 0) feels none. */
    moved.left_decay = moved.left_since = 0.0;
    if (sim->out.t_free && lo > 1) {
        moved.left_decay = sim->model.drag * moved.inv_mass[lo - 2];
        moved.left_since = sim->out.t_free[lo - 2];
    }
    if (sim->state.window &&
        taper_window_set_range(sim->state.window, taper_dyn_begin(&moved), taper_dyn_end(&moved)) != 0)
        return -1;
    sim->dyn = moved;
    return 0;
}

/* ---- drag: the handover of a departed granule's loss ------------------------- */
/* A granule that leaves the window under drag goes on losing drag v^2 in
 * its flight.  Dropping that term from the dissipation quadrature's
 * right-hand side at once is a jump of dD/dt, which CVODE's error test
 * meets with ever shorter steps: E + D = E(0) was off by 8.8e-7 on a
 * backward linear chain (S = 0.5, N = 300, drag 0.001) at the default
 * tolerances, and at rtol 1e-13 CVODE failed (flag -3) on a monodisperse
 * one.  So the term fades out: from hand_start (the end of the step the
 * granule left in: the quadrature holds its loss up to there) over
 * hand_length it integrates drag v(t)^2 w(u), u = (t - hand_start) /
 * hand_length, w = 1 - S_6(u) with S_6 the smoothstep of degree 13 (w - 1
 * and w vanish to sixth order at u = 0 and 1), and the flight's closed
 * form accounts for the rest: drag v^2 (1 - w) and everything after.  Its
 * integral is taken by Gauss-Legendre quadrature (exact on the polynomial
 * w, to rounding on the exponential).  The length: HANDOVER_STEPS steps
 * of the departure's size, smooth on the scale the stepper steps at. */
#define HANDOVER_STEPS 64.0

static double fade(double u)
{
    if (!(u > 0.0)) return 1.0;
    if (!(u < 1.0)) return 0.0;
    static const double c[7] = {1716.0, -9009.0, 20020.0, -24024.0, 16380.0, -6006.0, 924.0};
    double p = c[6];
    for (int i = 5; i >= 0; i--) p = p * u + c[i];
    const double u3 = u * u * u;
    return 1.0 - u3 * u3 * u * p;
}

static double handover_term(const taper_sim *sim, size_t j, double t)
{
    const taper_out *out = &sim->out;
    const double s = t - out->hand_start[j - 1], length = out->hand_length[j - 1];
    if (!(s < length)) return 0.0;
    double v;
    taper_sim_flight(sim, j, t, NULL, &v);
    return sim->model.drag * v * v * fade(s / length);
}

double taper_sim_handover_power(const taper_sim *sim, double t)
{
    double p = 0.0;
    for (size_t i = 0; i < sim->out.n_handing; i++) p += handover_term(sim, sim->out.handing[i], t);
    return p;
}

/* 16-point Gauss-Legendre nodes and weights on [-1, 1] (the positive half). */
static const double gl_node[8] = {0.98940093499164994, 0.9445750230732326,  0.86563120238783176,
                                  0.755404408355003,   0.61787624440264377, 0.45801677765722737,
                                  0.28160355077925892, 0.095012509837637441};
static const double gl_weight[8] = {0.027152459411754058, 0.062253523938647776, 0.095158511682492897,
                                    0.12462897125553395,  0.14959598881657682,  0.16915651939500256,
                                    0.18260341504492361,  0.18945061045506847};

/* The quadrature's share of granule j's loss up to t: the integral of the
 * handover term from hand_start to t (panels short against the decay of
 * v^2, so that the exponential is integrated to rounding). */
static double handover_integral(const taper_sim *sim, size_t j, double t)
{
    const double a = sim->out.hand_start[j - 1];
    const double b = fmin(t, a + sim->out.hand_length[j - 1]);
    if (!(b > a)) return 0.0;
    const double decay = 2.0 / taper_sim_drag_time(sim, j) * (b - a);
    const size_t panels = decay > 2.0 ? (size_t)ceil(decay / 2.0) : 1;
    const double width = (b - a) / (double)panels;
    double sum = 0.0;
    for (size_t p = 0; p < panels; p++) {
        const double mid = a + ((double)p + 0.5) * width, half = 0.5 * width;
        for (int i = 0; i < 8; i++)
            sum += gl_weight[i] * half *
                   (handover_term(sim, j, mid - half * gl_node[i]) + handover_term(sim, j, mid + half * gl_node[i]));
    }
    return sum;
}

/* The drag's work on granule j, out of the window, that the quadrature
 * does not hold, up to t: its flight's loss from hand_start on, less the
 * handover's share (none before hand_start: there the quadrature, read at
 * t, holds the loss of the window's own motion). */
static double dissipated_in_flight(const taper_sim *sim, size_t j, double t)
{
    const double start = sim->out.hand_start[j - 1];
    if (!(t > start)) return 0.0;
    double v_start, v;
    taper_sim_flight(sim, j, start, NULL, &v_start);
    taper_sim_flight(sim, j, t, NULL, &v);
    return 0.5 * sim->mass[j - 1] * (v_start - v) * (v_start + v) - handover_integral(sim, j, t);
}

double taper_sim_dissipated_out(const taper_sim *sim)
{
    const taper_out *out = &sim->out;
    if (!out->t_free) return 0.0;
    double e = out->dissipated_recalled;
    for (size_t j = 1; j < sim->dyn.lo; j++) e += dissipated_in_flight(sim, j, sim->t);
    return e;
}

/* Under drag: granule j's flight starts now, its loss handed over from
 * t_step (see above); handovers that have ended are dropped from the
 * list. */
static int start_flight_under_drag(taper_sim *sim, size_t j, double t_step, double h_step)
{
    taper_out *out = &sim->out;
    size_t kept = 0;
    for (size_t i = 0; i < out->n_handing; i++) {
        const size_t k = out->handing[i];
        if (sim->t < out->hand_start[k - 1] + out->hand_length[k - 1]) out->handing[kept++] = k;
    }
    out->n_handing = kept;
    if (out->n_handing == out->handing_size) {
        const size_t size = out->handing_size ? 2 * out->handing_size : 16;
        size_t *handing = realloc(out->handing, size * sizeof *handing);
        if (!handing) return -1;
        out->handing = handing;
        out->handing_size = size;
    }
    out->handing[out->n_handing++] = j;
    out->t_free[j - 1] = sim->t;
    out->hand_start[j - 1] = t_step;
    out->hand_length[j - 1] = HANDOVER_STEPS * h_step;
    /* when it will move slower than an absorbed pulse (solve.c) */
    const double v = fabs(out->v_free[j - 1]), slow = sim->spec.rtol + sim->spec.atol * sim->v_scale[j - 1];
    const double tau = taper_sim_drag_time(sim, j);
    if (v > slow && isfinite(tau)) out->quiet_after = fmax(out->quiet_after, sim->t + tau * log(v / slow));
    return 0;
}

/* Granule j comes back under drag at sim->t: its loss in flight is booked,
 * its handover ends, and the stepper restarts here (the caller), so a handover
 * that was to start later starts now (the quadrature, read at sim->t, no
 * longer holds the window's motion of those granules beyond it). */
static void end_flight_under_drag(taper_sim *sim, size_t j)
{
    taper_out *out = &sim->out;
    out->dissipated_recalled += dissipated_in_flight(sim, j, sim->t);
    size_t kept = 0;
    for (size_t i = 0; i < out->n_handing; i++) {
        const size_t k = out->handing[i];
        if (k == j) continue;
        if (out->hand_start[k - 1] > sim->t) out->hand_start[k - 1] = sim->t;
        out->handing[kept++] = k;
    }
    out->n_handing = kept;
}

int taper_sim_release_granule(taper_sim *sim, double watch, int at_rest, double t_step, double h_step)
{
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_entries(sim);
    const size_t j = d->lo;
    const double v = taper_dyn_v(d, y, j);
    const double x = taper_dyn_position(d, y, j);
    taper_out *out = &sim->out;
    out->v_free[j - 1] = v;
    if (out->t_free) { /* drag flight from here and now (taper_sim_flight) */
        out->x_free[j - 1] = x;
        if (start_flight_under_drag(sim, j, t_step, h_step) != 0) return -1;
    } else {
        out->x_free[j - 1] = x - v * sim->t;
    }
    out->energy_free += 0.5 * sim->mass[j - 1] * v * v;
    out->momentum_free += sim->mass[j - 1] * v;
    out->gap_watch[j - 1] = watch;
    if (at_rest) out->left_resting++;
    /* Shrinking on the left never needs new buffers: this cannot fail. */
    (void)taper_sim_move_window(sim, j + 1, d->hi, v);
    return 0;
}

static double free_position(const taper_sim *sim, size_t j)
{
    double x;
    taper_sim_flight(sim, j, sim->t, &x, NULL);
    return x;
}

int taper_sim_recall_granule(taper_sim *sim)
{
    const size_t j = sim->dyn.lo - 1;
    taper_out *out = &sim->out;
    const double v0 = out->v_free[j - 1];
    double v;
    taper_sim_flight(sim, j, sim->t, NULL, &v);
    if (taper_sim_move_window(sim, j, sim->dyn.hi, j > 1 ? out->v_free[j - 2] : 0.0) != 0)
        return -1;
    out->energy_free -= 0.5 * sim->mass[j - 1] * v0 * v0;
    out->momentum_free -= sim->mass[j - 1] * v0;
    if (out->t_free) end_flight_under_drag(sim, j);
    double *y = taper_sim_entries(sim);
    y[taper_idx_v(j) - taper_dyn_begin(&sim->dyn)] = v;
    if (j > 1) y[0] = free_position(sim, j - 1) - free_position(sim, j);
    return 0;
}
