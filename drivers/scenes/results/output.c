/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * output.c -- atomic TSV result files (see output.h).
 */
#include "results/output.h"

#include "results/footer.h"
#include "util/number.h"
#include "util/text.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

const char *const out_column_names[OUT_N_COLUMNS] = {
    "k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
    "theory_v", "theory_T", "theory_t",
};

/* The temporary files being written, for out_signal_cleanup: one slot per
 * writing thread (the main thread, or the workers of a sweep), set and
 * cleared with the termination signals blocked, read by a signal handler. */
#define PENDING_SLOTS 512
static char *_Atomic pending_tmp[PENDING_SLOTS];

static int (*stop_signal)(void);
static _Thread_local out_mode mode = OUT_WHOLE;

void out_set_stop_check(int (*check)(void)) { stop_signal = check; }

static int stop_now(void) { return stop_signal ? stop_signal() : 0; }

int out_stop_signal(void) { return stop_now(); }

void out_set_mode(out_mode m) { mode = m; }

static void block_signals(sigset_t *old)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    sigaddset(&set, SIGXCPU);
    pthread_sigmask(SIG_BLOCK, &set, old);
}

static void restore_signals(const sigset_t *old) { pthread_sigmask(SIG_SETMASK, old, NULL); }

void out_signal_cleanup(void)
{
    for (int i = 0; i < PENDING_SLOTS; i++) {
        char *p = atomic_load(&pending_tmp[i]);
        if (p) unlink(p); /* async-signal-safe */
    }
}

/* A free slot for path (with the signals blocked), -1 if none: that file
 * is then not removed by a second signal, but by the next run into its
 * directory (out_remove_temporaries). */
static int take_slot(char *path)
{
    for (int i = 0; i < PENDING_SLOTS; i++) {
        char *none = NULL;
        if (atomic_compare_exchange_strong(&pending_tmp[i], &none, path)) return i;
    }
    return -1;
}

static void release_slot(out_file *f)
{
    if (f->slot >= 0) atomic_store(&pending_tmp[f->slot], NULL);
    f->slot = -1;
}

static char *join(const char *dir, const char *name)
{
    size_t a = strlen(dir), b = strlen(name);
    char *p = malloc(a + b + 2);
    if (!p) return NULL;
    memcpy(p, dir, a);
    p[a] = '/';
    memcpy(p + a + 1, name, b + 1);
    return p;
}

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int out_mkdir_p(const char *dir, char **msg)
{
    *msg = NULL;
    size_t n = strlen(dir);
    char *p = malloc(n + 1);
    if (!p) {
        *msg = text_printf("%s: out of memory", dir);
        return -1;
    }
    memcpy(p, dir, n + 1);
    /* Create each prefix in turn; EEXIST is fine if it is a directory. */
    for (size_t i = 1; i <= n; i++) {
        if (p[i] != '/' && p[i] != '\0') continue;
        char c = p[i];
        p[i] = '\0';
        if (mkdir(p, 0777) != 0 && !(errno == EEXIST && is_dir(p))) {
            *msg = text_printf("cannot create output directory %s: %s", p,
                               errno == EEXIST ? "exists and is not a directory" : strerror(errno));
            free(p);
            return -1;
        }
        p[i] = c;
    }
    free(p);
    return 0;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

out_file *out_open(const char *dir, const char *name, char **msg)
{
    *msg = NULL;
    out_file *f = calloc(1, sizeof *f);
    char *tmpl = text_printf(".%s.XXXXXX", name);
    if (!f || !tmpl) goto nomem;
    f->slot = -1;
    f->footer = ends_with(name, ".tsv");
    f->stoppable = mode == OUT_WHOLE;
    f->tmp_path = join(dir, tmpl);
    f->final_path = join(dir, name);
    free(tmpl);
    tmpl = NULL;
    if (!f->tmp_path || !f->final_path) goto nomem;
    if (out_stopping(f)) { /* nothing starts after the signal */
        *msg = out_stopped_message(f);
        free(f->tmp_path);
        f->tmp_path = NULL;
        out_discard(f);
        return NULL;
    }
    sigset_t old;
    block_signals(&old);
    int fd = mkstemp(f->tmp_path);
    if (fd >= 0) f->slot = take_slot(f->tmp_path);
    restore_signals(&old);
    if (fd < 0) {
        *msg = text_printf("cannot write in output directory %s: %s", dir, strerror(errno));
        free(f->tmp_path);
        f->tmp_path = NULL;
        out_discard(f);
        return NULL;
    }
    /* mkstemp creates 0600; results are ordinary files. */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    if (!(f->fp = fdopen(fd, "w"))) {
        close(fd);
        *msg = text_printf("%s: %s", f->tmp_path, strerror(errno));
        out_discard(f);
        return NULL;
    }
    return f;
nomem:
    free(tmpl);
    *msg = text_printf("%s/%s: out of memory", dir, name);
    out_discard(f);
    return NULL;
}

int out_stopping(out_file *f)
{
    if (!f->stopped && f->stoppable && stop_now()) f->stopped = 1;
    return f->stopped;
}

static const char stopped_words[] = " not written: interrupted by a signal";

char *out_stopped_message(const out_file *f)
{
    return text_printf("%s%s", f->final_path, stopped_words);
}

int out_was_stopped(const char *msg)
{
    size_t n = msg ? strlen(msg) : 0, k = sizeof stopped_words - 1;
    return n >= k && strcmp(msg + n - k, stopped_words) == 0;
}

void out_discard(out_file *f)
{
    if (!f) return;
    if (f->fp) fclose(f->fp);
    sigset_t old;
    block_signals(&old);
    if (f->tmp_path) unlink(f->tmp_path);
    release_slot(f);
    restore_signals(&old);
    free(f->tmp_path);
    free(f->final_path);
    free(f);
}

/* The footer of what fd holds (results/footer.h), read back from the file
 * as written: the checksum is of the bytes on disk, not of a buffer.  0,
 * or -1 with errno. */
static int footer_of(int fd, char line[FOOTER_SIZE])
{
    footer_sum s;
    footer_start(&s);
    char *buf = malloc(1 << 16);
    if (!buf) return -1;
    off_t at = 0;
    for (ssize_t r; (r = pread(fd, buf, 1 << 16, at)) != 0; at += r) {
        if (r < 0) {
            if (errno == EINTR) {
                r = 0;
                continue;
            }
            free(buf);
            return -1;
        }
        footer_add(&s, buf, (size_t)r);
    }
    free(buf);
    footer_line(&s, line);
    return 0;
}

int out_commit(out_file *f, char **msg)
{
    *msg = NULL;
    if (out_stopping(f)) {
        *msg = out_stopped_message(f);
        out_discard(f);
        return -1;
    }
    /* errno: the last failed write's, when the stream saw one (stdio keeps
     * only the flag; no call since has failed) */
    int ok = !f->failed && !ferror(f->fp) && fflush(f->fp) == 0;
    if (ok && f->footer) {
        char line[FOOTER_SIZE];
        ok = footer_of(fileno(f->fp), line) == 0 && fputs(line, f->fp) >= 0 &&
             fflush(f->fp) == 0;
    }
    if (ok) ok = fsync(fileno(f->fp)) == 0;
    int err = errno;
    int closed = fclose(f->fp) == 0;
    if (ok && !closed) err = errno;
    f->fp = NULL;
    if (!ok || !closed) {
        *msg = text_printf("writing %s failed: %s (the incomplete file is removed)",
                           f->final_path, strerror(err ? err : EIO));
        out_discard(f);
        return -1;
    }
    /* The rename and forgetting the temporary name happen with the signals
     * blocked: a handler sees either the temporary file or none. */
    sigset_t old;
    block_signals(&old);
    if (rename(f->tmp_path, f->final_path) != 0) {
        int e = errno;
        restore_signals(&old);
        *msg = text_printf("cannot rename to %s: %s", f->final_path, strerror(e));
        out_discard(f);
        return -1;
    }
    release_slot(f);
    restore_signals(&old);
    free(f->tmp_path);
    f->tmp_path = NULL; /* renamed: nothing to remove */
    out_discard(f);
    return 0;
}

/* .NAME.XXXXXX: mkstemp's six characters after NAME. */
static int is_temporary_of(const char *entry, const char *name)
{
    size_t n = strlen(name);
    return entry[0] == '.' && strncmp(entry + 1, name, n) == 0 && entry[n + 1] == '.' &&
           strlen(entry + n + 2) == 6;
}

size_t out_remove_temporaries(const char *dir, const char *const *names, size_t n)
{
    DIR *d = opendir(dir);
    if (!d) return 0;
    size_t removed = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        int ours = 0;
        for (size_t i = 0; i < n && !ours; i++) ours = is_temporary_of(e->d_name, names[i]);
        if (!ours) continue;
        char *p = join(dir, e->d_name);
        if (p && unlink(p) == 0) removed++;
        free(p);
    }
    closedir(d);
    return removed;
}

