/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * design_report.c -- a design's result files (design_report.h).
 */
#include "optimise/design_report.h"

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

/* "wall_peak_force_right[N]" */
static void objective_column(const design_problem *d, FILE *fp)
{
    fprintf(fp, "%s%s%s%s", d->objective.name, d->unit ? "[" : "", d->unit ? d->unit : "",
            d->unit ? "]" : "");
}

static void setting_columns(const design_problem *d, FILE *fp)
{
    for (size_t i = 0; i < d->space->n; i++) {
        const opt_param *q = &d->space->p[i];
        fprintf(fp, "%s%s%s%s\t", q->name, q->unit ? "[" : "", q->unit ? q->unit : "",
                q->unit ? "]" : "");
    }
}

static int write_design(const design_problem *d, const char *dir, char **msg)
{
    const scene_config *cfg = scene_cfg(d->sc);
    out_file *f = out_open(dir, "design.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    fputs("setting\tvalue\tunit\tstart\tlower\tupper\tat_bound\n", fp);
    fprintf(fp, "# taper %s design of %s\n", taper_version(), scene_path(d->sc));
    fprintf(fp, "# objective: %s ", d->maximise ? "maximise" : "minimise");
    objective_column(d, fp);
    fputs(" = ", fp);
    out_cell(fp, d->best_objective, 1);
    fprintf(fp, "# outcome: %s: %s\n", outcome_word(d->outcome), d->reason ? d->reason : "");
    if (cfg->design.method == SCENE_GRID)
        fprintf(fp, "# method: grid, %lld points per setting from lower to upper\n",
                cfg->design.grid);
    else
        fprintf(fp, "# method: %s (GSL %s) from the best of a grid of %lld points per setting, "
                "tolerance %g, in variables mapped onto the bounds\n",
                cfg->design.method == SCENE_BFGS ? "bfgs" : "nelder_mead",
                cfg->design.method == SCENE_BFGS ? "vector_bfgs2" : "nmsimplex2",
                cfg->design.grid, cfg->design.tolerance);
    if (d->space->hold != SCENE_HOLD_NONE) {
        char held[NUMBER_SIZE];
        number_shortest(held, d->space->hold_target);
        fprintf(fp, "# hold: the chain's %s at %s %s (&material radius scaled at every run)\n",
                d->space->hold == SCENE_HOLD_LENGTH ? "length (sum of diameters)" : "mass",
                held, d->space->hold == SCENE_HOLD_LENGTH ? "m" : "kg");
    }
    fprintf(fp, "# iterations = %zu\n# runs = %zu (the optimiser's, made here)\n"
            "# runs_reused = %zu\n# profile_runs = %zu\n", d->iterations, d->runs, d->reused,
            d->profile_runs);
    fputs("# at_bound: 1 lower, 2 upper, 0 neither (an optimum on a bound is one: the best "
          "within the bounds)\n", fp);
    for (size_t i = 0; i < d->space->n; i++) {
        const opt_param *q = &d->space->p[i];
        fprintf(fp, "%s\t", q->name);
        out_cell(fp, d->best[i], 0);
        fprintf(fp, "%s\t", q->unit ? q->unit : "-");
        out_cell(fp, q->start, 0);
        out_cell(fp, q->lower, 0);
        out_cell(fp, q->upper, 0);
        fprintf(fp, "%d\n", d->at_bound[i]);
    }
    return out_commit(f, msg);
}

static int write_scan(const design_problem *d, const char *dir, char **msg)
{
    out_file *f = out_open(dir, "scan.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    setting_columns(d, fp);
    objective_column(d, fp);
    fputc('\n', fp);
    fprintf(fp, "# taper %s: the optimum at each combination of the integer settings scanned\n",
            taper_version());
    for (size_t c = 0; c < d->n_scan; c++) {
        for (size_t i = 0; i < d->space->n; i++) out_cell(fp, d->scan_values[c * d->space->n + i], 0);
        out_cell(fp, d->scan_objective[c], 1);
    }
    return out_commit(f, msg);
}

static int write_profiles(const design_problem *d, const char *dir, char **msg)
{
    out_file *f = out_open(dir, "profile.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    fputs("setting\tvalue\t", fp);
    objective_column(d, fp);
    fputc('\n', fp);
    fprintf(fp, "# taper %s: the objective along each setting through the optimum (the others "
            "there); one block per setting, two blank lines apart (gnuplot index i); nan: the "
            "run failed\n", taper_version());
    const size_t m = d->profile_points;
    for (size_t i = 0; i < d->space->n; i++) {
        if (i) fputs("\n\n", fp);
        for (size_t k = 0; k < m; k++) {
            fprintf(fp, "%s\t", d->space->p[i].name);
            out_cell(fp, d->profile_value[i * m + k], 0);
            out_cell(fp, d->profile_objective[i * m + k], 1);
        }
    }
    return out_commit(f, msg);
}

static int write_script(const design_problem *d, const char *dir, char **msg)
{
    out_file *f = out_open(dir, "design.gp", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    const size_t p = d->space->n;
    fprintf(fp, "# taper %s: the objective through the optimum along each setting; render: "
            "gnuplot design.gp (in this directory) -> design.png\n", taper_version());
    fprintf(fp, "set terminal pngcairo size %zu,450 enhanced font ',11'\n", 450 * p + 100);
    fputs("set output 'design.png'\nset termoption noenhanced\n", fp);
    char *title = text_printf("%s of %s: %s = %.6g%s%s at the optimum",
                              d->maximise ? "maximising" : "minimising", scene_path(d->sc),
                              d->objective.name, d->best_objective, d->unit ? " " : "",
                              d->unit ? d->unit : "");
    fprintf(fp, "set multiplot layout 1,%zu title ", p);
    plot_gp_string(fp, title ? title : "design");
    free(title);
    fputs("\nset grid\nunset key\n", fp);
    for (size_t i = 0; i < p; i++) {
        const opt_param *q = &d->space->p[i];
        fputs("set xlabel ", fp);
        char *label = text_printf("%s%s%s%s", q->name, q->unit ? " [" : "", q->unit ? q->unit : "",
                                  q->unit ? "]" : "");
        plot_gp_string(fp, label ? label : q->name);
        free(label);
        fprintf(fp, "\nset ylabel '%s%s%s%s'\n", d->objective.name, d->unit ? " [" : "",
                d->unit ? d->unit : "", d->unit ? "]" : "");
        fprintf(fp, "plot 'profile.tsv' index %zu using 2:3 with linespoints pt 7 ps 0.6 lc 1, "
                "'-' using 1:2 with points pt 6 ps 2 lw 2 lc 7\n%.17g %.17g\ne\n", i, d->best[i],
                d->best_objective);
    }
    fputs("unset multiplot\n", fp);
    return out_commit(f, msg);
}

int design_report(const design_problem *d, const char *dir, FILE *out, char **msg)
{
    *msg = NULL;
    if (write_design(d, dir, msg) != 0) return -1;
    fprintf(out, "! wrote %s/design.tsv\n", dir);
    if (d->n_scan > 1) {
        if (write_scan(d, dir, msg) != 0) return -1;
        fprintf(out, "! wrote %s/scan.tsv\n", dir);
    }
    if (!d->profile_points) return 0;
    if (write_profiles(d, dir, msg) != 0 || write_script(d, dir, msg) != 0) return -1;
    fprintf(out, "! wrote %s/profile.tsv and %s/design.gp\n", dir, dir);
    return plot_render_reported(dir, "design.gp", out, msg);
}

void design_print(const design_problem *d, FILE *out)
{
    fprintf(out, "! optimum: %s = %.10g%s%s\n", d->objective.name, d->best_objective,
            d->unit ? " " : "", d->unit ? d->unit : "");
    for (size_t i = 0; i < d->space->n; i++) {
        const opt_param *q = &d->space->p[i];
        fprintf(out, "! %s = %.10g%s%s%s\n", q->name, d->best[i], q->unit ? " " : "",
                q->unit ? q->unit : "",
                d->at_bound[i] == 1 ? "  (at its lower bound)"
                : d->at_bound[i] == 2 ? "  (at its upper bound)" : "");
    }
    fprintf(out, "! %zu iterations, %zu runs (%zu reused)\n", d->iterations, d->runs, d->reused);
}
