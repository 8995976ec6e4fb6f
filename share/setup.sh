#!/bin/sh
# setup.sh -- make this checkout ready: install what is missing (Debian 12,
# as root or through sudo), configure the Meson build in ./build, compile.
# Idempotent: a second run only recompiles what changed.
#
#   sh share/setup.sh            # from the top of the checkout
#   BUILD_DIR=build-asan MESON_ARGS='-Db_sanitize=address,undefined' sh share/setup.sh
set -eu

cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}

# Build tools, the three libraries we link (SUNDIALS CVODE, GSL, cmocka for
# the tests), gfortran for the Fortran module, gnuplot for the figures,
# python3 for the ctypes binding's test.
packages="meson ninja-build pkg-config gcc g++ gfortran cmake libsundials-dev libgsl-dev \
libcmocka-dev gnuplot-nox python3"

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

if [ ! -f "$build_dir/build.ninja" ]; then
    # shellcheck disable=SC2086
    meson setup "$build_dir" ${MESON_ARGS:-} >&2
fi
meson compile -C "$build_dir" >&2
