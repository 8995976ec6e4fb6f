/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * reference.c -- converged pass times of a paper chain, independent of
 * CVODE (reference.h; the method is described in taper-reference.c).
 */
#include "reference.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef long double real;

#define K_ROWS 8          /* extrapolation rows: substeps 2, 4, ..., 16; order 16 */
#define Z_JOIN 1e-40L     /* compression at which the granule ahead joins */
#define BEHIND 40         /* granules kept behind the last passed one */
#define ARM_FRACTION 1e-6L

typedef struct chain {
    size_t n;
    real exponent;
    real *inv_mass, *contact;
} chain;

/* Window state: granules lo..hi, y = (v_lo, z_lo, ..., v_hi, z_hi, gap).
 * z_k = x_k - x_{k+1} (x_{hi+1} = 0: at rest), the force of contact hi is
 * neglected (below Z_JOIN), gap = x_{lo-1} - x_lo watched with the frozen
 * velocity v_left of the last granule that left. */
typedef struct window {
    size_t lo, hi;
    real v_left;
    int has_left;
} window;

static size_t dim(const window *w) { return 2 * (w->hi - w->lo + 1) + 1; }

static real force(const chain *c, size_t k, real z)
{
    if (!(z > 0.0L)) return 0.0L;
    real p = c->exponent == 2.5L ? z * sqrtl(z) : powl(z, c->exponent - 1.0L);
    return c->contact[k - 1] * p;
}

static void rhs(const chain *c, const window *w, const real *y, real *f)
{
    real left = 0.0L;
    size_t m = w->hi - w->lo + 1;
    for (size_t i = 0; i < m; i++) {
        size_t k = w->lo + i;
        real right = k < w->hi ? force(c, k, y[2 * i + 1]) : 0.0L;
        real v_next = k < w->hi ? y[2 * i + 2] : 0.0L;
        f[2 * i] = (left - right) * c->inv_mass[k - 1];
        f[2 * i + 1] = y[2 * i] - v_next;
        left = right;
    }
    f[2 * m] = w->has_left ? w->v_left - y[0] : 0.0L;
}

/* One extrapolated step of size H from y0 into y1; err: the estimate
 * (difference of the last two diagonal entries) in the norm below. */
typedef struct work {
    size_t cap;
    real *table, *a, *b, *c, *f;
} work;

