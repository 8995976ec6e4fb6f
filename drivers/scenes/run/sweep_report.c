/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_report.c -- the files a sweep writes from its runs' files
 * (sweep_report.h).
 */
#include "run/sweep_report.h"

#include "results/analysis.h"
#include "results/footer.h"
#include "results/output.h"
#include "run/interrupt.h"
#include "util/number.h"
#include "util/text.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ---- results back from the files --------------------------------------------- */

/* The columns of a granules.tsv (out_column_names), granule k at k-1. */
typedef struct table_data {
    size_t n;
    double *col[OUT_N_COLUMNS]; /* col[0] unused; NULL: not in the file */
} table_data;

static void table_free(table_data *t)
{
    for (int c = 0; c < OUT_N_COLUMNS; c++) free(t->col[c]);
    memset(t, 0, sizeof *t);
}

/* Reads the numbers of a run back, every one as computed (the files hold
 * the shortest text that reads back to each double), for the
 * reports: DIR/report.tsv when the run wrote one (its granules.tsv leaves
 * rows or columns out), else DIR/granules.tsv.  Columns by their names. */
static int table_read(const char *dir, table_data *t, char **msg)
{
    memset(t, 0, sizeof *t);
    char *path = text_printf("%s/report.tsv", dir);
    FILE *fp = path ? fopen(path, "r") : NULL;
    if (!fp) {
        free(path);
        path = text_printf("%s/granules.tsv", dir);
        fp = path ? fopen(path, "r") : NULL;
    }
    if (!fp) {
        *msg = text_printf("cannot read %s: %s", path ? path : dir, strerror(errno));
        free(path);
        return -1;
    }
    char *line = NULL;
    size_t cap = 0, alloc = 0;
    int map[OUT_N_COLUMNS + 1], n_fields = 0, rc = 0;
    ssize_t len;
    while (rc == 0 && (len = getline(&line, &cap, fp)) >= 0) {
        if (line[0] == '#') continue;
        if (len > 0 && line[len - 1] == '\n') line[--len] = '\0';
        if (n_fields == 0) { /* the header line: which column is which */
            for (char *f = strtok(line, "\t"); f && n_fields <= OUT_N_COLUMNS; f = strtok(NULL, "\t")) {
                map[n_fields] = -1;
                for (int c = 0; c < OUT_N_COLUMNS; c++)
                    if (strcmp(f, out_column_names[c]) == 0) map[n_fields] = c;
                n_fields++;
            }
            if (n_fields == 0 || map[0] != 0) rc = -1;
            continue;
        }
        char *p = line, *end;
        unsigned long long k = strtoull(p, &end, 10);
        if (end == p || k == 0) {
            rc = -1;
            break;
        }
        if (k > alloc) {
            size_t grown_n = alloc ? alloc : 1024;
            while (grown_n < k) grown_n *= 2;
            for (int f = 1; f < n_fields; f++) {
                int c = map[f];
                if (c < 0) continue;
                double *grown = realloc(t->col[c], grown_n * sizeof *grown);
                if (!grown) {
                    rc = -1;
                    break;
                }
                for (size_t j = alloc; j < grown_n; j++) grown[j] = NAN;
                t->col[c] = grown;
            }
            alloc = grown_n;
        }
        for (int f = 1; rc == 0 && f < n_fields; f++) {
            if (*end != '\t') {
                rc = -1;
                break;
            }
            p = end + 1;
            double x = strtod(p, &end);
            if (end == p) rc = -1;
            if (map[f] >= 0) t->col[map[f]][k - 1] = x;
        }
        if (k > t->n) t->n = (size_t)k;
    }
    free(line);
    fclose(fp);
    if (rc != 0 || n_fields == 0) {
        *msg = text_printf("%s: not a granules table of taper", path);
        table_free(t);
        rc = -1;
    }
    free(path);
    return rc;
}

