# SPDX-License-Identifier: GPL-3.0-or-later
"""SI in and SI out: with the &material keywords every dimensional input is
SI and the results come back in SI with their units; a Kuwabara-Kono
collision of two steel beads given entirely in SI has the restitution
coefficient of the same collision in rescaled units, and of an independent
integration of the force law in SI."""

import math

import numpy as np
import pytest

import taper

# Stainless steel beads (share/scenes/physics/steel_wall_si.nml).
E, NU, RHO, R1, V = 193e9, 0.3, 8000.0, 4.76e-3, 0.5
STEEL = dict(young=E, poisson=NU, density=RHO, radius=R1, velocity=V)


def unit_time_and_length():
    """The rescaling of eq. (5) for Hertz contacts (n = 5/2): y = R_1
    alpha^(1/n) x with alpha = M_1 V^2 / (a R_1^(n + 1/2)) of eq. (4), a r_1
    the Hertz constant (4/3) E* sqrt(R*) of two equal spheres, r_1 =
    R_1^(1/2) (eq. (7) with R = R_1); the unit of time is the length over V."""
    n = 2.5
    e_star, r_star = E / (2 * (1 - NU**2)), R1 / 2
    a = 4 / 3 * e_star * math.sqrt(r_star) / math.sqrt(R1)
    mass = 4 / 3 * math.pi * RHO * R1**3
    alpha = mass * V**2 / (a * R1 ** (n + 0.5))
    length = R1 * alpha ** (1 / n)
    return length / V, length


def test_si_columns_stats_and_units():
    """simulate(young=193e9, ...) returns every column in SI with its unit:
    the rescaled run's columns times the units of eq. (5)."""
    T, L = unit_time_and_length()
    mass = 4 / 3 * math.pi * RHO * R1**3
    si = taper.simulate(n_granules=50, **STEEL)
    rs = taper.simulate(n_granules=50)
    assert si.complete and si.stats["steps"] == rs.stats["steps"]
    assert si.units == {**{c: u for c, u in (("R", "m"), ("m", "kg"), ("X0", "m"),
                                             ("t_pass", "s"), ("T_res", "s"), ("v_peak", "m/s"),
                                             ("t_peak", "s"), ("X_pass", "m"),
                                             ("theory_v", "m/s"), ("theory_T", "s"),
                                             ("theory_t", "s"))},
                        "t_final": "s", "energy_initial": "J", "energy_dissipated": "J",
                        "energy_transmitted": "J", "energy_reflected": "J",
                        "energy_in_chain": "J", "wall_peak_force_left": "N",
                        "wall_peak_time_left": "s", "wall_impulse_left": "N s",
                        "wall_peak_force_right": "N", "wall_peak_time_right": "s",
                        "wall_impulse_right": "N s", "pulse_speed": "m/s", "x_final": "m",
                        "v_final": "m/s"}
    assert rs.units == {}
    close = dict(rtol=1e-14, atol=0)
    assert np.allclose(si.t_pass, rs.t_pass * T, equal_nan=True, **close)
    assert np.allclose(si.theory_T, rs.theory_T * T, equal_nan=True, **close)
    assert np.allclose(si.v_peak, rs.v_peak * V, equal_nan=True, **close)
    assert np.allclose(si.R, rs.R * R1, **close) and np.allclose(si.m, rs.m * mass, **close)
    # X_pass = X0 + x_k: the rest position in R_1, the displacement in the unit of length
    assert np.allclose(si.X_pass, rs.X0 * R1 + (rs.X_pass - rs.X0) * L, equal_nan=True, **close)
    assert si.stats["t_final"] == pytest.approx(rs.stats["t_final"] * T, rel=1e-14)
    assert si.stats["energy_initial"] == pytest.approx(0.5 * mass * V**2, rel=1e-14)
    assert si.stats["energy_error"] == rs.stats["energy_error"]   # a pure number
    assert si.x_final == pytest.approx(rs.x_final * L, rel=1e-14)
    # rescaled results of the same SI inputs
    kept = taper.simulate(n_granules=50, units="rescaled", **STEEL)
    assert kept.units == {} and kept.equals(rs)
    # the theory alone and the chain, in SI too
    th = taper.theory(n_granules=50, **STEEL)
    assert th.units["theory_t"] == "s" and np.array_equal(th.theory_t, si.theory_t, equal_nan=True)
    c = taper.chain(n_granules=50, **STEEL)
    assert c.units == {"R": "m", "m": "kg", "X0": "m", "mu": "kg", "striker_mass": "kg"}
    assert np.array_equal(c.R, si.R) and np.array_equal(c.m, si.m)
    assert c.mu[0] == pytest.approx(mass / 2, rel=1e-14)


def test_dimensional_inputs_are_si_with_material():
    """t_end, a load, drag and the sensor interval given in SI are the
    rescaled run's given in rescaled units."""
    T, L = unit_time_and_length()
    mass = 4 / 3 * math.pi * RHO * R1**3
    force, drag = mass * V**2 / L, mass / T
    si = taper.simulate(n_granules=20, right="wall", t_end=60 * T, load=0.05 * force,
                        drag=0.01 * drag, interval=2 * T, **STEEL)
    rs = taper.simulate(n_granules=20, right="wall", t_end=60.0, load=0.05, drag=0.01,
                        interval=2.0)
    assert np.allclose(si.t_pass, rs.t_pass * T, rtol=1e-9, atol=0, equal_nan=True)
    assert si.stats["wall_peak_force_right"] == pytest.approx(
        rs.stats["wall_peak_force_right"] * force, rel=1e-9)
    assert si.units["force"] == "N" and si.units["t"] == "s"
    assert np.allclose(si.samples["t"], rs.samples["t"] * T, rtol=1e-12, atol=0)
    assert np.allclose(si.samples["force"], rs.samples["force"] * force, rtol=1e-7, atol=1e-9 * force)
    assert np.allclose(si.samples["x"], rs.samples["x"] * L, rtol=1e-7, atol=1e-9 * L)
    # the settings are as given: SI
    assert si.settings["t_end"] == 60 * T and si.settings["load"] == 0.05 * force


