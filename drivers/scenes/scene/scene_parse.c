/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_parse.c -- namelist lexer and parser: text -> scene values.
 *
 * Two passes keep each simple: a screening pass rejects what is not text
 * (control bytes, absurd lines) with a line number, then a lexer cuts the
 * text into tokens and a recursive-descent parser assigns values to table
 * variables, checking their types.  Ranges and relations between variables
 * are the validation pass (scene_check.c), so that a scene that parses can
 * still be echoed and corrected.
 */
#include "scene_impl.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef enum tok_kind { T_EOF, T_GROUP, T_SLASH, T_EQ, T_COMMA, T_STRING, T_WORD } tok_kind;

typedef struct token {
    tok_kind kind;
    const char *text;   /* T_GROUP: the name after '&'; T_STRING: inside quotes */
    size_t len;
    int line;
    char quote;         /* T_STRING: ' or "                                   */
} token;

typedef struct parser {
    scene *sc;
    const char *src;
    size_t len, pos;
    int line;
    token tok;              /* current token                                 */
    token next;             /* one token of look-ahead                       */
    int failed;
    size_t list_values;     /* values in lists of more than one value so far */
} parser;

/* ---- screening ----------------------------------------------------------- */

/* Rejects binary data and over-long lines before any tokenising. */
static int screen(scene *sc, const char *s, size_t len)
{
    int line = 1;
    size_t col = 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '\n') {
            line++;
            col = 0;
            continue;
        }
        if (++col > SCENE_MAX_LINE) {
            scene_error(sc, line, NULL, NULL,
                        "line longer than %d characters: split values over several lines",
                        SCENE_MAX_LINE);
            return -1;
        }
        if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f) {
            scene_error(sc, line, NULL, NULL,
                        "binary data (byte 0x%02x, column %zu): not a text scene file", c, col);
            return -1;
        }
    }
    return 0;
}

/* ---- lexer ---------------------------------------------------------------- */

static int is_word_char(int c)
{
    return c > ' ' && c != ',' && c != '=' && c != '/' && c != '&' && c != '!' && c != '\'' &&
           c != '"';
}

static void skip_blanks(parser *p)
{
    while (p->pos < p->len) {
        char c = p->src[p->pos];
        if (c == '\n') {
            p->line++;
            p->pos++;
        } else if (c == ' ' || c == '\t' || c == '\r') {
            p->pos++;
        } else if (c == '!') {
            while (p->pos < p->len && p->src[p->pos] != '\n') p->pos++;
        } else {
            break;
        }
    }
}

/* A quoted string; a doubled quote inside stands for one (Fortran). */
static int lex_string(parser *p, token *t)
{
    char q = p->src[p->pos++];
    t->kind = T_STRING;
    t->quote = q;
    t->text = p->src + p->pos;
    while (p->pos < p->len && p->src[p->pos] != '\n') {
        if (p->src[p->pos] == q) {
            if (p->pos + 1 < p->len && p->src[p->pos + 1] == q) {
                p->pos += 2;
                continue;
            }
            t->len = (size_t)(p->src + p->pos - t->text);
            p->pos++;
            return 0;
        }
        p->pos++;
    }
    scene_error(p->sc, t->line, NULL, NULL, "string opened with %c is not closed on this line", q);
    return -1;
}

static int lex(parser *p, token *t)
{
    skip_blanks(p);
    memset(t, 0, sizeof *t);
    t->line = p->line;
    if (p->pos >= p->len) return 0; /* T_EOF */
    char c = p->src[p->pos];
    if (c == '\'' || c == '"') return lex_string(p, t);
    if (c == '&') {
        p->pos++;
        t->kind = T_GROUP;
        t->text = p->src + p->pos;
        while (p->pos < p->len && is_word_char((unsigned char)p->src[p->pos])) p->pos++;
        t->len = (size_t)(p->src + p->pos - t->text);
        if (t->len == 0) {
            scene_error(p->sc, t->line, NULL, NULL, "'%c' must be followed by a group name", c);
            return -1;
        }
        return 0;
    }
    t->text = p->src + p->pos;
    t->len = 1;
    p->pos++;
    switch (c) {
    case '/': t->kind = T_SLASH; return 0;
    case '=': t->kind = T_EQ; return 0;
    case ',': t->kind = T_COMMA; return 0;
    default: break;
    }
    t->kind = T_WORD;
    while (p->pos < p->len && is_word_char((unsigned char)p->src[p->pos])) p->pos++;
    t->len = (size_t)(p->src + p->pos - t->text);
    return 0;
}

