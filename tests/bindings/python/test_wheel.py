# SPDX-License-Identifier: GPL-3.0-or-later
"""share/wheel.sh on a clean copy of the checkout builds the self-contained
wheel the README promises (docs/python.md, "Installing"): a manylinux wheel
of the distribution taper-chains with the optimised SUNDIALS linked in, GSL
carried inside it, and the licences of all three; installed with pip into a
fresh venv it imports and runs with the system's GSL and SUNDIALS out of
reach: every library the extension loads is inside the wheel or on the
manylinux policy's list, and in a mount namespace where the system's
libgsl and libsundials files are replaced by empty ones it still runs.
Slow: one full build (SUNDIALS from Debian's source package, the build
requirements and auditwheel from PyPI)."""

import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import zipfile

import pytest

pytestmark = pytest.mark.slow


def run(cmd, **kw):
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    assert proc.returncode == 0, f"{cmd}\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return proc


@pytest.fixture(scope="module")
def built(source, tmp_path_factory):
    """(clone, wheel, auditwheel show's output): share/wheel.sh run on a
    copy of the files git knows in the checkout (a clean clone, with the
    changes not yet committed), for the Python running the tests."""
    clone = tmp_path_factory.mktemp("clone")
    files = run(["git", "-C", source, "ls-files", "-z", "--cached", "--others",
                 "--exclude-standard"]).stdout.split("\0")
    for name in filter(None, files):
        if (source / name).is_file():
            (clone / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source / name, clone / name)
    out = run(["sh", "share/wheel.sh"], cwd=clone, timeout=3600,
              env={**os.environ, "PYTHON": sys.executable})
    (wheel,) = (clone / "dist").glob("*.whl")
    assert out.stdout.strip() == str(wheel)
    return clone, wheel, out.stderr


def test_the_wheel_is_manylinux_and_carries_its_libraries_and_licences(built, source):
    clone, wheel, log = built
    version = re.search(r"version:\s*'([^']+)'", (source / "meson.build").read_text()).group(1)
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    m = re.fullmatch(rf"taper_chains-{re.escape(version)}-{tag}-{tag}-(manylinux_2_(\d+)_x86_64)"
                     r"\.whl", wheel.name)
    assert m, wheel.name
    # auditwheel show: consistent with that manylinux policy, nothing outside it
    assert f'is consistent with the following platform tag: "{m.group(1)}"' in \
        " ".join(log.split()), log
    assert "external" not in log.replace("external versioned symbols", ""), log
    names = zipfile.ZipFile(wheel).namelist()
    libs = sorted(n for n in names if n.startswith("taper_chains.libs/"))
    assert [re.sub(r"-[0-9a-f]{8}\.so.*", "", n.split("/")[-1]) for n in libs if
            not n.endswith("/")] == ["libgsl", "libgslcblas"], libs
    assert not [n for n in names if "sundials" in n.lower() and n.endswith((".so", ".a"))]
    assert not [n for n in names if "libtaper" in n or n.endswith(".h")], names
    for module in ("__init__.py", "__init__.pyi", "py.typed", "_core.pyi", "result.py",
                   "_signature.py", "_progress.py", "_geometry.py", "plotting.py"):
        assert f"taper/{module}" in names, module
    dist_info = f"taper_chains-{version}.dist-info"
    z = zipfile.ZipFile(wheel)
    licences = {n[len(dist_info) + len("/licenses/"):] for n in names
                if n.startswith(f"{dist_info}/licenses/") and not n.endswith("/")}
    assert licences == {"LICENSE", "share/sundials/LICENSE", "share/sundials/NOTICE",
                        "vendored/libgsl27.copyright", "vendored/libgslcblas0.copyright",
                        "vendored/SOURCES"}, licences
    assert z.read(f"{dist_info}/licenses/LICENSE") == (source / "LICENSE").read_bytes()
    assert b"BSD 3-Clause" in z.read(f"{dist_info}/licenses/share/sundials/LICENSE")
    assert z.read(f"{dist_info}/licenses/vendored/libgsl27.copyright") == \
        pathlib.Path("/usr/share/doc/libgsl27/copyright").read_bytes()
    sources = z.read(f"{dist_info}/licenses/vendored/SOURCES").decode()
    assert re.search(r"libgsl\.so\.27 .* source package gsl \S+", sources), sources
    metadata = z.read(f"{dist_info}/METADATA").decode()
    assert "Name: taper-chains\n" in metadata
    assert "License-Expression: GPL-3.0-or-later\n" in metadata
    for licence in licences:
        assert f"License-File: {licence}\n" in metadata, licence
    record = z.read(f"{dist_info}/RECORD").decode().splitlines()
    assert sorted(line.split(",")[0] for line in record) == \
        sorted(n for n in names if not n.endswith("/"))


@pytest.fixture(scope="module")
def installed(built, tmp_path_factory):
    """A fresh venv with the wheel pip-installed (numpy from PyPI)."""
    _, wheel, _ = built
    venv = tmp_path_factory.mktemp("venv")
    run([sys.executable, "-m", "venv", venv])
    py = venv / "bin" / "python"
    run([py, "-m", "pip", "install", "-q", wheel], timeout=900)
    return venv, py


