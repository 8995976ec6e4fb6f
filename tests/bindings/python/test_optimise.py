# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.calibrate() and taper.design() (docs/calibration.md,
docs/optimal-design.md): the driver's optimisers from Python.

* calibrate() recovers Young's modulus and the Kuwabara-Kono damping of
  stainless steel beads from a sensor's force made by taper.simulate() at a
  tighter tolerance, with 1 % Gaussian noise: within 2 standard errors;
  its refusals name the keyword and, for the data, FILE:LINE:COLUMN;
* design() finds the taper of 20 steel beads that minimises the wall's peak
  force at fixed length within 1 % of a 41-point scan, in fewer runs;
* Python and the driver give the same optimum, to the last bit, for the
  same scene (calibration and design).
"""

import math
import pathlib
import subprocess

import numpy as np
import pytest

import taper

STEEL = dict(young=193e9, poisson=0.3, density=8000.0, radius=2.38e-3, velocity=0.5)
CHAIN = dict(n_granules=8, right="wall", striker_radius=2.38e-3)
YOUNG, DAMPING = 193e9, 1e-7


def sensor_table(path, noise, seed=1):
    """The force a sensor in bead 4 reads every microsecond for 120 us, made
    at rtol 1e-12, with Gaussian noise of `noise` times its peak."""
    r = taper.simulate(**CHAIN, **STEEL, damping=DAMPING, rtol=1e-12, atol=1e-15,
                       t_end=120e-6, interval=1e-6)
    s = r.samples
    force = 0.5 * (s["force"][:, 3] + s["force"][:, 4])
    t = s["t"]
    peak = np.max(np.abs(force))
    rng = np.random.default_rng(seed)
    measured = force + (rng.normal(0, noise * peak, size=force.shape) if noise else 0)
    with open(path, "w") as f:
        f.write("t[s]\tgranule\tforce[N]\n# the sensor in bead 4\n")
        for ti, fi in zip(t, measured):
            f.write(f"{float(ti)!r}\t4\t{float(fi)!r}\n")
    return peak


def test_calibrate_recovers_young_and_damping(tmp_path):
    data = tmp_path / "sensor.tsv"
    peak = sensor_table(data, 0.01)
    fit = taper.calibrate(str(data), ["young", "damping"], start=[0.8 * YOUNG, 2 * DAMPING],
                          noise=0.01 * peak, **CHAIN, **{**STEEL, "young": 0.8 * YOUNG},
                          damping=2 * DAMPING)
    assert fit.converged, fit.reason
    assert fit.absolute_errors
    assert abs(fit.values["young"] - YOUNG) < 2 * fit.errors["young"]
    assert abs(fit.values["damping"] - DAMPING) < 2 * fit.errors["damping"]
    assert fit.units == {"young": "Pa", "damping": "s"}
    assert abs(fit.chi2_per_dof - 1) < 3 * math.sqrt(2 / fit.dof)
    assert fit.correlation.shape == (2, 2) and fit.correlation[0, 0] == pytest.approx(1)
    assert len(fit.measured) == 121 and set(fit.quantity) == {"force"}
    # the fitted scene reproduces the fitted run: young in it
    assert "young" in fit.scene and "&calibrate" not in fit.scene


def test_calibrate_noise_free_to_the_tolerance(tmp_path):
    data = tmp_path / "sensor.tsv"
    sensor_table(data, 0.0)
    fit = taper.calibrate(str(data), "young damping", start=[0.8 * YOUNG, 2 * DAMPING],
                          **CHAIN, **STEEL, damping=DAMPING)
    assert fit.converged, fit.reason
    assert fit.values["young"] == pytest.approx(YOUNG, rel=1e-8)
    assert fit.values["damping"] == pytest.approx(DAMPING, rel=1e-6)


def test_calibrate_refusals(tmp_path):
    data = tmp_path / "bad.tsv"
    data.write_text("t[ms]\tgranule\tforce[N]\n0\t4\t0\n")
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.calibrate(str(data), ["young"], **CHAIN, **STEEL)
    assert e.value.field == "calibrate_data"
    assert f"{data}:1:1:" in str(e.value) and "in s" in str(e.value)
    data.write_text("t[s]\tgranule\tforce[N]\n0\t4\tnan\n1e-6\t4\t1\n")
    with pytest.raises(taper.InvalidArgumentError, match=r"bad.tsv:2:5: .*not a measurement"):
        taper.calibrate(str(data), ["young"], **CHAIN, **STEEL)
    data.write_text("t[s]\tgranule\tforce[N]\n0\t9\t0\n1e-6\t4\t1\n")
    with pytest.raises(taper.InvalidArgumentError, match=r"bad.tsv:2:2: granule 9 is beyond"):
        taper.calibrate(str(data), ["young"], **CHAIN, **STEEL)
    data.write_text("t[s]\tgranule\tforce[N]\n0\t4\t0\n1e-6\t4\t1\n2e-6\t4\t1\n")
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.calibrate(str(data), ["yung"], **CHAIN, **STEEL)
    assert e.value.field == "calibrate_free" and "did you mean young" in str(e.value)
    with pytest.raises(TypeError):
        taper.calibrate(str(data), [1.0], **CHAIN, **STEEL)


DESIGN = dict(n_granules=20, right="wall", striker_radius=2.38e-3, t_end=1e-3, **STEEL)


def test_design_against_a_scan():
    keys = dict(log_radii=[0], lower=[-2], upper=[2], hold="length", profile_points=0, **DESIGN)
    d = taper.design("wall_peak_force_right", ["log_radii(1)"], **keys)
    scan = taper.design("wall_peak_force_right", ["log_radii(1)"], method="grid", grid=41, **keys)
    assert d.converged and scan.converged
    assert scan.runs == 41 and len(scan.evaluations["status"]) == 41
    assert d.objective <= 1.01 * scan.objective
    assert d.runs < scan.runs
    assert d.objective_unit == "N"
    assert d.at_bound == {"log_radii(1)": "lower"}


def test_python_and_the_driver_agree(driver, tmp_path):
    scene = tmp_path / "design.nml"
    scene.write_text("""&chain n_granules = 20 /
