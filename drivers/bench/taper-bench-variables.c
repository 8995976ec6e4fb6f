/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper-bench-variables -- why the dynamics integrates compressions.
 *
 * Integrates the same backward linear chain (whole chain, CVODE Adams of
 * order <= 6, fixed-point iteration, atol = 5e-4 rtol) in displacement
 * variables (x_k, v_k) and in compression variables (v_k, z_k = x_k - x_{k+1})
 * up to time T, and reports the largest velocity error against a compression
 * run at rtol 1e-13, relative to the largest velocity.  Self-contained on
 * purpose: it is the experiment behind a design decision (docs/design.md),
 * not a use of libtaper.
 *
 *   taper-bench-variables N S T        e.g.  150 0.5 20000   and   150 0 150
 */
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct {
    size_t n;
    double *mass, *contact;
} chain;

static double force(const chain *c, size_t k, double z)
{
    return z > 0.0 ? c->contact[k] * z * sqrt(z) : 0.0;
}

/* x_k at 2k, v_k at 2k+1 (0-based k) */
static int rhs_displacements(double t, N_Vector yv, N_Vector dv, void *user)
{
    (void)t;
    const chain *c = user;
    const double *y = N_VGetArrayPointer(yv);
    double *d = N_VGetArrayPointer(dv), left = 0.0;
    for (size_t k = 0; k < c->n; k++) {
        double f = k + 1 < c->n ? force(c, k, y[2 * k] - y[2 * k + 2]) : 0.0;
        d[2 * k] = y[2 * k + 1];
        d[2 * k + 1] = (left - f) / c->mass[k];
        left = f;
    }
    return 0;
}

/* v_k at 2k, z_k at 2k+1 (as src/sim/dynamics.h) */
static int rhs_compressions(double t, N_Vector yv, N_Vector dv, void *user)
{
    (void)t;
    const chain *c = user;
    const double *y = N_VGetArrayPointer(yv);
    double *d = N_VGetArrayPointer(dv), left = 0.0;
    for (size_t k = 0; k < c->n; k++) {
        double f = k + 1 < c->n ? force(c, k, y[2 * k + 1]) : 0.0;
        double v_next = k + 1 < c->n ? y[2 * k + 2] : 0.0;
        d[2 * k] = (left - f) / c->mass[k];
        d[2 * k + 1] = y[2 * k] - v_next;
        left = f;
    }
    return 0;
}

/* Velocities at t_end; NULL on failure. */
static double *solve(chain *c, int compressions, double rtol, double t_end, long *steps)
{
    SUNContext ctx;
    if (SUNContext_Create(NULL, &ctx)) return NULL;
    N_Vector y = N_VNew_Serial((sunindextype)(2 * c->n), ctx);
    N_VConst(0.0, y);
    double *yd = N_VGetArrayPointer(y);
    yd[compressions ? 0 : 1] = 1.0; /* v_1 = 1 */
    void *cv = CVodeCreate(CV_ADAMS, ctx);
    SUNNonlinearSolver nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
    int flag = CVodeInit(cv, compressions ? rhs_compressions : rhs_displacements, 0.0, y);
    if (!flag) flag = CVodeSStolerances(cv, rtol, rtol * 5e-4);
    if (!flag) flag = CVodeSetUserData(cv, c);
    if (!flag) flag = CVodeSetMaxNumSteps(cv, -1);
    if (!flag) flag = CVodeSetMaxOrd(cv, 6);
    if (!flag) flag = CVodeSetNonlinearSolver(cv, nls);
    double t = 0.0;
    if (!flag) flag = CVode(cv, t_end, y, &t, CV_NORMAL);
    CVodeGetNumSteps(cv, steps);
    double *v = flag < 0 ? NULL : malloc(c->n * sizeof(double));
    for (size_t k = 0; v && k < c->n; k++) v[k] = yd[compressions ? 2 * k : 2 * k + 1];
    CVodeFree(&cv);
    SUNNonlinSolFree(nls);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return v;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: %s N S T\n", argv[0]);
        return 2;
    }
    chain c = {.n = (size_t)atol(argv[1])};
    double s = atof(argv[2]), t_end = atof(argv[3]);
    c.mass = malloc(c.n * sizeof(double));
    c.contact = malloc(c.n * sizeof(double));
    for (size_t k = 0; k < c.n; k++) {
        double a = 1.0 + s * (double)k, b = a + s;
        c.mass[k] = a * a * a;
        c.contact[k] = sqrt(2.0 * a * b / (a + b));
    }
    long steps;
    double *ref = solve(&c, 1, 1e-13, t_end, &steps);
    if (!ref) return 1;
    double vmax = 0.0;
    for (size_t k = 0; k < c.n; k++) vmax = fmax(vmax, fabs(ref[k]));
    printf("variables\trtol\tsteps\tmax_velocity_error\n");
    for (int compressions = 0; compressions < 2; compressions++) {
        for (double rtol = 1e-8; rtol >= 1e-12; rtol /= 100.0) {
            double *v = solve(&c, compressions, rtol, t_end, &steps), e = 0.0;
            if (!v) return 1;
            for (size_t k = 0; k < c.n; k++) e = fmax(e, fabs(v[k] - ref[k]) / vmax);
            printf("%s\t%.0e\t%ld\t%.2e\n", compressions ? "compressions" : "displacements", rtol, steps, e);
            free(v);
        }
    }
    free(ref);
    free(c.mass);
    free(c.contact);
    return 0;
}
