/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * granules.c -- granules.tsv (granules.h).
 */
#include "results/granules.h"

#include "results/output.h"
#include "results/pulse.h"
#include "util/number.h"
#include "util/text.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The resolved scene as '#' lines; for a sweep, with this run's value only. */
static void write_scene_comment(const granules_run *r, FILE *fp)
{
    char *text = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&text, &len);
    if (!mem) return;
    scene_write_point(r->sc, mem, r->point);
    fclose(mem);
    for (char *line = text, *end; line && *line; line = end ? end + 1 : NULL) {
        end = strchr(line, '\n');
        fprintf(fp, "# %.*s\n", end ? (int)(end - line) : (int)strlen(line), line);
    }
    free(text);
}

/* A statistic with a dimension: NAME = VALUE, or NAME[UNIT] = VALUE in SI. */
static void write_dimensioned(const granules_run *r, FILE *fp, taper_statistic which,
                              taper_dimension dim)
{
    const scene_config *cfg = &r->at;
    const char *name = taper_statistic_name(which), *unit = scene_unit_suffix(cfg, dim);
    double x = taper_sim_statistic(r->sim, which) * scene_unit(cfg, dim);
    if (!name) return;
    fprintf(fp, "# %s%s%s%s = ", name, unit ? "[" : "", unit ? unit : "", unit ? "]" : "");
    char num[NUMBER_SIZE];
    number_shortest(num, x);
    fprintf(fp, "%s\n", num);
}

/* The statistics of the run, by name, in the order of taper_statistic:
 * counts as integers, the time to every digit, errors to four; then the
 * energy budget (every run has one; with a piston its work, which the
 * budget adds up to), and the peak force, its time and the impulse of each
 * wall the chain has (a free end has none: no line; a piston's are the left
 * wall's). */
static void write_stats_comment(const granules_run *r, const out_columns *cols, FILE *fp)
{
    if (!r->sim) {
        fputs("# numerics = .false.: theory only, no dynamics\n", fp);
        return;
    }
    for (int i = 0; i <= TAPER_STAT_COMPLETE; i++) {
        taper_statistic which = (taper_statistic)i;
        double x = taper_sim_statistic(r->sim, which);
        const char *name = taper_statistic_name(which);
        switch (which) {
        case TAPER_STAT_COMPLETE: break; /* the first comment line says it */
        case TAPER_STAT_MAX_WINDOW:
        case TAPER_STAT_GRANULE_REACHED: fprintf(fp, "# %s = %zu\n", name, (size_t)x); break;
        case TAPER_STAT_T_FINAL:
            write_dimensioned(r, fp, which, taper_statistic_dimension(which));
            break;
        case TAPER_STAT_ENERGY_ERROR:
        case TAPER_STAT_MOMENTUM_ERROR: fprintf(fp, "# %s = %.3e\n", name, x); break;
        default: fprintf(fp, "# %s = %ld\n", name, (long)x); break;
        }
    }
    for (int i = TAPER_STAT_ENERGY_INITIAL; i <= TAPER_STAT_ENERGY_IN_CHAIN; i++)
        write_dimensioned(r, fp, (taper_statistic)i, taper_statistic_dimension((taper_statistic)i));
    /* The pulse's speed from the columns as written (pulse.h): in SI m/s. */
    const char *speed_unit = scene_unit_suffix(&r->at, TAPER_DIM_VELOCITY);
    char speed[NUMBER_SIZE];
    number_shortest(speed, pulse_speed(cols->col[4 + TAPER_X_PASS], cols->col[4 + TAPER_T_PASS],
                                       NULL, cols->n));
    fprintf(fp, "# %s%s%s%s = %s\n", PULSE_SPEED_NAME, speed_unit ? "[" : "",
            speed_unit ? speed_unit : "", speed_unit ? "]" : "", speed);
    /* A piston: the budget adds up to its work, E(0) = 0 (the energy error
     * above is relative to it); its force is the left wall's. */
    const int piston = taper_chain_piston_duration(r->chain) > 0.0;
    if (piston) {
        const char *unit = scene_unit_suffix(&r->at, TAPER_DIM_ENERGY);
        char num[NUMBER_SIZE];
        number_shortest(num, taper_sim_piston_work(r->sim) * scene_unit(&r->at, TAPER_DIM_ENERGY));
        fprintf(fp, "# piston_work%s%s%s = %s\n", unit ? "[" : "", unit ? unit : "",
                unit ? "]" : "", num);
    }
    static const taper_statistic wall_stats[TAPER_N_ENDS][3] = {
        {TAPER_STAT_WALL_PEAK_FORCE_LEFT, TAPER_STAT_WALL_PEAK_TIME_LEFT,
         TAPER_STAT_WALL_IMPULSE_LEFT},
        {TAPER_STAT_WALL_PEAK_FORCE_RIGHT, TAPER_STAT_WALL_PEAK_TIME_RIGHT,
         TAPER_STAT_WALL_IMPULSE_RIGHT}};
    int said = 0;
    for (int e = 0; e < TAPER_N_ENDS; e++) {
        if (taper_chain_end(r->chain, (taper_end)e) != TAPER_END_WALL && !(piston && e == TAPER_LEFT))
            continue;
        if (!said++)
            fputs("# wall_*: over the run, [0, t_final], which goes on until the right wall's "
                  "first contact has opened (and to t_end if later): its peak and impulse are "
                  "the whole contact's\n", fp);
        for (int j = 0; j < 3; j++)
            write_dimensioned(r, fp, wall_stats[e][j], taper_statistic_dimension(wall_stats[e][j]));
    }
}

