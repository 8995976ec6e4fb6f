/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * gen_namelists.c OUT -- writes the Fortran module taper_nml_scene
 * (taper_nml_scene.f90) for the variables of a scene, from the scene's
 * table (drivers/scenes/scene/scene.c: scene_var_count, scene_var_*) and the
 * library's table of settings (taper_setting_find), so that the Fortran
 * scene driver taper_nml follows every variable the scene has without a
 * hand edit: the derived type scene_values, one component per variable
 * under its keyword (fit_x, striker_radius), and `sv`, the scene's values;
 * the groups; one subroutine per group that declares the group's keys, its
 * NAMELIST and their defaults and READs it; read_group; the keys of each
 * group for messages; the checks of what READ gave (lengths, choices, finite
 * reals); --dump; and apply_chain, apply_solver, which hand each library
 * setting to a spec by name (taper_chain_spec_set_option,
 * taper_solver_spec_set_option).
 *
 * The defaults of the library's settings are left to the library at run
 * time (library_default, library_choice in taper_nml_base.f90); those of
 * the scene's own variables are the scene's, written here.  A variable
 * whose default follows the scene's path (&output dir) is recognised by
 * comparing two scenes, and must follow it as default_dir does (out/NAME).
 *
 * A build-time tool of taper_nml (run by drivers/fortran/meson.build),
 * never installed.  It fails, naming the variable, when a key cannot be a
 * Fortran name in its group's subroutine.
 */
#include "scene/scene.h"

#include <ctype.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* How a variable is kept in Fortran. */
typedef enum storage {
    ST_TEXT,    /* a string or a choice: character(len=LEN_STR)              */
    ST_LOGICAL, /* logical                                                   */
    ST_INT,     /* one integer: integer(int64)                               */
    ST_INTS,    /* an integer a list sweeps: type(int_values)                */
    ST_REAL,    /* one real: real(c_double), NOT_GIVEN when left out         */
    ST_REALS,   /* a real a list sweeps: type(real_values)                   */
    ST_LIST     /* a list of reals: type(real_values), up to MAX_LIST        */
} storage;

typedef struct var {
    size_t row;              /* in the scene's table                          */
    const char *group, *key, *keyword;
    scene_type type;
    storage st;
    const taper_setting *lib; /* the library's row, or NULL: the scene's own  */
    int sweep;               /* ordinal among the sweepable (1-based), or 0   */
} var;

static var *vars;
static size_t n_vars, n_sweep;
static const char *groups[64];
static size_t n_groups;

static void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "gen_namelists: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(1);
}

/* The names the generated group subroutines use besides their keys: a key
 * spelt like one of them would hide it (Fortran ignores case). */
static const char *const reserved[] = {
    "sv", "given", "path", "probing", "check_read", "read_group", "group_keys", "take_text",
    "take_int", "take_ints", "take_real", "take_reals", "fresh_ints", "fresh_reals",
    "library_default", "library_choice", "default_dir", "len_str", "max_sweep", "max_list",
    "not_given_text", "not_given_int", "not_given_real", "int64", "c_double", "nml_file",
    "nml_unit", "nml_ios", "nml_msg", "transfer", "int", "real", NULL};

static void check_name(const var *v)
{
    const char *k = v->key;
    size_t n = strlen(k);
    int ok = n > 0 && n <= 63 && isalpha((unsigned char)k[0]);
    for (size_t j = 0; ok && j < n; j++)
        ok = isalnum((unsigned char)k[j]) || k[j] == '_';
    if (!ok) die("&%s %s: not a Fortran name", v->group, k);
    for (size_t j = 0; reserved[j]; j++)
        if (strcasecmp(k, reserved[j]) == 0)
            die("&%s %s: the key is a name the generated subroutine uses (rename one)", v->group,
                k);
    if (strcasecmp(k, v->group) == 0)
        die("&%s %s: a key spelt as its group's namelist cannot be declared beside it", v->group,
            k);
}

