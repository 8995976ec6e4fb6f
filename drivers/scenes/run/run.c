/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * run.c -- the runs of a scene (run.h).
 *
 * Three phases, so that the output is the same whatever the number of
 * threads:
 *   prepare  (in sweep order)  the chain and the sim (the library checks
 *            what needs the chain and computes the theory once), then the
 *            output directory: a scene the library rejects leaves none;
 *   compute  (in parallel)     taper_sim_run, or taper_theory_compute when
 *            the numerics are off; nothing is printed here;
 *   finish   (in sweep order)  messages and granules.tsv; then fits, table
 *            and figure.
 * A sweep (several runs) is run/sweep.c's: each run prepared, computed and
 * written on its own (run_point), on threads or MPI ranks, its messages
 * printed in the order of the sweep.
 */
#include "run/run.h"

#include "results/analysis.h"
#include "results/granules.h"
#include "results/output.h"
#include "results/plot.h"
#include "results/sensors.h"
#include "results/table.h"
#include "run/interrupt.h"
#include "run/parallel.h"
#include "run/outdir.h"
#include "util/text.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* ---- progress ------------------------------------------------------------ */

typedef struct progress_state {
    int show;           /* stderr is a terminal and progress = .true.   */
    int printed;        /* a progress line is on screen                 */
    double start, last; /* wall-clock seconds                           */
    const double *theory_t; /* the theory's t_k (eq. (19)), or NULL     */
    size_t granules;        /* its length                               */
} progress_state;

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* "granule 1234/100000  t = 567.8  2.3e+04 granules/s  4.3 s left": the
 * time left from the granules still to pass at the rate so far, and from
 * the time still to go to the theory's pass time of the target (eq. (19))
 * at the rate t has advanced so far, the longer of the two.  The second is
 * what a run has before its first passes, or while the pulse hardly moves
 * (below n = 2 on a steep forward taper the pulse can take 1e8 steps to
 * leave granule 1: sim.c, advise_on_slow_light_end); the theory's time is
 * within a factor of about 2 of the dynamics' on every profile. */
static int monitor(const taper_progress *p, void *user)
{
    progress_state *ps = user;
    if (p->window_hi == 0) return interrupt_signal() != 0; /* the theory: no line */
    if (ps->show) {
        double now = wall_seconds(), elapsed = fmax(now - ps->start, 1e-9);
        if (now - ps->last >= 0.2 || p->granule >= p->target) {
            double rate = (double)p->granule / elapsed;
            size_t todo = p->granule < p->target ? p->target - p->granule : 0;
            fprintf(stderr, "\rtaper: granule %zu/%zu  t = %.6g  %.3g granules/s", p->granule,
                    p->target, p->t, rate);
            double left = rate > 0 && isfinite(rate) ? (double)todo / rate : NAN;
            const double t_target = ps->theory_t && p->target >= 1 && p->target <= ps->granules
                                        ? ps->theory_t[p->target - 1] : NAN;
            if (todo && isfinite(t_target) && t_target > p->t && p->t > 0.0) {
                double by_time = (t_target - p->t) * elapsed / p->t;
                if (!(left >= by_time)) left = by_time;
            }
            if (isfinite(left))
                fprintf(stderr, "  %.1f s left   ", left);
            else
                fputs("                ", stderr);
            ps->last = now;
            ps->printed = 1;
        }
    }
    return interrupt_signal() != 0;
}

static void progress_done(progress_state *ps)
{
    if (ps->printed) fputc('\n', stderr);
    ps->printed = 0;
}

/* ---- one run ------------------------------------------------------------- */

