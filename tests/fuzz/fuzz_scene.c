/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * fuzz_scene.c -- libFuzzer harness for the scene parser and validation
 * (drivers/scenes/scene/scene*.c), and for what a valid scene feeds into the library.
 *
 * For every input:
 *   1. scene_parse: any bytes; errors must come with a message.
 *   2. scene_validate on a scene that parsed.
 *   3. A scene that validates must survive its own echo: scene_write, parse
 *      the text again, validate again (0 errors) and write again: the two
 *      texts are identical (the driver's resolved-scene echo must run again
 *      to the same numbers).
 *   4. Its specs (every sweep point) are built through the library's
 *      setters and go to taper_chain_alloc, taper_theory_compute and
 *      taper_sim_alloc (not run): building the specs of a validated scene
 *      never fails (validation made those very calls), and what the library
 *      can only check with the chain built (ERANGE of the masses, last_granule
 *      beyond N) names a field the scene reports at a key.
 * A violated property aborts (a libFuzzer finding); sanitizers catch the rest.
 *
 * Built two ways (tests/fuzz/meson.build):
 *   - fuzz_scene        -Dfuzz=true with clang: linked with -fsanitize=fuzzer;
 *   - fuzz_scene_replay -DFUZZ_REPLAY_MAIN: a plain main() that feeds every
 *     file of the directories (or files) given to the same function, run by
 *     `meson test --suite fuzz` over tests/fuzz/regressions and the seeds.
 * See docs/robustness.md.
 */
#include "scene/scene.h"
#include "taper.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The library is not asked to build chains longer than this per input:
 * fuzzing wants many inputs per second (N up to 1e7 is valid). */
#define FUZZ_MAX_GRANULES 4096
#define FUZZ_MAX_SWEEP 4
#define FUZZ_MAX_SHOWN 2000

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_scene: property violated: %s%s%s\n", what, detail ? ": " : "",
            detail ? detail : "");
    abort();
}

static FILE *null_stream(void)
{
    static FILE *devnull;
    if (!devnull) devnull = fopen("/dev/null", "w");
    return devnull;
}

/* Every recorded diagnostic has a non-empty message. */
static void check_diags(const scene *sc, size_t errors)
{
    size_t n = scene_diag_count(sc);
    if (errors > 0 && n == 0) fail("errors counted but no diagnostic recorded", NULL);
    if (n > SCENE_MAX_DIAGS) fail("more diagnostics than slots", NULL);
    for (size_t i = 0; i < n; i++) {
        const scene_diag *d = scene_diag_at(sc, i);
        if (!d->message || !d->group || !d->key) fail("diagnostic without text", NULL);
        if (d->message[0] == '\0') fail("empty diagnostic message", NULL);
        if (d->line < 0) fail("negative line number", d->message);
    }
    FILE *fp = null_stream();
    if (fp) scene_print_diags(sc, fp);
}

/* The scene as namelist text (malloc'd; NULL if out of memory). */
static char *scene_text(const scene *sc, size_t *len)
{
    char *text = NULL;
    FILE *fp = open_memstream(&text, len);
    if (!fp) return NULL;
    scene_write(sc, fp, 0);
    fclose(fp);
    return text;
}

/* Property 3: echo -> parse -> validate -> echo is a fixed point.  Every
 * valid scene is checked, the longest lists too: their echo fits the file
 * limit (SCENE_MAX_LIST, finding B in docs/robustness.md, fixed) and takes
 * a few seconds at most (250000 values). */
