/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * optimise.c -- a calibration or a design run by the driver (optimise.h).
 */
#include "optimise/optimise.h"

#include "optimise/calibrate.h"
#include "optimise/calibrate_report.h"
#include "optimise/design.h"
#include "optimise/design_report.h"
#include "results/output.h"
#include "run/interrupt.h"
#include "run/outdir.h"
#include "run/run.h"
#include "util/text.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int optimise_wanted(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    return cfg->calibrate.data[0] != '\0' || cfg->design.objective[0] != '\0';
}

static int stop(void *user)
{
    (void)user;
    return interrupt_signal() != 0;
}

static void progress(const char *line, void *user)
{
    printf("! %s: %s\n", (const char *)user, line);
    fflush(stdout);
}

/* The scene at values, into DIR/NAME.nml (its &output dir DIR/NAME), then
 * run there as any scene: granules.tsv and what its &sensors ask for. */
static int write_and_run(const opt_space *space, const double *values, const char *dir,
                         const char *name)
{
    char *msg = NULL;
    scene *at = opt_scene_at(space, values, &msg);
    char *sub = text_printf("%s/%s", dir, name), *file = text_printf("%s.nml", name);
    int rc = RUN_COMPLETE;
    if (!at || !sub || !file || scene_set_output_dir(at, sub) != 0) {
        fprintf(stderr, "%s: the scene at the %s: %s\n", space->path, name,
                msg ? msg : "out of memory");
        rc = RUN_FAILED;
        goto out;
    }
    out_file *f = out_open(dir, file, &msg);
    if (f) {
        fprintf(f->fp, "! taper %s: the scene at the %s of %s; `taper %s/%s` reproduces its run\n",
                taper_version(), name, space->path, dir, file);
        scene_write(at, f->fp, 0);
    }
    if (!f || out_commit(f, &msg) != 0) {
        fprintf(stderr, "%s: %s\n", space->path, msg ? msg : "out of memory");
        rc = RUN_FAILED;
        goto out;
    }
    printf("! wrote %s/%s\n", dir, file);
    fflush(stdout);
    rc = run_scene(at);
out:
    free(msg);
    free(sub);
    free(file);
    scene_free(at);
    return rc;
}

/* The result files of an earlier calibration or design in DIR go before
 * this one starts: an interrupted one leaves none to be taken for its own
 * (its runs stay in evaluations.tsv, for the resume).  0, or -1 after
 * printing why. */
static int remove_earlier(const scene *sc)
{
    static const char *const names[] = {"calibration.tsv", "residuals.tsv", "calibration.gp",
                                        "calibration.png", "fitted.nml", "design.tsv",
                                        "profile.tsv", "scan.tsv", "design.gp", "design.png",
                                        "optimum.nml"};
    const char *dir = scene_cfg(sc)->output.dir;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char *msg = NULL;
        if (out_remove(dir, names[i], &msg) != 0) {
            scene_print_output_error(sc, msg ? msg : "out of memory", stderr);
            free(msg);
            return -1;
        }
    }
    return 0;
}

static opt_options options_of(const scene_config *cfg, const char *what, const opt_runner *runner)
{
    return (opt_options){.threads = (unsigned)cfg->output.threads, .stop = stop,
                         .dir = cfg->output.dir, .progress = progress,
                         .progress_user = (void *)what,
                         .runner = runner ? *runner : (opt_runner){0}};
}

/* How an optimisation's outcome becomes the exit status, said on stderr. */
static int status_of(const scene *sc, opt_outcome outcome, const char *what, const char *reason)
{
    switch (outcome) {
    case OPT_CONVERGED: return RUN_COMPLETE;
    case OPT_NOT_CONVERGED:
        fprintf(stderr, "%s: %s NOT CONVERGED: %s\n", scene_path(sc), what, reason);
        return RUN_NOT_CONVERGED;
    case OPT_INTERRUPTED:
        fprintf(stderr, "%s: %s interrupted: %s\n", scene_path(sc), what, reason);
        return RUN_PARTIAL;
    case OPT_FAILED: break;
    }
    fprintf(stderr, "%s: %s failed: %s\n", scene_path(sc), what, reason);
    return RUN_FAILED;
}

