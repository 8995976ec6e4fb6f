# SPDX-License-Identifier: GPL-3.0-or-later
"""The keywords of simulate(), theory() and chain() are the scene's
variables: every variable `taper --defaults` prints is a keyword under the
one naming rule (the key in its group, with the group's name in front where
two groups share a key), but those docs/python.md names as making no sense
for one run; each is a keyword-only parameter of the signature with its
default (help() and the stub too), accepted at its default with a result
equal to simulate()'s bit for bit; taper.variables() lists the same table;
unknown keywords and wrong Python types are TypeErrors naming them."""

import inspect
import pydoc
import re
import subprocess

import numpy as np
import pytest

import taper


def defaults(driver):
    """(group, key, value) of every variable `taper --defaults` prints, the
    value parsed from its namelist text (None for one it prints as "(none)"
    or leaves to the scene's file name)."""
    out = subprocess.run([str(driver), "--defaults"], capture_output=True, text=True,
                         check=True, timeout=60).stdout
    rows, group = [], None
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("&"):
            group = line[1:]
            continue
        m = re.match(r"!?\s*(\w+)\s*=\s*(.*)$", line)
        if not m or group is None or line.startswith("! &"):
            continue
        key, rest = m.group(1), m.group(2)
        if line.startswith("!"):           # "! radii = (none)", "! dir = 'out/NAME'"
            rows.append((group, key, None))
            continue
        text = rest.split("!")[0].strip() if not rest.startswith("'") else \
            rest[:rest.index("'", 1) + 1]
        rows.append((group, key, namelist_value(text)))
    return rows


def namelist_value(text):
    if text.startswith("'"):
        return text[1:-1].replace("''", "'")
    if text.lower() in (".true.", ".false."):
        return text.lower() == ".true."
    try:
        return int(text)
    except ValueError:
        return float(text.replace("d", "e").replace("D", "e"))


@pytest.fixture(scope="module")
def table(driver):
    return defaults(driver)


def test_defaults_and_variables_are_one_table(table):
    """taper.variables() is the table --defaults prints, in its order, each
    name following the rule, unique, with the same default."""
    variables = taper.variables()
    assert [(v.group, v.key) for v in variables] == [(g, k) for g, k, _ in table]
    names = [v.name for v in variables]
    assert len(set(names)) == len(names)
    for v, (group, key, value) in zip(variables, table):
        # the rule: the key, or the key with its group's name in front
        # (where two groups share a key, and for &fit, &table, &figure, &sweep)
        assert v.name in (key, f"{group}_{key}"), v
        if value is not None:
            assert v.default == value or (isinstance(value, int) and v.default == float(value)), v
        assert v.description and isinstance(v.range, str)
        assert v.type in ("real", "integer", "logical", "string", "choice", "real list")
        assert (v.choices is not None) == (v.type == "choice")
        if v.choices:
            assert v.default is None or v.default in v.choices, v
    by = {v.name: v for v in variables}
    assert by["striker_radius"].key == "radius" and by["striker_radius"].group == "striker"
    assert by["radius"].group == "material" and by["radius"].unit == "m"
    assert by["figure_every"].key == "every" and by["every"].group == "output"
    assert by["t_end"].unit == "s" and by["damping"].unit == "s" and by["load"].unit == "N"
    assert by["drag"].unit == "kg/s" and by["interval"].unit == "s" and by["s"].unit is None
    assert by["n_granules"].sweep and by["n_granules"].range == "[2, 1e+07]"
    assert by["method"].choices == taper.METHODS and by["profile"].choices == taper.PROFILES
    assert by["damping"].beyond_paper and not by["s"].beyond_paper


def documented_driver_only(source):
    """The variables docs/python.md names as no keyword of a call (its table
    "What a call does not take": every name in backquotes in the first
    column), and the reasons it gives."""
    text = (source / "docs" / "python.md").read_text()
    section = text[text.index("### What a call does not take"):]
    section = section[:section.index("\n#", 1)]
    names = {}
    for line in section.splitlines():
        if not line.startswith("| `"):
            continue
        first, reason = line.split("|")[1:3]
        for name in re.findall(r"`([a-z_]+)`", first):
            names[name] = reason.strip()
    return names


