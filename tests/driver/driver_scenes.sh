#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# driver_scenes.sh TAPER SOURCE_DIR -- the taper driver end to end:
#  - every shipped scene (share/scenes/*.nml) runs, writes a complete tidy
#    granules.tsv (one row per granule, the contract columns) and echoes a
#    resolved scene that runs again to the same numbers;
#  - every bad scene (tests/driver/scenes/bad/*.nml) exits 2 with FILE:LINE: &group key:
#    as listed in tests/driver/scenes/bad/EXPECT;
#  - partial runs (t_max, Ctrl-C) write granules.partial.tsv, exit 3, and
#    leave no granules.tsv;
#  - command line: --help, --version, --defaults, bad options, missing file.
set -u
# Meson passes paths relative to the build directory: anchor them before cd.
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SRC=$(absolute "$2")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_driver.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0

fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

COLUMNS_WANTED=$(printf 'k\tR\tm\tX0\tt_pass\tT_res\tv_peak\tt_peak\tX_pass\ttheory_v\ttheory_T\ttheory_t')
COLUMNS_THEORY=$(printf 'k\tR\tm\tX0\ttheory_v\ttheory_T\ttheory_t')

# check_table FILE N NUMERICS: the header as the first line (the contract
# columns, each with its unit in brackets in SI, R[m]; without numerics, F,
# only those of the chain and the theory), N
# rows with as many fields, k = 1..N, R and theory_v numeric; with numerics,
# T, t_pass numeric but nan on the last row (P: a partial run, t_pass not
# checked).
check_table() {
    file=$1 n=$2 numerics=$3
    header=$(head -n 1 "$file" | sed 's/\[[^]]*\]//g')
    if [ "$numerics" = F ]; then want=$COLUMNS_THEORY; else want=$COLUMNS_WANTED; fi
    [ "$header" = "$want" ] || fail "$file: first line is '$header'"
    grep -q '^# taper [0-9]' "$file" || fail "$file: no version comment"
    awk -F '\t' -v n="$n" -v numerics="$numerics" -v file="$file" '
        NR == 1 { for (i = 1; i <= NF; i++) { name = $i; sub(/\[.*\]$/, "", name); col[name] = i }
                  fields = NF; next }
        /^#/ { next }
        {
            rows++
            if (NF != fields) { print file ": row " rows " has " NF " fields"; bad = 1 }
            if ($1 != rows) { print file ": row " rows " has k = " $1; bad = 1 }
            if ($col["R"] !~ /^[0-9.e+-]+$/ || $col["theory_v"] !~ /^[0-9.e+-]+$/) { print file ": row " rows ": R or theory_v not a number"; bad = 1 }
            if (numerics == "T" && rows < n && $col["t_pass"] !~ /^[0-9.e+-]+$/) { print file ": row " rows ": t_pass = " $col["t_pass"]; bad = 1 }
            last_tpass = numerics == "F" ? "nan" : $col["t_pass"]
        }
        END {
            if (rows != n) { print file ": " rows " rows, wanted " n; bad = 1 }
            if (numerics != "P" && last_tpass != "nan") { print file ": t_pass of the last granule is " last_tpass; bad = 1 }
            exit bad
        }' "$file" >&2 || fail "$file: table malformed"
}

# n_granules and numerics from the resolved scene in the comments.
scene_n() { sed -n 's/^#   n_granules = \([0-9]*\)$/\1/p' "$1"; }
scene_numerics() { grep -q '^#   numerics = .true.' "$1" && echo T || echo F; }

check_result_dir() {
    dir=$1
    f=$dir/granules.tsv
    [ -f "$f" ] || { fail "$dir: no granules.tsv"; return; }
    [ -e "$dir/granules.partial.tsv" ] && fail "$dir: partial file next to a complete one"
    ls -a "$dir" | grep -q '^\.granules' && fail "$dir: temporary file left behind"
    grep -q '^# complete' "$f" || fail "$f: not marked complete"
    numerics=$(scene_numerics "$f")
    if [ "$numerics" = T ]; then
        for key in steps rhs_evals root_evals jac_evals energy_error momentum_error t_final; do
            grep -q "^# $key\(\[[^]]*\]\)\{0,1\} = " "$f" || fail "$f: no $key statistic"
        done
    fi
    check_table "$f" "$(scene_n "$f")" "$numerics"
}

