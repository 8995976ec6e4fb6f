/*
 * test_util.h -- assertions for doubles.  cmocka 1.1.5's assert_float_equal
 * casts to float (7 digits); these compare in double with a relative
 * tolerance and print both values and the relative difference on failure.
 */
#ifndef TAPER_TEST_UTIL_H
#define TAPER_TEST_UTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

static inline double rel_diff(double a, double b)
{
    double scale = fmax(fabs(a), fabs(b));
    return scale == 0.0 ? 0.0 : fabs(a - b) / scale;
}

/* |a - b| <= rtol * max(|a|, |b|); NaN never passes. */
#define assert_double_rel(a, b, rtol)                                                   \
    do {                                                                                \
        double a_ = (a), b_ = (b), r_ = (rtol);                                         \
        if (!(rel_diff(a_, b_) <= r_)) {                                                \
            print_error("%s = %.17g vs %s = %.17g: relative difference %.3g > %.3g\n",  \
                        #a, a_, #b, b_, rel_diff(a_, b_), r_);                         \
            fail();                                                                     \
        }                                                                               \
    } while (0)

/* |a - b| <= atol. */
#define assert_double_abs(a, b, atol)                                                   \
    do {                                                                                \
        double a_ = (a), b_ = (b), t_ = (atol);                                         \
        if (!(fabs(a_ - b_) <= t_)) {                                                   \
            print_error("%s = %.17g vs %s = %.17g: |difference| %.3g > %.3g\n", #a, a_, \
                        #b, b_, fabs(a_ - b_), t_);                                     \
            fail();                                                                     \
        }                                                                               \
    } while (0)

#endif