int out_remove(const char *dir, const char *name, char **msg)
{
    *msg = NULL;
    char *p = join(dir, name);
    if (!p) {
        *msg = text_printf("%s/%s: out of memory", dir, name);
        return -1;
    }
    int rc = 0;
    if (unlink(p) != 0 && errno != ENOENT) {
        *msg = text_printf("cannot remove stale %s: %s", p, strerror(errno));
        rc = -1;
    }
    free(p);
    return rc;
}

/* One number, the shortest text that reads back to it (number_shortest:
 * exact integer arithmetic, much faster than fprintf, which took 5-8 % of a
 * long run's CPU time in granules.tsv). */
static void put_number(FILE *fp, double x)
{
    char buf[NUMBER_SIZE];
    fwrite(buf, 1, (size_t)number_shortest(buf, x), fp);
}

void out_cell(FILE *fp, double x, int last)
{
    if (isnan(x))
        fputs("nan", fp);
    else
        put_number(fp, x);
    fputc(last ? '\n' : '\t', fp);
}

static int column_on(const out_columns *cols, size_t c)
{
    return cols->set == 0 || (cols->set >> c & 1u);
}

void out_write_header(FILE *fp, const out_columns *cols, const char *lead_name)
{
    if (lead_name) fprintf(fp, "%s\t", lead_name);
    fputs(out_column_names[0], fp);
    for (size_t c = 1; c < OUT_N_COLUMNS; c++) {
        if (!column_on(cols, c)) continue;
        fprintf(fp, "\t%s", out_column_names[c]);
        if (cols->unit[c]) fprintf(fp, "[%s]", cols->unit[c]);
    }
    fputc('\n', fp);
}

void out_write_rows(out_file *f, const out_columns *cols, const char *lead_name, double lead)
{
    FILE *fp = f->fp;
    size_t every = cols->every ? cols->every : 1;
    for (size_t k = 1; k <= cols->n; k++) {
        if ((k - 1) % every != 0 && k != cols->n) continue;
        if ((k & 4095) == 0 && out_stopping(f)) return;
        if (lead_name) out_cell(fp, lead, 0);
        fprintf(fp, "%zu", k);
        for (size_t c = 1; c < OUT_N_COLUMNS; c++) {
            if (!column_on(cols, c)) continue;
            fputc('\t', fp);
            double x = cols->col[c] ? cols->col[c][k - 1] : NAN;
            if (isnan(x))
                fputs("nan", fp);
            else
                put_number(fp, x);
        }
        fputc('\n', fp);
    }
}
