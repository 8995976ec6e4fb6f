/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * measurements.c -- a table of measurements read and checked
 * (measurements.h): the header's columns and units, then the rows.
 */
#include "optimise/measurements.h"

#include "util/number.h"
#include "util/text.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bytes in one line, and lines in a table: an oscilloscope's record of a
 * few sensors is far below either. */
#define MEAS_MAX_LINE 65536
#define MEAS_MAX_POINTS 50000000u

/* ---- the vocabulary: taper's own column names -------------------------------- */

static const struct {
    const char *name;
    taper_dimension dim;
} quantities[MEAS_N_QUANTITIES] = {
    [MEAS_X] = {"x", TAPER_DIM_LENGTH},
    [MEAS_V] = {"v", TAPER_DIM_VELOCITY},
    [MEAS_F_LEFT] = {"f_left", TAPER_DIM_FORCE},
    [MEAS_F_RIGHT] = {"f_right", TAPER_DIM_FORCE},
    [MEAS_FORCE] = {"force", TAPER_DIM_FORCE},
    [MEAS_WALL_LEFT] = {"force_left", TAPER_DIM_FORCE},
    [MEAS_WALL_RIGHT] = {"force_right", TAPER_DIM_FORCE},
    [MEAS_T_PASS] = {"t_pass", TAPER_DIM_TIME},
    [MEAS_T_RES] = {"T_res", TAPER_DIM_TIME},
    [MEAS_V_PEAK] = {"v_peak", TAPER_DIM_VELOCITY},
    [MEAS_T_PEAK] = {"t_peak", TAPER_DIM_TIME},
    [MEAS_X_PASS] = {"X_pass", TAPER_DIM_LENGTH},
};

const char *meas_quantity_name(meas_quantity q)
{
    return (unsigned)q < MEAS_N_QUANTITIES ? quantities[q].name : NULL;
}

taper_dimension meas_quantity_dimension(meas_quantity q)
{
    return (unsigned)q < MEAS_N_QUANTITIES ? quantities[q].dim : TAPER_DIM_NUMBER;
}

int meas_quantity_observable(meas_quantity q)
{
    return q >= MEAS_T_PASS && q <= MEAS_X_PASS ? (int)(q - MEAS_T_PASS) : -1;
}

/* The measured quantities of each form, and what it says of itself. */
static const struct {
    const char *file;           /* the taper file of this form              */
    const char *key;            /* its key column: granule, k, t             */
    meas_quantity first, last;  /* its measured quantities                   */
    const char *columns;        /* every column it may have, for messages    */
} forms[] = {
    [MEAS_SENSORS] = {"sensors.tsv", "granule", MEAS_X, MEAS_FORCE,
                      "t granule x v f_left f_right force"},
    [MEAS_WALLS] = {"walls.tsv", "t", MEAS_WALL_LEFT, MEAS_WALL_RIGHT,
                    "t force_left force_right"},
    [MEAS_GRANULES] = {"granules.tsv", "k", MEAS_T_PASS, MEAS_X_PASS,
                       "k t_pass T_res v_peak t_peak X_pass (R m X0 theory_v theory_T "
                       "theory_t skipped)"},
};

/* granules.tsv's columns that are not measurements: skipped, with their
 * units checked all the same. */
static const struct {
    const char *name;
    taper_dimension dim;
} skipped[] = {{"R", TAPER_DIM_SIZE},          {"m", TAPER_DIM_MASS},
               {"X0", TAPER_DIM_SIZE},         {"theory_v", TAPER_DIM_VELOCITY},
               {"theory_T", TAPER_DIM_TIME},   {"theory_t", TAPER_DIM_TIME}};

/* ---- a line cut into fields -------------------------------------------------- */

typedef struct fields {
    char *text;        /* the line, cut in place                           */
    char **field;
    int *start;        /* 1-based character column of each field          */
    size_t n, cap;
} fields;

static int is_separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == '\r' || c == '\n'; }

/* Cuts line (modified) at separators; a '#' ends it.  0, or -1 out of
 * memory. */
static int split(fields *f, char *line)
{
    f->n = 0;
    char *hash = strchr(line, '#');
    if (hash) *hash = '\0';
    for (char *p = line; *p;) {
        while (*p && is_separator(*p)) p++;
        if (!*p) break;
        if (f->n == f->cap) {
            size_t cap = f->cap ? 2 * f->cap : 16;
            char **fl = realloc(f->field, cap * sizeof *fl);
            int *st = fl ? realloc(f->start, cap * sizeof *st) : NULL;
            if (fl) f->field = fl;
            if (!fl || !st) return -1;
            f->start = st;
            f->cap = cap;
        }
        f->start[f->n] = (int)(p - line) + 1;
        f->field[f->n++] = p;
        while (*p && !is_separator(*p)) p++;
        if (*p) *p++ = '\0';
    }
    return 0;
}

