/*
 * analysis.c -- &fit applied to a run (taper_fit over a granule window).
 */
#include "results/analysis.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int model_of(const char *name)
{
    static const char *const names[] = {"power", "exponential", "divergence_b", "divergence_c",
                                        "divergence_m"};
    for (int i = 0; i < 5; i++)
        if (strcmp(names[i], name) == 0) return i; /* = taper_fit_model */
    return -1;
}

/* a -> 0; b, c, m -> 1; p, f -> 2 (the order of taper_fit_result.param). */
static int param_index(const char *report)
{
    if (strcmp(report, "a") == 0) return 0;
    if (strcmp(report, "p") == 0 || strcmp(report, "f") == 0) return 2;
    return 1;
}

static void fit_spec(const scene *sc, int model, taper_fit_spec *spec)
{
    taper_fit_spec_init(spec, model);
    spec->index_begin = (size_t)scene_int(sc, "fit", "k_min") - 1;
    spec->index_end = (size_t)scene_int(sc, "fit", "k_max");
    double p = scene_real(sc, "fit", "p");
    if (!isnan(p)) spec->p = p;
}

void analysis_fit_side(const scene *sc, const series_source *src, int side, analysis_fit *out)
{
    memset(out, 0, sizeof *out);
    out->value = out->error = NAN;
    int model = model_of(scene_str(sc, "fit", "model"));
    double *x = malloc(src->n * sizeof *x), *y = malloc(src->n * sizeof *y);
    if (model < 0 || !x || !y) {
        snprintf(out->message, sizeof out->message, model < 0 ? "no fit" : "out of memory");
        goto done;
    }
    if (series_fill(src, side, scene_str(sc, "fit", "x"), x) != 0 ||
        series_fill(src, side, scene_str(sc, "fit", "y"), y) != 0) {
        snprintf(out->message, sizeof out->message, "no %s", side ? "numerics" : "theory");
        goto done;
    }
    taper_fit_spec spec;
    fit_spec(sc, model, &spec);
    taper_error err = {0};
    if (taper_fit(&spec, x, y, src->n, &out->result, &err) != TAPER_OK) {
        snprintf(out->message, sizeof out->message, "%s", err.message);
        goto done;
    }
    int i = param_index(scene_str(sc, "fit", "report"));
    double factor = scene_real(sc, "fit", "factor");
    out->value = factor * out->result.param[i];
    out->error = fabs(factor) * out->result.param_err[i];
    out->ok = 1;
done:
    free(x);
    free(y);
}

double analysis_closed_theory(const scene *sc, const taper_chain_spec *spec)
{
    const char *t = scene_str(sc, "fit", "theory");
    /* The paper's signed q: forward chains are evaluated at -q (Sec. IV B). */
    double q = spec->profile == TAPER_FORWARD_EXPONENTIAL ? -spec->q : spec->q;
    if (strcmp(t, "rate") == 0) return fabs(taper_asymptotic_lnA(q));
    if (strcmp(t, "f") == 0) return taper_asymptotic_f(q, spec->exponent);
    if (strcmp(t, "b") == 0) return taper_asymptotic_forward_linear_b(spec->s);
    return NAN;
}

const char *analysis_label(const scene *sc)
{
    const char *label = scene_str(sc, "fit", "label");
    return label[0] ? label : scene_str(sc, "fit", "report");
}

void analysis_apply(report *r)
{
    if (!scene_group_active(r->sc, "fit")) return;
    for (size_t i = 0; i < r->n; i++) {
        report_point *pt = &r->points[i];
        analysis_fit_side(r->sc, &pt->src, SERIES_THEORY, &pt->fit[SERIES_THEORY]);
        analysis_fit_side(r->sc, &pt->src, SERIES_NUMERICS, &pt->fit[SERIES_NUMERICS]);
        pt->theory = analysis_closed_theory(r->sc, &pt->spec);
        if (isnan(pt->theory)) pt->theory = pt->fit[SERIES_THEORY].value;
    }
}
