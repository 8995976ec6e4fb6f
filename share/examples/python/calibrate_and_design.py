# SPDX-License-Identifier: GPL-3.0-or-later
"""calibrate_and_design.py -- a chain of stainless steel beads calibrated
from one sensor's record, then redesigned as a shock absorber with the
calibrated model.

The experiment.  A bead strikes a row of eight like it at 0.5 m/s; the row
rests against a steel wall.  The beads are type 316 stainless steel, 4.76 mm
across (handbook E = 193 GPa, nu = 0.3, rho = 8000 kg/m^3), as in the bead
chains with force gauges inside the beads of Daraio, Nesterenko, Herbold and
Jin, Phys. Rev. E 73, 026610 (2006): here bead 4 carries the gauge, read
every microsecond for 120 us.  Its contacts lose energy as viscoelastic
spheres do (Kuwabara and Kono, Jpn. J. Appl. Phys. 26, 1230 (1987);
Brilliantov et al., Phys. Rev. E 53, 5382 (1996)): F = r (z^(3/2) +
(3/2) A z^(1/2) dz/dt), with a damping time A that no handbook lists and
every experiment must measure.  The record is synthetic, made the way a
laboratory's is: a run of taper at a tolerance 100 times tighter than the
fit's, with A = 0.1 us (an illustrative value: a coefficient of restitution
near 0.96 at 1 m/s, share/examples/fortran/restitution.f90) and E = 193 GPa,
plus Gaussian noise of 1 % of the peak force (numpy's generator, seed
2024).

Part 1, calibration (&calibrate, docs/calibration.md).  Pretending to know
neither, we start from E = 150 GPa and A = 0.2 us and fit both to the
record by nonlinear least squares over runs of the chain
(taper.calibrate).  What to look at: both come back within two standard
errors, E to 0.07 % and A to 3 %; the errors are what the noise allows
(they are absolute: the noise is given), and chi2/dof is near 1, the sign
that the model and the noise are right.  The damping is weakly seen in one
record of 120 us: its relative error is 40 times E's.

Part 2, design (&design, docs/optimal-design.md).  With the calibrated
beads, which chain of 20 beads protects the wall best?  The chain keeps
its length (20 diameters of 4.76 mm: the space the protector may take) and
its radii follow ln(R_k/R_1) = c x, x = (k - 1)/19: c < 0 shrinks towards
the wall ("forward" taper), c > 0 grows.  The objective is the wall's peak
force, followed for 1 ms.  Fraternali, Porter and Daraio (Mech. Adv.
Mater. Struct. 17, 1 (2010), arXiv:0802.1451) found by a genetic algorithm
that the best protectors put light beads near the wall; here a
Nelder-Mead search over c (taper.design) finds the same: the optimum lies
at the steepest forward taper the bounds allow (the last bead 0.14 of the
first), the wall's peak force cut nearly seven times below the uniform
chain's, and a 41-point scan of c confirms it in more runs.

The checks: E and A within two standard errors of the truth, chi2/dof
within 3 sigma of 1; the design's optimum within 1 % of the scan's best in
fewer runs, below the uniform chain's force.  The script exits non-zero
otherwise.  With matplotlib installed it draws the record and the fit, and
the wall's peak force against c, into calibrate_and_design.png (or the
file named by the first argument).

    python3 calibrate_and_design.py [figure.png]        # the package installed (docs/python.md)
    python3 calibrate_and_design.py --data sensor.tsv   # only write the record
"""

import math
import os
import sys
import tempfile

import numpy as np

import taper

STEEL = dict(young=193e9, poisson=0.3, density=8000.0, radius=0.5 * 4.76e-3, velocity=0.5)
TRUE_DAMPING = 1e-7             # s, Kuwabara-Kono A of the record
SENSOR = 4                      # the bead with the gauge
CHAIN = dict(n_granules=8, right="wall", striker_radius=STEEL["radius"])
NOISE = 0.01                    # of the peak force
SEED = 2024


def write_record(path):
    """The gauge's record, in the form of taper's sensors.tsv (t[s], granule,
    force[N]): a run at rtol 1e-12, plus noise."""
    r = taper.simulate(**CHAIN, **STEEL, damping=TRUE_DAMPING, rtol=1e-12, atol=1e-15,
                       t_end=120e-6, interval=1e-6)
    s = r.samples
    force = 0.5 * (s["force"][:, SENSOR - 1] + s["force"][:, SENSOR])  # what a gauge reads
    peak = float(np.max(np.abs(force)))
    rng = np.random.default_rng(SEED)
    noisy = force + rng.normal(0.0, NOISE * peak, size=force.shape)
    with open(path, "w") as f:
        f.write("t[s]\tgranule\tforce[N]\n")
        f.write(f"# synthetic: the force gauge in bead {SENSOR} of 8 stainless steel beads "
                f"(R = 2.38 mm) struck at 0.5 m/s against a wall, E = 193 GPa, A = 0.1 us, "
                f"taper at rtol 1e-12, plus Gaussian noise of {NOISE:g} x the peak "
                f"({NOISE * peak:.6g} N), numpy seed {SEED}; written by "
                f"share/examples/python/calibrate_and_design.py --data FILE\n")
        for t, x in zip(s["t"], noisy):
            f.write(f"{float(t)!r}\t{SENSOR}\t{float(x)!r}\n")
    return NOISE * peak