/* ---- errors ------------------------------------------------------------------- */

typedef struct reader {
    const char *path;
    int line;
    char **msg;
    int failed;
} reader;

static void fail_at(reader *r, int column, const char *fmt, ...) TEXT_PRINTF(3, 4);
static void fail_at(reader *r, int column, const char *fmt, ...)
{
    if (r->failed) return;
    r->failed = 1;
    va_list ap;
    va_start(ap, fmt);
    char *what = text_vprintf(fmt, ap);
    va_end(ap);
    if (column > 0)
        *r->msg = text_printf("%s:%d:%d: %s", r->path, r->line, column, what ? what : "out of memory");
    else
        *r->msg = text_printf("%s:%d: %s", r->path, r->line, what ? what : "out of memory");
    free(what);
}

/* ---- the header --------------------------------------------------------------- */

/* What one column of the header is. */
typedef enum col_role { COL_SKIP = 0, COL_TIME, COL_GRANULE, COL_MEASURED } col_role;

typedef struct column {
    col_role role;
    meas_quantity q;       /* COL_MEASURED                                  */
    int fitted;            /* COL_MEASURED chosen by `columns`              */
    char *name;            /* as the header writes it, unit included        */
} column;

/* NAME[UNIT] -> name, unit (NULL without brackets), in place. */
static int name_and_unit(char *text, char **unit)
{
    *unit = NULL;
    char *open = strchr(text, '[');
    if (!open) return strchr(text, ']') ? -1 : 0;
    size_t n = strlen(text);
    if (n < 2 || text[n - 1] != ']' || open == text) return -1;
    text[n - 1] = '\0';
    *open = '\0';
    *unit = open + 1;
    return strchr(*unit, '[') || strchr(*unit, ']') ? -1 : 0;
}

static int find_quantity(const char *name, meas_quantity first, meas_quantity last,
                         meas_quantity *q)
{
    for (int i = (int)first; i <= (int)last; i++)
        if (strcmp(quantities[i].name, name) == 0) {
            *q = (meas_quantity)i;
            return 0;
        }
    return -1;
}

/* The form of a table from its key column. */
static int form_of(const fields *f, meas_form *form)
{
    int has_t = 0;
    for (size_t i = 0; i < f->n; i++) {
        char *bracket = strchr(f->field[i], '[');
        size_t len = bracket ? (size_t)(bracket - f->field[i]) : strlen(f->field[i]);
        if (len == 7 && strncmp(f->field[i], "granule", 7) == 0) {
            *form = MEAS_SENSORS;
            return 0;
        }
        if (len == 1 && f->field[i][0] == 'k') {
            *form = MEAS_GRANULES;
            return 0;
        }
        if (len == 1 && f->field[i][0] == 't') has_t = 1;
    }
    if (!has_t) return -1;
    *form = MEAS_WALLS;
    return 0;
}

/* The unit taper writes for dim with &material ("s", "N"). */
static const char *si_unit(taper_dimension dim) { return taper_dimension_unit(dim); }

/* Checks a column's unit: none for numbers; for the others SI or none,
 * the same choice for every column (*si: -1 undecided). */
static void check_unit(reader *r, int col, const char *name, const char *unit,
                       taper_dimension dim, int *si, const char **si_column)
{
    if (dim == TAPER_DIM_NUMBER) {
        if (unit)
            fail_at(r, col, "%s[%s]: %s is a number and has no unit (write %s)", name, unit, name,
                    name);
        return;
    }
    const char *want = si_unit(dim);
    if (unit && strcmp(unit, want) != 0) {
        fail_at(r, col, "%s[%s]: taper reads %s in %s (as it writes it: %s[%s]); convert the "
                "column to %s, or leave the unit out for rescaled units", name, unit, name, want,
                name, want, want);
        return;
    }
    int has = unit != NULL;
    if (*si < 0) {
        *si = has;
        *si_column = name;
    } else if (*si != has) {
        fail_at(r, col, "%s%s%s%s: column %s %s a unit and this one %s: give every column its "
                "SI unit as taper writes it (%s[%s]), or none (rescaled units)", name,
                has ? "[" : "", has ? unit : "", has ? "]" : "", *si_column,
                *si ? "has" : "has no", has ? "has one" : "has none", name, want);
    }
}