&ends right = 'wall' /
&striker radius = 2.38e-3 /
&losses damping = 1e-7 /
&solver t_end = 1e-3 /
&material young = 193e9, poisson = 0.3, density = 8000, radius = 2.38e-3, velocity = 0.5 /
&design objective = 'energy_dissipated', goal = 'maximise', free = 'log_radii(1)',
        log_radii = 0.5, lower = -2, upper = 2, hold = 'length', profile_points = 3 /
""")
    out = tmp_path / "out"
    proc = subprocess.run([str(driver), str(scene), "-o", str(out)], capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stderr
    rows = [line.split("\t") for line in (out / "design.tsv").read_text().splitlines()
            if line and not line.startswith("#")]
    assert rows[0][:2] == ["setting", "value"]
    driver_value = float(rows[1][1])
    d = taper.design("energy_dissipated", "log_radii(1)", goal="maximise", log_radii=[0.5],
                     lower=[-2], upper=[2], hold="length", profile_points=3, damping=1e-7,
                     **DESIGN)
    assert d.values["log_radii(1)"] == driver_value  # the same runs: the same bits
    objective = [line for line in (out / "design.tsv").read_text().splitlines()
                 if line.startswith("# objective:")][0]
    assert float(objective.split("=")[-1]) == d.objective
    assert len(d.profiles["log_radii(1)"][0]) == 3


def test_python_and_the_driver_agree_on_a_calibration(driver, tmp_path):
    data = tmp_path / "sensor.tsv"
    sensor_table(data, 0.01, seed=7)
    scene = tmp_path / "fit.nml"
    scene.write_text(f"""&chain n_granules = 8 /
&ends right = 'wall' /
&striker radius = 2.38e-3 /
&losses damping = 2e-7 /
&material young = 150e9, poisson = 0.3, density = 8000, radius = 2.38e-3, velocity = 0.5 /
&calibrate data = '{data}', free = 'young damping' /
""")
    out = tmp_path / "out"
    proc = subprocess.run([str(driver), str(scene), "-o", str(out)], capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stderr
    rows = {r[0]: r for r in (line.split("\t") for line in
                              (out / "calibration.tsv").read_text().splitlines())
            if r[0] in ("young", "damping")}
    fit = taper.calibrate(str(data), "young damping", **CHAIN,
                          **{**STEEL, "young": 150e9}, damping=2e-7)
    for name in ("young", "damping"):
        assert fit.values[name] == float(rows[name][1])
        assert fit.errors[name] == float(rows[name][2])
    # the fitted scene, run by the driver, is the fitted run
    assert (out / "fitted.nml").is_file() and (out / "fitted" / "granules.tsv").is_file()


INTERRUPTED = """
import taper
print("started", flush=True)
d = None
try:
    d = taper.design("wall_peak_force_right", "log_radii(1)", method="grid", grid=1001,
                     log_radii=[0], lower=[-2], upper=[2], hold="length", profile_points=0,
                     n_granules=20, right="wall", striker_radius=2.38e-3, t_end=1e-3,
                     young=193e9, poisson=0.3, density=8000, radius=2.38e-3, velocity=0.5)
except KeyboardInterrupt:
    print("interrupted, result:", d, flush=True)
    print("after:", taper.simulate(n_granules=10).complete, flush=True)
    raise
"""


def test_ctrl_c_stops_a_design():
    import signal
    import sys
    import time
    proc = subprocess.Popen([sys.executable, "-c", INTERRUPTED], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "started"
    time.sleep(1.5)  # well into its 1001 runs (about 25 s of them)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert "interrupted, result: None" in out, (out, err)
    assert "after: True" in out, (out, err)
    assert "KeyboardInterrupt" in err
    assert time.monotonic() - sent < 10
