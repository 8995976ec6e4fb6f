/*
 * sweep.c -- the runs of a sweep (sweep.h).
 *
 * Each run is prepared, computed and written on its own (run_point) by a
 * worker thread or an MPI rank, so that a sweep of thousands of long
 * chains holds one chain per worker in memory; the main thread prints each
 * run's messages in the order of the sweep as soon as the runs before it
 * are done (the same text whatever the threads and ranks), shows the
 * progress, and at the end builds sweep.tsv and the reports from the runs'
 * granules.tsv, which hold every number to the last bit (%.17g), so that
 * the results do not depend on where a run was computed, or when.
 */
#include "run/sweep.h"

#include "results/analysis.h"
#include "results/output.h"
#include "run/outdir.h"
#include "run/run.h"
#include "util/text.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* ---- the sweep object ------------------------------------------------------- */

enum { TODO = 0, RUNNING = 1, DONE = 2 };

typedef struct sweep_item {
    char *name;          /* q=0.05,exponent=2.5                        */
    char *dir;           /* DIR/name                                    */
    double cost;         /* estimate: the granules the pulse crosses    */
    int state;
    int reused;          /* its result was on disk                      */
    int elsewhere;       /* another part's run (--part)                 */
    run_outcome outcome; /* rc, and the text it printed                 */
} sweep_item;

struct sweep {
    const scene *sc;
    const scene_config *cfg;
    size_t n;
    sweep_item *items;
    size_t *order;       /* dearest first                               */
    size_t next;         /* into order                                  */
    pthread_mutex_t lock;
    pthread_cond_t cond;
    size_t done, reused, failed, untrusted, computed;
    double cost_done, cost_todo;
};

/* A run whose rows are in sweep.tsv: complete, trusted or not. */
static int has_rows(int rc) { return rc == RUN_COMPLETE || rc == RUN_UNTRUSTED; }

static const sweep_remote *remote;
static size_t only_part, n_parts; /* --part only_part/n_parts; 0: all */

void sweep_set_remote(const sweep_remote *r) { remote = r; }

void sweep_set_part(size_t part, size_t parts)
{
    only_part = part;
    n_parts = parts;
}

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The granules the pulse crosses: the cost of a run grows with them (a
 * theory-only run costs next to nothing). */
static double estimate(const scene_config *cfg, size_t point)
{
    scene_config at;
    scene_config_at(cfg, point, &at);
    double n = scene_setting(&at, "n_granules"), last = scene_setting(&at, "last_granule");
    if (last > 0 && last < n) n = last;
    return at.solver.numerics ? n : 1e-3 * n;
}

static const sweep *sort_sweep; /* qsort has no context argument */

static int dearest_first(const void *a, const void *b)
{
    size_t i = *(const size_t *)a, j = *(const size_t *)b;
    double ci = sort_sweep->items[i].cost, cj = sort_sweep->items[j].cost;
    if (ci != cj) return ci > cj ? -1 : 1;
    return i < j ? -1 : i > j;
}

sweep *sweep_open(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    sweep *sw = calloc(1, sizeof *sw);
    if (!sw) return NULL;
    sw->sc = sc;
    sw->cfg = cfg;
    sw->n = cfg->runs.n;
    sw->items = calloc(sw->n, sizeof *sw->items);
    sw->order = calloc(sw->n, sizeof *sw->order);
    if (!sw->items || !sw->order) goto fail;
    pthread_mutex_init(&sw->lock, NULL);
    pthread_cond_init(&sw->cond, NULL);
    for (size_t i = 0; i < sw->n; i++) {
        sweep_item *it = &sw->items[i];
        if (!(it->name = scene_point_name(cfg, i))) goto fail;
        if (!(it->dir = text_printf("%s/%s", cfg->output.dir, it->name))) goto fail;
        it->cost = estimate(cfg, i);
        sw->order[i] = i;
    }
    sort_sweep = sw;
    qsort(sw->order, sw->n, sizeof *sw->order, dearest_first);
    return sw;
fail:
    sweep_close(sw);
    return NULL;
}