/* Moves to the next token; sets p->failed on a lexical error. */
static void advance(parser *p)
{
    p->tok = p->next;
    if (!p->failed && lex(p, &p->next) != 0) p->failed = 1;
}

/* Up to size-1 bytes of a token, for messages (never unbounded); bytes
 * that are not printable ASCII are shown as \xNN by scene_error. */
static const char *tok_text(const token *t, char *buf, size_t size)
{
    if (t->kind == T_EOF) return "end of file";
    size_t n = t->len < size - 1 ? t->len : size - 1;
    memcpy(buf, t->text, n);
    buf[n] = '\0';
    if (n < t->len && size > 4) memcpy(buf + size - 4, "...", 4);
    return buf;
}

/* ---- values ----------------------------------------------------------------- */

/* One element of a value list after repeat counts are expanded. */
typedef struct element {
    enum { E_NUMBER, E_INTEGER, E_LOGICAL, E_STRING } kind;
    double x;
    long long i;
    int b;
    token tok;          /* the value's token (by value: tokens are small)  */
} element;

static int is_digit_run(const char *s, size_t n, size_t *i)
{
    size_t start = *i;
    while (*i < n && isdigit((unsigned char)s[*i])) (*i)++;
    return *i > start;
}

/* Fortran numeric syntax: [+-] digits [. [digits]] | . digits, then an
 * optional exponent [eEdD][+-]digits.  *is_int: no '.' and no exponent. */
static int number_syntax(const char *s, size_t n, int *is_int)
{
    size_t i = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    int mant = is_digit_run(s, n, &i);
    *is_int = 1;
    if (i < n && s[i] == '.') {
        i++;
        *is_int = 0;
        mant |= is_digit_run(s, n, &i);
    }
    if (!mant) return 0;
    if (i < n && strchr("eEdD", s[i])) {
        i++;
        *is_int = 0;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        if (!is_digit_run(s, n, &i)) return 0;
    }
    return i == n;
}

static int logical_syntax(const char *s, size_t n, int *b)
{
    static const char *const forms[] = {"t", "f", ".t", ".f", ".t.", ".f.", ".true.", ".false.",
                                        "true", "false"};
    for (size_t k = 0; k < sizeof forms / sizeof forms[0]; k++) {
        if (strlen(forms[k]) == n && strncasecmp(s, forms[k], n) == 0) {
            *b = (k % 2) == 0;
            return 1;
        }
    }
    return 0;
}

static int looks_nonfinite(const char *s, size_t n)
{
    if (n > 0 && (s[0] == '+' || s[0] == '-')) s++, n--;
    return (n >= 3 && (strncasecmp(s, "nan", 3) == 0 || strncasecmp(s, "inf", 3) == 0));
}

/* Converts a word to an element, reporting errors against group/key. */
static int word_value(parser *p, const token *t, const char *group, const char *key, element *e)
{
    char buf[64];
    int is_int;
    if (logical_syntax(t->text, t->len, &e->b)) {
        e->kind = E_LOGICAL;
        return 0;
    }
    if (looks_nonfinite(t->text, t->len)) {
        scene_error(p->sc, t->line, group, key, "'%s' is not a finite number", tok_text(t, buf, sizeof buf));
        return -1;
    }
    if (!number_syntax(t->text, t->len, &is_int) || t->len >= sizeof buf) {
        scene_error(p->sc, t->line, group, key,
                    "'%s' is not a value (numbers like 1.5d-3, logicals .true./.false., "
                    "strings in quotes: '%s')",
                    tok_text(t, buf, sizeof buf), buf);
        return -1;
    }
    memcpy(buf, t->text, t->len);
    buf[t->len] = '\0';
    for (char *c = buf; *c; c++)
        if (*c == 'd' || *c == 'D') *c = 'e';
    errno = 0;
    e->x = strtod(buf, NULL);
    if (errno == ERANGE || !isfinite(e->x)) {
        scene_error(p->sc, t->line, group, key, "%s is outside the range of double precision", buf);
        return -1;
    }
    e->kind = E_NUMBER;
    if (is_int) {
        errno = 0;
        e->i = strtoll(buf, NULL, 10);
        if (errno != ERANGE) e->kind = E_INTEGER;
    }
    return 0;
}