static storage storage_of(scene_type t, int sweep)
{
    switch (t) {
    case SCENE_STRING:
    case SCENE_CHOICE: return ST_TEXT;
    case SCENE_LOGICAL: return ST_LOGICAL;
    case SCENE_INTEGER: return sweep ? ST_INTS : ST_INT;
    case SCENE_REAL: return sweep ? ST_REALS : ST_REAL;
    case SCENE_REAL_LIST: return ST_LIST;
    }
    die("unknown scene type %d", (int)t);
    return ST_TEXT;
}

static void load_table(void)
{
    n_vars = scene_var_count();
    vars = calloc(n_vars, sizeof *vars);
    if (!vars) die("out of memory");
    for (size_t i = 0; i < n_vars; i++) {
        var *v = &vars[i];
        v->row = i;
        v->group = scene_var_group(i);
        v->key = scene_var_name(i);
        v->keyword = scene_var_keyword_at(i);
        v->type = scene_var_type(i);
        int sweep = scene_var_takes_list(i) && v->type != SCENE_REAL_LIST;
        v->st = storage_of(v->type, sweep);
        v->sweep = sweep ? (int)++n_sweep : 0;
        v->lib = taper_setting_find(v->keyword, NULL);
        check_name(v);
        size_t g = 0;
        while (g < n_groups && strcmp(groups[g], v->group) != 0) g++;
        if (g == n_groups) {
            if (n_groups + 1 == sizeof groups / sizeof groups[0]) die("too many groups");
            groups[n_groups++] = v->group;
        }
    }
}

/* ---- Fortran text ------------------------------------------------------------- */

/* A Fortran string literal of s. */
static void put_string(FILE *out, const char *s)
{
    fputc('"', out);
    for (; *s; s++) {
        if (*s == '"') fputc('"', out);
        fputc(*s, out);
    }
    fputc('"', out);
}

/* The exact double x. */
static void put_real(FILE *out, double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    fprintf(out, "transfer(int(z'%016" PRIX64 "', int64), 0.0_c_double)", u);
}

/* Names joined by ", ", broken into continuation lines. */
typedef struct joiner {
    FILE *out;
    int column, first;
    const char *indent;
} joiner;

static void join(joiner *j, const char *text)
{
    int n = (int)strlen(text);
    if (!j->first) {
        fputc(',', j->out);
        j->column++;
        if (j->column + n + 3 > 100) {
            fprintf(j->out, " &\n%s", j->indent);
            j->column = (int)strlen(j->indent);
        } else {
            fputc(' ', j->out);
            j->column++;
        }
    }
    fputs(text, j->out);
    j->column += n;
    j->first = 0;
}

/* A character array constructor of a NULL-terminated list of names, the
 * line's text so far `column` characters long. */
static void put_names(FILE *out, const char *const *names, int column, const char *indent)
{
    size_t width = 1;
    for (size_t k = 0; names[k]; k++)
        if (strlen(names[k]) > width) width = strlen(names[k]);
    fprintf(out, "[character(len=%zu) :: ", width);
    joiner j = {out, column + 24, 1, indent};
    for (size_t k = 0; names[k]; k++) {
        char quoted[256];
        snprintf(quoted, sizeof quoted, "\"%s\"", names[k]);
        join(&j, quoted);
    }
    fputc(']', out);
}

/* ---- defaults -------------------------------------------------------------------- */

static scene *scene_a, *scene_b; /* two scenes that differ in their path only */