/* One value of a sweep (or the only run). */
typedef struct run {
    const scene *sc;
    const scene_config *cfg; /* &at: the scene at this point               */
    scene_config at;
    FILE *out, *log;         /* stdout, stderr; a sweep's run: its buffers   */
    char *label;             /* names the run in messages: SCENE, or
                                SCENE: run NAME in a sweep                   */
    const char *name;        /* NAME in a sweep, NULL otherwise              */
    size_t point;
    char *dir;
    taper_chain_spec *spec;
    taper_chain *chain;
    taper_sim *sim;                                   /* NULL without numerics */
    double *own_theory[TAPER_N_THEORY_QUANTITIES];    /* without numerics      */
    const double *theory[TAPER_N_THEORY_QUANTITIES];  /* by TAPER_THEORY_*     */
    const char *theory_note; /* taper_chain_theory_note: why the theory is NaN */
    sensors *sensors;        /* &sensors: the sampler's records, or NULL     */
    progress_state progress;
    int show_progress;       /* only when runs are computed one at a time */
    taper_status status;     /* taper_sim_run's (TAPER_OK without numerics) */
    int rc;                  /* run_status of this run                      */
    int computed;            /* 0: skipped (interrupted before it started)  */
    taper_error err;
    char *message;           /* printed by finish_run (malloc'd)            */
    char *stopped_at;        /* the file a signal stopped while the results
                                were written (its message, malloc'd)       */
} run;

/* The library's warnings (level 1) go to stderr, named by scene and run;
 * its information messages (level 0) are not shown. */
static void report_warning(int level, const char *message, void *user)
{
    const run *r = user;
    if (level >= 1) fprintf(r->log, "%s: warning: %s\n", r->label, message);
}

static void run_free(run *r)
{
    sensors_free(r->sensors);
    taper_sim_free(r->sim);
    taper_chain_free(r->chain);
    taper_chain_spec_free(r->spec);
    for (int i = 0; i < TAPER_N_THEORY_QUANTITIES; i++) free(r->own_theory[i]);
    free(r->message);
    free(r->stopped_at);
    free(r->dir);
    free(r->label);
}

/* "SCENE: message" for finish_run. */
static void set_message(run *r, const char *message)
{
    free(r->message);
    r->message = text_printf("%s: %s", r->label, message);
}

/* A message about the scene's text (FILE:LINE: &group key: ...), with the
 * run it comes from in a sweep. */
static void print_scene_message(const run *r, char *text)
{
    size_t n = text ? strlen(text) : 0;
    if (n && text[n - 1] == '\n') text[--n] = '\0';
    if (r->name)
        fprintf(r->log, "%s (run %s)\n", text ? text : "out of memory", r->name);
    else
        fprintf(r->log, "%s\n", text ? text : "out of memory");
}

/* A library refusal of a validated scene: what needs the whole chain
 * (masses beyond double precision, last_granule beyond N).  The library
 * names the setting; the scene names its line. */
static int refused(const run *r, scene_lib lib)
{
    char *text = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&text, &len);
    if (mem) {
        scene_print_library_error(r->sc, lib, &r->err, mem);
        fclose(mem);
    }
    print_scene_message(r, text);
    free(text);
    return r->err.status == TAPER_ENOMEM ? RUN_FAILED : RUN_INPUT;
}

/* A long chain's building or theory stopped by a signal
 * (taper_chain_alloc_monitored, taper_sim_alloc or
 * taper_theory_compute_monitored): nothing of the run is written. */
static int stopped_before_run(run *r, const char *while_what)
{
    char by[64];
    interrupt_describe(by, sizeof by);
    free(r->message);
    r->message = text_printf("%s: interrupted by %s while %s (%s): nothing of this run is "
                             "written", r->label, by, while_what, r->err.message);
    r->computed = 0;
    return RUN_PARTIAL;
}

static int theory_interrupted(run *r)
{
    return stopped_before_run(r, "the binary-collision theory was computed");
}

static int build_chain(run *r)
{
    if (!(r->spec = scene_chain_spec(r->cfg, r->point, &r->err))) return refused(r, SCENE_LIB_CHAIN);
    /* The monitor: a signal stops the building of a long chain too. */
    if (!(r->chain = taper_chain_alloc_monitored(r->spec, monitor, &r->progress, &r->err)))
        return r->err.status == TAPER_EINTERRUPTED ? stopped_before_run(r, "the chain was built")
                                                   : refused(r, SCENE_LIB_CHAIN);
    return RUN_COMPLETE;
}

/* Where the binary-collision theory does not describe the chain (losses,
 * a static load: taper_chain_theory_note), its columns are NaN, whatever
 * the arrays held: never the theory of another model.  0, or -1 out of
 * memory. */
