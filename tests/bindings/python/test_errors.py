# SPDX-License-Identifier: GPL-3.0-or-later
"""Bad input: every wrong type or value raises TypeError or ValueError naming
the argument, with the library's message for values it refuses; nothing
crashes, however many combinations are tried."""

import math
import random

import numpy as np
import pytest

import taper

CHAIN = ("profile", "s", "q", "n_granules", "exponent", "radii")
SOLVER = ("method", "rtol", "atol", "window", "last_granule", "max_order", "t_max", "max_steps")

# Values of the wrong type for each keyword.
WRONG_TYPE = {
    "profile": [1, 2.5, b"monodisperse", ["monodisperse"], object()],
    "method": [0, 1.0, b"adams", ("bdf",)],
    "s": ["0.5", b"0.5", [0.5], 1j, True, object(), {}],
    "q": ["0.1", [0.1], 2j, False],
    "exponent": ["2.5", (2.5,), 1 + 0j, True],
    "rtol": ["1e-8", [1e-8], True, object()],
    "atol": ["1e-8", 1j, False],
    "t_max": ["10", [10.0]],
    "n_granules": [10.0, "10", True, np.float64(10), [10], 1j],
    "last_granule": [5.0, "5", False],
    "max_order": [3.0, "3", True],
    "max_steps": [100.0, "100", True],
    "window": [1.0, "yes", [True], None.__class__],
    "radii": ["1,2,3", b"123", True, [[1.0, 2.0], [3.0, 4.0]], ["a", "b"], [1j, 2j], object()],
}

# Values of the right type the library refuses, and the field it names.
REFUSED = {
    "profile": ["conical", "", "monodisperse "],
    "method": ["rk4", ""],
    "s": [-0.1, math.nan, math.inf, 1e300],
    "q": [-1.0, math.nan, 1e9],
    "exponent": [1.0, 0.5, -2.0, 21.0, math.nan, math.inf],
    "rtol": [0.0, -1e-8, 1e-16, 0.5, math.nan],
    "atol": [0.0, -1.0, 1.0, math.nan, math.inf],
    "t_max": [-1.0, math.nan],
    "n_granules": [0, 1, 10**7 + 1, 10**30, -1, -10**30],
    "last_granule": [-1, 10**30],
    "max_order": [-1, 13, 10**12],
    "max_steps": [-1, 10**30],
    "radii": [[1.0, -1.0], [1.0, math.nan], [1.0, 0.0], [1.0, math.inf]],
}


def check_type_error(kw, value):
    with pytest.raises(TypeError) as e:
        taper.simulate(**{kw: value})
    assert kw in str(e.value)


@pytest.mark.parametrize("kw", sorted(WRONG_TYPE))
def test_wrong_types_are_type_errors_naming_the_argument(kw):
    for value in WRONG_TYPE[kw]:
        check_type_error(kw, value)


@pytest.mark.parametrize("kw", sorted(REFUSED))
def test_refused_values_are_value_errors_naming_the_field(kw):
    for value in REFUSED[kw]:
        with pytest.raises(ValueError) as e:
            taper.simulate(**{kw: value})
        err = e.value
        assert isinstance(err, taper.InvalidArgumentError), (kw, value, err)
        assert err.field == kw, (kw, value, err.field, str(err))
        assert str(err).startswith(kw), str(err)
        assert err.status in ("invalid", "range")


@pytest.mark.parametrize("kw,value,field", [
    (dict(profile="forward_linear", s=0.1, n_granules=20), None, "n_granules"),
    (dict(profile="custom", n_granules=5), None, "radii"),
    (dict(profile="custom", radii=[1.0, 2.0, 3.0], n_granules=4), None, "radii"),
    (dict(profile="backward_exponential", q=1.5), None, "q"),
    (dict(n_granules=10, last_granule=11), None, "last_granule"),
    (dict(method="bdf", max_order=6), None, "max_order"),
])
def test_relations_name_the_setting_to_change(kw, value, field):
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(**kw)
    assert e.value.field in (field, "s", "profile"), (kw, e.value.field, str(e.value))
    assert e.value.message  # the library's own message


