/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * number.h -- a double as the shortest text that reads back to it.
 *
 * The result files hold every number to the last bit, and no digit more:
 * 0.03, not %.17g's 0.029999999999999999 (strtod reads either back to the
 * same double).  The style is %.17g's: fixed-point for decimal exponents
 * -4 to 15, an exponent otherwise.  glibc's printf converts through
 * multiprecision arithmetic, about 250 ns a number (5-8 % of a default
 * monodisperse run of 10^5 granules went to writing granules.tsv,
 * docs/benchmarks.md); number_shortest uses exact integer arithmetic for
 * the numbers rescaled result files hold.
 */
#ifndef TAPER_NUMBER_H
#define TAPER_NUMBER_H

/* Enough for any double's text: "-1.2345678901234567e-308" and the NUL. */
#define NUMBER_SIZE 32

/* Writes the shortest text of x that strtod reads back to x (among texts
 * of that length, the nearest to x), the NUL included, in the "C" locale;
 * returns the length.  NaN and the infinities as printf writes them
 * ("nan", "inf", "-inf").  tests/driver/test_number.c checks it against a
 * reference search with printf and strtod. */
int number_shortest(char buf[NUMBER_SIZE], double x);

#endif