static int blank_theory(run *r)
{
    if (!(r->theory_note = taper_chain_theory_note(r->chain))) return 0;
    size_t n = taper_chain_size(r->chain);
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++) {
        if (!r->own_theory[q] && !(r->own_theory[q] = malloc(n * sizeof(double)))) return -1;
        for (size_t k = 0; k < n; k++) r->own_theory[q][k] = NAN;
        r->theory[q] = r->own_theory[q];
    }
    return 0;
}

/* &sensors: the library's sampler records into r->sensors. */
static int attach_sensors(run *r, taper_solver_spec *spec)
{
    int failed;
    if (!(r->sensors = sensors_new(r->cfg, r->chain, &failed))) {
        if (!failed) return RUN_COMPLETE;
        fprintf(r->log, "%s: out of memory for the sensors\n", r->label);
        return RUN_FAILED;
    }
    if (taper_solver_spec_set_sampler(spec, scene_sample_interval(r->cfg), sensors_sample,
                                      r->sensors, &r->err) == TAPER_OK)
        return RUN_COMPLETE;
    return refused(r, SCENE_LIB_SOLVER);
}

/* The sim, and with it the theory, computed once by the library. */
/* How long the run will last, before it starts: until t_end, and until
 * the pulse has passed the chain, when the binary-collision theory says
 * (eq. (19)); a chain it does not describe (losses, a load) by the
 * monodisperse pulse's 1.19 time units a granule (docs/physics.md,
 * Nesterenko's wave), with room. */
static double duration_estimate(const run *r)
{
    const double *t = taper_sim_theory(r->sim, TAPER_THEORY_T);
    size_t n = taper_chain_size(r->chain);
    double pulse = 1.5 * (double)n;
    for (size_t k = n; k-- > 0;)
        if (t && isfinite(t[k])) {
            pulse = t[k];
            break;
        }
    double t_end = taper_solver_spec_t_end(NULL); /* the default, replaced below */
    taper_solver_spec *spec = scene_solver_spec(r->cfg, NULL);
    if (spec) t_end = taper_solver_spec_t_end(spec);
    taper_solver_spec_free(spec);
    return fmax(pulse, t_end);
}

/* &output max_output: a run whose samples would fill the disk is refused
 * before it starts, with the estimate and what to change. */
static int check_output_size(run *r)
{
    const double limit = r->cfg->output.max_output;
    const double interval = scene_sample_interval(r->cfg);
    const double duration = duration_estimate(r);
    const double samples = floor(duration / interval) + 1.0;
    const double bytes = samples * sensors_bytes_per_sample(r->sensors);
    if (limit == 0.0 || bytes <= limit) return RUN_COMPLETE;
    const int si = scene_unit_suffix(r->cfg, TAPER_DIM_TIME) != NULL;
    const int line = scene_line_of(r->sc, "interval");
    char where[32] = "";
    if (line > 0) snprintf(where, sizeof where, "%d:", line);
    char *text = text_printf(
        "%s:%s &sensors interval: the samples would take about %.2g bytes (%.3g samples to t = "
        "%.4g%s, the pulse's crossing by the binary-collision theory or t_end), more than "
        "&output max_output = %g: give a longer interval or fewer sensor granules, or raise "
        "max_output", scene_path(r->sc), where, bytes, samples,
        si ? duration * scene_unit(r->cfg, TAPER_DIM_TIME) : duration, si ? " s" : "", limit);
    print_scene_message(r, text);
    free(text);
    return RUN_INPUT;
}

static int build_sim(run *r)
{
    taper_solver_spec *spec = scene_solver_spec(r->cfg, &r->err);
    if (!spec) return refused(r, SCENE_LIB_SOLVER);
    taper_solver_spec_set_monitor(spec, monitor, &r->progress);
    taper_solver_spec_set_log(spec, report_warning, r);
    int rc = attach_sensors(r, spec);
    if (rc != RUN_COMPLETE) {
        taper_solver_spec_free(spec);
        return rc;
    }
    r->sim = taper_sim_alloc(r->chain, spec, &r->err);
    taper_solver_spec_free(spec);
    if (!r->sim) {
        if (r->err.status == TAPER_EINTERRUPTED) return stopped_before_run(r, "the run was set up");
        if (r->err.field) return refused(r, SCENE_LIB_SOLVER);
        /* The theory overflowing, or memory: not the scene's syntax. */
        fprintf(r->log, "%s: %s\n", r->label, r->err.message);
        return RUN_FAILED;
    }
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++)
        r->theory[q] = taper_sim_theory(r->sim, (taper_theory_quantity)q);
    if (blank_theory(r) != 0) {
        fprintf(r->log, "%s: out of memory\n", r->label);
        return RUN_FAILED;
    }
    return r->sensors ? check_output_size(r) : RUN_COMPLETE;
}

