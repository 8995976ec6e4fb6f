# SPDX-License-Identifier: GPL-3.0-or-later
"""The package behaves as Python users expect (issue 35, "Native Python"):
import taper leaves numpy alone; Result.to_pandas() names SI columns as the
driver's granules.tsv header does and carries units, settings and
statistics; the repr shows what a physicist checks first; progress= draws
a bar where someone watches and calls a callable with the run's progress;
taper.plot labels its axes with quantity and unit; taper_from_radii and
radii_from_taper agree with the library's chain."""

import math
import os
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import taper

STEEL = dict(young=193e9, poisson=0.3, density=8000.0, radius=4.76e-3, velocity=0.5)


def run_python(code, **kw):
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=300, **kw)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


# ---- import --------------------------------------------------------------------

def test_import_taper_does_not_import_numpy():
    """numpy's import is most of a package's import: taper imports it on the
    first call that returns arrays, and then works as before."""
    out = run_python("""
        import sys, taper
        print('numpy' in sys.modules, len(taper.variables()) > 50, taper.PROFILES[0])
        r = taper.theory(n_granules=3)
        print('numpy' in sys.modules, type(r.theory_v).__module__)
    """)
    assert out.split("\n")[:2] == ["False True monodisperse", "True numpy"], out


# ---- to_pandas -----------------------------------------------------------------

def test_to_pandas_names_si_columns_as_granules_tsv(run_driver):
    """The DataFrame of an SI run has granules.tsv's header as its columns
    (the driver's, for the same scene), the same numbers, and attrs with
    the units, settings and statistics."""
    pd = pytest.importorskip("pandas")
    r = taper.simulate(n_granules=30, units="si", **STEEL)
    scene = "&chain n_granules = 30 /\n&output units = 'si' /\n&material " + ", ".join(
        f"{k} = {v!r}" for k, v in STEEL.items()) + " /\n"
    path = run_driver(scene)
    header = path.read_text().splitlines()[0].split("\t")
    df = r.to_pandas()
    assert list(df.columns) == header
    assert "t_pass[s]" in header and "v_peak[m/s]" in header and "k" in header
    driver = pd.read_csv(path, sep="\t", comment="#")
    for column in header:
        np.testing.assert_array_equal(df[column].to_numpy(), driver[column].to_numpy())
    assert list(df.index) == list(range(1, 31))
    assert df.attrs["units"]["t_pass"] == "s" and df.attrs["units"]["t_final"] == "s"
    assert df.attrs["units"] == r.units
    assert df.attrs["settings"]["n_granules"] == 30 and df.attrs["settings"]["young"] == 193e9
    assert df.attrs["stats"] == r.stats and df.attrs["stats"]["complete"] is True
    assert df.attrs["complete"] is True and df.attrs["status"] == "ok"


def test_to_pandas_of_rescaled_results_has_the_bare_names():
    pytest.importorskip("pandas")
    r = taper.simulate(profile="backward_linear", s=0.1, n_granules=20)
    df = r.to_pandas()
    assert list(df.columns) == list(taper.COLUMNS)
    assert df.attrs["units"] == {} and df.attrs["settings"]["s"] == 0.1
    np.testing.assert_array_equal(df["v_peak"].to_numpy(), r.v_peak)


# ---- repr and the pulse's speed ---------------------------------------------------