/* Appends the data lines of DIR/granules.tsv to fp, each after the lead
 * cells; *header: the file's column names (malloc'd) when NULL before. */
static int copy_rows(const char *dir, const char *lead, FILE *fp, char **header, char **msg)
{
    char *path = text_printf("%s/granules.tsv", dir);
    FILE *in = path ? fopen(path, "r") : NULL;
    if (!in) {
        *msg = text_printf("cannot read %s: %s", path ? path : dir, strerror(errno));
        free(path);
        return -1;
    }
    char *line = NULL;
    size_t cap = 0;
    int first = 1;
    while (getline(&line, &cap, in) >= 0) {
        if (line[0] == '#') continue;
        if (first) {
            first = 0;
            if (!*header) *header = text_dup(line);
            continue;
        }
        fputs(lead, fp);
        fputs(line, fp);
    }
    free(line);
    fclose(in);
    free(path);
    return 0;
}

/* The first line of a run's messages, for sweep.tsv and runs.tsv, without
 * the "SCENE: run NAME: " that names it there already. */
static char *first_line(const sweep *sw, const sweep_item *it)
{
    const char *log = it->outcome.log;
    if (!log || !log[0]) return text_dup(it->outcome.rc == RUN_PARTIAL ? "partial result" : "failed");
    char *label = text_printf("%s: run %s: ", scene_path(sw->sc), it->name);
    if (label && strncmp(log, label, strlen(label)) == 0) log += strlen(label);
    free(label);
    const char *nl = strchr(log, '\n');
    char *s = text_printf("%.*s", nl ? (int)(nl - log) : (int)strlen(log), log);
    for (char *c = s; c && *c; c++)
        if (*c == '\t') *c = ' ';
    return s;
}

static const char *status_name(int rc)
{
    switch (rc) {
    case RUN_COMPLETE: return "complete";
    case RUN_UNTRUSTED: return "untrusted";
    case RUN_PARTIAL: return "partial";
    case RUN_INPUT: return "refused";
    default: return "failed";
    }
}

/* A sweep file that could not be written (msg, freed): the disk
 * (RUN_FAILED), or a stop signal while it was written (RUN_PARTIAL: the
 * runs are complete on disk, the same command writes it). */
static int report_failure(const sweep *sw, char *msg)
{
    int rc = RUN_FAILED;
    char *said = NULL;
    if (out_was_stopped(msg) && interrupt_signal()) {
        said = run_stopped_writing(msg);
        rc = RUN_PARTIAL;
    }
    fprintf(stderr, "%s: %s%s\n", scene_path(sw->sc), said ? said : msg ? msg : "out of memory",
            rc == RUN_PARTIAL ? " (every run is on disk: the same command writes the sweep's "
                                "files again)" : "");
    free(said);
    free(msg);
    return rc;
}

/* The swept variables' names, ", "-separated, and the sweep's shape. */
static void write_lead_header(const scene_config *cfg, FILE *fp)
{
    for (size_t k = 0; k < cfg->runs.n_swept; k++)
        fprintf(fp, "%s%s", k ? ", " : "", scene_swept_name(cfg, k));
}

/* The comment lines of sweep.tsv: what it is, and each run without rows. */
static void sweep_comments(const sweep *sw, FILE *fp)
{
    const scene_config *cfg = sw->cfg;
    fprintf(fp, "# taper %s sweep over ", taper_version());
    write_lead_header(cfg, fp);
    if (cfg->runs.n_swept > 1)
        fprintf(fp, " (%s, %zu runs)", cfg->sweep.mode == SCENE_SWEEP_ZIP ? "zipped" : "grid",
                sw->n);
    fputs(": the rows of every ", fp);
    for (size_t k = 0; k < cfg->runs.n_swept; k++)
        fprintf(fp, "%s%s=VALUE", k ? "," : "", scene_swept_name(cfg, k));
    fputs("/granules.tsv\n", fp);
    for (size_t j = 0; j < sw->n; j++) {
        const sweep_item *it = &sw->items[j];
        if (sweep_has_rows(it->outcome.rc)) continue;
        char *why = first_line(sw, it);
        fprintf(fp, "# %s run %s: no rows (%s)\n", status_name(it->outcome.rc), it->name,
                why ? why : "");
        free(why);
    }
}

