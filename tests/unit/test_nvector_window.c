/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_nvector_window.c -- the sliding-window N_Vector (src/sim/nvector_window.c)
 * against plain loops over the active range, through SUNDIALS' own
 * N_V* entry points (which is how CVODE calls them), including the cases
 * CVODE's Adams steps use most: the predictor's in-place sum
 * zn[j-1] += zn[j] and the fused array operations of the Nordsieck rescale;
 * and the window's storage they share with plain buffers
 * (src/sim/window_storage.c): the tail, and a buffer that is no vector.
 * The column-wise fused operations give bit for bit what the pass-by-pass
 * loops give, and the window's fixed-point corrector
 * (src/sim/stepper_cvode_corrector.c) takes bit for bit SUNDIALS' own
 * fixed-point steps.
 */
#include "sim/nvector_window.h"
#include "sim/stepper_cvode_memory.h"
#include "sim/sundials_compat.h"

#include <cvode/cvode.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* ---- the column-wise fused operations ------------------------------------ */
#define COLUMNS 14 /* one more than CVODE uses (q + 1 <= 13): the fallback too */

typedef struct {
    SUNContext ctx;
    taper_window *w;
    N_Vector v[COLUMNS + 2];
    size_t n;
} columns;

/* Vectors of a window of odd length (the column kernels work two elements
 * at a time, then the last alone). */
static void columns_make(columns *c)
{
    assert_int_equal(taper_sundials_context_new(&c->ctx), 0);
    c->w = taper_window_alloc(3, 28, 64);
    assert_non_null(c->w);
    c->n = 25;
    for (int j = 0; j < COLUMNS + 2; j++) {
        c->v[j] = j == 0 ? taper_window_vector_new(c->w, c->ctx) : N_VClone(c->v[0]);
        assert_non_null(c->v[j]);
        double *d = taper_window_data(c->v[j]);
        for (size_t i = 0; i < c->n; i++) d[i] = value(j, (int)i);
    }
}

static void columns_free(columns *c)
{
    for (int j = 0; j < COLUMNS + 2; j++) N_VDestroy(c->v[j]);
    taper_window_free(c->w);
    taper_sundials_context_free(&c->ctx);
}

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* z = sum_j c_j x_j for every number of vectors, against the pass-by-pass
 * loop (z = c_0 x_0, then z += c_j x_j): the same bits; and with z one of
 * the x_j, the combination of the values before (a column's entries are
 * all read before it is written). */
static void linear_combination_columns(void **state)
{
    (void)state;
    columns c;
    columns_make(&c);
    double coef[COLUMNS];
    for (int j = 0; j < COLUMNS; j++) coef[j] = 0.3 + 1.7 * j - 0.11 * j * j;
    N_Vector z = c.v[COLUMNS];
    for (int nv = 1; nv <= COLUMNS; nv++) {
        assert_int_equal(N_VLinearCombination(nv, coef, c.v, z), 0);
        for (size_t i = 0; i < c.n; i++) {
            double expect = coef[0] * value(0, (int)i);
            for (int j = 1; j < nv; j++) expect += coef[j] * value(j, (int)i);
            if (!same_bits(taper_window_data(z)[i], expect))
                fail_msg("nv = %d, i = %zu: %.17g, the loop %.17g", nv, i, taper_window_data(z)[i], expect);
        }
    }
    /* z = x_3 among 9 vectors (CVodeGetDky's number at order 8) */
    double before[COLUMNS][32];
    for (int j = 0; j < 9; j++) memcpy(before[j], taper_window_data(c.v[j]), c.n * sizeof(double));
    assert_int_equal(N_VLinearCombination(9, coef, c.v, c.v[3]), 0);
    for (size_t i = 0; i < c.n; i++) {
        double expect = coef[0] * before[0][i];
        for (int j = 1; j < 9; j++) expect += coef[j] * before[j][i];
        assert_true(same_bits(taper_window_data(c.v[3])[i], expect));
    }
    columns_free(&c);
}

