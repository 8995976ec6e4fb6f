# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python examples of share/examples/python, run as a user runs them:
each script with this interpreter (the package installed), in a fresh
folder.  Each checks its own physics and exits non-zero when a check fails;
each must also run without matplotlib, skipping only its figure.  The runs
with matplotlib (figures drawn) are marked slow: the runs without it check
the same physics in a third of the time."""

import subprocess
import sys

import pytest

EXAMPLES = ["paper_figure1.py", "loaded_chain.py", "calibrate_and_design.py"]

# Runs a script with matplotlib made unimportable (sys.modules entry None).
WITHOUT_MATPLOTLIB = ("import runpy, sys; sys.modules['matplotlib'] = None; "
                      "sys.argv = sys.argv[1:]; runpy.run_path(sys.argv[0], run_name='__main__')")


def run(args, cwd):
    return subprocess.run([sys.executable, *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600)


@pytest.mark.slow
@pytest.mark.parametrize("name", EXAMPLES)
def test_example_runs_and_its_checks_hold(name, source, tmp_path):
    script = (source / "share" / "examples" / "python" / name).resolve()
    figure = tmp_path / "figure.png"
    proc = run([str(script), str(figure)], tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "all hold" in proc.stdout, proc.stdout
    pytest.importorskip("matplotlib")
    assert figure.stat().st_size > 0


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_runs_without_matplotlib(name, source, tmp_path):
    script = (source / "share" / "examples" / "python" / name).resolve()
    figure = tmp_path / "figure.png"
    proc = run(["-c", WITHOUT_MATPLOTLIB, str(script), str(figure)], tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "matplotlib is not installed: no figure" in proc.stdout, proc.stdout
    assert "all hold" in proc.stdout, proc.stdout
    assert not figure.exists()
