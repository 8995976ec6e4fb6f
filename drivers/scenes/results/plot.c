/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * plot.c -- figure data, gnuplot script, rendering.
 */
#include "results/plot.h"

#include "util/number.h"

#include "results/output.h"
#include "util/text.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* ---- data ----------------------------------------------------------------- */

static void data_block(const report *r, const report_point *p, double *buf[4], FILE *fp)
{
    const scene_figure_config *fig = &r->cfg->figure;
    scene_quantity qx = fig->x, qy = fig->y;
    size_t n = p->src.n, every = (size_t)fig->every;
    size_t last = (size_t)fig->k_max;
    if (last == 0 || last > n) last = n;
    int num = series_fill(&p->src, SERIES_NUMERICS, qx, buf[2]) == 0 &&
              series_fill(&p->src, SERIES_NUMERICS, qy, buf[3]) == 0;
    series_fill(&p->src, SERIES_THEORY, qx, buf[0]);
    series_fill(&p->src, SERIES_THEORY, qy, buf[1]);
    /* Log-log axes: about 40 points per decade of k instead of every n-th
     * (which would leave the first decade nearly empty). */
    int geometric = fig->log_x && fig->log_y;
    char param[NUMBER_SIZE];
    number_shortest(param, p->param);
    fprintf(fp, "# %s = %s\n", r->param_name, param);
    for (size_t i = 0, kept = 0; i < last; i += geometric ? 1 : every) {
        if (geometric && i > 0 && (double)(i + 1) < 1.06 * (double)kept) continue;
        kept = i + 1;
        out_cell(fp, p->param, 0);
        fprintf(fp, "%zu\t", i + 1);
        out_cell(fp, buf[0][i], 0);
        out_cell(fp, buf[1][i], 0);
        out_cell(fp, num ? buf[2][i] : NAN, 0);
        out_cell(fp, num ? buf[3][i] : NAN, 1);
    }
    fputs("\n\n", fp); /* gnuplot: next index */
}

static int write_data(const report *r, char **msg)
{
    out_file *f = out_open(r->dir, "figure.tsv", msg);
    if (!f) return -1;
    fprintf(f->fp, "# taper %s figure data: one block per run (gnuplot index i = run i)\n",
            taper_version());
    fprintf(f->fp, "# x = %s, y = %s for the theory and the numerics\n",
            scene_quantity_name(r->cfg->figure.x), scene_quantity_name(r->cfg->figure.y));
    fputs("param\tk\tx_theory\ty_theory\tx_numerics\ty_numerics\n", f->fp);
    size_t n = r->n ? r->points[0].src.n : 0;
    for (size_t i = 1; i < r->n; i++)
        if (r->points[i].src.n > n) n = r->points[i].src.n;
    double *buf[4] = {0};
    int rc = 0;
    for (int c = 0; c < 4; c++)
        if (!(buf[c] = malloc((n ? n : 1) * sizeof(double)))) rc = -1;
    for (size_t i = 0; rc == 0 && i < r->n; i++) data_block(r, &r->points[i], buf, f->fp);
    for (int c = 0; c < 4; c++) free(buf[c]);
    if (rc != 0) {
        *msg = text_printf("%s/figure.tsv: out of memory", r->dir);
        out_discard(f);
        return -1;
    }
    return out_commit(f, msg);
}

static int write_inset(const report *r, char **msg)
{
    out_file *f = out_open(r->dir, "inset.tsv", msg);
    if (!f) return -1;
    fprintf(f->fp, "# taper %s inset: %s of the fit against %s\n", taper_version(),
            analysis_label(r->cfg), r->param_name);
    fputs("param\ttheory\ttheory_fit\ttheory_fit_stderr\tnumerics\tnumerics_stderr\n", f->fp);
    for (size_t i = 0; i < r->n; i++) {
        const report_point *p = &r->points[i];
        double row[] = {p->param, p->theory, p->fit[0].value, p->fit[0].error, p->fit[1].value,
                        p->fit[1].error};
        for (int c = 0; c < 6; c++) out_cell(f->fp, row[c], c == 5);
    }
    return out_commit(f, msg);
}

