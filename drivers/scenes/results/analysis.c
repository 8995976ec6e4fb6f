/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * analysis.c -- &fit applied to a run (taper_fit over a granule window).
 */
#include "results/analysis.h"

#include "util/text.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* a -> 0; b, c, m -> 1; p, f -> 2 (the order of taper_fit_result_param). */
static size_t param_index(scene_fit_report report)
{
    switch (report) {
    case SCENE_REPORT_A: return 0;
    case SCENE_REPORT_P:
    case SCENE_REPORT_F: return 2;
    default: return 1;
    }
}

static void fit_failed(analysis_fit *out, const char *why)
{
    out->message = text_dup(why);
}

void analysis_fit_side(const scene_config *cfg, const series_source *src, int side,
                       analysis_fit *out)
{
    memset(out, 0, sizeof *out);
    out->value = out->error = NAN;
    taper_error err = {0};
    taper_fit_spec *spec = scene_fit_spec(cfg, &err);
    double *x = malloc(src->n * sizeof *x), *y = malloc(src->n * sizeof *y);
    if (!spec || !x || !y) {
        fit_failed(out, !spec ? err.message : "out of memory");
        goto done;
    }
    if (series_fill(src, side, cfg->fit.x, x) != 0 || series_fill(src, side, cfg->fit.y, y) != 0) {
        fit_failed(out, side == SERIES_NUMERICS ? "no numerics" : "no theory");
        goto done;
    }
    if (!(out->result = taper_fit(spec, x, y, src->n, &err))) {
        fit_failed(out, err.message);
        goto done;
    }
    size_t i = param_index(cfg->fit.report);
    double factor = cfg->fit.factor;
    out->value = factor * taper_fit_result_param(out->result, i);
    out->error = fabs(factor) * taper_fit_result_param_error(out->result, i);
    out->ok = 1;
done:
    taper_fit_spec_free(spec);
    free(x);
    free(y);
}

double analysis_closed_theory(const scene_config *cfg, const taper_chain_spec *spec)
{
    /* The paper's signed q: forward chains are evaluated at -q (Sec. IV B). */
    double q = taper_chain_spec_q(spec);
    if (taper_chain_spec_profile(spec) == TAPER_FORWARD_EXPONENTIAL) q = -q;
    switch (cfg->fit.theory) {
    case SCENE_THEORY_RATE: return fabs(taper_asymptotic_lnA(q));
    case SCENE_THEORY_F: return taper_asymptotic_f(q, taper_chain_spec_exponent(spec));
    case SCENE_THEORY_B: return taper_asymptotic_forward_linear_b(taper_chain_spec_s(spec));
    default: return NAN;
    }
}

const char *analysis_label(const scene_config *cfg)
{
    return cfg->fit.label[0] ? cfg->fit.label : scene_fit_report_name(cfg->fit.report);
}

void analysis_apply(report *r)
{
    if (!r->cfg->runs.fit) return;
    for (size_t i = 0; i < r->n; i++) {
        report_point *pt = &r->points[i];
        analysis_fit_side(r->cfg, &pt->src, SERIES_THEORY, &pt->fit[SERIES_THEORY]);
        analysis_fit_side(r->cfg, &pt->src, SERIES_NUMERICS, &pt->fit[SERIES_NUMERICS]);
        pt->theory = analysis_closed_theory(r->cfg, pt->spec);
        if (isnan(pt->theory)) pt->theory = pt->fit[SERIES_THEORY].value;
    }
}

void analysis_free(report *r)
{
    for (size_t i = 0; r->points && i < r->n; i++)
        for (int side = 0; side < 2; side++) {
            taper_fit_result_free(r->points[i].fit[side].result);
            free(r->points[i].fit[side].message);
            r->points[i].fit[side].result = NULL;
            r->points[i].fit[side].message = NULL;
        }
}
