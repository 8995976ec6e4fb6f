/*
 * taper -- the command line: read and validate a scene, echo it resolved,
 * and run it (run/run.c); or print the defaults, the reference, or one
 * resolved value.
 *
 *   taper SCENE.nml [-o DIR] [--set GROUP.KEY=VALUE]...   run a scene
 *   taper SCENE.nml [--set ...] --get GROUP.KEY           print one value
 *   taper --defaults                                      every default
 *   taper --doc                                           the reference
 *
 * Exit status: 0 complete; 1 library or output failure; 2 bad input
 * (scene, command line, output directory); 3 partial result (solver failure,
 * Ctrl-C, t_max or max_steps reached: granules.partial.tsv is written and no
 * granules.tsv exists; an interrupted sweep); 4 a sweep whose runs all ran,
 * some of them failing (sweep.tsv and runs.tsv name them; run/sweep.h).
 */
#include "run/run.h"
#include "run/sweep.h"
#include "scene/scene.h"
#include "taper.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef TAPER_MPI
#include "run/mpi.h" /* mpirun -np K taper SCENE.nml: a sweep's runs on K ranks */
#endif

static const char usage[] =
    "usage: taper SCENE.nml [-o DIR] [--set GROUP.KEY=VALUE]... [--get GROUP.KEY]\n"
    "                   [--part I/N]\n"
    "       taper --defaults | --doc | --help | --version\n"
    "\n"
    "Runs the scene (Fortran namelist, see docs/scene.md): builds the chain,\n"
    "computes the binary-collision theory and integrates the dynamics, echoes the\n"
    "resolved scene on stdout and writes DIR/granules.tsv (DIR: &output dir, or\n"
    "-o DIR).  A run that ends early writes DIR/granules.partial.tsv instead.\n"
    "\n"
    "  -o DIR      output directory (overrides &output dir; created if missing)\n"
    "  --set GROUP.KEY=VALUE\n"
    "              override one variable (VALUE in namelist syntax: 12, 1d-9,\n"
    "              'bdf', .false., 0.1, 0.2); may be repeated\n"
    "  --get GROUP.KEY\n"
    "              print the resolved value of one variable and exit\n"
    "  --part I/N  a sweep's runs split in N parts: compute part I only (a job\n"
    "              array); then the same command without --part merges them\n"
    "              (reuses every run on disk, writes sweep.tsv; docs/cluster.md)\n"
    "  --defaults  print a complete scene with every default, documented\n"
    "  --doc       print the scene reference (Markdown)\n"
    "\n"
    "Exit status: 0 complete, 1 failure, 2 bad input, 3 partial result,\n"
    "4 some runs of a sweep failed (DIR/runs.tsv names them).\n";

typedef struct options {
    const char *path;
    const char *out_dir;
    const char *get;
    const char **sets;
    size_t n_sets;
    size_t part, parts;   /* --part part/parts; 0: the whole sweep */
} options;

/* Reads, overrides and validates the scene; NULL (after printing why) if
 * it is not valid. */
static scene *load_scene(const options *o)
{
    scene *sc = scene_new(o->path);
    if (!sc) {
        fprintf(stderr, "%s: out of memory\n", o->path);
        return NULL;
    }
    size_t errors = scene_load(sc);
    for (size_t i = 0; errors == 0 && i < o->n_sets; i++) errors = scene_set(sc, o->sets[i]);
    if (errors == 0) errors = scene_validate(sc);
    if (errors == 0 && (!o->out_dir || scene_set_output_dir(sc, o->out_dir) == 0)) return sc;
    scene_print_diags(sc, stderr);
    if (scene_error_count(sc) == 0) fprintf(stderr, "%s: out of memory\n", o->path);
    scene_free(sc);
    return NULL;
}

static int run(const options *o)
{
    scene *sc = load_scene(o);
#ifdef TAPER_MPI
    if (mpi_rank() > 0) { /* the runs rank 0 hands out, nothing printed */
        int worker_rc = mpi_worker(o->get ? NULL : sc);
        scene_free(sc);
        return sc ? RUN_COMPLETE : worker_rc;
    }
#endif
    if (!sc) return RUN_INPUT;
    if (o->parts && !scene_cfg(sc)->runs.swept) {
        fprintf(stderr, "taper: --part %zu/%zu: %s is not a sweep (no variable takes a list)\n",
                o->part, o->parts, o->path);
        scene_free(sc);
        return RUN_INPUT;
    }
    sweep_set_part(o->part, o->parts);
    int rc;
    if (o->get) {
        rc = scene_print_value(sc, o->get, stdout) == 0 ? RUN_COMPLETE : RUN_INPUT;
        if (rc != RUN_COMPLETE)
            fprintf(stderr, "taper: --get %s: no such variable (write GROUP.KEY, e.g. "
                    "chain.n_granules)\n", o->get);
    } else {
        run_install_sigint();
        scene_write(sc, stdout, 0);
        fflush(stdout);
        rc = run_scene(sc);
    }
    scene_free(sc);
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
    return RUN_COMPLETE;
}

static int bad_argument(const char *a)
{
    fprintf(stderr, "taper: unexpected argument '%s'\n%s", a, usage);
    return RUN_INPUT;
}

int main(int argc, char **argv)
{
    options o = {0};
    int rc = -1;
#ifdef TAPER_MPI
    mpi_start(&argc, &argv);
#endif
    if (!(o.sets = calloc((size_t)argc, sizeof *o.sets))) return RUN_FAILED;
    for (int i = 1; rc < 0 && i < argc; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc && argv[i + 1][0];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            rc = RUN_COMPLETE;
        } else if (strcmp(a, "--version") == 0) {
            printf("taper %s\n", taper_version());
            rc = RUN_COMPLETE;
        } else if (strcmp(a, "--defaults") == 0 || strcmp(a, "--doc") == 0) {
            rc = print_defaults(strcmp(a, "--doc") == 0);
        } else if (strcmp(a, "-o") == 0 && has_value) {
            o.out_dir = argv[++i];
        } else if (strcmp(a, "--set") == 0 && has_value) {
            o.sets[o.n_sets++] = argv[++i];
        } else if (strcmp(a, "--get") == 0 && has_value) {
            o.get = argv[++i];
        } else if (strcmp(a, "--part") == 0 && has_value) {
            const char *v = argv[++i];
            char *end = NULL;
            unsigned long long part = strtoull(v, &end, 10), parts = 0;
            if (end != v && *end == '/') {
                const char *q = end + 1;
                parts = strtoull(q, &end, 10);
                if (end == q) parts = 0;
            }
            if (parts == 0 || part == 0 || part > parts || *end != '\0' || v[0] == '-') {
                fprintf(stderr, "taper: --part %s: write I/N with 1 <= I <= N (e.g. --part 3/8)\n",
                        v);
                rc = RUN_INPUT;
            } else {
                o.part = (size_t)part;
                o.parts = (size_t)parts;
            }
        } else if (a[0] == '-' || o.path) {
            rc = bad_argument(a);
        } else {
            o.path = a;
        }
    }
    if (rc < 0 && !o.path) {
        fputs(usage, stderr);
        rc = RUN_INPUT;
    }
    if (rc < 0) rc = run(&o);
    free(o.sets);
#ifdef TAPER_MPI
    rc = mpi_stop(rc);
#endif
    return rc;
}