/* The default of a scene's own variable: its value in a new scene. */
static void put_own_default(FILE *out, const var *v)
{
    size_t n = 0;
    const double *x;
    switch (v->st) {
    case ST_TEXT: {
        const char *a = scene_var_text(scene_a, v->row), *b = scene_var_text(scene_b, v->row);
        if (strcmp(a, b) == 0) {
            put_string(out, a);
        } else if (strcmp(a, "out/a") == 0 && strcmp(b, "out/c") == 0) {
            fputs("default_dir(path)", out); /* out/NAME for NAME.nml */
        } else {
            die("&%s %s: a default that follows the scene's path other than out/NAME", v->group,
                v->key);
        }
        return;
    }
    case ST_LOGICAL: fputs(scene_var_integer(scene_a, v->row) ? ".true." : ".false.", out); return;
    case ST_INT: fprintf(out, "%lld_int64", scene_var_integer(scene_a, v->row)); return;
    case ST_INTS:
        fprintf(out, "[%lld_int64]", scene_var_integer(scene_a, v->row));
        return;
    case ST_REAL:
        x = scene_var_reals(scene_a, v->row, &n);
        if (n == 0)
            fputs("NOT_GIVEN_REAL", out); /* no default: left out */
        else
            put_real(out, x[0]);
        return;
    case ST_REALS:
    case ST_LIST:
        x = scene_var_reals(scene_a, v->row, &n);
        fputs("[real(c_double) ::", out);
        for (size_t k = 0; k < n; k++) {
            fputs(k ? ", " : " ", out);
            put_real(out, x[k]);
        }
        fputc(']', out);
        return;
    }
}

/* The default of a library setting: the library's, at run time. */
static void put_library_default(FILE *out, const var *v)
{
    const char *kw = v->keyword;
    switch (v->st) {
    case ST_TEXT: fprintf(out, "library_choice(\"%s\")", kw); return;
    case ST_LOGICAL: fprintf(out, "library_default(\"%s\") > 0", kw); return;
    case ST_INT: fprintf(out, "int(library_default(\"%s\"), int64)", kw); return;
    case ST_INTS: fprintf(out, "[int(library_default(\"%s\"), int64)]", kw); return;
    case ST_REAL: fprintf(out, "library_default(\"%s\")", kw); return;
    case ST_REALS: fprintf(out, "[library_default(\"%s\")]", kw); return;
    case ST_LIST: fputs("[real(c_double) ::]", out); return; /* lists start empty */
    }
}

static void put_default(FILE *out, const var *v)
{
    if (v->lib)
        put_library_default(out, v);
    else
        put_own_default(out, v);
}

/* ---- DECLS ----------------------------------------------------------------------- */

static const char *fortran_type(storage st)
{
    switch (st) {
    case ST_TEXT: return "character(len=LEN_STR)";
    case ST_LOGICAL: return "logical";
    case ST_INT: return "integer(int64)";
    case ST_INTS: return "type(int_values)";
    case ST_REAL: return "real(c_double)";
    case ST_REALS:
    case ST_LIST: return "type(real_values)";
    }
    return "";
}

static void write_decls(FILE *out)
{
    size_t width = 1;
    for (size_t g = 0; g < n_groups; g++)
        if (strlen(groups[g]) > width) width = strlen(groups[g]);
    fprintf(out, "  integer, parameter :: N_VARS = %zu, N_SWEEPABLE = %zu\n", n_vars, n_sweep);
    fprintf(out, "  ! The groups, in the order of the table.\n");
    int column = fprintf(out, "  character(len=*), parameter :: GROUPS(%zu) = ", n_groups);
    groups[n_groups] = NULL;
    put_names(out, groups, column, "       ");
    fprintf(out, "\n  ! The group of each variable, in the order of the table.\n");
    const char **names = calloc(n_vars + 1, sizeof *names);
    if (!names) die("out of memory");
    for (size_t i = 0; i < n_vars; i++) names[i] = vars[i].group;
    column = fprintf(out, "  character(len=*), parameter :: GROUP_OF(N_VARS) = ");
    put_names(out, names, column, "       ");
    fprintf(out, "\n  ! The keyword of each sweepable variable (a real or an integer a list\n"
                 "  ! sweeps), in the order of the table.\n");
    size_t k = 0;
    for (size_t i = 0; i < n_vars; i++)
        if (vars[i].sweep) names[k++] = vars[i].keyword;
    names[k] = NULL;
    column = fprintf(out, "  character(len=*), parameter :: SWEPT_KEYWORDS(N_SWEEPABLE) = ");
    put_names(out, names, column, "       ");
    free(names);
    fprintf(out, "\n\n  ! Every variable of the scene under its keyword, as the scene resolves it.\n");
    fprintf(out, "  type :: scene_values\n");
    for (size_t i = 0; i < n_vars; i++)
        fprintf(out, "     %s :: %s  ! &%s %s%s\n", fortran_type(vars[i].st), vars[i].keyword,
                vars[i].group, vars[i].key, vars[i].lib ? " (library)" : "");
    fprintf(out, "  end type scene_values\n\n");
    fprintf(out, "  type(scene_values), allocatable :: sv   ! the scene (allocatable: released whole)\n");
    fprintf(out, "  logical :: given(N_VARS) = .false.      ! the file gave variable i (a logical: "
                 "never known)\n");
}

