/*
 * granules.c -- granules.tsv and sweep.tsv (granules.h).
 */
#include "results/granules.h"

#include "results/output.h"

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

/* The statistics of the run, by name, in the order of taper_statistic:
 * counts as integers, the time to every digit, errors to four. */
static void write_stats_comment(const granules_run *r, FILE *fp)
{
    if (!r->sim) {
        fputs("# numerics = .false.: theory only, no dynamics\n", fp);
        return;
    }
    for (int i = 0; i < TAPER_N_STATISTICS; i++) {
        taper_statistic which = (taper_statistic)i;
        double x = taper_sim_statistic(r->sim, which);
        const char *name = taper_statistic_name(which);
        switch (which) {
        case TAPER_STAT_COMPLETE: break; /* the first comment line says it */
        case TAPER_STAT_MAX_WINDOW:
        case TAPER_STAT_GRANULE_REACHED: fprintf(fp, "# %s = %zu\n", name, (size_t)x); break;
        case TAPER_STAT_T_FINAL: fprintf(fp, "# %s = %.17g\n", name, x); break;
        case TAPER_STAT_ENERGY_ERROR:
        case TAPER_STAT_MOMENTUM_ERROR: fprintf(fp, "# %s = %.3e\n", name, x); break;
        default: fprintf(fp, "# %s = %ld\n", name, (long)x); break;
        }
    }
}

_Static_assert(OUT_N_COLUMNS == SCENE_N_COLUMNS, "granules.tsv columns");

static void run_columns(const granules_run *r, out_columns *cols)
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
}

/* The column names first, as a line of their own, then the '#' block,
 * then the rows: numpy.genfromtxt(names=True) and pandas.read_csv(sep='\t',
 * comment='#') take their names from the first line, numpy.loadtxt skips
 * exactly one line (skiprows=1) and every comment, gnuplot reads the names
 * with `set datafile columnheaders` (or skips the line as non-numeric). */
static void write_granules(const granules_run *r, FILE *fp, int partial)
{
    out_columns cols;
    run_columns(r, &cols);
    out_write_header(fp, &cols, NULL);
    fprintf(fp, "# taper %s granules: per-granule pulse observables and binary-collision theory\n",
            taper_version());
    if (partial)
        fprintf(fp, "# PARTIAL result (%s): %s\n", taper_strerror(r->status), r->message);
    else
        fputs("# complete\n", fp);
    if (r->untrusted) fprintf(fp, "# UNTRUSTED: %s\n", r->untrusted);
    fprintf(fp, "# scene file: %s\n", scene_path(r->sc));
    write_scene_comment(r, fp);
    write_stats_comment(r, fp);
    out_write_rows(fp, &cols, NULL, 0);
}

int granules_save(const char *dir, const granules_run *run, int partial, char **msg)
{
    const char *name = partial ? "granules.partial.tsv" : "granules.tsv";
    const char *stale = partial ? "granules.tsv" : "granules.partial.tsv";
    if (out_remove(dir, stale, msg) != 0) return -1;
    out_file *f = out_open(dir, name, msg);
    if (!f) return -1;
    write_granules(run, f->fp, partial);
    return out_commit(f, msg);
}

int granules_write(const char *dir, const granules_run *run, int partial, char **msg)
{
    if (granules_save(dir, run, partial, msg) != 0) return -1;
    printf("! wrote %s/%s\n", dir, partial ? "granules.partial.tsv" : "granules.tsv");
    return 0;
}

int granules_write_sweep(const char *dir, const granules_run *runs, size_t n, const char *name,
                         const double *values, char **msg)
{
    out_file *f = out_open(dir, "sweep.tsv", msg);
    if (!f) return -1;
    for (size_t i = 0; i < n; i++) {
        out_columns cols;
        run_columns(&runs[i], &cols);
        if (i == 0) {
            out_write_header(f->fp, &cols, name);
            fprintf(f->fp, "# taper %s sweep over %s: the rows of every %s=VALUE/granules.tsv\n",
                    taper_version(), name, name);
        }
        out_write_rows(f->fp, &cols, name, values[i]);
    }
    if (out_commit(f, msg) != 0) return -1;
    printf("! wrote %s/sweep.tsv\n", dir);
    return 0;
}