void sweep_close(sweep *sw)
{
    if (!sw) return;
    for (size_t i = 0; sw->items && i < sw->n; i++) {
        free(sw->items[i].name);
        free(sw->items[i].dir);
        run_outcome_free(&sw->items[i].outcome);
    }
    if (sw->items && sw->order) {
        pthread_mutex_destroy(&sw->lock);
        pthread_cond_destroy(&sw->cond);
    }
    free(sw->items);
    free(sw->order);
    free(sw);
}

size_t sweep_size(const sweep *sw) { return sw->n; }

size_t sweep_next(sweep *sw)
{
    size_t i = SIZE_MAX;
    pthread_mutex_lock(&sw->lock);
    while (!run_interrupted() && sw->next < sw->n) {
        size_t j = sw->order[sw->next++];
        if (sw->items[j].state != TODO) continue; /* reused */
        sw->items[j].state = RUNNING;
        i = j;
        break;
    }
    pthread_mutex_unlock(&sw->lock);
    return i;
}

void sweep_done(sweep *sw, size_t i, run_outcome *o)
{
    pthread_mutex_lock(&sw->lock);
    sweep_item *it = &sw->items[i];
    run_outcome_free(&it->outcome);
    it->outcome = *o;
    memset(o, 0, sizeof *o);
    it->state = DONE;
    sw->done++;
    sw->computed++;
    sw->cost_done += it->cost;
    if (!has_rows(it->outcome.rc)) sw->failed++;
    if (it->outcome.rc == RUN_UNTRUSTED) sw->untrusted++;
    pthread_cond_broadcast(&sw->cond);
    pthread_mutex_unlock(&sw->lock);
}

/* ---- scene.hash: which scene a run's result was made from ---------------- */