/* ---- script ----------------------------------------------------------------- */

void plot_gp_string(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') fputc('\\', fp);
        fputc(*s, fp);
    }
    fputc('"', fp);
}

/* The paper writes S and q. */
static const char *display_name(const report *r)
{
    return strcmp(r->param_name, "s") == 0 ? "S" : r->param_name;
}

static const char *label_or(const char *label, scene_quantity quantity)
{
    return label[0] ? label : series_label(quantity);
}

static void script_head(const report *r, FILE *fp)
{
    fprintf(fp, "# taper %s: %s (scene %s)\n", taper_version(), r->cfg->figure.name,
            r->scene_path);
    fputs("# Render: gnuplot figure.gp (in this directory) -> figure.png\n", fp);
    fputs("if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
          "    set terminal pngcairo size 900,660 enhanced font \"Sans,12\"\n"
          "} else {\n"
          "    set terminal png size 900,660\n"
          "}\n", fp);
    fputs("set output \"figure.png\"\nset datafile missing \"nan\"\n"
          "set border lw 1.2\nset tics scale 1.2\n", fp);
    /* Ten distinguishable colours, none black (black is the key's
     * theory/numerics legend). */
    static const char *const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                          "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
    for (int i = 0; i < 10; i++)
        fprintf(fp, "set linetype %d lc rgb \"%s\"\n", i + 1, colours[i]);
    fputs("set linetype cycle 10\n", fp);
}

/* The main panel's frame on the canvas (screen coordinates), fixed so that
 * the inset can be placed inside it; the key sits right of it. */
#define FRAME_L 0.10
#define FRAME_R 0.78
#define FRAME_B 0.11
#define FRAME_T 0.92

static void main_panel(const report *r, FILE *fp, int inset, double y_lo, double y_hi)
{
    const scene_figure_config *fig = &r->cfg->figure;
    int th = fig->curves != SCENE_CURVES_NUMERICS, nu = fig->curves != SCENE_CURVES_THEORY;
    if (inset) fputs("set multiplot\n", fp);
    fprintf(fp, "set lmargin at screen %g\nset rmargin at screen %g\n"
                "set bmargin at screen %g\nset tmargin at screen %g\n",
            FRAME_L, FRAME_R, FRAME_B, FRAME_T);
    fputs("set title ", fp);
    char *title = text_printf("%s  %s", fig->name, fig->title);
    plot_gp_string(fp, title ? title : fig->name);
    free(title);
    fputs("\nset xlabel ", fp);
    plot_gp_string(fp, label_or(fig->x_label, fig->x));
    fputs("\nset ylabel ", fp);
    plot_gp_string(fp, label_or(fig->y_label, fig->y));
    fputc('\n', fp);
    if (fig->log_x) fputs("set logscale x\nset format x \"10^{%L}\"\n", fp);
    if (fig->log_y) fputs("set logscale y\nset format y \"10^{%L}\"\n", fp);
    if (!isnan(y_lo)) fprintf(fp, "set yrange [%.17g:%.17g] # room for the inset\n", y_lo, y_hi);
    fputs("set key outside right top spacing 1.1\nset mxtics\nset mytics\n", fp);
    fprintf(fp, "n = %zu\ntitles = \"", r->n);
    for (size_t i = 0; i < r->n; i++)
        fprintf(fp, "%s%s=%g", i ? " " : "", display_name(r), r->points[i].param);
    fputs("\"\nplot \\\n", fp);
    if (th) fputs("  keyentry with points pt 6 ps 1.1 lc rgb \"black\" title \"theory\", \\\n", fp);
    if (nu) fputs("  keyentry with points pt 7 ps 0.9 lc rgb \"black\" title \"numerics\", \\\n", fp);
    if (th)
        fprintf(fp, "  for [i=0:n-1] \"figure.tsv\" index i using 3:4 with points pt 6 ps 1.1 "
                    "lc (i+1) %s%s\n", nu ? "notitle" : "title word(titles, i+1)",
                nu ? ", \\" : "");
    if (nu)
        fputs("  for [i=0:n-1] \"figure.tsv\" index i using 5:6 with points pt 7 ps 0.8 "
              "lc (i+1) title word(titles, i+1)\n", fp);
}