/* ---- PROCS ----------------------------------------------------------------------- */

/* One group's subroutine: its keys as local variables, left out (NOT_GIVEN)
 * until READ gives them, then each kept in sv with its default if left out. */
static void write_read_group(FILE *out, const char *group)
{
    fprintf(out, "  ! &%s: READ into its keys, kept in sv (a value left out: its default).\n",
            group);
    fprintf(out, "  recursive subroutine read_%s(nml_file, nml_unit)\n", group);
    fprintf(out, "    character(len=*), intent(in) :: nml_file\n");
    fprintf(out, "    integer, intent(in) :: nml_unit\n");
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        if (strcmp(v->group, group) != 0) continue;
        switch (v->st) {
        case ST_TEXT: fprintf(out, "    character(len=LEN_STR) :: %s\n", v->key); break;
        case ST_LOGICAL: fprintf(out, "    logical :: %s\n", v->key); break;
        case ST_INT: fprintf(out, "    integer(int64) :: %s\n", v->key); break;
        case ST_INTS: fprintf(out, "    integer(int64), allocatable :: %s(:)\n", v->key); break;
        case ST_REAL: fprintf(out, "    real(c_double) :: %s\n", v->key); break;
        case ST_REALS:
        case ST_LIST: fprintf(out, "    real(c_double), allocatable :: %s(:)\n", v->key); break;
        }
    }
    fprintf(out, "    namelist /%s/ ", group);
    char indent[64];
    snprintf(indent, sizeof indent, "         ");
    joiner j = {out, 18 + (int)strlen(group), 1, indent};
    for (size_t i = 0; i < n_vars; i++)
        if (strcmp(vars[i].group, group) == 0) join(&j, vars[i].key);
    fprintf(out, "\n    integer :: nml_ios\n    character(len=512) :: nml_msg\n");
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        if (strcmp(v->group, group) != 0) continue;
        switch (v->st) {
        case ST_TEXT: fprintf(out, "    %s = NOT_GIVEN_TEXT\n", v->key); break;
        case ST_LOGICAL:
            fprintf(out, "    %s = ", v->key);
            put_default(out, v);
            fputc('\n', out);
            break;
        case ST_INT: fprintf(out, "    %s = NOT_GIVEN_INT\n", v->key); break;
        case ST_INTS: fprintf(out, "    call fresh_ints(%s, MAX_SWEEP)\n", v->key); break;
        case ST_REAL: fprintf(out, "    %s = NOT_GIVEN_REAL\n", v->key); break;
        case ST_REALS: fprintf(out, "    call fresh_reals(%s, MAX_SWEEP)\n", v->key); break;
        case ST_LIST: fprintf(out, "    call fresh_reals(%s, MAX_LIST)\n", v->key); break;
        }
    }
    fprintf(out, "    read (nml_unit, nml=%s, iostat=nml_ios, iomsg=nml_msg)\n", group);
    fprintf(out, "    call check_read(nml_file, nml_unit, \"%s\", nml_ios, nml_msg, read_group, &\n"
                 "         group_keys)\n", group);
    fprintf(out, "    if (probing) return\n");
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        if (strcmp(v->group, group) != 0) continue;
        static const char *const take[] = {
            [ST_TEXT] = "take_text", [ST_INT] = "take_int", [ST_INTS] = "take_ints",
            [ST_REAL] = "take_real", [ST_REALS] = "take_reals", [ST_LIST] = "take_reals"};
        if (v->st == ST_LOGICAL) {
            fprintf(out, "    sv%%%s = %s\n", v->keyword, v->key);
            continue;
        }
        fprintf(out, "    call %s(sv%%%s, %s, &\n         ", take[v->st], v->keyword, v->key);
        put_default(out, v);
        fprintf(out, ", given(%zu))\n", v->row + 1);
    }
    fprintf(out, "  end subroutine read_%s\n\n", group);
}

