/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_nvector_window.c -- the sliding-window N_Vector (src/sim/nvector_window.c)
 * against plain loops over the active range, through SUNDIALS' own
 * N_V* entry points (which is how CVODE calls them), including the cases
 * CVODE's Adams steps use most: the predictor's in-place sum
 * zn[j-1] += zn[j] and the fused array operations of the Nordsieck rescale;
 * and the window's storage they share with plain buffers
 * (src/sim/window_storage.c): the tail, and a buffer that is no vector.
 */
#include "sim/nvector_window.h"
#include "sim/sundials_compat.h"

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "test_util.h"

#define CAPACITY 64
#define BEGIN 7 /* odd: the window starts at a compression, as behind a pulse */
#define END 31
#define LEN (END - BEGIN)
#define NV 5

typedef struct {
    SUNContext ctx;
    taper_window *w;
    N_Vector v[NV];
} fixture;

/* Deterministic values of both signs and several magnitudes. */
static double value(int vec, int i) { return sin(1.0 + 3.1 * vec + 0.7 * i) * pow(10.0, (i % 5) - 2); }

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f || taper_sundials_context_new(&f->ctx) != 0) return -1;
    f->w = taper_window_alloc(BEGIN, END, CAPACITY);
    if (!f->w) return -1;
    for (int j = 0; j < NV; j++) {
        f->v[j] = j == 0 ? taper_window_vector_new(f->w, f->ctx) : N_VClone(f->v[0]);
        if (!f->v[j]) return -1;
        double *d = taper_window_data(f->v[j]);
        for (int i = 0; i < LEN; i++) d[i] = value(j, i);
    }
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    for (int j = 0; j < NV; j++) N_VDestroy(f->v[j]);
    taper_window_free(f->w);
    taper_sundials_context_free(&f->ctx);
    free(f);
    return 0;
}

static double *data(fixture *f, int j) { return taper_window_data(f->v[j]); }

static void length_is_the_window(void **state)
{
    fixture *f = *state;
    assert_int_equal(N_VGetLength(f->v[0]), LEN);
    assert_int_equal(taper_window_length(f->v[3]), LEN);
}

/* Every branch of linear_sum: general, z = x with b = 1 (the predictor)
 * and with b != 1, and z = y. */
static void linear_sum_all_aliasings(void **state)
{
    fixture *f = *state;
    N_VLinearSum(2.0, f->v[0], -3.0, f->v[1], f->v[2]);
    for (int i = 0; i < LEN; i++) assert_double_rel(data(f, 2)[i], 2.0 * value(0, i) - 3.0 * value(1, i), 1e-15);
    N_VLinearSum(1.0, f->v[3], 1.0, f->v[1], f->v[3]);
    for (int i = 0; i < LEN; i++) assert_double_rel(data(f, 3)[i], value(3, i) + value(1, i), 1e-15);
    N_VLinearSum(1.0, f->v[4], -0.5, f->v[0], f->v[4]);
    for (int i = 0; i < LEN; i++) assert_double_rel(data(f, 4)[i], value(4, i) - 0.5 * value(0, i), 1e-15);
    N_VLinearSum(0.25, f->v[0], 1.0, f->v[1], f->v[1]);
    for (int i = 0; i < LEN; i++) assert_double_rel(data(f, 1)[i], 0.25 * value(0, i) + value(1, i), 1e-15);
}

/* CVODE's predictor, k = 1..q, j = q..k: zn[j-1] += zn[j], which turns the
 * Nordsieck array into its Pascal-triangle sums. */
static void predictor_pascal_triangle(void **state)
{
    fixture *f = *state;
    const int q = NV - 1;
    for (int k = 1; k <= q; k++)
        for (int j = q; j >= k; j--) N_VLinearSum(1.0, f->v[j - 1], 1.0, f->v[j], f->v[j - 1]);
    /* zn[i] after the predictor: sum_{j >= i} C(j, i) zn[j] */
    for (int i = 0; i < LEN; i++)
        for (int r = 0; r <= q; r++) {
            double expect = 0.0, binom = 1.0;
            for (int j = r; j <= q; j++) {
                expect += binom * value(j, i);
                binom = binom * (j + 1) / (j + 1 - r);
            }
            assert_double_rel(data(f, r)[i], expect, 1e-14);
        }
}

static void fused_array_operations(void **state)
{
    fixture *f = *state;
    double c[NV] = {1.5, -2.0, 0.5, 3.0, -0.25};
    assert_int_equal(N_VScaleVectorArray(NV, c, f->v, f->v), 0);
    for (int j = 0; j < NV; j++)
        for (int i = 0; i < LEN; i++) assert_double_rel(data(f, j)[i], c[j] * value(j, i), 1e-15);
    double norms[NV];
    N_Vector w[NV] = {f->v[0], f->v[0], f->v[0], f->v[0], f->v[0]};
    assert_int_equal(N_VWrmsNormVectorArray(NV, f->v, w, norms), 0);
    for (int j = 0; j < NV; j++) assert_double_rel(norms[j], N_VWrmsNorm(f->v[j], f->v[0]), 1e-15);
    N_Vector x[2] = {f->v[0], f->v[1]}, y[2] = {f->v[2], f->v[3]}, z[2] = {f->v[4], f->v[3]};
    double before3[LEN];
    for (int i = 0; i < LEN; i++) before3[i] = data(f, 3)[i];
    assert_int_equal(N_VLinearSumVectorArray(2, 1.0, x, -1.0, y, z), 0);
    for (int i = 0; i < LEN; i++) {
        assert_double_rel(data(f, 4)[i], data(f, 0)[i] - data(f, 2)[i], 1e-15);
        assert_double_rel(data(f, 3)[i], data(f, 1)[i] - before3[i], 1e-15);
    }
    assert_int_equal(N_VConstVectorArray(NV, 0.5, f->v), 0);
    for (int j = 0; j < NV; j++)
        for (int i = 0; i < LEN; i++) assert_true(data(f, j)[i] == 0.5);
}

