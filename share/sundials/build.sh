#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# share/sundials/build.sh PREFIX [shared|static] -- build the SUNDIALS that
# taper links, optimised, from the distribution's own source package, and
# install it in PREFIX.
#   shared  (the default) shared libraries: share/setup.sh, PREFIX =
#           <build dir>/sundials, linked by libtaper.so and the programs
#   static  static libraries of position-independent code: meson.build's
#           -Dsundials=build (pip install .), PREFIX = <build dir>/sundials-static,
#           linked into the Python extension (and libtaper.so), so that a
#           wheel carries its SUNDIALS and needs no build directory
# See docs/design.md, "SUNDIALS: bundled and optimised".
#
#   1. Nothing to do if PREFIX/.stamp matches this script, the patches, the
#      source version and the kind (a second run costs a few milliseconds).
#   2. A deb-src entry for every deb entry of the system's own apt sources
#      (read at run time from the files apt reads: no host name is written in
#      this repository), in a private sources dir and lists dir under
#      PREFIX.work: the system's apt configuration is left as it was.
#   3. apt-get source sundials=VERSION, VERSION being the source version of the
#      installed libsundials-dev (6.4.1+dfsg1-3 on Debian 12), so that the
#      bundled build and the system one differ only in flags and our patches.
#   4. Below 6.5.0: share/sundials/rootfind-underflow.patch (the upstream
#      6.5.0 root-finding underflow fix, backported); then, where it applies,
#      share/sundials/fused-predictor.patch (CVODE's predictor without a
#      vector call per addition, each element's column in registers: bit
#      for bit the same results, 1.12x and then a further 1.12x on taper's
#      short window vectors; docs/benchmarks.md) and
#      share/sundials/adams-bookkeeping.patch (cvSetAdams' coefficients kept
#      while their inputs are unchanged, CVodeGetDky's powers of s by one
#      multiplication each: bit for bit the same results).
#   5. CMake Release (-O3 -DNDEBUG), libraries of the one kind asked for (both
#      would compile every file twice), CVODE and ARKODE and no other package,
#      no examples; installed in PREFIX, work dir removed.
#
# Exit 0: PREFIX holds the build.  Exit 1: it could not be made; stdout then
# holds one short reason (for the fallback line of setup.sh and of
# meson.build's -Dsundials=build), the details are in PREFIX.log.
# Environment: TAPER_SUNDIALS_JOBS (default: nproc).
set -u

prefix=$1
kind=${2:-shared}
here=$(cd "$(dirname "$0")" && pwd)
patch_file=$here/rootfind-underflow.patch
predictor_patch=$here/fused-predictor.patch
bookkeeping_patch=$here/adams-bookkeeping.patch
work=$prefix.work
jobs=${TAPER_SUNDIALS_JOBS:-$(nproc 2>/dev/null || echo 2)}

fail() {
    echo "$1"
    exit 1
}

case $kind in
    shared) shared=ON static=OFF suffix=so ;;
    static) shared=OFF static=ON suffix=a ;;
    *) fail "share/sundials/build.sh: unknown kind '$kind' (shared or static)" ;;
esac

if ! command -v apt-get >/dev/null 2>&1 || ! command -v dpkg-query >/dev/null 2>&1; then
    fail "not a Debian system"
fi

