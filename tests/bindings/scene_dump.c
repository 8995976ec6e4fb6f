/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_dump.c SCENE.nml -- the resolved values of a scene as read by our C
 * parser (scene.c), one variable per line in table order, in the canonical
 * form that drivers/fortran/taper_nml.f90 --dump prints from gfortran's own
 * namelist READ, so that tests/bindings/scene_agree.sh can compare the two readers:
 *
 *     group.name = VALUE
 *
 * strings and choices without trailing blanks (a Fortran character variable
 * cannot tell them apart), integers in decimal, logicals T/F, reals as the
 * 16 hex digits of their IEEE bits.  A variable that takes a list (a list,
 * or a real or an integer that a list sweeps) prints the number of its
 * values, then each; a real without a default that the file leaves out
 * prints nothing after " =" (a sweepable one: 0 values).  Bits, not decimal
 * text: the two readers must agree on the double, not on a way of printing
 * it.
 *
 * Every variable of the table is printed, in every group, so that the two
 * readers are compared on all of them (taper_nml's namelists are generated
 * from the same table: a variable it did not learn would be missing here).
 */
#include "scene/scene.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

static void print_bits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    printf(" %016" PRIX64, u);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: scene_dump SCENE.nml\n");
        return 2;
    }
    scene *sc = scene_new(argv[1]);
    if (!sc) return 1;
    if (scene_load(sc) != 0 || scene_validate(sc) != 0) {
        scene_print_diags(sc, stderr);
        scene_free(sc);
        return 2;
    }
    for (size_t i = 0; i < scene_var_count(); i++) {
        printf("%s.%s =", scene_var_group(i), scene_var_name(i));
        switch (scene_var_type(i)) {
        case SCENE_STRING:
        case SCENE_CHOICE: {
            const char *str = scene_var_text(sc, i);
            size_t n = strlen(str);
            while (n > 0 && str[n - 1] == ' ') n--;
            printf(" %.*s", (int)n, str);
            break;
        }
        case SCENE_INTEGER: {
            size_t n = 0;
            const double *x = scene_var_reals(sc, i, &n); /* a sweep's values */
            if (!scene_var_takes_list(i))
                printf(" %lld", scene_var_integer(sc, i));
            else if (n == 0)
                printf(" 1 %lld", scene_var_integer(sc, i));
            else
                printf(" %zu", n);
            for (size_t k = 0; k < n; k++) printf(" %lld", (long long)x[k]);
            break;
        }
        case SCENE_LOGICAL: printf(" %c", scene_var_integer(sc, i) ? 'T' : 'F'); break;
        case SCENE_REAL:
        case SCENE_REAL_LIST: {
            size_t n = 0;
            const double *x = scene_var_reals(sc, i, &n);
            if (scene_var_type(i) == SCENE_REAL_LIST || scene_var_takes_list(i)) printf(" %zu", n);
            for (size_t k = 0; k < n; k++) print_bits(x[k]);
            break;
        }
        }
        printf("\n");
    }
    scene_free(sc);
    return 0;
}