/* DIR/sweep.tsv: the column names (the swept variables', then those of
 * granules.tsv), the comment lines, then the rows of every complete run's
 * granules.tsv as they are, the swept values first.  One swept variable:
 * the form of a one-variable sweep exactly. */
static int write_sweep_tsv(sweep *sw)
{
    const scene_config *cfg = sw->cfg;
    char *msg = NULL, *header = NULL;
    out_file *f = out_open(cfg->output.dir, "sweep.tsv", &msg);
    if (!f) goto fail;
    /* The column names of the first run with rows (every run has the same). */
    for (size_t i = 0; i < sw->n && !header; i++) {
        if (!sweep_has_rows(sw->items[i].outcome.rc)) continue;
        char *path = text_printf("%s/granules.tsv", sw->items[i].dir);
        FILE *in = path ? fopen(path, "r") : NULL;
        char *line = NULL;
        size_t cap = 0;
        while (in && getline(&line, &cap, in) >= 0)
            if (line[0] != '#') {
                header = text_dup(line);
                break;
            }
        free(line);
        if (in) fclose(in);
        if (!header) {
            msg = text_printf("cannot read %s: %s", path ? path : "granules.tsv", strerror(errno));
            free(path);
            goto fail;
        }
        free(path);
    }
    for (size_t k = 0; k < cfg->runs.n_swept; k++)
        fprintf(f->fp, "%s%s", scene_swept_name(cfg, k), header || k + 1 < cfg->runs.n_swept ? "\t" : "\n");
    if (header) fputs(header, f->fp);
    sweep_comments(sw, f->fp);
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        if (!sweep_has_rows(it->outcome.rc)) continue;
        char lead[SCENE_MAX_SWEPT * 32 + 1];
        size_t used = 0;
        for (size_t k = 0; k < cfg->runs.n_swept; k++) {
            char num[NUMBER_SIZE]; /* out_cell's spelling */
            number_shortest(num, scene_swept_value(cfg, i, k));
            used += (size_t)snprintf(lead + used, sizeof lead - used, "%s\t", num);
        }
        char *skip = NULL;
        if (copy_rows(it->dir, lead, f->fp, &skip, &msg) != 0) goto fail;
        free(skip);
    }
    free(header);
    header = NULL;
    int committed = out_commit(f, &msg);
    f = NULL;
    if (committed != 0) goto fail;
    printf("! wrote %s/sweep.tsv\n", cfg->output.dir);
    return RUN_COMPLETE;
fail:
    free(header);
    if (f) out_discard(f);
    return report_failure(sw, msg);
}

/* ---- the per-run summary ------------------------------------------------------- */

/* The statistics lines of a result file's header ("# steps = 4336",
 * "# t_final[s] = 0.0123"): a name (with its unit in brackets in SI), " = "
 * and one number, right after "# " (the echo's lines are indented).  Their
 * names and texts, in the file's order (malloc'd). */
typedef struct run_stats {
    size_t n;
    char **name, **value;
} run_stats;

static void stats_free(run_stats *st)
{
    for (size_t k = 0; k < st->n; k++) {
        free(st->name[k]);
        free(st->value[k]);
    }
    free(st->name);
    free(st->value);
    memset(st, 0, sizeof *st);
}

static int is_name_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}

/* "# NAME = VALUE\n" or "# NAME[UNIT] = VALUE\n": 0 with the two parts
 * cut out of line (in place), -1 for any other line. */