static void write_dispatch(FILE *out)
{
    fprintf(out, "  ! READ(unit, NML=group) of one group, checked by check_read.  Recursive:\n"
                 "  ! check_read's locate_error calls it again on part of the file.\n");
    fprintf(out, "  recursive subroutine read_group(file, unit, group)\n"
                 "    character(len=*), intent(in) :: file, group\n"
                 "    integer, intent(in) :: unit\n"
                 "    select case (group)\n");
    for (size_t g = 0; g < n_groups; g++)
        fprintf(out, "    case (\"%s\")\n       call read_%s(file, unit)\n", groups[g], groups[g]);
    fprintf(out, "    end select\n  end subroutine read_group\n\n");

    fprintf(out, "  ! The keys of a group, as listed in the messages.\n");
    fprintf(out, "  function group_keys(group) result(keys)\n"
                 "    character(len=*), intent(in) :: group\n"
                 "    character(len=:), allocatable :: keys\n"
                 "    keys = \"\"\n"
                 "    select case (group)\n");
    for (size_t g = 0; g < n_groups; g++) {
        fprintf(out, "    case (\"%s\")\n       keys = \"", groups[g]);
        int first = 1, column = 15;
        for (size_t i = 0; i < n_vars; i++) {
            if (strcmp(vars[i].group, groups[g]) != 0) continue;
            int n = (int)strlen(vars[i].key);
            if (!first) {
                if (column + n > 90) {
                    fputs(", \" // &\n            \"", out);
                    column = 13;
                } else {
                    fputs(", ", out);
                }
            }
            fputs(vars[i].key, out);
            column += n + 2;
            first = 0;
        }
        fputs("\"\n", out);
    }
    fprintf(out, "    end select\n  end function group_keys\n\n");

    fprintf(out, "  ! The group and key of a variable by its keyword (taper_error.field names\n"
                 "  ! a library setting by it); '' for an unknown one.\n");
    fprintf(out, "  subroutine var_place(keyword, group, key)\n"
                 "    character(len=*), intent(in) :: keyword\n"
                 "    character(len=:), allocatable, intent(out) :: group, key\n"
                 "    group = \"\"\n    key = \"\"\n"
                 "    select case (keyword)\n");
    for (size_t i = 0; i < n_vars; i++)
        fprintf(out, "    case (\"%s\")\n       group = \"%s\"\n       key = \"%s\"\n",
                vars[i].keyword, vars[i].group, vars[i].key);
    fprintf(out, "    end select\n  end subroutine var_place\n\n");

    fprintf(out, "  ! The row of a variable by its keyword, 0 for an unknown one.\n");
    fprintf(out, "  integer function var_index(keyword) result(i)\n"
                 "    character(len=*), intent(in) :: keyword\n"
                 "    i = 0\n"
                 "    select case (keyword)\n");
    for (size_t i = 0; i < n_vars; i++)
        fprintf(out, "    case (\"%s\")\n       i = %zu\n", vars[i].keyword, i + 1);
    fprintf(out, "    end select\n  end function var_index\n\n");
}

/* What READ cannot check: a string cut at its variable's length, a choice's
 * spelling (the scene's are refused here; the library's are left to the
 * library, which names them), NaN and infinities. */
