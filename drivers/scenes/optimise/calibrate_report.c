/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * calibrate_report.c -- a calibration's result files (calibrate_report.h).
 */
#include "optimise/calibrate_report.h"

#include "results/output.h"
#include "results/plot.h"
#include "util/number.h"
#include "util/text.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *outcome_word(opt_outcome o)
{
    switch (o) {
    case OPT_CONVERGED: return "converged";
    case OPT_NOT_CONVERGED: return "NOT CONVERGED";
    case OPT_INTERRUPTED: return "INTERRUPTED";
    case OPT_FAILED: return "FAILED";
    }
    return "?";
}

static void cell(FILE *fp, double x, int last) { out_cell(fp, x, last); }

static void header_comments(const calibration *c, FILE *fp)
{
    const measurements *m = c->data;
    fprintf(fp, "# taper %s calibration of %s to %s\n", taper_version(), scene_path(c->sc),
            c->data_path);
    fprintf(fp, "# outcome: %s: %s\n", outcome_word(c->outcome), c->reason ? c->reason : "");
    fputs("# chi2 = ", fp);
    cell(fp, c->chi2, 1);
    fprintf(fp, "# dof = %zu\n# chi2_per_dof = ", c->dof);
    cell(fp, c->dof ? c->chi2 / (double)c->dof : NAN, 1);
    if (c->absolute)
        fputs("# errors: absolute, from &calibrate noise (chi2_per_dof near 1 says the noise "
              "and the model are right)\n", fp);
    else
        fputs("# errors: scaled by sqrt(chi2_per_dof): the noise estimated from the residuals, "
              "each relative to its column's peak\n", fp);
    fprintf(fp, "# measurements = %zu (", m->n);
    for (size_t i = 0; i < m->n_quantities; i++)
        fprintf(fp, "%s%s", i ? ", " : "", meas_quantity_name(m->quantity[i]));
    fprintf(fp, "; %s units)\n", m->si ? "SI" : "rescaled");
    fprintf(fp, "# iterations = %zu\n# runs = %zu\n# runs_reused = %zu\n", c->iterations, c->runs,
            c->reused);
    fprintf(fp, "# jacobian: forward differences, each setting stepped by %.3g of its size "
            "(sqrt of &solver rtol = %g), the runs in parallel\n", c->jacobian_step, c->rtol);
    fputs("# at_bound: 1 lower, 2 upper, 0 neither; corr_NAME: the correlation with NAME\n", fp);
}

