# SPDX-License-Identifier: GPL-3.0-or-later
"""pip wheel . builds a wheel from the source tree with build isolation (its
build requirements from PyPI), and the wheel installs into a fresh venv and
works there, with no libtaper.so beside it, and with the optimised SUNDIALS
linked in (no libsundials loaded) or, where the build could not make it, the
system's and the one line saying so.  Slow: one full build."""

import json
import os
import pathlib
import re
import subprocess
import sys
import zipfile

import pytest


def run(cmd, **kw):
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    assert proc.returncode == 0, f"{cmd}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return proc.stdout


@pytest.mark.slow
def test_wheel_builds_installs_and_imports(source, tmp_path):
    version = re.search(r"version:\s*'([^']+)'", (source / "meson.build").read_text()).group(1)
    wheels = tmp_path / "wheels"
    # -v: the build's own output, where a SUNDIALS fallback line would be.
    built = run([sys.executable, "-m", "pip", "wheel", "-v", "--no-deps", "-w", wheels, source],
                timeout=1800)
    (wheel,) = wheels.glob("taper-*.whl")
    assert wheel.name.startswith(f"taper-{version}-")
    names = zipfile.ZipFile(wheel).namelist()
    assert any(re.match(r"taper/_core\..*so$", n) for n in names), names
    assert "taper/py.typed" in names and "taper/_core.pyi" in names
    for module in ("__init__", "result", "plotting", "asymptotic", "_fit", "_chain", "_variables"):
        assert f"taper/{module}.py" in names, (module, names)
    assert not [n for n in names if "libtaper" in n or n.endswith(".h")], names

    venv = tmp_path / "venv"
    run([sys.executable, "-m", "venv", venv])
    py = venv / "bin" / "python"
    run([py, "-m", "pip", "install", "-q", wheel], timeout=900)
    code = ("import taper, os; r = taper.simulate(profile='backward_linear', s=0.5, n_granules=20);"
            "assert r.complete, r; print(taper.__version__, taper.__file__)")
    out = run([py, "-c", code], cwd=tmp_path, env={**os.environ, "PYTHONPATH": ""})
    got, where = out.split()
    assert got == version
    assert pathlib.Path(where).is_relative_to(venv)
    ext = next(pathlib.Path(where).parent.glob("_core.*so"))
    needed = run(["readelf", "-d", ext])
    assert "libtaper" not in needed

    # Which SUNDIALS the running extension uses: the files mapped into the
    # process after a run, against what the build recorded and printed.
    code = ("import json, taper; r = taper.simulate(profile='monodisperse', n_granules=20);"
            "maps = open('/proc/self/maps').read().splitlines();"
            "print(json.dumps([taper.build_info(), r.stats['steps'],"
            " sorted({m.split()[-1] for m in maps if 'libsundials' in m})]))")
    info, steps, loaded = json.loads(run([py, "-c", code], cwd=tmp_path,
                                         env={**os.environ, "PYTHONPATH": ""}))
    assert steps > 0
    fallback = [line for line in built.splitlines() if "using the system SUNDIALS" in line]
    if info["sundials"] == "bundled":
        assert info["sundials_linked"] == "static" and info["sundials_optimised"], info
        assert loaded == [], loaded
        assert "sundials" not in needed, needed
        assert fallback == [] and info["sundials_fallback"] == "", (fallback, info)
    else:
        assert info["sundials"] == "system" and not info["sundials_optimised"], info
        assert len(fallback) == 1 and info["sundials_fallback"] in fallback[0], (fallback, info)
        assert any(p.rsplit("/", 1)[-1].startswith("libsundials_cvode.so") for p in loaded), loaded
