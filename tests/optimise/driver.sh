#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# driver.sh TAPER SECTION SOURCE -- calibration and design through the driver,
# one section per test (tests/optimise/meson.build):
#   errors   bad &calibrate / &design keys at FILE:LINE: &group key, bad
#            data at FILE:LINE:COLUMN (wrong units, unknown column, nan, a
#            time beyond the run, a granule beyond the chain): exit 2 and no
#            result files
#   status   a converged calibration (exit 0) and its files; a fitted
#            setting at its bound and an undetermined one (exit 6, the files
#            saying NOT CONVERGED); a design's files and its optimum's scene,
#            which run alone gives the optimum's objective to the last bit;
#            hold = 'length' and 'mass' kept by the optimum's chain
#   resume   a design stopped by SIGTERM (exit 3, its runs in
#            evaluations.tsv) and run again: it reuses them and ends where
#            an uninterrupted one does, to the last bit
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SECTION=$2
SRC=$(absolute "$3") # the source tree: share/scenes
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_optimise.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

# The chain every scene here describes: a striker, 8 stainless steel beads,
# a wall, Kuwabara-Kono contacts.
chain() {
    cat <<EOF
&chain n_granules = 8 /
&ends right = 'wall' /
&striker radius = 2.38e-3 /
&losses damping = 1e-7 /
&solver t_end = 1.2e-4 /
&material young = $1, poisson = 0.3, density = 8000, radius = 2.38e-3, velocity = 0.5 /
EOF
}

# The data: the sensor in bead 4 of the true chain, every microsecond.
{ chain 193e9; printf "&sensors interval = 1e-6, granules = 4 /\n"; } > truth.nml
"$TAPER" truth.nml -o truth > /dev/null 2>&1 || { echo "FAIL: the truth run" >&2; exit 1; }
cut -f1,2,7 truth/sensors.tsv > data.tsv # t[s] granule force[N]

# expect_error NAME STATUS PATTERN: the scene NAME.nml exits STATUS and
# stderr matches PATTERN (grep -E); no calibration.tsv is written.
expect_error() {
    "$TAPER" "$1.nml" -o "out_$1" > "$1.out" 2> "$1.err"
    status=$?
    [ "$status" -eq "$2" ] || fail "$1: exit status $status, wanted $2 ($(cat "$1.err"))"
    grep -Eq "$3" "$1.err" || fail "$1: stderr lacks /$3/: $(cat "$1.err")"
    [ -e "out_$1/calibration.tsv" ] && fail "$1: wrote calibration.tsv"
    [ -e "out_$1/design.tsv" ] && fail "$1: wrote design.tsv"
}

# calibrate NAME DATA KEYS: a calibration scene of the chain.
calibrate() {
    { chain 150e9; printf "&calibrate data = '%s'%s /\n" "$2" "$3"; } > "$1.nml"
}

errors() {
    calibrate free_typo data.tsv ", free = 'yung damping'"
    expect_error free_typo 2 "^free_typo.nml:7: &calibrate free: 'yung' is not a variable of the scene: did you mean young\?"
    calibrate free_choice data.tsv ", free = 'profile'"
    expect_error free_choice 2 "&calibrate free: 'profile' is a choice or string"
    calibrate start_length data.tsv ", free = 'young damping', start = 1e11"
    expect_error start_length 2 "^start_length.nml:7: &calibrate start: 1 values for 2 free settings"
    calibrate no_free data.tsv ""
    expect_error no_free 2 "&calibrate free: no free setting"
    calibrate missing missing.tsv ", free = 'young'"
    expect_error missing 2 "&calibrate data: missing.tsv: cannot open"
    # the data's own errors: FILE:LINE:COLUMN
    sed '1s/t\[s\]/t[ms]/' data.tsv > units.tsv
    calibrate units units.tsv ", free = 'young'"
    expect_error units 2 "^units.nml:7: &calibrate data: units.tsv:1:1: t\[ms\]: taper reads t in s"
    sed '1s/force\[N\]/forse[N]/' data.tsv > column.tsv
    calibrate column column.tsv ", free = 'young'"
    expect_error column 2 "column.tsv:1:[0-9]+: unknown column 'forse'"
    awk -F'\t' 'NR == 40 { $3 = "nan" } 1' OFS='\t' data.tsv > nan.tsv
    calibrate nan nan.tsv ", free = 'young'"
    expect_error nan 2 "nan.tsv:40:[0-9]+: force\[N\]: 'nan' is not a measurement"
    { cat data.tsv; printf "2e-4\t4\t1\n"; } > late.tsv
    calibrate late late.tsv ", free = 'young'"
    expect_error late 2 "late.tsv:[0-9]+:1: time 0.0002 s is beyond the run: it ends at &solver t_end"
    { cat data.tsv; printf "1e-5\t9\t1\n"; } > granule.tsv
    calibrate granule granule.tsv ", free = 'young'"
    expect_error granule 2 "granule.tsv:[0-9]+:[0-9]+: granule 9 is beyond the chain \(n_granules = 8\)"
    calibrate columns data.tsv ", free = 'young', columns = 'v'"
    expect_error columns 2 "&calibrate columns: columns: 'v' is not a measured column"
    # the design's keys
    { chain 193e9; printf "&design objective = 'wall_peak_force', free = 's', lower = 0, upper = 1 /\n"; } > objective.nml
    expect_error objective 2 "&design objective: 'wall_peak_force' is not a result of the run.*wall_peak_force_right"
    { chain 193e9; printf "&design objective = 'wall_peak_force_right', free = 'damping' /\n"; } > bounds.nml
    expect_error bounds 2 "&design (lower|upper): damping: a design needs finite bounds"
    chain 193e9 | sed "1s/.*/\&chain n_granules = 8, profile = 'backward_linear', s = 0.01 \//" > profile.nml
    printf "&design objective = 'wall_peak_force_right', free = 'log_radii(1)', lower = -1, upper = 1, log_radii = 0 /\n" >> profile.nml
    expect_error profile 2 "&design log_radii: log_radii make the chain's radii"
    { chain 193e9; printf "&calibrate data = 'data.tsv', free = 'young' /\n&design objective = 'wall_peak_force_right', free = 'damping', lower = 0, upper = 1e-6 /\n"; } > both.nml
    expect_error both 2 "&design objective: a scene is a calibration .* or a design .*, not both"
}