static int read_header(reader *r, fields *f, measurements *m, column **cols_out)
{
    meas_form form;
    if (form_of(f, &form) != 0) {
        fail_at(r, 0, "the first line names no column t, granule or k: it must name the "
                "columns as taper writes them (sensors.tsv: %s; walls.tsv: %s; granules.tsv: "
                "k t_pass ...)", forms[MEAS_SENSORS].columns, forms[MEAS_WALLS].columns);
        return -1;
    }
    m->form = form;
    column *cols = calloc(f->n, sizeof *cols);
    if (!cols) {
        fail_at(r, 0, "out of memory");
        return -1;
    }
    *cols_out = cols;
    int si = -1;
    const char *si_column = NULL;
    for (size_t i = 0; i < f->n && !r->failed; i++) {
        int col = f->start[i];
        if (!(cols[i].name = text_dup(f->field[i]))) {
            fail_at(r, col, "out of memory");
            break;
        }
        char *unit, *name = f->field[i];
        if (name_and_unit(name, &unit) != 0) {
            fail_at(r, col, "'%s' is not NAME or NAME[UNIT]", cols[i].name);
            break;
        }
        for (size_t j = 0; j < i; j++) {
            char *other = text_dup(cols[j].name), *ou;
            int same = other && name_and_unit(other, &ou) == 0 && strcmp(other, name) == 0;
            free(other);
            if (same) {
                fail_at(r, col, "column %s is given twice (columns %zu and %zu)", name, j + 1, i + 1);
                break;
            }
        }
        if (r->failed) break;
        meas_quantity q;
        if (strcmp(name, "t") == 0 && form != MEAS_GRANULES) {
            cols[i].role = COL_TIME;
            m->time_column = (int)i + 1;
            check_unit(r, col, name, unit, TAPER_DIM_TIME, &si, &si_column);
        } else if (strcmp(name, forms[form].key) == 0 && form != MEAS_WALLS) {
            cols[i].role = form == MEAS_SENSORS ? COL_GRANULE : COL_TIME;
            if (form == MEAS_SENSORS) m->granule_column = (int)i + 1;
            else m->time_column = (int)i + 1;
            check_unit(r, col, name, unit, TAPER_DIM_NUMBER, &si, &si_column);
        } else if (find_quantity(name, forms[form].first, forms[form].last, &q) == 0) {
            cols[i].role = COL_MEASURED;
            cols[i].q = q;
            check_unit(r, col, name, unit, quantities[q].dim, &si, &si_column);
        } else {
            int known = 0;
            for (size_t j = 0; form == MEAS_GRANULES && j < sizeof skipped / sizeof skipped[0]; j++)
                if (strcmp(skipped[j].name, name) == 0) {
                    known = 1;
                    check_unit(r, col, name, unit, skipped[j].dim, &si, &si_column);
                }
            if (!known)
                fail_at(r, col, "unknown column '%s': a table in the form of taper's %s (it has "
                        "column %s) has the columns %s", name, forms[form].file, forms[form].key,
                        forms[form].columns);
        }
    }
    if (r->failed) return -1;
    if (!m->time_column) {
        fail_at(r, 0, "no column t: a table in the form of %s gives the time of each row "
                "(t[s], or t in rescaled units)", forms[form].file);
        return -1;
    }
    m->si = si > 0;
    return 0;
}

/* `columns` of the scene: the measured columns fitted (all by default). */
static int choose(column *cols, size_t n, const char *columns, const char *path, char **msg)
{
    const char *p = columns ? columns : "";
    int named = 0;
    while (*p) {
        size_t len = strcspn(p, " ,\t");
        if (len == 0) {
            p++;
            continue;
        }
        int found = 0;
        for (size_t i = 0; i < n; i++)
            if (cols[i].role == COL_MEASURED && strlen(quantities[cols[i].q].name) == len &&
                strncmp(quantities[cols[i].q].name, p, len) == 0)
                found = cols[i].fitted = 1;
        if (!found) {
            char *list = NULL;
            size_t size = 0;
            FILE *fp = open_memstream(&list, &size);
            for (size_t i = 0; fp && i < n; i++)
                if (cols[i].role == COL_MEASURED) fprintf(fp, " %s", quantities[cols[i].q].name);
            if (fp) fclose(fp);
            *msg = text_printf("columns: '%.*s' is not a measured column of %s (it has:%s)",
                               (int)(len > 64 ? 64 : len), p, path, list && size ? list : " none");
            free(list);
            return -1;
        }
        named = 1;
        p += len;
    }
    int any = 0;
    for (size_t i = 0; i < n; i++) {
        if (cols[i].role == COL_MEASURED && !named) cols[i].fitted = 1;
        any |= cols[i].fitted;
    }
    if (!any) {
        *msg = text_printf("%s:1: no measured column: give one of the quantities of taper's "
                           "files (force[N], v[m/s], t_pass[s], ...)", path);
        return -1;
    }
    return 0;
}