static int write_table(const calibration *c, const char *dir, char **msg)
{
    out_file *f = out_open(dir, "calibration.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    const opt_space *s = c->space;
    fputs("setting\tvalue\terror\tunit\tstart\tlower\tupper\tat_bound", fp);
    for (size_t i = 0; i < s->n; i++) fprintf(fp, "\tcorr_%s", s->p[i].name);
    fputc('\n', fp);
    header_comments(c, fp);
    for (size_t i = 0; i < s->n; i++) {
        const opt_param *p = &s->p[i];
        fprintf(fp, "%s\t", p->name);
        cell(fp, c->value[i], 0);
        cell(fp, c->error[i], 0);
        fprintf(fp, "%s\t", p->unit ? p->unit : "-");
        cell(fp, p->start, 0);
        cell(fp, p->lower, 0);
        cell(fp, p->upper, 0);
        fprintf(fp, "%d", c->at_bound[i]);
        for (size_t k = 0; k < s->n; k++) {
            fputc('\t', fp);
            char num[NUMBER_SIZE];
            number_shortest(num, c->correlation[i * s->n + k]);
            fputs(num, fp);
        }
        fputc('\n', fp);
    }
    return out_commit(f, msg);
}

/* The points in signals: quantity, then granule, then time. */
static const calibration *sorting;
static int by_signal(const void *a, const void *b)
{
    const meas_point *p = &sorting->data->points[*(const size_t *)a];
    const meas_point *q = &sorting->data->points[*(const size_t *)b];
    if (p->q != q->q) return p->q < q->q ? -1 : 1;
    if (sorting->data->form == MEAS_GRANULES) return p->granule < q->granule ? -1 : p->granule > q->granule;
    if (p->granule != q->granule) return p->granule < q->granule ? -1 : 1;
    if (p->t != q->t) return p->t < q->t ? -1 : 1;
    return p->line < q->line ? -1 : p->line > q->line;
}

/* The order of the points by signal, and the number of signals. */
static size_t *signal_order(const calibration *c, size_t *n_signals)
{
    size_t n = c->data->n;
    size_t *order = malloc(n * sizeof *order);
    if (!order) return NULL;
    for (size_t i = 0; i < n; i++) order[i] = i;
    sorting = c; /* qsort has no context argument; the writer is single-threaded */
    qsort(order, n, sizeof *order, by_signal);
    *n_signals = 0;
    for (size_t i = 0; i < n; i++) {
        const meas_point *p = &c->data->points[order[i]];
        const meas_point *q = i ? &c->data->points[order[i - 1]] : NULL;
        int granule_signal = c->data->form != MEAS_GRANULES;
        if (!q || q->q != p->q || (granule_signal && q->granule != p->granule)) ++*n_signals;
    }
    return order;
}

static int write_residuals(const calibration *c, const char *dir, const size_t *order, char **msg)
{
    out_file *f = out_open(dir, "residuals.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    const measurements *m = c->data;
    fprintf(fp, "line\tt%s\tgranule\tquantity\tunit\tmeasured\tfitted\tresidual\tnormalised\n",
            m->si ? "[s]" : "");
    fprintf(fp, "# taper %s: the measurements of %s and the calibrated run at them\n",
            taper_version(), c->data_path);
    fputs("# line: of the data file; residual = fitted - measured; normalised: times its "
          "weight (its sum of squares is chi2)\n", fp);
    fputs("# one block per signal (quantity and granule; a per-granule table: one per "
          "quantity), two blank lines apart: gnuplot index i\n", fp);
    for (size_t o = 0; o < m->n; o++) {
        size_t i = order[o];
        const meas_point *p = &m->points[i];
        if (o) {
            const meas_point *q = &m->points[order[o - 1]];
            if (q->q != p->q || (m->form != MEAS_GRANULES && q->granule != p->granule))
                fputs("\n\n", fp);
        }
        const char *unit = m->si ? taper_dimension_unit(meas_quantity_dimension(p->q)) : "-";
        fprintf(fp, "%d\t", p->line);
        cell(fp, p->t, 0);
        fprintf(fp, "%zu\t%s\t%s\t", p->granule, meas_quantity_name(p->q), unit);
        double fitted = c->fitted ? c->fitted[i] : NAN;
        cell(fp, p->value, 0);
        cell(fp, fitted, 0);
        cell(fp, fitted - p->value, 0);
        cell(fp, c->w[i] * (fitted - p->value), 1);
    }
    return out_commit(f, msg);
}

static int write_script(const calibration *c, const char *dir, const size_t *order,
                        size_t n_signals, char **msg)
{
    out_file *f = out_open(dir, "calibration.gp", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    const measurements *m = c->data;
    const int per_granule = m->form == MEAS_GRANULES;
    fprintf(fp, "# taper %s: measured and fitted signals; render: gnuplot calibration.gp (in "
            "this directory) -> calibration.png\n", taper_version());
    fprintf(fp, "set terminal pngcairo size 900,%zu enhanced font ',11'\n",
            (size_t)(300 * m->n_quantities + 100));
    fputs("set output 'calibration.png'\nset termoption noenhanced\n", fp);
    fprintf(fp, "set multiplot layout %zu,1 title ", m->n_quantities);
    char *title = NULL;
    size_t len = 0;
    FILE *t = open_memstream(&title, &len);
    if (t) {
        fprintf(t, "calibration of %s:", scene_path(c->sc));
        for (size_t i = 0; i < c->space->n; i++)
            fprintf(t, "%s %s = %.6g%s%s", i ? "," : "", c->space->p[i].name, c->value[i],
                    c->space->p[i].unit ? " " : "", c->space->p[i].unit ? c->space->p[i].unit : "");
        fclose(t);
    }
    plot_gp_string(fp, title ? title : "calibration");
    free(title);
    fputs("\nset key outside right top\nset grid\n", fp);
    /* one panel per quantity, in the order of the blocks (signal_order:
     * by quantity), its signals' blocks */
    size_t block = 0;
    size_t o = 0;
    for (int qi = 0; qi < MEAS_N_QUANTITIES; qi++) {
        meas_quantity q = (meas_quantity)qi;
        int fitted = 0;
        for (size_t k = 0; k < m->n_quantities; k++) fitted |= m->quantity[k] == q;
        if (!fitted) continue;
        const char *unit = m->si ? taper_dimension_unit(meas_quantity_dimension(q)) : NULL;
        fprintf(fp, "set xlabel '%s'\n", per_granule ? "granule k"
                                                     : m->si ? "t [s]" : "t [rescaled, eq. (5)]");
        fprintf(fp, "set ylabel '%s%s%s%s'\n", meas_quantity_name(q), unit ? " [" : "",
                unit ? unit : "", unit ? "]" : "");
        fputs("plot ", fp);
        int first = 1;
        /* the blocks of this quantity, in the file's order of signals */
        for (; o < m->n; o++) {
            const meas_point *p = &m->points[order[o]];
            if (p->q != q) break;
            int starts = o == 0 || m->points[order[o - 1]].q != p->q ||
                         (!per_granule && m->points[order[o - 1]].granule != p->granule);
            if (!starts) continue;
            char name[64];
            if (per_granule) snprintf(name, sizeof name, "%s", meas_quantity_name(q));
            else if (p->q == MEAS_WALL_LEFT || p->q == MEAS_WALL_RIGHT)
                snprintf(name, sizeof name, "%s", meas_quantity_name(q));
            else snprintf(name, sizeof name, "granule %zu", p->granule);
            int x = per_granule ? 3 : 2;
            fprintf(fp, "%s'residuals.tsv' index %zu using %d:6 with points pt 7 ps 0.5 lc %zu "
                    "title '%s measured', '' index %zu using %d:7 with lines lw 2 lc %zu title "
                    "'fitted'", first ? "" : ", \\\n     ", block, x, block % 8 + 1, name, block,
                    x, block % 8 + 1);
            first = 0;
            block++;
        }
        fputc('\n', fp);
    }
    fputs("unset multiplot\n", fp);
    (void)n_signals;
    return out_commit(f, msg);
}

int calibration_report(const calibration *c, const char *dir, FILE *out, char **msg)
{
    *msg = NULL;
    if (write_table(c, dir, msg) != 0) return -1;
    fprintf(out, "! wrote %s/calibration.tsv\n", dir);
    size_t n_signals = 0;
    size_t *order = signal_order(c, &n_signals);
    if (!order) {
        *msg = text_printf("out of memory");
        return -1;
    }
    int rc = write_residuals(c, dir, order, msg);
    if (rc == 0) rc = write_script(c, dir, order, n_signals, msg);
    free(order);
    if (rc != 0) return -1;
    fprintf(out, "! wrote %s/residuals.tsv and %s/calibration.gp\n", dir, dir);
    return plot_render_reported(dir, "calibration.gp", out, msg);
}

void calibration_print(const calibration *c, FILE *out)
{
    for (size_t i = 0; i < c->space->n; i++) {
        const opt_param *p = &c->space->p[i];
        fprintf(out, "! %s = %.10g +- %.3g%s%s", p->name, c->value[i], c->error[i],
                p->unit ? " " : "", p->unit ? p->unit : "");
        if (c->value[i] != 0 && isfinite(c->error[i]))
            fprintf(out, " (%.2g %%)", 100 * c->error[i] / fabs(c->value[i]));
        fputs(c->at_bound[i] ? "  AT ITS BOUND\n" : "\n", out);
    }
    fprintf(out, "! chi2 = %.6g, dof = %zu, chi2/dof = %.6g; %zu iterations, %zu runs (%zu "
            "reused)\n", c->chi2, c->dof, c->dof ? c->chi2 / (double)c->dof : NAN, c->iterations,
            c->runs, c->reused);
}
