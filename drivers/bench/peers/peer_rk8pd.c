/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * peer_rk8pd.c -- the GSL odeiv2 rk8pd baseline of peers.h.
 *
 * The state is taper_dynamics' whole-chain state (v_k, z_k interleaved),
 * the RHS is taper_dynamics_rhs itself, and the root functions are those
 * of taper_sim (src/sim/events.c): pass(k) g = v_{k+1} - v_k upward,
 * peak(k) g = taper_dynamics_peak_function downward.
 *
 * Event location without dense output: after each accepted step
 * (t0, y0) -> (t0 + h, y1) the ring slots are compared at both ends; for a
 * sign change the Illinois variant of regula falsi is run on theta in
 * (0, h), each g(theta) from one rk8pd step of size theta from (t0, y0)
 * (local error O(theta^9), far below the step's own error).  It stops when
 * the bracket is below 4 eps t, or g is exactly zero, or after 60
 * iterations.  Every such trial step is counted in rhs_evals and event_evals.
 *
 * GSL errors.  GSL's default error handler aborts, and setting another one
 * (gsl_set_error_handler_off) changes global state for the whole program,
 * so this file never does; instead no GSL_ERROR path is reachable from a
 * valid call, except a failed malloc inside GSL's allocators (GSL 2.7,
 * ode-initval2/):
 *  - gsl_odeiv2_step_alloc, gsl_odeiv2_evolve_alloc: GSL_ERROR_NULL only
 *    when malloc fails.  Their sizes (dim doubles, a few times) cannot
 *    overflow: n <= SIZE_MAX / (2 sizeof(double)) is checked first, and our
 *    own buffers are allocated before them.  Out of memory there still goes
 *    to GSL's handler: the peers are therefore not in libtaper.so
 *    (src/meson.build), only in taper-bench and test_peers.
 *  - gsl_odeiv2_control_y_new: GSL_ERROR_NULL when malloc fails (as above;
 *    with a non-aborting handler it would then initialise a NULL control,
 *    GSL 2.7 cstd.c), or for a negative tolerance: rtol, atol in (0, 1) are
 *    checked first.
 *  - gsl_odeiv2_evolve_apply: GSL_ERROR if the step and evolve dimensions
 *    differ (both are c.dim) or if the step h and t1 - t have opposite
 *    signs: h starts at 1e-4 and evolve only ever scales it by a factor in
 *    [0.2, 5] (cstd.c), and the loop calls it only while t < t1.
 *  - gsl_odeiv2_step_apply (rk8pd_apply), gsl_strerror: no GSL_ERROR; the
 *    right-hand side always returns GSL_SUCCESS.
 */
#include "peers.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define CACHE 64

typedef struct rk_ctx {
    taper_dynamics *dyn;
    long rhs_evals;
    gsl_odeiv2_step *step;
    gsl_odeiv2_system sys;
    double *y0, *y1, *ytry, *yerr, *dydt0;
    size_t dim;
} rk_ctx;

static int rhs(double t, const double y[], double dydt[], void *params)
{
    (void)t;
    rk_ctx *c = params;
    c->rhs_evals++;
    taper_dynamics_rhs(c->dyn, y, dydt);
    return GSL_SUCCESS;
}

/* Slot functions with the arming of events.c; kind 0: pass, 1: peak. */
static double slot_g(const taper_peer_events *ev, const rk_ctx *c, const double *y, int kind, size_t k)
{
    double v = taper_peer_v(y, k);
    if (kind == 0) {
        if (!taper_peer_pass_armed(ev, k, v)) return -1.0;
        return taper_peer_v(y, k + 1) - v;
    }
    if (!taper_peer_peak_armed(ev, v)) return 1.0;
    return taper_dynamics_peak_function(c->dyn, y, k);
}

/* Granule k moves at the end of the step: the slot ring is widened to every
 * such granule, so that loose tolerances (long steps) miss no event. */
static int in_front(const taper_peer_events *ev, const rk_ctx *c, size_t k)
{
    return taper_peer_peak_armed(ev, taper_peer_v(c->y1, k));
}

/* The state at t0 + theta into c->ytry; 0 or a GSL error code. */
static int state_at(rk_ctx *c, taper_peer_result *r, double t0, double theta)
{
    memcpy(c->ytry, c->y0, c->dim * sizeof(double));
    r->event_evals++;
    if (theta == 0.0) return 0;
    return gsl_odeiv2_step_apply(c->step, t0, theta, c->ytry, c->yerr, c->dydt0, NULL, &c->sys);
}