/* ---- the rows ------------------------------------------------------------------- */

static int number(reader *r, const fields *f, size_t i, const column *c, double *x)
{
    char *end;
    errno = 0;
    *x = strtod(f->field[i], &end);
    if (end == f->field[i] || *end) {
        fail_at(r, f->start[i], "%s: '%.40s' is not a number", c->name, f->field[i]);
        return -1;
    }
    if (!isfinite(*x) || errno == ERANGE) {
        fail_at(r, f->start[i], "%s: '%.40s' is not a measurement (a finite number): leave the "
                "row out, or its value", c->name, f->field[i]);
        return -1;
    }
    return 0;
}

static int push(measurements *m, size_t *cap, const meas_point *p)
{
    if (m->n == *cap) {
        size_t c = *cap ? 2 * *cap : 1024;
        meas_point *g = realloc(m->points, c * sizeof *g);
        if (!g) return -1;
        m->points = g;
        *cap = c;
    }
    m->points[m->n++] = *p;
    return 0;
}

static int read_row(reader *r, const fields *f, size_t n_cols, const column *cols,
                    measurements *m, size_t *cap)
{
    if (f->n != n_cols) {
        fail_at(r, f->n > n_cols ? f->start[n_cols] : 0,
                "%zu values, but the first line names %zu columns", f->n, n_cols);
        return -1;
    }
    double t = NAN, granule = 0;
    for (size_t i = 0; i < n_cols; i++) {
        if (cols[i].role == COL_TIME) {
            if (number(r, f, i, &cols[i], &t) != 0) return -1;
            if (m->form == MEAS_GRANULES) {
                granule = t;
                t = NAN;
            } else if (t < 0) {
                fail_at(r, f->start[i], "%s: time %s is before the run's start (t = 0: the "
                        "impact)", cols[i].name, f->field[i]);
                return -1;
            }
        } else if (cols[i].role == COL_GRANULE) {
            if (number(r, f, i, &cols[i], &granule) != 0) return -1;
        }
    }
    if (m->form != MEAS_WALLS && !(granule >= 1 && granule == floor(granule) && granule <= 1e7)) {
        int gc = m->form == MEAS_SENSORS ? m->granule_column : m->time_column;
        fail_at(r, f->start[gc - 1], "%s: '%s' is not a granule (a whole number from 1)",
                cols[gc - 1].name, f->field[gc - 1]);
        return -1;
    }
    for (size_t i = 0; i < n_cols; i++) {
        if (cols[i].role != COL_MEASURED || !cols[i].fitted) continue;
        meas_point p = {.t = t, .granule = (size_t)granule, .q = cols[i].q, .line = r->line,
                        .column = f->start[i]};
        if (number(r, f, i, &cols[i], &p.value) != 0) return -1;
        if (m->n >= MEAS_MAX_POINTS) {
            fail_at(r, f->start[i], "more than %u measurements: thin the table", MEAS_MAX_POINTS);
            return -1;
        }
        if (push(m, cap, &p) != 0) {
            fail_at(r, 0, "out of memory");
            return -1;
        }
        if (fabs(p.value) > m->peak[p.q]) m->peak[p.q] = fabs(p.value);
    }
    return 0;
}

/* ---- the table ----------------------------------------------------------------- */

void meas_free(measurements *m)
{
    if (!m) return;
    free(m->points);
    free(m->path);
    free(m);
}

static int blank(const char *line)
{
    for (; *line && *line != '#'; line++)
        if (!isspace((unsigned char)*line)) return 0;
    return 1;
}