static int calibrate(const scene *sc, const opt_runner *runner)
{
    const scene_config *cfg = scene_cfg(sc);
    opt_error e;
    calibration *c = calibration_new(sc, &e);
    if (!c) {
        opt_error_print(sc, &e, stderr);
        opt_error_clear(&e);
        return RUN_INPUT;
    }
    if (outdir_lock(sc, cfg->output.dir, 0) != 0 || remove_earlier(sc) != 0) {
        calibration_free(c);
        return RUN_INPUT;
    }
    printf("! calibrate: %zu measurements of %s, %zu free settings\n", c->data->n, c->data_path,
           c->space->n);
    fflush(stdout);
    opt_options o = options_of(cfg, "calibrate", runner);
    opt_outcome outcome = calibration_run(c, &o);
    int rc = status_of(sc, outcome, "calibration", c->reason);
    if (outcome == OPT_CONVERGED || outcome == OPT_NOT_CONVERGED) {
        char *msg = NULL;
        calibration_print(c, stdout);
        if (calibration_report(c, cfg->output.dir, stdout, &msg) != 0) {
            fprintf(stderr, "%s: %s\n", scene_path(sc), msg ? msg : "out of memory");
            rc = run_worst(rc, RUN_FAILED);
        }
        free(msg);
        rc = run_worst(rc, write_and_run(c->space, c->value, cfg->output.dir, "fitted"));
    }
    calibration_free(c);
    return rc;
}

static int design(const scene *sc, const opt_runner *runner)
{
    const scene_config *cfg = scene_cfg(sc);
    opt_error e;
    design_problem *d = design_new(sc, &e);
    if (!d) {
        opt_error_print(sc, &e, stderr);
        opt_error_clear(&e);
        return RUN_INPUT;
    }
    if (outdir_lock(sc, cfg->output.dir, 0) != 0 || remove_earlier(sc) != 0) {
        design_free(d);
        return RUN_INPUT;
    }
    printf("! design: %s %s over %zu settings\n",
           cfg->design.goal == SCENE_MAXIMISE ? "maximise" : "minimise", d->objective.name,
           d->space->n);
    fflush(stdout);
    opt_options o = options_of(cfg, "design", runner);
    opt_outcome outcome = design_run(d, &o);
    int rc = status_of(sc, outcome, "design", d->reason);
    if (outcome == OPT_CONVERGED || outcome == OPT_NOT_CONVERGED) {
        char *msg = NULL;
        design_print(d, stdout);
        if (design_profiles(d, &o) == OPT_INTERRUPTED) {
            rc = run_worst(rc, status_of(sc, OPT_INTERRUPTED, "design", "during the profiles "
                                         "through the optimum; the same command resumes"));
        } else if (design_report(d, cfg->output.dir, stdout, &msg) != 0) {
            fprintf(stderr, "%s: %s\n", scene_path(sc), msg ? msg : "out of memory");
            rc = run_worst(rc, RUN_FAILED);
        }
        free(msg);
        if (rc != RUN_PARTIAL)
            rc = run_worst(rc, write_and_run(d->space, d->best, cfg->output.dir, "optimum"));
    }
    design_free(d);
    return rc;
}

int optimise_scene(const scene *sc, const opt_runner *runner)
{
    const scene_config *cfg = scene_cfg(sc);
    if (cfg->calibrate.data[0] && cfg->design.objective[0]) {
        opt_error e = {.message = text_printf("a scene is a calibration (&calibrate data) or a "
                                              "design (&design objective), not both: split it"),
                       .keyword = "design_objective"};
        opt_error_print(sc, &e, stderr);
        opt_error_clear(&e);
        return RUN_INPUT;
    }
    return cfg->calibrate.data[0] ? calibrate(sc, runner) : design(sc, runner);
}

/* ---- another process's share of the runs ------------------------------------------------ */

struct optimise_remote {
    calibration *c;         /* one of the two */
    design_problem *d;
    opt_problem pb;         /* no journal: the optimising process keeps it */
};

optimise_remote *optimise_remote_new(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    optimise_remote *w = calloc(1, sizeof *w);
    opt_error e = {0};
    if (!w || (cfg->calibrate.data[0] && cfg->design.objective[0])) goto fail;
    if (cfg->calibrate.data[0]) {
        if (!(w->c = calibration_new(sc, &e))) goto fail;
        w->pb = (opt_problem){.space = w->c->space, .plan = &w->c->plan};
    } else {
        if (!(w->d = design_new(sc, &e))) goto fail;
        w->pb = (opt_problem){.space = w->d->space, .objective = &w->d->objective};
    }
    w->pb.stop = stop;
    return w;
fail:
    opt_error_clear(&e);
    optimise_remote_free(w);
    return NULL;
}

size_t optimise_remote_size(const optimise_remote *w) { return w->pb.space->n; }

void optimise_remote_evaluate(const optimise_remote *w, const double *values, opt_result *r)
{
    opt_evaluate(&w->pb, values, r);
}

void optimise_remote_free(optimise_remote *w)
{
    if (!w) return;
    calibration_free(w->c);
    design_free(w->d);
    free(w);
}
