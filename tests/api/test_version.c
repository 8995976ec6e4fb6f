/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_version.c -- the version macros of taper.h, the version of the
 * loaded library (taper_version()) and the project version of meson.build
 * (passed as TAPER_MESON_VERSION) all agree.
 */
#include "taper.h"

#include <stdio.h>
#include <string.h>

#define STR_(x) #x
#define STR(x) STR_(x)

int main(void)
{
    const char *macros = STR(TAPER_VERSION_MAJOR) "." STR(TAPER_VERSION_MINOR) "." STR(
        TAPER_VERSION_PATCH);
    const char *runtime = taper_version();
    int fails = 0;
    if (strcmp(macros, TAPER_VERSION_STRING) != 0) {
        fprintf(stderr, "MAJOR.MINOR.PATCH = %s but TAPER_VERSION_STRING = %s\n", macros,
                TAPER_VERSION_STRING);
        fails++;
    }
    if (!runtime || strcmp(runtime, TAPER_VERSION_STRING) != 0) {
        fprintf(stderr, "taper_version() = %s but the header says %s\n",
                runtime ? runtime : "(null)", TAPER_VERSION_STRING);
        fails++;
    }
    if (strcmp(TAPER_MESON_VERSION, TAPER_VERSION_STRING) != 0) {
        fprintf(stderr, "meson.build project version %s but the header says %s\n",
                TAPER_MESON_VERSION, TAPER_VERSION_STRING);
        fails++;
    }
    if (!fails) printf("version %s: header macros, taper_version() and meson.build agree\n", runtime);
    return fails != 0;
}