measurements *meas_read(const char *path, const char *columns, char **msg)
{
    *msg = NULL;
    measurements *m = calloc(1, sizeof *m);
    fields f = {0};
    column *cols = NULL;
    size_t n_cols = 0, cap = 0;
    reader r = {.path = path, .msg = msg};
    FILE *fp = m ? fopen(path, "r") : NULL;
    if (!m || !(m->path = text_dup(path))) {
        *msg = text_printf("%s: out of memory", path);
        goto fail;
    }
    if (!fp) {
        *msg = text_printf("%s: cannot open: %s", path, strerror(errno));
        goto fail;
    }
    char *line = NULL;
    size_t size = 0;
    ssize_t len;
    int header = 0;
    while (!r.failed && (len = getline(&line, &size, fp)) >= 0) {
        r.line++;
        if (len > MEAS_MAX_LINE) {
            fail_at(&r, 0, "line longer than %d characters: not a table of measurements",
                    MEAS_MAX_LINE);
            break;
        }
        if (memchr(line, '\0', (size_t)len)) {
            fail_at(&r, 0, "binary data: not a text table of measurements");
            break;
        }
        if (blank(line)) continue;
        if (split(&f, line) != 0) {
            fail_at(&r, 0, "out of memory");
            break;
        }
        if (!header) {
            header = 1;
            n_cols = f.n;
            if (read_header(&r, &f, m, &cols) != 0) break;
            if (choose(cols, n_cols, columns, path, msg) != 0) r.failed = 1;
            for (size_t i = 0; !r.failed && i < n_cols; i++)
                if (cols[i].fitted) m->quantity_column[m->n_quantities] = (int)i + 1,
                                    m->quantity[m->n_quantities++] = cols[i].q;
            continue;
        }
        read_row(&r, &f, n_cols, cols, m, &cap);
    }
    if (!r.failed && ferror(fp)) fail_at(&r, 0, "read error: %s", strerror(errno));
    free(line);
    if (!r.failed && !header) {
        *msg = text_printf("%s: empty: no line names the columns", path);
        r.failed = 1;
    }
    if (!r.failed && m->n == 0) {
        *msg = text_printf("%s: no measurement below the first line", path);
        r.failed = 1;
    }
    if (r.failed) goto fail;
    fclose(fp);
    for (size_t i = 0; i < n_cols; i++) free(cols[i].name);
    free(cols);
    free(f.field);
    free(f.start);
    return m;
fail:
    if (fp) fclose(fp);
    for (size_t i = 0; cols && i < n_cols; i++) free(cols[i].name);
    free(cols);
    free(f.field);
    free(f.start);
    meas_free(m);
    if (!*msg) *msg = text_printf("%s: out of memory", path);
    return NULL;
}

double meas_last_time(const measurements *m)
{
    double last = 0;
    for (size_t i = 0; m->form != MEAS_GRANULES && i < m->n; i++)
        if (m->points[i].t > last) last = m->points[i].t;
    return last;
}

static int fail_point(const measurements *m, const meas_point *p, int column, char **msg,
                      const char *fmt, ...) TEXT_PRINTF(5, 6);
static int fail_point(const measurements *m, const meas_point *p, int column, char **msg,
                      const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *what = text_vprintf(fmt, ap);
    va_end(ap);
    *msg = text_printf("%s:%d:%d: %s", m->path, p->line, column, what ? what : "out of memory");
    free(what);
    return -1;
}

int meas_check(const measurements *m, const meas_run_limits *lim, char **msg)
{
    *msg = NULL;
    const char *unit = m->si ? " s" : "";
    for (size_t i = 0; i < m->n; i++) {
        const meas_point *p = &m->points[i];
        int key = m->form == MEAS_SENSORS ? m->granule_column : m->time_column;
        if (m->form != MEAS_WALLS && p->granule > lim->n_granules)
            return fail_point(m, p, key, msg, "granule %zu is beyond the chain (n_granules = %zu)",
                              p->granule, lim->n_granules);
        if (p->q == MEAS_WALL_LEFT && !lim->wall_left)
            return fail_point(m, p, p->column, msg, "force_left: the scene has no left wall "
                              "(&ends left = 'wall')");
        if (p->q == MEAS_WALL_RIGHT && !lim->wall_right)
            return fail_point(m, p, p->column, msg, "force_right: the scene has no right wall "
                              "(&ends right = 'wall')");
        if (m->form == MEAS_GRANULES) continue;
        char t[NUMBER_SIZE], end[NUMBER_SIZE];
        number_shortest(t, p->t);
        if (lim->t_max > 0 && p->t >= lim->t_max) {
            number_shortest(end, lim->t_max);
            return fail_point(m, p, m->time_column, msg, "time %s%s is beyond the run: it ends "
                              "at &solver t_max = %s%s; raise t_max (0: no limit)", t, unit, end,
                              unit);
        }
        if (lim->t_end > 0 && p->t > lim->t_end) {
            number_shortest(end, lim->t_end);
            return fail_point(m, p, m->time_column, msg, "time %s%s is beyond the run: it ends "
                              "at &solver t_end = %s%s; raise t_end, or leave it out (the "
                              "calibration then runs to the last measured time)", t, unit, end,
                              unit);
        }
    }
    return 0;
}