CHECK = """
import json, taper
r = taper.simulate(profile="backward_linear", s=0.5, n_granules=20)
f = taper.fit(r.k, r.theory_v, index_window=(5, None))   # GSL's multifit
maps = open("/proc/self/maps").read().splitlines()
print(json.dumps([taper.__version__, taper.__file__, r.complete, f.params[1],
                  taper.build_info(),
                  sorted({m.split()[-1] for m in maps if "gsl" in m or "sundials" in m})]))
"""


def check_run(py, cwd, prefix=()):
    out = run([*prefix, py, "-c", CHECK], cwd=cwd, env={**os.environ, "PYTHONPATH": ""},
              timeout=300).stdout
    return json.loads(out.splitlines()[-1])


def test_every_library_the_extension_loads_is_in_the_wheel_or_the_policy(installed, built):
    """ldd of the installed extension and of the libraries beside it: each
    resolves inside the venv or is on the whitelist of the wheel's manylinux
    policy (auditwheel's own policy file); the running process maps GSL
    from the wheel and no SUNDIALS library at all (it is linked in)."""
    venv, py = installed
    clone, wheel, _ = built
    policy_name = re.search(r"(manylinux_2_\d+_x86_64)", wheel.name).group(1)
    policy_file = next((clone / "build" / "wheel" / "venv").glob(
        "lib/python*/site-packages/auditwheel/policy/manylinux-policy.json"))
    policy = next(p for p in json.loads(policy_file.read_text())
                  if p["name"] == policy_name.replace("_x86_64", ""))
    whitelist = set(policy["lib_whitelist"])
    site = next(venv.glob("lib/python*/site-packages"))
    objects = list((site / "taper").glob("_core*.so")) + list((site / "taper_chains.libs").glob("*"))
    assert len(objects) == 3, objects
    for obj in objects:
        for line in run(["ldd", obj]).stdout.splitlines():
            m = re.match(r"\s*(\S+) => (\S+)", line)
            if not m:
                continue
            soname, path = m.groups()
            assert path != "not", (obj, line)
            inside = pathlib.Path(path).resolve().is_relative_to(venv)
            assert inside or soname in whitelist, (obj.name, soname, path)
            assert inside == soname.startswith("libgsl"), (obj.name, soname, path)
        needed = run(["readelf", "-d", obj]).stdout
        assert "sundials" not in needed and "libtaper" not in needed, needed
    version, where, complete, slope, info, mapped = check_run(py, venv.parent)
    assert pathlib.Path(where).is_relative_to(venv) and complete
    assert abs(slope + 1.5) < 0.1, slope      # v_k ~ k^-3/2 of the theory, eq. (22)
    assert info["sundials"] == "bundled" and info["sundials_linked"] == "static"
    assert info["sundials_optimised"] and info["sundials_fallback"] == ""
    assert mapped and all(pathlib.Path(p).is_relative_to(venv) for p in mapped), mapped


def test_it_runs_with_the_systems_gsl_and_sundials_hidden(installed):
    """In a mount namespace (unshare -m, as root) every libgsl* and
    libsundials* file of the system's library directories is replaced by an
    empty one (a bind mount of /dev/null): a loader that reached for them
    would fail ("file too short"); the wheel's Python runs as before."""
    venv, py = installed
    if os.geteuid() != 0 or not shutil.which("unshare"):
        pytest.skip("needs root and unshare(1) for a mount namespace")
    hidden = sorted({str(p.resolve()) for d in ("/usr/lib/x86_64-linux-gnu", "/lib/x86_64-linux-gnu",
                                               "/usr/local/lib")
                     if os.path.isdir(d) for p in pathlib.Path(d).iterdir()
                     if p.name.startswith(("libgsl", "libsundials")) and p.exists()})
    assert any("libgsl.so" in h for h in hidden), hidden
    script = "set -e; " + " ".join(f"mount --bind /dev/null {h};" for h in hidden) + \
        ' exec "$@"'
    probe = subprocess.run(["unshare", "-m", "sh", "-c", script, "sh", "true"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"no mount namespace here: {probe.stderr.strip()}")
    # the system's GSL is out of reach in there: a program that links it fails
    broken = subprocess.run(["unshare", "-m", "sh", "-c", script, "sh", sys.executable, "-c",
                             "import ctypes; ctypes.CDLL('libgsl.so.27')"],
                            capture_output=True, text=True)
    assert broken.returncode != 0 and "libgsl.so.27" in broken.stderr, broken.stderr
    version, where, complete, slope, info, mapped = check_run(
        py, venv.parent, prefix=("unshare", "-m", "sh", "-c", script, "sh"))
    assert complete and abs(slope + 1.5) < 0.1
    assert mapped and all(pathlib.Path(p).is_relative_to(venv) for p in mapped), mapped