/* A tic step of 1, 2 or 5 times a power of ten giving 3-6 tics. */
static double tic_step(const report *r)
{
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < r->n; i++) {
        lo = fmin(lo, r->points[i].param);
        hi = fmax(hi, r->points[i].param);
    }
    double span = hi > lo ? hi - lo : fabs(hi) + 1e-300;
    double unit = pow(10.0, floor(log10(span / 4.0)));
    double step = span / 4.0 / unit;
    return unit * (step < 1.5 ? 1.0 : step < 3.5 ? 2.0 : 5.0);
}

/* The inset, as in the paper: a small plot inside the main panel, in the
 * corner where the main panel draws the fewest points.  Corners, as
 * fractions of the main frame: the inset's own frame (width and height
 * INSET_W) with room for its tic labels and axis titles left of and below it
 * (INSET_PAD_L, INSET_PAD_B), INSET_GAP from the main frame. */
#define INSET_W 0.36
#define INSET_PAD_L 0.14
#define INSET_PAD_B 0.15
#define INSET_GAP 0.03

/* The inset's frame: lower left corner and size, fractions of the main frame. */
typedef struct inset_box { double u0, v0, w; } inset_box;

/* Corner c (0 upper right, 1 upper left, 2 lower right, 3 lower left) of
 * an inset of size w. */
static inset_box corner_box(int c, double w)
{
    inset_box b = {c % 2 ? INSET_GAP + INSET_PAD_L : 1 - INSET_GAP - w,
                   c < 2 ? 1 - INSET_GAP - w : INSET_GAP + INSET_PAD_B, w};
    return b;
}

/* The range gnuplot's autoscale draws for data in [lo, hi] (in log10 on a
 * logarithmic axis): out to whole decades, or to the next tic of a step of 1,
 * 2 or 5 times a power of ten. */
static void autoscale(double *lo, double *hi, int logarithmic)
{
    if (!(*hi > *lo)) return;
    if (logarithmic) {
        *lo = floor(*lo);
        *hi = ceil(*hi);
        return;
    }
    double span = *hi - *lo, unit = pow(10.0, floor(log10(span)));
    double step = span / unit > 5 ? unit : span / unit > 2 ? unit / 2 : unit / 5;
    *lo = floor(*lo / step) * step;
    *hi = ceil(*hi / step) * step;
}

/* Does the inset at b (with room for its labels) cover the point (u, v)? */
static int covers(const inset_box *b, double u, double v)
{
    return u >= b->u0 - INSET_PAD_L - INSET_GAP && u <= b->u0 + b->w + INSET_GAP &&
           v >= b->v0 - INSET_PAD_B - INSET_GAP && v <= b->v0 + b->w + INSET_GAP;
}

/* The drawn points (the rows figure.tsv holds) as fractions (u, v) of the
 * axes' autoscaled range (logarithmic where the axis is), 2 doubles each;
 * lo, hi: the data's range before autoscaling (log10 on a log axis).
 * malloc'd, NULL (and *count 0) when nothing can be placed. */
