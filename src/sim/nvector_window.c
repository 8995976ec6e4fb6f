/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * nvector_window.c -- the sliding-window N_Vector (see nvector_window.h).
 * The operations are the serial ones restricted to the active range; the
 * buffers and their range are window_storage.c's.
 */
#include "nvector_window.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    taper_window *w;
    double *buf;   /* capacity entries; buf[i] is absolute index base + i */
} window_content;

#define CONTENT(v) ((window_content *)(v)->content)

/* (inline here: every operation starts with them) */
static inline double *data_of(N_Vector v)
{
    const window_content *c = CONTENT(v);
    return taper_window_entries(c->w, c->buf);
}
static inline size_t length_of(N_Vector v) { return taper_window_size(CONTENT(v)->w); }

double *taper_window_data(N_Vector v) { return data_of(v); }
size_t taper_window_length(N_Vector v) { return length_of(v); }

/* ---- required operations -------------------------------------------- */
static N_Vector_ID window_id(N_Vector v) { (void)v; return SUNDIALS_NVEC_CUSTOM; }

static void window_destroy(N_Vector v)
{
    if (!v) return;
    if (v->content) {
        taper_window_detach(CONTENT(v)->w, &CONTENT(v)->buf);
        free(v->content);
        v->content = NULL;
    }
    N_VFreeEmpty(v);
}

static N_Vector window_new_like(taper_window *w, SUNContext ctx, N_Vector ops_from)
{
    N_Vector v = N_VNewEmpty(ctx);
    if (!v) return NULL;
    if (ops_from && N_VCopyOps(ops_from, v) != 0) {
        N_VFreeEmpty(v);
        return NULL;
    }
    window_content *c = malloc(sizeof *c);
    if (c) c->w = w;
    if (!c || taper_window_attach(w, &c->buf) != 0) {
        free(c);
        N_VFreeEmpty(v);
        return NULL;
    }
    v->content = c;
    return v;
}

static N_Vector window_clone(N_Vector v) { return window_new_like(CONTENT(v)->w, v->sunctx, v); }

static void window_space(N_Vector v, sunindextype *lrw, sunindextype *liw)
{
    *lrw = (sunindextype)CONTENT(v)->w->capacity;
    *liw = 2;
}

static double *window_array(N_Vector v) { return data_of(v); }
static sunindextype window_get_length(N_Vector v) { return (sunindextype)length_of(v); }

#define LOOP(v) for (size_t i = 0, n_ = length_of(v); i < n_; i++)

/* ---- the kernels ------------------------------------------------------
 * CVODE's Adams step is a few dozen operations on vectors of ~24 entries
 * (a window of 12 granules): what the loops cost besides their arithmetic
 * is what counts.  The operations CVODE calls at every step get kernels
 * whose operands are declared apart (restrict), chosen by how the vectors
 * alias, so that the compiler vectorises them without run-time overlap
 * checks; the fused ones work column by column (below).  Every kernel
 * evaluates the same expression, element by element, as the plain loop of
 * the serial vector would (a x + b y with both products rounded, sums in
 * the same order), so the results are bit for bit the same. */

/* z = a x + b y */
static void sum_apart(size_t n, double a, const double *restrict x, double b, const double *restrict y,
                      double *restrict z)
{
    for (size_t i = 0; i < n; i++) z[i] = a * x[i] + b * y[i];
}
/* z = a z + b y */
static void sum_into_x(size_t n, double a, double *restrict z, double b, const double *restrict y)
{
    for (size_t i = 0; i < n; i++) z[i] = a * z[i] + b * y[i];
}
/* z = a x + b z */
static void sum_into_y(size_t n, double a, const double *restrict x, double b, double *restrict z)
{
    for (size_t i = 0; i < n; i++) z[i] = a * x[i] + b * z[i];
}

/* The fixed-point corrector calls this 3 times per iteration
 * (y = zn[0] + ycor, res = h f - zn[1] in place, the change of the
 * correction) and CVODE's step once more; the predictor's in-place sums
 * are share/sundials/fused-predictor.patch's. */
