/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * solver_spec.c -- taper_solver_spec: allocation, the typed setters and
 * getters of taper.h (thin calls into the table of settings), and what is
 * not a setting of the table: the sampler, the monitor and the log, which
 * are functions.  What depends on the chain or on the method (last_granule
 * <= N, max_order per method) is checked by taper_sim_alloc, which sees
 * both.
 */
#include "settings/settings.h"

#include <math.h>
#include <stdlib.h>

static const setting_row *row(const char *name)
{
    return setting_row_of(name, TAPER_SETTING_SOLVER, NULL);
}

void taper_solver_spec_defaults(struct taper_solver_spec *spec)
{
    *spec = (struct taper_solver_spec){0};
    /* The defaults of rtol and atol were measured (docs/benchmarks.md,
     * "Results"): with atol relative to each granule's binary-collision
     * scale, t_pass and v_peak stay within 3.8e-9 and 2.1e-8 of the
     * reference on the five benchmark chains up to N = 1000. */
    setting_defaults(spec, TAPER_SETTING_SOLVER);
}

int taper_method_max_order(taper_method method)
{
    switch (method) {
    case TAPER_ADAMS: return TAPER_MAX_ORDER_ADAMS;
    case TAPER_BDF: return TAPER_MAX_ORDER_BDF;
    case TAPER_RK8: return 0; /* a fixed order: its coefficients are one pair */
    }
    return 0;
}

taper_solver_spec *taper_solver_spec_alloc(taper_error *err)
{
    taper_solver_spec *spec = malloc(sizeof *spec);
    if (!spec) {
        taper_fail(err, TAPER_ENOMEM, "cannot allocate a solver spec");
        return NULL;
    }
    taper_solver_spec_defaults(spec);
    taper_ok(err);
    return spec;
}

void taper_solver_spec_free(taper_solver_spec *spec) { free(spec); }

static taper_status set(taper_solver_spec *spec, const char *function, const char *name,
                        double value, taper_error *err)
{
    if (!spec) return setting_null_spec(err, function);
    const setting_row *r = row(name);
    taper_status st = setting_check(r, value, err);
    if (st == TAPER_OK) setting_store(spec, r, value);
    return st;
}

static double get(const taper_solver_spec *spec, const char *name)
{
    return setting_value(spec, row(name));
}

taper_status taper_solver_spec_set_method(taper_solver_spec *spec, taper_method method,
                                          taper_error *err)
{
    return set(spec, __func__, "method", (double)(int)method, err);
}
taper_status taper_solver_spec_set_rtol(taper_solver_spec *spec, double rtol, taper_error *err)
{
    return set(spec, __func__, "rtol", rtol, err);
}
taper_status taper_solver_spec_set_atol(taper_solver_spec *spec, double atol, taper_error *err)
{
    return set(spec, __func__, "atol", atol, err);
}
taper_status taper_solver_spec_set_last_granule(taper_solver_spec *spec, size_t last_granule,
                                                taper_error *err)
{
    return set(spec, __func__, "last_granule", (double)last_granule, err);
}
/* Any non-zero int switches it on, as C reads a flag. */
taper_status taper_solver_spec_set_window(taper_solver_spec *spec, int window, taper_error *err)
{
    return set(spec, __func__, "window", window != 0, err);
}
taper_status taper_solver_spec_set_max_order(taper_solver_spec *spec, int max_order,
                                             taper_error *err)
{
    return set(spec, __func__, "max_order", (double)max_order, err);
}
taper_status taper_solver_spec_set_t_max(taper_solver_spec *spec, double t_max, taper_error *err)
{
    return set(spec, __func__, "t_max", t_max, err);
}
taper_status taper_solver_spec_set_max_steps(taper_solver_spec *spec, long max_steps,
                                             taper_error *err)
{
    return set(spec, __func__, "max_steps", (double)max_steps, err);
}
taper_status taper_solver_spec_set_t_end(taper_solver_spec *spec, double t_end, taper_error *err)
{
    return set(spec, __func__, "t_end", t_end, err);
}

