#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# physics_scenes.sh TAPER SOURCE_DIR -- the scenes beyond the paper end to end
# (share/scenes/physics, one per capability), each checked for what it is
# about, not only for files:
#   wall_reflection    the wave comes back: most of the energy reflected,
#                      walls.tsv's force integrates to the wall's impulse,
#                      the peak on the sampled curve; no statistics of the
#                      free end; sensors.tsv one row per granule and sample
#   striker            the striker's mass is density radius^3: E0 = 8/2
#   precompressed,     the theory columns are nan, the header and stderr
#   damped             say why; energy dissipated > 0 and the budget adds up
#   steel_wall_si      units in every header; the SI files are the rescaled
#                      ones times the unit scales exactly (si_units.py)
#   mixed_si           masses from the materials' densities, sizes in metres
#   decorated          the effective chain's theory at the large granules
#   disorder_ensemble  one run per seed; a seed run alone is the same run
#   radii_file         N and R_k from the file; the echo runs elsewhere
# and every new numeric variable sweeps (damping, young); a wall's
# statistics are those of its whole first contact without t_end.
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SRC=$(absolute "$2")
PHYS=$SRC/share/scenes/physics
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_physics.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

# header_value FILE NAME: the value of "# NAME = VALUE".
header_value() { sed -n "s/^# $2 = \\([^ ]*\\).*$/\\1/p" "$1" | head -n 1; }
# awk_true EXPR: awk's verdict on a numeric expression.
awk_true() { awk "BEGIN { exit !($1) }"; }
is_png() { [ "$(od -An -c -N4 "$1" 2> /dev/null | tr -d ' ')" = '211PNG' ]; }
have_gnuplot() { command -v "${TAPER_GNUPLOT:-gnuplot}" > /dev/null 2>&1; }