status() {
    calibrate good data.tsv ", free = 'young damping', start = 150e9, 2e-7"
    "$TAPER" good.nml -o good > good.out 2> good.err
    s=$?
    [ "$s" -eq 0 ] || fail "good: exit status $s ($(cat good.err))"
    for f in calibration.tsv residuals.tsv calibration.gp evaluations.tsv fitted.nml fitted/granules.tsv; do
        [ -s "good/$f" ] || fail "good: no $f"
    done
    grep -q "^# outcome: converged" good/calibration.tsv || fail "good: not converged"
    grep -q "^! young = 1.9299999" good.out || fail "good: young not recovered: $(grep young good.out)"
    # residuals.tsv: a row per measurement (121) and the file's own header
    [ "$(grep -c '^[0-9]' good/residuals.tsv)" -eq 121 ] || fail "good: residuals.tsv rows"
    # the fitted scene runs alone, without &calibrate
    grep -q '&calibrate' good/fitted.nml && fail "good: fitted.nml has &calibrate"
    "$TAPER" good/fitted.nml -o refit > /dev/null 2>&1 || fail "good: fitted.nml does not run"
    # two measured columns, the file's order not taper's: a panel each, the
    # blocks of residuals.tsv in the panels they belong to
    cut -f1,2,4,7 truth/sensors.tsv | awk -F'\t' 'BEGIN { OFS = "\t" } { print $1, $2, $4, $3 }' > two.tsv
    calibrate two two.tsv ", free = 'young', start = 150e9"
    "$TAPER" two.nml -o two > /dev/null 2> two.err || fail "two columns: $(cat two.err)"
    [ "$(grep -c '^plot' two/calibration.gp)" -eq 2 ] || fail "two columns: not two panels"
    sed -n '/ylabel .v \[m\/s\]/,/^plot/p' two/calibration.gp | grep -q "index 0" ||
        fail "two columns: v's panel does not draw block 0"
    awk -F'\t' '$1 ~ /^[0-9]/ { print $4 }' two/residuals.tsv | uniq | tr '\n' ' ' | grep -q '^v force $' ||
        fail "two columns: residuals.tsv's blocks are not v then force"
    # a setting pushed to its bound: exit 6, the files say so
    calibrate bound data.tsv ", free = 'young damping', start = 150e9, 2e-7, lower = 1e11, 0, upper = 1.6e11, 1e-6"
    "$TAPER" bound.nml -o bound > bound.out 2> bound.err
    s=$?
    [ "$s" -eq 6 ] || fail "bound: exit status $s, wanted 6"
    grep -q "calibration NOT CONVERGED: young = 1.6e+11 is at its upper bound" bound.err || fail "bound: $(cat bound.err)"
    grep -q "^# outcome: NOT CONVERGED" bound/calibration.tsv || fail "bound: calibration.tsv does not say so"
    # settings the data cannot tell apart: exit 6
    calibrate twins data.tsv ", free = 'young poisson', start = 150e9, 0.25"
    "$TAPER" twins.nml -o twins > /dev/null 2> twins.err
    s=$?
    [ "$s" -eq 6 ] || fail "twins: exit status $s, wanted 6"
    grep -q "do not determine poisson" twins.err || fail "twins: $(cat twins.err)"
    # a design: its files, and its optimum's scene run alone gives its objective
    { chain 193e9; printf "&design objective = 'wall_peak_force_right', free = 'damping', lower = 0, upper = 1e-6, profile_points = 5 /\n"; } > design.nml
    "$TAPER" design.nml -o design > design.out 2> design.err
    s=$?
    [ "$s" -eq 0 ] || fail "design: exit status $s ($(cat design.err))"
    for f in design.tsv profile.tsv design.gp evaluations.tsv optimum.nml optimum/granules.tsv; do
        [ -s "design/$f" ] || fail "design: no $f"
    done
    # the shipped worked example: E and A of the synthetic record within 2
    # standard errors of what made it (193 GPa, 0.1 us)
    "$TAPER" "$SRC/share/scenes/optimise/calibrate_sensor.nml" -o shipped > /dev/null 2> shipped.err ||
        fail "calibrate_sensor.nml: $(cat shipped.err)"
    awk -F'\t' '$1 == "young" { if (($2 - 193e9) ^ 2 >= (2 * $3) ^ 2) exit 1; n++ }
                 $1 == "damping" { if (($2 - 1e-7) ^ 2 >= (2 * $3) ^ 2) exit 1; n++ }
                 END { exit n != 2 }' shipped/calibration.tsv ||
        fail "calibrate_sensor.nml: not within 2 errors of the truth: $(grep -v '^#' shipped/calibration.tsv)"
    # hold = 'length' and 'mass': the optimum's chain keeps the scene's (20
    # beads of 2.38 mm: 95.2 mm, 9.035 g), summed from its granules.tsv
    for h in length mass; do
        "$TAPER" "$SRC/share/scenes/optimise/design_taper.nml" -o "hold_$h" design.hold="'$h'" \
            design.profile_points=0 design.grid=3 design.tolerance=0.01 > /dev/null 2>&1 ||
            fail "hold $h: the design failed"
        awk -F'\t' -v h="$h" '$1 ~ /^[0-9]/ { L += 2 * $2; M += $3 }
            END { x = h == "length" ? L / 0.0952 : M / (20 * 8000 * 4 / 3 * 3.14159265358979 * 2.38e-3 ^ 3)
                  exit !(x > 1 - 1e-12 && x < 1 + 1e-12) }' "hold_$h/optimum/granules.tsv" ||
            fail "hold $h: the optimum's chain does not keep it"
    done
    best=$(sed -n 's/^# objective: minimise wall_peak_force_right\[N\] = //p' design/design.tsv)
    again=$(sed -n 's/^# wall_peak_force_right\[N\] = //p' design/optimum/granules.tsv)
    [ -n "$best" ] && [ "$best" = "$again" ] || fail "design: optimum $best, its scene run alone $again"
}