def test_the_signature_is_the_table_less_what_a_call_does_not_take(table, source):
    """The issue's must-show: len(inspect.signature(taper.simulate).parameters)
    is the number of variables --defaults prints, less those docs/python.md
    names with a reason; each of those is refused with a TypeError saying
    why, every other one is a keyword-only parameter with its default."""
    name = {(v.group, v.key): v.name for v in taper.variables()}
    excluded = documented_driver_only(source)
    assert excluded and all(reason for reason in excluded.values()), excluded
    assert set(excluded) <= set(name.values()), set(excluded) - set(name.values())
    params = inspect.signature(taper.simulate).parameters
    assert len(params) == len(table) - len(excluded)
    defaults = {v.name: v.default for v in taper.variables()}
    for group, key, _ in table:
        n = name[group, key]
        if n in excluded:
            assert n not in params
            for call in (taper.simulate, taper.theory, taper.chain):
                with pytest.raises(TypeError, match=f"does not take {n}: "):
                    call(**{n: defaults[n]})
        else:
            p = params[n]
            assert p.kind is inspect.Parameter.KEYWORD_ONLY, p
            assert p.default == defaults[n] or (p.default is None and defaults[n] is None), p
    theory = inspect.signature(taper.theory).parameters
    assert list(theory) == [n for n in params if n != "numerics"]
    assert list(inspect.signature(taper.chain).parameters) == list(params)
    assert inspect.signature(taper.simulate).return_annotation is taper.Result


def test_help_shows_every_keyword_with_its_unit_and_description():
    doc = pydoc.render_doc(taper.simulate, renderer=pydoc.plaintext)
    for v in taper.variables():
        if v.name not in inspect.signature(taper.simulate).parameters:
            continue
        # "      name: type = default  [unit with &material]", then the
        # description indented further
        m = re.search(rf"^ {{6}}{v.name}: (.*)$\n {{10}}(.*)$", doc, re.M)
        assert m, v.name
        if v.unit:
            assert f"[{v.unit} with &material]" in m.group(1), (v.name, m.group(1))
        assert v.description.split()[0] in m.group(2) or v.name == "progress", (v.name, m.group(2))


def test_the_stub_has_the_same_parameters():
    """__init__.pyi ships with the package (PEP 561: py.typed), its
    simulate(), theory() and chain() with the parameters of the runtime
    signatures, in order, with the same defaults."""
    import ast
    import pathlib
    here = pathlib.Path(taper.__file__).parent
    assert (here / "py.typed").is_file()
    tree = ast.parse((here / "__init__.pyi").read_text())
    funcs = {f.name: f for f in tree.body if isinstance(f, ast.FunctionDef)}
    for func in (taper.simulate, taper.theory, taper.chain):
        stub = funcs[func.__name__].args
        runtime = inspect.signature(func).parameters
        assert [a.arg for a in stub.kwonlyargs] == list(runtime)
        for a, d in zip(stub.kwonlyargs, stub.kw_defaults):
            assert ast.literal_eval(d) == runtime[a.arg].default, a.arg


def test_simulate_accepts_every_keyword_at_its_default(table, source):
    """Every keyword at its default (None for those without one): the run is
    simulate()'s, bit for bit, statistics and settings included."""
    name = {(v.group, v.key): v.name for v in taper.variables()}
    excluded = documented_driver_only(source)
    ref = taper.simulate()
    assert ref.complete and len(ref) == 100
    for group, key, value in table:
        if name[group, key] in excluded:
            continue
        kw = {name[group, key]: value}
        r = taper.simulate(**kw)
        assert r.equals(ref), kw
        assert _same(r.stats, ref.stats), kw
        assert _same(r.settings, ref.settings), kw
        if value is not None:
            assert r.settings[name[group, key]] == value, kw
    assert set(ref.settings) == set(inspect.signature(taper.simulate).parameters)
    # all of them at once too, and the settings given back
    everything = {name[g, k]: v for g, k, v in table if name[g, k] not in excluded}
    assert taper.simulate(**everything).equals(ref)
    assert taper.simulate(**ref.settings).equals(ref)


def _same(a, b):
    """Equal dicts, NaN equal to NaN, arrays compared by value."""
    def eq(x, y):
        if isinstance(x, np.ndarray):
            return np.array_equal(x, y)
        return x == y or (isinstance(x, float) and x != x and y != y)
    return a.keys() == b.keys() and all(eq(a[k], b[k]) for k in a)