def test_pulse_speed_against_the_columns_and_the_theory():
    """The pulse speed over a stretch is the slope of X_pass against t_pass
    there; in a monodisperse chain the binary collision theory's speed (rest
    spacing 2 over its times t_k, eq. (19)) is within 5 % of the numerics',
    and in SI it is the rescaled speed times R_1 over the unit of time."""
    r = taper.simulate(n_granules=200)
    k0, k1 = 150, 199
    assert r.pulse_speed(k0, k1) == (r.X_pass[k1 - 1] - r.X_pass[k0 - 1]) / \
        (r.t_pass[k1 - 1] - r.t_pass[k0 - 1])
    # the default stretch: the last tenth of the granules passed (180..199)
    assert r.pulse_speed() == r.pulse_speed(180, 199)
    theory = taper.theory(n_granules=200).pulse_speed()
    assert abs(theory / r.pulse_speed() - 1) < 0.05, (theory, r.pulse_speed())
    # SI: rest positions in R_1, displacements and times in the units of
    # eq. (5) (test_units.py)
    from test_units import unit_time_and_length
    T, L = unit_time_and_length()
    si = taper.simulate(n_granules=200, **STEEL)
    i0, i1 = 179, 198
    x = r.X_pass - r.X0
    expected = ((r.X0[i1] - r.X0[i0]) * STEEL["radius"] + (x[i1] - x[i0]) * L) / \
        ((r.t_pass[i1] - r.t_pass[i0]) * T)
    assert si.pulse_speed() == pytest.approx(expected, rel=1e-12)
    assert math.isnan(taper.simulate(n_granules=30, max_steps=5).pulse_speed())


def test_pulse_speed_is_the_drivers_whatever_the_rows_and_columns(tmp_path):
    """stats["pulse_speed"] comes from every granule's columns in the
    result's units (drivers/scenes/results/pulse.h), so that neither &output
    every nor columns changes it, and granules.tsv's header (the driver's
    file, rows thinned, X_pass and t_pass left out) holds the same double;
    the theory alone gets it from the same function."""
    r = taper.simulate(n_granules=200)
    thin = taper.simulate(n_granules=200, every=7, columns="k v_peak")
    assert "X_pass" not in thin.columns and thin.stats["pulse_speed"] == r.stats["pulse_speed"]
    assert thin.pulse_speed() == r.pulse_speed() == r.pulse_speed(180, 199)
    scene = tmp_path / "thin.nml"
    scene.write_text("&chain n_granules = 200 /\n&output every = 7, columns = 'k v_peak' /\n")
    subprocess.run([os.environ["TAPER_DRIVER"], str(scene), "-o", str(tmp_path / "out")],
                   check=True, capture_output=True)
    header = taper.read_granules(tmp_path / "out" / "granules.tsv")
    assert header.stats["pulse_speed"] == r.stats["pulse_speed"]
    th = taper.theory(n_granules=200)
    k0, k1 = 180, 199   # the theory's t_k is known to granule 199
    assert th.pulse_speed() == (th.X0[k1 - 1] - th.X0[k0 - 1]) / (th.theory_t[k1 - 1] -
                                                                  th.theory_t[k0 - 1])


def test_repr_shows_what_a_physicist_checks_first():
    r = taper.simulate(profile="backward_linear", s=0.5, n_granules=60)
    text = repr(r)
    assert text.startswith("<taper.Result backward_linear s=0.5 N=60 complete: ")
    assert f"t_final={r.stats['t_final']:.4g}" in text
    assert f"energy error {r.energy_error:.2g}" in text
    assert f"pulse speed {r.pulse_speed():.4g}" in text
    wall = taper.simulate(n_granules=30, right="wall", t_end=100, **STEEL)
    force = wall.stats["wall_peak_force_right"]
    assert force > 0 and f"right wall peak force {force:.4g} N" in repr(wall)
    assert f"pulse speed {wall.pulse_speed():.4g} m/s" in repr(wall)
    assert "left wall" not in repr(wall)
    partial = taper.simulate(n_granules=50, max_steps=20)
    assert "N=50 PARTIAL (limit: max_steps reached" in repr(partial)
    bad = taper.simulate(n_granules=200, rtol=0.1, atol=0.1, max_energy_error=1e-12)
    assert "UNTRUSTED" in repr(bad)
    th = taper.theory(profile="forward_exponential", q=0.1, n_granules=40)
    assert repr(th).startswith("<taper.Result forward_exponential q=0.1 N=40 theory only: "
                               "pulse speed ")