static int prepare_dir(const run *r)
{
    char *msg = NULL;
    if (out_mkdir_p(r->dir, &msg) == 0 && access(r->dir, W_OK | X_OK) == 0) return 0;
    if (!msg) msg = text_printf("output directory %s is not writable", r->dir);
    char *text = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&text, &len);
    if (mem) {
        scene_print_output_error(r->sc, msg ? msg : "out of memory", mem);
        fclose(mem);
    }
    print_scene_message(r, text);
    free(text);
    free(msg);
    return -1;
}

/* Before any computation: the chain and sim (a scene the library rejects
 * leaves no empty directory); the directories come after (prepare_dirs). */
static void prepare_run(run *r)
{
    r->rc = build_chain(r);
    if (r->rc == RUN_COMPLETE && r->cfg->solver.numerics) r->rc = build_sim(r);
}

static int theory_monitor(const taper_progress *p, void *user)
{
    (void)p;
    (void)user;
    return interrupt_signal() != 0;
}

/* Without numerics: the theory alone. */
static int compute_theory(run *r)
{
    size_t n = taper_chain_size(r->chain);
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++) {
        if (!(r->own_theory[q] = malloc(n * sizeof(double)))) {
            set_message(r, "out of memory");
            return RUN_FAILED;
        }
        r->theory[q] = r->own_theory[q];
    }
    taper_status status = taper_theory_compute_monitored(
        r->chain, r->own_theory[TAPER_THEORY_V], r->own_theory[TAPER_THEORY_MU],
        r->own_theory[TAPER_THEORY_T_RES], r->own_theory[TAPER_THEORY_T], theory_monitor, NULL,
        &r->err);
    if (status == TAPER_OK) {
        if (blank_theory(r) == 0) return RUN_COMPLETE;
        set_message(r, "out of memory");
        return RUN_FAILED;
    }
    if (status == TAPER_EINTERRUPTED) return theory_interrupted(r);
    /* The library's theory messages name it already ("theory: velocity of ..."). */
    set_message(r, r->err.message);
    return RUN_FAILED;
}

static int simulate(run *r)
{
    progress_state *ps = &r->progress;
    ps->show = r->show_progress && r->cfg->output.progress && isatty(STDERR_FILENO);
    ps->start = ps->last = wall_seconds();
    ps->theory_t = r->theory[TAPER_THEORY_T];
    ps->granules = taper_chain_size(r->chain);
    r->status = taper_sim_run(r->sim, &r->err);
    progress_done(ps);
    if (r->status == TAPER_EINTERRUPTED && interrupt_signal()) {
        /* Name the signal, in the message and the partial file's header. */
        static const char word[] = "interrupted";
        char rest[sizeof r->err.message];
        const char *m = r->err.message;
        int lead = strncmp(m, word, sizeof word - 1) == 0;
        snprintf(rest, sizeof rest, "%s", lead ? m + sizeof word - 1 : m);
        char by[64];
        interrupt_describe(by, sizeof by);
        snprintf(r->err.message, sizeof r->err.message, "interrupted by %s%s%.400s", by,
                 lead ? "" : ": ", rest);
    }
    if (r->status == TAPER_OK) return RUN_COMPLETE;
    set_message(r, r->err.message);
    if (r->status == TAPER_ESOLVER || r->status == TAPER_EINTERRUPTED || r->status == TAPER_ELIMIT)
        return RUN_PARTIAL;
    return RUN_FAILED;
}

/* The computation of one run: thread-safe (the library has no global
 * state), prints nothing. */
