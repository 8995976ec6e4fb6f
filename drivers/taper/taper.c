/*
 * taper -- run one scene: chain, binary-collision theory and (unless
 * numerics = .false.) the full dynamics, written to DIR/granules.tsv.
 *
 *   taper SCENE.nml [-o DIR]    run a scene
 *   taper --defaults            a complete, documented scene of defaults
 *   taper --doc                 the scene reference in Markdown
 *
 * Exit status: 0 complete; 1 library or output failure; 2 bad input
 * (scene, command line, output directory); 3 partial result (solver failure,
 * Ctrl-C, t_max or max_steps reached: granules.partial.tsv is written and no
 * granules.tsv exists).
 */
#include "results/analysis.h"
#include "results/output.h"
#include "results/plot.h"
#include "scene/scene.h"
#include "results/sweep.h"
#include "results/table.h"
#include "taper.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { EXIT_COMPLETE = 0, EXIT_FAILED = 1, EXIT_INPUT = 2, EXIT_PARTIAL = 3 };

static const char usage[] =
    "usage: taper SCENE.nml [-o DIR]\n"
    "       taper --defaults | --doc | --help | --version\n"
    "\n"
    "Runs the scene (Fortran namelist, see docs/scene.md): builds the chain,\n"
    "computes the binary-collision theory and integrates the dynamics, echoes the\n"
    "resolved scene on stdout and writes DIR/granules.tsv (DIR: &output dir, or\n"
    "-o DIR).  A run that ends early writes DIR/granules.partial.tsv instead.\n"
    "\n"
    "  -o DIR      output directory (overrides &output dir; created if missing)\n"
    "  --defaults  print a complete scene with every default, documented\n"
    "  --doc       print the scene reference (Markdown)\n"
    "\n"
    "Exit status: 0 complete, 1 failure, 2 bad input, 3 partial result.\n";

/* ---- interruption and progress ------------------------------------------ */

static volatile sig_atomic_t interrupted;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* Ctrl-C ends the run partial, keeping what was found; a second Ctrl-C
 * (SA_RESETHAND) kills the process as usual. */
static void install_sigint(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, NULL);
}

typedef struct progress_state {
    int show;           /* stderr is a terminal and progress = .true.   */
    int printed;        /* a progress line is on screen                 */
    double start, last; /* wall-clock seconds                           */
} progress_state;

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int monitor(const taper_progress *p, void *user)
{
    progress_state *ps = user;
    if (ps->show) {
        double now = wall_seconds();
        if (now - ps->last >= 0.2 || p->granule >= p->target) {
            double rate = (double)p->granule / fmax(now - ps->start, 1e-9);
            size_t todo = p->granule < p->target ? p->target - p->granule : 0;
            double left = rate > 0 ? (double)todo / rate : NAN;
            fprintf(stderr, "\rtaper: granule %zu/%zu  %.3g granules/s  %.1f s left   ",
                    p->granule, p->target, rate, left);
            ps->last = now;
            ps->printed = 1;
        }
    }
    return interrupted != 0;
}

static void progress_done(progress_state *ps)
{
    if (ps->printed) fputc('\n', stderr);
    ps->printed = 0;
}

/* ---- one run ------------------------------------------------------------- */

/* One value of a sweep (or the only run).  Computed possibly on a worker
 * thread: nothing here prints; what is to be said waits in `message`. */
typedef struct run {
    const scene *sc;
    size_t sweep_index;
    char dir[4200];
    taper_chain_spec spec;
    taper_chain *chain;
    taper_sim *sim;
    double *theory[4];       /* v, mu, T, t */
    taper_stats stats;
    int numerics;
    int show_progress;       /* only when runs are computed one at a time */
    int status;              /* taper_sim_run's status (TAPER_OK without numerics) */
    int rc;                  /* exit status of this run                   */
    int computed;            /* 0: skipped (interrupted before it started) */
    taper_error err;
    char message[TAPER_MESSAGE_SIZE + 4300];
} run;

static void run_free(run *r)
{
    taper_sim_free(r->sim);
    taper_chain_free(r->chain);
    for (int i = 0; i < 4; i++) free(r->theory[i]);
}

