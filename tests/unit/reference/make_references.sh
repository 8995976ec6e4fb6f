#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# tests/unit/reference/make_references.sh BUILD_DIR -- the converged pass
# times that test_accuracy compares taper with, written next to this script.
#
# For each chain, drivers/bench/taper-reference (extrapolated modified
# midpoint steps in long double, events and contact kinks located on the
# step, compensated time: independent of CVODE) runs at TOL 1e-16 and
# 1e-17; the 1e-17 run is kept, and the script fails unless the two agree
# to 2e-14 relative over granules 1..N-2 (the largest difference is written
# into the file's header).  About two minutes on one core, most of it the
# monodisperse chain.  Run it again when the chains or the equations
# change: `sh tests/unit/reference/make_references.sh build`.
set -eu
build=$1
here=$(cd "$(dirname "$0")" && pwd)
ref=$build/drivers/bench/taper-reference
[ -x "$ref" ] || { echo "make_references.sh: $ref not built (meson compile -C $build)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# name profile N s q
while read -r name profile n s q; do
    "$ref" "$profile" "$n" "$s" "$q" 1e-16 > "$tmp/coarse"
    "$ref" "$profile" "$n" "$s" "$q" 1e-17 > "$tmp/fine"
    agree=$(paste "$tmp/coarse" "$tmp/fine" | awk -v n="$n" '
        $1 <= n - 2 { d = ($2 - $4) / $4; if (d < 0) d = -d; if (d > m) m = d }
        END { printf "%.1e", m }')
    awk -v a="$agree" 'BEGIN { if (a + 0 > 2e-14) exit 1 }' ||
        { echo "make_references.sh: $name: TOL 1e-16 and 1e-17 differ by $agree" >&2; exit 1; }
    {
        echo "# taper-reference $profile $n $s $q 1e-17: k t_pass"
        echo "# agrees with TOL 1e-16 to $agree (relative, granules 1..N-2)"
        cat "$tmp/fine"
    } > "$here/$name.txt"
    echo "$name: agreement $agree"
done <<'CHAINS'
monodisperse_1000 monodisperse 1000 0 0
backward_linear_400 backward_linear 400 0.5 0
backward_exponential_200 backward_exponential 200 0 0.05
forward_linear_100 forward_linear 100 0.009 0
forward_exponential_100 forward_exponential 100 0 0.05
forward_exponential_80 forward_exponential 80 0 0.045
CHAINS
