/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * journal.c -- the runs of an optimisation remembered (journal.h): a hash
 * table of points in memory, evaluations.tsv and the cache in DIR.
 */
#include "optimise/journal.h"

#include "util/number.h"
#include "util/text.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CACHE_NAME ".evaluations.cache"
#define TABLE_NAME "evaluations.tsv"
#define CACHE_MAGIC "taper-optimise-cache 1"

typedef struct entry {
    double *values;
    opt_result result;
} entry;

struct opt_journal {
    size_t p;               /* free settings                                  */
    size_t n_model;
    entry *entries;
    size_t n, cap;
    size_t *slots;          /* open addressing: index + 1, 0 empty           */
    size_t n_slots;
    FILE *table, *cache;    /* NULL: in memory only                           */
    char *dir;
};

void opt_result_free(opt_result *r)
{
    if (!r) return;
    free(r->message);
    free(r->model);
    r->message = NULL;
    r->model = NULL;
}

int opt_result_copy(opt_result *dst, const opt_result *src)
{
    *dst = *src;
    dst->message = NULL;
    dst->model = NULL;
    if (src->message && !(dst->message = text_dup(src->message))) return -1;
    if (src->model && src->n_model) {
        if (!(dst->model = malloc(src->n_model * sizeof *dst->model))) {
            free(dst->message);
            dst->message = NULL;
            return -1;
        }
        memcpy(dst->model, src->model, src->n_model * sizeof *dst->model);
    }
    return 0;
}

/* FNV-1a over bytes. */
static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *b = data;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}

static size_t slot_of(const opt_journal *j, const double *values)
{
    /* The bits of the values: a point is the same point only exactly
     * (-0.0 and 0.0 run the same chain, and hash apart: harmless). */
    return (size_t)(fnv(14695981039346656037ull, values, j->p * sizeof *values) % j->n_slots);
}

static int same(const double *a, const double *b, size_t p)
{
    return memcmp(a, b, p * sizeof *a) == 0;
}

const opt_result *opt_journal_find(const opt_journal *j, const double *values)
{
    if (!j || !j->n_slots) return NULL;
    for (size_t s = slot_of(j, values);; s = (s + 1) % j->n_slots) {
        size_t e = j->slots[s];
        if (!e) return NULL;
        if (same(j->entries[e - 1].values, values, j->p)) return &j->entries[e - 1].result;
    }
}

static int rehash(opt_journal *j)
{
    size_t n_slots = j->n_slots ? 2 * j->n_slots : 1024;
    size_t *slots = calloc(n_slots, sizeof *slots);
    if (!slots) return -1;
    free(j->slots);
    j->slots = slots;
    j->n_slots = n_slots;
    for (size_t e = 0; e < j->n; e++) {
        size_t s = slot_of(j, j->entries[e].values);
        while (j->slots[s]) s = (s + 1) % j->n_slots;
        j->slots[s] = e + 1;
    }
    return 0;
}

/* Remembers values -> r in memory (a copy).  0, or -1 out of memory. */
static int remember(opt_journal *j, const double *values, const opt_result *r)
{
    if (opt_journal_find(j, values)) return 0;
    if (j->n == j->cap) {
        size_t cap = j->cap ? 2 * j->cap : 64;
        entry *g = realloc(j->entries, cap * sizeof *g);
        if (!g) return -1;
        j->entries = g;
        j->cap = cap;
    }
    entry *e = &j->entries[j->n];
    if (!(e->values = malloc(j->p * sizeof *e->values))) return -1;
    memcpy(e->values, values, j->p * sizeof *e->values);
    if (opt_result_copy(&e->result, r) != 0) {
        free(e->values);
        return -1;
    }
    e->result.reused = 1;
    j->n++;
    if (2 * j->n > j->n_slots) return rehash(j);
    size_t s = slot_of(j, values);
    while (j->slots[s]) s = (s + 1) % j->n_slots;
    j->slots[s] = j->n;
    return 0;
}

size_t opt_journal_count(const opt_journal *j) { return j ? j->n : 0; }
const double *opt_journal_point(const opt_journal *j, size_t i)
{
    return j && i < j->n ? j->entries[i].values : NULL;
}
const opt_result *opt_journal_result(const opt_journal *j, size_t i)
{
    return j && i < j->n ? &j->entries[i].result : NULL;
}