/* ---- assignment: elements -> typed value ------------------------------------ */

static int type_error(parser *p, const scene_var *var, const element *e)
{
    static const char *const example[] = {"'text'", "1.5", "10", ".true.", "1.0, 1.2, 1.5",
                                          "'text'"};
    char buf[64];
    const char *what = e->kind == E_STRING ? "a string" : tok_text(&e->tok, buf, sizeof buf);
    if (var->type == SCENE_INTEGER && e->kind == E_NUMBER) {
        /* 1e9, 2.0, 1d5: a number, but not written as an integer; or
         * digits beyond a long long. */
        char *range = scene_range_text(var);
        int is_int = 0;
        number_syntax(e->tok.text, e->tok.len, &is_int);
        scene_error(p->sc, e->tok.line, var->group, var->name,
                    "%s %s: %s takes integers in %s, written with digits only (e.g. %s = "
                    "1000)", what, is_int ? "is out of range" : "is not written as an integer",
                    var->name, range ? range : "its range", var->name);
        free(range);
        return -1;
    }
    scene_error(p->sc, e->tok.line, var->group, var->name,
                "expects %s %s, got %s (e.g. %s = %s)", var->type == SCENE_INTEGER ? "an" : "a",
                scene_type_name(var), what, var->name, example[var->type]);
    return -1;
}

static char *string_value(const token *t)
{
    char *s = malloc(t->len + 1);
    if (!s) return NULL;
    size_t n = 0;
    for (size_t i = 0; i < t->len; i++) {
        s[n++] = t->text[i];
        if (t->text[i] == t->quote) i++; /* doubled quote */
    }
    s[n] = '\0';
    return s;
}

/* The strings of a list given to a SCENE_WORDS row ('young', 'damping'),
 * as one string of names separated by commas ("young, damping"), the form
 * the row also takes and the echo writes. */
static char *joined_words(const element *el, size_t n)
{
    size_t len = 1;
    for (size_t i = 0; i < n; i++) len += el[i].tok.len + 2;
    char *s = malloc(len);
    if (!s) return NULL;
    s[0] = '\0';
    for (size_t i = 0; i < n; i++) {
        char *word = string_value(&el[i].tok);
        if (!word) {
            free(s);
            return NULL;
        }
        if (i) strcat(s, ", ");
        strcat(s, word);
        free(word);
    }
    return s;
}

/* A string for a CHOICE row: one of its names (any case), or an error
 * listing them. */
static int choice_value(parser *p, const scene_var *var, const element *e, int line, int *value)
{
    char *str = string_value(&e->tok);
    if (!str) {
        scene_error(p->sc, line, var->group, var->name, "out of memory");
        return -1;
    }
    if (scene_choice_find(var, str, value) == 0) {
        free(str);
        return 0;
    }
    /* Shown: at most 31 bytes of what was written, marked when cut. */
    char *allowed = scene_range_text(var);
    size_t len = strlen(str);
    scene_error(p->sc, line, var->group, var->name, "'%.*s%s' is not allowed: use one of %s",
                len > 31 ? 28 : (int)len, str, len > 31 ? "..." : "",
                allowed ? allowed : "(out of memory)");
    free(allowed);
    free(str);
    return -1;
}