# ---- every scene runs -----------------------------------------------------------
for scene in "$PHYS"/*.nml; do
    name=$(basename "$scene" .nml)
    "$TAPER" "$scene" -o "run/$name" > "$name.out" 2> "$name.err"
    status=$?
    [ "$status" -eq 0 ] || fail "$name: exit status $status ($(head -c 600 "$name.err"))"
    files=$(find "run/$name" -name granules.tsv)
    [ -n "$files" ] || { fail "$name: no granules.tsv"; continue; }
    for f in $files; do
        head -n 1 "$f" | grep -q '^k	R' || fail "$f: first line is not the column names"
        grep -q '^# complete' "$f" || fail "$f: not complete"
        grep -q '^# energy_initial' "$f" || fail "$f: no energy budget in the header"
    done
    grep -q '^! energy at t_final: initial' "$name.out" || fail "$name: no energy line on stdout"
done

# ---- wall_reflection -------------------------------------------------------------
d=run/wall_reflection
g=$d/granules.tsv
[ "$(head -n 1 $d/walls.tsv)" = "$(printf 't\tforce_right')" ] || fail "walls.tsv: first line $(head -n 1 $d/walls.tsv)"
grep -q '^# wall_.*_left' "$g" && fail "$g: statistics of a wall the chain does not have (left end free)"
e0=$(header_value "$g" energy_initial)
er=$(header_value "$g" energy_reflected)
awk_true "$e0 == 0.5" || fail "wall_reflection: energy_initial = $e0, wanted 1/2 (v_1 = 1, m_1 = 1)"
awk_true "$er > 0.95 * $e0" || fail "wall_reflection: energy_reflected = $er: the wave does not come back"
peak=$(header_value $d/walls.tsv wall_peak_force_right)
impulse=$(header_value $d/walls.tsv wall_impulse_right)
[ "$peak" = "$(header_value "$g" wall_peak_force_right)" ] || fail "walls.tsv and granules.tsv disagree on the peak"
# The sampled force: its trapezoid integral is the impulse (1 %), its largest
# sample at most the exact peak and within 3 % of it (sampled every 0.25).
awk -F '\t' -v impulse="$impulse" -v peak="$peak" '
    NR == 1 || /^#/ { next }
    { if (n++) sum += ($1 - t) * ($2 + f) / 2; t = $1; f = $2; if ($2 > top) top = $2 }
    END {
        if (!(impulse > 0) || (sum - impulse) / impulse > 0.01 || (impulse - sum) / impulse > 0.01) { print "impulse " impulse ", integral of walls.tsv " sum; bad = 1 }
        if (top > peak * (1 + 1e-12) || top < 0.97 * peak) { print "peak " peak ", largest sample " top; bad = 1 }
        exit bad }' $d/walls.tsv >&2 || fail "wall_reflection: walls.tsv against its statistics"
[ "$(head -n 1 $d/sensors.tsv)" = "$(printf 't\tgranule\tx\tv\tf_left\tf_right\tforce')" ] || fail "sensors.tsv: first line"
samples=$(sed -n 's/^# sampled every .*; \([0-9]*\) samples$/\1/p' $d/sensors.tsv)
rows=$(grep -vc '^#' $d/sensors.tsv)
[ "$rows" -eq $((3 * samples + 1)) ] || fail "sensors.tsv: $rows lines for 3 granules x $samples samples"
# t_end = 110 sampled every 0.25: samples at 0, 0.25, ..., 110.
[ "$samples" -eq 441 ] || fail "sensors.tsv: $samples samples, wanted 441 (t = 0 .. t_end every 0.25)"
[ -s $d/spacetime.tsv ] && [ -s $d/spacetime.gp ] || fail "wall_reflection: no space-time data"
if have_gnuplot; then is_png $d/spacetime.png || fail "wall_reflection: spacetime.png is not a PNG"; fi

# A long chain's picture stays within its bounds (at most spacetime_granules
# columns and spacetime_times rows, plus the samples after the last full
# row), and the pulse shows in every row though it is narrower than a cell:
# a monodisperse solitary wave keeps v_max ~ 0.68 all along.
printf '&chain n_granules = 3000 /\n&sensors interval = 1, spacetime = .true.,\n  spacetime_granules = 100, spacetime_times = 50 /\n' > long.nml
"$TAPER" long.nml -o run/long > /dev/null 2> long.err || fail "long chain picture: $(cat long.err)"
awk -F '\t' 'NR == 1 || /^#/ || NF < 3 { next }
    { k[$2] = 1; if (!($1 in vmax)) { rows++; vmax[$1] = 0 } if ($3 > vmax[$1]) vmax[$1] = $3 }
    END {
        n = 0; for (x in k) n++
        if (n > 100 || rows > 51 || rows < 25) { print "grid " n " x " rows; bad = 1 }
        for (t in vmax) if (t > 10 && vmax[t] < 0.5) { print "t = " t ": largest v " vmax[t]; bad = 1 }
        exit bad }' run/long/spacetime.tsv >&2 || fail "long chain picture: grid or pulse lost"

# ---- striker ------------------------------------------------------------------------
e0=$(header_value run/striker/granules.tsv energy_initial)
awk_true "$e0 == 4" || fail "striker: energy_initial = $e0, wanted 4 (mass 2^3, unit velocity)"

# ---- theory out of its model: nan, and said so ----------------------------------------
for name in precompressed damped; do
    g=run/$name/granules.tsv
    grep -q '^# theory: nan: ' "$g" || fail "$name: no '# theory: nan:' line"
    grep -q 'note: the theory columns are nan' "$name.err" || fail "$name: no note on stderr"
    awk -F '\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } /^#/ { next }
        $c["theory_v"] != "nan" || $c["theory_T"] != "nan" || $c["theory_t"] != "nan" { bad = 1 }
        END { exit bad }' "$g" || fail "$name: a theory column is not nan"
done
g=run/damped/granules.tsv
awk -v e0="$(header_value $g energy_initial)" -v d="$(header_value $g energy_dissipated)" \
    -v t="$(header_value $g energy_transmitted)" -v r="$(header_value $g energy_reflected)" \
    -v c="$(header_value $g energy_in_chain)" 'BEGIN {
        s = d + t + r + c
        if (!(d > 0.1 * e0)) { print "dissipated " d " of " e0; exit 1 }
        if ((s - e0) / e0 > 1e-6 || (e0 - s) / e0 > 1e-6) { print "budget " s " against " e0; exit 1 } }' >&2 ||
    fail "damped: energy budget"
grep -q '^# theory: nan' run/wall_reflection/granules.tsv && fail "wall_reflection: a wall keeps the theory of the first pass"

# ---- real units ---------------------------------------------------------------------------
d=run/steel_wall_si
head -n 1 $d/granules.tsv | grep -q "	t_pass\[s\]	" || fail "steel_wall_si: granules.tsv header $(head -n 1 $d/granules.tsv)"
[ "$(head -n 1 $d/walls.tsv)" = "$(printf 't[s]\tforce_right[N]')" ] || fail "steel_wall_si: walls.tsv header"
head -n 1 $d/sensors.tsv | grep -q '^t\[s\]	granule	x\[m\]	v\[m/s\]' || fail "steel_wall_si: sensors.tsv header"
grep -q '^# unit_time = .* s$' $d/granules.tsv || fail "steel_wall_si: no unit lines"
"$TAPER" "$PHYS/steel_wall_si.nml" "output.units='rescaled'" -o run/steel_rescaled > /dev/null 2>&1 ||
    fail "steel_wall_si in rescaled units does not run"
python3 "$SRC/tests/driver/si_units.py" run/steel_rescaled $d >&2 || fail "steel_wall_si: SI files are not rescaled x units"
# the wall is steel: the impact lasts microseconds, the peak force is of
# newtons to kilonewtons for 0.5 m/s on 4.76 mm beads
peak=$(header_value $d/granules.tsv 'wall_peak_force_right\[N\]')
awk_true "$peak > 10 && $peak < 10000" || fail "steel_wall_si: wall peak force $peak N"

# SI in: with &material, t_end and the sensors' interval are seconds: 1.5 ms
# sampled every microsecond is 1501 samples, not 1.5e-3 rescaled units at
# intervals of 1e-6 of them (which wrote 9 GB)
"$TAPER" "$PHYS/steel_wall_si.nml" solver.t_end=1.5e-3 sensors.interval=1e-6 -o run/si_in > /dev/null 2>&1 ||
    fail "steel_wall_si with t_end = 1.5e-3 s does not run"
samples=$(grep -cv '^[#t]' run/si_in/walls.tsv)
[ "$samples" -eq 1501 ] || fail "t_end = 1.5e-3 s every 1e-6 s: $samples samples, wanted 1501"
# a sweep of the impact velocity keeps every physical input fixed: both runs
# end at t_end = 1.5 ms and sample every microsecond (in rescaled units both
# differ, as the unit of time scales as V^(-1/5))
"$TAPER" "$PHYS/steel_wall_si.nml" solver.t_end=1.5e-3 sensors.interval=1e-6 material.velocity=0.5,1 \
    -o run/si_velocity > /dev/null 2>&1 || fail "a sweep of &material velocity does not run"
for v in 0.5 1; do
    last=$(grep -v '^[#t]' "run/si_velocity/velocity=$v/walls.tsv" | tail -n 1 | cut -f 1)
    awk_true "($last - 1.5e-3) ^ 2 < 1e-24" || fail "velocity $v: last sample at t = $last s, wanted 1.5e-3 s"
done
# and 1e8 samples are refused before the run, with the estimate
"$TAPER" "$PHYS/steel_wall_si.nml" sensors.interval=1e-11 -o run/si_huge > /dev/null 2> huge.err
rc=$?
[ "$rc" -eq 2 ] || fail "1e8 samples: exit status $rc, wanted 2"
grep -q 'the samples would take about .* bytes (1.27e+08 samples' huge.err ||
    fail "1e8 samples: no estimate in '$(cat huge.err)'"
grep -q 'max_output' huge.err || fail "1e8 samples: the message does not name max_output"
[ -e run/si_huge/walls.tsv ] && fail "1e8 samples: walls.tsv written"

# a wall's peak is found without t_end: the run goes on until the wall's
# force has peaked and fallen (the same peak as the run to t_end)
"$TAPER" "$PHYS/steel_wall_si.nml" solver.t_end=0 -o run/wall_no_t_end > /dev/null 2>&1 ||
    fail "steel_wall_si without t_end does not run"
p0=$(header_value run/wall_no_t_end/granules.tsv 'wall_peak_force_right\[N\]')
p1=$(header_value run/steel_wall_si/granules.tsv 'wall_peak_force_right\[N\]')
[ -n "$p0" ] && [ "$p0" = "$p1" ] || fail "wall peak force without t_end '$p0', with t_end '$p1'"
# a wall the pulse never reached has no peak: nan and a warning, never 0
# (forward taper: granule 1 follows the lighter ones, never back to the wall)
printf '&chain profile = %s, q = 0.2, n_granules = 20 /\n&ends left = %s /\n' "'forward_exponential'" "'wall'" > left_wall.nml
"$TAPER" left_wall.nml -o run/left_wall > /dev/null 2> left_wall.err || fail "a left wall without t_end does not run"
[ "$(header_value run/left_wall/granules.tsv wall_peak_force_left)" = nan ] ||
    fail "left wall not reached: peak force $(header_value run/left_wall/granules.tsv wall_peak_force_left)"
grep -q 'the left wall felt no force' left_wall.err || fail "left wall not reached: no warning ($(cat left_wall.err))"

# the space-time picture has a title and says the unit of each axis
for d in run/damped run/mixed_si; do
    grep -q '^set title "velocity v(k, t)' $d/spacetime.gp || fail "$d/spacetime.gp: no title"
done
grep -q "^set ylabel 't \[rescaled time, eq. (5)\]'" run/damped/spacetime.gp || fail "damped/spacetime.gp: time axis unit"
grep -q "^set cblabel 'v \[m/s\]'" run/mixed_si/spacetime.gp || fail "mixed_si/spacetime.gp: velocity unit"

# a mixed chain: each granule's mass from its material (PTFE 2200 kg/m^3
# between steel 8000), sizes in metres (R = R_1 = 2.38 mm, the beads'
# 4.76 mm diameter)
awk -F '\t' 'NR == 1 || /^#/ { next }
    { m[$1] = $3; if ($2 != 0.00238) bad = 1 }
    END {
        r = m[30] / m[10]
        if (bad || (r - 2200 / 8000) ^ 2 > 1e-28 || m[50] != m[10]) { print "R or masses: m10 " m[10] " m30 " m[30] " m50 " m[50]; exit 1 } }' \
    run/mixed_si/granules.tsv >&2 || fail "mixed_si: sizes or masses of the materials"

# ---- decorated ------------------------------------------------------------------------------
awk -F '\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } /^#/ { next }
    $1 % 2 == 1 && $1 < 90 && ($c["theory_v"] == "nan" || $c["v_peak"] == "nan") { bad = 1 }
    END { exit bad }' run/decorated/granules.tsv || fail "decorated: theory or numerics missing at a large granule"

# ---- the ensemble ------------------------------------------------------------------------------
d=run/disorder_ensemble
[ "$(ls -d $d/seed=* | wc -l)" -eq 8 ] || fail "disorder_ensemble: $(ls -d $d/seed=* | wc -l) runs, wanted 8"
head -n 1 $d/sweep.tsv | grep -q '^seed	k	R' || fail "disorder_ensemble: sweep.tsv header $(head -n 1 $d/sweep.tsv)"
cut -f 2 "$d/seed=1/granules.tsv" | grep -v '^#' > r1
cut -f 2 "$d/seed=2/granules.tsv" | grep -v '^#' > r2
cmp -s r1 r2 && fail "disorder_ensemble: seeds 1 and 2 give the same radii"
"$TAPER" "$PHYS/disorder_ensemble.nml" chain.seed=3 -o run/seed3 > /dev/null 2>&1 || fail "one seed alone does not run"
grep -v '^#' "$d/seed=3/granules.tsv" > a.tsv
grep -v '^#' run/seed3/granules.tsv > b.tsv
cmp -s a.tsv b.tsv || fail "disorder_ensemble: seed 3 alone differs from seed 3 of the ensemble"

# ---- radii from a file ----------------------------------------------------------------------------
g=run/radii_file/granules.tsv
grep -q '^#   n_granules = 120$' "$g" || fail "radii_file: n_granules not resolved from the file"
grep -v '^#' "$PHYS/radii_file.txt" | sed 's/#.*//; s/[ 	]*$//' | grep -v '^$' > want.txt
grep -v '^#' "$g" | sed 1d | cut -f 2 > got.txt
paste want.txt got.txt | awk '$1 != $2 + 0 && ($1 - $2) ^ 2 > 1e-30 { bad = 1 } END { exit bad || NR != 120 }' ||
    fail "radii_file: R column differs from the file"
