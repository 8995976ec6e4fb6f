# SPDX-License-Identifier: GPL-3.0-or-later
"""The chain settings beyond the paper (taper.h) through the Python
package: every keyword reaches its library setter through the scene, a
refusal names the keyword, the paper's defaults given explicitly change
nothing, and the
physics each option brings is there (disorder reproducible and independent
of N, masses and contact factors of mixed materials, the striker's energy,
the energy budget closing, damping and drag slowing the pulse, a load
speeding it up, a wall pushing back)."""

import math

import numpy as np
import pytest

import taper

BUDGET = ("energy_initial", "energy_dissipated", "energy_transmitted", "energy_reflected",
          "energy_in_chain")
WALL = ("wall_peak_force_left", "wall_peak_time_left", "wall_impulse_left",
        "wall_peak_force_right", "wall_peak_time_right", "wall_impulse_right")


def test_names_follow_the_header():
    assert len(taper.PROFILES) == 7 and taper.PROFILES[6] == "decorated"
    assert len(taper.STATISTICS) == 25
    assert set(BUDGET + WALL) <= set(taper.STATISTICS)
    assert taper.BOUNDARIES == ("free", "wall")
    assert taper.DISORDERS == ("radius", "mass")


def test_the_paper_defaults_given_explicitly_change_nothing():
    plain = taper.simulate(profile="backward_linear", s=0.1, n_granules=40)
    given = taper.simulate(profile="backward_linear", s=0.1, n_granules=40, left="free",
                           right="free", striker_radius=0, load=0, damping=0, drag=0,
                           disorder_amplitude=0, densities=None, compliances=None,
                           pattern=None, t_end=0)
    for c in ("t_pass", "v_peak", "T_res", "t_peak"):
        assert np.array_equal(getattr(plain, c), getattr(given, c), equal_nan=True), c
    assert plain.stats["steps"] == given.stats["steps"]


def test_settings_read_back_in_any_keyword_order():
    c = taper.chain(n_granules=10, left_compliance=0.5, left="wall",
                    right="Wall", striker_density=None)
    assert c.settings["left"] == "wall" and c.settings["left_compliance"] == 0.5
    assert c.settings["right"] == "wall" and c.settings["right_compliance"] == 0
    c = taper.chain(n_granules=10, striker_density=2.0, striker_radius=0.5,
                    seed=2**53 - 1, disorder_amplitude=0.2, disorder="mass")
    s = c.settings
    assert (s["striker_radius"], s["striker_density"]) == (0.5, 2.0)
    assert (s["disorder"], s["disorder_amplitude"], s["seed"]) == ("mass", 0.2, 2**53 - 1)
    # striker mass = density radius^3
    assert c.striker_mass == pytest.approx(2.0 * 0.5**3, rel=1e-15)


@pytest.mark.parametrize("kw, field", [
    (dict(damping=-1.0), "damping"),
    (dict(drag=math.inf), "drag"),
    (dict(load=-0.1), "load"),
    (dict(left="glue"), "left"),
    (dict(right_compliance=-1.0, right="wall"), "right_compliance"),
    (dict(striker_radius=-1.0), "striker_radius"),
    (dict(disorder="volume"), "disorder"),
    (dict(disorder_amplitude=1.0), "disorder_amplitude"),
    (dict(seed=-1), "seed"),
    (dict(densities=[1.0, 2.0], compliances=[1.0]), ("densities", "compliances")),
])
def test_refusals_name_the_keyword(kw, field):
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.chain(n_granules=10, **kw)
    assert e.value.field in (field if isinstance(field, tuple) else (field,)), e.value


