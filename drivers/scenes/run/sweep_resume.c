/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_resume.c -- a sweep's results on disk, and resuming from them
 * (sweep_resume.h).
 */
#include "run/sweep_resume.h"

#include "results/output.h"
#include "run/outdir.h"
#include "util/text.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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
    if (sweep_has_rows(o->rc) && write_stamp(sw, i, &msg) != 0) {
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

int sweep_remove_others(sweep *sw) { return outdir_clean(sw->sc, is_run_of, sw); }

void sweep_find_reusable(sweep *sw)
{
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        if (it->state != SWEEP_TODO) continue; /* another part's */
        outdir_remove_temporaries(it->dir);
        if (reusable(sw, i)) sweep_reuse(sw, i, untrusted_file(it->dir) ? RUN_UNTRUSTED : RUN_COMPLETE);
    }
}