static int assign(parser *p, int vi, const element *el, size_t n, int line)
{
    const scene_var *var = scene_var_at((size_t)vi);
    scene_config *cfg = &p->sc->cfg;
    int words = var->type == SCENE_STRING && (var->flags & SCENE_WORDS);
    int multi_ok = scene_var_is_list(var) || (var->flags & SCENE_SWEEP) || words;
    if (n > 1 && !multi_ok) {
        scene_error(p->sc, line, var->group, var->name,
                    "expects one value, got %zu (lists sweep reals and integers of &chain and "
                    "&solver: s, q, exponent, n_granules, rtol, ...)", n);
        return -1;
    }
    if (n > 1) {
        /* The echo repeats every value: all lists together are bounded so
         * that it fits the file limit (scene.c).  One limit for a file, the
         * command line and a program (the Python package), whose scene is
         * echoed alike; a chain of more custom radii reads them from a
         * radii_file, which the echo names. */
        if (n > SCENE_MAX_LIST - p->list_values) {
            scene_error(p->sc, line, var->group, var->name,
                        "%zu values here and %zu in other lists: a scene's lists hold at most "
                        "%d values in all%s", n, p->list_values, SCENE_MAX_LIST,
                        strcmp(var->keyword, "radii") == 0
                            ? " (a longer custom chain: its radii in a radii_file)" : "");
            return -1;
        }
        p->list_values += n;
    }
    for (size_t i = 0; i < n; i++) {
        int k = el[i].kind;
        int ok = ((var->type == SCENE_STRING || var->type == SCENE_CHOICE) && k == E_STRING) ||
                 (var->type == SCENE_LOGICAL && k == E_LOGICAL) ||
                 (var->type == SCENE_INTEGER && k == E_INTEGER) ||
                 ((var->type == SCENE_REAL || var->type == SCENE_REAL_LIST) &&
                  (k == E_NUMBER || k == E_INTEGER));
        if (!ok) return type_error(p, var, &el[i]);
    }
    int choice = 0;
    if (var->type == SCENE_CHOICE && choice_value(p, var, &el[0], line, &choice) != 0) return -1;
    scene_field_clear(cfg, var);
    void *f = scene_field(cfg, var);
    scene_mark_given(p->sc, (size_t)vi, line);
    if (scene_var_is_list(var)) {
        scene_reals *r = f;
        if (!(r->v = malloc(n * sizeof *r->v))) goto nomem;
        for (size_t i = 0; i < n; i++) r->v[i] = el[i].x;
        r->n = n;
        return 0;
    }
    if (n > 1 && !words) {
        /* A sweep of a one-value field: the list aside (scene_sweep.c), the
         * first value in the field.  Integers are stored as doubles. */
        scene_reals *r = &cfg->sweep.lists[vi];
        if (!(r->v = malloc(n * sizeof *r->v))) goto nomem;
        for (size_t i = 0; i < n; i++) {
            if (var->type == SCENE_INTEGER && (el[i].i > (1LL << 53) || el[i].i < -(1LL << 53))) {
                free(r->v);
                r->v = NULL;
                scene_error(p->sc, line, var->group, var->name,
                            "%lld: the values of a swept integer must be at most 2^53", el[i].i);
                return -1;
            }
            r->v[i] = var->type == SCENE_INTEGER ? (double)el[i].i : el[i].x;
        }
        r->n = n;
    }
    switch (var->type) {
    case SCENE_STRING:
        if (!(*(char **)f = n > 1 ? joined_words(el, n) : string_value(&el[0].tok))) goto nomem;
        break;
    case SCENE_CHOICE: memcpy(f, &choice, sizeof choice); break;
    case SCENE_LOGICAL: memcpy(f, &el[0].b, sizeof el[0].b); break;
    case SCENE_INTEGER: memcpy(f, &el[0].i, sizeof el[0].i); break;
    default: memcpy(f, &el[0].x, sizeof el[0].x); break;
    }
    return 0;
nomem:
    scene_error(p->sc, line, var->group, var->name, "out of memory");
    return -1;
}

/* ---- parser ------------------------------------------------------------------ */

