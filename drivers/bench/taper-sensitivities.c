/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper-sensitivities -- the calibration's Jacobian two ways, with one
 * CVODES (docs/calibration.md, "Finite differences or sensitivities").
 *
 *   taper-sensitivities [--reps K | --check] [--check-taper SENSORS.TSV]
 *   taper-sensitivities --one fd|analytic|analytic-errcon|dq|dq-errcon RTOL
 *
 * The problem is share/scenes/optimise/calibrate_sensor.nml written out in
 * SI with its two free settings explicit: a striker and 8 steel beads
 * against a rigid wall, Hertz contacts k(E) z^(3/2) with Kuwabara-Kono
 * damping A (docs/physics.md, "Viscoelastic contacts" and "Real units"),
 * the residuals the force gauge in bead 4 (the mean of its two contact
 * forces) at t = 0, 1, ..., 120 us.  The Jacobian d force(t_j) / d(E, A) is
 * computed (a) by forward differences, 1 + p runs stepped by sqrt(rtol) of
 * each setting's size as drivers/scenes/optimise/calibrate.c does, and
 * (b) by CVODES' forward sensitivities, one run, their right-hand side by
 * CVODES' difference quotients or analytic.  Both integrate with the same
 * library (the system's CVODES) and the same settings as taper's stepper:
 * Adams up to order 8, fixed-point iteration, the step band (0, 1.2).
 *
 * This executable does not link libtaper: CVODES exports the same CVode*
 * names as the optimised CVODE libtaper links, and one process cannot have
 * both.  It is a benchmark that prints figures, never a timed test;
 * --check (tests/bench) asserts only that the two Jacobians agree.
 */
#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#define N_PARAMS 2 /* Young's modulus E [Pa], the damping time A [s] */
#define MAX_BODIES 64
#define MAX_TIMES 1024

/* ---- the chain in SI ---------------------------------------------------- */
/* Bodies 0 (the striker) .. n (bead n), contact c between body c and c+1,
 * contact n between bead n and the rigid wall.  State: v_0, z_0, v_1, z_1,
 * ..., v_n, z_n (velocities and compressions, taper's variables,
 * docs/design.md), so 2(n+1) entries. */
typedef struct chain {
    int n;                 /* beads after the striker */
    double radius, poisson, density, velocity;
    double p[N_PARAMS];    /* E, A: CVODES' difference quotients perturb these */
    double mass;           /* every body: (4/3) pi rho R^3 */
    int gauge;             /* the bead whose mean contact force is measured */
    double v_scale, z_scale; /* atol's scales: V and a binary collision's maximum compression */
} chain;

/* Hertz's constant of contact c per unit E: (4/3) E* sqrt(R*), with
 * E* = E / (2 (1 - nu^2)), R* = R/2 between two beads and E* = E / (1 - nu^2),
 * R* = R against the rigid wall (docs/physics.md, "Walls", "Real units"). */
static double stiffness_per_young(const chain *ch, int c)
{
    const double one_minus = 1.0 - ch->poisson * ch->poisson;
    if (c == ch->n) return 4.0 / 3.0 / one_minus * sqrt(ch->radius);
    return 4.0 / 3.0 / (2.0 * one_minus) * sqrt(ch->radius / 2.0);
}

/* F = k (z^(3/2) + A (3/2) z^(1/2) dz/dt) while positive, else 0: the
 * library's excess_force (src/sim/dynamics.c) with no load.  The partial
 * derivatives, where wanted, for the sensitivities and the gauge's. */
typedef struct contact_force {
    double f, df_dz, df_dzdot, df_dyoung, df_damping;
} contact_force;

static contact_force force_of(const chain *ch, int c, double z, double zdot, const double *p)
{
    contact_force r = {0};
    if (!(z >= 0.0)) return r;
    const double k = p[0] * stiffness_per_young(ch, c), A = p[1], s = sqrt(z);
    const double f = k * (z * s + A * 1.5 * s * zdot);
    if (!(f > 0.0)) return r;
    r.f = f;
    r.df_dz = k * (1.5 * s + (s > 0.0 ? A * 0.75 * zdot / s : 0.0));
    r.df_dzdot = k * A * 1.5 * s;
    r.df_dyoung = f / p[0];
    r.df_damping = k * 1.5 * s * zdot;
    return r;
}

static double relative_velocity(const chain *ch, const double *y, int c)
{
    return y[2 * c] - (c < ch->n ? y[2 * c + 2] : 0.0);
}

static int rhs(sunrealtype t, N_Vector yv, N_Vector ydotv, void *user)
{
    (void)t;
    const chain *ch = user;
    const double *y = N_VGetArrayPointer(yv);
    double *ydot = N_VGetArrayPointer(ydotv);
    double left = 0.0;
    for (int c = 0; c <= ch->n; c++) {
        const double zdot = relative_velocity(ch, y, c);
        const double f = force_of(ch, c, y[2 * c + 1], zdot, ch->p).f;
        ydot[2 * c] = (left - f) / ch->mass;
        ydot[2 * c + 1] = zdot;
        left = f;
    }
    return 0;
}

/* s_i' = (df/dy) s_i + df/dp_i, analytic. */
static int sens_rhs(int ns, sunrealtype t, N_Vector yv, N_Vector ydotv, int is, N_Vector sv,
                    N_Vector sdotv, void *user, N_Vector tmp1, N_Vector tmp2)
{
    (void)ns, (void)t, (void)ydotv, (void)tmp1, (void)tmp2;
    const chain *ch = user;
    const double *y = N_VGetArrayPointer(yv), *s = N_VGetArrayPointer(sv);
    double *sdot = N_VGetArrayPointer(sdotv);
    double left = 0.0;
    for (int c = 0; c <= ch->n; c++) {
        const double zdot = relative_velocity(ch, y, c), szdot = relative_velocity(ch, s, c);
        const contact_force f = force_of(ch, c, y[2 * c + 1], zdot, ch->p);
        const double df = f.df_dz * s[2 * c + 1] + f.df_dzdot * szdot +
                          (is == 0 ? f.df_dyoung : f.df_damping);
        sdot[2 * c] = (left - df) / ch->mass;
        sdot[2 * c + 1] = szdot;
        left = df;
    }
    return 0;
}

/* The gauge's reading, and its derivative along a sensitivity s_i. */
static double gauge_force(const chain *ch, const double *y, const double *p)
{
    const int g = ch->gauge;
    return 0.5 * (force_of(ch, g - 1, y[2 * g - 1], relative_velocity(ch, y, g - 1), p).f +
                  force_of(ch, g, y[2 * g + 1], relative_velocity(ch, y, g), p).f);
}

static double gauge_sensitivity(const chain *ch, const double *y, const double *s, int is)
{
    double sum = 0.0;
    for (int c = ch->gauge - 1; c <= ch->gauge; c++) {
        const contact_force f = force_of(ch, c, y[2 * c + 1], relative_velocity(ch, y, c), ch->p);
        sum += f.df_dz * s[2 * c + 1] + f.df_dzdot * relative_velocity(ch, s, c) +
               (is == 0 ? f.df_dyoung : f.df_damping);
    }
    return 0.5 * sum;
}

static void chain_init(chain *ch, int n, double young, double damping)
{
    ch->n = n;
    ch->radius = 2.38e-3;
    ch->poisson = 0.3;
    ch->density = 8000.0;
    ch->velocity = 0.5;
    ch->p[0] = young;
    ch->p[1] = damping;
    ch->mass = 4.0 / 3.0 * acos(-1.0) * ch->density * pow(ch->radius, 3);
    ch->gauge = n >= 4 ? 4 : n;
    /* two beads at V: (5/4) (m/2) V^2 = k z^(5/2) at the deepest point */
    const double k = young * stiffness_per_young(ch, 0);
    ch->v_scale = ch->velocity;
    ch->z_scale = pow(1.25 * 0.5 * ch->mass * ch->velocity * ch->velocity / k, 0.4);
}

/* ---- one run ------------------------------------------------------------ */
typedef enum { PLAIN, SENS_DQ, SENS_ANALYTIC } run_kind;

typedef struct run_stats {
    long steps, rhs, sens_rhs;
    double cpu;
} run_stats;

static double cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_utime.tv_sec + 1e-6 * (double)u.ru_utime.tv_usec +
           (double)u.ru_stime.tv_sec + 1e-6 * (double)u.ru_stime.tv_usec;
}

