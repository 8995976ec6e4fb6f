# SPDX-License-Identifier: GPL-3.0-or-later
"""The checks of the retired ctypes binding's test (tests/bindings/test_python.py),
on the package: a backward linear chain through taper.simulate()/chain()/
theory() and through the driver (scene -> granules.tsv) gives the same
numbers bit for bit, the statistics by the library's names are the driver's
header, and refusals raise InvalidArgumentError naming the setting
(the ctypes binding's TaperError.field)."""

import os
import math

import numpy as np
import pytest

import taper

SCENE = """! a short backward linear chain
&chain
  profile = 'backward_linear'
  s = 0.2
  n_granules = 40
/
&output
  progress = .false.
/
"""
KW = dict(profile="backward_linear", s=0.2, n_granules=40)


def same_bits(a, b):
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and bool(np.all((a.view(np.int64) == b.view(np.int64))
                                              | (np.isnan(a) & np.isnan(b))))


@pytest.fixture(scope="module")
def runs(driver, tmp_path_factory):
    import subprocess
    tmp = tmp_path_factory.mktemp("agreement")
    scene = tmp / "scene.nml"
    scene.write_text(SCENE)
    proc = subprocess.run([str(driver), str(scene), "-o", str(tmp / "out")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    path = tmp / "out" / "granules.tsv"
    return path, taper.simulate(**KW)


def test_version():
    # The package's version is the library's, which is meson.build's project
    # version (passed by the test's definition in tests/bindings/python).
    assert taper.version() == taper.__version__ == os.environ["TAPER_PROJECT_VERSION"]


def test_every_column_equals_the_driver(runs):
    path, r = runs
    table = taper.read_granules(path)
    assert r.complete and r.status == "ok"
    c = taper.chain(**KW)
    th = taper.theory(**KW)
    assert len(c) == 40 and c.profile == "backward_linear"
    for name in table.columns:
        assert same_bits(r[name], table[name]), name
    for name in ("R", "m", "X0"):  # the chain alone, without a run
        assert same_bits(c[name], table[name]), name
    for name in ("theory_v", "theory_T", "theory_t"):  # the theory alone
        assert same_bits(th[name], table[name]), name
    assert math.isnan(r.t_pass[-1])


def test_statistics_are_the_driver_header(runs):
    """Every statistic the library names is in the driver's file (read by
    read_granules, the package's one reader of granules.tsv) with the run's
    value: counts and times exactly, the conservation errors to the 4
    digits the file keeps."""
    path, r = runs
    header = taper.read_granules(path).stats
    assert r.stats["complete"] is True and r.stats["granule_reached"] == 39
    assert set(r.stats) == set(taper.STATISTICS) | {"pulse_speed"}
    # The driver leaves out what the run does not have (the wall statistics
    # of a chain without walls are NaN); everything else is there.
    missing = [n for n in taper.STATISTICS if n != "complete" and n not in header
               and not math.isnan(r.stats[n])]
    assert not missing, f"statistics missing from the driver's header: {missing}"
    # the pulse's speed: one C function for the header and the package
    assert header["pulse_speed"] == r.stats["pulse_speed"] == r.pulse_speed() > 0
    for name in taper.STATISTICS:
        if name == "complete" or name not in header:  # a line of its own; absent: NaN
            continue
        value, ref = r.stats[name], header[name]
        if isinstance(value, float) and math.isnan(value):
            assert math.isnan(ref), (name, ref)
            continue
        if name.endswith("_error"):
            assert float("%.4g" % value) == ref, (name, value, ref)
        else:
            assert ref == value, (name, value, ref)


def test_state_where_the_run_ended(runs):
    _, r = runs
    assert r.x_final.shape == (40,) and r.v_final.shape == (40,)
    assert np.all(np.isfinite(r.x_final)) and np.all(np.isfinite(r.v_final))


@pytest.mark.parametrize("field,call", [
    ("n_granules", lambda: taper.chain(profile="forward_linear", n_granules=100, s=0.5)),
    ("rtol", lambda: taper.simulate(**KW, rtol=-1)),
    ("atol", lambda: taper.simulate(**KW, atol=0.5)),
    ("s", lambda: taper.chain(profile="backward_linear", s=float("nan"))),
    ("n_granules", lambda: taper.chain(profile="monodisperse", n_granules=1)),
    ("n_granules", lambda: taper.chain(profile="monodisperse", n_granules=-3)),
    ("exponent", lambda: taper.chain(profile="monodisperse", exponent=1.0)),
    ("radii", lambda: taper.chain(profile="custom", radii=[1.0, -1.0, 1.0])),
    ("radii", lambda: taper.chain(profile="custom", n_granules=3)),
    ("profile", lambda: taper.chain(profile="no_such_profile")),
    ("method", lambda: taper.simulate(**KW, method="rk4")),
    ("last_granule", lambda: taper.simulate(**KW, last_granule=41)),
    ("max_order", lambda: taper.simulate(**KW, method="bdf", max_order=6)),
    ("xtol", lambda: taper.fit([1, 2, 3], [1, 2, 3], xtol=0)),
    ("model", lambda: taper.fit([1, 2, 3], [1, 2, 3], model="cubic")),
    ("law", lambda: taper.asymptotic.exponent("no_such_law")),
])
def test_refusals_name_the_setting(field, call):
    with pytest.raises(taper.InvalidArgumentError) as e:
        call()
    err = e.value
    assert isinstance(err, ValueError) and err.field == field, (field, err.field, str(err))
    assert err.status == "invalid" and len(err.message) > 10


def test_unknown_keyword_is_a_type_error():
    for call in (taper.simulate, taper.theory, taper.chain):
        with pytest.raises(TypeError):
            call(no_such_setting=1)
    with pytest.raises(TypeError):
        taper.fit([1, 2, 3], [1, 2, 3], no_such_setting=1)


def test_custom_chain():
    c = taper.chain(profile="custom", radii=[1.0, 1.5, 2.0, 2.5])
    assert c.profile == "custom" and len(c) == 4 and c.R[3] == 2.5


def test_partial_runs_keep_their_observables():
    p = taper.simulate(**KW, max_steps=10)
    assert p.status == "limit" and "max_steps" in p.message and not p.complete
    assert p.stats["complete"] is False and len(p.t_pass) == 40


def test_law_exponent():
    assert taper.asymptotic.exponent("v_of_k") == -1.5