/* Appends `count` copies of e to the element array, growing it. */
static int push(parser *p, element **el, size_t *n, size_t *cap, const element *e,
                long long count, const char *group, const char *key)
{
    if (count < 1) {
        scene_error(p->sc, e->tok.line, group, key, "repeat count %lld: it must be at least 1", count);
        return -1;
    }
    if ((unsigned long long)count > SCENE_MAX_LIST - *n) {
        scene_error(p->sc, e->tok.line, group, key,
                    "list longer than %d values (repeat count %lld)", SCENE_MAX_LIST, count);
        return -1;
    }
    if (*n + (size_t)count > *cap) {
        size_t c = *cap ? *cap : 16;
        while (c < *n + (size_t)count) c *= 2;
        element *grown = realloc(*el, c * sizeof *grown);
        if (!grown) {
            scene_error(p->sc, e->tok.line, group, key, "out of memory");
            return -1;
        }
        *el = grown;
        *cap = c;
    }
    for (long long i = 0; i < count; i++) (*el)[(*n)++] = *e;
    return 0;
}

/* One value token: a string, or a word possibly with an r* repeat count. */
static int one_value(parser *p, element **el, size_t *n, size_t *cap, const char *group,
                     const char *key)
{
    token *t = &p->tok;
    element e = {0};
    e.tok = *t;
    if (t->kind == T_STRING) {
        e.kind = E_STRING;
        return push(p, el, n, cap, &e, 1, group, key);
    }
    const char *star = memchr(t->text, '*', t->len);
    long long count = 1;
    token part = *t;
    if (star) {
        int is_int;
        size_t head = (size_t)(star - t->text);
        char buf[24];
        if (head == 0 || head >= sizeof buf || !number_syntax(t->text, head, &is_int) || !is_int ||
            !isdigit((unsigned char)t->text[0]) || head + 1 == t->len) {
            scene_error(p->sc, t->line, group, key,
                        "'%s' is not a repeat: write COUNT*VALUE, e.g. 3*1.0",
                        tok_text(t, buf, sizeof buf));
            return -1;
        }
        memcpy(buf, t->text, head);
        buf[head] = '\0';
        count = strtoll(buf, NULL, 10);
        part.text += head + 1;
        part.len -= head + 1;
    }
    if (word_value(p, &part, group, key, &e) != 0) return -1;
    return push(p, el, n, cap, &e, count, group, key);
}

/* A key of the group where a value should be: the '=' after it was
 * forgotten ("s 0.5").  Reported against that key, not the previous one. */
static int missing_equals(parser *p, const token *t, const char *group)
{
    char name[48];
    if (t->len >= sizeof name) return 0;
    for (size_t i = 0; i < t->len; i++) name[i] = (char)tolower((unsigned char)t->text[i]);
    name[t->len] = '\0';
    if (scene_var_find(group, name) < 0) return 0;
    scene_error(p->sc, t->line, group, name, "expected '=' after the key (write %s = value)", name);
    return 1;
}

/* key = value [,] value ... up to the next key, '/' or end of input. */
static int parse_values(parser *p, int vi, const char *group, const char *key, int key_line)
{
    element *el = NULL;
    size_t n = 0, cap = 0;
    int rc = -1, prev_comma = 0;
    for (;;) {
        token *t = &p->tok;
        if (p->failed) goto out;
        if (t->kind == T_COMMA) {
            if (n == 0 || prev_comma) {
                scene_error(p->sc, t->line, group, key,
                            "empty value before ',' (null values are not supported)");
                goto out;
            }
            prev_comma = 1;
            advance(p);
            continue;
        }
        int is_value = t->kind == T_STRING || (t->kind == T_WORD && p->next.kind != T_EQ);
        if (!is_value) break;
        if (t->kind == T_WORD && missing_equals(p, t, group)) goto out;
        if (one_value(p, &el, &n, &cap, group, key) != 0) goto out;
        prev_comma = 0;
        advance(p);
    }
    if (n == 0) {
        char buf[40];
        scene_error(p->sc, p->tok.line, group, key, "no value after '=' (found %s)",
                    tok_text(&p->tok, buf, sizeof buf));
        goto out;
    }
    rc = vi < 0 ? 0 : assign(p, vi, el, n, key_line);
out:
    free(el);
    return rc;
}

