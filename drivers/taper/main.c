/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper -- the command line: read and validate a scene, echo it resolved,
 * and run it (run/run.c); or print the defaults, the reference, or one
 * resolved value.
 *
 *   taper SCENE.nml... [-o DIR] [GROUP.KEY=VALUE]...      run scenes
 *   taper SCENE.nml [--set GROUP.KEY=VALUE]... --get GROUP.KEY
 *   taper [SCENE.nml] [GROUP.KEY=VALUE]... --cite         what to cite (BibTeX)
 *   taper --defaults | --doc
 *
 * Exit status (docs/scene.md, "Exit status"): 0 complete; 1 library or
 * output failure (standard output included); 2 bad input (scene, command
 * line, output directory); 3 partial or interrupted (solver failure, a
 * signal, t_max or max_steps: granules.partial.tsv is written and no
 * granules.tsv exists; a signal before a run or while results are written:
 * stderr names what is not written); 4 complete but UNTRUSTED (conservation errors beyond &output
 * max_energy_error / max_momentum_error); 5 a sweep whose runs all ran, some
 * of them failing (sweep.tsv and runs.tsv name them; run/sweep.h); 6 a
 * calibration or design without an answer to trust (optimise/optimise.h).
 * With several scenes, the gravest.
 *
 * Sweeps: `--part I/N` computes part I of N of a sweep's runs (a job array;
 * the same command without it merges them), and `mpirun -np K taper ...`
 * spreads the runs over K ranks when taper is built with MPI (sweep_mpi.h,
 * docs/cluster.md), as it spreads each batch of a calibration's or design's
 * runs (optimise_mpi.h).
 */
#include "optimise/optimise.h"
#include "run/interrupt.h"
#include "run/run.h"
#include "run/sweep.h"
#include "scene/scene.h"
#include "taper.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef TAPER_MPI
#include "optimise_mpi.h" /* and a calibration's or design's batches of runs */
#include "sweep_mpi.h" /* mpirun -np K taper SCENE.nml: a sweep's runs on K ranks */
#endif

static const char usage[] =
    "usage: taper SCENE.nml... [-o DIR] [GROUP.KEY=VALUE]... [--get GROUP.KEY]\n"
    "                          [--part I/N]\n"
    "       taper [SCENE.nml] [GROUP.KEY=VALUE]... --cite\n"
    "       taper --defaults | --doc | --help | --version\n"
    "\n"
    "Runs each scene (Fortran namelist, see docs/scene.md; - reads standard input):\n"
    "builds the chain, computes the binary-collision theory and integrates the\n"
    "dynamics, echoes the resolved scene on stdout and writes DIR/granules.tsv\n"
    "(DIR: &output dir, or -o DIR).  A run that ends early writes\n"
    "DIR/granules.partial.tsv instead.\n"
    "\n"
    "  -o DIR      output directory (overrides &output dir; created if missing;\n"
    "              one scene only)\n"
    "  GROUP.KEY=VALUE, --set GROUP.KEY=VALUE\n"
    "              override one variable of every scene (VALUE in namelist syntax:\n"
    "              chain.n_granules=1000, solver.method='bdf', chain.s=0.1,0.2);\n"
    "              may be repeated\n"
    "  --get GROUP.KEY\n"
    "              print the resolved value of one variable and exit\n"
    "  --part I/N  a sweep's runs split in N parts: compute part I only (a job\n"
    "              array); then the same command without --part merges them\n"
    "              (reuses every run on disk, writes sweep.tsv; docs/cluster.md)\n"
    "  --cite      print BibTeX for what the scene's runs use (taper, the paper,\n"
    "              SUNDIALS or GSL, the contact models); without a scene: the\n"
    "              default scene's\n"
    "  --defaults  print a complete scene with every default, documented\n"
    "  --doc       print the scene reference (Markdown)\n"
    "\n"
    "Exit status: 0 complete, 1 failure, 2 bad input, 3 partial or interrupted,\n"
    "4 untrusted result (conservation errors beyond the scene's bounds),\n"
    "5 some runs of a sweep failed (DIR/runs.tsv names them), 6 a calibration\n"
    "or design without an answer to trust (not converged, a setting at its bound).\n";

