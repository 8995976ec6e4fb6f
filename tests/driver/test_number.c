/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_number.c -- number_shortest (drivers/scenes/util/number.c) writes
 * every double as the shortest text that reads back to it, the nearest of
 * that length, in %.17g's style.  Checked number by number against a slow
 * reference (printf with growing precision, strtod) over random bit
 * patterns (every class of double), the fixed-point range of the fast path,
 * its edges (neighbours of powers of ten, powers of two where the rounding
 * interval is lopsided, 1e-4 and 1e16 where the style changes), integers,
 * and decimal fractions that %.17g writes long (0.03, 2e-4).
 */
#include "util/number.h"
#include "test_util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static long mismatches;

/* The reference: the fewest significant digits, in scientific notation,
 * that strtod reads back; among the candidates of that length (the two
 * neighbours of the %.*e rounding), the nearest to x. */
static int reference_digits(double x, char digits[32], int *exp10)
{
    char buf[64];
    for (int prec = 0; prec < 17; prec++) {
        snprintf(buf, sizeof buf, "%.*e", prec, x);
        if (strtod(buf, NULL) == x) {
            /* digits without the point and the sign */
            int n = 0;
            for (const char *c = buf; *c && *c != 'e'; c++)
                if (*c >= '0' && *c <= '9') digits[n++] = *c;
            digits[n] = '\0';
            *exp10 = atoi(strchr(buf, 'e') + 1);
            return n;
        }
    }
    return 0;
}

static void check(double x)
{
    char ours[NUMBER_SIZE];
    int len = number_shortest(ours, x);
    if (len != (int)strlen(ours) || len >= NUMBER_SIZE) goto bad;
    if (!isfinite(x)) {
        char theirs[64];
        snprintf(theirs, sizeof theirs, "%g", x);
        if (strcmp(ours, theirs) != 0) goto bad;
        return;
    }
    /* It reads back, bit for bit. */
    double back = strtod(ours, NULL);
    if (memcmp(&back, &x, sizeof x) != 0 && !(x == 0 && back == 0)) goto bad;
    /* Its significant digits are the reference's (no shorter text reads
     * back, and of that length the nearest). */
    char want[32], got[32];
    int e;
    reference_digits(x, want, &e);
    int n = 0;
    const char *c = ours;
    if (*c == '-') c++;
    while (*c == '0' || *c == '.') c++;
    for (; *c && *c != 'e'; c++)
        if (*c >= '0' && *c <= '9') got[n++] = *c;
    while (n > 1 && got[n - 1] == '0' && strchr(ours, '.') == NULL && strchr(ours, 'e') == NULL)
        n--; /* an integer's trailing zeros are not significant */
    got[n] = '\0';
    size_t wn = strlen(want);
    while (wn > 1 && want[wn - 1] == '0') want[--wn] = '\0';
    if (x != 0 && strcmp(got, want) != 0) goto bad;
    /* %.17g's style: an exponent exactly when %.17g writes one. */
    char g17[64];
    snprintf(g17, sizeof g17, "%.17g", x);
    if ((strchr(ours, 'e') != NULL) != (strchr(g17, 'e') != NULL) && fabs(x) < 1e16) goto bad;
    return;
bad:
    if (mismatches < 10) {
        char want17[64];
        snprintf(want17, sizeof want17, "%.17g", x);
        print_error("%a (%s): number_shortest '%s'\n", x, want17, ours);
    }
    mismatches++;
}

static void with_neighbours(double x)
{
    check(x);
    check(nextafter(x, 0.0));
    check(nextafter(x, INFINITY));
    check(-x);
}

/* xorshift64: a fixed sequence, so that a failure repeats. */
static uint64_t state = 88172645463325252ULL;
static uint64_t next_random(void)
{
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
}

static double from_bits(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static void random_doubles(void **unused)
{
    (void)unused;
    mismatches = 0;
    for (long i = 0; i < 60000; i++) check(from_bits(next_random()));
    assert_int_equal(mismatches, 0);
}

/* The fast path's range, log-uniform: where result files' numbers lie. */
static void fast_range(void **unused)
{
    (void)unused;
    mismatches = 0;
    for (long i = 0; i < 100000; i++) {
        double u = (double)(next_random() >> 11) / 9007199254740992.0;
        check(pow(10.0, -4.0 + 20.0 * u));
    }
    assert_int_equal(mismatches, 0);
}

static void edges(void **unused)
{
    (void)unused;
    mismatches = 0;
    for (int e = -6; e <= 17; e++) with_neighbours(pow(10.0, e));
    for (int e = -20; e <= 60; e++) with_neighbours(ldexp(1.0, e)); /* lopsided intervals */
    for (long k = 1; k <= 100000; k++) check((double)k);
    const double specials[] = {0.0, -0.0, NAN, INFINITY, -INFINITY, 1e-4, 9.9999999999999991e15,
                               1e16, 5e-324, 1.7976931348623157e308, 2.0300000000000002};
    for (size_t i = 0; i < sizeof specials / sizeof specials[0]; i++) check(specials[i]);
    for (int k = 1; k < 1000; k++) with_neighbours(k / 1000.0);
    assert_int_equal(mismatches, 0);
}

/* The examples: what %.17g writes long, in full and short. */
static void examples(void **unused)
{
    (void)unused;
    const struct {
        double x;
        const char *text;
    } cases[] = {{0.03, "0.03"}, {1.03, "1.03"}, {2e-4, "0.0002"}, {1e-5, "1e-05"},
                 {0.1 + 0.2, "0.30000000000000004"}, {100, "100"}, {1234567890123456.0,
                 "1234567890123456"}, {-2.5, "-2.5"}, {1e20, "1e+20"}, {0, "0"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char buf[NUMBER_SIZE];
        number_shortest(buf, cases[i].x);
        assert_string_equal(buf, cases[i].text);
    }
}

/* `test_number` runs the examples, the edges and the fast path's range;
 * `test_number --long` the 60000 random bit patterns against the slow
 * reference (test number_long, in the suite 'slow' too:
 * tests/driver/meson.build). */
int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(examples),
        cmocka_unit_test(edges),
        cmocka_unit_test(fast_range),
    };
    const struct CMUnitTest long_tests[] = {
        cmocka_unit_test(random_doubles),
    };
    if (argc == 2 && strcmp(argv[1], "--long") == 0)
        return cmocka_run_group_tests_name("number_long", long_tests, NULL, NULL);
    if (argc != 1) {
        print_error("usage: test_number [--long]\n");
        return 2;
    }
    return cmocka_run_group_tests_name("number", tests, NULL, NULL);
}
