/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * number.c -- the shortest text that reads back to the same double
 * (number.h).
 *
 * Shortest: the fewest significant digits whose decimal number lies in the
 * double's rounding interval, so that strtod gives the double back; among
 * those, the nearest to it (as Python's repr and Steele and White's
 * algorithm choose).  For 1e-4 <= |x| < 1e16, where pass times, positions,
 * velocities and masses of the rescaled result files lie, this is exact
 * integer arithmetic: x = m 2^-s with m < 2^53, so x 10^p = m 10^p 2^-s,
 * and with p <= 20 (x >= 1e-4) every product below is under 2^126 and
 * exact in unsigned __int128.  The digits are those of x rounded to n
 * significant digits (to nearest, ties to even) for the smallest n whose
 * result lies in the rounding interval: the nearest n-digit number is in
 * the interval if any is.  The interval is [x - u/2, x + u/2] around
 * x = m u (u = 2^-s), closed when m is even (strtod rounds a tie to the
 * even mantissa), its lower half u/4 when m = 2^52 (the double below has
 * the next smaller exponent).  Every other x (and NaN, the infinities)
 * goes to snprintf, the precision raised until strtod reads it back.
 */
#include "util/number.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DIGITS 17
#define LOW_17 10000000000000000ULL   /* 10^16: the smallest 17-digit integer */
#define HIGH_17 100000000000000000ULL /* 10^17 */

/* %g's text with the fewest digits that reads back: the slow path.  A
 * precision that reads back makes every higher one read back too wherever
 * the rounding interval is symmetric about x (each added digit brings the
 * nearest decimal no farther from x), so the least one is found by
 * bisection, four or five printf and strtod instead of up to seventeen
 * (sensors.tsv, whose forces and small displacements lie below 1e-4, was
 * written at 14 MB/s).  At a power of two the interval's lower half is
 * half as wide, a closer decimal may fall outside it: there, and for zero,
 * NaN and the infinities, the precisions are tried in turn. */
static int shortest_printf(char buf[NUMBER_SIZE], double x)
{
    int len = 0;
    const double a = fabs(x);
    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    if (isfinite(x) && a > 0.0 && (bits & ((1ULL << 52) - 1)) != 0) {
        int lo = 1, hi = DIGITS; /* DIGITS always reads back */
        while (lo < hi) {
            const int mid = (lo + hi) / 2;
            snprintf(buf, NUMBER_SIZE, "%.*g", mid, x);
            if (strtod(buf, NULL) == x)
                hi = mid;
            else
                lo = mid + 1;
        }
        return snprintf(buf, NUMBER_SIZE, "%.*g", lo, x);
    }
    for (int prec = 1; prec <= DIGITS; prec++) {
        len = snprintf(buf, NUMBER_SIZE, "%.*g", prec, x);
        if (!isfinite(x) || strtod(buf, NULL) == x) break;
    }
    return len;
}

#ifndef __SIZEOF_INT128__
/* No 128-bit integers (32-bit targets): printf for every number. */
int number_shortest(char buf[NUMBER_SIZE], double x) { return shortest_printf(buf, x); }
#else
typedef unsigned __int128 u128;

static const uint64_t pow10_u64[20] = {
    1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL, 100000000ULL,
    1000000000ULL, 10000000000ULL, 100000000000ULL, 1000000000000ULL, 10000000000000ULL,
    100000000000000ULL, 1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL,
    1000000000000000000ULL, 10000000000000000000ULL};

static u128 pow10_u128(int p)
{
    return p < 20 ? (u128)pow10_u64[p] : (u128)pow10_u64[19] * pow10_u64[p - 19];
}

/* a 2^k for k >= 0, a / 2^-k for k < 0 (exact where used: k >= -1 and a
 * even, or k >= 0). */
static u128 times_pow2(u128 a, int k) { return k >= 0 ? a << k : a >> -k; }

