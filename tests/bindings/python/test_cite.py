# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.cite(): the BibTeX of `taper --cite` for the same settings, the
works by what the run uses, and the refusals of simulate()."""

import inspect
import subprocess
import sys

import pytest

import taper

CASES = [({}, []),
         ({"method": "rk8"}, ["solver.method='rk8'"]),
         ({"damping": 0.1}, ["losses.damping=0.1"]),
         ({"load": 1.0}, ["chain.load=1"]),
         ({"numerics": False}, ["solver.numerics=.false."])]


@pytest.mark.parametrize("keywords,overrides", CASES)
def test_cite_is_the_drivers(driver, keywords, overrides):
    text = subprocess.run([str(driver), *overrides, "--cite"], capture_output=True, text=True,
                          check=True).stdout
    assert taper.cite(**keywords) == text


def test_cite_names_what_the_run_uses():
    default = taper.cite()
    assert "harbola2009tapered" in default and "0905.4512" in default
    assert "031303" in default and "hindmarsh2005sundials" in default
    rk8 = taper.cite(method="rk8")
    assert "sundials" not in rk8 and "prince1981high" in rk8 and "galassi2009gsl" in rk8
    assert "kuwabara1987restitution" in taper.cite(damping=0.1)


def test_cite_with_keywords_as_a_process_first_call():
    """cite(method=...) before any other call: its keywords are read with
    numpy's C API, which the first call of a process imports (it crashed)."""
    code = "import taper; print('sundials' in taper.cite(method='rk8'), len(taper.cite()) > 0)"
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout == "False True\n", (p.returncode, p.stderr)


def test_cite_signature_and_refusals():
    assert set(inspect.signature(taper.cite).parameters) == \
        set(inspect.signature(taper.simulate).parameters)
    with pytest.raises(taper.InvalidArgumentError):
        taper.cite(n_granules=1)
    with pytest.raises(TypeError):
        taper.cite(dir="out")


def test_cite_with_keywords_first_in_a_fresh_interpreter():
    # The keywords' values may be numpy numbers: cite() imports numpy's C
    # API as every scene call does, also when it is the first call.
    code = "import sys, taper; sys.stdout.write(taper.cite(n_granules=31, damping=0.1))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == taper.cite(n_granules=31, damping=0.1)