def kuwabara_kono_restitution(A, steps_per_sample, n_samples, interval):
    """Two equal spheres, the first at V, the second at rest, touching at t
    = 0: the overlap z obeys mu z'' = -F, F = k (z^(3/2) + (3/2) A z^(1/2)
    z') clipped at 0 (the contact never pulls), k = (4/3) E* sqrt(R*) (Hertz,
    E* = E / (2 (1 - nu^2)), R* = R / 2), mu = M / 2; integrated in SI by
    classical RK4 on a fixed step.  Returns the restitution coefficient
    -z'(end) / V and z' at the sample times."""
    k = 4 / 3 * E / (2 * (1 - NU**2)) * math.sqrt(R1 / 2)
    mu = 4 / 3 * math.pi * RHO * R1**3 / 2

    def acc(z, w):
        if z <= 0:
            return 0.0
        return -max(k * (z**1.5 + 1.5 * A * math.sqrt(z) * w), 0.0) / mu

    h = interval / steps_per_sample
    z, w = 0.0, V
    rate = [w]
    for _ in range(n_samples):
        for _ in range(steps_per_sample):
            k1z, k1w = w, acc(z, w)
            k2z, k2w = w + 0.5 * h * k1w, acc(z + 0.5 * h * k1z, w + 0.5 * h * k1w)
            k3z, k3w = w + 0.5 * h * k2w, acc(z + 0.5 * h * k2z, w + 0.5 * h * k2w)
            k4z, k4w = w + h * k3w, acc(z + h * k3z, w + h * k3w)
            z += h / 6 * (k1z + 2 * k2z + 2 * k3z + k4z)
            w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w)
        rate.append(w)
    return -w / V, np.array(rate)


def test_kuwabara_kono_collision_in_si():
    """The issue's must-show: a two-sphere Kuwabara-Kono collision of steel
    beads given entirely in SI (A, t_end and the sensor interval in
    seconds) has the restitution coefficient of the rescaled scene with A /
    unit_time to 1e-12, and of an independent integration in SI."""
    A, t_end, interval = 1e-6, 1.5e-3, 1e-6
    T, _ = unit_time_and_length()
    si = taper.simulate(n_granules=2, damping=A, t_end=t_end, interval=interval, **STEEL)
    rs = taper.simulate(n_granules=2, damping=A / T, t_end=t_end / T, interval=interval / T)
    assert si.complete and rs.complete
    e_si = (si.v_final[1] - si.v_final[0]) / V            # m/s over m/s
    e_rs = rs.v_final[1] - rs.v_final[0]                  # in units of V
    assert e_si == pytest.approx(e_rs, rel=1e-12, abs=0)
    assert 0.5 < e_si < 0.99                              # damped, not absorbed
    # the samples: t = 0, 1 us, ..., 1.5 ms (about 1500, in seconds)
    t = si.samples["t"]
    assert si.units["t"] == "s" and len(t) == 1501
    assert t[1] == pytest.approx(interval, rel=1e-12) and t[-1] == pytest.approx(t_end, rel=1e-12)
    # the independent integration, converging to the library's value
    rate_si = si.samples["v"][:, 0] - si.samples["v"][:, 1]
    errors = []
    for m in (100, 400):
        e_rk, rate_rk = kuwabara_kono_restitution(A, m, 60, interval)
        errors.append(abs(e_rk - e_si))
    assert errors[1] < errors[0] / 2 and errors[1] < 3e-8 * e_si, errors
    assert np.max(np.abs(rate_si[:61] - rate_rk)) < 1e-7 * V
    # separated for good: the relative velocity is e V from then on
    assert rate_si[-1] == pytest.approx(-e_si * V, rel=1e-12)
    # elastic contacts give back every bit of the approach velocity (eq. (9), equal masses)
    el = taper.simulate(n_granules=2, t_end=t_end, **STEEL)
    assert (el.v_final[1] - el.v_final[0]) / V == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("name", ["steel_wall_si", "mixed_si"])
def test_run_scene_of_an_si_scene_is_the_drivers_file(name, source, driver, tmp_path):
    """run_scene on a scene with &material: SI columns, statistics and units,
    each the driver's granules.tsv bit for bit (read_granules takes the
    units from its header)."""
    import subprocess
    scene = source / "share" / "scenes" / "physics" / f"{name}.nml"
    proc = subprocess.run([str(driver), str(scene), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    ref = taper.read_granules(tmp_path / "out" / "granules.tsv")
    (r,) = taper.run_scene(scene)
    assert r.columns == ref.columns and r.units["t_pass"] == "s"
    for c in ref.columns:
        assert np.array_equal(r[c], ref[c], equal_nan=True), c
    for k, u in ref.units.items():
        assert r.units[k] == u, k
    for k, v in ref.stats.items():
        if k not in ("energy_error", "momentum_error"):
            assert v == r.stats[k] or (math.isnan(v) and math.isnan(r.stats[k])), k
    assert r.samples["t"][1] == pytest.approx(r.settings["interval"], rel=1e-12)