static double *drawn_points(const report *r, size_t *count, double lo[2], double hi[2])
{
    const scene_figure_config *fig = &r->cfg->figure;
    size_t n = 0, total = 0;
    *count = 0;
    for (size_t i = 0; i < r->n; i++) {
        if (r->points[i].src.n > n) n = r->points[i].src.n;
        total += r->points[i].src.n;
    }
    double *buf[4] = {0}, *uv = malloc((2 * total + 2) * sizeof(double) * 2);
    int ok = n > 0 && uv;
    for (int c = 0; c < 4; c++)
        if (!(buf[c] = malloc((n ? n : 1) * sizeof(double)))) ok = 0;
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    const int lg[2] = {fig->log_x, fig->log_y};
    size_t m = 0;
    for (size_t i = 0; ok && i < r->n; i++) {
        const report_point *p = &r->points[i];
        int have[2];
        have[0] = fig->curves != SCENE_CURVES_NUMERICS &&
                  series_fill(&p->src, SERIES_THEORY, fig->x, buf[0]) == 0 &&
                  series_fill(&p->src, SERIES_THEORY, fig->y, buf[1]) == 0;
        have[1] = fig->curves != SCENE_CURVES_THEORY &&
                  series_fill(&p->src, SERIES_NUMERICS, fig->x, buf[2]) == 0 &&
                  series_fill(&p->src, SERIES_NUMERICS, fig->y, buf[3]) == 0;
        size_t last = (size_t)fig->k_max;
        if (last == 0 || last > p->src.n) last = p->src.n;
        for (size_t k = 0; k < last; k++)
            for (int s = 0; s < 2; s++) {
                if (!have[s]) continue;
                double xy[2] = {buf[2 * s][k], buf[2 * s + 1][k]};
                int good = 1;
                for (int a = 0; a < 2; a++) {
                    if (lg[a]) xy[a] = xy[a] > 0 ? log10(xy[a]) : NAN;
                    if (!isfinite(xy[a])) good = 0;
                }
                if (!good) continue;
                for (int a = 0; a < 2; a++) {
                    lo[a] = fmin(lo[a], xy[a]);
                    hi[a] = fmax(hi[a], xy[a]);
                }
                uv[m++] = xy[0];
                uv[m++] = xy[1];
            }
    }
    for (int c = 0; c < 4; c++) free(buf[c]);
    if (!ok || !(hi[0] > lo[0]) || !(hi[1] > lo[1])) {
        free(uv);
        return NULL;
    }
    double alo[2] = {lo[0], lo[1]}, ahi[2] = {hi[0], hi[1]};
    for (int a = 0; a < 2; a++) autoscale(&alo[a], &ahi[a], lg[a]);
    for (size_t j = 0; j < m; j += 2)
        for (int a = 0; a < 2; a++) uv[j + a] = (uv[j + a] - alo[a]) / (ahi[a] - alo[a]);
    *count = m / 2;
    return uv;
}

/* A free place for an inset of size w: where it covers no point, as near
 * a corner as can be (the corners first, then places a step further in, on
 * a grid of GRID x GRID).  1 and *b, or 0. */
#define GRID 7
static int free_place(const double *uv, size_t n, double w, inset_box *b)
{
    const inset_box top_right = corner_box(0, w), bottom_left = corner_box(3, w);
    for (int d = 0; d < GRID; d++)
        for (int i = 0; i < GRID; i++)
            for (int j = 0; j < GRID; j++) {
                int di = i < GRID - 1 - i ? i : GRID - 1 - i, dj = j < GRID - 1 - j ? j : GRID - 1 - j;
                if ((di > dj ? di : dj) != d) continue;
                inset_box c = {top_right.u0 - (top_right.u0 - bottom_left.u0) * i / (GRID - 1),
                               top_right.v0 - (top_right.v0 - bottom_left.v0) * j / (GRID - 1), w};
                size_t k = 0;
                while (k < n && !covers(&c, uv[2 * k], uv[2 * k + 1])) k++;
                if (k == n) {
                    *b = c;
                    return 1;
                }
            }
    return 0;
}

/* Where the inset goes, as in the paper: inside the main panel where it
 * covers no point, at full size (INSET_W) or down to two thirds of it;
 * where no place is free, full size in the corner needing the least growth
 * of the y range, away from the corner, for it and its labels to cover no
 * point.  *y_lo, *y_hi: the y range to set (data units), or NaN to leave
 * gnuplot's. */
