/*
 * peer_rk8_window.c -- a single-step method inside an active window: GSL's
 * rk8pd (Prince-Dormand 8(7), 13 stages) on the granules that move, the
 * question being whether such a method beats CVODE Adams (multistep, whose
 * order every contact kink costs) inside taper's window.  An experiment for
 * taper-bench (method rk8-window), not part of libtaper.
 *
 * The window is taper-reference's (drivers/bench/reference.c), in double:
 * granules lo..hi, the granule ahead joins once z_hi exceeds 1e-27 of its
 * binary-collision compression (taper's threshold is ~2e-27 on Hertz
 * chains), granules 40 behind the front leave once separating from the
 * next or at rest to 1e-12 of the pulse, and the gap to the last one that
 * left is watched.  Error control in the max norm with taper's scaled
 * tolerances: |err_i| <= rtol |y_i| + atol scale_i, scale_i the granule's
 * binary-collision velocity or compression (docs/design.md, "Tolerances
 * and defaults"); no dilution by the idle granules of the window, as a
 * WRMS norm has.  Passes and peaks (armed as in src/sim/events.c) are
 * located by the Illinois method on fresh rk8pd steps from the start of the
 * step that holds them (order 8 everywhere, no interpolant), to a few ulps
 * of t; time is a compensated sum of the steps.  Contact kinks are not
 * located: each step is accepted on its error estimate, as rk8pd's.
 */
#include "peers.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GROW_FRACTION 1e-27
#define BEHIND 40
#define REST 1e-12
#define ARM_FRACTION 1e-6

typedef struct win {
    size_t n, lo, hi;
    double exponent, v_left;
    int has_left;
    const double *inv_mass, *contact;
    double *rho, *v_scale, *z_scale;
    gsl_odeiv2_step *step;
    size_t step_dim;
    double *y, *y1, *yp, *err, *scratch;
    double t, t_comp, v_ref, z_ref;
    size_t next_pass, next_peak;
    taper_peer_result *r;
    long rhs_evals;
} win;

static size_t dim(const win *w) { return 2 * (w->hi - w->lo + 1) + 1; }

static double force(const win *w, size_t k, double z)
{
    if (!(z > 0.0)) return 0.0;
    return w->contact[k - 1] * (w->exponent == 2.5 ? z * sqrt(z) : pow(z, w->exponent - 1.0));
}

static int rhs(double t, const double *y, double *f, void *params)
{
    (void)t;
    win *w = params;
    w->rhs_evals++;
    double left = 0.0;
    size_t m = w->hi - w->lo + 1;
    for (size_t i = 0; i < m; i++) {
        size_t k = w->lo + i;
        double right = k < w->hi ? force(w, k, y[2 * i + 1]) : 0.0;
        f[2 * i] = (left - right) * w->inv_mass[k - 1];
        f[2 * i + 1] = y[2 * i] - (k < w->hi ? y[2 * i + 2] : 0.0);
        left = right;
    }
    f[2 * m] = w->has_left ? w->v_left - y[0] : 0.0;
    return GSL_SUCCESS;
}

/* One rk8pd step of size h from y into out; the max-norm error in units of
 * the tolerance.  -1 on failure. */
static double step(win *w, const double *y, double h, double *out, double rtol, double atol)
{
    size_t d = dim(w);
    if (w->step_dim != d) {
        if (w->step) gsl_odeiv2_step_free(w->step);
        w->step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, d);
        w->step_dim = d;
        if (!w->step) return -1.0;
    }
    gsl_odeiv2_step_reset(w->step);
    gsl_odeiv2_system sys = {rhs, NULL, d, w};
    memcpy(out, y, d * sizeof *out);
    if (gsl_odeiv2_step_apply(w->step, w->t, h, out, w->err, NULL, NULL, &sys) != GSL_SUCCESS) return -1.0;
    double e = 0.0;
    for (size_t i = 0; i < d; i++) {
        size_t k = w->lo + i / 2;
        double scale = i == d - 1 ? w->z_scale[w->lo > 1 ? w->lo - 2 : 0]
                       : i % 2   ? w->z_scale[k - 1] : w->v_scale[k - 1];
        double q = fabs(w->err[i]) / (rtol * fabs(out[i]) + atol * scale);
        if (!(q <= e)) e = q;
    }
    return e;
}

static double vel(const win *w, const double *y, size_t k)
{
    return k >= w->lo && k <= w->hi ? y[2 * (k - w->lo)] : 0.0;
}

static double comp(const win *w, const double *y, size_t k)
{
    return k >= w->lo && k <= w->hi ? y[2 * (k - w->lo) + 1] : 0.0;
}

/* Events: passes lo..hi, then peaks lo..hi. */
static double event_value(const win *w, const double *y, size_t e, int *armed)
{
    size_t m = w->hi - w->lo + 1, k = w->lo + (e < m ? e : e - m);
    const taper_peer_result *r = w->r;
    if (e < m) {
        *armed = k < w->n && isnan(r->t_pass[k - 1]) &&
                 (k == w->next_pass || vel(w, y, k) > ARM_FRACTION * w->v_ref);
        return vel(w, y, k + 1) - vel(w, y, k);
    }
    *armed = isnan(r->t_peak[k - 1]) && vel(w, y, k) > ARM_FRACTION * w->v_ref;
    double left = k > w->lo ? w->rho[k - 2] * comp(w, y, k - 1) : 0.0;
    return left - (k < w->hi ? w->rho[k - 1] * comp(w, y, k) : 0.0);
}

