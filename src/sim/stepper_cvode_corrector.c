/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * stepper_cvode_corrector.c -- the corrector of CVODE's Adams steps on the
 * window: a SUNNonlinearSolver of the fixed-point type (SUNDIALS'
 * SUNNonlinSol_FixedPoint without acceleration, the same iteration) whose
 * iteration is fused over the window's entries.
 *
 * CVODE's fixed-point corrector solves ycor = G(ycor) with
 *     G(ycor) = rl1 (h f(tn, ypred + ycor) - zn[1])
 * (cvode_nls.c, cvNlsFPFunction; ypred = zn[0], rl1 = 1/l_1).  SUNDIALS'
 * solver makes each iteration nine vector operations: copy ycor, y =
 * ypred + ycor, f, res = h f - zn[1], res *= rl1, copy res into ycor, the
 * change ycor - yprev, its norm (CVODE's convergence test), with a call
 * and a loop each over ~24 entries on a monodisperse chain, where the
 * calls and loop set-up cost more than the arithmetic.  Here an iteration
 * is one loop before the right-hand side (y = ypred + ycor) and one after
 * it (G, the change, the new ycor), and CVODE's own convergence test.
 *
 * The system is computed from CVodeGetNonlinearSystemData, the interface
 * SUNDIALS provides for custom nonlinear solvers (tcur, ypred, yn, rl1,
 * zn[1]) and the step h (CVodeGetCurrentStep, CVODE's h during its
 * step); each element gets the same products and sums, in the same order,
 * as cvNlsFPFunction and the solver's vector operations give it, so every
 * step is bit for bit SUNDIALS' own (granules.tsv identical).  Should a
 * SUNDIALS version's h and gamma disagree (gamma = h rl1 is how CVODE sets
 * it), the system is G = gamma f - rl1 zn[1], the same function.
 *
 * The right-hand side is the one CVODE was given (CVodeInit), called with
 * CVODE's user data; the evaluations made here are not in CVODE's nfe (it
 * counts those it makes itself) and are counted for the stepper instead
 * (corrector_rhs_evals).
 */
#include "stepper_cvode_memory.h"

#include <cvode/cvode.h>

#include <stdlib.h>

typedef struct {
    cvode_rhs_fn rhs;
    long *rhs_evals;
    N_Vector f, delta;          /* the right-hand side; the change of ycor */
    SUNNonlinSolSysFn sys;      /* CVODE's G: kept, computed here fused   */
    SUNNonlinSolConvTestFn test;
    void *test_data;
    int iteration, max_iterations;
    long iterations, failures;  /* of the last solve                      */
} corrector;

#define CORRECTOR(nls) ((corrector *)(nls)->content)

static SUNNonlinearSolver_Type corrector_type(SUNNonlinearSolver nls)
{
    (void)nls;
    return SUNNONLINEARSOLVER_FIXEDPOINT;
}

static int corrector_initialize(SUNNonlinearSolver nls)
{
    corrector *c = CORRECTOR(nls);
    if (!c->sys || !c->test) return SUN_NLS_MEM_NULL;
    c->iterations = c->failures = 0;
    return SUN_NLS_SUCCESS;
}

/* y = ypred + ycor (as N_VLinearSum(1, ypred, 1, ycor, y)) */
static void predicted_plus(size_t n, const double *restrict ypred, const double *restrict ycor,
                           double *restrict y)
{
    for (size_t i = 0; i < n; i++) y[i] = ypred[i] + ycor[i];
}

/* g = rl1 (h f - zn1), delta = g - ycor, ycor = g: as N_VLinearSum(h, f,
 * -1, zn1, f), N_VScale(rl1, f, f), N_VScale(1, ycor, yprev), N_VScale(1,
 * f, ycor), N_VLinearSum(1, ycor, -1, yprev, delta) */
static void corrected(size_t n, double h, double rl1, const double *restrict f,
                      const double *restrict zn1, double *restrict ycor, double *restrict delta)
{
    for (size_t i = 0; i < n; i++) {
        const double g = rl1 * (h * f[i] - zn1[i]);
        delta[i] = g - ycor[i];
        ycor[i] = g;
    }
}

/* The same with G = gamma f - rl1 zn1 (h not CVODE's step: see the top). */
static void corrected_gamma(size_t n, double gamma, double rl1, const double *restrict f,
                            const double *restrict zn1, double *restrict ycor, double *restrict delta)
{
    for (size_t i = 0; i < n; i++) {
        const double g = gamma * f[i] - rl1 * zn1[i];
        delta[i] = g - ycor[i];
        ycor[i] = g;
    }
}

/* SUNNonlinSolSolve_FixedPoint without acceleration (m = 0), the system
 * fused: returns as it does (a failed right-hand side is a recoverable
 * convergence failure there too; ours does not fail). */