static inset_box inset_place(const report *r, double *y_lo, double *y_hi)
{
    const int lg_y = r->cfg->figure.log_y;
    *y_lo = *y_hi = NAN;
    size_t n = 0;
    double lo[2], hi[2];
    double *uv = drawn_points(r, &n, lo, hi);
    if (!uv) return corner_box(0, INSET_W);
    inset_box b;
    for (double w = INSET_W; w >= INSET_W * 2 / 3 - 1e-9; w -= INSET_W / 9)
        if (free_place(uv, n, w, &b)) {
            free(uv);
            return b;
        }
    /* No free place: a corner, and room made for it. */
    double need[4] = {0, 0, 1, 1}; /* upper corners: highest v; lower: lowest v */
    for (size_t k = 0; k < n; k++)
        for (int c = 0; c < 4; c++) {
            const inset_box cb = corner_box(c, INSET_W);
            double u = uv[2 * k], v = uv[2 * k + 1];
            if (u < cb.u0 - INSET_PAD_L - INSET_GAP || u > cb.u0 + INSET_W + INSET_GAP) continue;
            need[c] = c < 2 ? fmax(need[c], v) : fmin(need[c], v);
        }
    free(uv);
    double grow[4];
    for (int c = 0; c < 4; c++) {
        const inset_box cb = corner_box(c, INSET_W);
        double edge = c < 2 ? cb.v0 - INSET_PAD_B - INSET_GAP : cb.v0 + INSET_W + INSET_GAP;
        grow[c] = c < 2 ? fmax(1.0, need[c] / edge)
                        : fmax(1.0, 1.0 + (edge - need[c]) / (1.0 - edge));
    }
    int best = 0;
    for (int c = 1; c < 4; c++)
        if (grow[c] < grow[best] - 1e-9) best = c;
    if (grow[best] > 1.0) {
        double l = lo[1], h = hi[1];
        autoscale(&l, &h, lg_y);
        double span = h - l;
        if (best < 2) h = l + grow[best] * span;
        else l = h - grow[best] * span;
        autoscale(&l, &h, lg_y);
        *y_lo = lg_y ? pow(10.0, l) : l;
        *y_hi = lg_y ? pow(10.0, h) : h;
    }
    return corner_box(best, INSET_W);
}

static void inset_panel(const report *r, FILE *fp, const inset_box *b)
{
    double ref = r->cfg->figure.inset_reference; /* NaN: none */
    double w = FRAME_R - FRAME_L, h = FRAME_T - FRAME_B;
    double x0 = FRAME_L + b->u0 * w, y0 = FRAME_B + b->v0 * h;
    fputs("set autoscale\nunset logscale\nunset title\nunset mxtics\nunset mytics\n"
          "set format x \"% g\"\nset format y \"% g\"\nset tics font \",9\" scale 0.8\n", fp);
    fprintf(fp, "set xtics %.17g\n", tic_step(r));
    fprintf(fp, "set lmargin at screen %.4f\nset rmargin at screen %.4f\n"
                "set bmargin at screen %.4f\nset tmargin at screen %.4f\n",
            x0, x0 + b->w * w, y0, y0 + b->w * h);
    fputs("set object 1 rectangle from graph 0, graph 0 to graph 1, graph 1 behind "
          "fillcolor rgb \"white\" fillstyle solid 1.0 noborder\n", fp);
    fputs("set key inside bottom right spacing 0.9 font \",9\" samplen 1 opaque\n", fp);
    fprintf(fp, "set xlabel \"%s\" font \",10\" offset 0, 0.6\nset ylabel ", display_name(r));
    plot_gp_string(fp, analysis_label(r->cfg));
    fputs(" font \",10\" offset 1.5, 0\n", fp);
    fputs("set offsets graph 0.08, graph 0.08, graph 0.15, graph 0.15\n", fp);
    fputs("plot \"inset.tsv\" using 1:2 with points pt 6 ps 1.1 lc rgb \"black\" title \"theory\", \\\n"
          "     \"inset.tsv\" using 1:5:6 with yerrorbars pt 7 ps 0.8 lc rgb \"black\" title \"numerics\"",
          fp);
    if (!isnan(ref))
        fprintf(fp, ", \\\n     %.17g with lines dt 2 lc rgb \"gray40\" title \"%.4g\"", ref, ref);
    fputs("\nunset multiplot\n", fp);
}