/* ---- the files ------------------------------------------------------------------------ */

/* A message on one line: tabs and line breaks as blanks. */
static void one_line(FILE *fp, const char *s)
{
    for (; s && *s; s++) fputc(*s == '\n' || *s == '\t' || *s == '\r' ? ' ' : *s, fp);
}

static void write_table_row(opt_journal *j, const double *values, const opt_result *r,
                            double summary)
{
    static const char *const status[] = {"ok", "failed", "interrupted"};
    char num[NUMBER_SIZE];
    fprintf(j->table, "%zu\t%s", j->n, status[r->status]);
    for (size_t i = 0; i < j->p; i++) {
        number_shortest(num, values[i]);
        fprintf(j->table, "\t%s", num);
    }
    number_shortest(num, r->status == 0 ? summary : NAN);
    fprintf(j->table, "\t%s\n", num);
    if (r->message) {
        fprintf(j->table, "# run %zu: ", j->n);
        one_line(j->table, r->message);
        fputc('\n', j->table);
    }
}

static void write_cache_entry(opt_journal *j, const double *values, const opt_result *r)
{
    FILE *fp = j->cache;
    for (size_t i = 0; i < j->p; i++) fprintf(fp, "%a\t", values[i]);
    fprintf(fp, "%d\t%a\t%zu", r->status, r->objective, r->model ? r->n_model : 0);
    for (size_t i = 0; r->model && i < r->n_model; i++) fprintf(fp, "\t%a", r->model[i]);
    fputc('\t', fp);
    one_line(fp, r->message ? r->message : "-");
    fputs("\t.\n", fp); /* the end: a line without it was cut short */
}

int opt_journal_add(opt_journal *j, const double *values, const opt_result *r, double summary,
                    char **msg)
{
    if (remember(j, values, r) != 0) {
        *msg = text_printf("out of memory remembering run %zu", j->n + 1);
        return -1;
    }
    if (!j->table) return 0;
    write_table_row(j, values, r, summary);
    write_cache_entry(j, values, r);
    /* Each run on disk as it ends: an interruption loses none. */
    if (fflush(j->table) != 0 || fflush(j->cache) != 0 || ferror(j->table) || ferror(j->cache)) {
        *msg = text_printf("%s: cannot write %s or %s: %s", j->dir, TABLE_NAME, CACHE_NAME,
                           strerror(errno));
        return -1;
    }
    return 0;
}

/* One line of the cache back into memory; 0, or -1 if it is not whole. */
static int read_cache_line(opt_journal *j, char *line)
{
    double values[64];
    opt_result r = {0};
    char *p = line, *end;
    if (j->p > 64) return -1;
    for (size_t i = 0; i < j->p; i++) {
        values[i] = strtod(p, &end);
        if (end == p || *end != '\t') return -1;
        p = end + 1;
    }
    long status = strtol(p, &end, 10);
    if (end == p || *end != '\t' || status < 0 || status > 1) return -1;
    r.status = (int)status;
    p = end + 1;
    r.objective = strtod(p, &end);
    if (end == p || *end != '\t') return -1;
    p = end + 1;
    unsigned long long n = strtoull(p, &end, 10);
    if (end == p || *end != '\t' || (n && n != j->n_model)) return -1;
    p = end + 1;
    if (n && !(r.model = malloc(n * sizeof *r.model))) return -1;
    r.n_model = n;
    for (size_t i = 0; i < n; i++) {
        r.model[i] = strtod(p, &end);
        if (end == p || *end != '\t') {
            opt_result_free(&r);
            return -1;
        }
        p = end + 1;
    }
    char *tab = strchr(p, '\t');
    if (!tab || strcmp(tab, "\t.\n") != 0) {
        opt_result_free(&r);
        return -1;
    }
    *tab = '\0';
    if (strcmp(p, "-") != 0) r.message = text_dup(p);
    int rc = remember(j, values, &r);
    opt_result_free(&r);
    return rc;
}

/* The runs of an earlier attempt with the same key; the cache rewritten
 * to hold only whole lines, ready to append to.  *resumed: their number. */
