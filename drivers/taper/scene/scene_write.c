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

void scene_format_real(double x, char *buf, size_t size)
{
    /* Shortest representation that reads back exactly: tidy scenes, and
     * the echo re-parses to the same doubles. */
    int prec = 15;
    snprintf(buf, size, "%.*g", prec, x);
    if (strtod(buf, NULL) == x) {
        /* 15 digits suffice: the shortest from 1 up (tidy values are short) */
        for (prec = 1; prec < 15; prec++) {
            snprintf(buf, size, "%.*g", prec, x);
            if (strtod(buf, NULL) == x) break;
        }
    } else {
        /* a value with 16 or 17 significant digits (most computed ones):
         * two tries rather than 17, so that long lists echo quickly */
        for (prec = 16; prec < 17; prec++) {
            snprintf(buf, size, "%.*g", prec, x);
            if (strtod(buf, NULL) == x) break;
        }
    }
    /* %g switches to an exponent once it has fewer digits than the integer
     * part: print 20 rather than 2e+01, keep 1e+06 and beyond short. */
    double mag = fabs(x);
    if (mag >= 1.0 && mag < 1e6) {
        int digits = (int)floor(log10(mag)) + 1;
        if (digits > prec) prec = digits;
    }
    snprintf(buf, size, "%.*g", prec, x);
}

static void append(char *buf, size_t size, size_t *used, const char *fmt_text)
{
    if (*used >= size) return;
    int k = snprintf(buf + *used, size - *used, "%s", fmt_text);
    if (k > 0) *used = *used + (size_t)k < size ? *used + (size_t)k : size;
}

void scene_range_text(const scene_var *var, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    if (var->type == SCENE_STRING) {
        for (const char *const *c = var->choices; c && *c; c++) {
            char item[64];
            snprintf(item, sizeof item, "%s'%s'", c == var->choices ? "" : ", ", *c);
            append(buf, size, &used, item);
        }
    } else if (var->type == SCENE_REAL || var->type == SCENE_INTEGER) {
        char lo[40], hi[40];
        scene_format_real(var->lo, lo, sizeof lo);
        scene_format_real(var->hi, hi, sizeof hi);
        snprintf(buf, size, "%c%s, %s%c", (var->flags & SCENE_LO_OPEN) ? '(' : '[', lo, hi,
                 (var->flags & SCENE_HI_OPEN) ? ')' : ']');
    } else if (var->type == SCENE_LOGICAL) {
        snprintf(buf, size, ".true., .false.");
    } else if (var->type == SCENE_REAL_LIST && (var->flags & SCENE_POSITIVE)) {
        snprintf(buf, size, "each > 0");
    }
}

/* Fortran string literal: quotes doubled, so any text survives. */
static void quote(const char *s, char *buf, size_t size)
{
    size_t used = 0;
    if (size < 3) return;
    buf[used++] = '\'';
    for (; *s && used + 3 < size; s++) {
        buf[used++] = *s;
        if (*s == '\'') buf[used++] = '\'';
    }
    buf[used++] = '\'';
    buf[used] = '\0';
}

void scene_value_text(const scene_var *var, const scene_value *v, char *buf, size_t size)
{
    char num[40];
    size_t used = 0;
    buf[0] = '\0';
    switch (var->type) {
    case SCENE_STRING: quote(v->str ? v->str : "", buf, size); break;
    case SCENE_INTEGER: snprintf(buf, size, "%lld", v->ival); break;
    case SCENE_LOGICAL: snprintf(buf, size, "%s", v->bval ? ".true." : ".false."); break;
    default:
        for (size_t i = 0; i < v->count; i++) {
            scene_format_real(v->list[i], num, sizeof num);
            if (i > 0) append(buf, size, &used, ", ");
            append(buf, size, &used, num);
        }
        break;
    }
}

/* A real list, five values per line (continuation lines are plain
 * namelist syntax). */
static void write_list(const scene_value *v, FILE *fp)
{
    char num[40];
    for (size_t i = 0; i < v->count; i++) {
        scene_format_real(v->list[i], num, sizeof num);
        fprintf(fp, "%s%s", num, i + 1 < v->count ? "," : "");
        if (i + 1 < v->count) fputs((i + 1) % 5 == 0 ? "\n      " : " ", fp);
    }
}

