/*
 * test_number.c -- number_17g (drivers/taper/util/number.c) writes every
 * double with the same characters as printf's "%.17g": the result files
 * must not change by a byte when their numbers are written without printf.
 * Compared number by number with snprintf over random bit patterns (every
 * class of double), the fixed-point range the fast path covers, its edges
 * (neighbours of powers of ten, where the digit count changes, and of 1e-4
 * and 1e16, where %g changes style), integers, and exact ties of the 17th
 * digit (rounded to even).
 */
#include "util/number.h"
#include "test_util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static long mismatches;

static void same_as_printf(double x)
{
    char ours[NUMBER_17G_SIZE], theirs[64];
    int len = number_17g(ours, x);
    int want = snprintf(theirs, sizeof theirs, "%.17g", x);
    if (len != want || strcmp(ours, theirs) != 0) {
        if (mismatches < 10) print_error("%a: number_17g '%s' (%d), printf '%s' (%d)\n", x, ours, len, theirs, want);
        mismatches++;
    }
}

static void same_with_neighbours(double x)
{
    same_as_printf(x);
    same_as_printf(nextafter(x, 0.0));
    same_as_printf(nextafter(x, INFINITY));
    same_as_printf(-x);
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
    for (long i = 0; i < 300000; i++) {
        uint64_t u = next_random();
        same_as_printf(from_bits(u)); /* any class: NaN, inf, subnormal, huge */
        /* binary exponents -15..54: the fast path's range and beyond */
        uint64_t biased = 1023 - 15 + next_random() % 70;
        same_with_neighbours(from_bits((u & ((1ULL << 52) - 1)) | (biased << 52)));
        /* short decimals, as times and positions often are */
        double decimal = (double)(next_random() % 100000000000000000ULL) / pow(10.0, (double)(next_random() % 22));
        same_with_neighbours(decimal);
        same_as_printf((double)(next_random() % (1ULL << 54)));
    }
    assert_true(mismatches == 0);
}

static void edges(void **unused)
{
    (void)unused;
    mismatches = 0;
    for (int e = -30; e <= 30; e++) {
        double p = pow(10.0, e), below = p, above = p;
        same_with_neighbours(p);
        for (int k = 0; k < 100; k++) {
            below = nextafter(below, 0.0);
            above = nextafter(above, INFINITY);
            same_as_printf(below);
            same_as_printf(above);
        }
        same_with_neighbours(9.9999999999999999 * p); /* rounds up to a new leading digit */
    }
    static const double special[] = {0.0, -0.0, 1.0, 0.5, 0.1, 1e-4, 1e16, 9007199254740993.0, 4503599627370495.5,
                                     1.2307855759017723, 593.86847448324681, 1e300, 5e-324, 2.2250738585072014e-308};
    for (size_t i = 0; i < sizeof special / sizeof *special; i++) same_with_neighbours(special[i]);
    assert_true(mismatches == 0);
}

/* An exact tie of the 17th digit: x has 18 significant digits ending in 5
 * (2^50 <= x < 2^51: steps of 0.25).  Rounded to even, as glibc does. */
static void ties_to_even(void **unused)
{
    (void)unused;
    char buf[NUMBER_17G_SIZE];
    number_17g(buf, 1234567890123456.25);
    assert_string_equal(buf, "1234567890123456.2");
    number_17g(buf, 1234567890123456.75);
    assert_string_equal(buf, "1234567890123456.8");
    number_17g(buf, -1234567890123457.25);
    assert_string_equal(buf, "-1234567890123457.2");
    mismatches = 0;
    for (long i = 0; i < 100000; i++) {
        double whole = (double)((1ULL << 50) + next_random() % (1ULL << 50));
        same_as_printf(whole + 0.25);
        same_as_printf(whole + 0.75);
    }
    assert_true(mismatches == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(random_doubles),
        cmocka_unit_test(edges),
        cmocka_unit_test(ties_to_even),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
