/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_settings.c -- the table of settings through the public API: every
 * row is well formed, its default is what a fresh spec holds and what a
 * NULL spec reads, its bounds are accepted and the values just beyond them
 * refused with a message that states both bounds and why, by name as by
 * the typed setters; choices by name and by index; lists; "did you mean".
 */
#include "taper.h"
#include "test_util.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const groups[] = {"chain", "ends", "striker", "losses", "solver", NULL};

static int in_list(const char *name, const char *const *list)
{
    for (; *list; list++)
        if (strcmp(*list, name) == 0) return 1;
    return 0;
}

/* Set `value` by name on the row's spec. */
static taper_status set(taper_chain_spec *c, taper_solver_spec *s, const taper_setting *row,
                        double value, taper_error *err)
{
    return row->object == TAPER_SETTING_CHAIN ? taper_chain_spec_set_option(c, row->name, value, err)
                                              : taper_solver_spec_set_option(s, row->name, value, err);
}

static double get(const taper_chain_spec *c, const taper_solver_spec *s, const taper_setting *row)
{
    return row->object == TAPER_SETTING_CHAIN ? taper_chain_spec_option(c, row->name)
                                              : taper_solver_spec_option(s, row->name);
}

/* Every row: a unique name, a known group, a description, a default in its
 * range, which a fresh spec and a NULL spec both read. */
static void test_rows(void **state)
{
    (void)state;
    taper_chain_spec *c = taper_chain_spec_alloc(NULL);
    taper_solver_spec *s = taper_solver_spec_alloc(NULL);
    size_t n = taper_setting_count();
    assert_true(n >= 30);
    assert_null(taper_setting_at(n));
    for (size_t i = 0; i < n; i++) {
        const taper_setting *row = taper_setting_at(i);
        assert_non_null(row);
        assert_true(in_list(row->group, groups));
        assert_true(strlen(row->description) > 10);
        assert_non_null(row->bounds_reason);
        assert_non_null(taper_dimension_unit(row->dimension));
        assert_ptr_equal(taper_setting_find(row->name, NULL), row);
        for (size_t j = 0; j < i; j++) assert_string_not_equal(taper_setting_at(j)->name, row->name);
        if (row->type == TAPER_SETTING_LIST) {
            size_t len = 9;
            assert_null(taper_chain_spec_option_list(c, row->name, &len));
            assert_int_equal(len, 0);
            continue;
        }
        if (row->type == TAPER_SETTING_CHOICE) assert_non_null(row->choices[0]);
        double d = row->default_value;
        assert_true(d == get(c, s, row));
        assert_true(d == get(NULL, NULL, row));
        taper_error err;
        assert_int_equal(set(c, s, row, d, &err), TAPER_OK);
    }
    /* Rows of the other spec and unknown names read as NaN. */
    assert_true(isnan(taper_chain_spec_option(c, "rtol")));
    assert_true(isnan(taper_solver_spec_option(s, "n_granules")));
    assert_true(isnan(taper_chain_spec_option(c, "no_such")));
    taper_chain_spec_free(c);
    taper_solver_spec_free(s);
}