def test_theory_and_chain_take_the_same_keywords(table, source):
    name = {(v.group, v.key): v.name for v in taper.variables()}
    excluded = documented_driver_only(source)
    th, c = taper.theory(), taper.chain()
    for group, key, value in table:
        if name[group, key] in excluded:
            continue
        kw = {name[group, key]: value}
        if name[group, key] == "numerics":
            with pytest.raises(TypeError, match="numerics"):
                taper.theory(**kw)
        else:
            assert taper.theory(**kw).equals(th), kw
        assert np.array_equal(taper.chain(**kw).R, c.R), kw


def test_unknown_keywords_say_the_nearest_name():
    for call in (taper.simulate, taper.theory, taper.chain):
        with pytest.raises(TypeError, match=r"unexpected keyword argument 'n_granule' "
                                            r"\(did you mean 'n_granules'\?"):
            call(n_granule=10)
        with pytest.raises(TypeError, match="'striker_radios'.*'striker_radius'"):
            call(striker_radios=1.0)
        with pytest.raises(TypeError, match="'no_such_variable'"):
            call(no_such_variable=1)


@pytest.mark.parametrize("kw,value,what", [
    ("s", "0.5", "a real number"),          # a str for a real
    ("damping", True, "a real number"),     # a bool for a number
    ("young", 1 + 2j, "a real number"),
    ("n_granules", 10.0, "an integer"),     # a float for an integer
    ("seed", np.float64(3), "an integer"),
    ("max_steps", False, "an integer"),
    ("window", 1, "a bool"),                # an int for a logical
    ("numerics", "yes", "a bool"),
    ("profile", 3, "a str"),                # a number for a choice
    ("columns", 1.0, "a str"),
    ("radii", 1.0, "a one-dimensional sequence"),
    ("radii", "1 2 3", "a sequence of real numbers"),
    ("densities", [[1.0, 2.0]], "a one-dimensional sequence"),
])
def test_a_wrong_python_type_is_a_type_error_naming_the_keyword(kw, value, what):
    with pytest.raises(TypeError) as e:
        taper.simulate(**{kw: value})
    assert str(e.value).startswith(kw) and what in str(e.value), str(e.value)


def test_a_list_for_a_sweepable_variable_is_refused():
    """A scene file sweeps a list; a call runs one chain."""
    for kw, value in (("s", [0.1, 0.2]), ("n_granules", (10, 20)), ("rtol", np.array([1e-8]))):
        with pytest.raises(TypeError, match=f"runs one chain: {kw} takes one value"):
            taper.simulate(**{kw: value})


def test_refusals_are_the_scenes_messages_with_the_keyword_as_field():
    # the scene's own rules: &material needs its five variables
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(young=193e9)
    assert e.value.field == "poisson" and "&material needs poisson" in e.value.message
    assert str(e.value).startswith("poisson: ") and "density: " in str(e.value)
    # a key the scene writes inside its group is reported by its keyword
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(every=0)
    assert e.value.field == "every"
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(striker_radius=-1.0)
    assert e.value.field == "striker_radius" and e.value.status == "invalid"
    # a choice's names
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(method="rk4")
    assert e.value.field == "method" and "'adams', 'bdf'" in e.value.message
    # not a finite number
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(t_end=float("inf"))
    assert e.value.field == "t_end"
    # relations: a piston's duration without a piston
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(piston_duration=2.0)
    assert e.value.field == "piston_duration"
    # an integer beyond 64 bits
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.simulate(seed=2**70)
    assert e.value.field == "seed"


def test_the_scene_of_a_result_runs_in_the_driver(driver, tmp_path):
    """Result.scene is the driver's echo: the driver runs it to the same
    columns, bit for bit."""
    r = taper.simulate(profile="backward_linear", s=0.3, n_granules=41, damping=0.01,
                       every=3, columns="v_peak t_pass theory_v")
    assert r.columns == ("k", "t_pass", "v_peak", "theory_v")
    assert list(r.k) == list(range(1, 41, 3)) + [41]
    path = tmp_path / "again.nml"
    path.write_text(r.scene)
    proc = subprocess.run([str(driver), str(path), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    back = taper.read_granules(tmp_path / "out" / "granules.tsv")
    assert back.equals(r)


def test_untrusted_as_the_driver_says():
    r = taper.simulate(n_granules=200, rtol=0.1, atol=0.1, max_energy_error=1e-12)
    assert r.untrusted.startswith("energy error") and "max_energy_error" in r.untrusted
    assert taper.simulate(n_granules=20).untrusted == ""
