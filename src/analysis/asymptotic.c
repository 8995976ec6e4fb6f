/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * asymptotic.c -- large-k laws of the binary collision approximation for the
 * four tapering protocols (paper, Secs. III-IV), for any contact exponent n.
 *
 * Everything follows from eq. (18),
 *     T_k = sqrt(pi) G(n) (n mu_k / (2 r_k))^(1/n) v_k^(2/n - 1),
 *     G(n) = Gamma(1+1/n) / Gamma(1/n+1/2),
 * with mu_k ~ m_k/2 ~ R^3/2 and r_k ~ R^(1/2) for slowly varying radii, so
 * that (mu/r)^(1/n) ~ R^(5/(2n)).  The derivations are summarised next to
 * each function; tests/unit/test_asymptotic.c checks each one against the exact
 * sums and products of taper_theory_compute.  Equation numbers are those
 * printed in arXiv:0905.4512.
 */
#include "taper.h"

#include <gsl/gsl_sf_gamma.h>
#include <math.h>

static int valid_n(double n) { return n > 1.0 && isfinite(n); }

/* Residence-time exponent in R (linear chains): T ~ R^beta, beta = 3/2 - 1/(2n).
 * (mu/r)^(1/n) ~ R^(5/(2n)) and v ~ R^(-3/2) give v^(2/n-1) ~ R^(3/2 - 3/n). */
static double beta_of(double n) { return 1.5 - 0.5 / n; }

#define LAW_NAME(constant, name) [constant] = name,
static const char *const law_names[] = {TAPER_LAW_LIST(LAW_NAME)};

const char *taper_law_name(taper_law law)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    if ((unsigned)law >= TAPER_N_LAWS) return NULL;
    return law_names[law];
}

double taper_asymptotic_exponent(taper_law law, double n)
{
    if (!valid_n(n)) return NAN;
    const double b1 = beta_of(n) + 1.0; /* t ~ k^b1 (backward), C - t ~ R^b1 (forward) */
    switch (law) {
    case TAPER_LAW_V_OF_K: return -1.5;     /* v_{k+1}/v_k = 1 - 3/(2k) + O(k^-2) */
    case TAPER_LAW_T_RES_OF_K: return b1 - 1.0;
    case TAPER_LAW_T_OF_K: return b1;       /* sum of k^beta */
    case TAPER_LAW_K_OF_T: return 1.0 / b1;
    case TAPER_LAW_V_OF_T: return -1.5 / b1;
    case TAPER_LAW_X_OF_T: return 2.0 / b1; /* X0 ~ S k^2 */
    case TAPER_LAW_C_OF_T: return 2.0 / b1 - 1.0;
    case TAPER_LAW_FWD_V_OF_K: return -1.5; /* v ~ R_k^(-3/2), R_k = (1+S)(1 - b k) */
    case TAPER_LAW_FWD_T_OF_K: return b1;   /* sum_{j>k} R_j^beta ~ R_k^b1 */
    case TAPER_LAW_FWD_V_OF_T: return -1.5 / b1;
    default: return NAN;
    }
}

double taper_asymptotic_A(double q)
{
    if (!(q < 1.0) || !isfinite(q)) return NAN;
    return 0.5 * (1.0 + pow(1.0 - q, -3.0)); /* eq. (35) */
}

/* ln A = ln(1 + ((1-q)^-3 - 1)/2) without cancellation at small q. */
double taper_asymptotic_lnA(double q)
{
    if (!(q < 1.0) || !isfinite(q)) return NAN;
    return log1p(0.5 * expm1(-3.0 * log1p(-q)));
}

/* mu_k ~ (1-q)^(-3k), r_k ~ (1-q)^(-k/2) and v_k ~ A^-k exactly (eqs.
 * (36), (37), (34)), so ln T_k is exactly linear in k with
 * slope -(5/(2n)) ln(1-q) + (1 - 2/n) ln A. */
double taper_asymptotic_eta(double q, double n)
{
    if (!valid_n(n)) return NAN;
    double lnA = taper_asymptotic_lnA(q);
    if (isnan(lnA)) return NAN;
    return (1.0 - 2.0 / n) * lnA - 2.5 / n * log1p(-q);
}

/* v_k = A^(1-k) and t ~ e^(eta k): ln v = -(ln A / eta) ln t + const. */
double taper_asymptotic_f(double q, double n)
{
    double eta = taper_asymptotic_eta(q, n);
    if (isnan(eta) || eta == 0.0) return NAN;
    return taper_asymptotic_lnA(q) / eta;
}