static int stat_line(char *line, char **name, char **value)
{
    if (strncmp(line, "# ", 2) != 0 || !(line[2] >= 'a' && line[2] <= 'z')) return -1;
    char *p = line + 2;
    while (is_name_char(*p)) p++;
    if (*p == '[') {
        char *close = strchr(p, ']');
        if (!close) return -1;
        p = close + 1;
    }
    if (strncmp(p, " = ", 3) != 0) return -1;
    *p = '\0';
    *name = line + 2;
    *value = p + 3;
    size_t n = strcspn(*value, " \t\n");
    if ((*value)[n] != '\n' && (*value)[n] != '\0') return -1; /* "unit_time = 2e-5 s" */
    (*value)[n] = '\0';
    return n ? 0 : -1;
}

static int stats_read(const char *path, run_stats *st)
{
    memset(st, 0, sizeof *st);
    FILE *fp = fopen(path, "r");
    if (!fp) return -1;
    char *line = NULL;
    size_t cap = 0;
    int lines = 0, rc = 0;
    while (rc == 0 && getline(&line, &cap, fp) >= 0) {
        if (lines++ > 0 && line[0] != '#') break; /* the rows: the header is over */
        char *name, *value;
        if (lines == 1 || stat_line(line, &name, &value) != 0) continue;
        char **nn = realloc(st->name, (st->n + 1) * sizeof *nn);
        if (nn) st->name = nn;
        char **vv = nn ? realloc(st->value, (st->n + 1) * sizeof *vv) : NULL;
        if (vv) st->value = vv;
        if (!nn || !vv) {
            rc = -1;
            break;
        }
        st->name[st->n] = text_dup(name);
        st->value[st->n] = text_dup(value);
        st->n++;
        if (!st->name[st->n - 1] || !st->value[st->n - 1]) rc = -1;
    }
    free(line);
    fclose(fp);
    if (rc != 0) stats_free(st);
    return rc;
}

/* The file a run's summary comes from: granules.tsv, granules.partial.tsv
 * for a run that ended early, none for a run that did not run (malloc'd,
 * or NULL). */
static char *result_path(const sweep_item *it)
{
    if (sweep_has_rows(it->outcome.rc)) return text_printf("%s/granules.tsv", it->dir);
    if (it->outcome.rc != RUN_PARTIAL) return NULL;
    char *p = text_printf("%s/granules.partial.tsv", it->dir);
    struct stat st;
    if (p && stat(p, &st) != 0) {
        free(p);
        return NULL;
    }
    return p;
}

/* The columns of runs.tsv's results: every statistic any run's file has,
 * in the order they first come (runs of one sweep write the same ones,
 * but for a piston or numerics that a swept value turns off). */
typedef struct summary {
    run_stats *runs; /* by run */
    size_t n_cols;
    const char **col; /* names: borrowed from runs[] */
} summary;

static void summary_free(summary *sm, size_t n)
{
    for (size_t i = 0; sm->runs && i < n; i++) stats_free(&sm->runs[i]);
    free(sm->runs);
    free(sm->col);
    memset(sm, 0, sizeof *sm);
}

static int summary_read(const sweep *sw, summary *sm, char **msg)
{
    memset(sm, 0, sizeof *sm);
    if (!(sm->runs = calloc(sw->n ? sw->n : 1, sizeof *sm->runs))) return -1;
    size_t cap = 0;
    for (size_t i = 0; i < sw->n; i++) {
        char *path = result_path(&sw->items[i]);
        if (!path) continue;
        int rc = stats_read(path, &sm->runs[i]);
        if (rc != 0) *msg = text_printf("cannot read %s: %s", path, strerror(errno));
        free(path);
        if (rc != 0) return -1;
        for (size_t k = 0; k < sm->runs[i].n; k++) {
            const char *name = sm->runs[i].name[k];
            size_t c = 0;
            while (c < sm->n_cols && strcmp(sm->col[c], name) != 0) c++;
            if (c < sm->n_cols) continue;
            if (sm->n_cols == cap) {
                cap = cap ? 2 * cap : 32;
                const char **grown = realloc(sm->col, cap * sizeof *grown);
                if (!grown) return -1;
                sm->col = grown;
            }
            sm->col[sm->n_cols++] = name;
        }
    }
    return 0;
}

