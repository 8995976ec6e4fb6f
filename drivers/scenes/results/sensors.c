/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensors.c -- time series of a run: recording in the sampler, the files
 * after it (sensors.h).
 */
#include "results/sensors.h"

#include "util/number.h"

#include "results/output.h"
#include "results/plot.h"
#include "util/text.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A growing array of doubles. */
typedef struct grow {
    double *v;
    size_t n, cap;
} grow;

static int push(grow *g, double x)
{
    if (g->n == g->cap) {
        size_t cap = g->cap ? 2 * g->cap : 1024;
        double *v = realloc(g->v, cap * sizeof *v);
        if (!v) return -1;
        g->v = v;
        g->cap = cap;
    }
    g->v[g->n++] = x;
    return 0;
}

struct sensors {
    scene_config at;        /* the run's configuration (units)                */
    size_t n;               /* granules in the chain                           */
    double interval;
    size_t *granule;        /* the sensors' granules                           */
    size_t n_granule;
    int wall[TAPER_N_ENDS]; /* 1: that end is a wall                           */
    int series;             /* sensors or walls: a row per sample              */
    grow t;                 /* sample times (series)                           */
    grow rec;               /* per sample: x, v, f_left, f_right per sensor,
                               then the left and right wall forces             */
    int spacetime;
    size_t st_stride;       /* granules 1, 1 + st_stride, ...                  */
    size_t st_cols;
    size_t st_cap;          /* rows kept at most                               */
    size_t st_every;        /* samples a row stands for                        */
    grow st_t, st_v;        /* rows: time, and v of st_cols granules           */
    double *pending;        /* the row being gathered (st_cols values)         */
    double pending_t;       /* its first sample's time                         */
    size_t pending_n;       /* samples gathered into it                        */
    size_t n_samples;
    double *x, *v, *f;      /* scratch: N, N, N + 1                            */
    int failed;             /* recording stopped: out of memory                */
    char why[sizeof(((taper_error *)0)->message)];
};

void sensors_free(sensors *s)
{
    if (!s) return;
    free(s->granule);
    free(s->t.v);
    free(s->rec.v);
    free(s->st_t.v);
    free(s->st_v.v);
    free(s->pending);
    free(s->x);
    free(s->v);
    free(s->f);
    free(s);
}

sensors *sensors_new(const scene_config *at, const taper_chain *chain, int *failed)
{
    *failed = 0;
    const scene_sensors_config *c = &at->sensors;
    if (!(c->interval > 0)) return NULL;
    sensors *s = calloc(1, sizeof *s);
    if (!s) goto nomem;
    s->at = *at;
    s->n = taper_chain_size(chain);
    s->interval = scene_sample_interval(at); /* rescaled: the library's time */
    s->n_granule = c->granules.n;
    if (s->n_granule && !(s->granule = malloc(s->n_granule * sizeof *s->granule))) goto nomem;
    for (size_t i = 0; i < s->n_granule; i++) s->granule[i] = (size_t)c->granules.v[i];
    for (int e = 0; e < TAPER_N_ENDS; e++)
        s->wall[e] = taper_chain_end(chain, (taper_end)e) == TAPER_END_WALL;
    s->series = s->n_granule > 0 || s->wall[TAPER_LEFT] || s->wall[TAPER_RIGHT];
    s->spacetime = c->spacetime;
    if (s->spacetime) {
        size_t most = (size_t)c->spacetime_granules;
        s->st_stride = (s->n + most - 1) / most;
        s->st_cols = (s->n - 1) / s->st_stride + 1;
        s->st_cap = (size_t)c->spacetime_times;
        s->st_every = 1;
        if (!(s->pending = malloc(s->st_cols * sizeof *s->pending))) goto nomem;
    }
    s->x = malloc(s->n * sizeof *s->x);
    s->v = malloc(s->n * sizeof *s->v);
    s->f = malloc((s->n + 1) * sizeof *s->f);
    if (!s->x || !s->v || !s->f) goto nomem;
    return s;
nomem:
    sensors_free(s);
    *failed = 1;
    return NULL;
}

static void stop(sensors *s, const char *why)
{
    s->failed = 1;
    snprintf(s->why, sizeof s->why, "%s", why);
}