# the echo names the file by its absolute path: it runs from anywhere
mkdir elsewhere
(cd elsewhere && "$TAPER" ../radii_file.out -o again > /dev/null 2> err.txt) || fail "radii_file: echo does not run elsewhere: $(cat elsewhere/err.txt)"

# ---- the new variables sweep ------------------------------------------------------------------------
"$TAPER" "$PHYS/damped.nml" losses.damping=0,0.05 sensors.interval=0 sensors.spacetime=.false. -o run/sweep_damping > sw.out 2> sw.err ||
    fail "a sweep of damping does not run: $(head -c 400 sw.err)"
d0=$(header_value "run/sweep_damping/damping=0/granules.tsv" energy_dissipated)
d1=$(header_value "run/sweep_damping/damping=0.05/granules.tsv" energy_dissipated)
awk_true "$d1 > $d0" || fail "damping sweep: dissipated $d0 (damping 0) and $d1 (0.05)"
"$TAPER" "$PHYS/steel_wall_si.nml" material.young=193e9,100e9 -o run/sweep_young > /dev/null 2> sy.err ||
    fail "a sweep of young does not run: $(head -c 400 sy.err)"
u1=$(header_value "run/sweep_young/young=1.93e+11/granules.tsv" unit_time)
u2=$(header_value "run/sweep_young/young=1e+11/granules.tsv" unit_time)
[ -n "$u1" ] && [ -n "$u2" ] && [ "$u1" != "$u2" ] || fail "young sweep: unit_time '$u1' and '$u2'"