static void compute_run(size_t i, void *data)
{
    run *r = &((run *)data)[i];
    if (r->rc != RUN_COMPLETE) return;
    if (interrupt_signal()) {
        char by[64];
        interrupt_describe(by, sizeof by);
        free(r->message);
        r->message = text_printf("%s: interrupted by %s before this run started: nothing of "
                                 "this run is written", r->label, by);
        r->rc = RUN_PARTIAL;
        return;
    }
    r->computed = 1;
    r->rc = r->sim ? simulate(r) : compute_theory(r);
}

static granules_run result_of(const run *r)
{
    granules_run g = {.sc = r->sc, .point = r->point, .chain = r->chain, .sim = r->sim,
                      .status = r->status, .message = r->err.message,
                      .theory_note = r->theory_note, .at = r->at};
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++) g.theory[q] = r->theory[q];
    return g;
}

/* Conservation beyond the scene's bounds (&output max_energy_error,
 * max_momentum_error): the run is not to be trusted.  Text for the header
 * line and stderr (malloc'd), or NULL. */
static char *distrust(const run *r)
{
    if (!r->sim) return NULL;
    const scene_output_config *o = &r->cfg->output;
    double e = taper_sim_statistic(r->sim, TAPER_STAT_ENERGY_ERROR);
    double p = taper_sim_statistic(r->sim, TAPER_STAT_MOMENTUM_ERROR);
    /* NaN (no energy to compare with) is not trusted either. */
    int bad_e = !(e <= o->max_energy_error), bad_p = !(p <= o->max_momentum_error);
    if (!bad_e && !bad_p) return NULL;
    char be[SCENE_REAL_TEXT], bp[SCENE_REAL_TEXT];
    scene_format_real(o->max_energy_error, be);
    scene_format_real(o->max_momentum_error, bp);
    if (bad_e && bad_p)
        return text_printf("energy error %.2e exceeds %s and momentum error %.2e exceeds %s "
                           "(&output max_energy_error, max_momentum_error)", e, be, p, bp);
    if (bad_e)
        return text_printf("energy error %.2e exceeds %s (&output max_energy_error)", e, be);
    return text_printf("momentum error %.2e exceeds %s (&output max_momentum_error)", p, bp);
}

/* Every row and column of a run whose granules.tsv leaves some out (&output
 * every, columns), for the fits, table and figure of a sweep, which read
 * their runs back from files (run/sweep.c): DIR/report.tsv. */
static int write_report_data(const run *r, char **msg)
{
    const scene_config *cfg = r->cfg;
    if (!(cfg->runs.fit || cfg->runs.table || cfg->runs.figure)) return 0;
    unsigned needed = 1u << 9 | 1u << 10 | 1u << 11; /* the theory's columns */
    if (cfg->solver.numerics) needed |= 0x1fu << 4;  /* and the observables    */
    /* SI files (&output units = 'si'): the reports stay rescaled. */
    if (cfg->output.every <= 1 && (cfg->output.column_set & needed) == needed &&
        cfg->output.units == SCENE_UNITS_RESCALED)
        return 0;
    out_columns cols;
    memset(&cols, 0, sizeof cols);
    cols.n = taper_chain_size(r->chain);
    cols.col[1] = taper_chain_radius(r->chain);
    cols.col[2] = taper_chain_mass(r->chain);
    cols.col[3] = taper_chain_rest_position(r->chain);
    if (r->sim)
        for (int o = 0; o < TAPER_N_OBSERVABLES; o++)
            cols.col[4 + o] = taper_sim_observable(r->sim, (taper_observable)o);
    cols.col[9] = r->theory[TAPER_THEORY_V];
    cols.col[10] = r->theory[TAPER_THEORY_T_RES];
    cols.col[11] = r->theory[TAPER_THEORY_T];
    out_file *f = out_open(r->dir, "report.tsv", msg);
    if (!f) return -1;
    out_write_header(f->fp, &cols, NULL);
    fputs("# every granule and column of this run, for the sweep's fits, table and figure\n",
          f->fp);
    out_write_rows(f, &cols, NULL, 0);
    return out_commit(f, msg);
}

/* The energy budget at the end of the run (docs/physics.md), one line on
 * stdout: where the initial energy (and a piston's work) went. */