static int load_cache(opt_journal *j, const char *path, const char *key, size_t *resumed)
{
    *resumed = 0;
    FILE *fp = fopen(path, "r");
    if (!fp) return 0;
    char *line = NULL;
    size_t size = 0;
    int ok = 0;
    if (getline(&line, &size, fp) > 0) {
        char head[256];
        snprintf(head, sizeof head, "%s %s\n", CACHE_MAGIC, key);
        ok = strcmp(line, head) == 0;
    }
    while (ok && getline(&line, &size, fp) > 0)
        if (read_cache_line(j, line) != 0) break; /* cut short by a kill: the rest is lost */
    free(line);
    fclose(fp);
    *resumed = ok ? j->n : 0;
    return ok;
}

opt_journal *opt_journal_open(const char *dir, const char *key, const opt_space *space,
                              const char *summary_name, size_t n_model, size_t *resumed,
                              char **msg)
{
    *msg = NULL;
    *resumed = 0;
    opt_journal *j = calloc(1, sizeof *j);
    if (!j) goto nomem;
    j->p = space->n;
    j->n_model = n_model;
    if (rehash(j) != 0) goto nomem;
    if (!dir) return j;
    if (!(j->dir = text_dup(dir))) goto nomem;
    char *cache = text_printf("%s/%s", dir, CACHE_NAME), *table = text_printf("%s/%s", dir, TABLE_NAME);
    if (!cache || !table) {
        free(cache);
        free(table);
        goto nomem;
    }
    int again = load_cache(j, cache, key, resumed);
    /* The cache rewritten whole (a line a kill cut short goes), then
     * appended to; the table appended to when resuming, else new. */
    j->cache = fopen(cache, "w");
    j->table = j->cache ? fopen(table, again ? "a" : "w") : NULL;
    if (j->cache) {
        fprintf(j->cache, "%s %s\n", CACHE_MAGIC, key);
        for (size_t e = 0; e < j->n; e++) write_cache_entry(j, j->entries[e].values, &j->entries[e].result);
        fflush(j->cache);
    }
    if (j->table && !again) {
        fputs("run\tstatus", j->table);
        for (size_t i = 0; i < space->n; i++) {
            const opt_param *p = &space->p[i];
            fprintf(j->table, "\t%s%s%s%s", p->name, p->unit ? "[" : "", p->unit ? p->unit : "",
                    p->unit ? "]" : "");
        }
        fprintf(j->table, "\t%s\n", summary_name);
        fprintf(j->table, "# taper %s: every run of the optimisation of %s, in the order made "
                "(the same command after an interruption resumes: the runs here are reused)\n",
                taper_version(), space->path);
        fflush(j->table);
    } else if (j->table) {
        fprintf(j->table, "# resumed: runs 1 to %zu above are reused\n", j->n);
        fflush(j->table);
    }
    if (!j->cache || !j->table || ferror(j->cache) || ferror(j->table)) {
        *msg = text_printf("cannot write %s: %s", j->cache ? table : cache, strerror(errno));
        free(cache);
        free(table);
        opt_journal_close(j);
        return NULL;
    }
    free(cache);
    free(table);
    return j;
nomem:
    opt_journal_close(j);
    *msg = text_printf("out of memory");
    return NULL;
}

void opt_journal_close(opt_journal *j)
{
    if (!j) return;
    if (j->table) fclose(j->table);
    if (j->cache) fclose(j->cache);
    for (size_t e = 0; e < j->n; e++) {
        free(j->entries[e].values);
        opt_result_free(&j->entries[e].result);
    }
    free(j->entries);
    free(j->slots);
    free(j->dir);
    free(j);
}

char *opt_journal_key(const char *scene_text, const char *data_path)
{
    uint64_t h = fnv(14695981039346656037ull, scene_text, strlen(scene_text));
    h = fnv(h, taper_version(), strlen(taper_version()));
    FILE *fp = data_path ? fopen(data_path, "rb") : NULL;
    if (fp) {
        char buf[65536];
        size_t n;
        while ((n = fread(buf, 1, sizeof buf, fp)) > 0) h = fnv(h, buf, n);
        fclose(fp);
    }
    return text_printf("%016llx", (unsigned long long)h);
}