/* FNV-1a, 64 bits: a change of the scene, not an adversary. */
static uint64_t fnv1a(const char *s, size_t n, uint64_t h)
{
    for (size_t i = 0; i < n; i++) {
        h ^= (unsigned char)s[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* The text scene.hash holds for run i: taper's version, the run, and the
 * hash of what its granules.tsv echoes (scene path, resolved scene at the
 * point). */
static char *stamp_text(const sweep *sw, size_t i)
{
    char *echo = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&echo, &len);
    if (!mem) return NULL;
    fprintf(mem, "taper %s\nscene file: %s\n", taper_version(), scene_path(sw->sc));
    scene_write_point(sw->sc, mem, i);
    if (fclose(mem) != 0) {
        free(echo);
        return NULL;
    }
    uint64_t h = fnv1a(echo, len, 14695981039346656037ull);
    free(echo);
    return text_printf("taper %s run %s\nscene %016llx\n", taper_version(), sw->items[i].name,
                       (unsigned long long)h);
}

static char *read_small_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    char buf[1024];
    size_t n = fread(buf, 1, sizeof buf - 1, fp);
    fclose(fp);
    buf[n] = '\0';
    return text_dup(buf);
}

static int file_exists(const char *dir, const char *name)
{
    char *p = text_printf("%s/%s", dir, name);
    struct stat st;
    int ok = p && stat(p, &st) == 0 && S_ISREG(st.st_mode);
    free(p);
    return ok;
}

/* 1: DIR/granules.tsv says "# UNTRUSTED: ..." in its comment block. */
static int untrusted_file(const char *dir)
{
    char *path = text_printf("%s/granules.tsv", dir);
    FILE *fp = path ? fopen(path, "r") : NULL;
    free(path);
    if (!fp) return 0;
    char *line = NULL;
    size_t cap = 0;
    int found = 0, lines = 0;
    while (!found && getline(&line, &cap, fp) >= 0) {
        if (lines++ > 0 && line[0] != '#') break; /* the rows: the block is over */
        found = strncmp(line, "# UNTRUSTED:", 12) == 0;
    }
    free(line);
    fclose(fp);
    return found;
}

/* 1: run i's complete result is on disk, made from this scene. */
static int reusable(const sweep *sw, size_t i)
{
    const sweep_item *it = &sw->items[i];
    if (!file_exists(it->dir, "granules.tsv")) return 0;
    char *path = text_printf("%s/scene.hash", it->dir);
    char *have = path ? read_small_file(path) : NULL;
    char *want = stamp_text(sw, i);
    int ok = have && want && strcmp(have, want) == 0;
    free(path);
    free(have);
    free(want);
    return ok;
}

static int write_stamp(const sweep *sw, size_t i, char **msg)
{
    char *text = stamp_text(sw, i);
    if (!text) {
        *msg = text_printf("%s/scene.hash: out of memory", sw->items[i].dir);
        return -1;
    }
    out_file *f = out_open(sw->items[i].dir, "scene.hash", msg);
    if (f) fputs(text, f->fp);
    free(text);
    return f ? out_commit(f, msg) : -1;
}

/* Appends "LABEL: message\n" to an outcome's log. */
static void append_log(run_outcome *o, const char *label, const char *message)
{
    char *joined = text_printf("%s%s: %s\n", o->log ? o->log : "", label, message);
    if (!joined) return;
    free(o->log);
    o->log = joined;
}

void sweep_compute(sweep *sw, size_t i, run_outcome *o)
{
    const sweep_item *it = &sw->items[i];
    char *msg = NULL;
    /* No stamp while the result is being replaced: a run stopped halfway
     * is never taken for done. */
    char *stamp = text_printf("%s/scene.hash", it->dir);
    if (stamp) unlink(stamp);
    free(stamp);
    run_point(sw->sc, i, it->dir, it->name, o);
    if (has_rows(o->rc) && write_stamp(sw, i, &msg) != 0) {
        append_log(o, scene_path(sw->sc), msg ? msg : "out of memory");
        o->rc = RUN_FAILED;
    }
    free(msg);
}

/* ---- earlier results in the output directory (run/outdir.c) ------------------ */

/* outdir_clean's test: NAME is a run of this sweep (kept). */
static int is_run_of(const char *name, const void *data)
{
    const sweep *sw = data;
    for (size_t i = 0; i < sw->n; i++)
        if (strcmp(sw->items[i].name, name) == 0) return 1;
    return 0;
}


/* ---- printing in the order of the sweep, progress ---------------------------- */

typedef struct printer {
    size_t committed;    /* runs 0..committed-1 printed                    */
    int show;            /* a progress line on a terminal                  */
    double every;        /* seconds between lines: 0.25 on a terminal;
                            under mpirun, which hides the terminal from
                            the ranks, a line of its own every 10 s         */
    int on_screen;
    double start, last;
    unsigned ranks, threads;
} printer;

static void clear_progress(printer *p)
{
    if (p->on_screen) fputs("\r\033[K", stderr);
    p->on_screen = 0;
}

static void show_progress(printer *p, sweep *sw, int force)
{
    if (!p->show) return;
    double now = wall_seconds();
    if (!force && now - p->last < p->every) return;
    p->last = now;
    pthread_mutex_lock(&sw->lock);
    size_t done = sw->done, reused = sw->reused, failed = sw->failed, computed = sw->computed;
    double cost_done = sw->cost_done, cost_todo = sw->cost_todo;
    pthread_mutex_unlock(&sw->lock);
    double elapsed = now - p->start;
    double rate = computed ? (double)computed / fmax(elapsed, 1e-9) : 0;
    fprintf(stderr, "%staper: runs %zu/%zu", p->every > 1 ? "" : "\r\033[K", done, sw->n);
    if (reused) fprintf(stderr, " (%zu reused)", reused);
    if (failed) fprintf(stderr, " %zu failed", failed);
    if (computed) {
        /* Time left from the estimated costs of what is left. */
        double left = cost_done > 0 ? elapsed * (cost_todo - cost_done) / cost_done : NAN;
        fprintf(stderr, "  %.3g runs/s", rate);
        if (isfinite(left)) fprintf(stderr, "  %.0f s left", fmax(left, 0));
    }
    fprintf(stderr, "  [%u rank%s x %u thread%s]", p->ranks, p->ranks == 1 ? "" : "s", p->threads,
            p->threads == 1 ? "" : "s");
    if (p->every > 1) {
        fputc('\n', stderr); /* a log line */
    } else {
        p->on_screen = 1;
    }
    fflush(stderr);
}

/* Prints the runs that are done and have every earlier run done. */
static void commit(printer *p, sweep *sw)
{
    for (;;) {
        pthread_mutex_lock(&sw->lock);
        int ready = p->committed < sw->n && sw->items[p->committed].state == DONE;
        pthread_mutex_unlock(&sw->lock);
        if (!ready) return;
        const sweep_item *it = &sw->items[p->committed++];
        clear_progress(p);
        if (it->outcome.log) fputs(it->outcome.log, stderr);
        if (it->outcome.out) fputs(it->outcome.out, stdout);
        if (it->reused) printf("! reused %s/granules.tsv\n", it->dir);
        if (it->elsewhere) continue;
        fflush(stdout);
        fflush(stderr);
    }
}

/* ---- local threads ----------------------------------------------------------- */

static void *worker(void *arg)
{
    sweep *sw = arg;
    for (size_t i; (i = sweep_next(sw)) != SIZE_MAX;) {
        run_outcome o;
        sweep_compute(sw, i, &o);
        sweep_done(sw, i, &o);
    }
    return NULL;
}

static unsigned online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (unsigned)n : 1u;
}

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