static void print_energy(const run *r)
{
    if (!r->sim) return;
    static const struct {
        taper_statistic which;
        const char *label;
    } parts[] = {{TAPER_STAT_ENERGY_TRANSMITTED, "transmitted"},
                 {TAPER_STAT_ENERGY_REFLECTED, "reflected"},
                 {TAPER_STAT_ENERGY_IN_CHAIN, "in the chain"},
                 {TAPER_STAT_ENERGY_DISSIPATED, "dissipated"}};
    double e0 = taper_sim_statistic(r->sim, TAPER_STAT_ENERGY_INITIAL);
    const double work = taper_sim_piston_work(r->sim); /* NaN: no piston */
    const double input = e0 + (work > 0 ? work : 0);
    if (!(input > 0)) return;
    double scale = scene_unit(r->cfg, TAPER_DIM_ENERGY);
    const char *unit = scene_unit_suffix(r->cfg, TAPER_DIM_ENERGY);
    fprintf(r->out, "! energy at t_final: initial %.6g%s%s", e0 * scale, unit ? " " : "",
            unit ? unit : "");
    if (!isnan(work))
        fprintf(r->out, ", piston work %.6g%s%s", work * scale, unit ? " " : "", unit ? unit : "");
    for (size_t i = 0; i < sizeof parts / sizeof parts[0]; i++) {
        double x = taper_sim_statistic(r->sim, parts[i].which);
        fprintf(r->out, ", %s %.6g%s%s (%.3g %%)", parts[i].label, x * scale, unit ? " " : "",
                unit ? unit : "", 100 * x / input);
    }
    fputc('\n', r->out);
}

char *run_stopped_writing(const char *msg)
{
    char by[64];
    interrupt_describe(by, sizeof by);
    const char *cut = strstr(msg, " not written: ");
    return text_printf("interrupted by %s while writing %.*s: it is not written, nor anything "
                       "after it; the files reported written (\"! wrote\") are complete, their "
                       "footers say so", by, cut ? (int)(cut - msg) : (int)strlen(msg), msg);
}

/* A failure while the results are written: a stop signal (the file and
 * those after it not written: RUN_PARTIAL, said once at the end of
 * finish_run), or the disk (RUN_FAILED). */
static void write_failed(run *r, char *msg)
{
    if (out_was_stopped(msg) && interrupt_signal()) {
        if (!r->stopped_at) {
            r->stopped_at = msg;
            return;
        }
    } else {
        fprintf(r->log, "%s: %s\n", r->label, msg ? msg : "out of memory");
        r->rc = RUN_FAILED;
    }
    free(msg);
}

/* &sensors: the time series of this run. */
static void write_sensors(run *r)
{
    char *msg = NULL;
    if (!r->sensors || !r->sim) return;
    const char *partial = r->rc == RUN_PARTIAL ? r->err.message : NULL;
    if (sensors_write(r->sensors, r->sim, partial, r->dir, r->out, &msg) != 0)
        write_failed(r, msg);
    else
        free(msg);
}

/* After the computation, in the order of the sweep.  A run that a signal
 * interrupted writes what it found (OUT_FOUND: whole, a second signal ends
 * the process); a complete run's files stop at a signal, the one being
 * written removed and none started after it (OUT_WHOLE), and the message
 * says which are on disk. */
static void finish_run(run *r)
{
    if (r->message) fprintf(r->log, "%s\n", r->message);
    if (!r->computed || (r->rc != RUN_COMPLETE && r->rc != RUN_PARTIAL)) return;
    if (r->theory_note)
        fprintf(r->log, "%s: note: the theory columns are nan: %s\n", r->label, r->theory_note);
    granules_run g = result_of(r);
    char *untrusted = distrust(r);
    if (untrusted) {
        fprintf(r->log, "%s: UNTRUSTED result: %s; a smaller rtol (and atol) keeps the "
                "conservation errors small\n", r->label, untrusted);
        if (r->rc == RUN_COMPLETE) r->rc = RUN_UNTRUSTED;
    }
    g.untrusted = untrusted;
    char *msg = NULL;
    const int partial = r->rc == RUN_PARTIAL;
    out_set_mode(partial && interrupt_signal() ? OUT_FOUND : OUT_WHOLE);
    const char *name = partial ? "granules.partial.tsv" : "granules.tsv";
    if (granules_save(r->dir, &g, partial, &msg) != 0) {
        write_failed(r, msg);
    } else {
        free(msg);
        msg = NULL;
        fprintf(r->out, "! wrote %s/%s\n", r->dir, name);
        print_energy(r);
        write_sensors(r);
        if (r->name && !partial && !r->stopped_at && write_report_data(r, &msg) != 0)
            write_failed(r, msg);
        else
            free(msg);
    }
    out_set_mode(OUT_WHOLE);
    if (r->stopped_at) {
        char *said = run_stopped_writing(r->stopped_at);
        fprintf(r->log, "%s: %s\n", r->label, said ? said : r->stopped_at);
        free(said);
        r->rc = RUN_PARTIAL;
    }
    free(untrusted);
}

