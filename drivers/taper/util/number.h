/*
 * number.h -- a double as printf's "%.17g" writes it, without printf.
 *
 * The result files hold every number to the last bit (%.17g: 17
 * significant digits read back to the same double).  glibc's printf
 * converts through multiprecision arithmetic, about 250 ns a number:
 * 5-8 % of a default monodisperse run of 10^5 granules went to writing
 * granules.tsv (docs/benchmarks.md, "Goal benchmark").  number_17g gives
 * the same bytes in ~30 ns for the numbers result files hold.
 */
#ifndef TAPER_NUMBER_H
#define TAPER_NUMBER_H

/* Enough for any %.17g of a double: "-1.2345678901234567e-308" and the NUL. */
#define NUMBER_17G_SIZE 32

/* Writes x as snprintf(buf, NUMBER_17G_SIZE, "%.17g", x) does in the "C"
 * locale (the decimal point is always '.'), the NUL included; returns the
 * length.  Exact: the same characters for every double, NaN and infinities
 * included (tests/driver/test_number.c compares the two). */
int number_17g(char buf[NUMBER_17G_SIZE], double x);

#endif
