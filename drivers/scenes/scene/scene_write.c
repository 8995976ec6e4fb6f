/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_write.c -- a scene back to text: the resolved namelist (the echo
 * and `taper --defaults`, which must parse again) and the Markdown
 * reference (`taper --doc`, committed as docs/scene.md).  Both walk the
 * variable table, so they cannot drift from the parser.
 */
#include "scene_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* A bound as text: 2^53, the largest whole number every double below it
 * holds exactly (the integers' bound), as "2^53"; any other shortest. */
static void format_bound(double x, char buf[SCENE_REAL_TEXT])
{
    if (x == 0x1p53) snprintf(buf, SCENE_REAL_TEXT, "2^53");
    else scene_format_real(x, buf);
}

char *scene_range_text(const scene_var *var)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp) return NULL;
    if (var->type == SCENE_CHOICE) {
        for (int v = var->choice_first; scene_choice_name(var, v); v++)
            fprintf(fp, "%s'%s'", v == var->choice_first ? "" : ", ", scene_choice_name(var, v));
    } else if ((var->type == SCENE_REAL || var->type == SCENE_INTEGER ||
                var->type == SCENE_REAL_LIST) && !(var->lo == 0 && var->hi == 0)) {
        char lo[SCENE_REAL_TEXT], hi[SCENE_REAL_TEXT];
        format_bound(var->lo, lo);
        format_bound(var->hi, hi);
        fprintf(fp, "%s%c%s, %s%c", var->type == SCENE_REAL_LIST ? "each in " : "",
                (var->flags & SCENE_LO_OPEN) ? '(' : '[', lo, hi,
                isinf(var->hi) || (var->flags & SCENE_HI_OPEN) ? ')' : ']');
    } else if (var->type == SCENE_LOGICAL) {
        fputs(".true., .false.", fp);
    }
    fclose(fp);
    return text;
}

char *scene_var_range(size_t i)
{
    return i < scene_var_count() ? scene_range_text(scene_var_at(i)) : NULL;
}

/* Fortran string literal: quotes doubled, so any text survives. */
static void write_quoted(const char *s, FILE *fp)
{
    fputc('\'', fp);
    for (; *s; s++) {
        fputc(*s, fp);
        if (*s == '\'') fputc('\'', fp);
    }
    fputc('\'', fp);
}

/* A real list, five values per line (continuation lines are plain
 * namelist syntax). */
static void write_list(const scene_reals *r, FILE *fp)
{
    char num[SCENE_REAL_TEXT];
    for (size_t i = 0; i < r->n; i++) {
        scene_format_real(r->v[i], num);
        fprintf(fp, "%s%s", num, i + 1 < r->n ? "," : "");
        if (i + 1 < r->n) fputs((i + 1) % 5 == 0 ? "\n      " : " ", fp);
    }
}

void scene_write_value(const scene_var *var, const scene_config *cfg, FILE *fp)
{
    const void *f = scene_cfield(cfg, var);
    char num[SCENE_REAL_TEXT];
    const scene_reals *sweep = cfg->sweep.lists ? &cfg->sweep.lists[scene_var_index(var)] : NULL;
    if (sweep && sweep->n > 1) {
        for (size_t i = 0; i < sweep->n; i++) {
            if (var->type == SCENE_INTEGER)
                snprintf(num, sizeof num, "%lld", (long long)sweep->v[i]);
            else
                scene_format_real(sweep->v[i], num);
            fprintf(fp, "%s%s", i ? ", " : "", num);
        }
        return;
    }
    if (scene_var_is_list(var)) {
        const scene_reals *r = f;
        for (size_t i = 0; i < r->n; i++) {
            scene_format_real(r->v[i], num);
            fprintf(fp, "%s%s", i ? ", " : "", num);
        }
        return;
    }
    switch (var->type) {
    case SCENE_STRING: {
        char *const *s = f;
        write_quoted(*s ? *s : "", fp);
        break;
    }
    case SCENE_CHOICE: {
        int v;
        memcpy(&v, f, sizeof v);
        const char *name = scene_choice_name(var, v);
        write_quoted(name ? name : "", fp);
        break;
    }
    case SCENE_INTEGER: {
        long long x;
        memcpy(&x, f, sizeof x);
        fprintf(fp, "%lld", x);
        break;
    }
    case SCENE_LOGICAL: {
        int b;
        memcpy(&b, f, sizeof b);
        fputs(b ? ".true." : ".false.", fp);
        break;
    }
    default: {
        double x;
        memcpy(&x, f, sizeof x);
        if (!isnan(x)) {
            scene_format_real(x, num);
            fputs(num, fp);
        }
        break;
    }
    }
}

/* The value text of var, malloc'd (for padded columns). */
static char *value_text(const scene_var *var, const scene_config *cfg)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp) return NULL;
    scene_write_value(var, cfg, fp);
    fclose(fp);
    return text;
}

