/*
 * output.c -- atomic TSV result files (see output.h).
 */
#include "results/output.h"

#include "util/text.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *const out_column_names[OUT_N_COLUMNS] = {
    "k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
    "theory_v", "theory_T", "theory_t",
};

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
    int fd = mkstemp(f->tmp_path);
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
    if (f->tmp_path) unlink(f->tmp_path);
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
    if (rename(f->tmp_path, f->final_path) != 0) {
        *msg = text_printf("cannot rename to %s: %s", f->final_path, strerror(errno));
        out_discard(f);
        return -1;
    }
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

void out_cell(FILE *fp, double x, int last)
{
    if (isnan(x))
        fputs("nan", fp);
    else
        fprintf(fp, "%.17g", x);
    fputc(last ? '\n' : '\t', fp);
}

void out_write_rows(FILE *fp, const out_columns *cols, const char *lead_name, double lead,
                    int header)
{
    if (header) {
        if (lead_name) fprintf(fp, "%s\t", lead_name);
        for (size_t c = 0; c < OUT_N_COLUMNS; c++)
            fprintf(fp, "%s%c", out_column_names[c], c + 1 < OUT_N_COLUMNS ? '\t' : '\n');
    }
    for (size_t k = 1; k <= cols->n; k++) {
        if (lead_name) out_cell(fp, lead, 0);
        fprintf(fp, "%zu\t", k);
        for (size_t c = 1; c < OUT_N_COLUMNS; c++)
            out_cell(fp, cols->col[c] ? cols->col[c][k - 1] : NAN, c + 1 == OUT_N_COLUMNS);
    }
}

void out_write_table(FILE *fp, const out_columns *cols) { out_write_rows(fp, cols, NULL, 0, 1); }