int number_shortest(char buf[NUMBER_SIZE], double x)
{
    const double a = fabs(x);
    if (!(a >= 1e-4 && a < 1e16)) return shortest_printf(buf, x);

    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    const int biased = (int)(bits >> 52);            /* a is normal: 1e-4 > 2^-1022 */
    const uint64_t m = (bits & ((1ULL << 52) - 1)) | (1ULL << 52);
    const int s = 1075 - biased;                     /* a = m 2^-s, -1 <= s <= 66 */
    /* p: the power of ten that brings a to 17 integer digits, q = floor(a
     * 10^p) in [10^16, 10^17); the guess 16 - floor(E log10 2) (E = biased
     * - 1023, 1233 / 4096 ~ log10 2) is off by at most one. */
    int p = 16 - (((biased - 1023) * 1233) >> 12);
    u128 n4, q;
    for (;;) {
        n4 = (u128)m * pow10_u128(p) << 2; /* 4 a 10^p 2^s, exact: below 2^123 */
        q = times_pow2(n4, -(s + 2));      /* floor(a 10^p) */
        if (q < LOW_17)
            p++;
        else if (q >= HIGH_17)
            p--;
        else
            break;
    }
    /* In units of 2^-(s+2) 10^-p: x is n4 = q 2^(s+2) + f, the interval's
     * half-widths are 2 10^p (above) and 2 10^p or 10^p (below, m = 2^52). */
    const int sh = s + 2;
    const u128 f = n4 - (q << sh);
    const u128 up = (u128)2 * pow10_u128(p);
    const u128 down = m == (1ULL << 52) ? pow10_u128(p) : up;
    const int closed = (m & 1) == 0;
    const uint64_t q64 = (uint64_t)q;
    /* The fewest digits whose nearest candidate lies in the interval: more
     * digits never lose (an nd-digit number is an (nd+1)-digit one too), so
     * bisect; 17 always do. */
    int lo_nd = 1, hi_nd = DIGITS;
    /* 17 digits: q rounded to nearest, ties to even */
    uint64_t d = q64 + ((f << 1) > ((u128)1 << sh) || ((f << 1) == ((u128)1 << sh) && (q64 & 1)));
    while (lo_nd < hi_nd) {
        const int mid = (lo_nd + hi_nd) / 2;
        const uint64_t unit = pow10_u64[DIGITS - mid];  /* one unit of digit mid, in q's */
        uint64_t c = q64 / unit;
        const u128 unit4 = (u128)unit << sh;
        u128 rem = ((u128)(q64 % unit) << sh) + f;      /* x - c unit, in n4's units */
        int above = 0;
        if ((rem << 1) > unit4 || ((rem << 1) == unit4 && (c & 1))) c++, rem = unit4 - rem, above = 1;
        const u128 bound = above ? up : down;
        if (rem < bound || (rem == bound && closed)) {
            hi_nd = mid;
            d = c;
        } else {
            lo_nd = mid + 1;
        }
    }
    int nd = hi_nd;
    /* d has nd digits, or nd + 1 when rounding carried (9.99 -> 10.0): then
     * one digit fewer of trailing zeros follows below. */
    int exp10 = DIGITS - 1 - p;                    /* the leading digit's power of ten */
    if (d >= pow10_u64[nd]) d /= 10, exp10++;      /* a carry: 9.96 -> 10.0 */
    char dig[DIGITS + 1];
    for (int i = nd - 1; i >= 0; i--) dig[i] = (char)('0' + d % 10), d /= 10;
    while (nd > 1 && dig[nd - 1] == '0') nd--;

    char *o = buf;
    if (x < 0) *o++ = '-';
    if (exp10 >= 16) { /* 9.9999999999999999e15 rounded up: %g's exponent style */
        return (int)(o - buf) + snprintf(o, NUMBER_SIZE - 1, "%c%s%.*se+%d", dig[0],
                                         nd > 1 ? "." : "", nd - 1, dig + 1, exp10);
    }
    if (exp10 >= 0) {
        const int whole = exp10 + 1;
        for (int i = 0; i < whole; i++) *o++ = i < nd ? dig[i] : '0';
        if (nd > whole) {
            *o++ = '.';
            memcpy(o, dig + whole, (size_t)(nd - whole));
            o += nd - whole;
        }
    } else {
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -exp10 - 1; i++) *o++ = '0';
        memcpy(o, dig, (size_t)nd);
        o += nd;
    }
    *o = '\0';
    return (int)(o - buf);
}
#endif
