/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * output.c -- atomic TSV result files (see output.h).
 */
#include "results/output.h"

#include "util/number.h"
#include "util/text.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

const char *const out_column_names[OUT_N_COLUMNS] = {
    "k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
    "theory_v", "theory_T", "theory_t",
};

/* The temporary file being written, for out_signal_cleanup: set and
 * cleared with the termination signals blocked, read by a signal handler.
 * Result files are written from one thread (the driver's main thread). */
static char *volatile pending_tmp;

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
    char *p = pending_tmp;
    if (p) unlink(p); /* async-signal-safe */
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

out_file *out_open(const char *dir, const char *name, char **msg)
{
    *msg = NULL;
    out_file *f = calloc(1, sizeof *f);
    char *tmpl = text_printf(".%s.XXXXXX", name);
    if (!f || !tmpl) goto nomem;
    f->tmp_path = join(dir, tmpl);
    f->final_path = join(dir, name);
    free(tmpl);
    tmpl = NULL;
    if (!f->tmp_path || !f->final_path) goto nomem;
    sigset_t old;
    block_signals(&old);
    int fd = mkstemp(f->tmp_path);
    if (fd >= 0) pending_tmp = f->tmp_path;
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

void out_discard(out_file *f)
{
    if (!f) return;
    if (f->fp) fclose(f->fp);
    sigset_t old;
    block_signals(&old);
    if (f->tmp_path) unlink(f->tmp_path);
    if (pending_tmp == f->tmp_path) pending_tmp = NULL;
    restore_signals(&old);
    free(f->tmp_path);
    free(f->final_path);
    free(f);
}

int out_commit(out_file *f, char **msg)
{
    *msg = NULL;
    int ok = !f->failed && !ferror(f->fp) && fflush(f->fp) == 0 && fsync(fileno(f->fp)) == 0;
    int err = errno;
    int closed = fclose(f->fp) == 0;
    f->fp = NULL;
    if (!ok || !closed) {
        *msg = text_printf("writing %s failed: %s", f->final_path, strerror(err ? err : EIO));
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
    pending_tmp = NULL;
    restore_signals(&old);
    free(f->tmp_path);
    f->tmp_path = NULL; /* renamed: nothing to remove */
    out_discard(f);
    return 0;
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

void out_write_rows(FILE *fp, const out_columns *cols, const char *lead_name, double lead)
{
    size_t every = cols->every ? cols->every : 1;
    for (size_t k = 1; k <= cols->n; k++) {
        if ((k - 1) % every != 0 && k != cols->n) continue;
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
