# SPDX-License-Identifier: GPL-3.0-or-later
"""pytest configuration of the `taper` package's tests.

Paths come from the environment (tests/bindings/python/run_pytest.py sets
them for `meson test`) or from options:

    TAPER_DRIVER   / --taper-driver   the driver binary (BUILD/drivers/taper/taper)
    TAPER_SOURCE   / --taper-source   the source tree (for share/scenes and the wheel test)

Tests that need one of them are skipped when it is not given.
"""

import os
import pathlib
import subprocess

import pytest

HERE = pathlib.Path(__file__).resolve().parent


def pytest_addoption(parser):
    parser.addoption("--taper-driver", default=os.environ.get("TAPER_DRIVER"),
                     help="the driver binary taper (default: $TAPER_DRIVER)")
    parser.addoption("--taper-source", default=os.environ.get("TAPER_SOURCE"),
                     help="the source tree (default: $TAPER_SOURCE, else this file's checkout)")


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "slow: the long tests (share/wheel.sh and its wheel in a fresh venv, the "
        "examples drawing their figures, chains in threads against serial runs, SIGINT in every "
        "phase of a call); meson test runs them in python_slow, suite 'slow'")


@pytest.fixture(scope="session")
def driver(pytestconfig):
    path = pytestconfig.getoption("--taper-driver")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("no driver binary: set TAPER_DRIVER or --taper-driver")
    return pathlib.Path(path)


@pytest.fixture(scope="session")
def source(pytestconfig):
    path = pytestconfig.getoption("--taper-source")
    path = pathlib.Path(path) if path else HERE.parents[2]
    if not (path / "meson.build").is_file():
        pytest.skip("no source tree: set TAPER_SOURCE or --taper-source")
    return path


@pytest.fixture
def run_driver(driver, tmp_path):
    """run_driver(scene_text) -> path of the granules.tsv the driver wrote."""
    def run(text, name="scene"):
        scene = tmp_path / f"{name}.nml"
        scene.write_text(text)
        out = tmp_path / f"out-{name}"
        proc = subprocess.run([str(driver), str(scene), "-o", str(out)],
                              capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr
        return out / "granules.tsv"
    return run