static void window_linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z)
{
    const size_t n = length_of(z);
    const double *xd = data_of(x), *yd = data_of(y);
    double *zd = data_of(z);
    if (x == z && y == z) {
        for (size_t i = 0; i < n; i++) zd[i] = a * zd[i] + b * zd[i];
    } else if (x == z) {
        sum_into_x(n, a, zd, b, yd);
    } else if (y == z) {
        sum_into_y(n, a, xd, b, zd);
    } else {
        sum_apart(n, a, xd, b, yd, zd);
    }
}

static void window_const(double c, N_Vector z)
{
    double *zd = data_of(z);
    LOOP(z) zd[i] = c;
}

static void window_prod(N_Vector x, N_Vector y, N_Vector z)
{
    const double *xd = data_of(x), *yd = data_of(y);
    double *zd = data_of(z);
    LOOP(z) zd[i] = xd[i] * yd[i];
}

static void window_div(N_Vector x, N_Vector y, N_Vector z)
{
    const double *xd = data_of(x), *yd = data_of(y);
    double *zd = data_of(z);
    LOOP(z) zd[i] = xd[i] / yd[i];
}

static void scale_apart(size_t n, double c, const double *restrict x, double *restrict z)
{
    for (size_t i = 0; i < n; i++) z[i] = c * x[i];
}

/* Copies (c = 1: the fixed-point iteration's, twice per iteration) and
 * CVODE's rescaling of the error estimate. */
static void window_scale(double c, N_Vector x, N_Vector z)
{
    const size_t n = length_of(z);
    double *zd = data_of(z);
    if (x == z) {
        for (size_t i = 0; i < n; i++) zd[i] = c * zd[i];
    } else {
        scale_apart(n, c, data_of(x), zd);
    }
}

static void window_abs(N_Vector x, N_Vector z)
{
    const double *xd = data_of(x);
    double *zd = data_of(z);
    LOOP(z) zd[i] = fabs(xd[i]);
}

static void window_inv(N_Vector x, N_Vector z)
{
    const double *xd = data_of(x);
    double *zd = data_of(z);
    LOOP(z) zd[i] = 1.0 / xd[i];
}

static void window_add_const(N_Vector x, double b, N_Vector z)
{
    const double *xd = data_of(x);
    double *zd = data_of(z);
    LOOP(z) zd[i] = xd[i] + b;
}

static double window_dot(N_Vector x, N_Vector y)
{
    const double *xd = data_of(x), *yd = data_of(y);
    double s = 0.0;
    LOOP(x) s += xd[i] * yd[i];
    return s;
}

static double window_max_norm(N_Vector x)
{
    const double *xd = data_of(x);
    double m = 0.0;
    LOOP(x) if (fabs(xd[i]) > m) m = fabs(xd[i]);
    return m;
}

static double window_wsqrsum(N_Vector x, N_Vector w)
{
    const double *xd = data_of(x), *wd = data_of(w);
    double s = 0.0;
    LOOP(x) {
        double p = xd[i] * wd[i];
        s += p * p;
    }
    return s;
}

static double window_wrms(N_Vector x, N_Vector w)
{
    size_t n = length_of(x);
    return n ? sqrt(window_wsqrsum(x, w) / (double)n) : 0.0;
}

static double window_wrms_mask(N_Vector x, N_Vector w, N_Vector id)
{
    const double *xd = data_of(x), *wd = data_of(w),
                 *md = data_of(id);
    double s = 0.0;
    size_t n = length_of(x);
    LOOP(x) if (md[i] > 0.0) {
        double p = xd[i] * wd[i];
        s += p * p;
    }
    return n ? sqrt(s / (double)n) : 0.0;
}

static double window_min(N_Vector x)
{
    const double *xd = data_of(x);
    double m = INFINITY;
    LOOP(x) if (xd[i] < m) m = xd[i];
    return m;
}

static double window_wl2(N_Vector x, N_Vector w) { return sqrt(window_wsqrsum(x, w)); }

static double window_l1(N_Vector x)
{
    const double *xd = data_of(x);
    double s = 0.0;
    LOOP(x) s += fabs(xd[i]);
    return s;
}