static int crossed(const win *w, const double *y0, const double *y1, size_t e)
{
    int a0, a1;
    double g0 = event_value(w, y0, e, &a0), g1 = event_value(w, y1, e, &a1);
    if (!a0 || !a1) return 0;
    return e < w->hi - w->lo + 1 ? g0 <= 0.0 && g1 > 0.0 : g0 >= 0.0 && g1 < 0.0;
}

static double locate(win *w, const double *y0, double H, size_t e, double rtol, double atol)
{
    int armed;
    double lo = 0.0, hi = H, glo = event_value(w, y0, e, &armed);
    step(w, y0, H, w->yp, rtol, atol);
    double ghi = event_value(w, w->yp, e, &armed);
    int side = 0;
    for (int it = 0; it < 100 && hi - lo > 4.0 * DBL_EPSILON * (fabs(w->t) + hi); it++) {
        double tau = (lo * ghi - hi * glo) / (ghi - glo);
        double margin = 0.01 * (hi - lo);
        if (!(tau > lo + margin)) tau = lo + margin;
        if (!(tau < hi - margin)) tau = hi - margin;
        step(w, y0, tau, w->yp, rtol, atol);
        double g = event_value(w, w->yp, e, &armed);
        if ((g > 0.0) == (ghi > 0.0)) {
            hi = tau, ghi = g;
            if (side == 1) glo *= 0.5;
            side = 1;
        } else {
            lo = tau, glo = g;
            if (side == -1) ghi *= 0.5;
            side = -1;
        }
    }
    return hi;
}

static void add_time(win *w, double h)
{
    double y = h - w->t_comp, t = w->t + y;
    w->t_comp = (t - w->t) - y;
    w->t = t;
}

static void grow(win *w)
{
    while (w->hi < w->n && w->y[2 * (w->hi - w->lo) + 1] > GROW_FRACTION * w->z_scale[w->hi - 1]) {
        size_t m = w->hi - w->lo + 1;
        double gap = w->y[2 * m];
        w->y[2 * m] = 0.0, w->y[2 * m + 1] = 0.0, w->y[2 * m + 2] = gap;
        w->hi++;
    }
}

static int shrink(win *w)
{
    while (w->lo + BEHIND < w->next_pass && w->lo + BEHIND < w->next_peak && w->lo + 2 < w->hi) {
        double v = w->y[0], z = w->y[1], v_next = w->y[2];
        int resting = fabs(v) <= REST * w->v_ref && fabs(v_next) <= REST * w->v_ref && fabs(z) <= REST * w->z_ref;
        if (!(z < 0.0 && v < v_next) && !resting) break;
        if (w->has_left && w->v_left > v && !resting) break;
        size_t d = dim(w);
        w->v_left = v, w->has_left = 1;
        memmove(w->y, w->y + 2, (d - 3) * sizeof(double));
        w->y[d - 3] = z;
        w->lo++;
    }
    return w->has_left && w->y[dim(w) - 1] > REST * w->z_ref ? -1 : 0;
}

static void record(win *w, size_t e)
{
    size_t m = w->hi - w->lo + 1, k = w->lo + (e < m ? e : e - m);
    taper_peer_result *r = w->r;
    double t = w->t + w->t_comp;
    if (e < m) {
        r->t_pass[k - 1] = t;
        double vn = vel(w, w->y, k + 1), z = comp(w, w->y, k);
        if (vn > 0.0) w->v_ref = vn;
        if (z > 0.0) w->z_ref = z;
        while (w->next_pass < w->n && !isnan(r->t_pass[w->next_pass - 1])) w->next_pass++;
    } else {
        r->t_peak[k - 1] = t;
        r->v_peak[k - 1] = vel(w, w->y, k);
        while (w->next_peak <= w->n && !isnan(r->t_peak[w->next_peak - 1])) w->next_peak++;
    }
}