/* A run at its point: the scene's configuration there, its messages to out
 * and log. */
static int run_init(run *r, const scene *sc, size_t point, const char *dir, const char *name,
                    FILE *out, FILE *log)
{
    r->sc = sc;
    r->point = point;
    scene_config_at(scene_cfg(sc), point, &r->at);
    r->cfg = &r->at;
    r->out = out;
    r->log = log;
    r->name = name;
    r->dir = text_dup(dir);
    r->label = name ? text_printf("%s: run %s", scene_path(sc), name) : text_dup(scene_path(sc));
    return r->dir && r->label ? 0 : -1;
}

static double thread_cpu_seconds(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return NAN;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void run_point(const scene *sc, size_t point, const char *dir, const char *name, run_outcome *o)
{
    const double cpu_start = thread_cpu_seconds();
    size_t n_out = 0, n_log = 0;
    memset(o, 0, sizeof *o);
    FILE *out = open_memstream(&o->out, &n_out), *log = open_memstream(&o->log, &n_log);
    run r;
    memset(&r, 0, sizeof r);
    if (!out || !log || run_init(&r, sc, point, dir, name, out, log) != 0) {
        o->rc = RUN_FAILED;
    } else {
        prepare_run(&r);
        if (r.rc == RUN_COMPLETE && prepare_dir(&r) != 0) r.rc = RUN_INPUT;
        compute_run(0, &r);
        finish_run(&r);
        o->rc = r.rc;
    }
    run_free(&r);
    o->cpu_seconds = thread_cpu_seconds() - cpu_start;
    if (out) fclose(out);
    if (log) fclose(log);
    if (!out || !log) {
        run_outcome_free(o);
        o->rc = RUN_FAILED;
    }
}

void run_outcome_free(run_outcome *o)
{
    free(o->out);
    free(o->log);
    o->out = o->log = NULL;
}

/* ---- the runs of a scene -------------------------------------------------- */

int run_worst(int a, int b)
{
    /* Order of gravity: input error > failure > partial > an optimisation
     * without an answer > some runs of a sweep failed > untrusted >
     * complete. */
    static const int rank[] = {0, 5, 6, 4, 1, 2, 3};
    return rank[b] > rank[a] ? b : a;
}

static void fill_point(const run *r, scene_chain_param param, report_point *p)
{
    memset(p, 0, sizeof *p);
    p->spec = r->spec;
    p->param = param == SCENE_PARAM_S ? taper_chain_spec_s(r->spec) : taper_chain_spec_q(r->spec);
    p->src.n = taper_chain_size(r->chain);
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++) p->src.theory[q] = r->theory[q];
    if (r->sim)
        for (int o = 0; o < TAPER_N_OBSERVABLES; o++)
            p->src.obs[o] = taper_sim_observable(r->sim, (taper_observable)o);
}

/* Fits, table and figure of a complete scene. */
static int write_reports(const scene *sc, const run *runs)
{
    const scene_config *cfg = scene_cfg(sc);
    report_point *points = calloc(cfg->runs.n, sizeof *points);
    if (!points) return RUN_FAILED;
    for (size_t i = 0; i < cfg->runs.n; i++) fill_point(&runs[i], cfg->runs.param, &points[i]);
    int rc = run_write_reports(sc, points);
    free(points);
    return rc;
}