static void window_compare(double c, N_Vector x, N_Vector z)
{
    const double *xd = data_of(x);
    double *zd = data_of(z);
    LOOP(z) zd[i] = fabs(xd[i]) >= c ? 1.0 : 0.0;
}

static booleantype window_inv_test(N_Vector x, N_Vector z)
{
    const double *xd = data_of(x);
    double *zd = data_of(z);
    booleantype ok = SUNTRUE;
    LOOP(z) {
        if (xd[i] == 0.0) ok = SUNFALSE;
        else zd[i] = 1.0 / xd[i];
    }
    return ok;
}

static booleantype window_constr_mask(N_Vector c, N_Vector x, N_Vector m)
{
    (void)c;
    window_const(0.0, m);
    (void)x;
    return SUNTRUE; /* no constraints are ever set */
}

static double window_min_quotient(N_Vector num, N_Vector denom)
{
    const double *nd = data_of(num), *dd = data_of(denom);
    double m = 1.0e300; /* BIG_REAL, as the serial vector */
    LOOP(num) if (dd[i] != 0.0 && nd[i] / dd[i] < m) m = nd[i] / dd[i];
    return m;
}

/* ---- fused operations: CVODE's interpolation and corrector -------------
 * CVODE 6.4 calls three of SUNDIALS' fused and vector-array operations
 * (N_VEnableFusedOps' set) on an Adams step: N_VLinearCombination in
 * CVodeGetDky (y(t) = sum_j s^j zn[j], at every trial time of the root
 * finder and at every root and output time), N_VScaleAddMulti in
 * cvCompleteStep (zn[j] += l_j acor, j = 0..q, once per step; also on
 * order changes) and N_VScaleVectorArray in cvRescale (zn[j] *= eta^j, on
 * a step size change).  N_VDotProdMulti serves only Anderson acceleration
 * (not used), the other array operations only CVODES and ARKODE.
 *
 * The first two work column by column: each element's q + 1 entries are
 * combined in registers and stored once, instead of one pass over the
 * vectors per column (which stores z and loads it again q times).  The
 * number of vectors is a constant in each case of a switch, so that the
 * compiler unrolls the column; with GCC or Clang two elements at a time in
 * a pair of doubles (their vector extension: element-wise IEEE
 * arithmetic, the same results).  Per element the products and sums are
 * those of the pass-by-pass loops, in the same order: bit for bit the
 * same results.  Reading every entry of an element before writing it, the
 * column order is also right where z is one of the x_j. */
#define COLUMNS_MAX 13 /* CVODE's q + 1 (Adams: q <= 12) */

#if defined(__GNUC__)
typedef double pair __attribute__((vector_size(2 * sizeof(double))));
static inline pair pair_load(const double *p)
{
    pair v;
    memcpy(&v, p, sizeof v);
    return v;
}
static inline void pair_store(double *p, pair v) { memcpy(p, &v, sizeof v); }
static inline pair pair_of(double c) { return (pair){c, c}; }
#define COMBINATION_PAIRS(NV)                                                                 \
    for (; i + 1 < n; i += 2) {                                                               \
        pair s = cc[0] * pair_load(xs[0] + i);                                                \
        for (int j = 1; j < (NV); j++) s += cc[j] * pair_load(xs[j] + i);                     \
        pair_store(z + i, s);                                                                 \
    }
#define SCALE_ADD_PAIRS(NV)                                                                   \
    for (; i + 1 < n; i += 2) {                                                               \
        const pair xi = pair_load(x + i);                                                     \
        for (int j = 0; j < (NV); j++) pair_store(zs[j] + i, cc[j] * xi + pair_load(ys[j] + i)); \
    }
#define SCALE_ADD_IN_PLACE_PAIRS(NV)                                                          \
    for (; i + 1 < n; i += 2) {                                                               \
        const pair xi = pair_load(x + i);                                                     \
        for (int j = 0; j < (NV); j++) pair_store(zs[j] + i, cc[j] * xi + pair_load(zs[j] + i)); \
    }
#define PAIRS_OF(NV, c) pair cc[NV]; for (int j = 0; j < (NV); j++) cc[j] = pair_of(c[j]);
#else
#define COMBINATION_PAIRS(NV)
#define SCALE_ADD_PAIRS(NV)
#define SCALE_ADD_IN_PLACE_PAIRS(NV)
#define PAIRS_OF(NV, c)
#endif

