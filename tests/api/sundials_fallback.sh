#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sundials_fallback.sh SOURCE_DIR -- `meson setup -Dsundials=build` (what
# pip install . asks for) where the optimised SUNDIALS cannot be made: the
# configuration still succeeds, on the system SUNDIALS, and says so in
# exactly one warning line, worded as share/setup.sh's fallback line; the
# decision is kept in PREFIX/fallback, so that a second configuration prints
# the line again without running share/sundials/build.sh.
#
# The source is made unreachable without touching the network or the system:
# APT_CONFIG names an apt configuration with no sources at all, so
# build.sh stops at "no apt source of the distribution to derive a deb-src
# entry from" (docs/design.md, "SUNDIALS: bundled and optimised").
set -eu
src=$(cd "$1" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/apt/parts"
cat >"$tmp/apt/apt.conf" <<EOF
Dir::Etc::sourcelist "/dev/null";
Dir::Etc::sourceparts "$tmp/apt/parts";
EOF
fail=0

configure() { # LOG [--reconfigure]
    log=$1
    shift
    APT_CONFIG=$tmp/apt/apt.conf meson setup "$tmp/build" "$src" "$@" -Dsundials=build \
        -Dtests=false -Dpython=disabled -Dfortran=disabled -Dmpi=disabled >"$log" 2>&1 || {
        tail -n 30 "$log" >&2
        echo "FAIL: meson setup -Dsundials=build did not configure on the system SUNDIALS" >&2
        exit 1
    }
}

# The words after the reason, as setup.sh prints them (up to the retry hint).
setup_words=$(sed -n 's/.*echo "setup: \$reason: \(using the system SUNDIALS[^;]*\);.*/\1/p' \
    "$src/share/setup.sh")
[ -n "$setup_words" ] || { echo "FAIL: no fallback line found in share/setup.sh" >&2; exit 1; }

check_line() { # LOG WHICH
    lines=$(grep -c "using the system SUNDIALS" "$1" || :)
    if [ "$lines" != 1 ]; then
        echo "FAIL: $2 configuration printed $lines fallback lines, not 1:" >&2
        grep "using the system SUNDIALS" "$1" >&2 || :
        fail=1
        return
    fi
    line=$(grep "using the system SUNDIALS" "$1")
    echo "$2: $line"
    expected="no apt source of the distribution to derive a deb-src entry from: $setup_words; rm -r $tmp/build/sundials-static to retry"
    case $line in
        *"WARNING: $expected") ;;
        *) echo "FAIL: the line is not a warning worded as setup.sh's:" >&2
           echo "  expected ...WARNING: $expected" >&2; fail=1 ;;
    esac
    grep -q "^Message: SUNDIALS [0-9.]*: system" "$1" ||
        { echo "FAIL: $2 configuration did not take the system SUNDIALS" >&2; fail=1; }
}

configure "$tmp/first.log"
check_line "$tmp/first.log" first
grep -q "share/sundials/build.sh" "$tmp/first.log" ||
    { echo "FAIL: the first configuration did not run share/sundials/build.sh" >&2; fail=1; }
[ "$(cat "$tmp/build/sundials-static/fallback" 2>/dev/null)" = \
  "no apt source of the distribution to derive a deb-src entry from" ] ||
    { echo "FAIL: the reason is not kept in PREFIX/fallback" >&2; fail=1; }

configure "$tmp/second.log" --reconfigure
check_line "$tmp/second.log" second
if grep -q "share/sundials/build.sh" "$tmp/second.log"; then
    echo "FAIL: the second configuration ran share/sundials/build.sh again" >&2; fail=1
fi
exit $fail