/* Root of the slot function in (0, h]: Illinois.
 * sign = +1: g rises through 0 (pass), -1: falls (peak). */
static int locate(taper_peer_events *ev, rk_ctx *c, double t0, double h, int kind, size_t k,
                  double g0, double g1, double *theta_out)
{
    taper_peer_result *r = ev->r;
    double sign = kind == 0 ? 1.0 : -1.0;
    double a = 0.0, b = h, fa = sign * g0, fb = sign * g1; /* fa < 0 <= fb */
    int side = 0;
    double tol = 4.0 * DBL_EPSILON * fmax(fabs(t0 + h), 1.0);
    for (int it = 0; it < 60 && b - a > tol && fb != 0.0; it++) {
        double m = b - fb * (b - a) / (fb - fa);
        if (!(m > a && m < b)) m = 0.5 * (a + b);
        int status = state_at(c, r, t0, m);
        if (status) return status;
        double fm = sign * slot_g(ev, c, c->ytry, kind, k);
        if (fm >= 0.0) {
            b = m, fb = fm;
            if (side == 1) fa *= 0.5;
            side = 1;
        } else {
            a = m, fa = fm;
            if (side == -1) fb *= 0.5;
            side = -1;
        }
    }
    *theta_out = b; /* the first point at or past the crossing, as CVODE */
    return 0;
}

static int find_events(taper_peer_events *ev, rk_ctx *c, double t0, double h)
{
    taper_peer_result *r = ev->r;
    for (int kind = 0; kind < 2; kind++) {
        /* crossings already located in this step: granule -> theta */
        size_t cache_k[CACHE];
        double cache_theta[CACHE];
        size_t n_cache = 0;
        for (;;) {
            /* earliest crossing among the slots of this kind */
            size_t first = kind == 0 ? ev->next_pass : ev->next_peak;
            size_t last = kind == 0 ? ev->pass_limit : ev->n;
            const double *known = kind == 0 ? r->t_pass : r->t_peak;
            size_t best_k = 0;
            double best_theta = INFINITY;
            for (size_t k = first; k <= last && (k < first + TAPER_PEER_SLOTS || in_front(ev, c, k)); k++) {
                if (!isnan(known[k - 1])) continue;
                double theta = NAN;
                for (size_t i = 0; i < n_cache; i++)
                    if (cache_k[i] == k) theta = cache_theta[i];
                if (isnan(theta)) {
                    double g0 = slot_g(ev, c, c->y0, kind, k), g1 = slot_g(ev, c, c->y1, kind, k);
                    int crossed = kind == 0 ? (g0 < 0.0 && g1 >= 0.0) : (g0 > 0.0 && g1 <= 0.0);
                    if (!crossed) theta = INFINITY;
                    else {
                        int status = locate(ev, c, t0, h, kind, k, g0, g1, &theta);
                        if (status) return status;
                    }
                    if (n_cache < CACHE) cache_k[n_cache] = k, cache_theta[n_cache++] = theta;
                }
                if (theta < best_theta) best_theta = theta, best_k = k;
            }
            if (!best_k) break;
            int status = state_at(c, r, t0, best_theta);
            if (status) return status;
            double t = t0 + best_theta;
            if (kind == 0)
                taper_peer_record_pass(ev, best_k, t, taper_peer_v(c->ytry, best_k + 1));
            else {
                double v = taper_peer_v(c->ytry, best_k);
                if (!(v > 0.0)) break; /* not a pulse peak; as events.c, look again later */
                taper_peer_record_peak(ev, best_k, t, v);
            }
        }
    }
    return 0;
}