static int ok(int flag, const char *what)
{
    if (flag < 0) fprintf(stderr, "taper-sensitivities: %s failed with flag %d\n", what, flag);
    return flag >= 0;
}

/* Integrates ch to each of times[0..m), writing the gauge's force into
 * force[j] and, for the sensitivity kinds, its derivatives into
 * jac[j * N_PARAMS + i].  0, or -1 with a message on stderr. */
static int run(chain *ch, double rtol, double atol, run_kind kind, int staggered, int errcon,
               const double *times, int m, double *force, double *jac, run_stats *st)
{
    const int len = 2 * (ch->n + 1);
    SUNContext ctx = NULL;
    if (SUNContext_Create(NULL, &ctx) != 0) return -1;
    int good = 1;
    void *mem = CVodeCreate(CV_ADAMS, ctx);
    N_Vector y = N_VNew_Serial(len, ctx), abstol = N_VNew_Serial(len, ctx);
    N_Vector *yS = NULL;
    SUNNonlinearSolver nls = NULL, nlsS = NULL;
    good = mem && y && abstol;
    const double t0 = cpu_seconds();
    if (good) {
        double *y0 = N_VGetArrayPointer(y), *a = N_VGetArrayPointer(abstol);
        for (int i = 0; i < len; i++) {
            y0[i] = 0.0;
            a[i] = atol * (i % 2 ? ch->z_scale : ch->v_scale);
        }
        y0[0] = ch->velocity;
    }
    good = good && ok(CVodeInit(mem, rhs, 0.0, y), "CVodeInit");
    good = good && ok(CVodeSVtolerances(mem, rtol, abstol), "CVodeSVtolerances");
    good = good && ok(CVodeSetUserData(mem, ch), "CVodeSetUserData");
    good = good && ok(CVodeSetMaxNumSteps(mem, 1000000), "CVodeSetMaxNumSteps");
    good = good && ok(CVodeSetMaxOrd(mem, 8), "CVodeSetMaxOrd");
    /* taper's step band (src/sim/stepper_cvode.c) */
    good = good && ok(CVodeSetEtaFixedStepBounds(mem, 0.0, 1.2), "CVodeSetEtaFixedStepBounds");
    if (good) nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
    good = good && nls && ok(CVodeSetNonlinearSolver(mem, nls), "CVodeSetNonlinearSolver");
    if (good && kind != PLAIN) {
        yS = N_VCloneVectorArray(N_PARAMS, y);
        good = yS != NULL;
        for (int i = 0; good && i < N_PARAMS; i++) N_VConst(0.0, yS[i]);
        good = good && ok(CVodeSensInit1(mem, N_PARAMS, staggered ? CV_STAGGERED : CV_SIMULTANEOUS,
                                         kind == SENS_ANALYTIC ? sens_rhs : NULL, yS),
                          "CVodeSensInit1");
        /* each sensitivity's absolute tolerance from the state's, scaled by
         * the parameter's size (CVODES' EE rule) */
        double pbar[N_PARAMS] = {ch->p[0], ch->p[1]};
        good = good && ok(CVodeSetSensParams(mem, ch->p, pbar, NULL), "CVodeSetSensParams");
        good = good && ok(CVodeSensEEtolerances(mem), "CVodeSensEEtolerances");
        good = good && ok(CVodeSetSensErrCon(mem, errcon ? SUNTRUE : SUNFALSE), "CVodeSetSensErrCon");
        if (good) nlsS = SUNNonlinSol_FixedPointSens(staggered ? N_PARAMS : N_PARAMS + 1, y, 0, ctx);
        good = good && nlsS;
        if (good) {
            if (staggered) {
                good = ok(CVodeSetNonlinearSolverSensStg(mem, nlsS), "CVodeSetNonlinearSolverSensStg");
            } else {
                good = ok(CVodeSetNonlinearSolverSensSim(mem, nlsS), "CVodeSetNonlinearSolverSensSim");
            }
        }
    }
    double *ys = N_VGetArrayPointer(y);
    for (int j = 0; good && j < m; j++) {
        double t = 0.0;
        if (times[j] > 0.0) good = ok(CVode(mem, times[j], y, &t, CV_NORMAL), "CVode");
        if (!good) break;
        force[j] = gauge_force(ch, ys, ch->p);
        if (kind != PLAIN) {
            if (times[j] > 0.0) good = ok(CVodeGetSens(mem, &t, yS), "CVodeGetSens");
            for (int i = 0; good && i < N_PARAMS; i++)
                jac[j * N_PARAMS + i] = gauge_sensitivity(ch, ys, N_VGetArrayPointer(yS[i]), i);
        }
    }
    st->cpu = cpu_seconds() - t0;
    long v = 0;
    st->steps = st->rhs = st->sens_rhs = 0;
    if (good && ok(CVodeGetNumSteps(mem, &v), "CVodeGetNumSteps")) st->steps = v;
    if (good && ok(CVodeGetNumRhsEvals(mem, &v), "CVodeGetNumRhsEvals")) st->rhs = v;
    if (good && kind != PLAIN && ok(CVodeGetSensNumRhsEvals(mem, &v), "CVodeGetSensNumRhsEvals"))
        st->sens_rhs = v;
    if (yS) N_VDestroyVectorArray(yS, N_PARAMS);
    if (nlsS) SUNNonlinSolFree(nlsS);
    if (nls) SUNNonlinSolFree(nls);
    CVodeFree(&mem);
    N_VDestroy(y);
    N_VDestroy(abstol);
    SUNContext_Free(&ctx);
    return good ? 0 : -1;
}