/* X0(k) = (2-q)/q ((1-q)^(1-k) - 1) ~ e^(-k ln(1-q)) (eq. (42)) and
 * t ~ e^(eta k): X ~ t^(-ln(1-q)/eta).  For n = 5/2,
 * -ln(1-q) = eta - ln A / 5, hence 1 - f/5 as in eq. (44). */
double taper_asymptotic_position_exponent(double q, double n)
{
    if (!(q > 0.0)) return NAN;
    double eta = taper_asymptotic_eta(q, n);
    if (isnan(eta)) return NAN;
    return -log1p(-q) / eta;
}

double taper_asymptotic_speed_exponent(double q, double n)
{
    return taper_asymptotic_position_exponent(q, n) - 1.0;
}

/* T_k = T_1 e^((k-1) eta) exactly, so t_k = sum_{j<=k} T_j = tau (e^(k eta) - 1)
 * with tau = T_1 / (e^eta - 1); with e^((k-1) eta) = 1 + t_{k-1}/tau,
 * v_k = e^(-(k-1) ln A) = (1 + t_{k-1}/tau)^(-f).  A continuum sum
 * (integral over k) would give T_1 / eta instead: the same to O(eta). */
double taper_asymptotic_timescale(double q, double n)
{
    double eta = taper_asymptotic_eta(q, n);
    if (isnan(eta) || eta == 0.0) return NAN;
    double mu1 = 1.0 / (1.0 + pow(1.0 - q, 3.0)); /* eq. (36), k = 1 */
    double r1 = 1.0 / sqrt(1.0 - 0.5 * q);       /* eq. (37), k = 1 */
    return taper_theory_collision_time(mu1, r1, 1.0, n) / expm1(eta);
}

double taper_asymptotic_M(double q, double n)
{
    if (!(q > 0.0) || !isfinite(q)) return NAN;
    return taper_asymptotic_timescale(-q, n);
}

/* Leading order: T_k ~ T0 R_k^beta with T0 = sqrt(pi) G(n) (n/4)^(1/n)
 * (mu -> R^3/2, r -> R^(1/2), v -> R^(-3/2)); R_k steps by S, so
 * sum_k R_k^beta -> (1/S) int_0^1 R^beta dR = 1 / ((beta+1) S). */
double taper_asymptotic_C0(double S, double n)
{
    if (!(S > 0.0 && S < 1.0) || !valid_n(n)) return NAN;
    double T0 = sqrt(3.14159265358979323846) * exp(gsl_sf_lngamma(1.0 + 1.0 / n) - gsl_sf_lngamma(1.0 / n + 0.5))
                * pow(n / 4.0, 1.0 / n);
    return T0 / ((beta_of(n) + 1.0) * S);
}

/* First correction.  With eps_k = S / R_k (R_{k+1} = R_k (1 - eps)):
 *   mu/r = (R^(5/2)/2) (1 - 5 eps/4 + O(eps^2)),
 *   ln v_{k+1} - ln v_k = -3/2 ln(1 - eps) - 9 eps^2/8 + O(eps^3), so
 *   v_k = R_k^(-3/2) exp(-9/8 S (1/R_k - 1)) to O(S),
 * hence T_k = T0 R_k^beta (1 + a eps_k + b S), a = -5/(4n) + 9/8 (1 - 2/n),
 * b = -9/8 (1 - 2/n).  Summing with Euler-Maclaurin (the endpoint R = 1
 * adds 1/2) and S sum R^(beta-1) -> 1/beta, S sum R^beta -> 1/(beta+1):
 *   C = C0 (1 + c1 S),  c1 = (beta+1)/2 + a (beta+1)/beta + b,
 * c1 = 57/130 = 0.4385 for n = 5/2.  Remaining error O(S^2) (the end of the
 * chain, where eps is not small, contributes O(S^(beta+1)) relative). */
double taper_asymptotic_C(double S, double n)
{
    double C0 = taper_asymptotic_C0(S, n);
    if (isnan(C0)) return NAN;
    double beta = beta_of(n), w = 1.0 - 2.0 / n;
    double a = -1.25 / n + 1.125 * w, b = -1.125 * w;
    double c1 = 0.5 * (beta + 1.0) + a * (beta + 1.0) / beta + b;
    return C0 * (1.0 + c1 * S);
}

/* R_k = 1 - S(k-1) = (1+S)(1 - k S/(1+S)): eq. (50)'s 1 - k/(1 + 1/S). */
double taper_asymptotic_forward_linear_b(double S)
{
    if (!(S > 0.0 && S < 1.0)) return NAN;
    return S / (1.0 + S);
}