/* With &material a dimensional value is given in SI: the echo says in
 * which unit, and what it is in the library's rescaled units (when the
 * configuration has one material: a sweep of &material has one per run). */
static void write_unit(const scene *sc, const scene_config *cfg, size_t i, FILE *fp)
{
    const scene_var *var = scene_var_at(i);
    /* A value the scene left out is echoed too (0: a dimensional setting
     * the echo writes without being given has the default 0, the same in
     * every unit; tests/driver/test_scene.c checks it). */
    (void)sc;
    fprintf(fp, "  ! %s", taper_dimension_unit(var->dim));
    for (size_t k = 0; k < cfg->runs.n_swept; k++)
        if (strcmp(scene_var_at(cfg->runs.swept_row[k])->group, "material") == 0) {
            fputc('\n', fp);
            return;
        }
    scene_config at;
    scene_config_at(cfg, 0, &at);
    double scale = scene_input_scale(&at, var->dim);
    if (var->type == SCENE_REAL && scene_row_count(cfg, i) == 1) {
        char num[SCENE_REAL_TEXT];
        scene_format_real(scene_row_value(cfg, i, 0) / scale, num);
        fprintf(fp, ", %s in rescaled units", num);
    } else {
        char num[SCENE_REAL_TEXT];
        scene_format_real(scale, num);
        fprintf(fp, "; one rescaled unit is %s %s", num, taper_dimension_unit(var->dim));
    }
    fputc('\n', fp);
}

/* A sweep of a one-value row (exponent, n_granules, rtol, ...): its list. */
static int write_sweep_list(const scene *sc, const scene_config *cfg, size_t i, FILE *fp, int doc)
{
    const scene_var *var = scene_var_at(i);
    if (!cfg->sweep.lists || cfg->sweep.lists[i].n < 2) return 0;
    const scene_reals *r = &cfg->sweep.lists[i];
    if (doc) fprintf(fp, "  ! %s\n", var->doc);
    fprintf(fp, "  %s = ", var->name);
    if (var->type == SCENE_INTEGER) {
        for (size_t j = 0; j < r->n; j++) {
            fprintf(fp, "%lld%s", (long long)r->v[j], j + 1 < r->n ? "," : "");
            if (j + 1 < r->n) fputs((j + 1) % 5 == 0 ? "\n      " : " ", fp);
        }
    } else {
        write_list(r, fp);
    }
    if (!doc && cfg->material.on && var->dim != TAPER_DIM_NUMBER)
        write_unit(sc, cfg, i, fp);
    else
        fputc('\n', fp);
    return 1;
}

/* cfg: the scene's, or its configuration at one point (scene_config_at). */
static void write_var(const scene *sc, const scene_config *cfg, size_t i, FILE *fp, int doc)
{
    const scene_var *var = scene_var_at(i);
    /* A variable beyond the paper that the scene leaves out holds its
     * default: the echo leaves it out too, so that every scene written
     * before it existed echoes exactly as it did. */
    if (!doc && (var->flags & SCENE_EXTRA) && !sc->origin[i].given) return;
    if (write_sweep_list(sc, cfg, i, fp, doc)) return;
    if (doc && !sc->origin[i].given && (var->flags & SCENE_FROM_PATH)) {
        /* Its default depends on the scene's file name: leave it derived. */
        fprintf(fp, "  ! %-10s = %-18s ! %s\n", var->name, "'out/NAME'", var->doc);
        return;
    }
    if (var->type == SCENE_REAL_LIST) {
        const scene_reals *r = scene_cfield(cfg, var);
        if (r->n == 0) {
            /* Namelists cannot say "empty list": leave it out, documented. */
            fprintf(fp, "  ! %s = (none)%s%s\n", var->name, doc ? "  ! " : "", doc ? var->doc : "");
            return;
        }
        if (doc) fprintf(fp, "  ! %s\n", var->doc);
        fprintf(fp, "  %s = ", var->name);
        write_list(r, fp);
        if (!doc && cfg->material.on && var->dim != TAPER_DIM_NUMBER)
            write_unit(sc, cfg, i, fp);
        else
            fputc('\n', fp);
        return;
    }
    if (var->type == SCENE_REAL && isnan(*(const double *)scene_cfield(cfg, var))) {
        /* A real without default, left out. */
        fprintf(fp, "  ! %s = (none)%s%s\n", var->name, doc ? "  ! " : "", doc ? var->doc : "");
        return;
    }
    if (doc) {
        char *text = value_text(var, cfg);
        fprintf(fp, "  %-12s = %-18s ! %s\n", var->name, text ? text : "", var->doc);
        free(text);
        return;
    }
    fprintf(fp, "  %s = ", var->name);
    scene_write_value(var, cfg, fp);
    if (cfg->material.on && var->dim != TAPER_DIM_NUMBER)
        write_unit(sc, cfg, i, fp);
    else
        fputc('\n', fp);
}

