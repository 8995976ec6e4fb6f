# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.read_sweep (issue 35): a sweep as one table, a row per run, the
swept variables as columns and every scalar result of runs.tsv with its
unit; from the driver's directory (its footer checked) or from run_scene's
Results, the same numbers either way."""
import math
import subprocess

import numpy as np
import pytest

import taper

STEEL = ("&material young = 193e9, poisson = 0.3, density = 8000, radius = 4.76e-3, "
         "velocity = 0.5 /\n")
# A forward linear sweep over s from the monodisperse s = 0, against a
# wall, in SI; s = 0.1 needs n_granules < 11: that run is refused, the
# others complete (status 5).
FAULTY = ("&chain profile = 'forward_linear', n_granules = 20, s = 0, 0.01, 0.1, 0.02 /\n"
          "&ends right = 'wall' /\n" + STEEL + "&output progress = .false. /\n")
GRID = ("&chain profile = 'backward_exponential', n_granules = 30, 40\n"
        "       q = 0.02, 0.05, exponent = 2.5, 3.0 /\n&output progress = .false. /\n")


def sweep(driver, tmp_path, text, name, status=0):
    scene = tmp_path / f"{name}.nml"
    scene.write_text(text)
    out = tmp_path / name
    p = subprocess.run([str(driver), str(scene), "-o", str(out)], capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == status, p.stderr
    return scene, out


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind == "f":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def test_a_row_per_run_with_units_and_the_refused_one(driver, tmp_path):
    pytest.importorskip("pandas")
    _, out = sweep(driver, tmp_path, FAULTY, "faulty", status=5)
    df = taper.read_sweep(out)
    assert list(df["run"]) == ["s=0", "s=0.01", "s=0.1", "s=0.02"]
    assert list(df["s"]) == [0.0, 0.01, 0.1, 0.02] and df["s"].dtype == np.float64
    assert list(df["status"]) == ["complete", "complete", "refused", "complete"]
    assert df.attrs["swept"] == ["s"] and df.attrs["source"] == str(out / "runs.tsv")
    units = df.attrs["units"]
    assert units["t_final"] == "s" and units["wall_peak_force_right"] == "N"
    assert units["pulse_speed"] == "m/s" and units["cpu_time"] == "s"
    assert units["wall_impulse_right"] == "N s" and "steps" not in units
    for name, unit in units.items():
        assert f"{name}[{unit}]" in df.columns
    assert list(df.columns[:4]) == ["run", "s", "status", "steps"]
    assert list(df.columns[-2:]) == ["cpu_time[s]", "message"]
    # the refused run: no statistics, its reason
    bad = df[df["status"] == "refused"].iloc[0]
    assert math.isnan(bad["steps"]) and math.isnan(bad["wall_peak_force_right[N]"])
    assert "needs n_granules < 1 + 1/s = 11" in bad["message"]
    # every complete run: the statistics of its granules.tsv, the same doubles
    for _, row in df[df["status"] == "complete"].iterrows():
        stats = taper.read_granules(out / row["run"] / "granules.tsv").stats
        for name, value in stats.items():
            if name == "complete":
                continue
            column = f"{name}[{units[name]}]" if name in units else name
            assert row[column] == value, (row["run"], name)
        assert row["cpu_time[s]"] > 0 and row["message"] == ""
    # the wall's peak force against the taper: what a user plots
    force = df.loc[df["status"] == "complete", "wall_peak_force_right[N]"]
    assert (force > 0).all() and np.all(np.diff(force.to_numpy()[[0, 1]]) != 0)


def test_without_pandas_a_dict_of_columns(driver, tmp_path):
    _, out = sweep(driver, tmp_path, FAULTY, "faulty", status=5)
    t = taper.read_sweep(out / "runs.tsv", pandas=False)
    assert isinstance(t, taper.SweepTable) and isinstance(t, dict)
    assert t.units["pulse_speed"] == "m/s" and t.attrs["swept"] == ["s"]
    assert {len(c) for c in t.values()} == {4}
    assert t["pulse_speed[m/s]"].dtype == np.float64 and t["run"][2] == "s=0.1"
    a = t.to_numpy()
    assert a.shape == (4,) and same(a["s"], t["s"])
    try:
        import pandas  # noqa: F401
    except ImportError:
        return
    df = taper.read_sweep(out)
    assert list(df.columns) == list(t) and df.attrs == t.attrs
    for c in t:
        assert same(df[c].to_numpy(), t[c]), c


def test_a_grid_is_a_row_per_point_not_a_chain(driver, tmp_path):
    scene, out = sweep(driver, tmp_path, GRID, "grid")
    t = taper.read_sweep(out, pandas=False)
    assert t.attrs["swept"] == ["n_granules", "q", "exponent"]
    assert len(t["run"]) == 8 and len(set(t["run"])) == 8
    assert t["n_granules"].dtype == np.int64 and t["q"].dtype == np.float64
    assert sorted(set(t["n_granules"])) == [30, 40]
    assert t["run"][0] == "n_granules=30,q=0.02,exponent=2.5"
    # the same table from run_scene's Results: the same doubles (the
    # conservation errors, which the files keep to 4 digits, to those)
    r = taper.read_sweep(taper.run_scene(scene), pandas=False)
    assert r.attrs["swept"] == t.attrs["swept"] and r.units == {}
    assert [c for c in t if c not in r] == ["cpu_time[s]", "message"]
    assert list(r) == [c for c in t if c in r]
    for c in r:
        if c.endswith("_error"):
            assert np.allclose(r[c], t[c], rtol=1e-3, atol=0), c
        else:
            assert same(r[c], t[c]), c


def test_run_scene_in_si_gives_the_drivers_columns(driver, tmp_path):
    text = FAULTY.replace("0, 0.01, 0.1, 0.02", "0, 0.01, 0.02")
    scene, out = sweep(driver, tmp_path, text, "si")
    t = taper.read_sweep(out, pandas=False)
    r = taper.read_sweep(taper.run_scene(scene), pandas=False)
    assert r.units == {k: v for k, v in t.units.items() if k != "cpu_time"}
    assert "wall_peak_force_right[N]" in r and "wall_peak_force_left[N]" not in r
    for c in r:
        if not c.startswith(("energy_error", "momentum_error")):
            assert same(r[c], t[c]), c


def test_damaged_or_foreign_files_are_refused_naming_them(driver, tmp_path):
    _, out = sweep(driver, tmp_path, GRID, "grid")
    runs = out / "runs.tsv"
    good = runs.read_bytes()
    lines = good.splitlines(keepends=True)
    for damage in (b"".join(lines[:-2]), good.replace(b"complete", b"complEte", 1),
                   b"".join(lines[:-1])):
        runs.write_bytes(damage)
        with pytest.raises(ValueError, match=str(runs)):
            taper.read_sweep(out)
    runs.write_bytes(b"".join(lines[:-1]))  # no footer: an older taper's
    assert len(taper.read_sweep(out, verify=False, pandas=False)["run"]) == 8
    one = out / "n_granules=30,q=0.02,exponent=2.5"
    with pytest.raises(ValueError, match="not the output directory of a sweep"):
        taper.read_sweep(one)
    with pytest.raises(ValueError, match="not a runs.tsv"):
        taper.read_sweep(one / "granules.tsv")
    with pytest.raises(TypeError, match="run_scene"):
        taper.read_sweep([taper.read_granules(one / "granules.tsv")])
    with pytest.raises(ValueError, match="not runs of a sweep"):
        taper.read_sweep([taper.simulate(n_granules=10)])