static int write_script(const report *r, int inset, char **msg)
{
    out_file *f = out_open(r->dir, "figure.gp", msg);
    if (!f) return -1;
    double y_lo = NAN, y_hi = NAN;
    inset_box place = inset ? inset_place(r, &y_lo, &y_hi) : corner_box(0, INSET_W);
    script_head(r, f->fp);
    main_panel(r, f->fp, inset, y_lo, y_hi);
    if (inset) inset_panel(r, f->fp, &place);
    return out_commit(f, msg);
}

int plot_write(const report *r, char **msg)
{
    int inset = r->cfg->figure.inset;
    if (write_data(r, msg) != 0) return -1;
    if (inset && write_inset(r, msg) != 0) return -1;
    if (write_script(r, inset, msg) != 0) return -1;
    printf("! wrote %s/figure.tsv%s and %s/figure.gp\n", r->dir, inset ? ", inset.tsv" : "",
           r->dir);
    return 0;
}

/* ---- rendering ------------------------------------------------------------------ */

int plot_render(const char *dir, char **msg) { return plot_render_script(dir, "figure.gp", msg); }

/* DIR/NAME.png, the image a script of ours renders (NAME.gp). */
static char *image_path(const char *dir, const char *script)
{
    size_t n = strlen(script);
    if (n > 3 && strcmp(script + n - 3, ".gp") == 0) n -= 3;
    return text_printf("%s/%.*s.png", dir, (int)n, script);
}

int plot_render_reported(const char *dir, const char *script, FILE *out, char **msg)
{
    int rendered = plot_render_script(dir, script, msg);
    if (rendered < 0) return -1;
    if (rendered == 0) {
        char *image = image_path(dir, script);
        fprintf(out, "! wrote %s\n", image ? image : script);
        free(image);
    } else {
        fprintf(out, "! note: %s\n", *msg ? *msg : "figure not rendered");
    }
    free(*msg);
    *msg = NULL;
    return 0;
}

int plot_render_script(const char *dir, const char *script, char **msg)
{
    *msg = NULL;
    const char *gp = getenv("TAPER_GNUPLOT");
    if (!gp || !gp[0]) gp = "gnuplot";
    char *image = image_path(dir, script);
    if (!image) {
        *msg = text_printf("%s/%s: out of memory", dir, script);
        return -1;
    }
    unlink(image); /* an earlier run's picture is not this one's */
    if (strcmp(gp, "none") == 0) {
        *msg = text_printf("rendering skipped (TAPER_GNUPLOT=none): cd %s && gnuplot %s", dir,
                           script);
        free(image);
        return 1;
    }
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        *msg = text_printf("cannot start %s: %s", gp, strerror(errno));
        free(image);
        return -1;
    }
    if (pid == 0) {
        if (chdir(dir) == 0) execlp(gp, gp, script, (char *)NULL);
        _exit(127);
    }
    /* Waits, looking for a stop signal every 20 ms: gnuplot drawing a
     * large picture is stopped with the run. */
    int status = 0, stopped = 0;
    for (;;) {
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid || (w < 0 && errno != EINTR)) break;
        if (!stopped && out_stop_signal()) {
            kill(pid, SIGTERM);
            stopped = 1;
        }
        struct timespec nap = {0, 20000000};
        nanosleep(&nap, NULL);
    }
    int rc;
    if (!stopped && WIFEXITED(status) && WEXITSTATUS(status) == 0) {
        rc = 0;
    } else if (!stopped && WIFEXITED(status) && WEXITSTATUS(status) == 127) {
        *msg = text_printf("%s not found: figure not rendered (install gnuplot, then: cd %s && "
                           "gnuplot %s)", gp, dir, script);
        rc = 1;
    } else {
        /* gnuplot opens its output before it draws: what it leaves under
         * the image's name is no figure. */
        unlink(image);
        *msg = stopped ? text_printf("%s not written: interrupted by a signal", image)
                       : text_printf("%s failed on %s/%s (status %d): %s not written", gp, dir,
                                     script, status, image);
        rc = -1;
    }
    free(image);
    return rc;
}