/* A group of variables beyond the paper only (&ends, &striker, ...) that
 * the scene does not give. */
static int extra_group_unused(const scene *sc, const char *group)
{
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *var = scene_var_at(i);
        if (strcmp(var->group, group) != 0) continue;
        if (!(var->flags & SCENE_EXTRA) || sc->origin[i].given) return 0;
    }
    return 1;
}

/* The optional groups are on when &fit model is not 'none' and &table or
 * &figure has a name; the groups beyond the paper when the scene gives one
 * of their variables. */
static int group_on(const scene *sc, const char *group)
{
    if (extra_group_unused(sc, group)) return 0;
    if (strcmp(group, "fit") == 0) return sc->cfg.fit.model != SCENE_FIT_NONE;
    if (strcmp(group, "table") == 0) return sc->cfg.table.name[0] != '\0';
    if (strcmp(group, "figure") == 0) return sc->cfg.figure.name[0] != '\0';
    if (strcmp(group, "sweep") == 0) {
        /* Only where it matters: several lists, or a mode the file gives. */
        int mode = scene_var_find("sweep", "mode");
        return sc->cfg.runs.n_swept > 1 || sc->origin[mode].given;
    }
    return 1;
}

/* point: write only that value of a swept variable (SIZE_MAX: all). */
static void write_scene(const scene *sc, FILE *fp, int doc, size_t point)
{
    scene_config at;
    const scene_config *cfg = &sc->cfg;
    if (point != SIZE_MAX) {
        scene_config_at(&sc->cfg, point, &at);
        cfg = &at;
    }
    for (size_t g = 0; g < SCENE_N_GROUPS; g++) {
        const char *group = scene_group_name(g);
        /* The echo leaves out optional groups that are off: shorter, and
         * the same scene.  One point of a sweep is a single run: no &sweep. */
        if (!doc && !group_on(sc, group)) continue;
        if (!doc && point != SIZE_MAX && strcmp(group, "sweep") == 0) continue;
        if (doc) fprintf(fp, "! &%s: %s\n", group, scene_group_doc(g));
        fprintf(fp, "&%s\n", group);
        for (size_t i = 0; i < scene_var_count(); i++)
            if (strcmp(scene_var_at(i)->group, group) == 0) write_var(sc, cfg, i, fp, doc);
        fputs("/\n", fp);
    }
}

void scene_write(const scene *sc, FILE *fp, int doc) { write_scene(sc, fp, doc, SIZE_MAX); }

void scene_write_point(const scene *sc, FILE *fp, size_t point)
{
    write_scene(sc, fp, 0, point);
}

int scene_print_value(const scene *sc, const char *name, FILE *fp)
{
    const char *dot = strchr(name, '.');
    if (!dot) return -1;
    char *group = text_printf("%.*s", (int)(dot - name), name);
    int i = group ? scene_var_find(group, dot + 1) : -1;
    free(group);
    if (i < 0) return -1;
    scene_write_value(scene_var_at((size_t)i), &sc->cfg, fp);
    fputc('\n', fp);
    return 0;
}

/* Default column of the Markdown table (malloc'd). */
static char *doc_default(const scene *sc, size_t i)
{
    const scene_var *var = scene_var_at(i);
    size_t n = 1;
    if (var->flags & SCENE_FROM_PATH) return text_printf("`'out/NAME'` for NAME.nml");
    if (var->type == SCENE_REAL_LIST) return text_printf("none");
    if (var->type == SCENE_REAL) scene_var_reals(sc, i, &n);
    if (n == 0) return text_printf("none");
    char *text = value_text(var, &sc->cfg);
    char *cell = text_printf("`%s`%s", text ? text : "",
                              var->lib != SCENE_OWN && !var->def ? " (library default)" : "");
    free(text);
    return cell;
}