static void check_round_trip(const scene *sc)
{
    size_t len1 = 0, len2 = 0;
    char *text1 = scene_text(sc, &len1);
    if (!text1) return;
    scene *again = scene_new(scene_path(sc));
    if (!again) {
        free(text1);
        return;
    }
    size_t errors = scene_parse(again, text1, len1);
    if (errors == 0) errors = scene_validate(again);
    if (errors != 0) {
        const scene_diag *d = scene_diag_at(again, 0);
        fprintf(stderr, "--- echo:\n%.*s--- error: line %d &%s %s: %s\n", FUZZ_MAX_SHOWN, text1,
                d ? d->line : 0, d ? d->group : "", d ? d->key : "", d ? d->message : "");
        fail("the echo of a valid scene does not parse and validate", NULL);
    }
    char *text2 = scene_text(again, &len2);
    if (text2 && (len1 != len2 || memcmp(text1, text2, len1) != 0)) {
        fprintf(stderr, "--- first echo:\n%.*s--- second echo:\n%.*s", FUZZ_MAX_SHOWN, text1,
                FUZZ_MAX_SHOWN, text2);
        fail("the echo is not a fixed point", NULL);
    }
    /* The other writers must not crash on any valid scene either. */
    FILE *fp = null_stream();
    if (fp) {
        scene_write(again, fp, 1);
        size_t points = scene_cfg(again)->runs.n;
        for (size_t i = 0; i < points && i < FUZZ_MAX_SWEEP; i++) scene_write_point(again, fp, i);
    }
    free(text2);
    free(text1);
    scene_free(again);
}

/* A refusal after validation must name a field the scene reports at a key,
 * with a message. */
static void check_refusal(const scene *sc, scene_lib lib, const taper_error *err,
                          const char *what)
{
    if (err->message[0] == '\0') fail(what, "failed without a message");
    if (err->status == TAPER_ENOMEM) return;
    FILE *fp = null_stream();
    if (fp) scene_print_library_error(sc, lib, err, fp);
    if (err->status == TAPER_EINVAL && !err->field) fail(what, err->message);
}

/* Property 4: the library accepts what validation accepted, up to what
 * needs the chain. */