def test_unknown_keyword_and_positional():
    with pytest.raises(TypeError, match="rtoll"):
        taper.simulate(rtoll=1e-8)
    with pytest.raises(TypeError, match="rtoll"):
        taper._core.simulate(rtoll=1e-8)
    with pytest.raises(TypeError, match="did you mean 'rtol'"):
        taper.simulate(rtoll=1e-8)
    with pytest.raises(TypeError, match="'RTOL'.*did you mean 'rtol'"):
        taper.simulate(RTOL=1e-8)    # a keyword is spelt as its variable
    with pytest.raises(TypeError, match="numerics"):
        taper.theory(numerics=True)  # the theory is the scene without numerics
    with pytest.raises(TypeError, match="numerics"):
        taper._core.theory(numerics=False)
    with pytest.raises(TypeError, match="'sample_interval'"):   # &sensors interval now
        taper.simulate(sample_interval=1.0)
    with pytest.raises(TypeError):
        taper.simulate("monodisperse")
    with pytest.raises(TypeError):
        taper._core.simulate("monodisperse")


def test_theory_and_other_entry_points():
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.theory(n_granules=1)
    assert e.value.field == "n_granules"
    with pytest.raises(TypeError):
        taper.theory(s="x")
    with pytest.raises(TypeError):
        taper.collision_time("a", 1, 1)
    assert math.isnan(taper.collision_time(-1.0, 1.0, 1.0))
    with pytest.raises(FileNotFoundError):
        taper.read_granules("/nonexistent/granules.tsv")
    with pytest.raises(taper.SceneError):
        taper.run_scene("/nonexistent/scene.nml")
    with pytest.raises(TypeError):
        taper.run_scene(42)


def test_read_granules_rejects_garbage(tmp_path):
    p = tmp_path / "g.tsv"
    # without footers: refused by it, and by the parser once it is waived
    for text, why in [("# only comments\n", "no header line"), ("k\tR\n1\tabc\n", "column R"),
                      ("k\tR\n1\t2\t3\n", "3 values per row")]:
        p.write_text(text)
        with pytest.raises(ValueError, match="no footer"):
            taper.read_granules(p)
        with pytest.raises(ValueError, match=why):
            taper.read_granules(p, verify=False)


POOL = {
    "profile": ["monodisperse", "backward_linear", "forward_linear", "backward_exponential",
                "forward_exponential", "custom", "nope", 3, None],
    "s": [0.0, 0.1, 0.5, -1.0, math.nan, "x", None],
    "q": [0.0, 0.05, 0.5, 1.0, -0.5, math.inf, None],
    "n_granules": [2, 3, 12, 0, -5, 10**8, 4.0, None],
    "exponent": [1.5, 2.5, 3.0, 1.0, 100.0, None],
    "radii": [[1.0, 1.2, 0.9], [1.0, 1.0], [], [1.0, -2.0], "r", None],
    "method": ["adams", "bdf", "BDF", "x", None],
    "rtol": [1e-6, 1e-10, 0.0, 1.0, None],
    "atol": [1e-8, 0.05, -1.0, None],
    "window": [True, False, 2, "no", None],
    "last_granule": [0, 2, 5, 100, -1, None],
    "max_order": [0, 1, 5, 12, 13, None],
    "t_max": [0.0, 5.0, -3.0, None],
    "max_steps": [0, 5000, -1, None],
}


def test_fuzz_sweep_never_crashes():
    """Random combinations (fixed seed): a Result or a TypeError/ValueError,
    never anything else; a ValueError from the library names a field."""
    rng = random.Random(16)
    outcomes = {"result": 0, "type": 0, "value": 0}
    for _ in range(400):
        kw = {k: rng.choice(v) for k, v in POOL.items() if rng.random() < 0.5}
        kw["max_steps"] = 5000 if kw.get("max_steps") in (None, 0) else kw["max_steps"]
        try:
            r = taper.simulate(**kw)
        except TypeError:
            outcomes["type"] += 1
        except ValueError as e:
            outcomes["value"] += 1
            if isinstance(e, taper.InvalidArgumentError) and e.field is not None:
                assert e.field in POOL, e.field
        else:
            outcomes["result"] += 1
            assert len(r) >= 2 and r.status in ("ok", "limit", "solver")
    assert all(outcomes.values()), outcomes