typedef struct options {
    const char **paths;
    size_t n_paths;
    const char *out_dir;
    const char *get;
    int cite;             /* --cite: print what to cite instead of running   */
    const char **sets;
    size_t n_sets;
    size_t part, parts;   /* --part part/parts; 0: the whole sweep */
} options;

/* Standard output: the echo and the "! wrote" lines.  A reader that stops
 * reading (`taper ... | head -1`) is no failure: SIGPIPE is ignored, EPIPE
 * ends the output quietly and the runs go on, their files complete.  Any
 * other write error (`> /dev/full`: ENOSPC) loses the echo: reported, exit
 * status 1.  0, or -1 after printing why. */
static int stdout_lost;

static int check_stdout(void)
{
    if (stdout_lost) return -1;
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout)) return 0;
    if (errno == EPIPE) return 0;
    stdout_lost = 1;
    fprintf(stderr, "taper: cannot write to standard output: %s (the echo of the scene and "
            "the list of files written are lost)\n", strerror(errno ? errno : EIO));
    return -1;
}

/* Reads, overrides and validates the scene; NULL (after printing why) if
 * it is not valid. */
static scene *load_scene(const options *o, const char *path)
{
    scene *sc = scene_new(path);
    if (!sc) {
        fprintf(stderr, "%s: out of memory\n", path);
        return NULL;
    }
    size_t errors = scene_load(sc);
    for (size_t i = 0; errors == 0 && i < o->n_sets; i++) errors = scene_set(sc, o->sets[i]);
    if (errors == 0) errors = scene_validate(sc);
    if (errors == 0 && (!o->out_dir || scene_set_output_dir(sc, o->out_dir) == 0)) return sc;
    scene_print_diags(sc, stderr);
    if (scene_error_count(sc) == 0) fprintf(stderr, "%s: out of memory\n", path);
    scene_free(sc);
    return NULL;
}

static int one_scene(const options *o, scene *sc);

/* 1: one_scene will run sc as a calibration or design (every rank asks
 * alike: under MPI the ranks serve such a scene together). */
static int will_optimise(const options *o, const scene *sc)
{
    return sc && !o->get && !(o->parts && !scene_cfg(sc)->runs.swept) && optimise_wanted(sc);
}

static int run_one(const options *o, const char *path)
{
    scene *sc = load_scene(o, path);
    int optimising = will_optimise(o, sc);
#ifdef TAPER_MPI
    if (mpi_rank() > 0) { /* the runs rank 0 hands out, nothing printed */
        if (optimising) optimise_mpi_serve(sc);
        int worker_rc = mpi_worker(o->get || optimising ? NULL : sc);
        scene_free(sc);
        return sc ? worker_rc : RUN_INPUT;
    }
#endif
    int rc = one_scene(o, sc);
#ifdef TAPER_MPI
    if (optimising) optimise_mpi_scene_end(); /* the other ranks' share is over */
    mpi_scene_end(); /* the other ranks are done with this scene too */
#else
    (void)optimising;
#endif
    return rc;
}

