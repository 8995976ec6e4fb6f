/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * table.c -- fits.tsv, table.tsv and the printed table.
 */
#include "results/table.h"

#include "results/output.h"

#include <math.h>
#include <string.h>

/* The paper's value number i, NaN if the scene gives none. */
static double paper(const scene_reals *values, size_t i)
{
    return i < values->n ? values->v[i] : NAN;
}

static void fits_header(const report *r, FILE *fp)
{
    const scene_fit_config *fit = &r->cfg->fit;
    fprintf(fp, "# taper %s fits: &fit model = '%s', y = %s against x = %s, granules %lld..%lld "
            "(0: last)\n", taper_version(), scene_fit_model_name(fit->model),
            scene_quantity_name(fit->y), scene_quantity_name(fit->x), fit->k_min, fit->k_max);
    fprintf(fp, "# param = %s; p0 p1 p2 = the model's parameters in the order of taper.h "
            "((a, b) | (a, b, p) | (a, C, p) | (a, M, f)); value = %s = factor * %s\n",
            r->param_name, analysis_label(r->cfg), scene_fit_report_name(fit->report));
    fputs("param\tside\tvalue\tvalue_stderr\tp0\tp0_stderr\tp1\tp1_stderr\tp2\tp2_stderr\t"
          "n_points\tchi2\n", fp);
}

static void fits_row(double param, const char *side, const analysis_fit *f, FILE *fp)
{
    out_cell(fp, param, 0);
    fprintf(fp, "%s\t", side);
    out_cell(fp, f->value, 0);
    out_cell(fp, f->error, 0);
    for (size_t i = 0; i < 3; i++) {
        int used = f->ok && i < taper_fit_result_n_params(f->result);
        out_cell(fp, used ? taper_fit_result_param(f->result, i) : NAN, 0);
        out_cell(fp, used ? taper_fit_result_param_error(f->result, i) : NAN, 0);
    }
    fprintf(fp, "%zu\t", f->ok ? taper_fit_result_n_points(f->result) : 0);
    out_cell(fp, f->ok ? taper_fit_result_chi2(f->result) : NAN, 1);
}

static int commit(const report *r, const char *name, out_file *f, char **msg)
{
    if (out_commit(f, msg) != 0) return -1;
    printf("! wrote %s/%s\n", r->dir, name);
    return 0;
}

int table_write_fits(const report *r, char **msg)
{
    out_file *f = out_open(r->dir, "fits.tsv", msg);
    if (!f) return -1;
    fits_header(r, f->fp);
    for (size_t i = 0; i < r->n; i++) {
        fits_row(r->points[i].param, "theory", &r->points[i].fit[SERIES_THEORY], f->fp);
        fits_row(r->points[i].param, "numerics", &r->points[i].fit[SERIES_NUMERICS], f->fp);
    }
    return commit(r, "fits.tsv", f, msg);
}

int table_write(const report *r, char **msg)
{
    const scene_config *cfg = r->cfg;
    out_file *f = out_open(r->dir, "table.tsv", msg);
    if (!f) return -1;
    fprintf(f->fp, "# taper %s %s: %s\n", taper_version(), cfg->table.name, cfg->table.caption);
    fprintf(f->fp, "# param = %s; value = %s; theory: &fit theory = '%s'\n", r->param_name,
            analysis_label(cfg), scene_fit_theory_name(cfg->fit.theory));
    fputs("param\ttheory\tnumerics\tnumerics_stderr\tpaper_theory\tpaper_numerics\t"
          "theory_fit\ttheory_fit_stderr\n", f->fp);
    for (size_t i = 0; i < r->n; i++) {
        const report_point *p = &r->points[i];
        double row[] = {p->param, p->theory, p->fit[SERIES_NUMERICS].value,
                        p->fit[SERIES_NUMERICS].error, paper(&cfg->table.paper_theory, i),
                        paper(&cfg->table.paper_numerics, i), p->fit[SERIES_THEORY].value,
                        p->fit[SERIES_THEORY].error};
        for (size_t c = 0; c < 8; c++) out_cell(f->fp, row[c], c == 7);
    }
    return commit(r, "table.tsv", f, msg);
}

/* A number with `digits` decimals, or "-" when it does not exist. */
static void cell(FILE *fp, double x, int digits, int width)
{
    if (isnan(x))
        fprintf(fp, "%*s", width, "-");
    else
        fprintf(fp, "%*.*f", width, digits, x);
}

void table_print(const report *r, FILE *fp)
{
    const scene_config *cfg = r->cfg;
    int d = (int)cfg->table.digits;
    int w = d + 5;
    fprintf(fp, "\n%s: %s\n", cfg->table.name, cfg->table.caption);
    fprintf(fp, "value: %s; theory: '%s'\n", analysis_label(cfg),
            scene_fit_theory_name(cfg->fit.theory));
    fprintf(fp, "%6s | %*s %*s %9s | %*s %*s\n", r->param_name, w, "theory", w, "numerics",
            "stderr", w, "paper th", w, "paper num");
    for (size_t i = 0; i < r->n; i++) {
        const report_point *p = &r->points[i];
        fprintf(fp, "%6g | ", p->param);
        cell(fp, p->theory, d, w);
        fputc(' ', fp);
        cell(fp, p->fit[SERIES_NUMERICS].value, d, w);
        fprintf(fp, " %9.1e | ", p->fit[SERIES_NUMERICS].error);
        cell(fp, paper(&cfg->table.paper_theory, i), d, w);
        fputc(' ', fp);
        cell(fp, paper(&cfg->table.paper_numerics, i), d, w);
        fputc('\n', fp);
    }
}