taper_status taper_peer_rk8pd(const taper_chain *chain, double rtol, double atol,
                              long max_steps, taper_peer_result *r, taper_error *err)
{
    if (!chain || !r) return taper_peer_fail(err, TAPER_EINVAL, "taper_peer_rk8pd: NULL argument");
    if (!(rtol > 0.0 && rtol < 1.0) || !(atol > 0.0 && atol < 1.0))
        return taper_peer_fail(err, TAPER_EINVAL, "rk8pd: rtol = %g, atol = %g must lie in (0, 1)", rtol, atol);
    size_t n = taper_chain_size(chain);
    if (n > SIZE_MAX / (2 * sizeof(double)))
        return taper_peer_fail(err, TAPER_ENOMEM, "rk8pd: %zu granules: the state does not fit in memory", n);
    rk_ctx c;
    memset(&c, 0, sizeof c);
    if (taper_peer_result_init(r, n) != 0) return taper_peer_fail(err, TAPER_ENOMEM, "rk8pd: out of memory");
    c.dim = 2 * n;
    /* Ours first: if these fail, GSL's allocators are not reached. */
    double *buf = calloc(5 * c.dim, sizeof(double));
    c.dyn = taper_dynamics_alloc(chain, NULL);
    gsl_odeiv2_control *control = NULL;
    gsl_odeiv2_evolve *evolve = NULL;
    taper_status status = TAPER_OK;
    if (buf && c.dyn) {
        c.step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, c.dim);
        control = gsl_odeiv2_control_y_new(atol, rtol);
        evolve = gsl_odeiv2_evolve_alloc(c.dim);
    }
    if (!buf || !c.dyn || !c.step || !control || !evolve) {
        status = taper_peer_fail(err, TAPER_ENOMEM, "rk8pd: out of memory");
        goto done;
    }
    c.y0 = buf, c.y1 = buf + c.dim, c.ytry = buf + 2 * c.dim, c.yerr = buf + 3 * c.dim;
    c.dydt0 = buf + 4 * c.dim;
    c.sys = (gsl_odeiv2_system){rhs, NULL, c.dim, &c};
    c.y1[0] = 1.0; /* the impulse */
    double e0, p0, e1, p1;
    taper_dynamics_energy_momentum(c.dyn, c.y1, &e0, &p0);
    taper_peer_events ev;
    taper_peer_events_init(&ev, r);
    double t = 0.0, h = 1e-4;
    while (!taper_peer_events_done(&ev, t)) {
        if (max_steps > 0 && r->steps >= max_steps) {
            status = taper_peer_fail(err, TAPER_ELIMIT, "rk8pd: max_steps reached at t = %g", t);
            break;
        }
        double t0 = t;
        memcpy(c.y0, c.y1, c.dim * sizeof(double));
        double t1 = isinf(ev.t_end) ? 1e300 : ev.t_end;
        if (!(t < t1)) { /* evolve_apply needs t1 - t of the sign of h > 0 */
            status = taper_peer_fail(err, TAPER_ELIMIT, "rk8pd: t = %g reached with passes missing", t);
            break;
        }
        int gs = gsl_odeiv2_evolve_apply(evolve, control, c.step, &c.sys, &t, t1, &h, c.y1);
        if (gs != GSL_SUCCESS) {
            status = taper_peer_fail(err, TAPER_ESOLVER, "rk8pd: GSL error %d (%s) at t = %g", gs,
                                gsl_strerror(gs), t);
            break;
        }
        r->steps++;
        /* f(y0) for the trial steps of event location: evolve computed it
         * but keeps it private; one more evaluation, only on event steps. */
        int any = 0;
        for (size_t k = ev.next_pass; k <= ev.pass_limit && (k < ev.next_pass + TAPER_PEER_SLOTS || in_front(&ev, &c, k)) && !any; k++)
            any = slot_g(&ev, &c, c.y0, 0, k) < 0.0 && slot_g(&ev, &c, c.y1, 0, k) >= 0.0;
        for (size_t k = ev.next_peak; k <= ev.n && (k < ev.next_peak + TAPER_PEER_SLOTS || in_front(&ev, &c, k)) && !any; k++)
            any = slot_g(&ev, &c, c.y0, 1, k) > 0.0 && slot_g(&ev, &c, c.y1, 1, k) <= 0.0;
        if (any) {
            rhs(t0, c.y0, c.dydt0, &c);
            int fs = find_events(&ev, &c, t0, t - t0);
            if (fs) {
                status = taper_peer_fail(err, TAPER_ESOLVER, "rk8pd: GSL error %d in event location", fs);
                break;
            }
        }
    }
    r->t_final = t;
    r->failed_steps = (long)evolve->failed_steps;
    r->rhs_evals = c.rhs_evals;
    taper_dynamics_energy_momentum(c.dyn, c.y1, &e1, &p1);
    r->energy_drift = fabs(e1 - e0) / e0;
    r->complete = ev.next_pass > ev.pass_limit;
done:
    if (evolve) gsl_odeiv2_evolve_free(evolve);
    if (control) gsl_odeiv2_control_free(control);
    if (c.step) gsl_odeiv2_step_free(c.step);
    taper_dynamics_free(c.dyn);
    free(buf);
    if (status != TAPER_OK && status != TAPER_ELIMIT) taper_peer_result_free(r);
    if (status == TAPER_OK) taper_peer_ok(err);
    return status;
}
