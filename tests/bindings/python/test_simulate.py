# SPDX-License-Identifier: GPL-3.0-or-later
"""simulate(), theory() and read_granules() against the driver and closed forms."""

import math

import numpy as np
import pytest

import taper

MONODISPERSE = """&chain profile = 'monodisperse', n_granules = 60 /
&output progress = .false. /
"""
BACKWARD_LINEAR = """&chain profile = 'backward_linear', s = 0.3, n_granules = 80 /
&solver rtol = 1d-9 /
&output progress = .false. /
"""


def parse_tsv(path):
    """The driver's table, parsed independently of read_granules: Python's
    float() on each cell."""
    lines = [l.rstrip("\n").split("\t") for l in open(path) if not l.startswith("#")]
    header, rows = lines[0], lines[1:]
    return {name: [float(r[i]) for r in rows] for i, name in enumerate(header)}


def assert_bitwise(a, b, name):
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    assert a.shape == b.shape, name
    same = (a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b))
    bad = np.flatnonzero(~same)
    assert bad.size == 0, f"{name} differs at granules {bad[:5] + 1}: {a[bad[:3]]} vs {b[bad[:3]]}"


@pytest.mark.parametrize("scene,kw", [
    (MONODISPERSE, dict(profile="monodisperse", n_granules=60)),
    (BACKWARD_LINEAR, dict(profile="backward_linear", s=0.3, n_granules=80, rtol=1e-9)),
])
def test_simulate_equals_driver_bit_for_bit(run_driver, scene, kw):
    path = run_driver(scene)
    table = parse_tsv(path)
    r = taper.simulate(**kw)
    assert r.complete and r.status == "ok" and r.message == ""
    assert list(r.columns) == list(table), "columns named and ordered as in granules.tsv"
    for name in table:
        assert_bitwise(r[name], table[name], name)
    # read_granules gives the same Result, the statistics too
    back = taper.read_granules(path)
    assert back.equals(r)
    assert back.complete
    for name in taper.STATISTICS:
        if name in back.stats and name not in ("energy_error", "momentum_error"):
            assert back.stats[name] == r.stats[name], name
    # the file rounds the errors to 4 digits
    assert back.energy_error == pytest.approx(r.energy_error, rel=1e-3, abs=1e-300)


def test_result_contents():
    r = taper.simulate(profile="backward_linear", s=0.5, n_granules=30)
    assert len(r) == 30 and r.k.dtype == np.int64 and list(r.k) == list(range(1, 31))
    for c in r.columns[1:]:
        assert r[c].dtype == np.float64 and r[c].shape == (30,)
    assert set(r.stats) == set(taper.STATISTICS) | {"pulse_speed"}
    assert r.stats["complete"] is True and isinstance(r.stats["steps"], int)
    assert r.stats["granule_reached"] == 29
    assert 0 <= r.energy_error < 1e-6 and 0 <= r.momentum_error < 1e-6
    assert math.isnan(r.t_pass[-1]) and r.v_peak[0] == 1.0
    assert r.settings["profile"] == "backward_linear" and r.settings["s"] == 0.5
    assert r.settings["rtol"] == 1e-10 and r.settings["method"] == "adams"
    assert r.x_final.shape == (30,) and r.v_final.shape == (30,)
    assert r.warnings == []
    s = r.to_numpy()
    assert s.dtype.names == r.columns and s["v_peak"][3] == r.v_peak[3]


def test_partial_run_is_returned_not_raised():
    r = taper.simulate(profile="monodisperse", n_granules=200, max_steps=50)
    assert not r.complete and r.status == "limit" and r.message
    assert r.stats["complete"] is False
    reached = r.stats["granule_reached"]
    assert reached < 199
    assert np.all(np.isnan(r.t_pass[reached:]))


def test_monodisperse_theory_closed_form():
    n = 2.5
    th = taper.theory(profile="monodisperse", n_granules=50, exponent=n)
    assert th.columns == taper.THEORY_COLUMNS
    # eq. (9): equal masses pass the velocity on unchanged, exactly
    assert np.all(th.theory_v == 1.0)
    # eq. (18) with mu = 1/2, r = 1, zdot0 = 1
    T = math.sqrt(math.pi) * (n / 4) ** (1 / n) * math.gamma(1 + 1 / n) / math.gamma(1 / n + 0.5)
    assert th.theory_T[:-1] == pytest.approx(np.full(49, T), rel=1e-14)
    assert taper.collision_time(0.5, 1.0, 1.0, n) == pytest.approx(T, rel=1e-14)
    # eq. (19): t_k = sum_{j<=k} T_j = k T
    assert th.theory_t[:-1] == pytest.approx(T * np.arange(1, 50), rel=1e-13)
    assert math.isnan(th.theory_T[-1]) and math.isnan(th.theory_t[-1])


@pytest.mark.parametrize("S", [0.1, 0.5, 0.9])
def test_backward_linear_theory_closed_form(S):
    N = 300
    th = taper.theory(profile="backward_linear", s=S, n_granules=N)
    k = np.arange(1, N + 1)
    assert th.R == pytest.approx(1 + S * (k - 1), rel=1e-15)
    # eq. (21), eq. (9) with m_k/m_{k+1} = (1 - S/(1 + S k))^3
    ratio = (1 - S / (1 + S * k[:-1])) ** -3.0
    v = np.concatenate([[1.0], np.cumprod(2 / (1 + ratio))])
    assert th.theory_v == pytest.approx(v, rel=1e-12)
    if S * N < 100:
        return
    # eq. (22): v_k ~ k^-3/2 for S k >> 1
    slope = np.log(th.theory_v[-1] / th.theory_v[-50]) / np.log(N / (N - 49))
    assert slope == pytest.approx(-1.5, abs=0.02)


def test_theory_equals_simulate_theory_columns():
    kw = dict(profile="backward_exponential", q=0.05, n_granules=40)
    th, r = taper.theory(**kw), taper.simulate(**kw)
    for c in taper.THEORY_COLUMNS:
        assert_bitwise(th[c], r[c], c)


def test_custom_radii_set_n_granules():
    radii = [1.0, 1.1, 1.3, 1.2, 1.5, 1.4]
    r = taper.simulate(profile="custom", radii=radii)
    assert len(r) == 6 and list(r.R) == radii and r.complete
    assert list(r.settings["radii"]) == radii


def test_to_pandas():
    pd = pytest.importorskip("pandas")
    r = taper.simulate(n_granules=10)
    df = r.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == list(r.columns)
    assert df.loc[3, "v_peak"] == r.v_peak[2]


def test_plot():
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    rs = [taper.simulate(profile="backward_linear", s=s, n_granules=30) for s in (0.2, 0.5)]
    ax = taper.plot(rs, "v")
    assert len(ax.lines) == 4
    ax = taper.plot(rs[0], "t", curves="theory", loglog=False)
    assert len(ax.lines) == 1


def test_nothing_is_printed_warnings_are_collected(capfd):
    r = taper.simulate(n_granules=200, rtol=0.1, atol=0.1)  # drifts: the library warns
    assert any("energy error" in w for w in r.warnings)  # among others (out-of-order passes)
    p = taper.simulate(n_granules=100, max_steps=20)         # a partial run
    assert p.status == "limit" and "max_steps" in p.message
    out, err = capfd.readouterr()  # the file descriptors, where C code would print
    assert out == "" and err == ""