taper_method taper_solver_spec_method(const taper_solver_spec *spec)
{
    return (taper_method)get(spec, "method");
}
double taper_solver_spec_rtol(const taper_solver_spec *spec) { return get(spec, "rtol"); }
double taper_solver_spec_atol(const taper_solver_spec *spec) { return get(spec, "atol"); }
size_t taper_solver_spec_last_granule(const taper_solver_spec *spec)
{
    return (size_t)get(spec, "last_granule");
}
int taper_solver_spec_window(const taper_solver_spec *spec) { return (int)get(spec, "window"); }
int taper_solver_spec_max_order(const taper_solver_spec *spec)
{
    return (int)get(spec, "max_order");
}
double taper_solver_spec_t_max(const taper_solver_spec *spec) { return get(spec, "t_max"); }
long taper_solver_spec_max_steps(const taper_solver_spec *spec)
{
    return (long)get(spec, "max_steps");
}
double taper_solver_spec_t_end(const taper_solver_spec *spec) { return get(spec, "t_end"); }

/* ---- functions, not settings of the table ---------------------------------- */

taper_status taper_solver_spec_set_sampler(taper_solver_spec *spec, double interval,
                                           taper_sample_fn fn, void *user, taper_error *err)
{
    if (!spec) return setting_null_spec(err, __func__);
    if (fn && !(interval > 0.0 && isfinite(interval)))
        return taper_fail_field(err, TAPER_EINVAL, "sample_interval",
                                "sample_interval = %g is out of range (0, inf): a sampling "
                                "interval is finite and > 0", interval);
    spec->sample_fn = fn;
    spec->sample_data = fn ? user : NULL;
    spec->sample_interval = fn ? interval : 0.0;
    spec->sample_times = NULL;
    spec->n_sample_times = 0;
    return taper_ok(err);
}

double taper_solver_spec_sample_interval(const taper_solver_spec *spec)
{
    return spec ? spec->sample_interval : 0.0;
}

taper_status taper_solver_spec_set_sample_times(taper_solver_spec *spec, const double *times,
                                                size_t n, taper_sample_fn fn, void *user,
                                                taper_error *err)
{
    if (!spec) return setting_null_spec(err, __func__);
    if (fn) {
        if (!times || n == 0)
            return taper_fail_field(err, TAPER_EINVAL, "sample_times",
                                    "sample_times: no times given (n = 0 or times NULL)");
        /* Increasing: the run goes forward and serves each time once (a
         * repeated time would ask the integrator for the time it is at). */
        for (size_t j = 0; j < n; j++)
            if (!(isfinite(times[j]) && times[j] >= 0.0) || (j > 0 && !(times[j] > times[j - 1])))
                return taper_fail_field(err, TAPER_EINVAL, "sample_times",
                                        "sample_times[%zu] = %g: the times must be finite, >= 0 "
                                        "and strictly increasing", j, times[j]);
    }
    spec->sample_fn = fn;
    spec->sample_data = fn ? user : NULL;
    spec->sample_interval = 0.0;
    spec->sample_times = fn ? times : NULL;
    spec->n_sample_times = fn ? n : 0;
    return taper_ok(err);
}

const double *taper_solver_spec_sample_times(const taper_solver_spec *spec, size_t *n)
{
    if (n) *n = spec ? spec->n_sample_times : 0;
    return spec ? spec->sample_times : NULL;
}

void taper_solver_spec_set_monitor(taper_solver_spec *spec, taper_monitor_fn monitor, void *user)
{
    if (!spec) return;
    spec->monitor = monitor;
    spec->monitor_data = user;
}

void taper_solver_spec_set_log(taper_solver_spec *spec, taper_log_fn log, void *user)
{
    if (!spec) return;
    spec->log = log;
    spec->log_data = user;
}