static void write_checks(FILE *out)
{
    fprintf(out, "  ! What READ gave, checked as the C parser does: strings that fill their\n"
                 "  ! variable (perhaps cut), choices (in their canonical spelling), reals\n"
                 "  ! that are not finite.\n");
    fprintf(out, "  subroutine check_values()\n");
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        const char *g = v->group, *k = v->key, *kw = v->keyword;
        switch (v->st) {
        case ST_TEXT:
            fprintf(out, "    call check_length(\"%s\", \"%s\", sv%%%s)\n", g, k, kw);
            if (v->type != SCENE_CHOICE) break;
            if (v->lib) {
                fprintf(out, "    sv%%%s = library_spelling(\"%s\", sv%%%s)\n", kw, kw, kw);
            } else {
                int column = fprintf(out, "    call own_choice(\"%s\", \"%s\", sv%%%s, ", g, k,
                                     kw);
                put_names(out, scene_var_choices(v->row), column, "         ");
                fprintf(out, ")\n");
            }
            break;
        case ST_REAL:
            fprintf(out, "    call check_finite(\"%s\", \"%s\", [sv%%%s])\n", g, k, kw);
            break;
        case ST_REALS:
        case ST_LIST:
            fprintf(out, "    call check_finite(\"%s\", \"%s\", sv%%%s%%v(1:sv%%%s%%n))\n", g, k,
                    kw, kw);
            break;
        default: break;
        }
    }
    fprintf(out, "  end subroutine check_values\n\n");
}

static void write_dump(FILE *out)
{
    fprintf(out, "  ! The canonical form of tests/bindings/scene_dump.c, in the order of the\n"
                 "  ! table: every variable.\n");
    fprintf(out, "  subroutine print_dump()\n");
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        char name[256];
        snprintf(name, sizeof name, "\"%s.%s\"", v->group, v->key);
        switch (v->st) {
        case ST_TEXT: fprintf(out, "    call print_text(%s, sv%%%s)\n", name, v->keyword); break;
        case ST_LOGICAL:
            fprintf(out, "    write (output_unit, '(a,l1)') %s//\" = \", sv%%%s\n", name,
                    v->keyword);
            break;
        case ST_INT:
            fprintf(out, "    write (output_unit, '(a,i0)') %s//\" = \", sv%%%s\n", name,
                    v->keyword);
            break;
        case ST_INTS: fprintf(out, "    call print_ints(%s, sv%%%s)\n", name, v->keyword); break;
        case ST_REAL: fprintf(out, "    call print_optional(%s, sv%%%s)\n", name, v->keyword); break;
        case ST_REALS:
        case ST_LIST: fprintf(out, "    call print_list(%s, sv%%%s)\n", name, v->keyword); break;
        }
    }
    fprintf(out, "  end subroutine print_dump\n\n");
}

/* The library's settings of one object into a spec, by name, each at its
 * value of the run (ix: the index of each sweepable variable's value). */
static void write_apply(FILE *out, taper_setting_object object)
{
    const char *obj = object == TAPER_SETTING_CHAIN ? "chain" : "solver";
    fprintf(out, "  ! Every %s setting of the library into spec, by name, at the run whose\n"
                 "  ! value of sweepable variable k is its ix(k)-th: TAPER_OK, or the first\n"
                 "  ! refusal (err names the setting).\n", obj);
    fprintf(out, "  integer(c_int) function apply_%s(spec, ix, err) result(st)\n"
                 "    type(c_ptr), intent(in) :: spec\n"
                 "    integer, intent(in) :: ix(:)\n"
                 "    type(taper_error), intent(inout) :: err\n"
                 "    st = TAPER_OK\n", obj);
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        if (!v->lib || v->lib->object != object) continue;
        fprintf(out, "    st = taper_%s_spec_set_option(spec, \"%s\", &\n         ", obj,
                v->keyword);
        switch (v->st) {
        case ST_TEXT: fprintf(out, "trim(sv%%%s)", v->keyword); break;
        case ST_LOGICAL:
        case ST_INT:
        case ST_REAL: fprintf(out, "sv%%%s", v->keyword); break;
        case ST_INTS:
        case ST_REALS: fprintf(out, "sv%%%s%%v(ix(%d))", v->keyword, v->sweep); break;
        case ST_LIST: fprintf(out, "sv%%%s%%v(1:sv%%%s%%n)", v->keyword, v->keyword); break;
        }
        fprintf(out, ", err)\n    if (st /= TAPER_OK) return\n");
    }
    fprintf(out, "  end function apply_%s\n\n", obj);
}