/* ---- the Jacobians ------------------------------------------------------ */
typedef struct method {
    const char *name;
    run_kind kind;
    int staggered, errcon;
} method;

/* Forward differences as calibrate.c's jacobian_y at its start point (y = 1
 * in units of each setting's size): h = sqrt(rtol) * size; 1 + p runs. */
static int jacobian_fd(chain *ch, double rtol, double atol, const double *times, int m,
                       double *f0, double *jac, run_stats *st)
{
    double *f1 = malloc(m * sizeof *f1);
    int rc = f1 ? 0 : -1;
    run_stats one = {0};
    rc = rc ? rc : run(ch, rtol, atol, PLAIN, 0, 0, times, m, f0, NULL, &one);
    *st = one;
    const double step = sqrt(rtol);
    for (int i = 0; rc == 0 && i < N_PARAMS; i++) {
        const double keep = ch->p[i], h = step * fabs(keep);
        ch->p[i] = keep + h;
        rc = run(ch, rtol, atol, PLAIN, 0, 0, times, m, f1, NULL, &one);
        ch->p[i] = keep;
        for (int j = 0; rc == 0 && j < m; j++) jac[j * N_PARAMS + i] = (f1[j] - f0[j]) / h;
        st->steps += one.steps;
        st->rhs += one.rhs;
        st->cpu += one.cpu;
    }
    free(f1);
    return rc;
}