/* Reads the numbers of a run back, every one as computed (%.17g), for the
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
        if (has_rows(it->outcome.rc)) continue;
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
        if (!has_rows(sw->items[i].outcome.rc)) continue;
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
        if (!has_rows(it->outcome.rc)) continue;
        char lead[SCENE_MAX_SWEPT * 32 + 1];
        size_t used = 0;
        for (size_t k = 0; k < cfg->runs.n_swept; k++) {
            double x = scene_swept_value(cfg, i, k); /* out_cell's spelling */
            used += (size_t)snprintf(lead + used, sizeof lead - used,
                                     isnan(x) ? "nan\t" : "%.17g\t", x);
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
    fprintf(stderr, "%s: %s\n", scene_path(sw->sc), msg ? msg : "out of memory");
    free(msg);
    return RUN_FAILED;
}

/* DIR/runs.tsv: each run, its swept values and how it ended. */
static int write_runs_tsv(sweep *sw)
{
    const scene_config *cfg = sw->cfg;
    char *msg = NULL;
    out_file *f = out_open(cfg->output.dir, "runs.tsv", &msg);
    if (!f) goto fail;
    fprintf(f->fp, "# taper %s runs of the sweep over ", taper_version());
    write_lead_header(cfg, f->fp);
    fputs(": status complete, untrusted (granules.tsv says why), partial "
          "(granules.partial.tsv), refused (the library refused the point), failed\nrun\t",
          f->fp);
    for (size_t k = 0; k < cfg->runs.n_swept; k++) fprintf(f->fp, "%s\t", scene_swept_name(cfg, k));
    fputs("status\tmessage\n", f->fp);
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        fprintf(f->fp, "%s\t", it->name);
        for (size_t k = 0; k < cfg->runs.n_swept; k++) out_cell(f->fp, scene_swept_value(cfg, i, k), 0);
        /* Runs with rows: no message (an untrusted one's granules.tsv says why),
         * so that runs.tsv is the same whether a run was reused or not. */
        char *why = has_rows(it->outcome.rc) ? text_dup("") : first_line(sw, it);
        fprintf(f->fp, "%s\t%s\n", status_name(it->outcome.rc), why ? why : "");
        free(why);
    }
    if (out_commit(f, &msg) != 0) goto fail;
    printf("! wrote %s/runs.tsv\n", cfg->output.dir);
    return RUN_COMPLETE;