static const char *summary_value(const summary *sm, size_t i, const char *col)
{
    const run_stats *st = &sm->runs[i];
    for (size_t k = 0; k < st->n; k++)
        if (strcmp(st->name[k], col) == 0) return st->value[k];
    return "nan";
}

/* DIR/runs.tsv: each run, its swept values, how it ended, the statistics
 * of its granules.tsv (granules.partial.tsv for a run that ended early;
 * nan for one that did not run), the CPU seconds it took (the one column
 * that differs between two computations of the same sweep: the tests that
 * compare sweeps byte for byte leave it out) and the message of a run
 * without rows.
 * The column names on the first line, as in granules.tsv. */
static int write_runs_tsv(sweep *sw)
{
    const scene_config *cfg = sw->cfg;
    char *msg = NULL;
    summary sm;
    if (summary_read(sw, &sm, &msg) != 0) {
        summary_free(&sm, sw->n);
        goto fail;
    }
    out_file *f = out_open(cfg->output.dir, "runs.tsv", &msg);
    if (!f) {
        summary_free(&sm, sw->n);
        goto fail;
    }
    fputs("run\t", f->fp);
    for (size_t k = 0; k < cfg->runs.n_swept; k++) fprintf(f->fp, "%s\t", scene_swept_name(cfg, k));
    fputs("status", f->fp);
    for (size_t c = 0; c < sm.n_cols; c++) fprintf(f->fp, "\t%s", sm.col[c]);
    fputs("\tcpu_time[s]\tmessage\n", f->fp);
    fprintf(f->fp, "# taper %s runs of the sweep over ", taper_version());
    write_lead_header(cfg, f->fp);
    fputs(": status complete, untrusted (granules.tsv says why), partial "
          "(granules.partial.tsv), refused (the library refused the point), failed; then the "
          "statistics of each run's granules.tsv header (granules.partial.tsv for a partial "
          "run, nan for a run without a result: docs/scene.md, \"Result files\"), the CPU "
          "time the run took (where and when it was computed: a reused run's is its "
          "scene.hash's), and the message of a run without rows\n", f->fp);
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        fprintf(f->fp, "%s\t", it->name);
        for (size_t k = 0; k < cfg->runs.n_swept; k++) out_cell(f->fp, scene_swept_value(cfg, i, k), 0);
        fputs(status_name(it->outcome.rc), f->fp);
        for (size_t c = 0; c < sm.n_cols; c++) fprintf(f->fp, "\t%s", summary_value(&sm, i, sm.col[c]));
        if (isnan(it->outcome.cpu_seconds))
            fputs("\tnan", f->fp);
        else
            fprintf(f->fp, "\t%.6f", it->outcome.cpu_seconds);
        /* Runs with rows: no message (an untrusted one's granules.tsv says why),
         * so that runs.tsv is the same whether a run was reused or not. */
        char *why = sweep_has_rows(it->outcome.rc) ? text_dup("") : first_line(sw, it);
        fprintf(f->fp, "\t%s\n", why ? why : "");
        free(why);
    }
    summary_free(&sm, sw->n);
    if (out_commit(f, &msg) != 0) goto fail;
    printf("! wrote %s/runs.tsv\n", cfg->output.dir);
    return RUN_COMPLETE;
fail:
    return report_failure(sw, msg);
}