# A wall over its whole first contact (issue 36, item 10): without t_end
# the run ends as the right wall's first contact opens, and the wall's
# impulse is the contact's, within 1e-6 of the same scene run with t_end
# past the contact's end (before the next one: the sampled contacts of
# wall_reflection are [40.5, 49.5], [253.25, 262.5]; of steel_wall_si
# [4.19e-4, 5.54e-4] s, [7.39e-4, 8.38e-4] s).  Before, the steel wall's
# impulse without t_end was 0.00383 of its 0.00424 N s.
for case in "wall_reflection.nml 100 wall_impulse_right" \
            "steel_wall_si.nml 6.5e-4 wall_impulse_right\[N s\]"; do
    set -- $case
    scene=$1 t_end=$2 stat=$3
    name=${scene%.nml}
    "$TAPER" "$PHYS/$scene" solver.t_end=0 -o "run/contact_$name" > /dev/null 2> contact.err ||
        fail "$scene without t_end: $(cat contact.err)"
    "$TAPER" "$PHYS/$scene" solver.t_end="$t_end" -o "run/past_$name" > /dev/null 2> past.err ||
        fail "$scene, t_end = $t_end: $(cat past.err)"
    impulse_line='s/^# wall_impulse_right\(\[N s\]\)\{0,1\} = //p' # [N s] in SI
    j0=$(sed -n "$impulse_line" "run/contact_$name/granules.tsv")
    j1=$(sed -n "$impulse_line" "run/past_$name/granules.tsv")
    [ -n "$j0" ] && [ -n "$j1" ] && awk_true "($j0 - $j1)^2 <= (1e-6 * $j1)^2" ||
        fail "$scene: the wall's impulse without t_end is $j0, with t_end = $t_end $j1"
    grep -q "^# wall_\*: over the run, \[0, t_final\]" "run/contact_$name/granules.tsv" ||
        fail "$scene: granules.tsv does not say over which interval the wall's statistics are"
done

if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)" >&2
    exit 1
fi
echo "physics scenes: all checks passed"