/* A cell of the picture holds the velocity of largest magnitude among its
 * granules and samples: a pulse narrower than a cell (a solitary wave is
 * about five granules wide) still shows, as it would not if every S-th
 * granule and sample were picked. */
static void keep_larger(double *cell, double v)
{
    if (fabs(v) > fabs(*cell) || isnan(*cell)) *cell = v;
}

/* Merges each pair of rows: the picture's rows stand for twice as many
 * samples.  With an odd number of rows the last one, half a new row,
 * becomes the row being gathered. */
static void thin_spacetime(sensors *s)
{
    size_t rows = s->st_t.n, cols = s->st_cols;
    double *v = s->st_v.v;
    for (size_t r = 0; r + 1 < rows; r += 2) {
        s->st_t.v[r / 2] = s->st_t.v[r];
        for (size_t c = 0; c < cols; c++) {
            double x = v[r * cols + c];
            keep_larger(&x, v[(r + 1) * cols + c]);
            v[r / 2 * cols + c] = x;
        }
    }
    if (rows % 2) {
        /* pending holds the samples gathered after the last row */
        for (size_t c = 0; c < cols; c++) {
            double x = v[(rows - 1) * cols + c];
            if (s->pending_n) keep_larger(&x, s->pending[c]);
            s->pending[c] = x;
        }
        s->pending_t = s->st_t.v[rows - 1];
        s->pending_n += s->st_every;
    }
    s->st_t.n = rows / 2;
    s->st_v.n = rows / 2 * cols;
    s->st_every *= 2;
}

static void record_spacetime(sensors *s, double t)
{
    if (s->pending_n == 0) {
        s->pending_t = t;
        for (size_t c = 0; c < s->st_cols; c++) s->pending[c] = NAN;
    }
    for (size_t k = 1; k <= s->n; k++) keep_larger(&s->pending[(k - 1) / s->st_stride], s->v[k - 1]);
    if (++s->pending_n < s->st_every) return;
    if (s->st_t.n == s->st_cap) {
        thin_spacetime(s);
        if (s->pending_n < s->st_every) return;
    }
    if (push(&s->st_t, s->pending_t) != 0)
        return stop(s, "out of memory recording the space-time picture");
    for (size_t c = 0; c < s->st_cols; c++)
        if (push(&s->st_v, s->pending[c]) != 0)
            return stop(s, "out of memory recording the space-time picture");
    s->pending_n = 0;
}

int sensors_sample(const taper_sim *sim, void *user)
{
    sensors *s = user;
    if (s->failed) return 0;
    taper_error e;
    double t = taper_sim_time(sim);
    if (taper_sim_state(sim, s->x, s->v, &e) != TAPER_OK ||
        taper_sim_forces(sim, s->f, &e) != TAPER_OK) {
        stop(s, e.message);
        return 0;
    }
    if (s->series) {
        int bad = push(&s->t, t) != 0;
        for (size_t i = 0; i < s->n_granule && !bad; i++) {
            size_t k = s->granule[i];
            bad = push(&s->rec, s->x[k - 1]) || push(&s->rec, s->v[k - 1]) ||
                  push(&s->rec, s->f[k - 1]) || push(&s->rec, s->f[k]);
        }
        if (!bad) bad = push(&s->rec, s->f[0]) || push(&s->rec, s->f[s->n]);
        if (bad) {
            stop(s, "out of memory recording the sensors");
            return 0;
        }
    }
    if (s->spacetime) record_spacetime(s, t);
    s->n_samples++;
    return 0;
}

/* ---- files ------------------------------------------------------------------- */

/* "NAME" or "NAME[UNIT]" in SI. */
static void column(FILE *fp, const sensors *s, const char *name, int dim, int last)
{
    const char *unit = dim < 0 ? NULL : scene_unit_suffix(&s->at, (taper_dimension)dim);
    fprintf(fp, "%s%s%s%s%c", name, unit ? "[" : "", unit ? unit : "", unit ? "]" : "",
            last ? '\n' : '\t');
}

static double unit(const sensors *s, taper_dimension dim) { return scene_unit(&s->at, dim); }