static int one_scene(const options *o, scene *sc)
{
    if (!sc) return RUN_INPUT;
    if (o->parts && !scene_cfg(sc)->runs.swept) {
        fprintf(stderr, "taper: --part %zu/%zu: %s is not a sweep (no variable takes a list)\n",
                o->part, o->parts, scene_path(sc));
        scene_free(sc);
        return RUN_INPUT;
    }
    sweep_options sweep_opts = {.part = o->part, .parts = o->parts};
    const opt_runner *opt_runs = NULL; /* a calibration's or design's: this process's threads */
#ifdef TAPER_MPI
    sweep_opts.remote = mpi_remote(); /* NULL but on rank 0 of several */
    opt_runs = optimise_mpi_runner();  /* likewise */
#endif
    int rc;
    if (o->get) {
        rc = scene_print_value(sc, o->get, stdout) == 0 ? RUN_COMPLETE : RUN_INPUT;
        if (rc != RUN_COMPLETE)
            fprintf(stderr, "taper: --get %s: no such variable (write GROUP.KEY, e.g. "
                    "chain.n_granules)\n", o->get);
    } else {
        if (o->n_paths > 1) printf("! scene %s\n", scene_path(sc));
        scene_write(sc, stdout, 0);
        /* The echo is the record of what ran: without it, nothing runs. */
        if (check_stdout() != 0)
            rc = RUN_FAILED;
        else if (optimise_wanted(sc)) /* &calibrate data or &design objective */
            rc = optimise_scene(sc, opt_runs);
        else if (scene_cfg(sc)->runs.swept)
            rc = sweep_run(sc, &sweep_opts);
        else
            rc = run_scene(sc);
    }
    scene_free(sc);
    return rc;
}

/* The scenes from i on, which a signal kept from starting. */
static void not_started(const options *o, size_t i)
{
    static size_t said = (size_t)-1;
    if (said != (size_t)-1) return; /* once, for all of them */
    said = i;
    char by[64];
    interrupt_describe(by, sizeof by);
    fprintf(stderr, "taper: interrupted by %s: not started, nothing written:", by);
    for (size_t j = i; j < o->n_paths; j++) fprintf(stderr, " %s", o->paths[j]);
    fputc('\n', stderr);
}

static int run(const options *o)
{
    interrupt_install();
    int rc = RUN_COMPLETE;
    for (size_t i = 0; i < o->n_paths; i++) {
        if (interrupt_signal()) { /* the scenes after it are not started */
#ifdef TAPER_MPI
            if (mpi_rank() == 0) not_started(o, i);
            mpi_scene_skip(); /* but walked in step with the other ranks */
            rc = run_worst(rc, RUN_PARTIAL);
            continue;
#else
            not_started(o, i);
            rc = run_worst(rc, RUN_PARTIAL);
            break;
#endif
        }
        rc = run_worst(rc, run_one(o, o->paths[i]));
        if (check_stdout() != 0) rc = run_worst(rc, RUN_FAILED);
    }
    return rc;
}

static int print_defaults(int markdown)
{
    scene *sc = scene_new("NAME.nml");
    if (!sc) return RUN_FAILED;
    if (markdown) {
        scene_write_doc(sc, stdout);
    } else {
        printf("! taper %s: every scene variable with its default.\n", taper_version());
        scene_write(sc, stdout, 1);
    }
    scene_free(sc);
    return check_stdout() == 0 ? RUN_COMPLETE : RUN_FAILED;
}

/* --cite: one BibTeX list for every scene given (GROUP.KEY=VALUE applied),
 * or without a scene for the defaults, and nothing run. */
static int cite(const options *o)
{
    unsigned works = 0;
    for (size_t i = 0; i < (o->n_paths ? o->n_paths : 1); i++) {
        scene *sc = o->n_paths ? load_scene(o, o->paths[i]) : scene_new("defaults");
        size_t errors = 0;
        if (sc && !o->n_paths) {
            for (size_t j = 0; errors == 0 && j < o->n_sets; j++) errors = scene_set(sc, o->sets[j]);
            if (errors == 0) errors = scene_validate(sc);
            if (errors) scene_print_diags(sc, stderr);
        }
        if (!sc || errors) {
            scene_free(sc);
            return RUN_INPUT;
        }
        int marked = scene_cite_mark(sc, &works);
        scene_free(sc);
        if (marked != 0) {
            fprintf(stderr, "taper: --cite: out of memory\n");
            return RUN_FAILED;
        }
    }
    return scene_write_citations(works, stdout) == 0 && check_stdout() == 0 ? RUN_COMPLETE
                                                                           : RUN_FAILED;
}