/* FILE[:LINE]: &group key: message, with the line of the key when given. */
static void key_error(const scene *sc, const char *group, const char *key, const char *msg)
{
    const scene_value *v = scene_get(sc, group, key);
    if (v && v->line > 0)
        fprintf(stderr, "%s:%d: &%s %s: %s\n", sc->path, v->line, group, key, msg);
    else
        fprintf(stderr, "%s: &%s %s: %s\n", sc->path, group, key, msg);
}

static int build_chain(run *r)
{
    scene_chain_spec(r->sc, r->sweep_index, &r->spec);
    r->chain = taper_chain_alloc(&r->spec, &r->err);
    if (r->chain) return EXIT_COMPLETE;
    /* Validation catches what it can name; what remains is the chain's size
     * (masses beyond double range): the key to change is n_granules. */
    key_error(r->sc, "chain", r->err.status == TAPER_ERANGE ? "n_granules" : "profile",
              r->err.message);
    return EXIT_INPUT;
}

static int compute_theory(run *r)
{
    size_t n = taper_chain_size(r->chain);
    for (int i = 0; i < 4; i++)
        if (!(r->theory[i] = malloc(n * sizeof(double)))) {
            snprintf(r->message, sizeof r->message, "%s: out of memory", r->sc->path);
            return EXIT_FAILED;
        }
    if (taper_theory_compute(r->chain, r->theory[0], r->theory[1], r->theory[2], r->theory[3],
                             &r->err) == TAPER_OK)
        return EXIT_COMPLETE;
    /* The library's theory messages name it already ("theory: velocity of ..."). */
    snprintf(r->message, sizeof r->message, "%s: %s", r->sc->path, r->err.message);
    return EXIT_FAILED;
}

/* The library's warnings (level 1) go to stderr, named by scene; its
 * information messages (level 0) are not shown. */
static void report_warning(int level, const char *message, void *user)
{
    if (level >= 1) fprintf(stderr, "%s: warning: %s\n", (const char *)user, message);
}

static int simulate(run *r)
{
    progress_state ps = {0};
    ps.show = r->show_progress && scene_bool(r->sc, "output", "progress") && isatty(STDERR_FILENO);
    ps.start = ps.last = wall_seconds();
    taper_solver_spec spec;
    taper_solver_spec_init(&spec);
    scene_solver_spec(r->sc, &spec);
    spec.monitor = monitor;
    spec.monitor_data = &ps;
    spec.log = report_warning;
    spec.log_data = (void *)r->sc->path;
    if (!(r->sim = taper_sim_alloc(r->chain, &spec, &r->err))) {
        snprintf(r->message, sizeof r->message, "%s: %s", r->sc->path, r->err.message);
        return EXIT_FAILED;
    }
    r->status = taper_sim_run(r->sim, &r->err);
    progress_done(&ps);
    taper_sim_stats(r->sim, &r->stats);
    if (r->status == TAPER_OK) return EXIT_COMPLETE;
    snprintf(r->message, sizeof r->message, "%s: %s", r->sc->path, r->err.message);
    if (r->status == TAPER_ESOLVER || r->status == TAPER_EINTERRUPTED || r->status == TAPER_ELIMIT)
        return EXIT_PARTIAL;
    return EXIT_FAILED;
}

/* The computation of one run: thread-safe (the library has no global
 * state), prints nothing. */
static void compute_run(size_t i, void *data)
{
    run *r = &((run *)data)[i];
    if (r->rc != EXIT_COMPLETE) return;
    if (interrupted) {
        r->rc = EXIT_PARTIAL;
        return;
    }
    r->computed = 1;
    r->rc = compute_theory(r);
    if (r->rc == EXIT_COMPLETE && r->numerics) r->rc = simulate(r);
}

/* ---- granules.tsv -------------------------------------------------------- */

/* The resolved scene as '#' lines; for a sweep, with this run's value only. */
static void write_scene_comment(const run *r, FILE *fp)
{
    char *text = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&text, &len);
    if (!mem) return;
    scene_write_point(r->sc, mem, r->sweep_index);
    fclose(mem);
    for (char *line = text, *end; line && *line; line = end ? end + 1 : NULL) {
        end = strchr(line, '\n');
        fprintf(fp, "# %.*s\n", end ? (int)(end - line) : (int)strlen(line), line);
    }
    free(text);
}

