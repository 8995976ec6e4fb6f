/*
 * number.c -- %.17g without printf (number.h).
 *
 * For 1e-4 <= |x| < 1e16, where %.17g writes fixed-point digits and where
 * pass times, positions, velocities and masses of the result files lie,
 * the 17 digits come from exact integer arithmetic: x = m 2^e with m < 2^53,
 * so x 10^p = m 10^p 2^e, and with p <= 20 (x >= 1e-4) the product m 10^p
 * is below 2^120 and its quotient and remainder by 2^-e (-e <= 66) are
 * exact in unsigned __int128.  The 17th digit is rounded to nearest, ties
 * to even, as glibc rounds in the default rounding mode.  %g's rules then
 * apply: no exponent for decimal exponents -4..16, trailing zeros and a
 * bare point removed.  Every other x goes to snprintf.
 */
#include "util/number.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static const uint64_t pow10_u64[20] = {
    1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL, 100000000ULL,
    1000000000ULL, 10000000000ULL, 100000000000ULL, 1000000000000ULL, 10000000000000ULL,
    100000000000000ULL, 1000000000000000ULL, 10000000000000000ULL, 100000000000000000ULL,
    1000000000000000000ULL, 10000000000000000000ULL};

#define DIGITS 17
#define LOW_17 10000000000000000ULL   /* 10^16: the smallest 17-digit integer */
#define HIGH_17 100000000000000000ULL /* 10^17 */

#ifndef __SIZEOF_INT128__
/* No 128-bit integers (32-bit targets): printf for every number. */
int number_17g(char buf[NUMBER_17G_SIZE], double x) { return snprintf(buf, NUMBER_17G_SIZE, "%.17g", x); }
#else
int number_17g(char buf[NUMBER_17G_SIZE], double x)
{
    const double a = fabs(x);
    if (!(a >= 1e-4 && a < 1e16)) return snprintf(buf, NUMBER_17G_SIZE, "%.17g", x);

    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    const int biased = (int)(bits >> 52);            /* a is normal: 1e-4 > 2^-1022 */
    const uint64_t m = (bits & ((1ULL << 52) - 1)) | (1ULL << 52);
    const int shift = 1075 - biased;                 /* a = m 2^-shift, -1 <= shift <= 66 */
    /* p: the power of ten that brings a to 17 integer digits; the guess
     * 16 - floor(E log10 2) (E = biased - 1023, 1233 / 4096 ~ log10 2) is
     * off by at most one, which the loop corrects. */
    int p = 16 - (((biased - 1023) * 1233) >> 12);
    unsigned __int128 q, rem = 0, half = 0;
    for (;;) {
        const unsigned __int128 scale =
            p < 20 ? (unsigned __int128)pow10_u64[p] : (unsigned __int128)pow10_u64[19] * pow10_u64[p - 19];
        const unsigned __int128 n = (unsigned __int128)m * scale;
        if (shift > 0) {
            q = n >> shift;
            rem = n & (((unsigned __int128)1 << shift) - 1);
            half = (unsigned __int128)1 << (shift - 1);
        } else {
            q = n << -shift;
        }
        if (q < LOW_17)
            p++;
        else if (q >= HIGH_17)
            p--;
        else
            break;
    }
    uint64_t d = (uint64_t)q;
    if (shift > 0 && (rem > half || (rem == half && (d & 1)))) d++;
    if (d == HIGH_17) d /= 10, p--; /* 99...9.5 rounded up: one digit more */
    const int exp10 = DIGITS - 1 - p; /* the leading digit's power of ten, -4..16 */

    char dig[DIGITS];
    for (int i = DIGITS - 1; i >= 0; i--) dig[i] = (char)('0' + d % 10), d /= 10;
    int nd = DIGITS;
    while (dig[nd - 1] == '0') nd--; /* the leading digit is not 0 */

    char *o = buf;
    if (x < 0) *o++ = '-';
    if (exp10 >= 0) {
        const int whole = exp10 + 1;
        memcpy(o, dig, (size_t)whole);
        o += whole;
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