fail:
    fprintf(stderr, "%s: %s\n", scene_path(sw->sc), msg ? msg : "out of memory");
    free(msg);
    return RUN_FAILED;
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
        if (has_rows(sw->items[i].outcome.rc) && table_read(sw->items[i].dir, &data[i], &msg) != 0) {
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

/* ---- the sweep ------------------------------------------------------------------ */

static int prepare(const scene *sc, sweep *sw)
{
    const scene_config *cfg = scene_cfg(sc);
    /* Created and locked: parts of one sweep share the lock (--part). */
    if (run_lock_dir(sc, cfg->output.dir, n_parts > 1) != 0) return RUN_INPUT;
    int rc = outdir_clean(sc, is_run_of, sw);
    if (rc != RUN_COMPLETE) return rc;
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        if (cfg->runs.n_swept == 1) {
            char num[SCENE_REAL_TEXT];
            scene_swept_text(cfg, i, 0, num);
            printf("! sweep %s = %s -> %s\n", scene_swept_name(cfg, 0), num, it->dir);
        } else {
            printf("! sweep %s -> %s\n", it->name, it->dir);
        }
        sw->cost_todo += it->cost;
        if (n_parts > 1) {
            /* Part k of n: positions k-1, k-1+n, ... of the dearest-first order. */
            size_t pos = 0;
            while (sw->order[pos] != i) pos++;
            if (pos % n_parts != only_part - 1) {
                sw->items[i].elsewhere = 1;
                sw->items[i].state = DONE;
                sw->done++;
                sw->cost_todo -= it->cost;
                continue;
            }
        }
        outdir_remove_temporaries(it->dir);
        if (reusable(sw, i)) {
            sw->items[i].reused = 1;
            sw->items[i].state = DONE;
            sw->items[i].outcome.rc = untrusted_file(it->dir) ? RUN_UNTRUSTED : RUN_COMPLETE;
            sw->untrusted += sw->items[i].outcome.rc == RUN_UNTRUSTED;
            sw->done++;
            sw->reused++;
            sw->cost_todo -= it->cost;
        }
    }
    size_t mine = sw->n;
    for (size_t i = 0; i < sw->n; i++) mine -= sw->items[i].elsewhere;
    if (n_parts > 1)
        printf("! part %zu/%zu: %zu of the %zu runs\n", only_part, n_parts, mine, sw->n);
    if (sw->reused)
        printf("! resuming: %zu of %zu runs reused (their results are on disk, from the same "
               "scene), %zu to compute\n", sw->reused, mine, mine - sw->reused);
    fflush(stdout);
    return RUN_COMPLETE;
}

