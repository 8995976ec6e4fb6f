/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * gen_module.c TEMPLATE OUT -- writes the Fortran module taper (OUT,
 * taper.f90) from its hand-written part (TEMPLATE, taper.f90.in), the list
 * of taper.h's functions (taper_functions.def) and the library's table of
 * settings, as SUNDIALS' Fortran modules (fcvode_mod.f90, ...) are written
 * by SWIG from the C headers and an interface file of typemaps.
 *
 * Why a list, and not taper.h itself.  A binding must know more than a C
 * prototype says: whether `double *` is a scalar the function writes, an
 * array it fills or an optional array (c_loc or c_null_ptr), which dummy
 * names programs already pass as keywords, what a Fortran caller needs to
 * be told.  SWIG keeps that knowledge in typemaps and %apply rules; here it
 * is one row per function in taper_functions.def, each argument a TYPE of
 * the table TYPES below (a C type and how it crosses).  Reading taper.h's
 * declarations as text instead would be fragile (macros, comments, line
 * breaks) and still need those rules.  The list cannot drift from the
 * header: this file expands every row into a C11 _Static_assert that the
 * function's type, as taper.h declares it, is exactly the row's (const,
 * enums and integer widths included), so that a changed prototype stops
 * the build here, naming the function; and the test fortran_binds_all
 * checks, against the C compiler's own list of taper.h's declarations, that
 * the written module binds every function and nothing else.
 *
 * From the list: every function as a bind(C) interface; a function that
 * gives or takes a C string is bound as c_NAME, and NAME, written here too,
 * takes and gives Fortran strings (trailing blanks ignored, '' for NULL),
 * unless its row is FN_C (its Fortran face hand-written in the template).
 * From the table of settings, read through the public API
 * (taper_setting_count, taper_setting_at): each typed setter's comment (the
 * setting's description, range, default), after checking that every setting
 * has a typed setter and getter in the list for the spec that holds it; and
 * for each spec, the generic taper_<spec>_spec_set_option, one specific
 * procedure per kind of Fortran value (a list where the spec has a list
 * setting), each a call of the hand-written set_real, set_text, ... with the
 * spec's C function.
 *
 * What stays hand-written (taper.f90.in): the module's frame and its
 * documentation, the three bind(C) structs (their layout is checked by the
 * test fortran_abi), c_string and the helpers that give Fortran pointers,
 * strings and rows (taper_message, taper_observable, taper_setting_row, ...),
 * and what each kind of value does in a setter by name.  The template marks
 * where the written parts go with three comment lines, each once:
 * `! @notice@`, `! @specification@` (public statements, generic interfaces,
 * the interface block), `! @procedures@` (after CONTAINS).  A template and
 * not a hand-written module of its own beside the written one: programs
 * compile the installed taper_constants.f90 and taper.f90 and nothing else
 * (the examples' build lines say so), and the hand-written structs and
 * helpers come before and after the interfaces in one module, taper_binding.
 * The structs stay hand-written: three short declarations read better than a
 * table that would describe them again.
 *
 * A build-time tool of the Fortran binding (drivers/fortran/module/
 * meson.build), never installed.  It links libtaper for its table and runs
 * on the build machine, so a cross build without a way to run host programs
 * leaves the Fortran module out.
 */
#include "taper.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- how each C type crosses to Fortran -------------------------------- */
/* X(TYPE, C type, declaration as a dummy ("%s": its name), what the dummy
 * imports, type as a result (NULL: never a result), what that imports). */
#define VALUE(type, kind) type ", value :: %s", kind, type, kind
#define AS_INT VALUE("integer(c_int)", "c_int")
#define AS_PTR VALUE("type(c_ptr)", "c_ptr")
#define INT_OUT "integer(c_int), intent(out) :: %s", "c_int", NULL, NULL
#define TYPES(X)                                                                                   \
    X(void, void, NULL, NULL, NULL, NULL)                                                          \
    X(int, int, AS_INT)                                                                            \
    X(long, long, VALUE("integer(c_long)", "c_long"))                                              \
    X(size, size_t, VALUE("integer(c_size_t)", "c_size_t"))                                        \
    X(uint64, uint64_t, VALUE("integer(c_int64_t)", "c_int64_t"))                                  \
    X(double, double, VALUE("real(c_double)", "c_double"))                                         \
    /* enums: integer(c_int) constants (taper_constants) */                                        \
    X(status, taper_status, AS_INT)                                                                \
    X(profile, taper_profile, AS_INT)                                                              \
    X(disorder, taper_disorder, AS_INT)                                                            \
    X(end, taper_end, AS_INT)                                                                      \
    X(boundary, taper_boundary, AS_INT)                                                            \
    X(dimension, taper_dimension, AS_INT)                                                          \
    X(theory_quantity, taper_theory_quantity, AS_INT)                                              \
    X(method, taper_method, AS_INT)                                                                \
    X(observable, taper_observable, AS_INT)                                                        \
    X(statistic, taper_statistic, AS_INT)                                                          \
    X(law, taper_law, AS_INT)                                                                      \
    X(fit_model, taper_fit_model, AS_INT)                                                          \
    /* an enum the function writes (*_from_name) */                                                \
    X(profile_out, taper_profile *, INT_OUT)                                                       \
    X(disorder_out, taper_disorder *, INT_OUT)                                                     \
    X(boundary_out, taper_boundary *, INT_OUT)                                                     \
    X(method_out, taper_method *, INT_OUT)                                                         \
    X(fit_model_out, taper_fit_model *, INT_OUT)                                                   \
    /* objects: type(c_ptr), whatever the constness C gives them */                                \
    X(chain_spec, taper_chain_spec *, AS_PTR)                                                      \
    X(const_chain_spec, const taper_chain_spec *, AS_PTR)                                          \
    X(solver_spec, taper_solver_spec *, AS_PTR)                                                    \
    X(const_solver_spec, const taper_solver_spec *, AS_PTR)                                        \
    X(chain, taper_chain *, AS_PTR)                                                                \
    X(const_chain, const taper_chain *, AS_PTR)                                                    \
    X(sim, taper_sim *, AS_PTR)                                                                    \
    X(const_sim, const taper_sim *, AS_PTR)                                                        \
    X(dynamics, taper_dynamics *, AS_PTR)                                                          \
    X(const_dynamics, const taper_dynamics *, AS_PTR)                                              \
    X(fit_spec, taper_fit_spec *, AS_PTR)                                                          \
    X(const_fit_spec, const taper_fit_spec *, AS_PTR)                                              \
    X(fit_result, taper_fit_result *, AS_PTR)                                                      \
    X(const_fit_result, const taper_fit_result *, AS_PTR)                                          \
    X(setting, const taper_setting *, AS_PTR) /* a row: taper_setting_row makes it one */          \
    X(user, void *, AS_PTR)                   /* the callbacks' user data */                       \
    X(monitor_fn, taper_monitor_fn, "type(c_funptr), value :: %s", "c_funptr", NULL, NULL)         \
    X(log_fn, taper_log_fn, "type(c_funptr), value :: %s", "c_funptr", NULL, NULL)                 \
    X(sample_fn, taper_sample_fn, "type(c_funptr), value :: %s", "c_funptr", NULL, NULL)           \
    X(error, taper_error *, "type(taper_error), intent(inout) :: %s", "taper_error", NULL, NULL)   \
    /* strings: a wrapper takes and gives Fortran strings */                                       \
    X(string, const char *, "character(kind=c_char), intent(in) :: %s(*)", "c_char",               \
      "type(c_ptr)", "c_ptr")                                                                      \
    X(strings, const char *const *, AS_PTR) /* a NULL-free array of n C strings */                 \
    /* pointers to doubles: a scalar written, an array read or filled, or a type(c_ptr) */         \
    X(size_out, size_t *, "integer(c_size_t), intent(out) :: %s", "c_size_t", NULL, NULL)          \
    X(double_out, double *, "real(c_double), intent(out) :: %s", "c_double", NULL, NULL)           \
    X(doubles_out, double *, "real(c_double), intent(out) :: %s(*)", "c_double", NULL, NULL)       \
    X(doubles_in, const double *, "real(c_double), intent(in) :: %s(*)", "c_double", NULL, NULL)   \
    X(doubles_ptr, double *, AS_PTR)             /* c_loc(array), or c_null_ptr: none */           \
    X(const_doubles_ptr, const double *, AS_PTR) /* c_loc(array); a result: the owner's */         \
    X(const_doubles_out, const double **, "type(c_ptr), intent(out) :: %s", "c_ptr", NULL, NULL)

/* ---- each row checked against taper.h by the C compiler ---------------- */
enum { MAX_ARGS = 8 }; /* arguments of a row at most */

#define TYPEDEF(type, ctype, ...) typedef ctype T_##type;
TYPES(TYPEDEF)
#undef TYPEDEF
#define A(type, name) T_##type
#define VOID void
#define FN(result, function, note, ...)                                                            \
    _Static_assert(_Generic(&function, T_##result(*)(__VA_ARGS__): 1, default: 0),                \
                   #function ": its row in taper_functions.def does not have the types "        \
                             "taper.h declares");
#define FN_C FN
#define SECTION(title)
#define SETTINGS(function, names)
#include "taper_functions.def"
#undef A
#undef VOID
#undef FN
/* (and no row has more arguments than a row holds) */
#define A(type, name) 0
#define VOID 0
#define FN(result, function, note, ...)                                                            \
    _Static_assert(sizeof((char[]){__VA_ARGS__}) <= MAX_ARGS,                                      \
                   #function ": more arguments than MAX_ARGS");
#include "taper_functions.def"
#undef A
#undef VOID
#undef FN
#undef FN_C
#undef SECTION
#undef SETTINGS

/* ---- the rows, as data --------------------------------------------------- */
typedef enum type_id {
    TYPE_NONE, /* the end of an argument list */
#define TYPE_ID(type, ...) TYPE_##type,
    TYPES(TYPE_ID)
#undef TYPE_ID
} type_id;

typedef struct crossing {
    const char *name, *dummy, *dummy_import, *result, *result_import;
} crossing;
static const crossing crossings[] = {
    {"(none)", NULL, NULL, NULL, NULL},
#define CROSSING(type, ctype, ...) {#type, __VA_ARGS__},
    TYPES(CROSSING)
#undef CROSSING
};

typedef enum row_kind { ROW_SECTION, ROW_FN, ROW_FN_C, ROW_SETTINGS } row_kind;
typedef struct argument {
    type_id type;
    const char *name;
} argument;
typedef struct row {
    row_kind kind;
    type_id result;
    const char *name; /* the C function's                                 */
    const char *text; /* a section's title, a note, SETTINGS' names       */
    argument args[MAX_ARGS];
} row;

static const row rows[] = {
#define A(type, name) {TYPE_##type, #name}
#define VOID {TYPE_NONE, NULL}
#define FN(result, function, note, ...) {ROW_FN, TYPE_##result, #function, note, {__VA_ARGS__}},
#define FN_C(result, function, note, ...)                                                          \
    {ROW_FN_C, TYPE_##result, #function, note, {__VA_ARGS__}},
#define SECTION(title) {ROW_SECTION, TYPE_NONE, NULL, title, {VOID}},
#define SETTINGS(function, names) {ROW_SETTINGS, TYPE_NONE, #function, names, {VOID}},
#include "taper_functions.def"
#undef A
#undef VOID
#undef FN
#undef FN_C
#undef SECTION
#undef SETTINGS
};
#define N_ROWS (sizeof rows / sizeof rows[0])

/* ---- writing ------------------------------------------------------------- */
static FILE *out;
static const char *out_path;

static void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "gen_module: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    if (out) fclose(out);
    if (out_path) remove(out_path);
    exit(1);
}

/* Lines of at most this many characters (free form allows 132). */
enum { WIDTH = 100 };

/* A statement, continued with `&` where it would be too long: after a
 * blank outside parentheses where one falls past the first third of the line
 * (before bind(C, ...), between names of a list), else after the last blank
 * (never inside a string literal: the literals written here have none). */
static void statement(int indent, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *text = n < 0 ? NULL : malloc((size_t)n + 1);
    if (!text) die("out of memory");
    va_start(ap, fmt);
    vsnprintf(text, (size_t)n + 1, fmt, ap);
    va_end(ap);
    const char *s = text;
    int first = 1;
    while (*s) {
        int lead = indent + (first ? 0 : 5);
        size_t room = WIDTH - (size_t)lead;
        if (strlen(s) <= room) {
            fprintf(out, "%*s%s\n", lead, "", s);
            break;
        }
        size_t cut = 0, outer = 0; /* after a blank; room for " &" */
        int depth = 0;
        for (size_t i = 1; i + 2 <= room; i++) {
            depth += (s[i - 1] == '(') - (s[i - 1] == ')');
            if (s[i - 1] != ' ') continue;
            cut = i;
            if (depth == 0) outer = i;
        }
        if (outer > room / 3) cut = outer;
        if (cut == 0) die("cannot break: %s", s);
        fprintf(out, "%*s%.*s&\n", lead, "", (int)cut, s);
        s += cut;
        first = 0;
    }
    free(text);
}

/* A comment: each line of text ('\n') filled to the width, but for lines
 * that begin with a blank (code), written as they are. */
static void comment(int indent, const char *text)
{
    const char *line = text;
    while (*line) {
        size_t len = strcspn(line, "\n");
        if (line[0] == ' ') {
            fprintf(out, "%*s!%.*s\n", indent, "", (int)len, line);
        } else {
            size_t room = WIDTH - (size_t)indent - 2, done = 0;
            while (done < len) {
                size_t take = len - done;
                if (take > room) {
                    take = room;
                    while (take > 0 && line[done + take] != ' ') take--;
                    if (take == 0) take = room;
                }
                size_t shown = take;
                while (shown > 0 && line[done + shown - 1] == ' ') shown--;
                fprintf(out, "%*s! %.*s\n", indent, "", (int)shown, line + done);
                done += take;
                while (done < len && line[done] == ' ') done++;
            }
        }
        line += len;
        if (*line == '\n') line++;
    }
}

/* ---- the rows of the list ------------------------------------------------ */
static int is_string(type_id t)
{
    return t == TYPE_string;
}

/* Gives or takes a C string: bound as c_NAME. */
static int has_strings(const row *r)
{
    if (is_string(r->result)) return 1;
    for (int i = 0; i < MAX_ARGS && r->args[i].type != TYPE_NONE; i++)
        if (is_string(r->args[i].type)) return 1;
    return 0;
}

static int n_args(const row *r)
{
    int n = 0;
    while (n < MAX_ARGS && r->args[n].type != TYPE_NONE) n++;
    return n;
}

/* The Fortran name of the interface. */
static const char *bound_name(const row *r)
{
    static char name[128];
    snprintf(name, sizeof name, "%s%s", has_strings(r) ? "c_" : "", r->name);
    return name;
}

/* "a, b, c": the dummies, or the actual arguments of a wrapper's call. */
static void argument_list(const row *r, int call, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < n_args(r); i++) {
        const argument *a = &r->args[i];
        const char *fmt = call && is_string(a->type) ? "%s%s//c_null_char" : "%s%s";
        const char *arg = a->name;
        char trimmed[96];
        if (call && is_string(a->type)) {
            snprintf(trimmed, sizeof trimmed, "trim(%s)", a->name);
            arg = trimmed;
        }
        used += (size_t)snprintf(buf + used, size - used, fmt, i ? ", " : "", arg);
        if (used >= size) die("%s: arguments too long", r->name);
    }
}

/* A result name that no dummy has. */
static const char *result_name(const row *r, const char *preferred)
{
    for (int i = 0; i < n_args(r); i++)
        if (strcasecmp(r->args[i].name, preferred) == 0) return "result_value";
    return preferred;
}

static const char *preferred_result(type_id t)
{
    if (t == TYPE_status) return "status";
    if (is_string(t)) return "s";
    return "x";
}

/* ---- the table of settings ---------------------------------------------- */
/* The specs that hold settings, each named as its functions are
 * (taper_chain_spec_*). */
static const char *spec_of_object(taper_setting_object object)
{
    switch (object) {
    case TAPER_SETTING_CHAIN: return "chain";
    case TAPER_SETTING_SOLVER: return "solver";
    }
    return NULL;
}

static size_t n_settings;
static const taper_setting **settings;

static void load_settings(void)
{
    n_settings = taper_setting_count();
    settings = calloc(n_settings ? n_settings : 1, sizeof *settings);
    if (!settings) die("out of memory");
    for (size_t i = 0; i < n_settings; i++) {
        settings[i] = taper_setting_at(i);
        if (!settings[i]) die("taper_setting_at(%zu) is NULL below taper_setting_count()", i);
        if (!spec_of_object(settings[i]->object))
            die("setting %s: its spec (object %d) is not one gen_module.c names (add it to "
                "spec_of_object)",
                settings[i]->name, (int)settings[i]->object);
    }
}

/* The spec a function of the list belongs to, and whether it is a setter:
 * "taper_chain_spec_set_s" -> chain, setter, suffix "s". */
static int spec_function(const char *function, taper_setting_object *object, int *setter,
                         const char **suffix)
{
    for (int o = 0; o < 2; o++) {
        taper_setting_object obj = o ? TAPER_SETTING_SOLVER : TAPER_SETTING_CHAIN;
        char prefix[64];
        snprintf(prefix, sizeof prefix, "taper_%s_spec_", spec_of_object(obj));
        size_t n = strlen(prefix);
        if (strncmp(function, prefix, n) != 0) continue;
        *object = obj;
        *setter = strncmp(function + n, "set_", 4) == 0;
        *suffix = function + n + (*setter ? 4 : 0);
        return 1;
    }
    return 0;
}

static const taper_setting *setting_named(const char *name, size_t len)
{
    for (size_t i = 0; i < n_settings; i++)
        if (strlen(settings[i]->name) == len && strncmp(settings[i]->name, name, len) == 0)
            return settings[i];
    return NULL;
}

static const row *settings_row_of(const char *function)
{
    for (size_t i = 0; i < N_ROWS; i++)
        if (rows[i].kind == ROW_SETTINGS && strcmp(rows[i].name, function) == 0) return &rows[i];
    return NULL;
}

/* The settings a typed setter or getter reaches, into found[] (at most
 * max); how many. */
static size_t reached(const row *r, const taper_setting **found, size_t max)
{
    taper_setting_object object;
    int setter;
    const char *suffix;
    if (!spec_function(r->name, &object, &setter, &suffix)) return 0;
    size_t n = 0;
    const row *listed = settings_row_of(r->name);
    if (listed) {
        const char *s = listed->text;
        while (*s) {
            size_t len = strcspn(s, " ");
            if (len) {
                const taper_setting *t = setting_named(s, len);
                if (!t)
                    die("SETTINGS(%s): '%.*s' is no row of the table of settings", r->name,
                        (int)len, s);
                if (n == max) die("SETTINGS(%s): too many", r->name);
                found[n++] = t;
            }
            s += len;
            while (*s == ' ') s++;
        }
    } else {
        const taper_setting *t = setting_named(suffix, strlen(suffix));
        if (t) found[n++] = t;
    }
    for (size_t i = 0; i < n; i++)
        if (found[i]->object != object)
            die("%s reaches the setting %s, which a %s spec holds", r->name, found[i]->name,
                spec_of_object(found[i]->object));
    return n;
}

/* Every setting has a typed setter and a typed getter in the list; every
 * SETTINGS names a function of the list. */
static void check_settings(void)
{
    int *has_setter = calloc(n_settings ? n_settings : 1, sizeof *has_setter);
    int *has_getter = calloc(n_settings ? n_settings : 1, sizeof *has_getter);
    if (!has_setter || !has_getter) die("out of memory");
    for (size_t i = 0; i < N_ROWS; i++) {
        const row *r = &rows[i];
        if (r->kind == ROW_SETTINGS) {
            int known = 0;
            for (size_t j = 0; j < N_ROWS; j++)
                known |= (rows[j].kind == ROW_FN || rows[j].kind == ROW_FN_C) &&
                         strcmp(rows[j].name, r->name) == 0;
            if (!known) die("SETTINGS(%s): no FN row of that name", r->name);
            continue;
        }
        if (r->kind != ROW_FN && r->kind != ROW_FN_C) continue;
        const taper_setting *found[16];
        size_t n = reached(r, found, 16);
        taper_setting_object object;
        int setter = 0;
        const char *suffix;
        if (n) spec_function(r->name, &object, &setter, &suffix);
        for (size_t k = 0; k < n; k++)
            for (size_t j = 0; j < n_settings; j++)
                if (settings[j] == found[k]) (setter ? has_setter : has_getter)[j] = 1;
    }
    for (size_t j = 0; j < n_settings; j++) {
        const char *spec = spec_of_object(settings[j]->object);
        if (!has_setter[j])
            die("setting %s: no typed setter in taper_functions.def (taper_%s_spec_set_%s, or "
                "SETTINGS naming it on the setter that sets it)",
                settings[j]->name, spec, settings[j]->name);
        if (!has_getter[j])
            die("setting %s: no typed getter in taper_functions.def (taper_%s_spec_%s, or "
                "SETTINGS naming it on the getter that reads it)",
                settings[j]->name, spec, settings[j]->name);
    }
    free(has_setter);
    free(has_getter);
}

/* A value of a setting as the table states it. */
static void format_value(const taper_setting *s, double x, char *buf, size_t size)
{
    if (isinf(x))
        snprintf(buf, size, "%sinfinity", x < 0 ? "-" : "");
    else if (s->type == TAPER_SETTING_INTEGER || s->type == TAPER_SETTING_BOOLEAN)
        snprintf(buf, size, "%.0f", x);
    else
        snprintf(buf, size, "%.15g", x);
}

/* "name (a time): description.  0 <= name <= 1000; default 0." */
static void document_setting(int indent, const taper_setting *s)
{
    char text[2048], range[512] = "", lo[40], hi[40], def[96];
    const char *name = s->name;
    size_t used;
    if (s->dimension != TAPER_DIM_NUMBER) {
        const char *dim = taper_dimension_name(s->dimension);
        used = (size_t)snprintf(text, sizeof text, "%s (%s %s): %s.  ", name,
                                strchr("aeiou", dim[0]) ? "an" : "a", dim, s->description);
    } else {
        used = (size_t)snprintf(text, sizeof text, "%s: %s.  ", name, s->description);
    }
    format_value(s, s->min, lo, sizeof lo);
    format_value(s, s->max, hi, sizeof hi);
    const char *what = s->type == TAPER_SETTING_LIST ? "each entry" : name;
    int has_lo = !isinf(s->min), has_hi = !isinf(s->max);
    const char *lt = s->min_open ? "<" : "<=", *gt = s->max_open ? "<" : "<=";
    switch (s->type) {
    case TAPER_SETTING_BOOLEAN: snprintf(range, sizeof range, "0 or 1"); break;
    case TAPER_SETTING_CHOICE: {
        size_t r = 0;
        for (size_t k = 0; s->choices && s->choices[k] && r < sizeof range; k++)
            r += (size_t)snprintf(range + r, sizeof range - r, "%s'%s'",
                                  k == 0 ? "one of " : ", ", s->choices[k]);
        break;
    }
    default:
        if (has_lo && has_hi)
            snprintf(range, sizeof range, "%s %s %s %s %s", lo, lt, what, gt, hi);
        else if (has_lo)
            snprintf(range, sizeof range, "%s %s %s", what, s->min_open ? ">" : ">=", lo);
        else if (has_hi)
            snprintf(range, sizeof range, "%s %s %s", what, gt, hi);
    }
    if (strncmp(range, "one of", 6) == 0 || strncmp(range, "each", 4) == 0)
        range[0] = (char)toupper((unsigned char)range[0]); /* a sentence, not a name */
    if (s->type == TAPER_SETTING_LIST)
        snprintf(def, sizeof def, "none");
    else if (s->type == TAPER_SETTING_CHOICE && s->choices)
        snprintf(def, sizeof def, "'%s'", s->choices[(size_t)s->default_value]);
    else
        format_value(s, s->default_value, def, sizeof def);
    snprintf(text + used, sizeof text - used, "%s%sefault %s.", range, range[0] ? "; d" : "D", def);
    comment(indent, text);
}

/* ---- the module's parts ---------------------------------------------------- */
static void write_notice(const char *template_path)
{
    const char *base = strrchr(template_path, '/');
    base = base ? base + 1 : template_path;
    fprintf(out, "! taper.f90 -- written at build time by gen_module.c (drivers/fortran/module)\n"
                 "! from %s (the hand-written part), taper_functions.def (the\n"
                 "! interfaces, checked against taper.h) and libtaper's table of settings\n"
                 "! (the setters' comments, the setters by name): do not edit.\n"
                 "!\n",
            base);
}

/* The generic setter by name of each spec, and the kinds of value it takes. */
typedef struct by_name_kind {
    const char *suffix, *value, *impl, *c_function;
    int list; /* only for a spec with a list setting */
} by_name_kind;
static const by_name_kind by_name_kinds[] = {
    {"real", "real(c_double), intent(in) :: value", "set_real", "set_option", 0},
    {"int", "integer(c_int), intent(in) :: value", "set_int", "set_option", 0},
    {"int64", "integer(c_int64_t), intent(in) :: value", "set_int64", "set_option", 0},
    {"logical", "logical, intent(in) :: value", "set_logical", "set_option", 0},
    {"text", "character(len=*), intent(in) :: value", "set_text", "set_option_text", 0},
    {"list", "real(c_double), intent(in) :: values(:)", "set_list", "set_option_list", 1},
};
#define N_KINDS (sizeof by_name_kinds / sizeof by_name_kinds[0])

static int spec_has(taper_setting_object object, taper_setting_type type)
{
    for (size_t i = 0; i < n_settings; i++)
        if (settings[i]->object == object && settings[i]->type == type) return 1;
    return 0;
}

static int spec_holds(taper_setting_object object)
{
    for (size_t i = 0; i < n_settings; i++)
        if (settings[i]->object == object) return 1;
    return 0;
}

static const row *function_row(const char *name)
{
    for (size_t i = 0; i < N_ROWS; i++)
        if ((rows[i].kind == ROW_FN || rows[i].kind == ROW_FN_C) && strcmp(rows[i].name, name) == 0)
            return &rows[i];
    return NULL;
}

static void write_by_name_generic(taper_setting_object object)
{
    const char *spec = spec_of_object(object);
    int list = spec_has(object, TAPER_SETTING_LIST);
    char text[4096];
    size_t used = (size_t)snprintf(
        text, sizeof text,
        "taper_%s_spec_set_option(spec, name, value, err): a setting of a %s spec by its name in "
        "the table of settings, value a real(c_double), an integer (c_int or int64: a whole "
        "number), a logical (a boolean setting), a string (a choice's name, any case; or a number "
        "as text)%s.  TAPER_EINVAL naming the setting for an unknown name, the other spec's "
        "setting, the wrong type or a value out of range (the message states the range and "
        "why).  Its settings:",
        spec, spec, list ? " or a real(c_double) array (a list; size 0 removes it)" : "");
    for (size_t i = 0; i < n_settings; i++)
        if (settings[i]->object == object)
            used += (size_t)snprintf(text + used, sizeof text - used, " %s,", settings[i]->name);
    if (used >= sizeof text) die("too many settings to list");
    text[used - 1] = '.';
    fprintf(out, "\n");
    comment(2, text);
    char procedures[1024];
    size_t p = 0;
    for (size_t k = 0; k < N_KINDS; k++) {
        const by_name_kind *kind = &by_name_kinds[k];
        if (kind->list && !list) continue;
        char c_name[96];
        snprintf(c_name, sizeof c_name, "taper_%s_spec_%s", spec, kind->c_function);
        const row *r = function_row(c_name);
        if (!r || r->kind != ROW_FN_C)
            die("the %s spec's settings by name need %s as an FN_C row of taper_functions.def",
                spec, c_name);
        p += (size_t)snprintf(procedures + p, sizeof procedures - p, "%s%s_set_%s", p ? ", " : "",
                              spec, kind->suffix);
    }
    fprintf(out, "  interface taper_%s_spec_set_option\n", spec);
    statement(5, "module procedure %s", procedures);
    fprintf(out, "  end interface taper_%s_spec_set_option\n", spec);
    fprintf(out, "  public :: taper_%s_spec_set_option\n", spec);
}

static void write_by_name_specifics(taper_setting_object object)
{
    const char *spec = spec_of_object(object);
    int list = spec_has(object, TAPER_SETTING_LIST);
    fprintf(out, "\n  ! ---- taper_%s_spec_set_option's specific procedures\n", spec);
    for (size_t k = 0; k < N_KINDS; k++) {
        const by_name_kind *kind = &by_name_kinds[k];
        if (kind->list && !list) continue;
        const char *value = kind->list ? "values" : "value";
        fprintf(out, "%s  function %s_set_%s(spec, name, %s, err) result(status)\n",
                k ? "\n" : "", spec, kind->suffix, value);
        fprintf(out, "    type(c_ptr), intent(in) :: spec\n"
                     "    character(len=*), intent(in) :: name\n"
                     "    %s\n"
                     "    type(taper_error), intent(inout) :: err\n"
                     "    integer(c_int) :: status\n",
                kind->value);
        statement(4, "status = %s(c_taper_%s_spec_%s, spec, name, %s, err)", kind->impl, spec,
                  kind->c_function, value);
        fprintf(out, "  end function %s_set_%s\n", spec, kind->suffix);
    }
}

/* "import :: c_int, c_ptr, taper_error", in a fixed order. */
static void write_imports(const row *r)
{
    static const char *const order[] = {"c_int",  "c_long", "c_size_t", "c_int64_t",  "c_double",
                                        "c_char", "c_ptr",  "c_funptr", "taper_error", NULL};
    int need[16] = {0};
    for (int i = 0; i < n_args(r); i++)
        for (int k = 0; order[k]; k++)
            if (strcmp(crossings[r->args[i].type].dummy_import, order[k]) == 0) need[k] = 1;
    if (r->result != TYPE_void)
        for (int k = 0; order[k]; k++)
            if (strcmp(crossings[r->result].result_import, order[k]) == 0) need[k] = 1;
    char list[256] = "";
    size_t used = 0;
    for (int k = 0; order[k]; k++)
        if (need[k]) used += (size_t)snprintf(list + used, sizeof list - used, "%s%s",
                                              used ? ", " : "", order[k]);
    if (used) statement(7, "import :: %s", list);
}

static void write_interface(const row *r)
{
    const char *name = bound_name(r);
    char dummies[512];
    argument_list(r, 0, dummies, sizeof dummies);
    const crossing *res = &crossings[r->result];
    if (r->result != TYPE_void && !res->result)
        die("%s: a %s cannot be a result (gen_module.c, TYPES)", r->name, res->name);
    int with_wrapper = r->kind == ROW_FN && has_strings(r);
    if (!with_wrapper && r->text[0]) comment(5, r->text);
    taper_setting_object object;
    int setter;
    const char *suffix;
    if (spec_function(r->name, &object, &setter, &suffix) && setter) {
        const taper_setting *found[16];
        size_t n = reached(r, found, 16);
        for (size_t k = 0; k < n; k++) document_setting(5, found[k]);
    }
    const char *result = preferred_result(r->result);
    result = result_name(r, result);
    if (r->result == TYPE_void)
        statement(5, "subroutine %s(%s) bind(C, name=\"%s\")", name, dummies, r->name);
    else
        statement(5, "function %s(%s) bind(C, name=\"%s\") result(%s)", name, dummies, r->name,
                  result);
    write_imports(r);
    for (int i = 0; i < n_args(r); i++) {
        const crossing *c = &crossings[r->args[i].type];
        if (!c->dummy) die("%s: a %s cannot be an argument", r->name, c->name);
        fprintf(out, "%7s", "");
        fprintf(out, c->dummy, r->args[i].name);
        fprintf(out, "\n");
    }
    if (r->result == TYPE_void) {
        fprintf(out, "     end subroutine %s\n", name);
    } else {
        fprintf(out, "       %s :: %s\n", res->result, result);
        fprintf(out, "     end function %s\n", name);
    }
}

/* NAME: the interface c_NAME with Fortran strings. */
static void write_wrapper(const row *r)
{
    char dummies[512], actuals[1024];
    argument_list(r, 0, dummies, sizeof dummies);
    argument_list(r, 1, actuals, sizeof actuals);
    fprintf(out, "\n");
    if (r->text[0]) comment(2, r->text);
    const char *result = result_name(r, preferred_result(r->result));
    if (r->result == TYPE_void)
        statement(2, "subroutine %s(%s)", r->name, dummies);
    else
        statement(2, "function %s(%s) result(%s)", r->name, dummies, result);
    for (int i = 0; i < n_args(r); i++) {
        const argument *a = &r->args[i];
        char decl[160];
        if (is_string(a->type)) {
            snprintf(decl, sizeof decl, "character(len=*), intent(in) :: %s", a->name);
        } else {
            /* what C takes by value, intent(in) here */
            const char *form = crossings[a->type].dummy, *value = strstr(form, ", value ::");
            if (value)
                snprintf(decl, sizeof decl, "%.*s, intent(in) :: %s", (int)(value - form), form,
                         a->name);
            else
                snprintf(decl, sizeof decl, form, a->name);
        }
        fprintf(out, "    %s\n", decl);
    }
    if (r->result == TYPE_void) {
        statement(4, "call c_%s(%s)", r->name, actuals);
        fprintf(out, "  end subroutine %s\n", r->name);
    } else if (is_string(r->result)) {
        fprintf(out, "    character(len=:), allocatable :: %s\n", result);
        statement(4, "%s = c_string(c_%s(%s))", result, r->name, actuals);
        fprintf(out, "  end function %s\n", r->name);
    } else {
        fprintf(out, "    %s :: %s\n", crossings[r->result].result, result);
        statement(4, "%s = c_%s(%s)", result, r->name, actuals);
        fprintf(out, "  end function %s\n", r->name);
    }
}

static void write_specification(void)
{
    /* public statements: every interface, every wrapper */
    char names[8192];
    size_t used = 0;
    for (size_t i = 0; i < N_ROWS; i++) {
        const row *r = &rows[i];
        if (r->kind != ROW_FN && r->kind != ROW_FN_C) continue;
        used += (size_t)snprintf(names + used, sizeof names - used, "%s%s", used ? ", " : "",
                                 bound_name(r));
        if (r->kind == ROW_FN && has_strings(r))
            used += (size_t)snprintf(names + used, sizeof names - used, ", %s", r->name);
        if (used >= sizeof names) die("too many names");
    }
    statement(2, "public :: %s", names);
    for (taper_setting_object o = TAPER_SETTING_CHAIN; o <= TAPER_SETTING_SOLVER; o++)
        if (spec_holds(o)) write_by_name_generic(o);
    fprintf(out, "\n  interface\n");
    for (size_t i = 0; i < N_ROWS; i++) {
        const row *r = &rows[i];
        if (r->kind == ROW_SECTION) {
            char title[512];
            snprintf(title, sizeof title, "---- %s", r->text);
            fprintf(out, "\n");
            comment(5, title);
        } else if (r->kind == ROW_FN || r->kind == ROW_FN_C) {
            write_interface(r);
        }
    }
    fprintf(out, "  end interface\n");
}

static void write_procedures(void)
{
    for (size_t i = 0; i < N_ROWS; i++)
        if (rows[i].kind == ROW_FN && has_strings(&rows[i])) write_wrapper(&rows[i]);
    for (taper_setting_object o = TAPER_SETTING_CHAIN; o <= TAPER_SETTING_SOLVER; o++)
        if (spec_holds(o)) write_by_name_specifics(o);
}

/* ---- the template ---------------------------------------------------------- */
static int marker(const char *line, const char *name)
{
    while (*line == ' ') line++;
    char want[64];
    snprintf(want, sizeof want, "! @%s@", name);
    size_t n = strlen(want);
    return strncmp(line, want, n) == 0 && (line[n] == '\n' || line[n] == '\0');
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: gen_module TEMPLATE OUT\n");
        return 2;
    }
    FILE *in = fopen(argv[1], "r");
    if (!in) {
        perror(argv[1]);
        return 1;
    }
    load_settings();
    check_settings();
    out_path = argv[2];
    out = fopen(out_path, "w");
    if (!out) die("%s: cannot write", out_path);

    static const char *const markers[] = {"notice", "specification", "procedures"};
    int seen = 0;
    char line[4096];
    while (fgets(line, sizeof line, in)) {
        if (!strchr(line, '\n') && !feof(in)) die("%s: a line longer than %zu", argv[1], sizeof line);
        int which = -1;
        for (int m = 0; m < 3; m++)
            if (marker(line, markers[m])) which = m;
        if (which < 0) {
            fputs(line, out);
            continue;
        }
        if (which != seen)
            die("%s: `! @%s@` where `! @%s@` was due (each once, in this order: notice, "
                "specification, procedures)",
                argv[1], markers[which], seen < 3 ? markers[seen] : "(none)");
        seen++;
        if (which == 0) write_notice(argv[1]);
        if (which == 1) write_specification();
        if (which == 2) write_procedures();
    }
    if (ferror(in)) die("%s: read error", argv[1]);
    fclose(in);
    if (seen != 3) die("%s: no `! @%s@` line", argv[1], markers[seen]);
    if (ferror(out) | fclose(out)) {
        out = NULL;
        die("%s: write error", out_path);
    }
    free(settings);
    return 0;
}