/* Nothing outside the window is touched: the zero invariant beyond `end`
 * that makes growing the window exact. */
static void outside_untouched(void **state)
{
    fixture *f = *state;
    double c[NV] = {2, 2, 2, 2, 2};
    N_VScaleVectorArray(NV, c, f->v, f->v);
    N_VConstVectorArray(NV, 7.0, f->v);
    assert_int_equal(taper_window_set_range(f->w, BEGIN, END + 4), 0);
    for (int j = 0; j < NV; j++)
        for (int i = LEN; i < LEN + 4; i++) assert_true(data(f, j)[i] == 0.0);
}

/* The window vector's tail (the quadratures of walls and losses): it
 * follows end when the window grows, in place and when the buffers move,
 * the entries it leaves are zero, and every operation covers it. */
static void window_tail(void **state)
{
    (void)state;
    SUNContext ctx;
    assert_int_equal(taper_sundials_context_new(&ctx), 0);
    taper_window *w = taper_window_alloc_tail(0, 4, 8, 3);
    assert_non_null(w);
    N_Vector a = taper_window_vector_new(w, ctx), b = N_VClone(a);
    assert_true(a && b);
    assert_int_equal((int)N_VGetLength(a), 7);
    double *x = taper_window_data(a);
    for (int i = 0; i < 7; i++) x[i] = i + 1.0; /* state 1..4, tail 5, 6, 7 */
    N_VScale(2.0, a, b);
    /* grow in place by one granule: the tail moves, the new entries are 0 */
    assert_int_equal(taper_window_set_range(w, 0, 6), 0);
    x = taper_window_data(a);
    const double expect[9] = {1, 2, 3, 4, 0, 0, 5, 6, 7};
    for (int i = 0; i < 9; i++) assert_true(x[i] == expect[i]);
    assert_true(taper_window_data(b)[8] == 14.0 && taper_window_data(b)[4] == 0.0);
    /* leave on the left, grow past the capacity: the buffers move */
    assert_int_equal(taper_window_set_range(w, 2, 40), 0);
    x = taper_window_data(a);
    assert_int_equal((int)N_VGetLength(a), 41);
    assert_true(x[0] == 3.0 && x[1] == 4.0 && x[2] == 0.0 && x[37] == 0.0);
    assert_true(x[38] == 5.0 && x[39] == 6.0 && x[40] == 7.0);
    /* operations see the tail: the max norm is the tail's 7 */
    assert_true(N_VMaxNorm(a) == 7.0 && N_VMaxNorm(b) == 14.0);
    N_VDestroy(a);
    N_VDestroy(b);
    taper_window_free(w);
    taper_sundials_context_free(&ctx);
}

/* A plain buffer of the window (rk8's state, window_storage.h) follows the
 * range with the window's vectors: in place, when the buffers move, and
 * with the tail; detached, it is gone from the window's list and freed. */
static void plain_buffer_follows(void **state)
{
    (void)state;
    SUNContext ctx;
    assert_int_equal(taper_sundials_context_new(&ctx), 0);
    taper_window *w = taper_window_alloc_tail(0, 4, 8, 2);
    assert_non_null(w);
    N_Vector a = taper_window_vector_new(w, ctx);
    double *plain = NULL;
    assert_true(a && taper_window_attach(w, &plain) == 0 && plain);
    assert_int_equal((int)w->n_buffers, 2);
    for (int i = 0; i < 6; i++) taper_window_data(a)[i] = taper_window_entries(w, plain)[i] = i + 1.0;
    assert_int_equal(taper_window_set_range(w, 2, 6), 0); /* in place */
    assert_int_equal(taper_window_set_range(w, 4, 50), 0); /* the buffers move */
    assert_int_equal((int)taper_window_size(w), 48);
    const double *p = taper_window_entries(w, plain), *v = taper_window_data(a);
    for (int i = 0; i < 48; i++) assert_true(p[i] == v[i]);
    assert_true(p[46] == 5.0 && p[47] == 6.0 && p[0] == 0.0); /* the tail; entry 4 was cleared */
    taper_window_detach(w, &plain);
    assert_null(plain);
    assert_int_equal((int)w->n_buffers, 1);
    N_VDestroy(a);
    assert_int_equal((int)w->n_buffers, 0);
    taper_window_free(w);
    taper_sundials_context_free(&ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(length_is_the_window, setup, teardown),
        cmocka_unit_test_setup_teardown(linear_sum_all_aliasings, setup, teardown),
        cmocka_unit_test_setup_teardown(predictor_pascal_triangle, setup, teardown),
        cmocka_unit_test_setup_teardown(fused_array_operations, setup, teardown),
        cmocka_unit_test_setup_teardown(outside_untouched, setup, teardown),
        cmocka_unit_test(window_tail),
        cmocka_unit_test(plain_buffer_follows),
    };
    return cmocka_run_group_tests_name("nvector_window", tests, NULL, NULL);
}
