/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * outdir.c -- what earlier runs and sweeps left in an output directory
 * (outdir.h): the single run and the sweep both clear it before they
 * write, so that results of different scenes are never mixed.
 */
#include "run/outdir.h"

#include "results/output.h"
#include "run/run.h"
#include "util/text.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The files a run directory of taper holds (and their temporaries). */
static int run_file(const char *name)
{
    static const char *const names[] = {"granules.tsv", "granules.partial.tsv", "scene.hash"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        size_t n = strlen(names[i]);
        if (strcmp(name, names[i]) == 0) return 1;
        /* .NAME.XXXXXX: out_open's temporary, left by a killed run */
        if (name[0] == '.' && strncmp(name + 1, names[i], n) == 0 && name[n + 1] == '.') return 1;
    }
    return 0;
}

/* NAME=VALUE[,NAME=VALUE...] with NAME a variable a list sweeps. */
static int looks_like_run(const char *name)
{
    const char *p = name;
    for (;;) {
        const char *eq = strchr(p, '=');
        if (!eq || eq == p) return 0;
        int known = 0;
        for (size_t i = 0; i < scene_var_count() && !known; i++)
            known = scene_var_takes_list(i) && strlen(scene_var_name(i)) == (size_t)(eq - p) &&
                    strncmp(scene_var_name(i), p, (size_t)(eq - p)) == 0;
        if (!known) return 0;
        const char *comma = strchr(eq, ',');
        if (eq[1] == '\0' || eq[1] == ',') return 0;
        if (!comma) return 1;
        p = comma + 1;
    }
}

/* Removes dir if it holds only a run's files; 1 removed, 0 kept. */
static int remove_run_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return 0;
    struct dirent *e;
    int only_ours = 1;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        if (!run_file(e->d_name)) only_ours = 0;
    }
    if (only_ours) {
        rewinddir(d);
        while ((e = readdir(d)) != NULL) {
            if (!run_file(e->d_name)) continue;
            char *p = text_printf("%s/%s", dir, e->d_name);
            if (p) unlink(p);
            free(p);
        }
    }
    closedir(d);
    return only_ours && rmdir(dir) == 0;
}

/* Temporaries a killed run left in its directory (.granules.tsv.XXXXXX). */
void outdir_remove_temporaries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] != '.' || !run_file(e->d_name)) continue;
        char *p = text_printf("%s/%s", dir, e->d_name);
        if (p) unlink(p);
        free(p);
    }
    closedir(d);
}

/* The sweep-level files an earlier sweep (or run) may have left. */
static const char *const sweep_files[] = {"sweep.tsv", "runs.tsv", "fits.tsv", "table.tsv",
                                          "figure.tsv", "inset.tsv", "figure.gp", "figure.png"};

int outdir_clean(const scene *sc, int (*in_this_sweep)(const char *name, const void *data),
                 const void *data)
{
    const char *dir = scene_cfg(sc)->output.dir;
    char *msg = NULL;
    int rc = RUN_COMPLETE;
    for (size_t i = 0; i < sizeof sweep_files / sizeof sweep_files[0]; i++)
        if (out_remove(dir, sweep_files[i], &msg) != 0) {
            fprintf(stderr, "%s: %s\n", scene_path(sc), msg ? msg : "out of memory");
            free(msg);
            msg = NULL;
            rc = RUN_FAILED;
        }
    if (in_this_sweep) {
        /* A single run's own result in DIR is not part of a sweep. */
        out_remove(dir, "granules.tsv", &msg);
        free(msg);
        msg = NULL;
        out_remove(dir, "granules.partial.tsv", &msg);
        free(msg);
        msg = NULL;
    }
    DIR *d = opendir(dir);
    if (!d) return rc;
    struct dirent *e;
    size_t removed = 0;
    while ((e = readdir(d)) != NULL) {
        if (!looks_like_run(e->d_name) || (in_this_sweep && in_this_sweep(e->d_name, data))) continue;
        char *sub = text_printf("%s/%s", dir, e->d_name);
        struct stat st;
        if (sub && stat(sub, &st) == 0 && S_ISDIR(st.st_mode)) {
            if (remove_run_dir(sub))
                removed++;
            else
                fprintf(stderr, "%s: warning: %s is a run of another sweep and holds other files: "
                        "kept (not part of this sweep's results)\n", scene_path(sc), sub);
        }
        free(sub);
    }
    closedir(d);
    if (removed)
        printf("! removed %zu run director%s of an earlier sweep from %s\n", removed,
               removed == 1 ? "y" : "ies", dir);
    return rc;
}

