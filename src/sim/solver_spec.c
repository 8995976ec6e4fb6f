/*
 * solver_spec.c -- the settings of a run (taper_solver_spec): defaults,
 * setters that check each value against its range in taper.h, getters,
 * and the names of the methods.  What depends on the chain or on the
 * method (last_granule <= N, max_order per method) is checked by
 * taper_sim_alloc, which sees both.
 */
#include "solver_spec.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <strings.h>

void taper_solver_spec_defaults(struct taper_solver_spec *spec)
{
    *spec = (struct taper_solver_spec){0};
    spec->method = TAPER_ADAMS;
    /* Measured (docs/benchmarks.md, "Results (full run)", session 6: the
     * work-precision study at 87c02f3): with atol relative to each
     * granule's binary-collision scale, t_pass and v_peak stay within 3.8e-9
     * and 2.1e-8 of the reference on the five benchmark chains up to
     * N = 1000 (the largest: backward exponential q = 0.05, N = 200): a
     * 2.6x / 4.7x margin on the 1e-8 / 1e-7 targets.  (At order 6, commit
     * d28163c: 1.2e-9 and 6.7e-9.) */
    spec->rtol = 1e-10;
    spec->atol = 1e-13;
    spec->last_granule = 0;
    spec->window = 1;
}

int taper_method_max_order(taper_method method)
{
    return method == TAPER_BDF ? TAPER_MAX_ORDER_BDF : TAPER_MAX_ORDER_ADAMS;
}

/* ---- names ---------------------------------------------------------------- */
static const char *const method_names[TAPER_N_METHODS] = {
    [TAPER_ADAMS] = "adams",
    [TAPER_BDF] = "bdf",
};

const char *taper_method_name(taper_method method)
{
    if ((int)method < 0 || (int)method >= TAPER_N_METHODS) return NULL;
    return method_names[method];
}

taper_status taper_method_from_name(const char *name, taper_method *method, taper_error *err)
{
    if (!name || !method)
        return taper_fail_field(err, TAPER_EINVAL, "method", "taper_method_from_name: %s is NULL",
                                name ? "method" : "name");
    for (int i = 0; i < TAPER_N_METHODS; i++)
        if (strcasecmp(name, method_names[i]) == 0) {
            *method = (taper_method)i;
            return taper_ok(err);
        }
    return taper_fail_field(err, TAPER_EINVAL, "method", "unknown method '%s': use 'adams' or 'bdf'",
                            name);
}

/* ---- the object ----------------------------------------------------------- */
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

static taper_status no_spec(taper_error *err, const char *field)
{
    return taper_fail_field(err, TAPER_EINVAL, field, "taper_solver_spec_set_%s: spec is NULL", field);
}

