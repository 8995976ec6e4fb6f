/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * outdir.c -- an output directory (outdir.h): its lock, and what earlier
 * runs and sweeps left in it.  The single run and the sweep both lock it
 * and clear it before they write, so that results of different scenes are
 * never mixed.
 */
#include "run/outdir.h"

#include "results/output.h"
#include "run/run.h"
#include "util/text.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- the lock ------------------------------------------------------------- */

/* The directories this process holds locked, by the lock file's device and
 * inode: a second scene of the same command (`taper a.nml b.nml`, both
 * into one &output dir) goes on under the lock the first took, as if the
 * two had run one after the other. */
enum { MAX_HELD = 64 };
static struct held {
    dev_t dev;
    ino_t ino;
} held[MAX_HELD];
static size_t n_held;
static pthread_mutex_t held_lock = PTHREAD_MUTEX_INITIALIZER;

static int held_by_us(const struct stat *st)
{
    pthread_mutex_lock(&held_lock);
    int found = 0;
    for (size_t i = 0; i < n_held && !found; i++)
        found = held[i].dev == st->st_dev && held[i].ino == st->st_ino;
    pthread_mutex_unlock(&held_lock);
    return found;
}

static void remember(const struct stat *st)
{
    pthread_mutex_lock(&held_lock);
    if (n_held < MAX_HELD) held[n_held++] = (struct held){st->st_dev, st->st_ino};
    pthread_mutex_unlock(&held_lock);
}

int outdir_lock(const scene *sc, const char *dir, int shared)
{
    char *msg = NULL;
    if (out_mkdir_p(dir, &msg) != 0) {
        scene_print_output_error(sc, msg ? msg : "out of memory", stderr);
        free(msg);
        return -1;
    }
    char *path = text_printf("%s/.taper.lock", dir);
    int fd = path ? open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666) : -1;
    struct stat st;
    if (fd >= 0 && fstat(fd, &st) == 0 && held_by_us(&st)) {
        close(fd); /* ours already: the lock stays on the first descriptor */
        free(path);
        return 0;
    }
    if (fd < 0) {
        msg = path ? text_printf("output directory %s is not writable: %s", dir, strerror(errno))
                   : NULL;
    } else if (flock(fd, (shared ? LOCK_SH : LOCK_EX) | LOCK_NB) != 0) {
        msg = errno == EWOULDBLOCK
                  ? text_printf("output directory %s is in use by another taper run (it holds "
                                "%s): wait for it to end, or write elsewhere with -o DIR", dir, path)
                  : text_printf("cannot lock %s: %s", path, strerror(errno));
        close(fd);
        fd = -1;
    } else {
        if (fstat(fd, &st) == 0) remember(&st);
        if (!shared) {
            /* The lock file says who holds it, for a person looking. */
            char pid[32];
            int n = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
            if (ftruncate(fd, 0) == 0 && write(fd, pid, (size_t)n) < 0) { /* informative only */ }
        }
    }
    free(path);
    if (fd >= 0) return 0;
    scene_print_output_error(sc, msg ? msg : "out of memory", stderr);
    free(msg);
    return -1;
}

/* ---- what earlier runs left ------------------------------------------------ */

/* The files a run of taper writes in its directory (a sweep: in each run's
 * directory), and their temporaries. */
static const char *const run_files[] = {"granules.tsv", "granules.partial.tsv", "scene.hash",
                                        "report.tsv", "sensors.tsv", "walls.tsv",
                                        "spacetime.tsv", "spacetime.gp", "spacetime.png"};
#define N_RUN_FILES (sizeof run_files / sizeof run_files[0])

/* The sweep-level files an earlier sweep (or run) may have left. */
static const char *const sweep_files[] = {"sweep.tsv", "runs.tsv", "fits.tsv", "table.tsv",
                                          "figure.tsv", "inset.tsv", "figure.gp", "figure.png"};
#define N_SWEEP_FILES (sizeof sweep_files / sizeof sweep_files[0])

static int run_file(const char *name)
{
    for (size_t i = 0; i < N_RUN_FILES; i++) {
        size_t n = strlen(run_files[i]);
        if (strcmp(name, run_files[i]) == 0) return 1;
        /* .NAME.XXXXXX: out_open's temporary, left by a killed run */
        if (name[0] == '.' && strncmp(name + 1, run_files[i], n) == 0 && name[n + 1] == '.') return 1;
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

size_t outdir_remove_temporaries(const char *dir)
{
    return out_remove_temporaries(dir, run_files, N_RUN_FILES) +
           out_remove_temporaries(dir, sweep_files, N_SWEEP_FILES);
}

int outdir_clean(const scene *sc, int (*in_this_sweep)(const char *name, const void *data),
                 const void *data)
{
    const char *dir = scene_cfg(sc)->output.dir;
    char *msg = NULL;
    int rc = RUN_COMPLETE;
    for (size_t i = 0; i < N_SWEEP_FILES; i++)
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

