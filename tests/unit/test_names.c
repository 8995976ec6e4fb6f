/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_names.c -- the names of the enums that had none before
 * (taper_observable_name, taper_theory_quantity_name, taper_law_name):
 * each list is the documented one in enum order (the observables are
 * granules.tsv's column names), the names are distinct, a walk
 * `for (i = 0; name(i); i++)` stops exactly at TAPER_N_*, and values
 * outside the enum (negative ones included) give NULL.  The bindings build
 * their name tuples from these walks (suite 'library').
 */
#include "test_util.h"

#include "taper.h"

typedef const char *(*name_fn)(int);

static const char *observable_i(int i) { return taper_observable_name((taper_observable)i); }
static const char *quantity_i(int i) { return taper_theory_quantity_name((taper_theory_quantity)i); }
static const char *law_i(int i) { return taper_law_name((taper_law)i); }

/* Walks name(0), name(1), ... until NULL and compares with `want` (n
 * names), then checks the round trip (each name found back at its own
 * index, so no two are equal) and NULL outside [0, n). */
static void check_walk(name_fn name, const char *const *want, int n)
{
    int i;
    for (i = 0; name(i); i++) {
        assert_true(i < n);
        assert_string_equal(name(i), want[i]);
    }
    assert_int_equal(i, n);
    for (i = 0; i < n; i++) {
        int found = -1;
        for (int j = 0; name(j); j++)
            if (strcmp(name(j), name(i)) == 0 && found < 0) found = j;
        assert_int_equal(found, i);
        assert_ptr_equal(name(i), name(i)); /* static storage */
    }
    assert_null(name(n));
    assert_null(name(n + 1));
    assert_null(name(-1));
    assert_null(name(-1000));
    assert_null(name(1 << 30));
}

static void test_observable_names(void **state)
{
    (void)state;
    static const char *const want[] = {"t_pass", "T_res", "v_peak", "t_peak", "X_pass"};
    check_walk(observable_i, want, TAPER_N_OBSERVABLES);
    assert_int_equal(sizeof want / sizeof want[0], TAPER_N_OBSERVABLES);
    assert_string_equal(taper_observable_name(TAPER_X_PASS), "X_pass");
}

static void test_theory_quantity_names(void **state)
{
    (void)state;
    static const char *const want[] = {"v", "mu", "T", "t"};
    check_walk(quantity_i, want, TAPER_N_THEORY_QUANTITIES);
    assert_int_equal(sizeof want / sizeof want[0], TAPER_N_THEORY_QUANTITIES);
    assert_string_equal(taper_theory_quantity_name(TAPER_THEORY_T_RES), "T");
}

static void test_law_names(void **state)
{
    (void)state;
    static const char *const want[] = {"v_of_k", "t_res_of_k", "t_of_k", "k_of_t", "v_of_t",
                                       "x_of_t", "c_of_t", "fwd_v_of_k", "fwd_t_of_k",
                                       "fwd_v_of_t"};
    check_walk(law_i, want, TAPER_N_LAWS);
    assert_int_equal(sizeof want / sizeof want[0], TAPER_N_LAWS);
    assert_string_equal(taper_law_name(TAPER_LAW_FWD_V_OF_T), "fwd_v_of_t");
    /* Every named law has an exponent, and the first value past the names
     * has none: the two lists end together. */
    for (int i = 0; taper_law_name((taper_law)i); i++)
        assert_true(isfinite(taper_asymptotic_exponent((taper_law)i, 2.5)));
    assert_true(isnan(taper_asymptotic_exponent((taper_law)TAPER_N_LAWS, 2.5)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_observable_names),
        cmocka_unit_test(test_theory_quantity_names),
        cmocka_unit_test(test_law_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