/* A run that ended early: its samples end there. */
static void partial_comment(FILE *fp, const char *partial)
{
    if (partial) fprintf(fp, "# PARTIAL: the run ended early (%s): the samples end there\n", partial);
}

static void interval_comment(const sensors *s, FILE *fp, double every)
{
    const char *u = scene_unit_suffix(&s->at, TAPER_DIM_TIME);
    char text[SCENE_REAL_TEXT];
    scene_format_real(every, text);
    fprintf(fp, "# sampled every %s (rescaled time)", text);
    if (u) {
        char num[NUMBER_SIZE];
        number_shortest(num, every * unit(s, TAPER_DIM_TIME));
        fprintf(fp, " = %s %s", num, u);
    }
    fprintf(fp, "; %zu samples\n", s->n_samples);
}

/* About 22 bytes a number: a shortest double (17 digits at most, a sign,
 * a point, an exponent) and its tab. */
#define BYTES_PER_NUMBER 22.0

double sensors_bytes_per_sample(const sensors *s)
{
    double numbers = (s->series ? 7.0 * (double)s->n_granule : 0.0) +
                     (s->wall[TAPER_LEFT] || s->wall[TAPER_RIGHT]
                          ? 1.0 + s->wall[TAPER_LEFT] + s->wall[TAPER_RIGHT] : 0.0);
    /* and what is kept in memory until the files are written */
    double kept = 8.0 * (4.0 * (double)s->n_granule + 3.0);
    return numbers * BYTES_PER_NUMBER + kept;
}