# ---- progress ------------------------------------------------------------------

def test_a_progress_callable_follows_the_run():
    """Called every 0.1 s while the run lasts and once at its end, with the
    granules passed (never fewer than before), the target (granule N - 1:
    passes are timed at the contacts), t and the rate; the last call is
    where the run ended."""
    calls = []
    r = taper.simulate(n_granules=20000, progress=lambda *a: calls.append(a))
    assert len(calls) >= 2, calls
    passed = [c[0] for c in calls]
    assert passed == sorted(passed) and all(c[1] == 19999 for c in calls)
    assert calls[-1][0] == r.stats["granule_reached"] == 19999
    assert calls[-1][2] == r.stats["t_final"]
    assert all(c[3] > 0 for c in calls) and all(isinstance(c[0], int) for c in calls)
    assert r.settings["progress"] is True
    # in SI t is in seconds, as the Result's
    si = []
    s = taper.simulate(n_granules=50, progress=lambda *a: si.append(a), **STEEL)
    assert si[-1][2] == s.stats["t_final"] < 1e-2


def test_an_exception_in_progress_stops_the_run():
    class Enough(Exception):
        pass

    def stop(passed, target, t, rate):
        raise Enough(passed)

    with pytest.raises(Enough):
        taper.simulate(n_granules=200_000, progress=stop)
    assert taper.simulate(n_granules=10).complete  # the package goes on


BAR = """
    import sys, taper
    {hide}
    r = taper.simulate(n_granules={n}, progress={progress})
    print("done", r.complete, flush=True)
"""


def run_with_terminal(code):
    """stdout, stderr of `code` with stderr a terminal (a pseudo-terminal)."""
    import fcntl
    import pty
    import struct
    import termios
    master, slave = pty.openpty()
    # a terminal of 24 lines of 100 columns (a new pty has none: 0 x 0)
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
    proc = subprocess.Popen([sys.executable, "-c", textwrap.dedent(code)],
                            stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    err = b""
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:
            break
        if not chunk:
            break
        err += chunk
    out = proc.communicate(timeout=300)[0]
    os.close(master)
    assert proc.returncode == 0, err
    return out, err.decode(errors="replace")


def test_progress_true_draws_a_line_on_a_terminal_and_clears_it():
    """Without tqdm: one line rewritten in place ("taper: granule k/N ..."),
    shown once the run has lasted half a second, blanked at the end."""
    out, err = run_with_terminal(BAR.format(hide="sys.modules['tqdm'] = None", n=30000,
                                            progress="True"))
    assert out == "done True\n"
    lines = re.findall(r"\rtaper: granule (\d+)/29999  t = \S+  \S+ granules/s", err)
    assert lines and int(lines[-1]) <= 29999, err[-500:]
    assert err.endswith("\r"), repr(err[-100:])


def test_progress_true_draws_a_tqdm_bar_when_tqdm_is_there():
    pytest.importorskip("tqdm")
    out, err = run_with_terminal(BAR.format(hide="", n=30000, progress="True"))
    assert out == "done True\n"
    assert re.search(r"taper: +\d+%\|.*\| *\d+/29999", err), err[-500:]


def test_progress_draws_nothing_unwatched_or_when_off():
    """stderr a pipe (a log, a batch job), as the driver's line: nothing;
    progress=False: nothing on a terminal either."""
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(
        BAR.format(hide="", n=30000, progress="True"))], capture_output=True, text=True,
        timeout=300)
    assert proc.stdout == "done True\n" and proc.stderr == ""
    out, err = run_with_terminal(BAR.format(hide="", n=30000, progress="False"))
    assert out == "done True\n" and err == ""


# ---- plot labels ------------------------------------------------------------------