/* Fits, table and figure from the runs' data (failed runs: no data). */
static int write_reports(sweep *sw)
{
    const scene_config *cfg = sw->cfg;
    report_point *points = calloc(sw->n, sizeof *points);
    taper_chain_spec **specs = calloc(sw->n, sizeof *specs);
    table_data *data = calloc(sw->n, sizeof *data);
    int rc = points && specs && data ? RUN_COMPLETE : RUN_FAILED;
    for (size_t i = 0; rc == RUN_COMPLETE && i < sw->n; i++) {
        char *msg = NULL;
        if (sweep_has_rows(sw->items[i].outcome.rc) && table_read(sw->items[i].dir, &data[i], &msg) != 0) {
            fprintf(stderr, "%s: %s\n", scene_path(sw->sc), msg ? msg : "out of memory");
            free(msg);
            rc = RUN_FAILED;
            break;
        }
        taper_error err;
        if (!(specs[i] = scene_chain_spec(cfg, i, &err))) {
            fprintf(stderr, "%s: run %s: %s\n", scene_path(sw->sc), sw->items[i].name, err.message);
            rc = RUN_FAILED;
            break;
        }
        report_point *p = &points[i];
        p->spec = specs[i];
        p->param = cfg->runs.param == SCENE_PARAM_S ? taper_chain_spec_s(specs[i])
                                                    : taper_chain_spec_q(specs[i]);
        p->src.n = data[i].n;
        if (data[i].n == 0) continue;
        p->src.theory[TAPER_THEORY_V] = data[i].col[9];
        p->src.theory[TAPER_THEORY_T_RES] = data[i].col[10];
        p->src.theory[TAPER_THEORY_T] = data[i].col[11];
        if (cfg->solver.numerics)
            for (int o = 0; o < TAPER_N_OBSERVABLES; o++) p->src.obs[o] = data[i].col[4 + o];
    }
    if (rc == RUN_COMPLETE) rc = run_write_reports(sw->sc, points);
    for (size_t i = 0; specs && i < sw->n; i++) taper_chain_spec_free(specs[i]);
    for (size_t i = 0; data && i < sw->n; i++) table_free(&data[i]);
    free(data);
    free(specs);
    free(points);
    return rc;
}

/* Every file the sweep's files are built from passes its footer
 * (results/footer.h) before any is written: a run's result cut or changed
 * after it was computed is refused, naming the file, never summarised.
 * RUN_COMPLETE, or RUN_FAILED after printing why. */
static int verify_runs(const sweep *sw, int reports)
{
    int rc = RUN_COMPLETE;
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        char *paths[2] = {result_path(it), NULL};
        if (reports && sweep_has_rows(it->outcome.rc)) {
            paths[1] = text_printf("%s/report.tsv", it->dir);
            struct stat st;
            if (paths[1] && stat(paths[1], &st) != 0) {
                free(paths[1]);
                paths[1] = NULL;
            }
        }
        for (int k = 0; k < 2; k++) {
            char *msg = NULL;
            if (paths[k] && footer_verify(paths[k], NULL, &msg) != 0) {
                fprintf(stderr, "%s: %s: run %s's result is refused; remove %s and run the sweep "
                        "again to compute it anew\n", scene_path(sw->sc), msg ? msg : "out of memory",
                        it->name, it->dir);
                rc = RUN_FAILED;
            }
            free(msg);
            free(paths[k]);
        }
    }
    if (rc != RUN_COMPLETE)
        fprintf(stderr, "%s: no sweep.tsv, runs.tsv or reports written: they would summarise "
                "results that are not those the runs wrote\n", scene_path(sw->sc));
    return rc;
}

int sweep_write_results(sweep *sw)
{
    const scene_config *cfg = sw->cfg;
    int reports = cfg->runs.fit || cfg->runs.table || cfg->runs.figure;
    int rc = verify_runs(sw, reports);
    if (rc != RUN_COMPLETE) return rc;
    rc = write_sweep_tsv(sw);
    if (rc == RUN_COMPLETE) rc = write_runs_tsv(sw);
    if (rc == RUN_COMPLETE && reports) rc = write_reports(sw);
    return rc;
}
