/* SPDX-License-Identifier: GPL-3.0-or-later */
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
#include <string.h>
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

/* A failure recorded in a taper_error: the status, the field at fault
 * (NULL: none) and a message containing `needle` (NULL: any non-empty). */
#define assert_taper_error(err, status_, field_, needle_)                               \
    do {                                                                                \
        const char *f_ = (field_), *n_ = (needle_);                                     \
        assert_int_equal((err).status, (status_));                                      \
        if (f_ == NULL ? (err).field != NULL                                            \
                       : (err).field == NULL || strcmp((err).field, f_) != 0) {         \
            print_error("field '%s', expected '%s' (message: %s)\n",                    \
                        (err).field ? (err).field : "(null)", f_ ? f_ : "(null)",       \
                        (err).message);                                                 \
            fail();                                                                     \
        }                                                                               \
        assert_true(strlen((err).message) > 0);                                         \
        if (n_ && !strstr((err).message, n_)) {                                         \
            print_error("message '%s' lacks '%s'\n", (err).message, n_);                \
            fail();                                                                     \
        }                                                                               \
    } while (0)

#endif