def test_plot_labels_axes_with_quantity_and_unit():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    si = taper.simulate(n_granules=20, **STEEL)
    ax = taper.plot(si, "v")
    assert ax.get_xlabel() == "granule $k$"
    assert ax.get_ylabel() == "pulse amplitude $v_k$ [m/s]"
    ax = taper.plot(si, "T_res", x="t_pass", loglog=False)
    assert ax.get_xlabel() == "time the pulse passes, $t_k$ [s]"
    assert ax.get_ylabel() == "residence time $T_k$ [s]"
    rescaled = taper.theory(profile="backward_linear", s=0.2, n_granules=20)
    ax = taper.plot(rescaled, "t", curves="theory")
    assert ax.get_ylabel() == "time the pulse passes, $t_k$ (rescaled units, eq. (5))"
    si_theory = taper.theory(n_granules=20, **STEEL)
    assert taper.plot(si_theory, "t").get_ylabel() == "time the pulse passes, $t_k$ [s]"
    import matplotlib.pyplot as plt
    plt.close("all")


# ---- geometry --------------------------------------------------------------------

@pytest.mark.parametrize("profile,value,n", [
    ("backward_linear", 0.05, 101), ("forward_linear", 0.009, 100),
    ("backward_exponential", 0.02, 300), ("forward_exponential", 0.1, 60)])
def test_radii_from_taper_is_the_librarys_chain_and_taper_from_radii_its_inverse(profile, value,
                                                                                 n):
    """R_N as the library builds the chain (eqs. of Secs. III-IV), bit for
    bit; and back to the parameter to within rounding."""
    name = "s" if "linear" in profile else "q"
    c = taper.chain(profile=profile, n_granules=n, **{name: value})
    first, last = taper.radii_from_taper(profile, value, n)
    assert (first, last) == (1.0, c.R[-1])
    assert taper.radii_from_taper(profile, value, n, first=2e-3) == (2e-3, 2e-3 * c.R[-1])
    back = taper.taper_from_radii(profile, 2e-3, 2e-3 * c.R[-1], n)
    assert back == pytest.approx(value, rel=1e-12)
    again = taper.chain(profile=profile, n_granules=n, **{name: back})
    assert again.R[-1] == pytest.approx(last, rel=1e-13)


def test_taper_from_radii_refuses_as_the_scene():
    with pytest.raises(taper.InvalidArgumentError, match="radii grow along the chain") as e:
        taper.taper_from_radii("backward_linear", 2.0, 1.0, 10)
    assert e.value.field == "last"
    with pytest.raises(taper.InvalidArgumentError, match="shrink") as e:
        taper.taper_from_radii("forward_exponential", 1.0, 3.0, 10)
    assert e.value.field == "last"
    with pytest.raises(taper.InvalidArgumentError, match="no tapering parameter") as e:
        taper.taper_from_radii("monodisperse", 1.0, 1.0, 10)
    assert e.value.field == "profile"
    with pytest.raises(taper.InvalidArgumentError) as e:   # the scene's own message
        taper.taper_from_radii("conical", 1.0, 2.0, 10)
    assert e.value.field == "profile" and "'backward_linear'" in str(e.value)
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.taper_from_radii("backward_linear", 1.0, 2.0, 1)
    assert e.value.field == "n_granules" and "[2, 1e+07]" in str(e.value)
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.taper_from_radii("backward_linear", 0.0, 2.0, 10)
    assert e.value.field == "first"
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.taper_from_radii("backward_linear", 1.0, float("inf"), 10)
    assert e.value.field == "last"
    # the scene's range of s: beyond 1e3 over one contact
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.taper_from_radii("backward_linear", 1.0, 5000.0, 2)
    assert e.value.field == "s" and "out of range" in str(e.value)
    with pytest.raises(TypeError):
        taper.taper_from_radii("backward_linear", "1", 2.0, 10)
    with pytest.raises(TypeError):
        taper.taper_from_radii("backward_linear", 1.0, 2.0, 10.0)
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.radii_from_taper("forward_linear", 0.5, 5)
    assert e.value.field == "n_granules" and "1 + 1/s" in str(e.value)