# Numbers only (comments name the directory, which differs).
data_rows() { grep -v '^#' "$1"; }

# ---- shipped scenes --------------------------------------------------------
for scene in "$SRC"/share/scenes/*.nml; do
    name=$(basename "$scene" .nml)
    "$TAPER" "$scene" -o "run/$name" > "$name.echo" 2> "$name.err"
    status=$?
    if [ "$status" -ne 0 ]; then
        fail "$name: exit status $status ($(cat "$name.err"))"
        continue
    fi
    dirs=$(find "run/$name" -name granules.tsv -exec dirname {} \; | sort)
    [ -n "$dirs" ] || { fail "$name: no granules.tsv anywhere"; continue; }
    if grep -q "^! sweep" "$name.echo"; then
        want=$(grep -c "^! sweep" "$name.echo")
        got=$(echo "$dirs" | wc -l)
        [ "$want" -eq "$got" ] || fail "$name: $want sweep values, $got result files"
    fi
    for d in $dirs; do check_result_dir "$d"; done
    # The echo is a scene: running it gives the same numbers.
    if "$TAPER" "$name.echo" -o "again/$name" > /dev/null 2> "$name.err2"; then
        for d in $dirs; do
            sub=${d#run/$name}
            data_rows "$d/granules.tsv" > a.tsv
            data_rows "again/$name$sub/granules.tsv" > b.tsv 2> /dev/null
            cmp -s a.tsv b.tsv || fail "$name: the echoed scene gives different numbers in $sub"
        done
    else
        fail "$name: the echoed scene does not run: $(cat "$name.err2")"
    fi
done

# ---- bad scenes ---------------------------------------------------------------
BAD=$SRC/tests/driver/scenes/bad
for scene in "$BAD"/*.nml; do
    base=$(basename "$scene")
    grep -q "^$base |" "$BAD/EXPECT" || fail "$base: no line in EXPECT"
done
grep -v '^#' "$BAD/EXPECT" | while IFS='|' read -r file prefix words; do
    file=$(echo "$file" | sed 's/ *$//')
    prefix=$(echo "$prefix" | sed 's/^ *//; s/ *$//')
    words=$(echo "$words" | sed 's/^ *//; s/ *$//')
    "$TAPER" "$BAD/$file" > /dev/null 2> err.txt
    status=$?
    [ "$status" -eq 2 ] || echo "FAIL: $file: exit status $status, wanted 2" >&2
    first=$(head -n 1 err.txt)
    case "$first" in
        "$BAD/$prefix"*) ;;
        *) echo "FAIL: $file: stderr '$first' does not start with '$BAD/$prefix'" >&2 ;;
    esac
    grep -qF -- "$words" err.txt || echo "FAIL: $file: stderr '$first' lacks '$words'" >&2
done 2> bad.log
if [ -s bad.log ]; then
    cat bad.log >&2
    failures=$((failures + $(wc -l < bad.log)))
fi
# Bad scenes never leave output behind.
[ -e out ] && fail "a bad scene created an output directory: $(ls -R out | head -5)"

# ---- partial runs ----------------------------------------------------------------
cat > limited.nml <<'EOF'
&chain profile = 'backward_linear', s = 0.1, n_granules = 60 /
&solver t_max = 5 /
EOF
"$TAPER" limited.nml -o lim > /dev/null 2> lim.err
status=$?
[ "$status" -eq 3 ] || fail "t_max run: exit status $status, wanted 3"
grep -q 'limited.nml: .*t_max' lim.err || fail "t_max run: stderr lacks the library message: $(cat lim.err)"
[ -e lim/granules.tsv ] && fail "t_max run wrote granules.tsv"
grep -q '^# PARTIAL' lim/granules.partial.tsv || fail "t_max run: partial file not marked PARTIAL"
check_table lim/granules.partial.tsv 60 P