/* z_j = a_j x + y_j: in place (z_j = y_j, cvCompleteStep's zn[j] +=
 * l_j acor), apart, and with x one of the z_j (then pass by pass: the later
 * z_j see x changed, as with the serial vector); the same bits as the
 * loops. */
static void scale_add_multi_columns(void **state)
{
    (void)state;
    columns c;
    columns_make(&c);
    double a[COLUMNS];
    for (int j = 0; j < COLUMNS; j++) a[j] = -1.25 + 0.5 * j;
    const double *x = taper_window_data(c.v[COLUMNS]);
    for (int nv = 1; nv <= 13; nv++) {
        double y[13][32];
        for (int j = 0; j < nv; j++) memcpy(y[j], taper_window_data(c.v[j]), c.n * sizeof(double));
        assert_int_equal(N_VScaleAddMulti(nv, a, c.v[COLUMNS], c.v, c.v), 0); /* in place */
        for (int j = 0; j < nv; j++)
            for (size_t i = 0; i < c.n; i++) assert_true(same_bits(taper_window_data(c.v[j])[i], a[j] * x[i] + y[j][i]));
    }
    /* apart: z_j = a_j x + y_j into other vectors */
    N_Vector ys[2] = {c.v[0], c.v[1]}, zs[2] = {c.v[2], c.v[COLUMNS + 1]};
    assert_int_equal(N_VScaleAddMulti(2, a, c.v[COLUMNS], ys, zs), 0);
    for (size_t i = 0; i < c.n; i++) {
        assert_true(same_bits(taper_window_data(c.v[2])[i], a[0] * x[i] + taper_window_data(c.v[0])[i]));
        assert_true(same_bits(taper_window_data(c.v[COLUMNS + 1])[i], a[1] * x[i] + taper_window_data(c.v[1])[i]));
    }
    /* x = z_0: z_1 = a_1 (a_0 x + y_0) + y_1 */
    double x0[32], y0[32], y1[32];
    memcpy(x0, taper_window_data(c.v[4]), c.n * sizeof(double));
    memcpy(y0, taper_window_data(c.v[5]), c.n * sizeof(double));
    memcpy(y1, taper_window_data(c.v[6]), c.n * sizeof(double));
    N_Vector yy[2] = {c.v[5], c.v[6]}, zz[2] = {c.v[4], c.v[7]};
    assert_int_equal(N_VScaleAddMulti(2, a, c.v[4], yy, zz), 0);
    for (size_t i = 0; i < c.n; i++) {
        const double z0 = a[0] * x0[i] + y0[i];
        assert_true(same_bits(taper_window_data(c.v[4])[i], z0));
        assert_true(same_bits(taper_window_data(c.v[7])[i], a[1] * z0 + y1[i]));
    }
    columns_free(&c);
}

/* ---- the corrector ---------------------------------------------------------- */
/* A Hertz chain of CORRECTOR_GRANULES equal granules, the first moving at 1:
 * (v_k, z_k) interleaved as in the library, v_k' = F(z_{k-1}) - F(z_k),
 * z_k' = v_k - v_{k+1}, F(z) = z^(3/2) for z > 0. */
#define CORRECTOR_GRANULES 12

static double hertz(double z) { return z > 0.0 ? z * sqrt(z) : 0.0; }

static int chain_rhs(double t, N_Vector yv, N_Vector fv, void *user)
{
    (void)t;
    ++*(long *)user;
    const double *y = taper_window_data(yv);
    double *f = taper_window_data(fv);
    double left = 0.0;
    for (int k = 0; k < CORRECTOR_GRANULES; k++) {
        const double right = k + 1 < CORRECTOR_GRANULES ? hertz(y[2 * k + 1]) : 0.0;
        f[2 * k] = left - right;
        f[2 * k + 1] = y[2 * k] - (k + 1 < CORRECTOR_GRANULES ? y[2 * k + 2] : 0.0);
        left = right;
    }
    return 0;
}

typedef struct {
    taper_window *w;
    N_Vector y;
    void *mem;
    SUNNonlinearSolver nls;
    long rhs_calls, corrector_evals;
} adams_run;

/* Adams of order 8 on the chain to t = 8 with SUNDIALS' fixed-point
 * solver or the window's corrector. */