/* "did you mean" plus the list of keys of the group. */
static void unknown_key(parser *p, const char *group, const char *key, int line)
{
    char *keys = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&keys, &len);
    const char *close = scene_nearest_key(group, key);
    for (size_t i = 0; fp && i < scene_var_count(); i++) {
        const scene_var *v = scene_var_at(i);
        if (strcmp(v->group, group) != 0) continue;
        fprintf(fp, "%s%s", len ? ", " : "", v->name);
        fflush(fp);
    }
    if (fp) fclose(fp);
    const char *list = keys ? keys : "?";
    if (close)
        scene_error(p->sc, line, group, key, "unknown key: did you mean %s? (&%s has: %s)", close,
                    group, list);
    else
        scene_error(p->sc, line, group, key, "unknown key (&%s has: %s)", group, list);
    free(keys);
}

static void copy_name(const token *t, char *buf, size_t size)
{
    size_t n = t->len < size - 1 ? t->len : size - 1;
    for (size_t i = 0; i < n; i++) buf[i] = (char)tolower((unsigned char)t->text[i]);
    buf[n] = '\0';
}

/* One key = values inside group. */
static int parse_assignment(parser *p, const char *group)
{
    char key[48], buf[48];
    int line = p->tok.line;
    copy_name(&p->tok, key, sizeof key);
    if (p->tok.len >= sizeof key) {
        scene_error(p->sc, line, group, NULL, "key '%s' is too long", tok_text(&p->tok, buf, sizeof buf));
        return -1;
    }
    if (p->next.kind != T_EQ) {
        scene_error(p->sc, line, group, key, "expected '=' after the key, found %s",
                    tok_text(&p->next, buf, sizeof buf));
        return -1;
    }
    if (strchr(key, '(') || strchr(key, '%')) {
        scene_error(p->sc, line, group, key,
                    "array elements and components are not supported: give the whole list");
        return -1;
    }
    int vi = scene_var_find(group, key);
    if (vi < 0) {
        unknown_key(p, group, key, line);
        return -1;
    }
    if (p->sc->origin[vi].given) {
        scene_error(p->sc, line, group, key, "repeated key (first given at line %d)",
                    p->sc->origin[vi].line);
        return -1;
    }
    advance(p); /* key */
    advance(p); /* = */
    return parse_values(p, vi, group, key, line);
}

static int parse_group(parser *p)
{
    char group[32], buf[48];
    int line = p->tok.line;
    copy_name(&p->tok, group, sizeof group);
    int gi = p->tok.len < sizeof group ? scene_group_index(group) : -1;
    if (gi < 0) {
        scene_unknown_group(p->sc, line, tok_text(&p->tok, buf, sizeof buf));
        return -1;
    }
    if (p->sc->group_line[gi]) {
        scene_error(p->sc, line, group, NULL, "group given twice (first at line %d): merge them",
                    p->sc->group_line[gi]);
        return -1;
    }
    p->sc->group_line[gi] = line;
    advance(p);
    for (;;) {
        if (p->failed) return -1;
        switch (p->tok.kind) {
        case T_SLASH: advance(p); return 0;
        case T_COMMA: advance(p); break;
        case T_WORD:
            if (parse_assignment(p, group) != 0) return -1;
            break;
        case T_EOF:
            scene_error(p->sc, line, group, NULL, "group is not closed: add '/' after its last value");
            return -1;
        case T_GROUP:
            /* &end closes a group in older namelist files (and for many
             * compilers): the same as '/'. */
            if (p->tok.len == 3 && strncasecmp(p->tok.text, "end", 3) == 0) {
                advance(p);
                return 0;
            }
            scene_error(p->sc, p->tok.line, group, NULL,
                        "&%s starts before &%s (line %d) is closed: add '/'",
                        tok_text(&p->tok, buf, sizeof buf), group, line);
            return -1;
        default:
            scene_error(p->sc, p->tok.line, group, NULL, "expected a key, found '%s'",
                        tok_text(&p->tok, buf, sizeof buf));
            return -1;
        }
    }
}

