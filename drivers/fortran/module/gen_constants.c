/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * gen_constants.c OUT -- writes the constants of include/taper.h as the
 * Fortran module taper_constants into OUT (taper_constants.f90), which the
 * module taper (taper.f90) uses and re-exports: the version, the status
 * codes, every enum of the header from its X-macro list (TAPER_*_LIST) with
 * its count, the two enums of the table of settings, and the ranges of the
 * settings.  The values are the C compiler's, so the module cannot drift
 * from the header: a value added to a list is a new parameter at the next
 * build.  (A module, not an INCLUDE file: the build recompiles what uses a
 * module when it changes, and tracks no INCLUDE.)
 *
 * A build-time tool of the Fortran binding (compiled for the build machine
 * by meson.build and run there), never installed: it includes taper.h and
 * links nothing.
 */
#include "taper.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Fortran free form allows 132 characters a line; the longest line here is
 * a constant, its value and its name as a comment. */
static void enum_value(FILE *out, const char *constant, long value, const char *name)
{
    fprintf(out, "  integer(c_int), parameter :: %s = %ld  ! \"%s\"\n", constant, value,
            name);
}

static void count(FILE *out, const char *constant, long value)
{
    fprintf(out, "  integer, parameter :: %s = %ld\n", constant, value);
}

/* A double as a Fortran real(c_double) literal that reads back to it. */
static void real_value(FILE *out, const char *kind, const char *constant, double x)
{
    char text[40];
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(text, sizeof text, "%.*g", prec, x);
        if (strtod(text, NULL) == x) break;
    }
    const char *point = strpbrk(text, ".e") ? "" : ".0";
    fprintf(out, "  real(%s), parameter :: %s = %s%s_%s\n", kind, constant, text, point,
            kind);
}

/* X(constant, "name") and X(constant, "name", third column). */
#define VALUE(constant, name) enum_value(out, #constant, (long)(constant), name);
#define VALUE3(constant, name, third) VALUE(constant, name)
/* One X-macro list of the header, in the order of its values. */
#define LIST(list, x)                                                                            \
    do {                                                                                         \
        fprintf(out, "\n  ! %s\n", #list);                                                       \
        list(x)                                                                                  \
    } while (0)
#define COUNT(n_constant) count(out, #n_constant, (long)(n_constant))

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: gen_constants OUT\n");
        return 2;
    }
    FILE *out = fopen(argv[1], "w");
    if (!out) {
        perror(argv[1]);
        return 1;
    }
    fprintf(out, "! %s -- the constants of taper.h, written at build time by\n"
                 "! drivers/fortran/module/gen_constants.c from the header's own lists: do not\n"
                 "! edit.  The module taper (taper.f90) re-exports them: `use taper`.\n"
                 "module taper_constants\n"
                 "  use, intrinsic :: iso_c_binding, only: c_int, c_size_t, c_double\n"
                 "  implicit none\n"
                 "  private :: c_int, c_size_t, c_double\n",
            strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1]);

    fprintf(out, "\n  ! version\n");
    fprintf(out, "  integer, parameter :: TAPER_VERSION_MAJOR = %d, TAPER_VERSION_MINOR = %d, "
                 "&\n       TAPER_VERSION_PATCH = %d\n",
            TAPER_VERSION_MAJOR, TAPER_VERSION_MINOR, TAPER_VERSION_PATCH);
    fprintf(out, "  character(len=*), parameter :: TAPER_VERSION_STRING = \"%s\"\n",
            TAPER_VERSION_STRING);
    fprintf(out, "  integer, parameter :: TAPER_MESSAGE_SIZE = %d\n", TAPER_MESSAGE_SIZE);

    LIST(TAPER_STATUS_LIST, VALUE3);
    LIST(TAPER_PROFILE_LIST, VALUE);
    COUNT(TAPER_N_PROFILES);
    LIST(TAPER_DISORDER_LIST, VALUE);
    COUNT(TAPER_N_DISORDERS);
    LIST(TAPER_END_LIST, VALUE);
    COUNT(TAPER_N_ENDS);
    LIST(TAPER_BOUNDARY_LIST, VALUE);
    COUNT(TAPER_N_BOUNDARIES);
    LIST(TAPER_DIMENSION_LIST, VALUE3);
    COUNT(TAPER_N_DIMENSIONS);
    LIST(TAPER_THEORY_QUANTITY_LIST, VALUE3);
    COUNT(TAPER_N_THEORY_QUANTITIES);
    LIST(TAPER_METHOD_LIST, VALUE);
    COUNT(TAPER_N_METHODS);
    LIST(TAPER_OBSERVABLE_LIST, VALUE3);
    COUNT(TAPER_N_OBSERVABLES);
    LIST(TAPER_STATISTIC_LIST, VALUE3);
    COUNT(TAPER_N_STATISTICS);
    LIST(TAPER_LAW_LIST, VALUE);
    COUNT(TAPER_N_LAWS);
    LIST(TAPER_FIT_MODEL_LIST, VALUE);
    COUNT(TAPER_N_FIT_MODELS);

    /* The table of settings' own enums are not lists: each by its name. */
    fprintf(out, "\n  ! taper_setting_type, taper_setting_object (the table of settings)\n");
    enum_value(out, "TAPER_SETTING_REAL", TAPER_SETTING_REAL, "real");
    enum_value(out, "TAPER_SETTING_INTEGER", TAPER_SETTING_INTEGER, "integer");
    enum_value(out, "TAPER_SETTING_BOOLEAN", TAPER_SETTING_BOOLEAN, "boolean");
    enum_value(out, "TAPER_SETTING_CHOICE", TAPER_SETTING_CHOICE, "choice");
    enum_value(out, "TAPER_SETTING_LIST", TAPER_SETTING_LIST, "list");
    enum_value(out, "TAPER_SETTING_CHAIN", TAPER_SETTING_CHAIN, "chain");
    enum_value(out, "TAPER_SETTING_SOLVER", TAPER_SETTING_SOLVER, "solver");

    fprintf(out, "\n  ! ranges of the settings (the table of settings states them too)\n");
    fprintf(out, "  integer(c_size_t), parameter :: TAPER_N_GRANULES_MIN = %d, "
                 "TAPER_N_GRANULES_MAX = %d\n",
            TAPER_N_GRANULES_MIN, TAPER_N_GRANULES_MAX);
    real_value(out, "c_double", "TAPER_S_MAX", TAPER_S_MAX);
    real_value(out, "c_double", "TAPER_Q_MAX", TAPER_Q_MAX);
    real_value(out, "c_double", "TAPER_EXPONENT_MIN", TAPER_EXPONENT_MIN);
    real_value(out, "c_double", "TAPER_EXPONENT_MAX", TAPER_EXPONENT_MAX);
    real_value(out, "c_double", "TAPER_RTOL_MIN", TAPER_RTOL_MIN);
    real_value(out, "c_double", "TAPER_RTOL_MAX", TAPER_RTOL_MAX);
    real_value(out, "c_double", "TAPER_ATOL_MAX", TAPER_ATOL_MAX);
    fprintf(out, "  integer(c_int), parameter :: TAPER_MAX_ORDER_ADAMS = %d, "
                 "TAPER_MAX_ORDER_BDF = %d\n",
            TAPER_MAX_ORDER_ADAMS, TAPER_MAX_ORDER_BDF);

    fprintf(out, "end module taper_constants\n");
    if (fclose(out) != 0) {
        perror(argv[1]);
        remove(argv[1]);
        return 1;
    }
    return 0;
}
