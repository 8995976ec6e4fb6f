#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""dense_output.py -- derives the dense output of method rk8 (the block
"the dense output" of src/sim/stepper_rk8_tableau.h) and prints it as C.

    python3 share/rk8pd/dense_output.py > block.h     # needs mpmath (python3-mpmath)
    python3 share/rk8pd/dense_output.py --compare     # the node sets compared

Prince and Dormand's RK8(7)13M (GSL's rk8pd) has no continuous extension of
its own order from its 13 stages and y' at the step's end: the weights
b_i(theta) of y(t0 + theta h) = y0 + h sum_i b_i(theta) k_i reach order 5
only.  More stages raise it, as Enright, Jackson, Norsett and Thomsen
("Interpolants for Runge-Kutta formulas", ACM TOMS 12 (1986) 193) and
Hairer, Norsett and Wanner ("Solving ODEs I", II.6: DOP853's dense output
of order 7, three stages more) do it: a new stage whose internal value is
accurate to order q at its node c (its row meets the conditions
sum_j a_ij Phi_j(t) = c^|t| / gamma(t) of every rooted tree t with
|t| <= q) gives a slope of that accuracy.  Here, measured on the rooted
trees (the order conditions, HNW II.2):
  - two stages of stage order 5 (nodes C5) make order 6 reachable, and
  - three more of stage order 6 (nodes C6), built on those, order 7;
  - fewer do not: one stage of order 5, or two and then one or two of
    order 6, leave the conditions of order 6 or 7 inconsistent.