#define COLUMN_CASES(CASE)                                                                    \
    CASE(1) CASE(2) CASE(3) CASE(4) CASE(5) CASE(6) CASE(7) CASE(8) CASE(9) CASE(10) CASE(11) \
    CASE(12) CASE(13)

/* z = sum_{j < nv} c_j x_j */
static void combine_columns(int nv, const double *c, const double *const *xs, double *z, size_t n)
{
    size_t i = 0;
    switch (nv) {
#define COMBINATION_CASE(NV)                                                                  \
    case NV: {                                                                                \
        PAIRS_OF(NV, c)                                                                       \
        COMBINATION_PAIRS(NV)                                                                 \
        for (; i < n; i++) {                                                                  \
            double s = c[0] * xs[0][i];                                                       \
            for (int j = 1; j < (NV); j++) s += c[j] * xs[j][i];                              \
            z[i] = s;                                                                         \
        }                                                                                     \
        return;                                                                               \
    }
        COLUMN_CASES(COMBINATION_CASE)
#undef COMBINATION_CASE
    default: break;
    }
}

/* zs_j = c_j x + ys_j, j < nv (x none of the zs_j) */
static void scale_add_columns(int nv, const double *c, const double *x, const double *const *ys,
                              double *const *zs, size_t n)
{
    size_t i = 0;
    switch (nv) {
#define SCALE_ADD_CASE(NV)                                                                    \
    case NV: {                                                                                \
        PAIRS_OF(NV, c)                                                                       \
        SCALE_ADD_PAIRS(NV)                                                                   \
        for (; i < n; i++) {                                                                  \
            const double xi = x[i];                                                           \
            for (int j = 0; j < (NV); j++) zs[j][i] = c[j] * xi + ys[j][i];                   \
        }                                                                                     \
        return;                                                                               \
    }
        COLUMN_CASES(SCALE_ADD_CASE)
#undef SCALE_ADD_CASE
    default: break;
    }
}

/* zs_j += c_j x, j < nv (x none of the zs_j): CVODE's case, zn[j] += l_j acor */
static void scale_add_in_place_columns(int nv, const double *c, const double *x, double *const *zs, size_t n)
{
    size_t i = 0;
    switch (nv) {
#define SCALE_ADD_IN_PLACE_CASE(NV)                                                           \
    case NV: {                                                                                \
        PAIRS_OF(NV, c)                                                                       \
        SCALE_ADD_IN_PLACE_PAIRS(NV)                                                          \
        for (; i < n; i++) {                                                                  \
            const double xi = x[i];                                                           \
            for (int j = 0; j < (NV); j++) zs[j][i] = c[j] * xi + zs[j][i];                   \
        }                                                                                     \
        return;                                                                               \
    }
        COLUMN_CASES(SCALE_ADD_IN_PLACE_CASE)
#undef SCALE_ADD_IN_PLACE_CASE
    default: break;
    }
}

static int window_linear_combination(int nv, double *c, N_Vector *x, N_Vector z)
{
    double *zd = data_of(z);
    const size_t n = length_of(z);
    if (nv >= 1 && nv <= COLUMNS_MAX) {
        const double *xs[COLUMNS_MAX];
        for (int j = 0; j < nv; j++) xs[j] = data_of(x[j]);
        combine_columns(nv, c, xs, zd, n);
        return 0;
    }
    /* more vectors than CVODE uses: pass by pass (z may be x[0], not
     * another x[j]) */
    const double *x0 = data_of(x[0]);
    for (size_t i = 0; i < n; i++) zd[i] = c[0] * x0[i];
    for (int j = 1; j < nv; j++) {
        const double *xj = data_of(x[j]);
        for (size_t i = 0; i < n; i++) zd[i] += c[j] * xj[i];
    }
    return 0;
}