static void check_library(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    for (size_t i = 0; i < cfg->runs.n && i < FUZZ_MAX_SWEEP; i++) {
        taper_error err = {0};
        taper_chain_spec *cs = scene_chain_spec(cfg, i, &err);
        if (!cs) {
            if (err.status != TAPER_ENOMEM) fail("the chain spec of a valid scene fails", err.message);
            return;
        }
        taper_solver_spec *ss = scene_solver_spec(cfg, &err);
        if (!ss) {
            if (err.status != TAPER_ENOMEM) fail("the solver spec of a valid scene fails", err.message);
            taper_chain_spec_free(cs);
            return;
        }
        /* One swept variable or none: validation checked the relations at
         * every run.  Several: some runs may break them (they fail alone,
         * marked by the sweep), but then the refusal names a field and
         * another run holds (validation refuses a grid where none does). */
        if (taper_chain_spec_check(cs, &err) != TAPER_OK) {
            if (cfg->runs.n_swept <= 1)
                fail("validated scene refused by taper_chain_spec_check", err.message);
            check_refusal(sc, SCENE_LIB_CHAIN, &err, "taper_chain_spec_check");
            taper_chain_spec_free(cs);
            taper_solver_spec_free(ss);
            continue;
        }
        if (taper_chain_spec_n_granules(cs) > FUZZ_MAX_GRANULES) {
            taper_chain_spec_free(cs);
            taper_solver_spec_free(ss);
            return;
        }
        taper_chain *chain = taper_chain_alloc(cs, &err);
        if (!chain) {
            check_refusal(sc, SCENE_LIB_CHAIN, &err, "taper_chain_alloc");
            if (err.status == TAPER_EINVAL) fail("validated scene rejected by taper_chain_alloc", err.message);
        } else {
            size_t n = taper_chain_size(chain);
            double *v = malloc(n * sizeof *v), *T = malloc(n * sizeof *T), *t = malloc(n * sizeof *t);
            if (v && T && t) {
                int st = taper_theory_compute(chain, v, NULL, T, t, &err);
                if (st != TAPER_OK && err.message[0] == '\0') fail("theory failed without a message", NULL);
                /* Where the binary collision approximation does not describe
                 * the chain (a load, losses, a decorated chain beyond its
                 * effective chain) every column is NaN and the chain says
                 * why; a decorated chain has columns at its large granules
                 * only (the first of each period but the last), NaN at the
                 * small ones;
                 * elsewhere every value is finite and positive. */
                const char *note = taper_chain_theory_note(chain);
                size_t period = 1;
                if (taper_chain_profile(chain) == TAPER_DECORATED) taper_chain_spec_pattern(cs, &period);
                if (st == TAPER_OK)
                    for (size_t k = 0; k + 1 < n; k++) {
                        /* The last period's large granule has no next
                         * effective granule to collide with. */
                        int given = !note && k % period == 0 && (period == 1 || k + period < n);
                        int valid = v[k] > 0.0 && T[k] > 0.0 && isfinite(t[k]);
                        int absent = isnan(v[k]) && isnan(T[k]) && isnan(t[k]);
                        int each = (isnan(v[k]) || (v[k] > 0.0 && isfinite(v[k]))) &&
                                   (isnan(T[k]) || (T[k] > 0.0 && isfinite(T[k]))) &&
                                   (isnan(t[k]) || isfinite(t[k]));
                        if (given && !valid)
                            fail("theory returned a non-finite or non-positive value with TAPER_OK", NULL);
                        if (!given && !absent && note)
                            fail("theory columns given although the chain says why they cannot be", note);
                        if (!given && !each)
                            fail("theory column neither a value nor NaN", NULL);
                    }
            }
            free(v);
            free(T);
            free(t);
            taper_sim *sim = taper_sim_alloc(chain, ss, &err);
            if (!sim) check_refusal(sc, SCENE_LIB_SOLVER, &err, "taper_sim_alloc");
            taper_sim_free(sim);
            taper_chain_free(chain);
        }
        taper_chain_spec_free(cs);
        taper_solver_spec_free(ss);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    scene *sc = scene_new("fuzz.nml");
    if (!sc) return 0;
    size_t errors = scene_parse(sc, (const char *)data, size);
    check_diags(sc, errors);
    if (errors == 0) {
        errors = scene_validate(sc);
        check_diags(sc, errors);
        if (errors == 0) {
            check_round_trip(sc);
            check_library(sc);
        }
    }
    scene_free(sc);
    return 0;
}

#ifdef FUZZ_REPLAY_MAIN
/* Replays files: each argument is a file or a directory of files. */
#include <dirent.h>
#include <sys/stat.h>

static int replay_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        fprintf(stderr, "%s: cannot open\n", path);
        return 1;
    }
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + len, 1, cap - len, fp)) > 0;) {
        len += got;
        if (len == cap) {
            char *grown = realloc(buf, cap *= 2);
            if (!grown) {
                free(buf);
                buf = NULL;
            } else {
                buf = grown;
            }
        }
    }
    fclose(fp);
    if (!buf) {
        fprintf(stderr, "%s: out of memory\n", path);
        return 1;
    }
    LLVMFuzzerTestOneInput((const uint8_t *)buf, len);
    free(buf);
    return 0;
}

int main(int argc, char **argv)
{
    int failures = 0;
    size_t files = 0;
    for (int i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "%s: no such file or directory\n", argv[i]);
            failures++;
            continue;
        }
        if (!S_ISDIR(st.st_mode)) {
            failures += replay_file(argv[i]);
            files++;
            continue;
        }
        DIR *dir = opendir(argv[i]);
        if (!dir) {
            failures++;
            continue;
        }
        for (struct dirent *e; (e = readdir(dir));) {
            if (e->d_name[0] == '.') continue;
            size_t len = strlen(argv[i]) + strlen(e->d_name) + 2;
            char *path = malloc(len);
            if (!path) {
                failures++;
                continue;
            }
            snprintf(path, len, "%s/%s", argv[i], e->d_name);
            if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
                failures += replay_file(path);
                files++;
            }
            free(path);
        }
        closedir(dir);
    }
    printf("fuzz_scene_replay: %zu inputs replayed, %d unreadable\n", files, failures);
    return failures != 0;
}
#endif