size_t scene_parse(scene *sc, const char *text, size_t len)
{
    size_t before = sc->n_errors;
    if (len > SCENE_MAX_FILE) {
        scene_error(sc, 0, NULL, NULL, "file larger than %u bytes: not a scene", SCENE_MAX_FILE);
        return sc->n_errors - before;
    }
    if (len >= 3 && memcmp(text, "\xef\xbb\xbf", 3) == 0) {
        scene_error(sc, 1, NULL, NULL,
                    "the file starts with a UTF-8 byte-order mark: save it as plain "
                    "ASCII/UTF-8 without BOM");
        return sc->n_errors - before;
    }
    if (screen(sc, text, len) != 0) return sc->n_errors - before;
    parser p = {.sc = sc, .src = text, .len = len, .line = 1};
    advance(&p);
    advance(&p);
    int groups = 0;
    char buf[48];
    while (!p.failed && p.tok.kind != T_EOF) {
        if (p.tok.kind != T_GROUP) {
            scene_error(sc, p.tok.line, NULL, NULL,
                        "expected a group (&chain, &solver or &output), found '%s'",
                        tok_text(&p.tok, buf, sizeof buf));
            break;
        }
        if (parse_group(&p) != 0) break;
        groups++;
    }
    if (sc->n_errors == before && groups == 0)
        scene_error(sc, 0, NULL, NULL, "empty scene: no &chain, &solver or &output group");
    return sc->n_errors - before;
}

size_t scene_load(scene *sc)
{
    size_t before = sc->n_errors;
    FILE *fp = sc->from_stdin ? stdin : fopen(sc->path, "rb");
    if (!fp) {
        scene_error(sc, 0, NULL, NULL, "cannot open: %s", strerror(errno));
        return 1;
    }
    char *buf = malloc(SCENE_MAX_FILE + 1);
    if (!buf) {
        fclose(fp);
        scene_error(sc, 0, NULL, NULL, "out of memory");
        return 1;
    }
    size_t n = fread(buf, 1, SCENE_MAX_FILE + 1, fp);
    if (ferror(fp))
        scene_error(sc, 0, NULL, NULL, "read error (is it a directory?)");
    else
        scene_parse(sc, buf, n);
    if (fp != stdin) fclose(fp);
    free(buf);
    return sc->n_errors - before;
}

/* --set GROUP.KEY=VALUE: the value is parsed as the namelist
 * "&GROUP KEY = VALUE /" on its own, so that it means exactly what it
 * would in the file, then moved into sc over the file's value. */
size_t scene_set(scene *sc, const char *assignment)
{
    size_t before = sc->n_errors;
    const char *dot = strchr(assignment, '.'), *eq = strchr(assignment, '=');
    if (!dot || !eq || dot > eq) {
        scene_error(sc, 0, NULL, NULL, "--set %s: write GROUP.KEY=VALUE (e.g. fit.k_min=12)",
                    assignment);
        return sc->n_errors - before;
    }
    char *group = text_printf("%.*s", (int)(dot - assignment), assignment);
    char *key = text_printf("%.*s", (int)(eq - dot - 1), dot + 1);
    char *text = text_printf("&%s %s = %s /", group ? group : "", key ? key : "", eq + 1);
    scene *tmp = scene_new(sc->path);
    int vi = scene_var_find(group, key);
    if (!group || !key || !text || !tmp) {
        scene_error(sc, 0, NULL, NULL, "out of memory");
    } else if (vi < 0) {
        /* the nearest group when the group is unknown, then its key */
        const char *in = scene_group_index(group) >= 0 ? group : scene_nearest_group(group);
        const char *close = in ? scene_nearest_key(in, key) : NULL;
        if (close)
            scene_error(sc, 0, group, key, "--set %s: unknown %s: did you mean %s.%s? (taper "
                        "--defaults lists them)", assignment, in == group ? "key" : "group", in,
                        close);
        else
            scene_error(sc, 0, group, key, "--set %s: no such variable (taper --defaults lists "
                        "them)", assignment);
    } else if (scene_parse(tmp, text, strlen(text)) != 0) {
        for (size_t i = 0; i < tmp->n_diags; i++)
            scene_error(sc, 0, tmp->diags[i].group, tmp->diags[i].key, "--set %s: %s", assignment,
                        tmp->diags[i].message);
    } else {
        for (size_t i = 0; i < scene_var_count(); i++)
            if (tmp->origin[i].given && (int)i != vi) {
                scene_error(sc, 0, group, key, "--set %s: one variable at a time", assignment);
                goto out;
            }
        /* Swap the fields: sc takes the new value, tmp frees the old. */
        const scene_var *var = scene_var_at((size_t)vi);
        unsigned char save[sizeof(scene_reals)]; /* the largest field (scene.c) */
        size_t size = scene_field_size(var);
        memcpy(save, scene_field(&sc->cfg, var), size);
        memcpy(scene_field(&sc->cfg, var), scene_field(&tmp->cfg, var), size);
        memcpy(scene_field(&tmp->cfg, var), save, size);
        scene_reals list = sc->cfg.sweep.lists[vi]; /* a sweep's list too */
        sc->cfg.sweep.lists[vi] = tmp->cfg.sweep.lists[vi];
        tmp->cfg.sweep.lists[vi] = list;
        scene_mark_given(sc, (size_t)vi, 0);
    }
out:
    scene_free(tmp);
    free(text);
    free(key);
    free(group);
    return sc->n_errors - before;
}

