/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * peer_common.c -- results, errors and event bookkeeping shared by the
 * baseline integrators of peers.h (same arming and end rules as
 * src/sim/events.c and src/sim/solve.c).
 */
#include "peers.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ARM_FRACTION 1e-6
#define PEAK_GRACE 20.0

/* A cut text says so, as taper.h's rule for taper_error's message. */
static void format_v(char *buf, size_t size, const char *fmt, va_list ap)
{
    static const char ellipsis[] = "...";
    int needed = vsnprintf(buf, size, fmt, ap);
    if (needed < 0 || (size_t)needed >= size)
        memcpy(buf + size - sizeof ellipsis, ellipsis, sizeof ellipsis);
}

void taper_peer_format(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    format_v(buf, size, fmt, ap);
    va_end(ap);
}

taper_status taper_peer_fail(taper_error *err, taper_status status, const char *fmt, ...)
{
    if (!err) return status;
    err->status = status;
    err->field = NULL;
    va_list ap;
    va_start(ap, fmt);
    format_v(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return status;
}

taper_status taper_peer_ok(taper_error *err)
{
    if (err) {
        err->status = TAPER_OK;
        err->field = NULL;
        err->message[0] = '\0';
    }
    return TAPER_OK;
}

int taper_peer_result_init(taper_peer_result *r, size_t n)
{
    memset(r, 0, sizeof *r);
    r->n = n;
    r->t_pass = malloc(n * sizeof(double));
    r->v_peak = malloc(n * sizeof(double));
    r->t_peak = malloc(n * sizeof(double));
    if (!r->t_pass || !r->v_peak || !r->t_peak) {
        taper_peer_result_free(r);
        return -1;
    }
    for (size_t i = 0; i < n; i++) r->t_pass[i] = r->v_peak[i] = r->t_peak[i] = NAN;
    r->v_peak[0] = 1.0;
    r->t_peak[0] = 0.0;
    r->energy_drift = NAN;
    return 0;
}

void taper_peer_result_free(taper_peer_result *r)
{
    if (!r) return;
    free(r->t_pass);
    free(r->v_peak);
    free(r->t_peak);
    r->t_pass = r->v_peak = r->t_peak = NULL;
}

void taper_peer_events_init(taper_peer_events *ev, taper_peer_result *r)
{
    ev->r = r;
    ev->n = r->n;
    ev->pass_limit = r->n - 1;
    ev->next_pass = 1;
    ev->next_peak = 2;
    ev->v_ref = 1.0;
    ev->t_end = INFINITY;
}

int taper_peer_pass_armed(const taper_peer_events *ev, size_t k, double v_k)
{
    return k == ev->next_pass || v_k > ARM_FRACTION * ev->v_ref;
}

int taper_peer_peak_armed(const taper_peer_events *ev, double v_k)
{
    return v_k > ARM_FRACTION * ev->v_ref;
}

void taper_peer_record_pass(taper_peer_events *ev, size_t k, double t, double v_next)
{
    taper_peer_result *r = ev->r;
    r->t_pass[k - 1] = t;
    if (v_next > 0.0) ev->v_ref = v_next;
    while (ev->next_pass <= ev->pass_limit && !isnan(r->t_pass[ev->next_pass - 1])) ev->next_pass++;
    if (ev->next_pass > ev->pass_limit && isinf(ev->t_end)) {
        size_t m = ev->pass_limit;
        double last = r->t_pass[m - 1] - (m > 1 ? r->t_pass[m - 2] : 0.0);
        ev->t_end = t + PEAK_GRACE * fmax(last, 1e-3);
    }
}

void taper_peer_record_peak(taper_peer_events *ev, size_t k, double t, double v)
{
    taper_peer_result *r = ev->r;
    if (!(v > 0.0)) return; /* a maximum while moving backwards is no pulse peak */
    r->t_peak[k - 1] = t;
    r->v_peak[k - 1] = v;
    while (ev->next_peak <= ev->n && !isnan(r->t_peak[ev->next_peak - 1])) ev->next_peak++;
}

int taper_peer_events_done(const taper_peer_events *ev, double t)
{
    if (ev->next_pass <= ev->pass_limit) return 0;
    return ev->next_peak > ev->n || t >= ev->t_end;
}