So five stages, only in a step that has a root or an output inside it
(stepper_rk8.c).  The rows leave out stages 2..5 (of stage order 1..3);
the weights b_i(theta) are polynomials of degree 8 in theta meeting every
condition of order <= 7 at every theta, with b(0) = 0, b'(0) = e_1 (y'
at the start), b(1) = b (the step's y1) and b'(1) = e_14 (y' at the end),
stages 2..5 and the two of order 5 weighing nothing; the freedom left
(a few dimensions) minimises the order-8 residuals integrated over
[0, 1].  The nodes: of the sets in NODE_SETS (--compare prints each one's
largest order-8 residual norm on [0, 1], 4.8e-5 to 7.3e-5, and its
largest weight coefficient), one with five distinct nodes, a residual
near the smallest (6.1e-5) and the smallest coefficients (C5, C6).  The weights are printed in the Bernstein basis
(binomials folded in), whose coefficients are of the size of the
weights' values, so that they are evaluated to a few rounding units.

tests/unit/test_rk8.c checks the printed doubles against the order
conditions in long double (coefficients_meet_their_order_conditions).
Takes a minute or two.
"""

import sys
from fractions import Fraction as F
from functools import lru_cache

from mpmath import binomial, cholesky, matrix, mp, mpf, sqrt

mp.dps = 40
RANK_TOL = mpf(10) ** -16  # GSL's rationals meet the conditions to ~1e-18
NODE_SETS = [("0.5,0.25", "0.3,0.6,0.9"), ("0.4,0.7", "0.1,0.4,0.7"), ("0.4,0.7", "0.2,0.5,0.8"),
             ("0.3,0.6", "0.1,0.4,0.7"), ("0.5,0.25", "0.2,0.5,0.8"), ("0.4,0.7", "0.3,0.6,0.9"),
             ("0.5,0.8", "0.2,0.5,0.8"), ("0.5,0.8", "0.1,0.4,0.7")]
C5 = [mpf("0.5"), mpf("0.25")]            # stage order 5
C6 = [mpf("0.3"), mpf("0.6"), mpf("0.9")]  # stage order 6
DEGREE = 8
ORDER = 7

# ---- rk8pd as GSL has it (ode-initval2/rk8pd.c) ------------------------------
ROWS = [
    [],
    [F(1, 18)],
    [F(1, 48), F(1, 16)],
    [F(1, 32), 0, F(3, 32)],
    [F(5, 16), 0, F(-75, 64), F(75, 64)],
    [F(3, 80), 0, 0, F(3, 16), F(3, 20)],
    [F(29443841, 614563906), 0, 0, F(77736538, 692538347), F(-28693883, 1125000000),
     F(23124283, 1800000000)],
    [F(16016141, 946692911), 0, 0, F(61564180, 158732637), F(22789713, 633445777),
     F(545815736, 2771057229), F(-180193667, 1043307555)],
    [F(39632708, 573591083), 0, 0, F(-433636366, 683701615), F(-421739975, 2616292301),
     F(100302831, 723423059), F(790204164, 839813087), F(800635310, 3783071287)],
    [F(246121993, 1340847787), 0, 0, F(-37695042795, 15268766246), F(-309121744, 1061227803),
     F(-12992083, 490766935), F(6005943493, 2108947869), F(393006217, 1396673457),
     F(123872331, 1001029789)],
    [F(-1028468189, 846180014), 0, 0, F(8478235783, 508512852), F(1311729495, 1432422823),
     F(-10304129995, 1701304382), F(-48777925059, 3047939560), F(15336726248, 1032824649),
     F(-45442868181, 3398467696), F(3065993473, 597172653)],
    [F(185892177, 718116043), 0, 0, F(-3185094517, 667107341), F(-477755414, 1098053517),
     F(-703635378, 230739211), F(5731566787, 1027545527), F(5232866602, 850066563),
     F(-4093664535, 808688257), F(3962137247, 1805957418), F(65686358, 487910083)],
    [F(403863854, 491063109), 0, 0, F(-5068492393, 434740067), F(-411421997, 543043805),
     F(652783627, 914296604), F(11173962825, 925320556), F(-13158990841, 6184727034),
     F(3936647629, 1978049680), F(-160528059, 685178525), F(248638103, 1413531060), 0],
]
B = [F(14005451, 335480064), 0, 0, 0, 0, F(-59238493, 1068277825), F(181606767, 758867731),
     F(561292985, 797845732), F(-1041891430, 1371343529), F(760417239, 1151165299),
     F(118820643, 751138087), F(-528747749, 2220607170), F(1, 4)]
END_SLOPE = 13              # k_14 = f(y1), 0-based
LEFT_OUT_OF_ROWS = {1, 2, 3, 4}  # stages 2..5


def to_mp(x):
    return mpf(x.numerator) / x.denominator if isinstance(x, F) else mpf(x)


# ---- rooted trees -------------------------------------------------------------
@lru_cache(None)
def trees(n):
    """the rooted trees with n vertices, each a sorted tuple of its children"""
    if n == 1:
        return [()]
    out = set()

    def children(left, largest):
        if left == 0:
            yield ()
            return
        for size in range(min(left, largest), 0, -1):
            for t in trees(size):
                for rest in children(left - size, size):
                    yield (t,) + rest
    for c in children(n - 1, n - 1):
        out.add(tuple(sorted(c)))
    return sorted(out)


def order(t):
    return 1 + sum(order(c) for c in t)


def gamma(t):
    g = order(t)
    for c in t:
        g *= gamma(c)
    return g


TREES = {n: trees(n) for n in range(1, ORDER + 2)}


def stage_weights(A, nmax):
    """Phi(t)_i = prod over children c of (A Phi(c))_i, per order, per tree"""
    s, cache = len(A), {}

    def phi(t):
        if t not in cache:
            v = [mpf(1)] * s
            for c in t:
                pc = phi(c)
                v = [v[i] * sum(A[i][j] * pc[j] for j in range(i)) for i in range(s)]
            cache[t] = v
        return cache[t]
    return {n: [phi(t) for t in TREES[n]] for n in range(1, nmax + 1)}


# ---- linear algebra (truncated SVD: the rationals meet the conditions to ~1e-18) --
def padded(rows, rhs):
    m, n = len(rows), len(rows[0])
    M = matrix(max(m, n), n)
    for i, r in enumerate(rows):
        for j, x in enumerate(r):
            M[i, j] = x
    return M, matrix(list(rhs) + [0] * (max(m, n) - m))


def solve(rows, rhs):
    """least-squares solution of least norm, its residual, and a basis of the null space"""
    M, r = padded(rows, rhs)
    U, S, V = mp.svd_r(M)
    rank = sum(1 for i in range(min(M.rows, M.cols)) if S[i] > RANK_TOL * S[0])
    Ur = U.T * r
    x = [sum(Ur[i] / S[i] * V[i, j] for i in range(rank)) for j in range(M.cols)]
    residual = mp.norm(M * matrix(x) - r)
    return x, residual, [[V[i, j] for j in range(M.cols)] for i in range(rank, V.rows)]


# ---- the construction -----------------------------------------------------------
def tableau():
    """rk8pd's 13 stages and y' at the step's end as a 14th (its row: b)"""
    A = [[mpf(0)] * 14 for _ in range(14)]
    for i, row in enumerate(ROWS):
        for j, a in enumerate(row):
            A[i][j] = to_mp(a)
    A[END_SLOPE] = [to_mp(b) for b in B] + [mpf(0)]
    return A


def add_stage(A, c, q):
    """a stage at node c whose value is of order q: its row (of least norm)"""
    W = stage_weights(A, q)
    cols = [j for j in range(len(A)) if j not in LEFT_OUT_OF_ROWS]
    rows, rhs = [], []
    for n in range(1, q + 1):
        for t, w in zip(TREES[n], W[n]):
            rows.append([w[j] for j in cols])
            rhs.append(c ** n / gamma(t))
    x, residual, _ = solve(rows, rhs)
    if residual > 1e-12:
        sys.exit(f"no stage of stage order {q} at c = {c} (residual {residual})")
    row = [mpf(0)] * (len(A) + 1)
    for k, j in enumerate(cols):
        row[j] = x[k]
    return [r + [mpf(0)] for r in A] + [row]


def dense_weights(A, weightless):
    """beta[i][m-1], b_i(theta) = sum_m beta_im theta^m: order ORDER, the ends as the docstring says"""
    s = len(A)
    cols = [j for j in range(s) if j not in weightless]
    W = stage_weights(A, ORDER + 1)
    G = [[w[j] for j in cols] for n in range(1, ORDER + 1) for w in W[n]]
    powers = [(n, mpf(1) / gamma(t)) for n in range(1, ORDER + 1) for t in TREES[n]]
    # each power m of theta: G beta_m = [order == m] / gamma, so beta_m = x_m + N z_m
    xs, worst = [], mpf(0)
    for m in range(1, DEGREE + 1):
        x, residual, null = solve(G, [g if n == m else 0 for n, g in powers])
        xs.append(x)
        worst = max(worst, residual)
    if worst > 1e-12:  # (consistent ones: ~1e-15; the sets of too few stages: ~1e-3)
        sys.exit(f"the conditions of order {ORDER} are inconsistent (residual {worst})")
    k, nc = len(null), len(cols)
    b1 = [to_mp(B[j]) if j < len(B) else mpf(0) for j in cols]

    def z(m, q):
        return (m - 1) * k + q
    rows, rhs = [], []
    for i in range(nc):  # b(1) = b, b'(1) = e_14, b'(0) = e_1
        for weight, value, powers_used in ((lambda m: 1, b1[i], range(1, DEGREE + 1)),
                                           (lambda m: m, 1 if cols[i] == END_SLOPE else 0,
                                            range(1, DEGREE + 1)),
                                           (lambda m: 1, 1 if cols[i] == 0 else 0, range(1, 2))):
            r = [mpf(0)] * (DEGREE * k)
            for m in powers_used:
                for q in range(k):
                    r[z(m, q)] = weight(m) * null[q][i]
            rows.append(r)
            rhs.append(value - sum(weight(m) * xs[m - 1][i] for m in powers_used))
    z0, residual, free = solve(rows, rhs)
    if residual > 1e-12:  # (the ends are set exactly in the doubles)
        sys.exit(f"the ends cannot be met (residual {residual})")

    def beta_of(zv):
        return [[xs[m - 1][i] + sum(null[q][i] * zv[z(m, q)] for q in range(k)) for m in range(1, DEGREE + 1)]
                for i in range(nc)]
    # the freedom left: least order-8 residual, integrated over [0, 1]
    H = matrix(DEGREE, DEGREE)
    for a in range(DEGREE):
        for b in range(DEGREE):
            H[a, b] = mpf(1) / (a + b + 3)  # int theta^(a+1) theta^(b+1)
    L = cholesky(H)
    base_beta = beta_of(z0)
    G8 = [[w[j] for j in cols] for w in W[ORDER + 1]]
    lrows, lrhs = [], []
    for t, g in zip(TREES[ORDER + 1], G8):
        base = [sum(base_beta[i][m - 1] * g[i] for i in range(nc)) - (mpf(1) / gamma(t) if m == ORDER + 1 else 0)
                for m in range(1, DEGREE + 1)]
        lin = [[sum(sum(null[q][i] * f[z(m, q)] for q in range(k)) * g[i] for i in range(nc)) for f in free]
               for m in range(1, DEGREE + 1)]
        for a in range(DEGREE):
            lrows.append([sum(L[b, a] * lin[b][f] for b in range(DEGREE)) for f in range(len(free))])
            lrhs.append(-sum(L[b, a] * base[b] for b in range(DEGREE)))
    w, _, _ = solve(lrows, lrhs)
    beta = beta_of([z0[j] + sum(free[f][j] * w[f] for f in range(len(free))) for j in range(len(z0))])
    full = [[mpf(0)] * DEGREE for _ in range(s)]
    for ii, j in enumerate(cols):
        full[j] = beta[ii]
    return full


def bernstein(beta_i):
    """the polynomial sum_m beta_m theta^m in the Bernstein basis of degree DEGREE, binomials folded in"""
    mono = [mpf(0)] + list(beta_i)
    out = [mpf(0)] * (DEGREE + 1)
    for m in range(DEGREE + 1):
        for j in range(m, DEGREE + 1):
            out[j] += mono[m] * binomial(j, m) / binomial(DEGREE, m)
    return [out[j] * binomial(DEGREE, j) for j in range(DEGREE + 1)]


def c_array(name, dims, rows):
    def num(x):
        return repr(float(x)).replace("e-0", "e-")
    lines = [f"static const double {name}{dims} = {{"]
    for row in rows:
        items, line = [num(x) for x in row], "    {"
        for i, it in enumerate(items):
            piece = it + (", " if i + 1 < len(items) else "},")
            if len(line) + len(piece) > 108:
                lines.append(line.rstrip())
                line = "     "
            line += piece
        lines.append(line)
    lines.append("};")
    return "\n".join(lines)


def construct(c5, c6):
    """the extra stages' tableau and the weights' Bernstein coefficients (doubles, the ends exact:
    b(0) = 0, b'(0) = e_1, b(1) = b, b'(1) = e_14), and the largest order-8 residual norm on [0, 1]"""
    A = tableau()
    for c in c5:
        A = add_stage(A, c, 5)
    for c in c6:
        A = add_stage(A, c, 6)
    weightless = {1, 2, 3, 4, 14, 15}  # stages 2..5 and the two of order 5
    beta = dense_weights(A, weightless)
    coef = []
    for i in range(len(A)):
        row = [mpf(float(x)) for x in bernstein(beta[i])]
        b_end = mpf(float(to_mp(B[i]))) if i < len(B) else mpf(0)
        row[0], row[1] = mpf(0), mpf(1 if i == 0 else 0)
        row[DEGREE], row[DEGREE - 1] = b_end, DEGREE * b_end - (1 if i == END_SLOPE else 0)
        coef.append(row)
    W = stage_weights(A, ORDER + 1)
    principal = mpf(0)
    for m in range(1, 21):
        th = mpf(m) / 20
        b = [sum(row[j] * th ** j * (1 - th) ** (DEGREE - j) for j in range(DEGREE + 1)) for row in coef]
        principal = max(principal, sqrt(sum((sum(b[i] * w[i] for i in range(len(A))) - th ** (ORDER + 1) / gamma(t)) ** 2
                                            for t, w in zip(TREES[ORDER + 1], W[ORDER + 1]))))
    return A, coef, principal


def main():
    if sys.argv[1:] == ["--compare"]:
        for c5, c6 in NODE_SETS:
            A, coef, principal = construct([mpf(x) for x in c5.split(",")], [mpf(x) for x in c6.split(",")])
            largest = max(abs(x) / binomial(DEGREE, j) for row in coef for j, x in enumerate(row))
            print(f"nodes {c5} {c6}: order-8 residual norm up to {float(principal):.2e}, "
                  f"largest Bernstein coefficient {float(largest):.2f}", flush=True)
        return
    A, coef, principal = construct(C5, C6)
    W = stage_weights(A, ORDER + 1)
    b7 = [mpf(13451932) / 455176623, 0, 0, 0, 0, mpf(-808719846) / 976000145, mpf(1757004468) / 5645159321,
          mpf(656045339) / 265891186, mpf(-3867574721) / 1518517206, mpf(465885868) / 322736535,
          mpf(53011238) / 667516719, mpf(2) / 45, 0, 0] + [0] * (len(A) - 14)
    embedded = sqrt(sum((sum(b7[i] * w[i] for i in range(len(A))) - mpf(1) / gamma(t)) ** 2
                        for t, w in zip(TREES[ORDER + 1], W[ORDER + 1])))
    print(f"/* (share/rk8pd/dense_output.py: nodes {', '.join(str(float(c)) for c in C5 + C6)}; order-8 "
          f"residual norm up to {float(principal):.2e} on [0, 1], the embedded 7th-order formula's "
          f"{float(embedded):.2e}) */")
    print("static const double rk8_dense_c[RK8_DENSE_EXTRA] = {%s};" % ", ".join(repr(float(c)) for c in C5 + C6))
    print(c_array("rk8_dense_a", "[RK8_DENSE_EXTRA][RK8_DENSE_STAGES - 1]", [r[:len(A) - 1] for r in A[14:]]))
    print(c_array("rk8_dense_b", "[RK8_DENSE_STAGES][RK8_DENSE_DEGREE + 1]", coef))


if __name__ == "__main__":
    main()