/* The values of a program (the Python package) for the variable named
 * `keyword`: checked by type as a file's are, and put in place of the
 * current value as --set does (line 0). */
size_t scene_set_values(scene *sc, const char *keyword, const scene_value *values, size_t n)
{
    size_t before = sc->n_errors;
    int vi = scene_var_keyword(keyword);
    if (vi < 0) {
        const char *close = scene_nearest_keyword(keyword);
        if (close)
            scene_error(sc, 0, NULL, keyword, "unknown variable: did you mean %s?", close);
        else
            scene_error(sc, 0, NULL, keyword, "unknown variable (taper --defaults lists them)");
        return sc->n_errors - before;
    }
    if (n == 0) {
        scene_error(sc, 0, scene_var_at((size_t)vi)->group, scene_var_at((size_t)vi)->name,
                    "no value");
        return sc->n_errors - before;
    }
    element *el = malloc(n * sizeof *el);
    if (!el) {
        scene_error(sc, 0, NULL, NULL, "out of memory");
        return sc->n_errors - before;
    }
    /* Only the first value's text is shown in a message: a type error names
     * it. */
    char first[SCENE_REAL_TEXT];
    first[0] = '\0';
    for (size_t i = 0; i < n; i++) {
        const scene_value *v = &values[i];
        element e = {0};
        switch (v->kind) {
        case SCENE_VALUE_REAL: e.kind = E_NUMBER; e.x = v->x; break;
        case SCENE_VALUE_INTEGER: e.kind = E_INTEGER; e.i = v->i; e.x = (double)v->i; break;
        case SCENE_VALUE_LOGICAL: e.kind = E_LOGICAL; e.b = v->b != 0; break;
        case SCENE_VALUE_STRING:
            e.kind = E_STRING;
            e.tok.kind = T_STRING;
            e.tok.text = v->s ? v->s : "";
            e.tok.len = strlen(e.tok.text);
            break;
        }
        if (i == 0 && e.kind != E_STRING) {
            if (e.kind == E_LOGICAL) snprintf(first, sizeof first, "%s", e.b ? ".true." : ".false.");
            else if (e.kind == E_INTEGER) snprintf(first, sizeof first, "%lld", e.i);
            else scene_format_real(e.x, first);
            e.tok.kind = T_WORD;
            e.tok.text = first;
            e.tok.len = strlen(first);
        }
        el[i] = e;
    }
    /* Reals given to a program are finite numbers or the error of a file's
     * "nan": the same message. */
    for (size_t i = 0; i < n; i++)
        if (el[i].kind == E_NUMBER && !isfinite(el[i].x)) {
            char num[SCENE_REAL_TEXT];
            scene_format_real(el[i].x, num);
            scene_error(sc, 0, scene_var_at((size_t)vi)->group, scene_var_at((size_t)vi)->name,
                        "'%s' is not a finite number", num);
            free(el);
            return sc->n_errors - before;
        }
    parser p = {.sc = sc};
    assign(&p, vi, el, n, 0);
    free(el);
    return sc->n_errors - before;
}