def test_wrong_types_and_names():
    with pytest.raises(TypeError, match="densities"):
        taper.chain(n_granules=3, densities="1, 2, 3")
    with pytest.raises(TypeError, match="left"):
        taper.chain(left=1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'dampin'.*'damping'"):
        taper.simulate(dampin=0.1)
    # the names of the old bindings are gone, with the way to the new one
    with pytest.raises(TypeError, match="'left_end'"):
        taper.chain(left_end="wall")
    with pytest.raises(TypeError, match="'disorder_seed'"):
        taper.chain(disorder_seed=3)


def test_decorated_profile_repeats_its_pattern():
    c = taper.chain(profile="decorated", pattern=[1.0, 0.5, 0.25], n_granules=7)
    assert list(c.R) == [1.0, 0.5, 0.25, 1.0, 0.5, 0.25, 1.0]
    assert np.allclose(c.m, c.R**3, rtol=1e-15)
    with pytest.raises(taper.InvalidArgumentError):   # a pattern needs the decorated profile
        taper.chain(pattern=[1.0, 0.5], n_granules=4)


def test_disorder_is_reproducible_and_independent_of_n():
    kw = dict(disorder="radius", disorder_amplitude=0.1, seed=7)
    a = taper.chain(n_granules=10, **kw).R
    b = taper.chain(n_granules=50, **kw).R
    assert a[0] == 1.0 and np.all(np.abs(a - 1) <= 0.1) and np.any(a != 1)
    assert np.array_equal(a, b[:10])                   # u_k from (seed, k) alone
    assert np.array_equal(a, taper.chain(n_granules=10, **kw).R)
    assert not np.array_equal(a, taper.chain(n_granules=10, **dict(kw, seed=8)).R)
    m = taper.chain(n_granules=10, disorder="mass", disorder_amplitude=0.1, seed=7)
    assert np.all(m.R == 1) and np.allclose(m.m / m.m[0] - 1, a - 1, rtol=1e-12, atol=0)


def test_materials_set_masses_and_contact_factors():
    rho = np.array([2.0, 4.0, 2.0, 8.0])
    c = np.array([1.0, 3.0, 1.0, 0.5])
    mixed = taper.chain(n_granules=4, densities=rho, compliances=c)
    plain = taper.chain(n_granules=4)
    assert np.allclose(mixed.m, rho / rho[0], rtol=1e-15)              # m_k = rho_k R_k^3
    rel = c / c[0]
    want = plain.r[:3] * 2 * rel[0] / (rel[:3] + rel[1:])               # r_k 2 c_1/(c_k + c_k+1)
    assert np.allclose(mixed.r[:3], want, rtol=1e-14)
    # the settings are the scene's, as given
    assert np.array_equal(mixed.settings["densities"], rho)
    assert np.array_equal(mixed.settings["compliances"], c)


def test_striker_energy_and_budget():
    r = taper.simulate(n_granules=30, striker_radius=0.5, striker_density=3.0)
    e0 = r.stats["energy_initial"]
    assert e0 == pytest.approx(0.5 * 3.0 * 0.5**3, rel=1e-12)        # the striker's alone
    assert r.stats["energy_dissipated"] == 0
    parts = sum(r.stats[k] for k in BUDGET[2:])
    assert abs(parts - e0) <= 1e-6 * e0, r.stats


def test_damping_dissipates_and_the_budget_closes():
    elastic = taper.simulate(n_granules=40)
    damped = taper.simulate(n_granules=40, damping=0.05)
    s = damped.stats
    assert s["energy_dissipated"] > 1e-3 * s["energy_initial"]
    parts = s["energy_dissipated"] + s["energy_transmitted"] + s["energy_reflected"] + \
        s["energy_in_chain"]
    assert abs(parts - s["energy_initial"]) <= 1e-6 * s["energy_initial"], s
    assert damped.v_peak[30] < elastic.v_peak[30]
    assert np.all(np.isnan(damped.theory_v))                          # outside the theory


def test_drag_slows_and_a_load_speeds_the_pulse():
    plain = taper.simulate(n_granules=40)
    dragged = taper.simulate(n_granules=40, drag=0.05)
    loaded = taper.simulate(n_granules=40, load=0.1)
    assert dragged.t_pass[30] > plain.t_pass[30] and dragged.v_peak[30] < plain.v_peak[30]
    assert loaded.t_pass[30] < plain.t_pass[30]      # precompression raises the sound speed
    assert taper.chain(n_granules=40, load=0.1).theory_note


def test_a_wall_pushes_back():
    free = taper.simulate(n_granules=20, t_end=40.0)
    walled = taper.simulate(n_granules=20, right="wall", t_end=40.0)
    for k in WALL:
        assert math.isnan(free.stats[k]), k
    assert math.isnan(walled.stats["wall_peak_force_left"])
    assert walled.stats["wall_peak_force_right"] > 0
    assert 0 < walled.stats["wall_peak_time_right"] <= 40.0
    # the wall's impulse is the momentum the chain lost: P(0) = 1 (the
    # impulse v_1 = 1 on m_1 = 1) minus sum m_k v_k at t_end
    p_end = float(np.sum(walled.m * walled.v_final))
    assert walled.stats["wall_impulse_right"] == pytest.approx(1.0 - p_end, rel=1e-6, abs=1e-9)
    assert p_end < 0                      # the pulse came back: the chain moves left
    assert walled.stats["t_final"] == pytest.approx(40.0)


@pytest.mark.parametrize("name", ["striker", "wall_reflection", "damped", "decorated",
                                  "piston", "precompressed"])
def test_run_scene_of_a_physics_scene_is_the_drivers_run(name, source, driver, tmp_path):
    """run_scene applies a scene's options through the driver's own reader
    (&striker, &ends, &losses, a decorated pattern, a piston, a load) and
    samples at its &sensors interval as the driver does: every column is
    the driver's bit for bit, the statistics too, the samples are there;
    and simulate() with the Result's settings as keywords is the same run
    (the keywords reach the same setters)."""
    import subprocess
    scene = source / "share" / "scenes" / "physics" / f"{name}.nml"
    proc = subprocess.run([str(driver), str(scene), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    ref = taper.read_granules(tmp_path / "out" / "granules.tsv")
    (r,) = taper.run_scene(scene)
    assert r.columns == ref.columns
    for c in ref.columns:
        assert np.array_equal(r[c], ref[c], equal_nan=True), c
    for k, v in ref.stats.items():
        if k not in ("energy_error", "momentum_error"):   # the file keeps 4 digits
            assert v == r.stats[k] or (math.isnan(v) and math.isnan(r.stats[k])), k
    assert r.samples is not None and r.samples["t"][1] == r.settings["interval"]
    again = taper.simulate(**r.settings)
    assert again.equals(r) and again.stats["steps"] == r.stats["steps"]
    assert again.settings.keys() == r.settings.keys()
    for k, v in r.settings.items():
        assert np.array_equal(again.settings[k], v) if isinstance(v, np.ndarray) \
            else again.settings[k] == v, k


def test_samples_hold_the_state_and_forces_that_conserve_energy():
    """&sensors interval: the state and contact forces at t = 0, 1, ..., 30 of
    a chain against a right wall.  The energy recomputed from the samples
    alone, sum m v^2 / 2 + sum F z / n (each contact's energy r z^n / n =
    F z / n, z the overlap: x_k - x_{k+1}, and x_N for the wall), is E(0) =
    1/2 at every sample."""
    n = 2.5
    r = taper.simulate(n_granules=20, right="wall", t_end=30.0, interval=1.0)
    smp = r.samples
    assert r.settings["interval"] == 1.0
    assert np.array_equal(smp["t"], np.arange(31.0))
    assert smp["x"].shape == (31, 20) and smp["v"].shape == (31, 20)
    assert smp["force"].shape == (31, 21)
    assert smp["v"][0, 0] == 1.0 and np.all(smp["v"][0, 1:] == 0)     # the impulse
    assert np.all(smp["force"] >= 0) and np.all(smp["force"][:, 0] == 0)  # free left end
    z = np.clip(smp["x"][:, :-1] - smp["x"][:, 1:], 0, None)
    z_wall = np.clip(smp["x"][:, -1], 0, None)
    energy = 0.5 * (r.m * smp["v"] ** 2).sum(axis=1) + \
        (smp["force"][:, 1:-1] * z).sum(axis=1) / n + smp["force"][:, -1] * z_wall / n
    assert np.allclose(energy, 0.5, rtol=0, atol=1e-7), energy
    assert smp["force"][:, -1].max() > 0                      # the pulse reached the wall
    none = taper.simulate(n_granules=20)
    assert none.samples is None
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(n_granules=20, interval=-1.0)
    assert e.value.field == "interval"
    # the samples need no sensors, walls or picture: they go to Result.samples
    assert taper.simulate(n_granules=5, interval=2.0).samples["x"].shape[1] == 5
    # samples beyond &output max_output bytes are refused before the run, as
    # the driver refuses sensor files: 20 granules to t = 30 every 0.5 are 61
    # samples of 62 doubles, 30256 bytes
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(n_granules=20, right="wall", t_end=30.0, interval=0.5, max_output=3e4)
    assert e.value.field == "interval" and "3e+04 bytes" in e.value.message, e.value
    assert "max_output = 30000" in e.value.message
    ok = taper.simulate(n_granules=20, right="wall", t_end=30.0, interval=0.5, max_output=3.1e4)
    assert len(ok.samples["t"]) == 61