def calibration(record, sigma):
    start = dict(young=150e9, damping=2e-7)
    fit = taper.calibrate(record, ["young", "damping"], noise=sigma, **CHAIN,
                          **{**STEEL, "young": start["young"]}, damping=start["damping"])
    print(f"# part 1: calibration of E and A to the gauge in bead {SENSOR} "
          f"({len(fit.measured)} samples, noise {sigma:.3g} N given)")
    print(f"# {'setting':>8} {'start':>10} {'fitted':>12} {'error':>10} {'truth':>10} "
          f"{'(fit-truth)/error':>18}")
    truth = dict(young=STEEL["young"], damping=TRUE_DAMPING)
    for name in fit.names:
        z = (fit.values[name] - truth[name]) / fit.errors[name]
        print(f"  {name:>8} {start[name]:10.4g} {fit.values[name]:12.6g} "
              f"{fit.errors[name]:10.3g} {truth[name]:10.4g} {z:18.2f}")
    print(f"# chi2/dof = {fit.chi2_per_dof:.3f} ({fit.dof} degrees of freedom), correlation "
          f"{fit.correlation[0, 1]:+.3f}; {fit.iterations} iterations, {fit.runs} runs")
    return fit, truth


def design(fit):
    beads = dict(n_granules=20, right="wall", striker_radius=STEEL["radius"], t_end=1e-3,
                 **{**STEEL, "young": fit.values["young"]}, damping=fit.values["damping"])
    keys = dict(log_radii=[0.0], lower=[-2.0], upper=[2.0], hold="length", profile_points=0,
                **beads)
    best = taper.design("wall_peak_force_right", ["log_radii(1)"], **keys)
    scan = taper.design("wall_peak_force_right", ["log_radii(1)"], method="grid", grid=41,
                        **keys)
    uniform = taper.simulate(**beads).stats["wall_peak_force_right"]
    c = best.values["log_radii(1)"]
    print("# part 2: the taper c of 20 calibrated beads at fixed length that minimises the "
          "wall's peak force")
    print(f"  uniform chain (c = 0):       {uniform:8.3f} N")
    print(f"  optimum, Nelder-Mead:        {best.objective:8.3f} N at c = {c:+.4f} "
          f"({best.at_bound.get('log_radii(1)', 'inside')} bound), {best.runs} runs")
    print(f"  41-point scan of c:          {scan.objective:8.3f} N in {scan.runs} runs")
    print(f"# the last bead's radius at the optimum: {math.exp(c):.3f} R_1 "
          f"(R_1 = {first_radius(best.scene) * 1e3:.3f} mm at the chain's length)")
    return best, scan, uniform


def first_radius(scene_text):
    """&material radius of a scene's text: R_1 after the length was held."""
    group = None
    for line in scene_text.splitlines():
        words = line.split()
        if words and words[0].startswith("&"):
            group = words[0][1:]
        elif group == "material" and len(words) >= 3 and words[:2] == ["radius", "="]:
            return float(words[2])
    return float("nan")


def draw(figure, fit, scan):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("# matplotlib is not installed: no figure")
        return
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4))
    a.plot(1e6 * fit.t, fit.measured, ".", ms=3, label="gauge (synthetic, 1 % noise)")
    a.plot(1e6 * fit.t, fit.fitted, "-", label="calibrated model")
    a.set_xlabel("t [us]")
    a.set_ylabel(f"force in bead {SENSOR} [N]")
    a.legend()
    ev = scan.evaluations
    b.plot(ev["log_radii(1)"], ev["wall_peak_force_right"], "o-", ms=3)
    b.set_xlabel("taper c: ln(R_20/R_1)")
    b.set_ylabel("wall's peak force [N]")
    fig.tight_layout()
    fig.savefig(figure)
    print(f"# figure: {figure}")


def main(args):
    if args[:1] == ["--data"]:
        write_record(args[1])
        return 0
    figure = args[0] if args else "calibrate_and_design.png"
    failed = []
    with tempfile.TemporaryDirectory() as tmp:
        record = os.path.join(tmp, "sensor.tsv")
        sigma = write_record(record)
        fit, truth = calibration(record, sigma)
    if not fit.converged:
        failed.append(f"the calibration did not converge: {fit.reason}")
    for name in fit.names:
        if not abs(fit.values[name] - truth[name]) < 2 * fit.errors[name]:
            failed.append(f"{name} is more than 2 errors from the truth")
    if not abs(fit.chi2_per_dof - 1) < 3 * math.sqrt(2 / fit.dof):
        failed.append(f"chi2/dof = {fit.chi2_per_dof:.3f}")
    best, scan, uniform = design(fit)
    if not best.objective <= 1.01 * scan.objective:
        failed.append("the optimum is worse than the scan's best")
    if not best.runs < scan.runs:
        failed.append("the optimiser took as many runs as the scan")
    if not best.objective < uniform:
        failed.append("the design does not beat the uniform chain")
    draw(figure, fit, scan)
    for line in failed:
        print("FAIL:", line, file=sys.stderr)
    print("# checks: E and A within 2 errors, chi2/dof near 1, the optimum within 1 % of the "
          f"scan in fewer runs and below the uniform chain: {'FAILED' if failed else 'all hold'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