/* Central differences, the reference's cross-check: step h = 1e-4 of each
 * setting (truncation ~h^2, integration error ~rtol/h). */
static int jacobian_central(chain *ch, double rtol, double atol, const double *times, int m,
                            double rel_step, double *jac)
{
    double *fp = malloc(m * sizeof *fp), *fm = malloc(m * sizeof *fm);
    int rc = fp && fm ? 0 : -1;
    run_stats st;
    for (int i = 0; rc == 0 && i < N_PARAMS; i++) {
        const double keep = ch->p[i], h = rel_step * fabs(keep);
        ch->p[i] = keep + h;
        rc = run(ch, rtol, atol, PLAIN, 0, 0, times, m, fp, NULL, &st);
        ch->p[i] = keep - h;
        if (rc == 0) rc = run(ch, rtol, atol, PLAIN, 0, 0, times, m, fm, NULL, &st);
        ch->p[i] = keep;
        for (int j = 0; rc == 0 && j < m; j++) jac[j * N_PARAMS + i] = (fp[j] - fm[j]) / (2 * h);
    }
    free(fp);
    free(fm);
    return rc;
}

/* The largest error of a column relative to the column's largest entry
 * (entries of the gauge's force before the pulse arrives are ~0, so a
 * pointwise relative error means nothing), the worst column. */