resume() {
    # 201 runs of a scan of 20-bead chains followed for 1 ms (about 5 s on
    # one thread): long enough to stop halfway
    chain 193e9 | sed -e '1s/8/20/' -e 's/1.2e-4/1e-3/' > scan.nml
    printf "&design objective = 'wall_peak_force_right', free = 'log_radii(1)', log_radii = 0, lower = -2, upper = 2, hold = 'length', method = 'grid', grid = 201, profile_points = 0 /\n&output threads = 1 /\n" >> scan.nml
    "$TAPER" scan.nml -o whole > /dev/null 2>&1 || fail "resume: the uninterrupted scan failed"
    cp whole/design.tsv stopped/ 2> /dev/null || { mkdir stopped && cp whole/design.tsv stopped/; }
    "$TAPER" scan.nml -o stopped > /dev/null 2> stopped.err &
    pid=$!
    sleep 1
    kill -TERM "$pid"
    wait "$pid"
    s=$?
    [ "$s" -eq 3 ] || fail "resume: stopped with exit status $s, wanted 3"
    grep -q "design interrupted" stopped.err || fail "resume: $(cat stopped.err)"
    [ -e stopped/design.tsv ] && fail "resume: an interrupted design wrote design.tsv"
    done=$(grep -c '^[0-9]' stopped/evaluations.tsv)
    [ "$done" -gt 0 ] && [ "$done" -lt 201 ] || fail "resume: $done runs before the stop"
    "$TAPER" scan.nml -o stopped > again.out 2> again.err || fail "resume: $(cat again.err)"
    grep -q "resuming: $done runs of an interrupted design are reused" again.out ||
        fail "resume: $(grep resuming again.out)"
    [ "$(grep -c '^[0-9]' stopped/evaluations.tsv)" -eq 201 ] || fail "resume: not 201 runs in all"
    # (the count of runs reused differs, and with it the footer's checksum)
    grep -v -e '^# runs' -e '^# end:' whole/design.tsv > a
    grep -v -e '^# runs' -e '^# end:' stopped/design.tsv > b
    cmp -s a b || fail "resume: design.tsv differs from the uninterrupted one: $(diff a b)"
}

case $SECTION in
errors | status | resume) "$SECTION" ;;
*) echo "driver.sh: no section $SECTION" >&2; exit 2 ;;
esac
[ "$failures" -eq 0 ] && echo "optimise $SECTION: all checks passed"
exit $((failures > 0))