static void write_var(const scene_var *var, const scene_value *v, FILE *fp, int doc)
{
    if (doc && !v->given && strcmp(var->name, "dir") == 0) {
        /* Its default depends on the scene's file name: leave it derived. */
        fprintf(fp, "  ! %-10s = %-18s ! %s\n", var->name, "'out/NAME'", var->doc);
        return;
    }
    if (var->type == SCENE_REAL_LIST || (var->type == SCENE_REAL && v->count != 1)) {
        if (v->count == 0) {
            /* Namelists cannot say "empty list": leave it out, documented. */
            fprintf(fp, "  ! %s = (none)%s%s\n", var->name, doc ? "  ! " : "", doc ? var->doc : "");
            return;
        }
        if (doc) fprintf(fp, "  ! %s\n", var->doc);
        fprintf(fp, "  %s = ", var->name);
        write_list(v, fp);
        fputc('\n', fp);
        return;
    }
    char text[1024];
    scene_value_text(var, v, text, sizeof text);
    if (doc)
        fprintf(fp, "  %-12s = %-18s ! %s\n", var->name, text, var->doc);
    else
        fprintf(fp, "  %s = %s\n", var->name, text);
}

/* sweep_index: write only that value of a swept variable (SIZE_MAX: all). */
static void write_scene(const scene *sc, FILE *fp, int doc, size_t sweep_index)
{
    for (size_t g = 0; g < scene_group_count(); g++) {
        const char *group = scene_group_name(g);
        /* The echo leaves out optional groups that are off: shorter, and
         * the same scene. */
        if (!doc && !scene_group_active(sc, group)) continue;
        if (doc) fprintf(fp, "! &%s: %s\n", group, scene_group_doc(g));
        fprintf(fp, "&%s\n", group);
        for (size_t i = 0; i < scene_var_count(); i++) {
            const scene_var *var = scene_var_at(i);
            if (strcmp(var->group, group) != 0) continue;
            scene_value one = sc->values[i];
            if ((var->flags & SCENE_SWEEP) && one.count > 1 && sweep_index < one.count) {
                one.list += sweep_index; /* a view of one element, nothing owned */
                one.count = 1;
            }
            write_var(var, &one, fp, doc);
        }
        fputs("/\n", fp);
    }
}

void scene_write(const scene *sc, FILE *fp, int doc) { write_scene(sc, fp, doc, SIZE_MAX); }

void scene_write_point(const scene *sc, FILE *fp, size_t sweep_index)
{
    write_scene(sc, fp, 0, sweep_index);
}

/* Default column of the Markdown table. */
static void doc_default(const scene *sc, size_t i, char *buf, size_t size)
{
    const scene_var *var = scene_var_at(i);
    char text[256];
    if (strcmp(var->group, "output") == 0 && strcmp(var->name, "dir") == 0) {
        snprintf(buf, size, "`'out/NAME'` for NAME.nml");
        return;
    }
    if (var->type == SCENE_REAL_LIST || (var->type == SCENE_REAL && !var->def &&
                                         !(var->flags & SCENE_LIBDEF))) {
        snprintf(buf, size, "none");
        return;
    }
    scene_value_text(var, &sc->values[i], text, sizeof text);
    snprintf(buf, size, "`%s`%s", text, (var->flags & SCENE_LIBDEF) ? " (library default)" : "");
}

static const char doc_intro[] =
    "# Scene files\n"
    "\n"
    "<!-- Generated by `taper --doc` from the variable table in drivers/taper/scene/scene.c; do not edit.\n"
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
    "Errors (unknown group or key, wrong type, repeated key, syntax, out-of-range\n"
    "values) are reported as `FILE:LINE: &group key: message`, and `taper` exits\n"
    "with status 2.\n"
    "\n"
    "**Sweeps.** `s` and `q` accept a list of values (`s = 0.1, 0.2, 0.3`); only one\n"
    "variable may be swept.  The driver then runs each value into its own\n"
    "sub-directory `DIR/s=VALUE/` (`DIR/q=VALUE/`), and writes the combined table\n"
    "`DIR/sweep.tsv` (the swept value as first column, then the columns of\n"
    "`granules.tsv`).  Runs are computed in parallel (`&output threads`), with results\n"
    "identical to serial runs.  Every other real takes one value.\n"
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
    "`share/scenes/paper/` (see docs/paper.md).\n";

void scene_write_doc(const scene *sc, FILE *fp)
{
    fputs(doc_intro, fp);
    for (size_t g = 0; g < scene_group_count(); g++) {
        const char *group = scene_group_name(g);
        fprintf(fp, "\n## `&%s`: %s\n\n", group, scene_group_doc(g));
        fputs("| name | type | default | allowed | description |\n", fp);
        fputs("|------|------|---------|---------|-------------|\n", fp);
        for (size_t i = 0; i < scene_var_count(); i++) {
            const scene_var *var = scene_var_at(i);
            if (strcmp(var->group, group) != 0) continue;
            char def[300], range[256];
            doc_default(sc, i, def, sizeof def);
            scene_range_text(var, range, sizeof range);
            fprintf(fp, "| `%s` | %s | %s | %s | %s |\n", var->name, scene_type_name(var), def,
                    range[0] ? range : "any", var->doc);
        }
    }
}