static int write_sensors(const sensors *s, const char *partial, const char *dir, FILE *out,
                         char **msg)
{
    out_file *f = out_open(dir, "sensors.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    column(fp, s, "t", TAPER_DIM_TIME, 0);
    fputs("granule\t", fp);
    column(fp, s, "x", TAPER_DIM_LENGTH, 0);
    column(fp, s, "v", TAPER_DIM_VELOCITY, 0);
    column(fp, s, "f_left", TAPER_DIM_FORCE, 0);
    column(fp, s, "f_right", TAPER_DIM_FORCE, 0);
    column(fp, s, "force", TAPER_DIM_FORCE, 1);
    fprintf(fp, "# taper %s sensors: granules", taper_version());
    for (size_t i = 0; i < s->n_granule; i++) fprintf(fp, " %zu", s->granule[i]);
    fputc('\n', fp);
    partial_comment(fp, partial);
    interval_comment(s, fp, s->interval);
    fputs("# x: displacement from rest; v: velocity; f_left, f_right: compressive forces of the "
          "contacts with granule k-1 (k = 1: the striker, a wall or the load) and k+1 (k = N: a "
          "wall or the load); force: their mean, what a sensor inside the bead reads\n", fp);
    double ut = unit(s, TAPER_DIM_TIME), ux = unit(s, TAPER_DIM_LENGTH);
    double uv = unit(s, TAPER_DIM_VELOCITY), uf = unit(s, TAPER_DIM_FORCE);
    size_t per = 4 * s->n_granule + 2;
    for (size_t j = 0; j < s->t.n; j++) {
        if ((j & 1023) == 0 && out_stopping(f)) break;
        const double *r = s->rec.v + j * per;
        for (size_t i = 0; i < s->n_granule; i++, r += 4) {
            out_cell(fp, s->t.v[j] * ut, 0);
            fprintf(fp, "%zu\t", s->granule[i]);
            out_cell(fp, r[0] * ux, 0);
            out_cell(fp, r[1] * uv, 0);
            out_cell(fp, r[2] * uf, 0);
            out_cell(fp, r[3] * uf, 0);
            out_cell(fp, 0.5 * (r[2] + r[3]) * uf, 1);
        }
    }
    if (out_commit(f, msg) != 0) return -1;
    fprintf(out, "! wrote %s/sensors.tsv\n", dir);
    return 0;
}

/* One wall statistic as a header line, in the file's units. */
static void wall_stat(const sensors *s, const taper_sim *sim, FILE *fp, taper_statistic which,
                      taper_dimension dim)
{
    const char *name = taper_statistic_name(which), *u = scene_unit_suffix(&s->at, dim);
    if (!name) return;
    fprintf(fp, "# %s%s%s%s = ", name, u ? "[" : "", u ? u : "", u ? "]" : "");
    out_cell(fp, taper_sim_statistic(sim, which) * unit(s, dim), 1);
}

static int write_walls(const sensors *s, const taper_sim *sim, const char *partial,
                       const char *dir, FILE *out, char **msg)
{
    out_file *f = out_open(dir, "walls.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    int l = s->wall[TAPER_LEFT], r = s->wall[TAPER_RIGHT];
    column(fp, s, "t", TAPER_DIM_TIME, 0);
    if (l) column(fp, s, "force_left", TAPER_DIM_FORCE, !r);
    if (r) column(fp, s, "force_right", TAPER_DIM_FORCE, 1);
    fprintf(fp, "# taper %s walls: the force each wall takes from its end granule\n",
            taper_version());
    partial_comment(fp, partial);
    interval_comment(s, fp, s->interval);
    fputs("# peak force, its time (exact: a root of the contact's rate) and impulse (the "
          "integral of the force) over the run, [0, t_final], which goes on until the right "
          "wall's first contact has opened (and to t_end if later): the whole contact's\n", fp);
    if (l) {
        wall_stat(s, sim, fp, TAPER_STAT_WALL_PEAK_FORCE_LEFT, TAPER_DIM_FORCE);
        wall_stat(s, sim, fp, TAPER_STAT_WALL_PEAK_TIME_LEFT, TAPER_DIM_TIME);
        wall_stat(s, sim, fp, TAPER_STAT_WALL_IMPULSE_LEFT, TAPER_DIM_IMPULSE);
    }
    if (r) {
        wall_stat(s, sim, fp, TAPER_STAT_WALL_PEAK_FORCE_RIGHT, TAPER_DIM_FORCE);
        wall_stat(s, sim, fp, TAPER_STAT_WALL_PEAK_TIME_RIGHT, TAPER_DIM_TIME);
        wall_stat(s, sim, fp, TAPER_STAT_WALL_IMPULSE_RIGHT, TAPER_DIM_IMPULSE);
    }
    double ut = unit(s, TAPER_DIM_TIME), uf = unit(s, TAPER_DIM_FORCE);
    size_t per = 4 * s->n_granule + 2;
    for (size_t j = 0; j < s->t.n; j++) {
        if ((j & 4095) == 0 && out_stopping(f)) break;
        const double *w = s->rec.v + j * per + 4 * s->n_granule;
        out_cell(fp, s->t.v[j] * ut, 0);
        if (l) out_cell(fp, w[0] * uf, !r);
        if (r) out_cell(fp, w[1] * uf, 1);
    }
    if (out_commit(f, msg) != 0) return -1;
    fprintf(out, "! wrote %s/walls.tsv\n", dir);
    return 0;
}

/* The data of the picture: rows t, k, v, a blank line after each time (a
 * grid gnuplot draws `with image`). */
static int write_spacetime_data(const sensors *s, const char *partial, const char *dir,
                                double *vmax, char **msg)
{
    out_file *f = out_open(dir, "spacetime.tsv", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    column(fp, s, "t", TAPER_DIM_TIME, 0);
    fputs("k\t", fp);
    column(fp, s, "v", TAPER_DIM_VELOCITY, 1);
    fprintf(fp, "# taper %s space-time picture v(k, t): cells of %zu granule%s (k = 1, %zu, "
            "...) by %zu sample%s\n", taper_version(), s->st_stride, s->st_stride > 1 ? "s" : "",
            1 + s->st_stride, s->st_every, s->st_every > 1 ? "s" : "");
    partial_comment(fp, partial);
    interval_comment(s, fp, s->interval);
    fputs("# each cell holds the velocity of largest magnitude among its granules and samples "
          "(a pulse narrower than a cell still shows)\n", fp);
    fputs("# a blank line after each time (gnuplot: plot ... using 2:1:3 with image)\n", fp);
    double ut = unit(s, TAPER_DIM_TIME), uv = unit(s, TAPER_DIM_VELOCITY);
    *vmax = 0;
    /* The rows, then the samples gathered since the last one. */
    size_t rows = s->st_t.n + (s->pending_n > 0);
    for (size_t j = 0; j < rows; j++) {
        if ((j & 255) == 0 && out_stopping(f)) break;
        int last = j == s->st_t.n;
        const double *row = last ? s->pending : s->st_v.v + j * s->st_cols;
        double t = last ? s->pending_t : s->st_t.v[j];
        for (size_t c = 0; c < s->st_cols; c++) {
            double v = row[c] * uv;
            if (fabs(v) > *vmax) *vmax = fabs(v);
            out_cell(fp, t * ut, 0);
            fprintf(fp, "%zu\t", 1 + c * s->st_stride);
            out_cell(fp, v, 1);
        }
        fputc('\n', fp);
    }
    return out_commit(f, msg);
}

/* The classic figure of the field: granule across, time up, velocity as
 * colour (red forward, blue backward, white at rest). */
static int write_spacetime_script(const sensors *s, const char *dir, double vmax, char **msg)
{
    out_file *f = out_open(dir, "spacetime.gp", msg);
    if (!f) return -1;
    FILE *fp = f->fp;
    const char *ut = scene_unit_suffix(&s->at, TAPER_DIM_TIME);
    const char *uv = scene_unit_suffix(&s->at, TAPER_DIM_VELOCITY);
    if (!(vmax > 0)) vmax = 1;
    fprintf(fp, "# taper %s: the space-time picture v(k, t); render: gnuplot spacetime.gp (in "
            "this directory) -> spacetime.png\n", taper_version());
    fputs("set terminal pngcairo size 900,700 enhanced font ',11'\n"
          "set output 'spacetime.png'\n", fp);
    /* Every axis says its unit: SI, or the rescaled units of eq. (5). */
    fputs("set title ", fp);
    char *title = text_printf("velocity v(k, t) of every granule: %s", dir);
    plot_gp_string(fp, title ? title : "velocity v(k, t) of every granule");
    free(title);
    fprintf(fp, "\nset xlabel 'granule k'\nset ylabel 't [%s]'\nset cblabel 'v [%s]'\n",
            ut ? ut : "rescaled time, eq. (5)", uv ? uv : "impulse velocity");
    fputs("set palette defined (-1 '#2c4f9e', 0 '#ffffff', 1 '#b2182b')\n", fp);
    fprintf(fp, "set cbrange [%.6g:%.6g]\n", -vmax, vmax);
    fputs("set autoscale xfix\nset autoscale yfix\n"
          "plot 'spacetime.tsv' skip 1 using 2:1:3 with image notitle\n", fp);
    return out_commit(f, msg);
}

static int write_spacetime(const sensors *s, const char *partial, const char *dir, FILE *out,
                           char **msg)
{
    double vmax;
    if (write_spacetime_data(s, partial, dir, &vmax, msg) != 0) return -1;
    if (write_spacetime_script(s, dir, vmax, msg) != 0) return -1;
    fprintf(out, "! wrote %s/spacetime.tsv and %s/spacetime.gp\n", dir, dir);
    if (s->st_t.n + (s->pending_n > 0) < 2 || s->st_cols < 2) {
        fprintf(out, "! note: %s/spacetime.png not drawn: %zu times of %zu granules is no "
                "picture (a longer run, &solver t_end, or a smaller &sensors interval)\n", dir,
                s->st_t.n + (s->pending_n > 0), s->st_cols);
        return 0;
    }
    return plot_render_reported(dir, "spacetime.gp", out, msg);
}

int sensors_write(const sensors *s, const taper_sim *sim, const char *partial, const char *dir,
                  FILE *out, char **msg)
{
    *msg = NULL;
    if (s->failed) {
        *msg = text_printf("sensors: %s", s->why);
        return -1;
    }
    if (s->n_granule && write_sensors(s, partial, dir, out, msg) != 0) return -1;
    if ((s->wall[TAPER_LEFT] || s->wall[TAPER_RIGHT]) &&
        write_walls(s, sim, partial, dir, out, msg) != 0)
        return -1;
    if (s->spacetime && write_spacetime(s, partial, dir, out, msg) != 0) return -1;
    return 0;
}
