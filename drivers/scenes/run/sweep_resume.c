/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_resume.c -- a sweep's results on disk, and resuming from them
 * (sweep_resume.h).
 */
#include "run/sweep_resume.h"

#include "results/footer.h"
#include "results/output.h"
#include "run/outdir.h"
#include "util/text.h"

#include <inttypes.h>
#include <math.h>
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

/* The first lines of run i's scene.hash: taper's version, the run, and the
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

/* The result files of a run that scene.hash vouches for, each by its
 * footer (results/footer.h): a file cut, changed or copied from another
 * run after the stamp no longer matches it.  granules.tsv always; the
 * others when the run wrote them. */
static const char *const stamped[] = {"granules.tsv", "report.tsv", "sensors.tsv", "walls.tsv",
                                      "spacetime.tsv"};

/* The lines naming run dir's files ("granules.tsv rows 200 crc32 1a2b3c4d"),
 * each file verified against its footer first (malloc'd).  NULL with *why
 * (malloc'd; NULL: out of memory) when one fails or granules.tsv is
 * missing. */
static char *files_text(const char *dir, char **why)
{
    *why = NULL;
    char *text = text_dup("");
    for (size_t k = 0; text && k < sizeof stamped / sizeof stamped[0]; k++) {
        char *path = text_printf("%s/%s", dir, stamped[k]);
        if (!path) {
            free(text);
            return NULL;
        }
        struct stat st;
        if (k > 0 && stat(path, &st) != 0) { /* not written by this run */
            free(path);
            continue;
        }
        footer_info f;
        if (footer_verify(path, &f, why) != 0) {
            free(path);
            free(text);
            return NULL;
        }
        free(path);
        char *more = text_printf("%s%s rows %" PRIu64 " crc32 %08" PRIx32 "\n", text, stamped[k],
                                 f.rows, f.crc);
        free(text);
        text = more;
    }
    return text;
}

static char *read_small_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    char buf[4096];
    size_t n = fread(buf, 1, sizeof buf - 1, fp);
    fclose(fp);
    buf[n] = '\0';
    return text_dup(buf);
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

/* The last line of a stamp: the CPU time the run took (runs.tsv's
 * cpu_time[s]), a measurement, not part of what the stamp vouches for. */
#define CPU_LINE "cpu_time[s] "

/* The CPU seconds of a stamp's last line after `vouched` (the text the
 * run's scene and files give), or NaN when it has none; -1 when anything
 * else follows. */
static double stamp_cpu(const char *have, const char *vouched)
{
    const size_t n = strlen(vouched);
    if (strncmp(have, vouched, n) != 0) return -1.0;
    const char *rest = have + n;
    if (!*rest) return NAN; /* a stamp of a taper that did not record it */
    if (strncmp(rest, CPU_LINE, strlen(CPU_LINE)) != 0) return -1.0;
    char *end;
    const double cpu = strtod(rest + strlen(CPU_LINE), &end);
    return end != rest + strlen(CPU_LINE) && strcmp(end, "\n") == 0 && cpu >= 0.0 ? cpu : -1.0;
}

/* 1: run i's complete result is on disk, made from this scene, every file
 * as the run wrote it (*cpu: the CPU time its stamp records, or NaN).  A
 * result whose stamp matches but whose files do not (cut, changed, another
 * run's copied in) is said on stdout and computed again. */
static int reusable(const sweep *sw, size_t i, double *cpu)
{
    *cpu = NAN;
    const sweep_item *it = &sw->items[i];
    char *path = text_printf("%s/scene.hash", it->dir);
    char *have = path ? read_small_file(path) : NULL;
    char *want = stamp_text(sw, i);
    free(path);
    int ok = have && want && strncmp(have, want, strlen(want)) == 0;
    if (ok) {
        char *why = NULL, *files = files_text(it->dir, &why);
        char *whole = files ? text_printf("%s%s", want, files) : NULL;
        *cpu = whole ? stamp_cpu(have, whole) : -1.0;
        ok = !(*cpu < 0.0); /* NaN: vouched for, no CPU time recorded */
        if (!ok && files)
            why = text_printf("%s: its result files are not those its scene.hash vouches for "
                              "(changed or copied in after the run)", it->dir);
        if (!ok)
            printf("! run %s: %s: computed again\n", it->name, why ? why : "out of memory");
        free(why);
        free(files);
        free(whole);
    }
    free(have);
    free(want);
    return ok;
}

static int write_stamp(const sweep *sw, size_t i, double cpu_seconds, char **msg)
{
    char *why = NULL;
    char *head = stamp_text(sw, i), *files = head ? files_text(sw->items[i].dir, &why) : NULL;
    if (!files) {
        *msg = why ? why : text_printf("%s/scene.hash: out of memory", sw->items[i].dir);
        free(head);
        return -1;
    }
    out_file *f = out_open(sw->items[i].dir, "scene.hash", msg);
    if (f) {
        fprintf(f->fp, "%s%s", head, files);
        if (cpu_seconds >= 0.0) fprintf(f->fp, CPU_LINE "%.6f\n", cpu_seconds);
    }
    free(head);
    free(files);
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
    if (sweep_has_rows(o->rc) && write_stamp(sw, i, o->cpu_seconds, &msg) != 0) {
        /* without its stamp the run is done again on resume */
        append_log(o, scene_path(sw->sc), msg ? msg : "out of memory");
        o->rc = out_was_stopped(msg) ? RUN_PARTIAL : RUN_FAILED;
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

size_t sweep_find_reusable(sweep *sw)
{
    size_t removed = 0;
    for (size_t i = 0; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        if (it->state != SWEEP_TODO) continue; /* another part's */
        removed += outdir_remove_temporaries(it->dir);
        double cpu;
        if (reusable(sw, i, &cpu))
            sweep_reuse(sw, i, untrusted_file(it->dir) ? RUN_UNTRUSTED : RUN_COMPLETE, cpu);
    }
    return removed;
}