static const char doc_intro[] =
    "# Scene files\n"
    "\n"
    "<!-- Generated by `taper --doc` from the variable table in drivers/scenes/scene/scene.c; do not edit.\n"
    "     Regenerate: build/drivers/taper/taper --doc > docs/scene.md -->\n"
    "\n"
    "A scene is a Fortran namelist file (`taper SCENE.nml [-o DIR]`).  Syntax:\n"
    "groups `&name ... /`; names are case-insensitive; `!` starts a comment;\n"
    "strings are quoted (`'..'` or `\"..\"`, a doubled quote stands for itself);\n"
    "logicals are `.true.`/`.false.` (also `T`/`F`, `.t.`/`.f.`); reals may use\n"
    "`d` or `e` exponents (`1d-10`, `1.5e3`, `2`); values are separated by commas\n"
    "or blanks and may continue on the next line; lists take repeat counts\n"
    "(`3*1.0`).  Every variable is optional; `taper --defaults` prints a complete\n"
    "scene with every default and its documentation.\n"
    "\n"
    "**Names.** Every variable has one *name*, unique over all groups: the keyword\n"
    "of the Python package (`taper.simulate(striker_radius=1.0)`), the setting of\n"
    "libtaper's table of settings (`taper_chain_spec_set_option`) and the field an\n"
    "error names.  In a scene file the variable is written in its group as its\n"
    "*key*: the name without the group's name in front, if it has it\n"
    "(`striker_radius` is `&striker radius`, `figure_every` is `&figure every`,\n"
    "`load` is `&chain load`).  The chain and solver variables are generated from\n"
    "the library's table (include/taper.h, \"Settings by name\"): their ranges,\n"
    "defaults and descriptions are the library's.\n"
    "\n"
    "**Units.** Without `&material`, every value is in the rescaled units of eq. (5)\n"
    "of arXiv:0905.4512 (lengths of granules in R_1, times in the unit of eq. (5),\n"
    "velocities in the impulse's).  With `&material` (real Hertz spheres) every\n"
    "value with a unit in the column \"SI unit\" is read in that unit: `t_end` and\n"
    "`&sensors interval` in s, `damping` (the Kuwabara-Kono constant A of\n"
    "F = r (z^(3/2) + (3/2) A z^(1/2) dz/dt)) in s, `drag` in kg/s, `load` in N,\n"
    "radii and the striker's radius in m (the first radius is `&material radius`),\n"
    "densities in kg/m^3, compliances (1 - nu^2)/E in 1/Pa; the echo writes each\n"
    "with its unit and its value in rescaled units, and the results are in SI too\n"
    "(`&output units` is then `'si'` unless the scene says `'rescaled'`).  A value\n"
    "the scene leaves out is the library's default.  So a sweep of `&material\n"
    "velocity` keeps every physical input fixed.\n"
    "\n"
    "Errors (unknown group or key, wrong type, repeated key, syntax, out-of-range\n"
    "values) are reported as `FILE:LINE: &group key: message`, and `taper` exits\n"
    "with status 2.  Each rule has one owner: the chain and solver settings and\n"
    "the fit's exponent are checked by the library (each message states the\n"
    "range and why its bounds are there), everything else by the scene (column\n"
    "\"checked by\").  A value the file leaves out is reported at the line where\n"
    "its group opens.\n"
    "\n"
    "On the command line, `GROUP.KEY=VALUE` (or `--set GROUP.KEY=VALUE`) overrides\n"
    "one variable (the value in namelist syntax, e.g. `taper scene.nml\n"
    "chain.n_granules=1000 fit.k_min=12`) and `--get GROUP.KEY` prints its\n"
    "resolved value instead of running the scene.  Several scenes run one after\n"
    "the other (`taper a.nml b.nml`), each into its own `&output dir`, every\n"
    "override applying to each; `-o DIR` takes one scene.  `-` reads the scene\n"
    "from standard input (named `stdin` in messages, default directory\n"
    "`out/stdin`).  A group may also end with `&end` instead of `/`, as older\n"
    "namelist files do.\n"
    "\n"
    "**Sweeps.** Every variable of type \"list: sweep\" below (the reals and integers\n"
    "of `&chain`, `&ends`, `&striker`, `&losses`, `&material`, `&solver`, and `&sensors\n"
    "interval`) accepts a list of values (`q = 0.05, 0.1`, `n_granules = 3*1000`,\n"
    "`seed = 1, 2, 3`: an ensemble of disordered chains).\n"
    "Lists of several variables make a grid, every combination, the variable later\n"
    "in this reference varying fastest; `&sweep mode = 'zip'` runs the i-th values\n"
    "together instead (lists of equal length).  Each run goes into its own\n"
    "sub-directory named by its values, `DIR/s=VALUE/` or\n"
    "`DIR/q=0.05,exponent=2.5/`, and the driver writes `DIR/sweep.tsv` (one column\n"
    "per swept variable, then the columns of `granules.tsv`) and `DIR/runs.tsv` (a\n"
    "row per run: the swept values, its status, every statistic of its\n"
    "`granules.tsv` header, and the reason of a run without rows: \"Result files\"\n"
    "below).  Runs are computed in parallel (`&output threads`; under\n"
    "`mpirun`, on every rank: docs/cluster.md), the dearest first, with results\n"
    "identical to serial runs.  A run that fails (solver failure, a point the\n"
    "library refuses such as `forward_linear` with N beyond 1 + 1/s, `t_max`) does\n"
    "not stop the others, for any number of swept variables: sweep.tsv and runs.tsv\n"
    "name it, and `taper` exits with status 5.  A sweep in which no run can hold\n"
    "is refused before any run.  `s = 0` and `q = 0` are the monodisperse chain, the\n"
    "limit of the taper, with the theory's columns of that chain: the baseline of a\n"
    "sweep over `s` or `q` (a tapered profile whose `s` or `q` is not given at all is\n"
    "refused).  A sweep stopped halfway (Ctrl-C, a killed job) resumes with the same\n"
    "command: complete runs made from the same resolved scene, whose files are\n"
    "those `DIR/RUN/scene.hash` names and pass their footers, are reused, the others\n"
    "computed; run directories of another sweep in DIR are removed.\n"
    "\n"
    "**Fits, tables, figures.** `&fit` fits one per-granule quantity against another\n"
    "over a window of granules, for every run, to the numerics and to the exact\n"
    "binary-collision theory alike, each with its standard error (`DIR/fits.tsv`).\n"
    "`&table` tabulates the fitted value over the sweep next to the paper's printed\n"
    "values (`DIR/table.tsv`, and on stdout).  `&figure` writes the per-granule data\n"
    "(`DIR/figure.tsv`), the fits (`DIR/fits.tsv`) and a gnuplot script\n"
    "(`DIR/figure.gp`), and renders `DIR/figure.png` when gnuplot is installed.\n"
    "These three groups are off unless `&fit model` or `&table`/`&figure name` is\n"
    "given.  The scenes of the paper's figures and tables are in\n"
    "`share/scenes/paper/` (see docs/paper.md).\n"
    "\n"
    "**Beyond the paper** (models and sources in docs/physics.md, one scene\n"
    "per capability in `share/scenes/physics/`).  `&ends` puts a wall at either end,\n"
    "`&striker` replaces the impulse by a striker or a piston, `&chain load` precompresses,\n"
    "`&losses` adds viscoelastic damping and drag, `&chain disorder` perturbs radii or\n"
    "masses from a seed, `profile = 'decorated'` repeats a `pattern`, `radii_file`\n"
    "reads a measured chain.  Every one defaults to the paper's idealisation, and the\n"
    "echo leaves out what a scene does not give, so the paper's scenes run and echo as\n"
    "before.  `&material` (Hertz contacts, n = 5/2) gives real units: Young's modulus,\n"
    "Poisson ratio, density, R_1 in metres and the impact velocity, mixed chains by a\n"
    "`sequence` of materials; every input is then in SI (above) and every result file\n"
    "too, each column's unit in its header (`t_pass[s]`, `force[N]`), the SI value of\n"
    "each rescaled unit in granules.tsv's header (`# unit_time = ... s`); fits, tables\n"
    "and figures stay rescaled.  `&sensors` samples the run every `interval` (with\n"
    "`&solver t_end` the run goes on past the pulse, to follow reflections):\n"
    "`sensors.tsv` (t, granule, x, v, contact forces of the chosen granules),\n"
    "`walls.tsv` (the force on each wall; its peak, time and impulse in the header) and\n"
    "the space-time picture of v(k, t), `spacetime.tsv` and `spacetime.png`.  Every run's\n"
    "granules.tsv header ends with its energy budget (`energy_initial`, `_dissipated`,\n"
    "`_transmitted`, `_reflected`, `_in_chain`), also printed on stdout.  Where the\n"
    "binary-collision theory does not describe the chain (a static load, losses), its\n"
    "columns are nan, and the header (`# theory: nan: ...`) and stderr say why.\n"
    "\n"
    "**Calibration and design.** `&calibrate data` makes the scene a calibration: the\n"
    "settings named by `free` fitted to a table of measurements in the form of taper's\n"
    "own files (docs/calibration.md).  `&design objective` makes it a design: a result of\n"
    "the run minimised or maximised over the settings named by `free` within bounds\n"
    "(docs/optimal-design.md).  Either runs the scene at every point it tries, writes its\n"
    "result files and the scene at the optimum (`fitted.nml`, `optimum.nml`), and exits\n"
    "with status 6 when it has no answer to trust.\n";