static int bad_argument(const char *a, const char *why)
{
    fprintf(stderr, "taper: %s%s\n%s", a, why, usage);
    return RUN_INPUT;
}

/* GROUP.KEY=VALUE (a name, '.', a name, '='): an override, not a file. */
static int is_assignment(const char *a)
{
    size_t g = strspn(a, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_0123456789");
    if (g == 0 || a[g] != '.') return 0;
    size_t k = strspn(a + g + 1, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_0123456789");
    return k > 0 && a[g + 1 + k] == '=';
}

int main(int argc, char **argv)
{
    options o = {0};
    int rc = -1;
#ifdef TAPER_MPI
    mpi_start(&argc, &argv);
#endif
    /* Standard output closed by its reader: EPIPE, not death (check_stdout). */
    signal(SIGPIPE, SIG_IGN);
    o.sets = calloc((size_t)argc, sizeof *o.sets);
    o.paths = calloc((size_t)argc, sizeof *o.paths);
    if (!o.sets || !o.paths) return RUN_FAILED;
    int stdin_used = 0;
    for (int i = 1; rc < 0 && i < argc; i++) {
        const char *a = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            rc = check_stdout() == 0 ? RUN_COMPLETE : RUN_FAILED;
        } else if (strcmp(a, "--version") == 0) {
            printf("taper %s\n", taper_version());
            rc = check_stdout() == 0 ? RUN_COMPLETE : RUN_FAILED;
        } else if (strcmp(a, "--cite") == 0) {
            o.cite = 1;
        } else if (strcmp(a, "--defaults") == 0 || strcmp(a, "--doc") == 0) {
            rc = print_defaults(strcmp(a, "--doc") == 0);
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--set") == 0 || strcmp(a, "--get") == 0) {
            if (!value || !value[0]) {
                rc = bad_argument(a, strcmp(a, "-o") == 0
                                         ? ": needs a directory (-o DIR)"
                                         : strcmp(a, "--set") == 0
                                               ? ": needs GROUP.KEY=VALUE (--set chain.n_granules=1000)"
                                               : ": needs GROUP.KEY (--get chain.n_granules)");
            } else if (a[1] == 'o') {
                if (o.out_dir) rc = bad_argument(a, ": given twice");
                o.out_dir = value;
            } else if (a[2] == 's') {
                o.sets[o.n_sets++] = value;
            } else {
                o.get = value;
            }
            i++;
        } else if (strcmp(a, "--part") == 0) {
            char *end = NULL;
            unsigned long long part = value ? strtoull(value, &end, 10) : 0, parts = 0;
            if (value && end != value && *end == '/') {
                const char *q = end + 1;
                parts = strtoull(q, &end, 10);
                if (end == q) parts = 0;
            }
            if (parts == 0 || part == 0 || part > parts || *end != '\0' || value[0] == '-') {
                rc = bad_argument(a, ": write I/N with 1 <= I <= N (e.g. --part 3/8)");
            } else {
                o.part = (size_t)part;
                o.parts = (size_t)parts;
            }
            i++;
        } else if (is_assignment(a)) {
            o.sets[o.n_sets++] = a;
        } else if (strcmp(a, "-") == 0) {
            if (stdin_used++) rc = bad_argument(a, ": standard input given twice");
            o.paths[o.n_paths++] = a;
        } else if (a[0] == '-') {
            rc = bad_argument(a, ": unknown option");
        } else {
            o.paths[o.n_paths++] = a;
        }
    }
    if (rc < 0 && o.cite)
        rc = cite(&o);
    if (rc < 0 && o.n_paths == 0) {
        fputs(usage, stderr);
        rc = RUN_INPUT;
    }
    if (rc < 0 && o.out_dir && o.n_paths > 1)
        rc = bad_argument("-o", ": one directory for one scene (several scenes each write "
                          "their own &output dir)");
    if (rc < 0) rc = run(&o);
    free(o.sets);
    free(o.paths);
#ifdef TAPER_MPI
    rc = mpi_stop(rc);
#endif
    return rc;
}
