/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * peer_verlet.c -- the textbook velocity-Verlet baseline of peers.h.
 *
 *   x <- x + v dt + a dt^2/2;   a' = F(x)/m;   v <- v + (a + a') dt/2
 *
 * in displacements x_k (overlap delta_k = x_k - x_{k+1}), fixed step, the
 * whole chain every step, one force evaluation per step.  Events between
 * steps n-1 and n, as codes of this kind do:
 *   pass(k): g = v_{k+1} - v_k changes sign upward, time by linear
 *            interpolation of g;
 *   peak(k): a_k changes sign downward, time by linear interpolation of a_k,
 *            value from the parabola v_k(t) whose derivative is that linear
 *            a_k(t).
 * Both are second-order accurate, like the integrator.  Every moving granule
 * is checked (the ring of peers.h, widened to all armed granules), since at
 * coarse steps the pulse passes several granules per step.
 */
#include "peers.h"

#include <math.h>
#include <stdlib.h>

typedef struct verlet {
    size_t n;
    double exponent;
    int hertz;
    const double *mass, *contact;
} verlet;

static double force(const verlet *c, size_t i, double delta) /* pair (i, i+1), 0-based */
{
    if (!(delta > 0.0)) return 0.0;
    double p = c->hertz ? delta * sqrt(delta) : pow(delta, c->exponent - 1.0);
    return c->contact[i] * p;
}

static void accelerations(const verlet *c, const double *x, double *a)
{
    double left = 0.0;
    for (size_t i = 0; i < c->n; i++) {
        double f = i + 1 < c->n ? force(c, i, x[i] - x[i + 1]) : 0.0;
        a[i] = (left - f) / c->mass[i];
        left = f;
    }
}

static double energy(const verlet *c, const double *x, const double *v)
{
    double e = 0.0;
    for (size_t i = 0; i < c->n; i++) {
        e += 0.5 * c->mass[i] * v[i] * v[i];
        if (i + 1 < c->n) {
            double d = x[i] - x[i + 1];
            if (d > 0.0) e += c->contact[i] / c->exponent * pow(d, c->exponent);
        }
    }
    return e;
}

/* Events in the step (t0, t0 + dt]: old state v0, a0; new v1, a1. */
static void find_events(taper_peer_events *ev, double t0, double dt, const double *v0,
                        const double *a0, const double *v1, const double *a1)
{
    taper_peer_result *r = ev->r;
    for (size_t k = ev->next_pass; k <= ev->pass_limit && (k < ev->next_pass + TAPER_PEER_SLOTS ||
                                                          taper_peer_peak_armed(ev, v1[k - 1])); k++) {
        if (!isnan(r->t_pass[k - 1])) continue;
        double g0 = v0[k] - v0[k - 1], g1 = v1[k] - v1[k - 1];
        int armed0 = taper_peer_pass_armed(ev, k, v0[k - 1]);
        int armed1 = taper_peer_pass_armed(ev, k, v1[k - 1]);
        if (!armed1 || !(g1 >= 0.0) || (armed0 && !(g0 < 0.0))) continue;
        double theta = g0 < 0.0 ? g0 / (g0 - g1) : 0.0;
        r->event_evals++;
        taper_peer_record_pass(ev, k, t0 + theta * dt, v0[k] + theta * (v1[k] - v0[k]));
    }
    for (size_t k = ev->next_peak; k <= ev->n && (k < ev->next_peak + TAPER_PEER_SLOTS ||
                                                  taper_peer_peak_armed(ev, v1[k - 1])); k++) {
        if (!isnan(r->t_peak[k - 1])) continue;
        double g0 = a0[k - 1], g1 = a1[k - 1];
        int armed0 = taper_peer_peak_armed(ev, v0[k - 1]);
        int armed1 = taper_peer_peak_armed(ev, v1[k - 1]);
        if (!armed1 || !(g1 <= 0.0) || (armed0 && !(g0 > 0.0))) continue;
        double theta = g0 > 0.0 ? g0 / (g0 - g1) : 0.0, s = theta * dt;
        double v = v0[k - 1] + g0 * s + 0.5 * (g1 - g0) / dt * s * s;
        r->event_evals++;
        taper_peer_record_peak(ev, k, t0 + s, v);
    }
}

taper_status taper_peer_verlet(const taper_chain *chain, double dt, long max_steps,
                               taper_peer_result *r, taper_error *err)
{
    if (!chain || !r) return taper_peer_fail(err, TAPER_EINVAL, "taper_peer_verlet: NULL argument");
    if (!(dt > 0.0) || isinf(dt)) return taper_peer_fail(err, TAPER_EINVAL, "verlet: dt = %g must be > 0", dt);
    verlet c = {
        .n = taper_chain_size(chain), .exponent = taper_chain_exponent(chain),
        .mass = taper_chain_mass(chain), .contact = taper_chain_contact(chain),
    };
    c.hertz = c.exponent == 2.5;
    if (taper_peer_result_init(r, c.n) != 0) return taper_peer_fail(err, TAPER_ENOMEM, "verlet: out of memory");
    double *buf = calloc(5 * c.n, sizeof(double));
    if (!buf) {
        taper_peer_result_free(r);
        return taper_peer_fail(err, TAPER_ENOMEM, "verlet: out of memory");
    }
    double *x = buf, *v[2] = {buf + c.n, buf + 2 * c.n}, *a[2] = {buf + 3 * c.n, buf + 4 * c.n};
    v[0][0] = 1.0;
    accelerations(&c, x, a[0]);
    r->rhs_evals = 1;
    const double e0 = energy(&c, x, v[0]);
    taper_peer_events ev;
    taper_peer_events_init(&ev, r);
    double t = 0.0;
    int cur = 0;
    taper_status status = TAPER_OK;
    while (!taper_peer_events_done(&ev, t)) {
        if (max_steps > 0 && r->steps >= max_steps) {
            status = taper_peer_fail(err, TAPER_ELIMIT, "verlet: max_steps reached at t = %g", t);
            break;
        }
        const double *v0 = v[cur], *a0 = a[cur];
        double *v1 = v[1 - cur], *a1 = a[1 - cur];
        const double h2 = 0.5 * dt * dt;
        for (size_t i = 0; i < c.n; i++) x[i] += v0[i] * dt + a0[i] * h2;
        accelerations(&c, x, a1);
        for (size_t i = 0; i < c.n; i++) v1[i] = v0[i] + 0.5 * (a0[i] + a1[i]) * dt;
        r->rhs_evals++;
        r->steps++;
        /* t_{n} = n dt, not a running sum, so that round-off does not drift. */
        double t0 = t;
        t = (double)r->steps * dt;
        find_events(&ev, t0, dt, v0, a0, v1, a1);
        cur = 1 - cur;
    }
    r->t_final = t;
    r->energy_drift = fabs(energy(&c, x, v[cur]) - e0) / e0;
    r->complete = ev.next_pass > ev.pass_limit;
    free(buf);
    if (status == TAPER_OK) taper_peer_ok(err);
    return status;
}