static double column_error(const double *jac, const double *ref, int m, int i)
{
    double scale = 0.0, err = 0.0;
    for (int j = 0; j < m; j++) {
        scale = fmax(scale, fabs(ref[j * N_PARAMS + i]));
        err = fmax(err, fabs(jac[j * N_PARAMS + i] - ref[j * N_PARAMS + i]));
    }
    return scale > 0.0 ? err / scale : err;
}

static double jacobian_error(const double *jac, const double *ref, int m)
{
    double worst = 0.0;
    for (int i = 0; i < N_PARAMS; i++) worst = fmax(worst, column_error(jac, ref, m, i));
    return worst;
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* This right-hand side against the taper driver's run of the worked
 * example at E = 193 GPa, A = 0.1 us, rtol 1e-12, sampled every microsecond
 * in bead 4 (docs/calibration.md gives the command): the largest difference
 * of the gauge's force, the peak, the samples.  0, or -1 with a message. */
static int taper_agreement(const char *path, double *diff, double *peak, int *samples)
{
    FILE *fp = fopen(path, "r");
    if (!fp) {
        fprintf(stderr, "taper-sensitivities: cannot open %s\n", path);
        return -1;
    }
    static double tt[MAX_TIMES], ft[MAX_TIMES], force[MAX_TIMES];
    char line[4096];
    int k = 0;
    while (k < MAX_TIMES && fgets(line, sizeof line, fp)) {
        double t, x, v, fl, fr, f;
        int g;
        if (sscanf(line, "%lf %d %lf %lf %lf %lf %lf", &t, &g, &x, &v, &fl, &fr, &f) == 7 && g == 4) {
            tt[k] = t;
            ft[k++] = f;
        }
    }
    fclose(fp);
    chain ch;
    chain_init(&ch, 8, 193e9, 1e-7);
    run_stats st;
    if (k < 2 || run(&ch, 1e-12, 1e-13, PLAIN, 0, 0, tt, k, force, NULL, &st) != 0) {
        fprintf(stderr, "taper-sensitivities: no samples of granule 4 in %s, or the run failed\n", path);
        return -1;
    }
    *peak = *diff = 0.0;
    for (int j = 0; j < k; j++) {
        *peak = fmax(*peak, fabs(ft[j]));
        *diff = fmax(*diff, fabs(force[j] - ft[j]));
    }
    *samples = k;
    return 0;
}

/* ---- the study ---------------------------------------------------------- */
static int study(int reps, const char *taper_sensors)
{
    const double atol = 1e-13; /* taper's default */
    static double times[MAX_TIMES], jac[MAX_TIMES * N_PARAMS], ref[MAX_TIMES * N_PARAMS],
        cen[MAX_TIMES * N_PARAMS], force[MAX_TIMES], ref_force[MAX_TIMES];
    const int m = 121; /* sensor_force.tsv: every microsecond to 120 us */
    for (int j = 0; j < m; j++) times[j] = 1e-6 * j;
    chain ch;
    printf("# taper-sensitivities: the Jacobian of calibrate_sensor.nml's residuals (bead 4's force\n"
           "# at t = 0..120 us) in (E, A) at the fit's start, E = 150 GPa, A = 0.2 us, two ways,\n"
           "# both integrated by the same CVODES (the system's SUNDIALS %s, as the distribution\n"
           "# built it), Adams order <= 8 with fixed-point iteration as taper's stepper.\n",
           SUNDIALS_VERSION);

    if (taper_sensors) {
        double diff, peak;
        int k;
        if (taper_agreement(taper_sensors, &diff, &peak, &k) != 0) return 1;
        printf("# this right-hand side against taper's sensors.tsv (E = 193 GPa, A = 0.1 us, rtol 1e-12,\n"
               "# %d samples of bead 4): largest difference %.3g N, %.3g of the peak %.6g N\n",
               k, diff, diff / peak, peak);
    }

    chain_init(&ch, 8, 150e9, 2e-7);
    run_stats st;
    if (run(&ch, 1e-12, atol, SENS_ANALYTIC, 1, 1, times, m, force, ref, &st) != 0) return 1;
    double refscale[N_PARAMS] = {0};
    for (int j = 0; j < m; j++)
        for (int i = 0; i < N_PARAMS; i++) refscale[i] = fmax(refscale[i], fabs(ref[j * N_PARAMS + i]));
    if (jacobian_central(&ch, 1e-13, atol * 0.1, times, m, 1e-4, cen) != 0) return 1;
    printf("# reference: analytic sensitivities at rtol 1e-12 (columns' largest |entries| %.4g N/Pa,\n"
           "# %.4g N/s); central differences (h = 1e-4 of each, rtol 1e-13) differ from them by\n"
           "# %.2g (E) and %.2g (A) of those\n",
           refscale[0], refscale[1], column_error(cen, ref, m, 0), column_error(cen, ref, m, 1));
    printf("# err_E, err_A: a column's largest |J - J_ref| over its largest |entry|; f_err: the\n"
           "# run's largest error in the force itself over the peak force (fd: its unstepped run);\n"
           "# cpu: median of n repetitions taken in turn with the other methods' (none more past 10 s),\n"
           "# seconds (getrusage); runs: cpu over one plain run's (a third of fd's) at that rtol\n"
           "# (the machine is shared: read ratios within one run);\n"
           "# rhs: right-hand sides; sens_rhs: CVODES' count of sensitivity right-hand sides\n"
           "# (by its difference quotients each costs 1-2 right-hand sides); errcon: the\n"
           "# sensitivities in the error test (CVodeSetSensErrCon) or not\n");
    printf("%-30s %6s %9s %9s %9s %10s %7s %8s %9s %9s %2s\n", "method", "rtol", "err_E", "err_A",
           "f_err", "cpu[s]", "runs", "steps", "rhs", "sens_rhs", "n");

    static const method methods[] = {
        {"fd, 1+p runs", PLAIN, 0, 0},
        {"sens analytic stg errcon", SENS_ANALYTIC, 1, 1},
        {"sens analytic sim errcon", SENS_ANALYTIC, 0, 1},
        {"sens analytic stg", SENS_ANALYTIC, 1, 0},
        {"sens analytic sim", SENS_ANALYTIC, 0, 0},
        {"sens dq stg errcon", SENS_DQ, 1, 1},
        {"sens dq sim errcon", SENS_DQ, 0, 1},
        {"sens dq stg", SENS_DQ, 1, 0},
        {"sens dq sim", SENS_DQ, 0, 0},
    };
    const double rtols[] = {1e-10, 1e-8, 1e-6};
    const int n_methods = (int)(sizeof methods / sizeof methods[0]);
    double *cpus = malloc((size_t)reps * n_methods * sizeof *cpus), *f = malloc(m * sizeof *f);
    if (!cpus || !f) return 1;
    double peak = 0.0;
    for (int j = 0; j < m; j++) peak = fmax(peak, fabs(force[j]));
    memcpy(ref_force, force, m * sizeof *force);
    /* The repetitions go round the methods, so that the load of the shared
     * machine falls on all of them alike; a method past 10 s of CPU is
     * not repeated. */
    enum { MAX_METHODS = 16 };
    for (size_t r = 0; r < sizeof rtols / sizeof rtols[0]; r++) {
        run_stats s[MAX_METHODS] = {{0}};
        double spent[MAX_METHODS] = {0}, ferr[MAX_METHODS] = {0}, err[MAX_METHODS][N_PARAMS];
        int done[MAX_METHODS] = {0};
        for (int k = 0; k < reps; k++) {
            for (int q = 0; q < n_methods; q++) {
                if (spent[q] >= 10.0) continue;
                int rc = methods[q].kind == PLAIN
                             ? jacobian_fd(&ch, rtols[r], atol, times, m, f, jac, &s[q])
                             : run(&ch, rtols[r], atol, methods[q].kind, methods[q].staggered,
                                   methods[q].errcon, times, m, f, jac, &s[q]);
                if (rc != 0) return 1;
                cpus[q * reps + done[q]++] = s[q].cpu;
                spent[q] += s[q].cpu;
                ferr[q] = 0.0;
                for (int j = 0; j < m; j++) ferr[q] = fmax(ferr[q], fabs(f[j] - ref_force[j]));
                for (int i = 0; i < N_PARAMS; i++) err[q][i] = column_error(jac, ref, m, i);
            }
        }
        double run_cpu = 0.0; /* one plain run: a third of fd's 1 + p */
        for (int q = 0; q < n_methods; q++) {
            double *c = cpus + q * reps;
            qsort(c, (size_t)done[q], sizeof *c, compare_double);
            const double cpu = c[done[q] / 2];
            if (q == 0) run_cpu = cpu / (1 + N_PARAMS);
            printf("%-30s %6.0e %9.2e %9.2e %9.2e %10.3e %7.2f %8ld %9ld %9ld %2d\n", methods[q].name,
                   rtols[r], err[q][0], err[q][1], ferr[q] / peak, cpu, cpu / run_cpu, s[q].steps,
                   s[q].rhs, s[q].sens_rhs, done[q]);
        }
        fflush(stdout);
    }
    free(cpus);
    free(f);
    printf("# fd's runs are independent: taper's calibration has the unstepped run already (its\n"
           "# residuals) and makes the p = %d stepped ones at once on its threads, so its Jacobian\n"
           "# costs p runs of CPU and about one run of wall time on 2 cores; a sensitivity run is\n"
           "# one thread.\n", N_PARAMS);
    return 0;
}

/* --check: a striker and 3 beads, the forward-difference Jacobian against
 * the sensitivities' (difference-quotient and analytic) at rtol 1e-8, where
 * forward differences are good to about 2 sqrt(rtol) = 2e-4 of a column;
 * with --check-taper, also this right-hand side against the library's:
 * the gauge's force within 1e-8 of its peak, both at rtol 1e-12. */
static int check(const char *taper_sensors)
{
    const double rtol = 1e-8, atol = 1e-13, bound = 20.0 * sqrt(rtol);
    static double times[64], fd[64 * N_PARAMS], sens[64 * N_PARAMS], force[64];
    const int m = 41;
    for (int j = 0; j < m; j++) times[j] = 1e-6 * j;
    chain ch;
    chain_init(&ch, 3, 193e9, 1e-7);
    run_stats st;
    if (jacobian_fd(&ch, rtol, atol, times, m, force, fd, &st) != 0) return 1;
    int failed = 0;
    for (int kind = SENS_DQ; kind <= SENS_ANALYTIC; kind++) {
        if (run(&ch, rtol, atol, (run_kind)kind, 1, 1, times, m, force, sens, &st) != 0) return 1;
        const double e = jacobian_error(fd, sens, m);
        printf("check: %s sensitivities against forward differences: %.3g (bound %.3g)\n",
               kind == SENS_DQ ? "difference-quotient" : "analytic", e, bound);
        if (!(e < bound)) failed = 1;
    }
    /* and the Jacobian is no accident: a column of zeros would also agree
     * with another column of zeros */
    double col[N_PARAMS] = {0};
    for (int j = 0; j < m; j++)
        for (int i = 0; i < N_PARAMS; i++) col[i] = fmax(col[i], fabs(sens[j * N_PARAMS + i]));
    if (!(col[0] > 0.0 && col[1] > 0.0)) {
        printf("check: a column of the Jacobian is zero\n");
        failed = 1;
    }
    if (taper_sensors) {
        double diff, peak;
        int k;
        if (taper_agreement(taper_sensors, &diff, &peak, &k) != 0) return 1;
        printf("check: bead 4's force against the taper driver's, %d samples: %.3g of the peak %.6g N "
               "(bound 1e-8)\n", k, diff / peak, peak);
        if (!(diff <= 1e-8 * peak) || !(peak > 1.0)) failed = 1;
    }
    return failed;
}

/* --one KIND RTOL: one Jacobian of the study's, once, for an instruction
 * count (valgrind --tool=callgrind) that the machine's load cannot move. */
static int one_jacobian(const char *kind, double rtol)
{
    static const struct { const char *name; run_kind kind; int errcon; } kinds[] = {
        {"fd", PLAIN, 0}, {"analytic", SENS_ANALYTIC, 0}, {"analytic-errcon", SENS_ANALYTIC, 1},
        {"dq", SENS_DQ, 0}, {"dq-errcon", SENS_DQ, 1},
    };
    static double times[MAX_TIMES], jac[MAX_TIMES * N_PARAMS], force[MAX_TIMES];
    const int m = 121;
    for (int j = 0; j < m; j++) times[j] = 1e-6 * j;
    chain ch;
    chain_init(&ch, 8, 150e9, 2e-7);
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        if (strcmp(kind, kinds[k].name)) continue;
        run_stats st;
        int rc = kinds[k].kind == PLAIN
                     ? jacobian_fd(&ch, rtol, 1e-13, times, m, force, jac, &st)
                     : run(&ch, rtol, 1e-13, kinds[k].kind, 1, kinds[k].errcon, times, m, force, jac, &st);
        if (rc == 0)
            printf("%s rtol %g: steps %ld, rhs %ld, sens_rhs %ld\n", kind, rtol, st.steps, st.rhs,
                   st.sens_rhs);
        return rc ? 1 : 0;
    }
    fprintf(stderr, "taper-sensitivities: --one wants fd, analytic, analytic-errcon, dq or dq-errcon\n");
    return 2;
}

int main(int argc, char **argv)
{
    int reps = 11, check_only = 0;
    const char *taper_sensors = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--check")) {
            check_only = 1;
            continue;
        }
        if (!strcmp(argv[i], "--one") && i + 2 < argc) return one_jacobian(argv[i + 1], atof(argv[i + 2]));
        if (!strcmp(argv[i], "--reps") && i + 1 < argc) {
            reps = atoi(argv[++i]);
            if (reps < 1) {
                fprintf(stderr, "taper-sensitivities: --reps wants a positive count\n");
                return 2;
            }
        } else if (!strcmp(argv[i], "--check-taper") && i + 1 < argc) {
            taper_sensors = argv[++i];
        } else {
            fprintf(stderr, "usage: taper-sensitivities [--reps K | --check] [--check-taper SENSORS.TSV] | --one KIND RTOL\n");
            return 2;
        }
    }
    if (check_only) return check(taper_sensors);
    return study(reps, taper_sensors) ? 1 : 0;
}