# A stale complete result is removed by a partial run, and vice versa.
sed 's/t_max = 5/t_max = 0/' limited.nml > full.nml
"$TAPER" full.nml -o lim > /dev/null 2>&1 || fail "full run failed"
[ -e lim/granules.partial.tsv ] && fail "complete run left a stale granules.partial.tsv"
[ -e lim/granules.tsv ] || fail "complete run wrote no granules.tsv"
"$TAPER" limited.nml -o lim > /dev/null 2>&1
[ -e lim/granules.tsv ] && fail "partial run left a stale granules.tsv"

# Ctrl-C: a long run ends partial with exit 3, keeping what was found.
cat > long.nml <<'EOF'
&chain n_granules = 200000 /
EOF
"$TAPER" long.nml -o long > /dev/null 2> long.err &
pid=$!
sleep 1
kill -INT "$pid"
wait "$pid"
status=$?
[ "$status" -eq 3 ] || fail "SIGINT: exit status $status, wanted 3 ($(cat long.err))"
[ -e long/granules.tsv ] && fail "SIGINT wrote granules.tsv"
grep -q '^# PARTIAL' long/granules.partial.tsv 2> /dev/null || fail "SIGINT: no partial file"

# ---- command line ------------------------------------------------------------------
"$TAPER" --help | grep -q '^usage: taper' || fail "--help"
"$TAPER" --version | grep -q '^taper [0-9]' || fail "--version"
"$TAPER" --bogus > /dev/null 2>&1
[ $? -eq 2 ] || fail "an unknown option must exit 2"
"$TAPER" > /dev/null 2>&1
[ $? -eq 2 ] || fail "no scene must exit 2"
"$TAPER" no_such_scene.nml > /dev/null 2> err.txt
[ $? -eq 2 ] || fail "a missing scene must exit 2"
grep -q '^no_such_scene.nml: cannot open' err.txt || fail "missing scene: $(cat err.txt)"
"$TAPER" --defaults > defaults.nml || fail "--defaults"
sed 's/numerics *= *.true./numerics = .false./' defaults.nml > defaults_theory.nml
"$TAPER" defaults_theory.nml > /dev/null 2> err.txt || fail "--defaults output does not run: $(cat err.txt)"
check_result_dir out/defaults_theory
# An unwritable directory given with -o is named.
"$TAPER" defaults_theory.nml -o defaults.nml/sub > /dev/null 2> err.txt
[ $? -eq 2 ] || fail "an output directory below a file must exit 2"
grep -q 'defaults.nml/sub\|defaults.nml: exists' err.txt || fail "unwritable -o: $(cat err.txt)"

# ---- figures -------------------------------------------------------------------------
# Fig. 1's y axis spans its data: the inset finds room inside it rather than
# stretching the axis decades below the lowest point (theory only: fast).
TAPER_GNUPLOT=none "$TAPER" "$SRC/share/scenes/paper/fig01.nml" solver.numerics=.false. \
    figure.curves=\'theory\' -o fig01 > /dev/null 2> err.txt || fail "fig01 theory only: $(cat err.txt)"
lowest=$(awk -F '\t' '!/^#/ && NF > 3 && $4 > 0 { if (m == "" || $4 < m) m = $4 } END { print m }' fig01/figure.tsv)
ylo=$(sed -n 's/^set yrange \[\([^:]*\):.*/\1/p' fig01/figure.gp)
[ -z "$ylo" ] || awk "BEGIN { exit !($ylo >= $lowest / 10) }" ||
    fail "fig01: the y axis starts at $ylo, the lowest point is $lowest"

if [ "$failures" -ne 0 ]; then
    echo "$failures failure(s)" >&2
    exit 1
fi
echo "driver: all checks passed"