/* The typed getters read the same values as the by-name ones. */
static void test_typed_and_named_agree(void **state)
{
    (void)state;
    taper_chain_spec *c = taper_chain_spec_alloc(NULL);
    taper_solver_spec *s = taper_solver_spec_alloc(NULL);
    taper_error err;
    assert_int_equal(taper_chain_spec_set_option_text(c, "profile", "Backward_Linear", &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option(c, "s", 0.25, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option(c, "n_granules", 321, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option_text(c, "right", "wall", &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option(c, "right_compliance", 0.5, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option(c, "seed", 12345, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option(c, "striker_radius", 2, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_option(c, "piston_duration", INFINITY, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_profile(c), TAPER_BACKWARD_LINEAR);
    assert_true(taper_chain_spec_s(c) == 0.25);
    assert_int_equal(taper_chain_spec_n_granules(c), 321);
    assert_int_equal(taper_chain_spec_end(c, TAPER_RIGHT), TAPER_END_WALL);
    assert_true(taper_chain_spec_end_compliance(c, TAPER_RIGHT) == 0.5);
    assert_true(taper_chain_spec_disorder_seed(c) == 12345);
    assert_true(taper_chain_spec_striker_radius(c) == 2);
    assert_true(isinf(taper_chain_spec_piston_duration(c)));
    assert_int_equal(taper_solver_spec_set_option_text(s, "method", "BDF", &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_option(s, "max_order", 4, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_option_text(s, "rtol", "1e-9", &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_option(s, "window", 0, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_method(s), TAPER_BDF);
    assert_int_equal(taper_solver_spec_max_order(s), 4);
    assert_true(taper_solver_spec_rtol(s) == 1e-9);
    assert_int_equal(taper_solver_spec_window(s), 0);
    /* and the reverse */
    assert_int_equal(taper_chain_spec_set_damping(c, 0.125, &err), TAPER_OK);
    assert_true(taper_chain_spec_option(c, "damping") == 0.125);
    assert_int_equal(taper_solver_spec_set_t_end(s, 7.5, &err), TAPER_OK);
    assert_true(taper_solver_spec_option(s, "t_end") == 7.5);
    taper_chain_spec_free(c);
    taper_solver_spec_free(s);
}

/* Each finite bound is accepted (closed) or refused (open), and a value
 * beyond it refused naming the row, with both bounds and the reason. */
static void expect_refused(taper_chain_spec *c, taper_solver_spec *s, const taper_setting *row,
                           double x)
{
    taper_error err;
    double before = get(c, s, row);
    if (set(c, s, row, x, &err) != TAPER_EINVAL) {
        print_error("%s = %.17g was accepted\n", row->name, x);
        fail();
    }
    assert_string_equal(err.field, row->name);
    assert_true(get(c, s, row) == before || (isnan(before) && isnan(get(c, s, row))));
    if (row->type == TAPER_SETTING_REAL || row->type == TAPER_SETTING_INTEGER) {
        char lo[64], hi[64];
        snprintf(lo, sizeof lo, "%c", row->min_open ? '(' : '[');
        snprintf(hi, sizeof hi, "%c", row->max_open ? ')' : ']');
        if (!strstr(err.message, "whole number")) {
            assert_non_null(strstr(err.message, "is out of range"));
            assert_non_null(strstr(err.message, lo));
            assert_non_null(strstr(err.message, hi));
            if (row->bounds_reason[0]) assert_non_null(strstr(err.message, row->bounds_reason));
        }
    }
}

static void test_bounds(void **state)
{
    (void)state;
    taper_chain_spec *c = taper_chain_spec_alloc(NULL);
    taper_solver_spec *s = taper_solver_spec_alloc(NULL);
    taper_error err;
    for (size_t i = 0; i < taper_setting_count(); i++) {
        const taper_setting *row = taper_setting_at(i);
        if (row->type == TAPER_SETTING_LIST) continue;
        if (row->type == TAPER_SETTING_CHOICE) {
            size_t n = 0;
            while (row->choices[n]) n++;
            assert_int_equal(set(c, s, row, (double)(n - 1), &err), TAPER_OK);
            expect_refused(c, s, row, (double)n);
            expect_refused(c, s, row, -1);
            expect_refused(c, s, row, 0.5);
            continue;
        }
        expect_refused(c, s, row, NAN);
        if (isfinite(row->min)) {
            double below = row->min == 0 ? -1e-300 : nextafter(row->min, -INFINITY);
            expect_refused(c, s, row, below);
            if (row->min_open) expect_refused(c, s, row, row->min);
            else assert_int_equal(set(c, s, row, row->min, &err), TAPER_OK);
        }
        if (isfinite(row->max)) {
            expect_refused(c, s, row, nextafter(row->max, INFINITY) * (row->max > 1 ? 1.0000001 : 1));
            if (row->max_open) expect_refused(c, s, row, row->max);
            else assert_int_equal(set(c, s, row, row->max, &err), TAPER_OK);
        } else if (row->max_open) {
            expect_refused(c, s, row, INFINITY);
        } else {
            assert_int_equal(set(c, s, row, INFINITY, &err), TAPER_OK);
        }
        if (row->type == TAPER_SETTING_INTEGER) expect_refused(c, s, row, row->min + 0.5);
        set(c, s, row, row->default_value, &err);
    }
    taper_chain_spec_free(c);
    taper_solver_spec_free(s);
}

/* The examples: both bounds and the reason of the one crossed. */
static void test_messages(void **state)
{
    (void)state;
    taper_solver_spec *s = taper_solver_spec_alloc(NULL);
    taper_chain_spec *c = taper_chain_spec_alloc(NULL);
    taper_error err;
    assert_int_equal(taper_solver_spec_set_rtol(s, 0.5, &err), TAPER_EINVAL);
    assert_string_equal(err.message, "rtol = 0.5 is out of range [3e-16, 0.1]: below 3e-16 (1.35 "
                        "rounding units of double precision) CVODE's error test cannot be met; "
                        "above 0.1 no digit of a result would be right");
    assert_int_equal(taper_chain_spec_set_option(c, "n_granules", -5, &err), TAPER_EINVAL);
    assert_non_null(strstr(err.message, "n_granules = -5 is out of range [2, 1e+07]: a chain "
                                        "needs two granules"));
    /* The value as given, not a rounding of it. */
    assert_int_equal(taper_chain_spec_set_q(c, 1000.0000001, &err), TAPER_EINVAL);
    assert_non_null(strstr(err.message, "q = 1000.0000001 is out"));
    taper_chain_spec_free(c);
    taper_solver_spec_free(s);
}

static void test_names(void **state)
{
    (void)state;
    taper_chain_spec *c = taper_chain_spec_alloc(NULL);
    taper_solver_spec *s = taper_solver_spec_alloc(NULL);
    taper_error err;
    assert_int_equal(taper_chain_spec_set_option(c, "n_granule", 5, &err), TAPER_EINVAL);
    assert_null(err.field);
    assert_string_equal(err.message, "unknown setting 'n_granule': did you mean 'n_granules'?");
    assert_null(taper_setting_find("stiker_radius", &err));
    assert_non_null(strstr(err.message, "did you mean 'striker_radius'?"));
    assert_null(taper_setting_find("xyzzy_plugh", &err));
    assert_null(strstr(err.message, "did you mean"));
    assert_ptr_equal(taper_setting_find("N_GRANULES", NULL), taper_setting_find("n_granules", NULL));
    /* A setting of the other spec. */
    assert_int_equal(taper_chain_spec_set_option(c, "rtol", 1e-8, &err), TAPER_EINVAL);
    assert_string_equal(err.field, "rtol");
    assert_non_null(strstr(err.message, "taper_solver_spec"));
    /* Choices by name, with the nearest name. */
    assert_int_equal(taper_chain_spec_set_option_text(c, "profile", "backward_lnear", &err),
                     TAPER_EINVAL);
    assert_string_equal(err.field, "profile");
    assert_non_null(strstr(err.message, "did you mean 'backward_linear'?"));
    assert_int_equal(taper_chain_spec_set_option_text(c, "s", "0.5x", &err), TAPER_EINVAL);
    assert_non_null(strstr(err.message, "not a number"));
    /* A list is not a scalar, and the reverse. */
    assert_int_equal(taper_chain_spec_set_option(c, "radii", 1, &err), TAPER_EINVAL);
    assert_string_equal(err.field, "radii");
    const double one = 1;
    assert_int_equal(taper_chain_spec_set_option_list(c, "s", &one, 1, &err), TAPER_EINVAL);
    /* The enum lookups answer the same way. */
    taper_method m;
    assert_int_equal(taper_method_from_name("adam", &m, &err), TAPER_EINVAL);
    assert_non_null(strstr(err.message, "did you mean 'adams'?"));
    taper_fit_model fm;
    assert_int_equal(taper_fit_model_from_name("powr", &fm, &err), TAPER_EINVAL);
    assert_non_null(strstr(err.message, "did you mean 'power'?"));
    const char *const words[] = {"alpha", "beta", "gamma"};
    assert_string_equal(taper_nearest_name("Gamm", words, 3), "gamma");
    assert_null(taper_nearest_name("omega", words, 3));
    assert_null(taper_nearest_name(NULL, words, 3));
    taper_chain_spec_free(c);
    taper_solver_spec_free(s);
}

/* Lists by name: checked entry by entry, copied, relative ones divided by
 * their first entry; NULL, 0 removes them. */
static void test_lists(void **state)
{
    (void)state;
    taper_chain_spec *c = taper_chain_spec_alloc(NULL);
    taper_error err;
    const double radii[] = {1, 0.5, 0.25}, bad[] = {1, 0.5, -2}, rho[] = {8000, 2200, 8000};
    assert_int_equal(taper_chain_spec_set_option_list(c, "radii", radii, 3, &err), TAPER_OK);
    size_t n = 0;
    const double *got = taper_chain_spec_option_list(c, "radii", &n);
    assert_int_equal(n, 3);
    assert_ptr_not_equal(got, radii);
    assert_true(got[2] == 0.25);
    assert_int_equal(taper_chain_spec_set_option_list(c, "radii", bad, 3, &err), TAPER_EINVAL);
    assert_string_equal(err.field, "radii");
    assert_non_null(strstr(err.message, "radii(3) = -2 is out of range (0, inf)"));
    assert_true(taper_chain_spec_option_list(c, "radii", &n)[2] == 0.25); /* unchanged */
    assert_int_equal(taper_chain_spec_set_option_list(c, "densities", rho, 3, &err), TAPER_OK);
    got = taper_chain_spec_option_list(c, "densities", &n);
    assert_true(got[0] == 1 && got[1] == 2200.0 / 8000.0 && got[2] == 1);
    assert_int_equal(taper_chain_spec_set_option_list(c, "radii", NULL, 0, &err), TAPER_OK);
    assert_null(taper_chain_spec_option_list(c, "radii", &n));
    assert_int_equal(n, 0);
    taper_chain_spec_free(c);
}

/* Every enum's names come from its one list: walked until NULL, they are
 * as many as its count and read back through from_name. */
static void test_enum_lists(void **state)
{
    (void)state;
    int i;
    for (i = 0; taper_profile_name((taper_profile)i); i++) {
        taper_profile p;
        assert_int_equal(taper_profile_from_name(taper_profile_name((taper_profile)i), &p, NULL),
                         TAPER_OK);
        assert_int_equal(p, i);
    }
    assert_int_equal(i, TAPER_N_PROFILES);
    for (i = 0; taper_status_name((taper_status)i); i++)
        assert_string_not_equal(taper_strerror((taper_status)i), "unknown status");
    assert_int_equal(i, TAPER_ELIMIT + 1);
    assert_string_equal(taper_status_name(TAPER_EINVAL), "invalid");
    for (i = 0; taper_statistic_name((taper_statistic)i); i++) continue;
    assert_int_equal(i, TAPER_N_STATISTICS);
    for (i = 0; taper_dimension_name((taper_dimension)i); i++) continue;
    assert_int_equal(i, TAPER_N_DIMENSIONS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows),  cmocka_unit_test(test_typed_and_named_agree),
        cmocka_unit_test(test_bounds), cmocka_unit_test(test_messages),
        cmocka_unit_test(test_names), cmocka_unit_test(test_lists),
        cmocka_unit_test(test_enum_lists),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