taper_status taper_peer_rk8_window(const taper_chain *chain, double rtol, double atol, long max_steps,
                                   taper_peer_result *r, taper_error *err)
{
    if (!chain) return taper_peer_fail(err, TAPER_EINVAL, "rk8-window: chain is NULL");
    if (!(rtol > 0.0 && rtol < 1.0) || !(atol > 0.0 && atol < 1.0))
        return taper_peer_fail(err, TAPER_EINVAL, "rk8-window: rtol = %g, atol = %g must lie in (0, 1)", rtol, atol);
    const size_t n = taper_chain_size(chain);
    if (taper_peer_result_init(r, n) != 0) return taper_peer_fail(err, TAPER_ENOMEM, "rk8-window: out of memory");
    win w = {.n = n, .exponent = taper_chain_exponent(chain), .inv_mass = NULL, .r = r};
    double *inv_mass = malloc(n * sizeof(double)), *mu = malloc(n * sizeof(double));
    w.rho = malloc(n * sizeof(double)), w.v_scale = malloc(n * sizeof(double));
    w.z_scale = malloc(n * sizeof(double));
    size_t cap = 2 * n + 1;
    double *buf = malloc(5 * cap * sizeof(double));
    taper_status status = TAPER_OK;
    if (!inv_mass || !mu || !w.rho || !w.v_scale || !w.z_scale || !buf ||
        taper_theory_compute(chain, w.v_scale, mu, NULL, NULL, NULL) != TAPER_OK) {
        status = taper_peer_fail(err, TAPER_ENOMEM, "rk8-window: out of memory (or no theory scales)");
        goto done;
    }
    w.y = buf, w.y1 = buf + cap, w.yp = buf + 2 * cap, w.err = buf + 3 * cap, w.scratch = buf + 4 * cap;
    const double *mass = taper_chain_mass(chain), *contact = taper_chain_contact(chain);
    for (size_t k = 1; k <= n; k++) {
        inv_mass[k - 1] = 1.0 / mass[k - 1];
        w.rho[k - 1] = k < n ? pow(contact[k - 1], 1.0 / (w.exponent - 1.0)) : 0.0;
        /* z_max(k) = (n mu_k v_k^2 / (2 r_k))^(1/n) (sim.h); the last granule: its neighbour's */
        w.z_scale[k - 1] = k < n ? pow(w.exponent * mu[k - 1] * w.v_scale[k - 1] * w.v_scale[k - 1] /
                                           (2.0 * contact[k - 1]), 1.0 / w.exponent)
                                 : w.z_scale[k - 2];
        if (!(w.v_scale[k - 1] > 0.0)) w.v_scale[k - 1] = k > 1 ? w.v_scale[k - 2] : 1.0;
    }
    w.inv_mass = inv_mass, w.contact = contact;
    memset(buf, 0, 5 * cap * sizeof(double));
    w.lo = 1, w.hi = n > 1 ? 2 : 1;
    w.y[0] = 1.0;
    w.v_ref = 1.0, w.z_ref = w.z_scale[0];
    w.next_pass = 1, w.next_peak = 2;
    r->v_peak[0] = 1.0, r->t_peak[0] = 0.0; /* the impulse */
    double h = 1e-4, grace_end = INFINITY, longest = 0.0;
    while (w.next_pass < n || w.next_peak <= n) {
        if (max_steps > 0 && r->steps >= max_steps) {
            status = taper_peer_fail(err, TAPER_ELIMIT, "rk8-window: max_steps reached at t = %g", w.t);
            goto done;
        }
        if (w.next_pass >= n && !isfinite(grace_end)) {
            for (size_t k = 1; k < n; k++)
                longest = fmax(longest, r->t_pass[k - 1] - (k > 1 ? r->t_pass[k - 2] : 0.0));
            grace_end = w.t + 20.0 * fmax(longest, 1e-3); /* missing peaks: as taper_sim */
        }
        if (w.t >= grace_end) break;
        double e = step(&w, w.y, h, w.y1, rtol, atol);
        if (e < 0.0) {
            status = taper_peer_fail(err, TAPER_ESOLVER, "rk8-window: GSL step failed at t = %g", w.t);
            goto done;
        }
        if (!(e <= 1.0)) {
            r->failed_steps++;
            h *= fmax(0.2, 0.9 * pow(e, -1.0 / 8.0));
            if (!(h > 1e-16 * fabs(w.t))) {
                status = taper_peer_fail(err, TAPER_ESOLVER, "rk8-window: step size underflow at t = %g", w.t);
                goto done;
            }
            continue;
        }
        double tau = h;
        size_t first = (size_t)-1, ne = 2 * (w.hi - w.lo + 1);
        for (size_t ev = 0; ev < ne; ev++)
            if (crossed(&w, w.y, w.y1, ev)) {
                double te = locate(&w, w.y, h, ev, rtol, atol);
                if (first == (size_t)-1 || te < tau) tau = te, first = ev;
            }
        if (first != (size_t)-1) step(&w, w.y, tau, w.y1, rtol, atol);
        r->steps++;
        add_time(&w, tau);
        memcpy(w.y, w.y1, dim(&w) * sizeof(double));
        if (first != (size_t)-1) record(&w, first);
        else h *= fmin(4.0, 0.9 * pow(fmax(e, 1e-30), -1.0 / 8.0));
        grow(&w);
        if (shrink(&w) != 0) {
            status = taper_peer_fail(err, TAPER_ESOLVER, "rk8-window: the gap behind granule %zu closed", w.lo);
            goto done;
        }
    }
    r->complete = w.next_pass >= n;
    r->t_final = w.t;
    r->energy_drift = NAN;
done:
    r->rhs_evals = w.rhs_evals;
    if (w.step) gsl_odeiv2_step_free(w.step);
    free(inv_mass), free(mu), free(w.rho), free(w.v_scale), free(w.z_scale), free(buf);
    return status;
}
