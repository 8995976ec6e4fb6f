/*
 * scene_dump.c SCENE.nml -- the resolved values of a scene as read by our C
 * parser (scene.c), one variable per line in table order, in the canonical
 * form that src/bindings/fortran/taper_nml.f90 --dump prints from gfortran's own
 * namelist READ, so that tests/bindings/scene_agree.sh can compare the two readers:
 *
 *     group.name = VALUE
 *
 * strings without trailing blanks (a Fortran character variable cannot tell
 * them apart), integers in decimal, logicals T/F, reals (and each element of
 * a list) as the 16 hex digits of their IEEE bits, preceded by the number of
 * elements for lists and sweeps; a real without a default that the file
 * leaves out prints nothing after " =".  Bits, not decimal text: the two
 * readers must agree on the double, not on a way of printing it.
 *
 * Every variable of the table is printed, in every group (&chain, &solver,
 * &output, &fit, &table, &figure), so that a variable -- or a group -- added
 * to the table without taper_nml.f90 learning it fails the comparison.
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
        case SCENE_INTEGER: printf(" %lld", scene_var_integer(sc, i)); break;
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