int sweep_run(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    sweep *sw = sweep_open(sc);
    if (!sw) {
        fprintf(stderr, "%s: out of memory\n", scene_path(sc));
        if (remote) remote->finish(NULL, remote->ctx);
        return RUN_FAILED;
    }
    int rc = prepare(sc, sw);
    if (rc != RUN_COMPLETE) {
        if (remote) remote->finish(NULL, remote->ctx); /* nothing to hand out */
        sweep_close(sw);
        return rc;
    }

    unsigned threads = (unsigned)cfg->output.threads;
    if (threads == 0) threads = remote ? remote->threads : online_cpus();
    if (threads > 256) threads = 256;
    size_t todo = sw->n - sw->reused;
    if (!remote && threads > todo) threads = todo ? (unsigned)todo : 1;
    int tty = isatty(STDERR_FILENO);
    printer p = {.show = cfg->output.progress && (tty || remote), .every = tty ? 0.25 : 10,
                 .start = wall_seconds(), .ranks = remote ? remote->ranks : 1,
                 .threads = threads};
    p.last = tty ? 0 : p.start;
    pthread_t tid[256];
    unsigned started = 0;
    for (; started < threads; started++)
        if (pthread_create(&tid[started], NULL, worker, sw) != 0) break;
    if (started == 0) worker(sw); /* no thread: here */

    /* Print runs in order as they finish; serve the other ranks. */
    for (;;) {
        if (remote) remote->serve(sw, remote->ctx);
        commit(&p, sw);
        show_progress(&p, sw, 0);
        pthread_mutex_lock(&sw->lock);
        size_t running = 0;
        for (size_t i = 0; i < sw->n; i++) running += sw->items[i].state == RUNNING;
        int finished = sw->done == sw->n || ((run_interrupted() || sw->next >= sw->n) && running == 0);
        if (!finished) {
            struct timespec ts;
            clock_gettime(CLOCK_REALTIME, &ts);
            long wait_ns = remote ? 1000000L : 200000000L; /* MPI: poll each ms */
            ts.tv_nsec += wait_ns;
            if (ts.tv_nsec >= 1000000000L) {
                ts.tv_sec++;
                ts.tv_nsec -= 1000000000L;
            }
            pthread_cond_timedwait(&sw->cond, &sw->lock, &ts);
        }
        pthread_mutex_unlock(&sw->lock);
        if (finished) break;
    }
    for (unsigned t = 0; t < started; t++) pthread_join(tid[t], NULL);
    if (remote) remote->finish(sw, remote->ctx);
    commit(&p, sw);
    show_progress(&p, sw, 1);
    clear_progress(&p);

    if (sw->done < sw->n || run_interrupted()) {
        /* What the runs done after the first one missing printed. */
        for (size_t i = p.committed; i < sw->n; i++) {
            const sweep_item *it = &sw->items[i];
            if (it->state != DONE) continue;
            if (it->outcome.log) fputs(it->outcome.log, stderr);
            if (it->outcome.out) fputs(it->outcome.out, stdout);
        }
        fflush(stdout);
        size_t complete = 0;
        for (size_t i = 0; i < sw->n; i++)
            complete += sw->items[i].state == DONE && has_rows(sw->items[i].outcome.rc);
        fprintf(stderr, "%s: interrupted: %zu of %zu runs complete; run the same command to "
                "resume (complete runs are reused)\n", scene_path(sc), complete, sw->n);
        sweep_close(sw);
        return RUN_PARTIAL;
    }
    if (n_parts > 1) {
        size_t complete = 0, mine = 0;
        for (size_t i = 0; i < sw->n; i++) {
            if (sw->items[i].elsewhere) continue;
            mine++;
            complete += has_rows(sw->items[i].outcome.rc);
        }
        printf("! part %zu/%zu done: %zu of its %zu runs complete; once every part is done, "
               "`taper %s` (without --part) merges them: it reuses their runs and writes "
               "sweep.tsv\n", only_part, n_parts, complete, mine, scene_path(sc));
        sweep_close(sw);
        return complete == mine ? RUN_COMPLETE : RUN_SOME_FAILED;
    }
    int reports = cfg->runs.fit || cfg->runs.table || cfg->runs.figure;
    rc = write_sweep_tsv(sw);
    if (rc == RUN_COMPLETE) rc = write_runs_tsv(sw);
    if (rc == RUN_COMPLETE && reports) rc = write_reports(sw);
    if (rc == RUN_COMPLETE && sw->failed) {
        fprintf(stderr, "%s: %zu of %zu runs failed (sweep.tsv and runs.tsv name them)\n",
                scene_path(sc), sw->failed, sw->n);
        rc = RUN_SOME_FAILED;
    } else if (rc == RUN_COMPLETE && sw->untrusted) {
        rc = RUN_UNTRUSTED; /* each run's granules.tsv and message say why */
    }
    sweep_close(sw);
    return rc;
}