/* After the tables: the driver's contract around the scene (exit status,
 * result files, signals, concurrent runs, limits). */
static void write_doc_outro(FILE *fp)
{
    fputs("\n## Exit status\n"
          "\n"
          "| status | meaning |\n"
          "|--------|---------|\n"
          "| 0 | complete: every result written, conservation within the bounds |\n"
          "| 1 | failure: the library (memory, theory overflow), a result file (a full disk, "
          "an I/O error, `ulimit -f`: its temporary removed), or standard output could not be "
          "written (`taper ... > /dev/full`: the echo is the record of what ran, so nothing "
          "runs) |\n"
          "| 2 | bad input: scene, command line, output directory (also: in use by another run) |\n"
          "| 3 | partial or interrupted: a run ended early (solver failure, `t_max`, "
          "`max_steps`, or SIGINT, SIGTERM, SIGHUP, SIGXCPU during its computation): "
          "`granules.partial.tsv` holds what was found, and there is no `granules.tsv` of that "
          "run; or a signal came before a run started, or while the results were written: "
          "stderr names what is not written, and every file with a result's name is whole "
          "(\"Signals, time limits and batch queues\") |\n"          "| 4 | untrusted: complete, but the relative energy or momentum error exceeds "
          "`&output max_energy_error` / `max_momentum_error` (default 1e-3, the library's "
          "drift warning); `granules.tsv` has the line `# UNTRUSTED: ...` after `# complete` |\n"
          "| 5 | some runs of a sweep failed: every run ran, but some ended early or were "
          "refused by the library (a point beyond a profile's limits, such as "
          "`forward_linear` with N >= 1 + 1/s, in a sweep of one variable or several); "
          "`sweep.tsv` names each with a comment line, `runs.tsv` gives every run's status "
          "and reason |\n"
          "| 6 | a calibration or a design without an answer to trust: it did not converge "
          "(`&calibrate max_iter`, `&design max_runs`), the data do not determine a fitted "
          "setting, or a fitted setting ended at its bound; its files are written and say so "
          "(docs/calibration.md, docs/optimal-design.md) |\n"
          "\n"
          "An observable a complete run could not find is nan, never 0, with a warning on "
          "stderr (Python: `Result.warnings`) and status 0: a velocity maximum that never "
          "came, passes beyond a pulse drag absorbed, a wall the pulse never reached (give "
          "`t_end`).  A run with a right wall goes on until the wall's first contact has "
          "opened (its force back to zero; under a static load, below half its rise), and to "
          "`t_end` if that is later: the wall's peak force, its time and its impulse "
          "(`wall_*` in the header, over [0, t_final]) are those of the whole contact without "
          "`t_end`.\n"
          "\n"
          "With several runs (a sweep, several scenes) the status is the gravest: 2, then 1, "
          "3, 6, 5, 4, 0 (an interrupted sweep, calibration or design: 3).  A reader that stops reading standard output (`taper ... | head -1`) is "
          "not a failure: the runs go on, their files are complete, and the status is theirs "
          "(SIGPIPE is ignored, and the echo stops quietly).\n"
          "\n"
          "Under MPI the status is the launcher's.  A signal that reaches the ranks (`srun` "
          "and `scancel`, a queue's time limit, `kill` of the ranks) stops the whole sweep "
          "with status 3, as above.  Open MPI's `mpirun` itself, sent Ctrl-C, SIGINT, SIGTERM "
          "or SIGHUP, sends SIGTERM to every rank (the runs say `interrupted by SIGTERM from "
          "mpirun`) and exits with status 1 whatever the ranks return; the sweep resumes all "
          "the same (docs/cluster.md, \"Stopping a sweep\").\n"
          "\n"
          "## Result files\n"
          "\n"
          "`granules.tsv` (and `granules.partial.tsv`, `sweep.tsv`) is tab-separated: the "
          "column names on the first line, then `#` comment lines (version, status, the "
          "resolved scene, the run's statistics), then one row per granule.  So\n"
          "\n"
          "    numpy.genfromtxt('granules.tsv', names=True)     # names from line 1, comments skipped\n"
          "    numpy.loadtxt('granules.tsv', skiprows=1)          # always exactly one line\n"
          "    pandas.read_csv('granules.tsv', sep='\\t', comment='#')\n"
          "    gnuplot> set datafile columnheaders; plot 'granules.tsv' using 'k':'v_peak'\n"
          "\n"
          "read it as it is; `nan` marks a value that does not exist.  A run without "
          "numerics has no columns of the dynamics (`k R m X0 theory_v theory_T theory_t`).  "
          "`&output columns` chooses columns (`k` is always first) and `&output every` thins "
          "the rows (granules 1, 1 + every, ..., and the last).  The files are written under a "
          "temporary name (`DIR/.granules.tsv.XXXXXX`) and renamed when complete: a file with "
          "a result's name is always whole.  A write that cannot finish (a full disk, an I/O "
          "error, a file beyond `ulimit -f`) removes its temporary file and ends the run with "
          "a message naming the file, status 1; the temporary files a killed run left "
          "(SIGKILL, a power cut) are removed by the next run into the directory, which says "
          "so.\n"
          "\n"
          "Every result table (`granules.tsv`, `granules.partial.tsv`, `sensors.tsv`, "
          "`walls.tsv`, `spacetime.tsv`, `sweep.tsv`, `runs.tsv`, `fits.tsv`, ...) ends with a "
          "footer that proves it whole and unchanged, a comment line the readers above "
          "skip:\n"
          "\n"
          "    # end: rows 200, bytes 34567, crc32 <8 hex digits>\n"
          "\n"
          "`rows` counts the data rows above it (the lines that are neither the first, the "
          "column names, nor a comment, nor empty), `bytes` every byte above it, and `crc32` is "
          "the CRC-32 of those bytes as zlib computes it (gzip's and PNG's), in hex.  In "
          "Python:\n"
          "\n"
          "    data = open(path, 'rb').read()\n"
          "    cut = data.rindex(b'\\n', 0, len(data) - 1) + 1\n"
          "    rows, size, crc = re.fullmatch(rb'# end: rows (\\d+), bytes (\\d+), crc32 "
          "([0-9a-f]{8})\\n', data[cut:]).groups()\n"
          "    assert int(size) == cut and int(crc, 16) == zlib.crc32(data[:cut])\n"
          "\n"
          "The Python package's `read_granules` checks it, a sweep's resume and its summary "
          "(`sweep.tsv`, `runs.tsv`, fits) check every run's files, and a file that fails is "
          "refused, naming it, or computed again (resume).\n"
          "\n"
          "`runs.tsv` (a sweep) has the column names on its first line too: `run`, each swept "
          "variable, `status` (`complete`, `untrusted`, `partial`, `refused`, `failed`), then "
          "every statistic of the run's `granules.tsv` header under the same name and unit "
          "(`steps`, `t_final`, `energy_error`, `energy_initial`, `energy_transmitted`, ..., "
          "`pulse_speed`, `wall_peak_force_right`, `wall_impulse_right` with a wall; "
          "`t_final[s]` in SI), from `granules.partial.tsv` for a partial run and `nan` for a "
          "run without a result, then `cpu_time[s]`, the CPU time the run took (a reused run's "
          "as its `scene.hash` recorded it: the one column two computations of a sweep do not "
          "share), and last `message`, the reason of a run without rows.  `pulse_speed` is "
          "(X_pass(k1) - X_pass(k0)) / (t_pass(k1) - t_pass(k0)) over the last tenth of the "
          "granules the pulse passed (k1 the last whose X_pass and t_pass are known, k0 the "
          "first known from k1 - max(1, k1/10) on), in the file's units whatever `&output "
          "every` and `columns` keep; the Python package's `Result.pulse_speed()` is the same "
          "number.\n"
          "\n"
          "A re-run into the same directory replaces the files it writes (`granules.tsv` "
          "removes a stale `granules.partial.tsv` and the other way round); files it does not "
          "write stay (an earlier sweep's `s=VALUE/` directories, `fits.tsv` of a scene that "
          "had `&fit`): compare the `# scene file` and scene block of each file, or use a "
          "fresh directory.  Two taper processes into one directory at once are refused: "
          "each holds a lock on `DIR/.taper.lock` (flock) until it exits, and a second one "
          "exits with status 2 naming the directory.  The scenes of one command into one "
          "directory (`taper a.nml b.nml`) run one after the other, each replacing the files "
          "of the one before.\n"
          "\n"
          "## Signals, time limits and batch queues\n"
          "\n"
          "SIGINT (Ctrl-C), SIGTERM (`timeout`, `kill`, Slurm and PBS at the time limit), "
          "SIGHUP (the terminal closed; left ignored under `nohup`) and SIGXCPU (a CPU-time "
          "limit) stop the runs within a fraction of a second in every phase, and the status "
          "and message say what is on disk:\n"
          "\n"
          "| the signal comes | what stops it | on disk | status |\n"
          "|------------------|---------------|---------|--------|\n"
          "| while a long chain is built, its run set up or its theory computed, or before a "
          "run starts | the library's monitor, every 65536 granules | nothing of that run "
          "(\"nothing of this run is written\") | 3 |\n"
          "| during the integration, also after the pulse (a loaded chain, `t_end`, the "
          "samples of `&sensors`) | the monitor: after each pulse event and sample, and every "
          "~0.05 s of steps | `granules.partial.tsv` (`# PARTIAL result (interrupted): "
          "interrupted by SIGTERM`) and the time series so far (their headers say `# "
          "PARTIAL`) | 3 |\n"
          "| while the results of a complete run are written | the writer, every few thousand "
          "rows; gnuplot is stopped | the files written before it, whole; the one being "
          "written and those after it are not (stderr names it) | 3 |\n"
          "| during a sweep | each run as above; no run starts after it | the complete runs, "
          "reused by the same command; no `sweep.tsv` | 3 |\n"
          "| after the last file was written | | everything | the runs' |\n"
          "\n"
          "Scenes after it on the command line are not started (stderr names them).  "
          "(tests/driver/edges.sh phases measures each phase: 0.01 to 0.23 s from SIGTERM to "
          "the exit here.)  What an interrupted run found is then written, which takes as long "
          "as its size asks (the 160 MB partial file of a 2*10^6-granule chain took 2.5 s, "
          "tests/driver/edges.sh signals; `&output columns` and `every` make it smaller); a "
          "second such signal while it is written removes the temporary file and ends the "
          "process at once (status 128 + signal, no partial file).  A queue that sends SIGTERM "
          "and then SIGKILL after a grace period (Slurm: KillWait, 30 s by default) keeps the "
          "partial file if it was written within the grace period, and nothing of that run if "
          "SIGKILL comes first (SIGKILL cannot be caught: a temporary "
          "`.granules.partial.tsv.XXXXXX` may remain, which the next run into the directory "
          "removes).  There is no checkpoint to continue from: a run killed by a queue is run "
          "again, with `&solver last_granule` or a shorter chain if the limit cannot be "
          "raised.\n"
          "\n"          "## Limits\n"
          "\n", fp);
    fprintf(fp,
            "A scene file holds at most %u MiB and lines of at most %d characters "
            "(split long lists over several lines); all lists of more than one value together "
            "(custom radii, sweeps, table values) hold at most %d values, so that the echo of "
            "any valid scene fits the same limits and reads back.  Inline custom radii are "
            "therefore at most %d, from a file, the command line or a program (the Python "
            "package) alike; a `radii_file` (echoed as its path) has no such limit.\n",
            SCENE_MAX_FILE >> 20, SCENE_MAX_LINE, SCENE_MAX_LIST, SCENE_MAX_LIST);
    fputs("\n"
          "Some chains are refused although every value is in its range, before any run, "
          "with status 2 and the key to change (`FILE:LINE: &chain n_granules: ...`): a mass "
          "beyond double precision (the message says how many granules fit); a collision "
          "shorter than the resolution of double precision at its time (the binary-collision "
          "theory's residence time T_k below 2.2e-16 t_k: a steep forward taper, e.g. "
          "`forward_exponential` with q = 1000 and 10 granules; the message says how many "
          "granules resolve); `damping` with an exponent below 2.  A last granule far lighter "
          "than the one before it is not refused: it rides on its neighbour and is carried "
          "with it (docs/design.md, \"A light end carried\").  "
          "Below n = 2 the precursor sets every granule moving at once, and on a steep forward "
          "taper the light end then vibrates on weakly compressed contacts and rattles like a "
          "gas (hundreds of thousands of collisions, each shorter the softer the touch), which "
          "costs millions of steps per unit time: such a run is slow, not refused.  It is "
          "announced before it starts (a warning when n < 2 and a granule is at least 1e5 times "
          "lighter than one before it: the reason, and that `t_max` or `max_steps` bound the "
          "run, keeping the observables found so far), and the progress line shows its rate "
          "and the time left, the longer of the estimates from the granules still to pass and "
          "from the time to the theory's pass time of the target (forward_exponential q = 0.1, "
          "100 granules, n = 3/2: "
          "2.5e7 steps, 76 s at the default tolerances; rtol 2e-11: 1e8 steps reach t = 0.9 of "
          "~26).  No refusal can be exact: the steps that chain takes to t = 1 change 4.6x when rtol "
          "changes by 10 % (docs/robustness.md, \"Below n = 2 on steep forward tapers\").\n",
          fp);
}

