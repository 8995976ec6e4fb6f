#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""run_pytest.py BUILD_DIR SOURCE_DIR DRIVER [pytest args...] -- the pytest
suite of the Python package `taper`, as `meson test` runs it.

1. A venv at BUILD_DIR/python-venv, made once (idempotent), with the build
   requirements of pyproject.toml and pytest, from PyPI.
2. `pip install SOURCE_DIR` into it: the package built by meson-python from
   the project's own meson.build.  Without build isolation and with the build
   directory kept at BUILD_DIR/python-build, so that a second run only
   recompiles what changed.
3. pytest on tests/bindings/python, with the driver binary and the source
   tree passed in TAPER_DRIVER and TAPER_SOURCE.  The wheel test (slow) runs
   share/wheel.sh on a clean copy of the checkout, with its own build venv.

Needs the Python headers and venv module of the Python running this script
(Debian: python3-dev, python3-venv).
"""

import os
import subprocess
import sys
import venv

# What the package's build needs (pyproject.toml [build-system] requires),
# what its tests need, and the optional extras the tests exercise.
REQUIREMENTS = ["meson-python>=0.18", "meson>=1.0.1", "ninja", "numpy>=2.0", "pytest",
                "pandas", "matplotlib", "tqdm"]


def run(cmd, **kw):
    print("+", " ".join(cmd), flush=True)
    return subprocess.run(cmd, **kw).returncode


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    build, source, driver = (os.path.abspath(a) for a in sys.argv[1:4])
    env_dir = os.path.join(build, "python-venv")
    py = os.path.join(env_dir, "bin", "python")
    if not os.path.exists(py):
        try:
            venv.EnvBuilder(with_pip=True, clear=True).create(env_dir)
        except Exception as e:  # ensurepip missing: Debian's python3-venv
            sys.exit(f"run_pytest: cannot create {env_dir} ({e}); on Debian: apt-get install "
                     "python3-venv python3-dev")
    stamp = os.path.join(env_dir, "taper-requirements.txt")
    wanted = "\n".join(REQUIREMENTS) + "\n"
    if not os.path.exists(stamp) or open(stamp).read() != wanted:
        if run([py, "-m", "pip", "install", "-q", *REQUIREMENTS]) != 0:
            sys.exit("run_pytest: installing the requirements from PyPI failed")
        with open(stamp, "w") as f:
            f.write(wanted)
    build_dir = os.path.join(build, "python-build")
    if run([py, "-m", "pip", "install", "-q", "--no-deps", "--no-build-isolation",
            "--force-reinstall", f"--config-settings=build-dir={build_dir}", source]) != 0:
        sys.exit("run_pytest: pip install of the package failed")
    env = dict(os.environ, TAPER_DRIVER=driver, TAPER_SOURCE=source,
               PYTHONDONTWRITEBYTECODE="1")
    env.pop("PYTHONPATH", None)
    tests = os.path.join(source, "tests", "bindings", "python")
    # From the build directory, so that no checkout folder shadows the
    # installed package.
    sys.exit(run([py, "-m", "pytest", "-p", "no:cacheprovider", "-ra", tests, *sys.argv[4:]],
                 cwd=build, env=env))


if __name__ == "__main__":
    main()