static void write_stats_comment(const run *r, FILE *fp)
{
    const taper_stats *s = &r->stats;
    if (!r->numerics) {
        fputs("# numerics = .false.: theory only, no dynamics\n", fp);
        return;
    }
    fprintf(fp, "# steps = %ld\n# rhs_evals = %ld\n# root_evals = %ld\n# jac_evals = %ld\n",
            s->steps, s->rhs_evals, s->root_evals, s->jac_evals);
    fprintf(fp, "# nonlin_iters = %ld\n# err_test_fails = %ld\n# window_changes = %ld\n",
            s->nonlin_iters, s->err_test_fails, s->window_changes);
    fprintf(fp, "# restarts = %ld\n", s->restarts); /* granules taken back into the window */
    fprintf(fp, "# max_window = %zu\n# granule_reached = %zu\n", s->max_window, s->granule_reached);
    fprintf(fp, "# t_final = %.17g\n# energy_error = %.3e\n# momentum_error = %.3e\n", s->t_final,
            s->energy_error, s->momentum_error);
}

static void run_columns(const run *r, out_columns *cols)
{
    memset(cols, 0, sizeof *cols);
    cols->n = taper_chain_size(r->chain);
    cols->col[1] = taper_chain_radius(r->chain);
    cols->col[2] = taper_chain_mass(r->chain);
    cols->col[3] = taper_chain_rest_position(r->chain);
    if (r->sim)
        for (int o = 0; o < TAPER_N_OBSERVABLES; o++) cols->col[4 + o] = taper_sim_observable(r->sim, o);
    cols->col[9] = r->theory[0];
    cols->col[10] = r->theory[2];
    cols->col[11] = r->theory[3];
}

static void write_granules(const run *r, FILE *fp, int partial)
{
    fprintf(fp, "# taper %s granules: per-granule pulse observables and binary-collision theory\n",
            taper_version());
    if (partial)
        fprintf(fp, "# PARTIAL result (%s): %s\n", taper_strerror(r->status), r->err.message);
    else
        fputs("# complete\n", fp);
    fprintf(fp, "# scene file: %s\n", r->sc->path);
    write_scene_comment(r, fp);
    write_stats_comment(r, fp);
    out_columns cols;
    run_columns(r, &cols);
    out_write_table(fp, &cols);
}

static int write_result(const run *r, int partial)
{
    const char *name = partial ? "granules.partial.tsv" : "granules.tsv";
    const char *stale = partial ? "granules.tsv" : "granules.partial.tsv";
    char msg[600];
    /* A stale result from an earlier run must not pass for this one. */
    if (out_remove(r->dir, stale, msg, sizeof msg) != 0) goto fail;
    out_file *f = out_open(r->dir, name, msg, sizeof msg);
    if (!f) goto fail;
    write_granules(r, f->fp, partial);
    if (out_commit(f, msg, sizeof msg) != 0) goto fail;
    printf("! wrote %s/%s\n", r->dir, name);
    return 0;
fail:
    fprintf(stderr, "%s: %s\n", r->sc->path, msg);
    return -1;
}

static int prepare_dir(const scene *sc, const char *dir)
{
    char msg[600];
    if (out_mkdir_p(dir, msg, sizeof msg) == 0 && access(dir, W_OK | X_OK) == 0) return 0;
    if (access(dir, F_OK) == 0) snprintf(msg, sizeof msg, "output directory %s is not writable", dir);
    key_error(sc, "output", "dir", msg);
    return -1;
}

/* Before any computation: the chain (a scene it rejects leaves no empty
 * directory), then the directory. */
static void prepare_run(run *r)
{
    r->numerics = scene_bool(r->sc, "solver", "numerics");
    r->rc = build_chain(r);
    if (r->rc == EXIT_COMPLETE && prepare_dir(r->sc, r->dir) != 0) r->rc = EXIT_INPUT;
}