/* ---- setters: each value against its range in taper.h --------------------- */
taper_status taper_solver_spec_set_method(taper_solver_spec *spec, taper_method method,
                                          taper_error *err)
{
    if (!spec) return no_spec(err, "method");
    if (!taper_method_name(method))
        return taper_fail_field(err, TAPER_EINVAL, "method",
                                "method = %d: use TAPER_ADAMS or TAPER_BDF", (int)method);
    spec->method = method;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_rtol(taper_solver_spec *spec, double rtol, taper_error *err)
{
    if (!spec) return no_spec(err, "rtol");
    if (!(rtol >= TAPER_RTOL_MIN && rtol <= TAPER_RTOL_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "rtol",
                                "rtol = %g: must lie in [%g, %g] (double precision resolves no "
                                "tighter tolerance)", rtol, TAPER_RTOL_MIN, TAPER_RTOL_MAX);
    spec->rtol = rtol;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_atol(taper_solver_spec *spec, double atol, taper_error *err)
{
    if (!spec) return no_spec(err, "atol");
    if (!(atol > 0.0 && atol <= TAPER_ATOL_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "atol", "atol = %g: must lie in (0, %g]", atol,
                                TAPER_ATOL_MAX);
    spec->atol = atol;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_last_granule(taper_solver_spec *spec, size_t last_granule,
                                                taper_error *err)
{
    if (!spec) return no_spec(err, "last_granule");
    if (last_granule > TAPER_N_GRANULES_MAX)
        return taper_fail_field(err, TAPER_EINVAL, "last_granule",
                                "last_granule = %zu: no chain has more than %d granules "
                                "(0: the whole chain)", last_granule, TAPER_N_GRANULES_MAX);
    spec->last_granule = last_granule;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_window(taper_solver_spec *spec, int window, taper_error *err)
{
    if (!spec) return no_spec(err, "window");
    spec->window = window != 0;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_max_order(taper_solver_spec *spec, int max_order,
                                             taper_error *err)
{
    if (!spec) return no_spec(err, "max_order");
    if (max_order < 0 || max_order > TAPER_MAX_ORDER_ADAMS)
        return taper_fail_field(err, TAPER_EINVAL, "max_order",
                                "max_order = %d: CVODE allows 1..%d (Adams), 1..%d (BDF); "
                                "0: the default", max_order, TAPER_MAX_ORDER_ADAMS,
                                TAPER_MAX_ORDER_BDF);
    spec->max_order = max_order;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_t_max(taper_solver_spec *spec, double t_max, taper_error *err)
{
    if (!spec) return no_spec(err, "t_max");
    if (!(t_max >= 0.0 && t_max <= DBL_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "t_max",
                                "t_max = %g: must be finite and >= 0 (0: no limit)", t_max);
    spec->t_max = t_max;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_max_steps(taper_solver_spec *spec, long max_steps,
                                             taper_error *err)
{
    if (!spec) return no_spec(err, "max_steps");
    if (max_steps < 0)
        return taper_fail_field(err, TAPER_EINVAL, "max_steps",
                                "max_steps = %ld: must be >= 0 (0: no limit)", max_steps);
    spec->max_steps = max_steps;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_t_end(taper_solver_spec *spec, double t_end, taper_error *err)
{
    if (!spec) return no_spec(err, "t_end");
    if (!(t_end >= 0.0 && t_end <= DBL_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "t_end",
                                "t_end = %g: must be finite and >= 0 (0: end once the "
                                "observables are known)", t_end);
    spec->t_end = t_end;
    return taper_ok(err);
}

taper_status taper_solver_spec_set_sampler(taper_solver_spec *spec, double interval,
                                           taper_sample_fn fn, void *user, taper_error *err)
{
    if (!spec) return no_spec(err, "sample_interval");
    if (fn && !(interval > 0.0 && interval <= DBL_MAX))
        return taper_fail_field(err, TAPER_EINVAL, "sample_interval",
                                "sample_interval = %g: must be finite and > 0", interval);
    spec->sample_fn = fn;
    spec->sample_data = fn ? user : NULL;
    spec->sample_interval = fn ? interval : 0.0;
    return taper_ok(err);
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

/* ---- getters (a NULL spec reads as the defaults) --------------------------- */
static const taper_solver_spec *or_defaults(const taper_solver_spec *spec,
                                            taper_solver_spec *defaults)
{
    if (spec) return spec;
    taper_solver_spec_defaults(defaults);
    return defaults;
}

taper_method taper_solver_spec_method(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->method;
}

double taper_solver_spec_rtol(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->rtol;
}

double taper_solver_spec_atol(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->atol;
}

size_t taper_solver_spec_last_granule(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->last_granule;
}

int taper_solver_spec_window(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->window;
}

int taper_solver_spec_max_order(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->max_order;
}

double taper_solver_spec_t_max(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->t_max;
}

long taper_solver_spec_max_steps(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->max_steps;
}

double taper_solver_spec_t_end(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->t_end;
}

double taper_solver_spec_sample_interval(const taper_solver_spec *spec)
{
    taper_solver_spec d;
    return or_defaults(spec, &d)->sample_interval;
}