static int corrector_solve(SUNNonlinearSolver nls, N_Vector y0, N_Vector ycor, N_Vector w, double tol,
                           booleantype call_setup, void *mem)
{
    (void)y0, (void)call_setup; /* y0 is ypred, read below with the rest */
    corrector *c = CORRECTOR(nls);
    double t, gamma, rl1, h;
    N_Vector ypred, yn, fn, zn1;
    void *user;
    c->iterations = c->failures = 0;
    if (CVodeGetNonlinearSystemData(mem, &t, &ypred, &yn, &fn, &gamma, &rl1, &zn1, &user) != CV_SUCCESS ||
        CVodeGetCurrentStep(mem, &h) != CV_SUCCESS)
        return SUN_NLS_MEM_NULL;
    const int by_step = h * rl1 == gamma;
    const size_t n = taper_window_length(ycor);
    double *yd = taper_window_data(yn), *fd = taper_window_data(c->f), *cd = taper_window_data(ycor),
           *dd = taper_window_data(c->delta);
    const double *pd = taper_window_data(ypred), *zd = taper_window_data(zn1);
    for (c->iteration = 0; c->iteration < c->max_iterations; c->iteration++) {
        predicted_plus(n, pd, cd, yd);
        const int status = c->rhs(t, yn, c->f, user);
        ++*c->rhs_evals;
        if (status != 0) break; /* as SUNDIALS' solver: a convergence failure */
        if (by_step) corrected(n, h, rl1, fd, zd, cd, dd);
        else corrected_gamma(n, gamma, rl1, fd, zd, cd, dd);
        c->iterations++;
        const int test = c->test(nls, ycor, c->delta, tol, w, c->test_data);
        if (test == SUN_NLS_SUCCESS) return SUN_NLS_SUCCESS;
        if (test != SUN_NLS_CONTINUE) {
            c->failures++;
            return test;
        }
    }
    c->failures++;
    return SUN_NLS_CONV_RECVR;
}

static int corrector_free(SUNNonlinearSolver nls)
{
    if (!nls) return SUN_NLS_SUCCESS;
    corrector *c = nls->content;
    if (c) {
        if (c->f) N_VDestroy(c->f);
        if (c->delta) N_VDestroy(c->delta);
        free(c);
        nls->content = NULL;
    }
    SUNNonlinSolFreeEmpty(nls);
    return SUN_NLS_SUCCESS;
}

static int corrector_set_system(SUNNonlinearSolver nls, SUNNonlinSolSysFn sys)
{
    if (!sys) return SUN_NLS_ILL_INPUT;
    CORRECTOR(nls)->sys = sys;
    return SUN_NLS_SUCCESS;
}

static int corrector_set_test(SUNNonlinearSolver nls, SUNNonlinSolConvTestFn test, void *data)
{
    if (!test) return SUN_NLS_ILL_INPUT;
    CORRECTOR(nls)->test = test;
    CORRECTOR(nls)->test_data = data;
    return SUN_NLS_SUCCESS;
}

static int corrector_set_max_iterations(SUNNonlinearSolver nls, int max_iterations)
{
    if (max_iterations < 1) return SUN_NLS_ILL_INPUT;
    CORRECTOR(nls)->max_iterations = max_iterations;
    return SUN_NLS_SUCCESS;
}

static int corrector_iterations(SUNNonlinearSolver nls, long *iterations)
{
    *iterations = CORRECTOR(nls)->iterations;
    return SUN_NLS_SUCCESS;
}

static int corrector_iteration(SUNNonlinearSolver nls, int *iteration)
{
    *iteration = CORRECTOR(nls)->iteration;
    return SUN_NLS_SUCCESS;
}

static int corrector_failures(SUNNonlinearSolver nls, long *failures)
{
    *failures = CORRECTOR(nls)->failures;
    return SUN_NLS_SUCCESS;
}

SUNNonlinearSolver cvode_corrector_new(N_Vector y, cvode_rhs_fn rhs, long *rhs_evals, SUNContext ctx)
{
    SUNNonlinearSolver nls = SUNNonlinSolNewEmpty(ctx);
    if (!nls) return NULL;
    corrector *c = calloc(1, sizeof *c);
    nls->content = c;
    if (!c || !(c->f = N_VClone(y)) || !(c->delta = N_VClone(y))) {
        corrector_free(nls);
        return NULL;
    }
    c->rhs = rhs;
    c->rhs_evals = rhs_evals;
    c->max_iterations = 3; /* SUNDIALS' default; CVODE sets its own (NLS_MAXCOR) */
    nls->ops->gettype = corrector_type;
    nls->ops->initialize = corrector_initialize;
    nls->ops->solve = corrector_solve;
    nls->ops->free = corrector_free;
    nls->ops->setsysfn = corrector_set_system;
    nls->ops->setctestfn = corrector_set_test;
    nls->ops->setmaxiters = corrector_set_max_iterations;
    nls->ops->getnumiters = corrector_iterations;
    nls->ops->getcuriter = corrector_iteration;
    nls->ops->getnumconvfails = corrector_failures;
    return nls;
}