/* After the computation, in the order of the sweep. */
static void finish_run(run *r)
{
    if (r->message[0]) fprintf(stderr, "%s\n", r->message);
    if (r->computed && (r->rc == EXIT_COMPLETE || r->rc == EXIT_PARTIAL) &&
        write_result(r, r->rc == EXIT_PARTIAL) != 0)
        r->rc = EXIT_FAILED;
}

/* ---- scenes and sweeps ------------------------------------------------------ */

static int worst(int a, int b)
{
    /* Order of gravity: input error > failure > partial > complete. */
    static const int rank[] = {0, 2, 3, 1};
    return rank[b] > rank[a] ? b : a;
}

/* DIR, or DIR/NAME=VALUE/ for each value of a swept variable. */
static void run_dirs(const scene *sc, int sv, const char *dir, run *runs, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (sv < 0) {
            snprintf(runs[i].dir, sizeof runs[i].dir, "%s", dir);
            continue;
        }
        char num[40];
        const scene_var *var = scene_var_at((size_t)sv);
        scene_format_real(sc->values[sv].list[i], num, sizeof num);
        snprintf(runs[i].dir, sizeof runs[i].dir, "%s/%s=%s", dir, var->name, num);
        printf("! sweep %s = %s -> %s\n", var->name, num, runs[i].dir);
    }
}

/* DIR/sweep.tsv: every run's granules.tsv rows, the swept value first. */
static int write_sweep_table(const scene *sc, int sv, const char *dir, const run *runs, size_t n)
{
    char msg[600];
    const char *name = scene_var_at((size_t)sv)->name;
    out_file *f = out_open(dir, "sweep.tsv", msg, sizeof msg);
    if (!f) goto fail;
    fprintf(f->fp, "# taper %s sweep over %s: the rows of every %s=VALUE/granules.tsv\n",
            taper_version(), name, name);
    for (size_t i = 0; i < n; i++) {
        out_columns cols;
        run_columns(&runs[i], &cols);
        out_write_rows(f->fp, &cols, name, sc->values[sv].list[i], i == 0);
    }
    if (out_commit(f, msg, sizeof msg) != 0) goto fail;
    printf("! wrote %s/sweep.tsv\n", dir);
    return EXIT_COMPLETE;
fail:
    fprintf(stderr, "%s: %s\n", sc->path, msg);
    return EXIT_FAILED;
}

static void fill_point(const run *r, report_point *p, const char *param_name)
{
    memset(p, 0, sizeof *p);
    p->spec = r->spec;
    p->param = strcmp(param_name, "s") == 0 ? r->spec.s : r->spec.q;
    p->src.n = taper_chain_size(r->chain);
    p->src.theory_v = r->theory[0];
    p->src.theory_T = r->theory[2];
    p->src.theory_t = r->theory[3];
    if (r->sim)
        for (int o = 0; o < TAPER_N_OBSERVABLES; o++) p->src.obs[o] = taper_sim_observable(r->sim, o);
}

/* Fits, table and figure of a complete scene. */
static int write_reports(const scene *sc, const char *dir, const run *runs, size_t n)
{
    report rep = {.sc = sc, .dir = dir, .n = n};
    const char *profile = scene_str(sc, "chain", "profile");
    rep.param_name = strstr(profile, "exponential") ? "q" : "s";
    if (!(rep.points = calloc(n, sizeof *rep.points))) return EXIT_FAILED;
    for (size_t i = 0; i < n; i++) fill_point(&runs[i], &rep.points[i], rep.param_name);
    analysis_apply(&rep);
    char msg[700];
    int rc = EXIT_COMPLETE;
    if (scene_group_active(sc, "fit") && table_write_fits(&rep, msg, sizeof msg) != 0) rc = EXIT_FAILED;
    if (rc == 0 && scene_group_active(sc, "table")) {
        if (table_write(&rep, msg, sizeof msg) != 0) rc = EXIT_FAILED;
        else table_print(&rep, stdout);
    }
    if (rc == 0 && scene_group_active(sc, "figure")) {
        if (plot_write(&rep, msg, sizeof msg) != 0) rc = EXIT_FAILED;
        int rendered = rc == 0 ? plot_render(dir, msg, sizeof msg) : -1;
        if (rendered == 0) printf("! wrote %s/figure.png\n", dir);
        if (rendered == 1) printf("! note: %s\n", msg), msg[0] = '\0';
        if (rendered < 0) rc = EXIT_FAILED;
    }
    if (rc != 0) fprintf(stderr, "%s: %s\n", sc->path, msg);
    free(rep.points);
    return rc;
}