int run_write_reports(const scene *sc, report_point *points)
{
    const scene_config *cfg = scene_cfg(sc);
    report rep = {.cfg = cfg, .scene_path = scene_path(sc), .dir = cfg->output.dir,
                  .n = cfg->runs.n, .param_name = scene_chain_param_name(cfg->runs.param),
                  .points = points};
    analysis_apply(&rep);
    char *msg = NULL;
    int rc = RUN_COMPLETE;
    if (cfg->runs.fit && table_write_fits(&rep, &msg) != 0) rc = RUN_FAILED;
    if (rc == RUN_COMPLETE && cfg->runs.table) {
        if (table_write(&rep, &msg) != 0)
            rc = RUN_FAILED;
        else
            table_print(&rep, stdout);
    }
    if (rc == RUN_COMPLETE && cfg->runs.figure) {
        if (plot_write(&rep, &msg) != 0) rc = RUN_FAILED;
        int rendered = rc == RUN_COMPLETE ? plot_render(rep.dir, &msg) : -1;
        if (rendered == 0) printf("! wrote %s/figure.png\n", rep.dir);
        if (rendered == 1) printf("! note: %s\n", msg ? msg : "figure not rendered");
        if (rendered < 0) rc = RUN_FAILED;
    }
    if (rc != RUN_COMPLETE && out_was_stopped(msg) && interrupt_signal()) {
        char *said = run_stopped_writing(msg);
        fprintf(stderr, "%s: %s\n", scene_path(sc), said ? said : msg);
        free(said);
        rc = RUN_PARTIAL;
    } else if (rc != RUN_COMPLETE) {
        fprintf(stderr, "%s: %s\n", scene_path(sc), msg ? msg : "out of memory");
    }
    free(msg);
    analysis_free(&rep);
    return rc;
}

/* "! removed 2 temporary files ...": a killed run's leftovers. */
static void note_removed_temporaries(const char *dir)
{
    size_t removed = outdir_remove_temporaries(dir);
    if (removed)
        printf("! removed %zu temporary file%s a killed taper left in %s\n", removed,
               removed == 1 ? "" : "s", dir);
}

int run_scene(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    size_t n = cfg->runs.n;
    run *runs = calloc(n, sizeof *runs);
    if (!runs) return RUN_FAILED;
    int rc = RUN_COMPLETE;
    int ready = 0;
    for (size_t i = 0; i < n; i++) {
        if (run_init(&runs[i], sc, i, cfg->output.dir, NULL, stdout, stderr) != 0) {
            fprintf(stderr, "%s: out of memory\n", scene_path(sc));
            rc = RUN_FAILED;
            goto out;
        }
        runs[i].show_progress = n == 1;
        prepare_run(&runs[i]);
        ready |= runs[i].rc == RUN_COMPLETE;
    }
    /* The directories once a run is known to start: none for a scene the
     * library rejects.  An earlier sweep's files there go (run/outdir.c),
     * and the temporary files a killed run of ours left. */
    if (ready && (outdir_lock(sc, cfg->output.dir, 0) != 0 ||
                  outdir_clean(sc, NULL, NULL) != RUN_COMPLETE))
        for (size_t i = 0; i < n; i++) runs[i].rc = RUN_INPUT;
    else if (ready)
        note_removed_temporaries(cfg->output.dir);
    for (size_t i = 0; i < n; i++)
        if (runs[i].rc == RUN_COMPLETE && prepare_dir(&runs[i]) != 0) runs[i].rc = RUN_INPUT;
    parallel_for(n, (unsigned)cfg->output.threads, compute_run, runs);
    for (size_t i = 0; i < n; i++) {
        finish_run(&runs[i]);
        rc = run_worst(rc, runs[i].rc);
    }
    /* Untrusted runs still get their tables: the status and each file's
     * header say what they are worth.  (A signal after the last file was
     * written loses nothing: the status stays the runs'.) */
    int whole = rc == RUN_COMPLETE || rc == RUN_UNTRUSTED;
    if (whole) rc = run_worst(rc, write_reports(sc, runs));
out:
    for (size_t i = 0; i < n; i++) run_free(&runs[i]);
    free(runs);
    return rc;
}