static void adams_run_do(adams_run *r, SUNContext ctx, int corrector)
{
    r->w = taper_window_alloc(0, 2 * CORRECTOR_GRANULES, 2 * CORRECTOR_GRANULES);
    assert_non_null(r->w);
    r->y = taper_window_vector_new(r->w, ctx);
    assert_non_null(r->y);
    taper_window_data(r->y)[0] = 1.0;
    r->mem = CVodeCreate(CV_ADAMS, ctx);
    assert_non_null(r->mem);
    assert_int_equal(CVodeInit(r->mem, chain_rhs, 0.0, r->y), CV_SUCCESS);
    assert_int_equal(CVodeSStolerances(r->mem, 1e-10, 1e-13), CV_SUCCESS);
    assert_int_equal(CVodeSetUserData(r->mem, &r->rhs_calls), CV_SUCCESS);
    assert_int_equal(CVodeSetMaxOrd(r->mem, 8), CV_SUCCESS);
    assert_int_equal(CVodeSetMaxNumSteps(r->mem, 100000), CV_SUCCESS);
    assert_int_equal(CVodeSetInitStep(r->mem, 1e-4), CV_SUCCESS);
    r->nls = corrector ? cvode_corrector_new(r->y, chain_rhs, &r->corrector_evals, ctx)
                       : SUNNonlinSol_FixedPoint(r->y, 0, ctx);
    assert_non_null(r->nls);
    assert_int_equal(CVodeSetNonlinearSolver(r->mem, r->nls), CV_SUCCESS);
    double t = 0.0;
    assert_int_equal(CVode(r->mem, 8.0, r->y, &t, CV_NORMAL), CV_SUCCESS);
}

static void adams_run_free(adams_run *r)
{
    CVodeFree(&r->mem);
    SUNNonlinSolFree(r->nls);
    N_VDestroy(r->y);
    taper_window_free(r->w);
}

/* The same steps, bit for bit: the state, the step count, the iterations
 * and failures, and every right-hand side accounted for (CVODE's count of
 * its own calls plus the corrector's own). */
static void corrector_is_sundials_fixed_point(void **state)
{
    (void)state;
    SUNContext ctx;
    assert_int_equal(taper_sundials_context_new(&ctx), 0);
    adams_run a = {0}, b = {0};
    adams_run_do(&a, ctx, 0);
    adams_run_do(&b, ctx, 1);
    assert_memory_equal(taper_window_data(a.y), taper_window_data(b.y), 2 * CORRECTOR_GRANULES * sizeof(double));
    long nst[2], nni[2], nfe[2], netf[2], ncf[2];
    adams_run *runs[2] = {&a, &b};
    for (int i = 0; i < 2; i++) {
        CVodeGetNumSteps(runs[i]->mem, &nst[i]);
        CVodeGetNumNonlinSolvIters(runs[i]->mem, &nni[i]);
        CVodeGetNumRhsEvals(runs[i]->mem, &nfe[i]);
        CVodeGetNumErrTestFails(runs[i]->mem, &netf[i]);
        CVodeGetNumNonlinSolvConvFails(runs[i]->mem, &ncf[i]);
    }
    assert_true(nst[0] > 200);
    assert_true(netf[0] > 0); /* contacts opened: steps were rejected and retried */
    assert_int_equal(nst[0], nst[1]);
    assert_int_equal(nni[0], nni[1]);
    assert_int_equal(netf[0], netf[1]);
    assert_int_equal(ncf[0], ncf[1]);
    assert_int_equal(a.rhs_calls, b.rhs_calls);
    assert_int_equal(b.corrector_evals, nni[1]);
    assert_int_equal(nfe[0], nfe[1] + b.corrector_evals);
    adams_run_free(&a);
    adams_run_free(&b);
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
        cmocka_unit_test(linear_combination_columns),
        cmocka_unit_test(scale_add_multi_columns),
        cmocka_unit_test(corrector_is_sundials_fixed_point),
    };
    return cmocka_run_group_tests_name("nvector_window", tests, NULL, NULL);
}
