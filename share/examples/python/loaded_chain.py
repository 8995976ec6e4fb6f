# SPDX-License-Identifier: GPL-3.0-or-later
"""loaded_chain.py -- from sonic vacuum to sound: a pulse in a chain of steel
beads under a growing static load.

A chain of beads that just touch has no sound speed: Hertz's force
F = kappa delta^(3/2) has no linear part, and a pulse travels at a speed set
by its own amplitude (Nesterenko's "sonic vacuum"; V. F. Nesterenko,
"Dynamics of Heterogeneous Materials", Springer 2001, Chap. 1).  Squeeze the
chain with a static force F0 and every contact becomes a spring of
stiffness K = dF/d delta = (3/2) kappa^(2/3) F0^(1/3); a weak pulse then
travels at the long-wave sound speed of the loaded chain,

    c0 = a sqrt(K / m),

a the bead diameter, m its mass: c0 grows as F0^(1/6).  Experiments tune the
speed of pulses in bead chains this way (Daraio, Nesterenko, Herbold and
Jin, Phys. Rev. E 73, 026610 (2006), by magnets).  For two beads of diameter
a, kappa = E sqrt(a) / (3 (1 - nu^2)) (Hertz; Landau and Lifshitz, Theory
of Elasticity, Sec. 9).

This script strikes 100 steel beads (diameter 4.76 mm, E = 193 GPa,
nu = 0.3, rho = 8000 kg/m^3, handbook values of type 316 stainless steel)
with a weak impulse, 1 mm/s given to the first, under loads from 0 to 10 N
(`load` in newtons: every input is SI with the &material keywords,
docs/python.md), and measures the pulse's speed between granules 40 and 90
from its passage times.  What to look at: without load the pulse is a
solitary wave of the sonic vacuum, 164 m/s at this amplitude; as the load
grows the speed climbs and joins c0 once the load's force dwarfs the
pulse's own.  There V/c0 settles at 0.989 whatever the load: the pulse is
then linear, and a linear chain's motion scales with c0 exactly; the 1.1 %
is the chain's dispersion (a wave of wavenumber q travels at
c0 cos(q a / 2), slower than c0), which the impulse's short wavelengths
feel.  With matplotlib installed the
speeds are drawn against the load next to c0 in loaded_chain.png (or the
file named by the first argument); without it the figure is skipped.

The checks: the speed grows with the load; at the two heaviest loads it
lies within 2 % of c0, by the same ratio within 0.1 % (the linear limit);
and energy is conserved (measured from the loaded equilibrium) in every
run.  The script exits non-zero otherwise.

    python3 loaded_chain.py [figure.png]      # with the package installed (docs/python.md)
"""

import math
import sys

import taper

STEEL = dict(young=193e9, poisson=0.3, density=8000.0, radius=0.5 * 4.76e-3)
VELOCITY = 1e-3                 # m/s, the impulse on bead 1
N = 100
LOADS = [0.0, 0.01, 0.1, 1.0, 3.0, 10.0]   # N
FROM, TO = 40, 90               # granules between which the speed is measured
MAX_SOUND_DEVIATION = 0.02
MAX_RATIO_SPREAD = 0.001
MAX_ENERGY_ERROR = 1e-6


def sound_speed(f0):
    """c0 of the loaded chain, in m/s, from Hertz's law in SI."""
    a = 2 * STEEL["radius"]
    e, nu, rho = STEEL["young"], STEEL["poisson"], STEEL["density"]
    kappa = e * math.sqrt(a) / (3 * (1 - nu * nu))
    stiffness = 1.5 * kappa ** (2 / 3) * f0 ** (1 / 3)
    mass = math.pi / 6 * rho * a ** 3
    return a * math.sqrt(stiffness / mass)


def pulse_speed(r):
    """Distance over time between the pulse's passages at FROM and TO, m/s."""
    i, j = FROM - 1, TO - 1
    return (r.X_pass[j] - r.X_pass[i]) / (r.t_pass[j] - r.t_pass[i])


def main(figure="loaded_chain.png"):
    print(f"# {N} steel beads, diameter {2e3 * STEEL['radius']:.2f} mm, bead 1 given "
          f"{1e3 * VELOCITY:g} mm/s; speed between granules {FROM} and {TO}")
    print(f"# {'F0 [N]':>7} {'V [m/s]':>9} {'c0 [m/s]':>9} {'V/c0':>7} {'steps':>7} "
          f"{'E error':>9}")
    failed, speeds = [], []
    for f0 in LOADS:
        r = taper.simulate(n_granules=N, load=f0, velocity=VELOCITY, last_granule=TO, **STEEL)
        v, c0 = pulse_speed(r), sound_speed(f0)
        speeds.append(v)
        ratio = f"{v / c0:7.4f}" if c0 > 0 else f"{'-':>7}"
        print(f"  {f0:7.2f} {v:9.2f} {c0:9.2f} {ratio} {r.stats['steps']:7.0f} "
              f"{r.energy_error:9.1e}")
        if not r.energy_error <= MAX_ENERGY_ERROR:
            failed.append(f"F0 = {f0} N: energy error {r.energy_error:.2g}")
    if not all(b > a for a, b in zip(speeds, speeds[1:])):
        failed.append("the speed does not grow with the load")
    ratios = [v / sound_speed(f0) for f0, v in zip(LOADS[-2:], speeds[-2:])]
    for f0, ratio in zip(LOADS[-2:], ratios):
        if not abs(ratio - 1) <= MAX_SOUND_DEVIATION:
            failed.append(f"F0 = {f0} N: the speed is {ratio:.4f} times the sound speed")
    if not abs(ratios[1] / ratios[0] - 1) <= MAX_RATIO_SPREAD:
        failed.append(f"V/c0 still changes with the load: {ratios[0]:.5f}, {ratios[1]:.5f}")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("# matplotlib is not installed: no figure")
    else:
        fig, ax = plt.subplots()
        loaded = [(f0, v) for f0, v in zip(LOADS, speeds) if f0 > 0]
        ax.loglog([f for f, _ in loaded], [v for _, v in loaded], "o", label="pulse, numerics")
        ax.loglog([f for f, _ in loaded], [sound_speed(f) for f, _ in loaded], "k--",
                  label="sound speed $c_0 \\propto F_0^{1/6}$")
        ax.axhline(speeds[0], color="grey", lw=0.8, label="no load (sonic vacuum)")
        ax.set_xlabel("static load $F_0$ [N]")
        ax.set_ylabel("pulse speed [m/s]")
        ax.legend()
        fig.savefig(figure)
        print(f"# figure: {figure}")

    for line in failed:
        print("FAIL:", line, file=sys.stderr)
    print(f"# checks: speed growing with the load, within {100 * MAX_SOUND_DEVIATION:g} % of "
          f"c0 at the heaviest loads by one ratio (within {MAX_RATIO_SPREAD:g}), energy error "
          f"below {MAX_ENERGY_ERROR:g}: {'FAILED' if failed else 'all hold'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:2]))