/* In SI (&output units = 'si'): the SI value of each rescaled unit, so that
 * a reader can go back (rescaled = SI / unit). */
static void write_units_comment(const granules_run *r, FILE *fp)
{
    const scene_config *cfg = &r->at;
    if (!scene_unit_suffix(cfg, TAPER_DIM_LENGTH)) return;
    fputs("# units: SI (&output units = 'si'); one rescaled unit (eq. (5) of arXiv:0905.4512) "
          "is:\n", fp);
    /* The dimensions of results (length to impulse); the others are those
     * of inputs (sizes, densities, compliances, drag). */
    char num[NUMBER_SIZE];
    for (int d = 0; d <= TAPER_DIM_IMPULSE; d++) {
        number_shortest(num, scene_unit(cfg, (taper_dimension)d));
        fprintf(fp, "# unit_%s = %s %s\n", taper_dimension_name((taper_dimension)d), num,
                taper_dimension_unit((taper_dimension)d));
    }
    number_shortest(num, cfg->material.radius);
    fprintf(fp, "# unit_radius = %s m: the sizes R and X0 are in units of R_1 (eq. (5): "
            "R'_k = R'_1 R_k), displacements in unit_length = R_1 alpha^(1/n); X_pass = X0 + "
            "x_k is X0 unit_radius + x_k unit_length\n", num);
}

_Static_assert(OUT_N_COLUMNS == SCENE_N_COLUMNS, "granules.tsv columns");

/* The columns of a run; in SI, converted copies (owned[c], freed by
 * free_columns) and each column's unit. */
static int run_columns(const granules_run *r, out_columns *cols, double *owned[OUT_N_COLUMNS])
{
    const scene_output_config *o = &scene_cfg(r->sc)->output;
    memset(cols, 0, sizeof *cols);
    cols->n = taper_chain_size(r->chain);
    cols->set = o->column_set;
    cols->every = (size_t)o->every;
    cols->col[1] = taper_chain_radius(r->chain);
    cols->col[2] = taper_chain_mass(r->chain);
    cols->col[3] = taper_chain_rest_position(r->chain);
    if (r->sim)
        for (int o = 0; o < TAPER_N_OBSERVABLES; o++)
            cols->col[4 + o] = taper_sim_observable(r->sim, (taper_observable)o);
    cols->col[9] = r->theory[TAPER_THEORY_V];
    cols->col[10] = r->theory[TAPER_THEORY_T_RES];
    cols->col[11] = r->theory[TAPER_THEORY_T];
    for (int c = 0; c < OUT_N_COLUMNS; c++) owned[c] = NULL;
    if (!scene_unit_suffix(&r->at, TAPER_DIM_LENGTH)) return 0;
    for (int c = 1; c < OUT_N_COLUMNS; c++) {
        cols->unit[c] = scene_unit_suffix(&r->at, scene_column_dimension((scene_column)c));
        if (!cols->col[c]) continue;
        if (!(owned[c] = malloc(cols->n * sizeof(double)))) return -1;
        memcpy(owned[c], cols->col[c], cols->n * sizeof(double));
        scene_column_convert(&r->at, (scene_column)c, owned[c], cols->col[3], cols->n);
    }
    for (int c = 1; c < OUT_N_COLUMNS; c++)
        if (owned[c]) cols->col[c] = owned[c];
    return 0;
}

static void free_columns(double *owned[OUT_N_COLUMNS])
{
    for (int c = 0; c < OUT_N_COLUMNS; c++) free(owned[c]);
}

/* The column names first, as a line of their own, then the '#' block,
 * then the rows: numpy.genfromtxt(names=True) and pandas.read_csv(sep='\t',
 * comment='#') take their names from the first line, numpy.loadtxt skips
 * exactly one line (skiprows=1) and every comment, gnuplot reads the names
 * with `set datafile columnheaders` (or skips the line as non-numeric). */
static int write_granules(const granules_run *r, out_file *f, int partial)
{
    FILE *fp = f->fp;
    out_columns cols;
    double *owned[OUT_N_COLUMNS];
    if (run_columns(r, &cols, owned) != 0) {
        free_columns(owned);
        return -1;
    }
    out_write_header(fp, &cols, NULL);
    fprintf(fp, "# taper %s granules: per-granule pulse observables and binary-collision theory\n",
            taper_version());
    if (partial)
        fprintf(fp, "# PARTIAL result (%s): %s\n", taper_strerror(r->status), r->message);
    else
        fputs("# complete\n", fp);
    if (r->untrusted) fprintf(fp, "# UNTRUSTED: %s\n", r->untrusted);
    fprintf(fp, "# scene file: %s\n", scene_path(r->sc));
    if (r->theory_note)
        fprintf(fp, "# theory: nan: %s (the binary-collision theory of arXiv:0905.4512 does not "
                "describe this chain)\n", r->theory_note);
    write_units_comment(r, fp);
    write_scene_comment(r, fp);
    write_stats_comment(r, &cols, fp);
    out_write_rows(f, &cols, NULL, 0);
    free_columns(owned);
    return 0;
}

int granules_save(const char *dir, const granules_run *run, int partial, char **msg)
{
    const char *name = partial ? "granules.partial.tsv" : "granules.tsv";
    const char *stale = partial ? "granules.tsv" : "granules.partial.tsv";
    if (out_remove(dir, stale, msg) != 0) return -1;
    out_file *f = out_open(dir, name, msg);
    if (!f) return -1;
    if (write_granules(run, f, partial) != 0) {
        out_discard(f);
        *msg = text_printf("%s/%s: out of memory", dir, name);
        return -1;
    }
    return out_commit(f, msg);
}