static void write_sweep(FILE *out)
{
    fprintf(out, "  ! The number of values of each sweepable variable (1: one value; 0: a\n"
                 "  ! real without default left out), in the order of the table.\n");
    fprintf(out, "  subroutine sweep_lengths(lens)\n"
                 "    integer, intent(out) :: lens(N_SWEEPABLE)\n");
    for (size_t i = 0; i < n_vars; i++)
        if (vars[i].sweep)
            fprintf(out, "    lens(%d) = sv%%%s%%n\n", vars[i].sweep, vars[i].keyword);
    fprintf(out, "  end subroutine sweep_lengths\n\n");

    fprintf(out, "  ! \"  key = value\" of each swept variable (lens > 1) at its ix-th value.\n");
    fprintf(out, "  subroutine write_swept(lens, ix)\n"
                 "    integer, intent(in) :: lens(N_SWEEPABLE), ix(N_SWEEPABLE)\n");
    for (size_t i = 0; i < n_vars; i++) {
        const var *v = &vars[i];
        if (!v->sweep) continue;
        fprintf(out, "    if (lens(%d) > 1) write (output_unit, '(a,%s)', advance=\"no\") "
                     "\"  %s = \", sv%%%s%%v(ix(%d))\n",
                v->sweep, v->st == ST_INTS ? "i0" : "g0.6", v->key, v->keyword, v->sweep);
    }
    fprintf(out, "  end subroutine write_swept\n\n");
}

static void write_procs(FILE *out)
{
    for (size_t g = 0; g < n_groups; g++) write_read_group(out, groups[g]);
    write_dispatch(out);
    write_checks(out);
    write_dump(out);
    write_apply(out, TAPER_SETTING_CHAIN);
    write_apply(out, TAPER_SETTING_SOLVER);
    write_sweep(out);
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* The module: the declarations, then the procedures. */
static void write_module(FILE *out, const char *name)
{
    fprintf(out, "! %s -- written at build time by drivers/fortran/gen_namelists.c from\n"
                 "! the scene's table and the library's table of settings: do not edit.\n"
                 "! The variables of a scene for taper_nml (drivers/fortran/taper_nml.f90).\n"
                 "module taper_nml_scene\n"
                 "  use, intrinsic :: iso_c_binding\n"
                 "  use, intrinsic :: iso_fortran_env, only: output_unit, int64\n"
                 "  use taper\n"
                 "  use taper_nml_base\n"
                 "  implicit none\n\n",
            name);
    write_decls(out);
    fprintf(out, "\ncontains\n\n");
    write_procs(out);
    fprintf(out, "end module taper_nml_scene\n");
}

/* Fortran's free form holds 132 characters a line: a name too long for the
 * lines written here fails the build, naming the line, rather than the
 * compiler later. */
static void check_lines(const char *path)
{
    FILE *in = fopen(path, "r");
    if (!in) die("%s: cannot read it back", path);
    int c, column = 0, line = 1;
    while ((c = getc(in)) != EOF) {
        if (c == '\n') {
            line++;
            column = 0;
        } else if (++column > 132) {
            fclose(in);
            remove(path);
            die("%s:%d: longer than 132 characters (a key or keyword too long?)", path, line);
        }
    }
    fclose(in);
}

static void write_file(const char *path)
{
    FILE *out = fopen(path, "w");
    if (!out) die("%s: cannot write", path);
    write_module(out, base_name(path));
    if (fclose(out) != 0) {
        remove(path);
        die("%s: write error", path);
    }
    check_lines(path);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: gen_namelists OUT.f90\n");
        return 2;
    }
    load_table();
    scene_a = scene_new("a.nml");
    scene_b = scene_new("b/c.nml");
    if (!scene_a || !scene_b) die("out of memory");
    write_file(argv[1]);
    scene_free(scene_a);
    scene_free(scene_b);
    free(vars);
    return 0;
}
