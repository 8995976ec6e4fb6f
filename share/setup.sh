#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# setup.sh -- make this checkout ready: install what is missing (Debian 12,
# as root or through sudo), build an optimised SUNDIALS from Debian's source
# package into BUILD_DIR/sundials, configure the Meson build in BUILD_DIR
# (default ./build) against it, compile.
# Idempotent: a second run rebuilds nothing that has not changed.
#
#   sh share/setup.sh            # from the top of the checkout
#   BUILD_DIR=build-asan MESON_ARGS='-Db_sanitize=address,undefined' sh share/setup.sh
#   MESON_ARGS=-Dsundials=system sh share/setup.sh    # Debian's SUNDIALS, no source build
#
# Where the source package cannot be had (no deb-src reachable, not Debian),
# the build uses the system SUNDIALS and says so in one line; to try again,
# remove BUILD_DIR/sundials.  docs/design.md, "SUNDIALS: bundled and optimised".
set -eu

cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}

# Build tools, the three libraries we link (SUNDIALS CVODE, GSL, cmocka for
# the tests), gfortran for the Fortran module, gnuplot for the figures,
# python3 with its headers and venv for the Python package and its tests; dpkg-dev and patch to unpack and
# patch SUNDIALS' source package (libsundials-dev stays: the fallback, and the
# -Dsundials=system build); Open MPI for sweeps on MPI ranks (-Dmpi,
# docs/cluster.md).
packages="meson ninja-build pkg-config gcc g++ gfortran cmake libsundials-dev libgsl-dev \
libcmocka-dev gnuplot-nox python3 python3-dev python3-venv dpkg-dev patch \
libopenmpi-dev openmpi-bin"

missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "setup: installing$missing" >&2
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends $missing >&2
fi

# SUNDIALS: the optimised build in $build_dir/sundials (share/sundials/build.sh,
# log in $build_dir/sundials.log; a no-op once built) unless MESON_ARGS chooses
# the system one or another prefix.  Where the source cannot be had, the system
# SUNDIALS, remembered in $build_dir/sundials/fallback so that later runs do not
# try the network again.
prefix=$build_dir/sundials
case $prefix in /*) ;; *) prefix=$(pwd)/$prefix ;; esac
sundials=""
case " ${MESON_ARGS:-} " in
    *" -Dsundials=system "*|*" -Dsundials_prefix="*) ;;
    *)
        mkdir -p "$build_dir"
        if [ -f "$prefix/fallback" ]; then
            reason=$(cat "$prefix/fallback")
        else
            [ -f "$prefix/.stamp" ] ||
                echo "setup: building SUNDIALS (CVODE, ARKODE; CMake Release) from the distribution's source package into $prefix" >&2
            if reason=$(sh share/sundials/build.sh "$prefix"); then
                sundials=bundled
            else
                rm -rf "$prefix" && mkdir -p "$prefix" && echo "$reason" > "$prefix/fallback"
            fi
        fi
        if [ "$sundials" != bundled ]; then
            sundials=system
            echo "setup: $reason: using the system SUNDIALS, built without optimisation, so runs take ~1.8x as long (1.8x the instructions on monodisperse N = 2000, docs/benchmarks.md); rm -r $build_dir/sundials to retry" >&2
        fi
        ;;
esac
# The caller's own -Dsundials=... wins.
case " ${MESON_ARGS:-} " in *" -Dsundials="*) sundials="" ;; esac

if [ ! -f "$build_dir/build.ninja" ]; then
    # shellcheck disable=SC2086
    meson setup "$build_dir" ${sundials:+-Dsundials=$sundials} ${MESON_ARGS:-} >&2
elif [ -n "$sundials" ]; then
    # An existing build dir: point it at the SUNDIALS chosen above if it is not.
    current=$(python3 -c 'import json, sys
print(next((o["value"] for o in json.load(open(sys.argv[1])) if o["name"] == "sundials"), ""))' \
        "$build_dir/meson-info/intro-buildoptions.json" 2>/dev/null || true)
    # (An empty answer: a build dir from before the option; its regeneration
    # picks the default, auto, which finds the same.)
    [ -z "$current" ] || [ "$current" = "$sundials" ] ||
        meson configure "$build_dir" -Dsundials="$sundials" >&2
fi
meson compile -C "$build_dir" >&2
