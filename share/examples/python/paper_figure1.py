# SPDX-License-Identifier: GPL-3.0-or-later
"""paper_figure1.py -- a sweep with a plot: Fig. 1 of the paper, the pulse
amplitude along backward tapered chains of four strengths.

Harbola, Rosas, Esposito and Lindenberg (arXiv:0905.4512, Sec. III A) show
that in a chain whose radii grow linearly, R_k = 1 + S (k - 1), the pulse's
amplitude falls off as a power of the granule index, v_k ~ k^(-3/2) once
S k >> 1 (eq. (22)), whatever the taper's strength S: a heavier granule
takes the pulse more slowly, and the binary collision approximation says
exactly how.  Their Fig. 1 plots v_k against k on log axes for S = 0.2,
0.4, 0.6 and 0.9, numerics and theory together.

This script runs the four chains (500 granules each, in parallel threads:
the library releases the GIL), prints for each S the exponent fitted to the
numerical peak velocities over granules 200-490 (as the paper's inset)
next to the theory's over the same granules, and, if matplotlib is
installed, draws the figure in figure1.png (or the file named by the first
argument): numerics filled, theory open circles, the k^(-3/2) law dashed.
What to look at: every S approaches the same slope; the fitted exponents
lie within 1 % of 3/2, the furthest at S = 0.2, where S k is still only
40 to 100 over the fit.

The checks: each fitted exponent within 1.5 % of 3/2, and energy conserved
in every run; the script exits non-zero otherwise (a refused keyword raises
and exits non-zero too).  Without matplotlib it skips the figure and says
so; everything else runs.

    python3 paper_figure1.py [figure.png]      # with the package installed (docs/python.md)
"""

import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import taper

S = [0.2, 0.4, 0.6, 0.9]
N = 500
FIT = slice(199, 490)          # granules 200-490
MAX_EXPONENT_DEVIATION = 0.015  # relative to 3/2
MAX_ENERGY_ERROR = 1e-6


def decay_exponent(k, v):
    """p of v ~ k^-p, least squares on the logarithms."""
    return -np.polyfit(np.log(k), np.log(v), 1)[0]


def main(figure="figure1.png"):
    with ThreadPoolExecutor() as pool:
        runs = list(pool.map(lambda s: taper.simulate(profile="backward_linear", s=s,
                                                      n_granules=N), S))
    law = -taper.asymptotic.exponent("v_of_k")          # 3/2, eq. (22)
    print(f"# backward linear chains, N = {N}: v_k ~ k^-p fitted over k = 200-490")
    print(f"# {'S':>4} {'p numerics':>11} {'p theory':>9} {'steps':>7} {'E error':>9}")
    failed = []
    for s, r in zip(S, runs):
        p = decay_exponent(r.k[FIT], r.v_peak[FIT])
        p_theory = decay_exponent(r.k[FIT], r.theory_v[FIT])
        print(f"  {s:4.1f} {p:11.4f} {p_theory:9.4f} {r.stats['steps']:7.0f} "
              f"{r.energy_error:9.1e}")
        for name, value in (("numerics", p), ("theory", p_theory)):
            if not abs(value / law - 1) <= MAX_EXPONENT_DEVIATION:
                failed.append(f"S = {s}: the {name}' exponent {value:.4f} is not {law}")
        if not r.energy_error <= MAX_ENERGY_ERROR:
            failed.append(f"S = {s}: energy error {r.energy_error:.2g}")

    try:
        import matplotlib
        matplotlib.use("Agg")                           # a file, no window
        import matplotlib.pyplot as plt
    except ImportError:
        print("# matplotlib is not installed: no figure")
    else:
        ax = taper.plot(runs, "v")
        k = runs[0].k[9:]
        ax.plot(k, 2 * k ** -law, "k--", label="$k^{-3/2}$, eq. (22)")
        ax.legend()
        plt.savefig(figure)
        print(f"# figure: {figure}")

    for line in failed:
        print("FAIL:", line, file=sys.stderr)
    print(f"# checks: exponents within {100 * MAX_EXPONENT_DEVIATION:g} % of {law}, energy "
          f"error below {MAX_ENERGY_ERROR:g}: {'FAILED' if failed else 'all hold'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:2]))
