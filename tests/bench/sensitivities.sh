#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensitivities.sh TAPER TAPER_SENSITIVITIES SOURCE -- the sensitivity study's
# physics (tests/bench/meson.build): its right-hand side against the taper
# driver's run of share/scenes/optimise/calibrate_sensor.nml at the truth
# of its data (bead 4's force within 1e-8 of the peak at rtol 1e-12), and
# its forward-difference and sensitivity Jacobians against each other
# (taper-sensitivities --check; the command of docs/calibration.md).
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SENSITIVITIES=$(absolute "$2")
SRC=$(absolute "$3")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_sensitivities.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
"$TAPER" "$SRC/share/scenes/optimise/calibrate_sensor.nml" -o "$WORK/truth" \
    calibrate.data="''" material.young=193e9 losses.damping=1e-7 solver.rtol=1e-12 \
    solver.t_end=1.2e-4 sensors.interval=1e-6 sensors.granules=4 > "$WORK/taper.log" 2>&1 || {
    echo "FAIL: the taper driver's run (exit $?):" >&2
    cat "$WORK/taper.log" >&2
    exit 1
}
"$SENSITIVITIES" --check --check-taper "$WORK/truth/sensors.tsv"