static int run_all(const scene *sc, const char *dir)
{
    int sv = scene_sweep_var(sc);
    size_t n = sv < 0 ? 1 : sc->values[sv].count;
    run *runs = calloc(n, sizeof *runs);
    if (!runs) return EXIT_FAILED;
    run_dirs(sc, sv, dir, runs, n);
    int rc = EXIT_COMPLETE;
    for (size_t i = 0; i < n; i++) {
        runs[i].sc = sc;
        runs[i].sweep_index = i;
        runs[i].show_progress = n == 1;
        prepare_run(&runs[i]);
    }
    sweep_parallel(n, (unsigned)scene_int(sc, "output", "threads"), compute_run, runs);
    for (size_t i = 0; i < n; i++) {
        finish_run(&runs[i]);
        rc = worst(rc, runs[i].rc);
    }
    if (interrupted) rc = worst(rc, EXIT_PARTIAL);
    if (rc == EXIT_COMPLETE && sv >= 0) rc = write_sweep_table(sc, sv, dir, runs, n);
    if (rc == EXIT_COMPLETE) rc = write_reports(sc, dir, runs, n);
    for (size_t i = 0; i < n; i++) run_free(&runs[i]);
    free(runs);
    return rc;
}

static scene *load_scene(const char *path, const char *out_dir)
{
    taper_solver_spec lib;
    taper_solver_spec_init(&lib);
    scene *sc = scene_new(path, &lib);
    if (!sc) {
        fprintf(stderr, "%s: out of memory\n", path);
        return NULL;
    }
    if (scene_load(sc) == 0 && scene_validate(sc) == 0 &&
        (!out_dir || scene_set_str(sc, "output", "dir", out_dir) == 0))
        return sc;
    scene_print_diags(sc, stderr);
    if (sc->n_errors == 0) fprintf(stderr, "%s: out of memory\n", path);
    scene_free(sc);
    return NULL;
}

static int run_scene(const char *path, const char *out_dir)
{
    scene *sc = load_scene(path, out_dir);
    if (!sc) return EXIT_INPUT;
    install_sigint();
    scene_write(sc, stdout, 0);
    fflush(stdout);
    int rc = run_all(sc, scene_str(sc, "output", "dir"));
    scene_free(sc);
    return rc;
}

static int print_defaults(int markdown)
{
    taper_solver_spec lib;
    taper_solver_spec_init(&lib);
    scene *sc = scene_new("NAME.nml", &lib);
    if (!sc) return EXIT_FAILED;
    if (markdown) {
        scene_write_doc(sc, stdout);
    } else {
        printf("! taper %s: every scene variable with its default.\n", taper_version());
        scene_write(sc, stdout, 1);
    }
    scene_free(sc);
    return EXIT_COMPLETE;
}

int main(int argc, char **argv)
{
    const char *path = NULL, *out_dir = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            return EXIT_COMPLETE;
        }
        if (strcmp(a, "--version") == 0) {
            printf("taper %s\n", taper_version());
            return EXIT_COMPLETE;
        }
        if (strcmp(a, "--defaults") == 0) return print_defaults(0);
        if (strcmp(a, "--doc") == 0) return print_defaults(1);
        if (strcmp(a, "-o") == 0 && i + 1 < argc && argv[i + 1][0]) {
            out_dir = argv[++i];
        } else if (a[0] == '-' || path) {
            fprintf(stderr, "taper: unexpected argument '%s'\n%s", a, usage);
            return EXIT_INPUT;
        } else {
            path = a;
        }
    }
    if (!path) {
        fputs(usage, stderr);
        return EXIT_INPUT;
    }
    return run_scene(path, out_dir);
}