/* The unit of a variable's value with &material ("" for a pure number). */
static const char *doc_unit(const scene_var *var)
{
    scene_var_about about;
    scene_var_describe(scene_var_index(var), &about);
    return about.unit ? about.unit : "";
}

void scene_write_doc(const scene *sc, FILE *fp)
{
    fputs(doc_intro, fp);
    for (size_t g = 0; g < SCENE_N_GROUPS; g++) {
        const char *group = scene_group_name(g);
        fprintf(fp, "\n## `&%s`: %s\n\n", group, scene_group_doc(g));
        fputs("| key | name | type | default | allowed | SI unit | checked by | description |\n", fp);
        fputs("|-----|------|------|---------|---------|---------|------------|-------------|\n", fp);
        for (size_t i = 0; i < scene_var_count(); i++) {
            const scene_var *var = scene_var_at(i);
            if (strcmp(var->group, group) != 0) continue;
            static const char *const checker[] = {"scene", "library (chain)", "library (solver)",
                                                  "library (fit)"};
            char *def = doc_default(sc, i), *range = scene_range_text(var);
            const char *reason = var->setting && var->setting->bounds_reason[0]
                                     ? var->setting->bounds_reason : NULL;
            fprintf(fp, "| `%s` | `%s` | %s | %s | %s | %s | %s | %s%s%s |\n", var->name,
                    var->keyword, scene_type_name(var), def ? def : "",
                    range && range[0] ? range : "any", doc_unit(var), checker[var->lib], var->doc,
                    reason ? ". Bounds: " : "", reason ? reason : "");
            free(def);
            free(range);
        }
    }
    write_doc_outro(fp);
}