static void midpoint(const chain *ch, const window *w, const real *y0, real H, int n, real *out, work *s)
{
    size_t d = dim(w);
    real h = H / n;
    real *a = s->a, *b = s->b, *f = s->f;
    rhs(ch, w, y0, f);
    for (size_t i = 0; i < d; i++) {
        a[i] = y0[i];
        b[i] = y0[i] + h * f[i];
    }
    for (int j = 1; j < n; j++) {
        rhs(ch, w, b, f);
        for (size_t i = 0; i < d; i++) {
            real t = a[i] + 2.0L * h * f[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
    rhs(ch, w, b, f);
    for (size_t i = 0; i < d; i++) out[i] = 0.5L * (a[i] + b[i] + h * f[i]);
}

static real gbs_step(const chain *ch, const window *w, const real *y0, real H, real *y1, work *s)
{
    size_t d = dim(w);
    real *T = s->table; /* T[j*d + i]: row j after extrapolation */
    for (int j = 0; j < K_ROWS; j++) {
        midpoint(ch, w, y0, H, 2 * (j + 1), T + (size_t)j * d, s);
        /* Neville in h^2: T_j,m from T_j,m-1 and T_j-1,m-1 (in place) */
        for (int m = j - 1; m >= 0; m--) {
            real ratio = (real)(j + 1) / (real)(m + 1);
            real den = ratio * ratio - 1.0L;
            for (size_t i = 0; i < d; i++)
                T[(size_t)m * d + i] = T[(size_t)(m + 1) * d + i] +
                                       (T[(size_t)(m + 1) * d + i] - T[(size_t)m * d + i]) / den;
        }
    }
    /* after the loop T[0] holds the fully extrapolated value, T[1] the one of
     * a row less */
    real vmax = 0.0L, zmax = 0.0L;
    size_t m = w->hi - w->lo + 1;
    for (size_t i = 0; i < m; i++) {
        vmax = fmaxl(vmax, fabsl(T[2 * i]));
        zmax = fmaxl(zmax, fabsl(T[2 * i + 1]));
    }
    real err = 0.0L;
    for (size_t i = 0; i < d; i++) {
        real scale = (i == d - 1 || i % 2) ? zmax : vmax;
        real e = fabsl(T[i] - T[d + i]) / (fabsl(T[i]) + scale + 1e-300L);
        if (e > err) {
            err = e;
        }
        y1[i] = T[i];
    }
    return err;
}

/* ---- events ---------------------------------------------------------------- */
typedef struct run {
    chain c;
    window w;
    real *y, *y1, *yp;
    real t, t_comp; /* compensated time: t + t_comp */
    real *t_pass;
    unsigned char *passed;
    size_t next_pass;
    real v_ref, z_ref; /* v_{k+1} and z_k at the last pass */
    work s;
} run;

static real vel(const run *r, const real *y, size_t k)
{
    return k >= r->w.lo && k <= r->w.hi ? y[2 * (k - r->w.lo)] : 0.0L;
}

static int pass_armed(const run *r, const real *y, size_t k)
{
    if (k >= r->c.n || r->passed[k - 1] || k > r->w.hi) return 0;
    return k == r->next_pass || vel(r, y, k) > ARM_FRACTION * r->v_ref;
}

/* Event functions: 0..m-2 contacts lo..hi-1 (z), then passes lo..hi. */
static size_t n_events(const run *r) { return 2 * (r->w.hi - r->w.lo + 1) - 1; }

static real event_value(const run *r, const real *y, size_t e, int *armed)
{
    size_t m = r->w.hi - r->w.lo + 1;
    if (e < m - 1) {
        *armed = 1;
        return y[2 * e + 1];
    }
    size_t k = r->w.lo + (e - (m - 1));
    *armed = pass_armed(r, y, k);
    return vel(r, y, k + 1) - vel(r, y, k);
}

static int crossed(const run *r, const real *y0, const real *y1, size_t e)
{
    int a0, a1;
    real g0 = event_value(r, y0, e, &a0), g1 = event_value(r, y1, e, &a1);
    size_t m = r->w.hi - r->w.lo + 1;
    /* a contact that opens or closes: a kink, either way; one that stays
     * below Z_JOIN (a granule that has just joined, rounding noise around
     * an open contact) carries a force below r 1e-60: none */
    if (e < m - 1) return (g0 > 0.0L) != (g1 > 0.0L) && fmaxl(g0, g1) > Z_JOIN;
    return a0 && a1 && g0 <= 0.0L && g1 > 0.0L;       /* upward only */
}

/* Root of event e in (0, H]: the step size tau whose end has crossed,
 * bracket narrowed by Illinois on re-integrated partial steps. */
static real locate(run *r, const real *y0, real H, size_t e)
{
    int armed;
    real lo = 0.0L, hi = H;
    real glo = event_value(r, y0, e, &armed);
    gbs_step(&r->c, &r->w, y0, H, r->yp, &r->s);
    real ghi = event_value(r, r->yp, e, &armed);
    int side = 0;
    for (int it = 0; it < 200 && hi - lo > 4.0L * 1.1e-19L * (fabsl(r->t) + hi); it++) {
        real tau = (lo * ghi - hi * glo) / (ghi - glo);
        if (!(tau > lo && tau < hi)) tau = 0.5L * (lo + hi);
        /* keep the new point away from the ends to guarantee progress */
        real margin = 0.01L * (hi - lo);
        if (tau - lo < margin) tau = lo + margin;
        if (hi - tau < margin) tau = hi - margin;
        gbs_step(&r->c, &r->w, y0, tau, r->yp, &r->s);
        real g = event_value(r, r->yp, e, &armed);
        if ((g > 0.0L) == (ghi > 0.0L)) {
            hi = tau, ghi = g;
            if (side == 1) glo *= 0.5L;
            side = 1;
        } else {
            lo = tau, glo = g;
            if (side == -1) ghi *= 0.5L;
            side = -1;
        }
    }
    return hi;
}

static void add_time(run *r, real h)
{
    real y = h - r->t_comp, t = r->t + y;
    r->t_comp = (t - r->t) - y;
    r->t = t;
}

static int resize(run *r)
{
    size_t need = 2 * r->c.n + 1;
    if (r->s.cap >= need) return 0;
    r->s.cap = need;
    r->y = realloc(r->y, need * sizeof(real));
    r->y1 = realloc(r->y1, need * sizeof(real));
    r->yp = realloc(r->yp, need * sizeof(real));
    r->s.table = realloc(r->s.table, K_ROWS * need * sizeof(real));
    r->s.a = realloc(r->s.a, need * sizeof(real));
    r->s.b = realloc(r->s.b, need * sizeof(real));
    r->s.f = realloc(r->s.f, need * sizeof(real));
    return r->y && r->y1 && r->yp && r->s.table && r->s.a && r->s.b && r->s.f ? 0 : -1;
}

/* Window changes at a step's end. */
static void grow(run *r)
{
    window *w = &r->w;
    while (w->hi < r->c.n && r->y[2 * (w->hi - w->lo) + 1] > Z_JOIN) {
        size_t m = w->hi - w->lo + 1;
        real gap = r->y[2 * m];
        r->y[2 * m] = 0.0L;     /* v of the new granule */
        r->y[2 * m + 1] = 0.0L; /* its compression with the one ahead */
        r->y[2 * m + 2] = gap;
        w->hi++;
    }
}

/* Granule lo leaves, BEHIND granules behind the front, when it separates
 * from lo+1 (and is no faster than the one that left before it), or when
 * both are at rest to REST of the pulse (the residue behind a monodisperse
 * pulse: velocities of 1e-15, compressions of 1e-13, forces of 1e-20; a
 * disturbance that small travels far slower than the pulse, whose speed
 * grows with its amplitude, and never reaches it).  The gap to the last
 * one that left is watched: closing by more than REST z_ref fails. */
#define REST 1e-12L

static int at_rest(const run *r, real v, real z, real v_next)
{
    return fabsl(v) <= REST * r->v_ref && fabsl(v_next) <= REST * r->v_ref && fabsl(z) <= REST * r->z_ref;
}

static int shrink(run *r)
{
    window *w = &r->w;
    while (w->lo + BEHIND < r->next_pass && w->lo + 2 < w->hi) {
        real v = r->y[0], z = r->y[1], v_next = r->y[2];
        int resting = at_rest(r, v, z, v_next);
        if (!(z < 0.0L && v < v_next) && !resting) break;
        if (w->has_left && w->v_left > v && !resting) break; /* the last one to leave would catch up */
        size_t d = dim(w);
        w->v_left = v;
        w->has_left = 1;
        memmove(r->y, r->y + 2, (d - 3) * sizeof(real));
        r->y[d - 3] = z; /* the new gap: x_lo - x_{lo+1} */
        w->lo++;
    }
    if (w->has_left && r->y[dim(w) - 1] > REST * r->z_ref) {
        fprintf(stderr, "taper-reference: the gap behind granule %zu closed at t = %.6Lg\n", w->lo, r->t);
        return -1;
    }
    return 0;
}

static int integrate(run *r, real tol)
{
    real H = 1e-6L;
    r->t = r->t_comp = 0.0L;
    for (long steps = 0; r->next_pass < r->c.n; steps++) {
        if (steps > 50000000L) {
            fprintf(stderr, "taper-reference: too many steps\n");
            return -1;
        }
        real err = gbs_step(&r->c, &r->w, r->y, H, r->y1, &r->s);
        if (!(err <= tol)) {
            H *= err > 0.0L && isfinite(err) ? fmaxl(0.2L, 0.9L * powl(tol / err, 1.0L / (2 * K_ROWS + 1))) : 0.2L;
            continue;
        }
        /* the earliest event inside the step ends it */
        real tau = H;
        size_t first = (size_t)-1;
        for (size_t e = 0; e < n_events(r); e++)
            if (crossed(r, r->y, r->y1, e)) {
                real te = locate(r, r->y, H, e);
                if (te < tau || first == (size_t)-1) tau = te, first = e;
            }
        if (first != (size_t)-1) gbs_step(&r->c, &r->w, r->y, tau, r->y1, &r->s);
        real grow_by = fminl(4.0L, 0.9L * powl(tol / fmaxl(err, 1e-300L), 1.0L / (2 * K_ROWS + 1)));
        add_time(r, tau);
        memcpy(r->y, r->y1, dim(&r->w) * sizeof(real));
        size_t m = r->w.hi - r->w.lo + 1;
        if (first != (size_t)-1 && first >= m - 1) {
            size_t k = r->w.lo + (first - (m - 1));
            r->passed[k - 1] = 1;
            r->t_pass[k - 1] = r->t + r->t_comp;
            real vn = vel(r, r->y, k + 1);
            if (vn > 0.0L) r->v_ref = vn;
            if (k < r->w.hi && r->y[2 * (k - r->w.lo) + 1] > 0.0L) r->z_ref = r->y[2 * (k - r->w.lo) + 1];
            while (r->next_pass < r->c.n && r->passed[r->next_pass - 1]) r->next_pass++;
        }
        grow(r);
        if (shrink(r) != 0) return -1;
        if (first == (size_t)-1) H *= grow_by;
    }
    return 0;
}

int taper_reference_pass_times(const taper_chain *chain, long double tol, long double *t_pass)
{
    run r = {0};
    int status = -1;
    r.c.n = taper_chain_size(chain);
    r.c.exponent = taper_chain_exponent(chain);
    r.c.inv_mass = malloc(r.c.n * sizeof(real));
    r.c.contact = malloc(r.c.n * sizeof(real));
    r.t_pass = t_pass;
    r.passed = calloc(r.c.n, 1);
    if (r.c.inv_mass && r.c.contact && r.passed && resize(&r) == 0) {
        for (size_t k = 1; k <= r.c.n; k++) {
            r.c.inv_mass[k - 1] = 1.0L / (real)taper_chain_mass(chain)[k - 1];
            r.c.contact[k - 1] = k < r.c.n ? (real)taper_chain_contact(chain)[k - 1] : 0.0L;
            r.t_pass[k - 1] = NAN;
        }
        /* granules 1 and 2, v_1 = 1 */
        r.w.lo = 1, r.w.hi = r.c.n > 1 ? 2 : 1;
        memset(r.y, 0, (2 * r.c.n + 1) * sizeof(real));
        r.y[0] = 1.0L;
        r.next_pass = 1;
        r.v_ref = 1.0L;
        r.z_ref = 1.0L;
        status = integrate(&r, tol);
    } else {
        fprintf(stderr, "taper-reference: out of memory\n");
    }
    free(r.c.inv_mass), free(r.c.contact), free(r.passed);
    free(r.y), free(r.y1), free(r.yp);
    free(r.s.table), free(r.s.a), free(r.s.b), free(r.s.f);
    return status;
}