# The version to build: the source version of the installed development package.
version=$(dpkg-query -W -f='${source:Version}' libsundials-dev 2>/dev/null) || version=""
[ -n "$version" ] || fail "libsundials-dev is not installed"
upstream=${version#*:}
upstream=${upstream%%-*}
upstream=${upstream%%+*}

# What the build depends on, in one line: a change to any of them rebuilds.
stamp="sundials $version; $(cat "$0" "$patch_file" "$predictor_patch" "$bookkeeping_patch" | sha256sum | cut -c1-16); $kind"
if [ -f "$prefix/.stamp" ] && [ "$(cat "$prefix/.stamp")" = "$stamp" ] &&
   [ -e "$prefix/lib/libsundials_cvode.$suffix" ]; then
    exit 0
fi

# From here on, the details go to PREFIX.log.
mkdir -p "$(dirname "$prefix")" || fail "cannot create the directory of $prefix"
exec 2>"$prefix.log"
rm -rf "$work" "$prefix"
mkdir -p "$work/sources.list.d" "$work/lists/partial" "$work/src" "$work/build" || fail "cannot write $work"

# 2. deb-src entries from the system's sources.  apt-config names the files apt
#    reads (so APT_CONFIG is honoured); only the distribution's own suites (its
#    codename, codename-updates, ...) are kept, not third-party repositories.
eval "$(apt-config shell sourcelist Dir::Etc::sourcelist/f sourceparts Dir::Etc::sourceparts/d)"
# shellcheck disable=SC1091
codename=$( . /etc/os-release 2>/dev/null; echo "${VERSION_CODENAME:-}")
python3 - "${sourcelist:-}" "${sourceparts:-}" "$codename" > "$work/sources.list.d/taper-deb-src.sources" <<'PY' ||
import glob, os, re, sys

sourcelist, sourceparts, codename = sys.argv[1:4]
families = {codename, "stable", "oldstable", "testing", "unstable", "sid"} - {""}

def own_suites(suites):
    return [s for s in suites if re.split(r"[-/]", s)[0] in families]

entries = []  # (uris, suites, components, extra deb822 lines)

def one_line(path):
    for line in open(path, errors="replace"):
        line = line.split("#", 1)[0].strip()
        m = re.match(r"(deb|deb-src)\s+(\[[^\]]*\]\s+)?(\S+)\s+(\S+)\s*(.*)$", line)
        if not m:
            continue
        extra = []
        for opt in (m.group(2) or "").strip()[1:-1].split():
            key, _, value = opt.partition("=")
            if key == "signed-by":
                extra.append("Signed-By: " + value)
            elif key == "trusted":
                extra.append("Trusted: " + value)
        entries.append(([m.group(3)], [m.group(4)], m.group(5).split(), extra))

def deb822(path):
    text = open(path, errors="replace").read()
    for para in re.split(r"\n\s*\n", text):
        fields, extra, last = {}, {}, None
        for line in para.splitlines():
            if line.startswith("#"):
                continue
            if line[:1] in (" ", "\t") and last:
                extra[last].append(line)
                continue
            key, sep, value = line.partition(":")
            if not sep:
                continue
            last = key.strip().lower()
            fields[last] = value.strip()
            extra[last] = [key.strip() + ": " + value.strip()]
        types = fields.get("types", "").split()
        if not types or fields.get("enabled", "yes").lower() == "no":
            continue
        if "deb" not in types and "deb-src" not in types:
            continue
        keep = [l for k in ("signed-by", "trusted") if k in extra for l in extra[k]]
        entries.append((fields.get("uris", "").split(), fields.get("suites", "").split(),
                        fields.get("components", "").split(), keep))

if sourcelist and os.path.isfile(sourcelist):
    one_line(sourcelist)
if sourceparts and os.path.isdir(sourceparts):
    for path in sorted(glob.glob(os.path.join(sourceparts, "*"))):
        if path.endswith(".list"):
            one_line(path)
        elif path.endswith(".sources"):
            deb822(path)

seen, out = set(), []
for uris, suites, components, extra in entries:
    suites = own_suites(suites)
    if not uris or not suites:
        continue
    key = (tuple(uris), tuple(suites), tuple(components))
    if key in seen:
        continue
    seen.add(key)
    out.append("\n".join(["Types: deb-src", "URIs: " + " ".join(uris),
                          "Suites: " + " ".join(suites),
                          "Components: " + " ".join(components)] + extra))
if not out:
    sys.exit(1)
print("\n\n".join(out))
PY
    fail "no apt source of the distribution to derive a deb-src entry from"

apt_opts="-o Dir::Etc::SourceList=/dev/null -o Dir::Etc::SourceParts=$work/sources.list.d \
-o Dir::State::Lists=$work/lists -o Dir::Cache::pkgcache= -o Dir::Cache::srcpkgcache= \
-o APT::Sandbox::User=root -o Acquire::Retries=1 -o Acquire::http::Timeout=20 -o Debug::NoLocking=1"

echo "sundials: deb-src entries:" >&2
cat "$work/sources.list.d/taper-deb-src.sources" >&2
# shellcheck disable=SC2086
apt-get $apt_opts -q update >&2 || echo "sundials: apt-get update reported errors (ignored if the source is found)" >&2
# shellcheck disable=SC2086
apt-cache $apt_opts showsrc sundials 2>/dev/null | grep -qx "Version: $version" ||
    fail "no deb-src reachable for sundials $version"

# 3. The source package, unpacked with Debian's own patches applied.
# shellcheck disable=SC2086
(cd "$work/src" && apt-get $apt_opts -q source "sundials=$version") >&2 ||
    fail "apt-get source sundials=$version failed"
srcdir=$(find "$work/src" -mindepth 1 -maxdepth 1 -type d -name 'sundials-*' | head -n 1)
[ -n "$srcdir" ] || fail "apt-get source gave no source tree"

# 4. The root-finding underflow fix, where the version predates it.
if dpkg --compare-versions "$upstream" lt 6.5.0; then
    patch -d "$srcdir" -p1 -N < "$patch_file" >&2 || fail "rootfind-underflow.patch does not apply to $version"
fi
# Speed patches only: where one does not apply (another version), go on
# without it.  (adams-bookkeeping.patch is made on top of the predictor's.)
for speed_patch in "$predictor_patch" "$bookkeeping_patch"; do
    if patch -d "$srcdir" -p1 -N --dry-run < "$speed_patch" >/dev/null 2>&1; then
        patch -d "$srcdir" -p1 -N < "$speed_patch" >&2 || fail "$(basename "$speed_patch") failed on $version"
    else
        echo "sundials: $(basename "$speed_patch") does not apply to $version: built without it (slower, same results)" >&2
    fi
done

# 5. Release build of the modules taper uses (meson.build, sundials_components;
#    ARKODE for taper-bench's ERK peer).
generator=""
command -v ninja >/dev/null 2>&1 && generator="-G Ninja"
# shellcheck disable=SC2086
cmake -S "$srcdir" -B "$work/build" $generator \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_INSTALL_LIBDIR=lib \
    -DBUILD_SHARED_LIBS=$shared -DBUILD_STATIC_LIBS=$static -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
    -DBUILD_CVODE=ON -DBUILD_ARKODE=ON -DBUILD_CVODES=OFF -DBUILD_IDA=OFF -DBUILD_IDAS=OFF \
    -DBUILD_KINSOL=OFF -DBUILD_NVECTOR_MANYVECTOR=OFF -DBUILD_FORTRAN_MODULE_INTERFACE=OFF \
    -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF \
    -DSUNDIALS_INDEX_SIZE=64 -DSUNDIALS_PRECISION=double >&2 ||
    fail "cmake could not configure sundials $version"
if ! cmake --build "$work/build" --parallel "$jobs" >&2 || ! cmake --install "$work/build" >&2; then
    rm -rf "$prefix"
    fail "sundials $version did not compile"
fi

echo "$stamp" > "$prefix/.stamp"
rm -rf "$work"
exit 0