static int window_scale_add_multi(int nv, double *a, N_Vector x, N_Vector *y, N_Vector *z)
{
    const double *xd = data_of(x);
    const size_t n = length_of(x);
    int apart = nv >= 1 && nv <= COLUMNS_MAX, in_place = 1;
    for (int j = 0; apart && j < nv; j++) {
        apart = z[j] != x;
        in_place = in_place && z[j] == y[j];
    }
    if (apart) {
        const double *ys[COLUMNS_MAX];
        double *zs[COLUMNS_MAX];
        for (int j = 0; j < nv; j++) zs[j] = data_of(z[j]);
        if (in_place) {
            scale_add_in_place_columns(nv, a, xd, zs, n);
            return 0;
        }
        for (int j = 0; j < nv; j++) ys[j] = data_of(y[j]);
        scale_add_columns(nv, a, xd, ys, zs, n);
        return 0;
    }
    /* x is one of the z (then pass by pass: the later z see it changed,
     * as in the serial vector), or more vectors than CVODE uses */
    for (int j = 0; j < nv; j++) {
        const double *yd = data_of(y[j]);
        double *zd = data_of(z[j]);
        for (size_t i = 0; i < n; i++) zd[i] = a[j] * xd[i] + yd[i];
    }
    return 0;
}

static int window_scale_vector_array(int nv, double *c, N_Vector *x, N_Vector *z)
{
    const size_t n = length_of(x[0]);
    for (int j = 0; j < nv; j++) {
        const double *xd = data_of(x[j]);
        double *zd = data_of(z[j]);
        for (size_t i = 0; i < n; i++) zd[i] = c[j] * xd[i];
    }
    return 0;
}

static int window_const_vector_array(int nv, double c, N_Vector *z)
{
    const size_t n = length_of(z[0]);
    for (int j = 0; j < nv; j++) {
        double *zd = data_of(z[j]);
        for (size_t i = 0; i < n; i++) zd[i] = c;
    }
    return 0;
}

static int window_linear_sum_vector_array(int nv, double a, N_Vector *x, double b, N_Vector *y,
                                          N_Vector *z)
{
    for (int j = 0; j < nv; j++) window_linear_sum(a, x[j], b, y[j], z[j]);
    return 0;
}

static int window_wrms_vector_array(int nv, N_Vector *x, N_Vector *w, double *norms)
{
    for (int j = 0; j < nv; j++) norms[j] = window_wrms(x[j], w[j]);
    return 0;
}

static void set_ops(N_Vector v)
{
    struct _generic_N_Vector_Ops *o = v->ops;
    o->nvgetvectorid = window_id;
    o->nvclone = window_clone;
    o->nvdestroy = window_destroy;
    o->nvspace = window_space;
    o->nvgetarraypointer = window_array;
    o->nvgetlength = window_get_length;
    o->nvlinearsum = window_linear_sum;
    o->nvconst = window_const;
    o->nvprod = window_prod;
    o->nvdiv = window_div;
    o->nvscale = window_scale;
    o->nvabs = window_abs;
    o->nvinv = window_inv;
    o->nvaddconst = window_add_const;
    o->nvdotprod = window_dot;
    o->nvmaxnorm = window_max_norm;
    o->nvwrmsnorm = window_wrms;
    o->nvwrmsnormmask = window_wrms_mask;
    o->nvmin = window_min;
    o->nvwl2norm = window_wl2;
    o->nvl1norm = window_l1;
    o->nvcompare = window_compare;
    o->nvinvtest = window_inv_test;
    o->nvconstrmask = window_constr_mask;
    o->nvminquotient = window_min_quotient;
    o->nvlinearcombination = window_linear_combination;
    o->nvscaleaddmulti = window_scale_add_multi;
    o->nvscalevectorarray = window_scale_vector_array;
    o->nvconstvectorarray = window_const_vector_array;
    o->nvlinearsumvectorarray = window_linear_sum_vector_array;
    o->nvwrmsnormvectorarray = window_wrms_vector_array;
}

/* ---- the window ------------------------------------------------------ */
N_Vector taper_window_vector_new(taper_window *w, SUNContext ctx)
{
    N_Vector v = window_new_like(w, ctx, NULL);
    if (v) set_ops(v);
    return v;
}

double **taper_window_vector_buffer(N_Vector v) { return &CONTENT(v)->buf; }
