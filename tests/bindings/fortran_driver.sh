#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# fortran_driver.sh TAPER_NML TAPER SCENE -- the Fortran driver (namelist
# READ + iso_c_binding) and the C driver run the same scene through the
# same library: the t_pass and v_peak the Fortran driver prints (8 digits)
# match the C driver's granules.tsv.  Then the inputs both must refuse
# (exit 2, a message, no gfortran backtrace): binary garbage, an empty file,
# s = nan, a misspelt key.
set -eu
fortran=$1
driver=$2
scene=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$fortran" "$scene" >"$tmp/f"
"$driver" "$scene" -o "$tmp/out" >/dev/null
cat "$tmp/f"
awk -F'\t' '
    FNR == NR { if ($0 !~ /^#/ && $1 != "k") { tp[$1] = $5; vp[$1] = $7 } next }
    /^#/ { next }
    { split($0, f, " "); rows++
      if (!(f[1] in tp)) { print "granule " f[1] " missing in granules.tsv"; bad = 1; next }
      d1 = f[2] - tp[f[1]]; d2 = f[4] - vp[f[1]]
      if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2
      if (d1 > 1e-7 * tp[f[1]] || d2 > 1e-7 * vp[f[1]]) {
          print "granule " f[1] ": Fortran " f[2] " " f[4] ", C " tp[f[1]] " " vp[f[1]]; bad = 1 } }
    END { if (rows < 5) { print "only " rows " rows from taper_nml"; bad = 1 } exit bad }
' "$tmp/out/granules.tsv" "$tmp/f" >&2
echo "taper_nml and taper agree on t_pass and v_peak for $(basename "$scene")"

bad=0
refuse() { # NAME WORDS: both drivers exit 2 on $tmp/NAME.nml; taper_nml says WORDS
    for prog in "$driver" "$fortran"; do   # taper_nml's stderr is kept
        status=0
        "$prog" "$tmp/$1.nml" > "$tmp/$1.out" 2> "$tmp/$1.err" || status=$?
        if [ "$status" -ne 2 ]; then
            echo "FAIL: $(basename "$prog") $1.nml: exit status $status, wanted 2" >&2
            bad=1
        fi
    done
    if ! grep -q -- "$2" "$tmp/$1.err" || grep -q 'Backtrace\|ERROR STOP' "$tmp/$1.err"; then
        echo "FAIL: taper_nml $1.nml: stderr '$(cat "$tmp/$1.err")' lacks '$2' or has a backtrace" >&2
        bad=1
    fi
}
printf '\033\001\377garbage\000\n' > "$tmp/garbage.nml"
refuse garbage "binary data"
: > "$tmp/empty.nml"
refuse empty "empty scene"
printf '! only a comment\n' > "$tmp/comments.nml"
refuse comments "empty scene"
printf "&chain profile = 'backward_linear', s = nan, n_granules = 10 /\n" > "$tmp/nan.nml"
refuse nan "&chain s: .*not a finite number"
printf "&solver rtol = inf /\n" > "$tmp/inf.nml"
refuse inf "&solver rtol: .*not a finite number"
# A misspelt key: the C driver's FILE:LINE: &group key: form,
# whichever group and line; gfortran alone names neither file line nor key.
same_place() { # NAME: both drivers' messages start with the same FILE:LINE: &group key:
    for prog in "$driver" "$fortran"; do
        "$prog" "$tmp/$1.nml" > /dev/null 2> "$tmp/$1.$(basename "$prog").err" || :
    done
    c=$(sed -n 's/^\([^:]*:[0-9]*: &[a-z]* [a-z_]*\):.*/\1/p' "$tmp/$1.$(basename "$driver").err" | head -n 1)
    f=$(sed -n 's/^\([^:]*:[0-9]*: &[a-z]* [a-z_]*\):.*/\1/p' "$tmp/$1.$(basename "$fortran").err" | head -n 1)
    if [ -z "$c" ] || [ "$c" != "$f" ]; then
        echo "FAIL: $1.nml: taper says '$(cat "$tmp/$1.$(basename "$driver").err")', taper_nml '$(cat "$tmp/$1.$(basename "$fortran").err")'" >&2
        bad=1
    fi
}
printf "&chain n_granule = 10 /\n" > "$tmp/misspelt.nml"
refuse misspelt "misspelt.nml:1: &chain n_granule: unknown key: did you mean n_granules?"
same_place misspelt
printf "! a scene\n&chain\n  profile = 'monodisperse',\n  n_granules = 20 /\n&solver\n  rtol = 1e-8,\n\n  windw = .true. /\n" > "$tmp/misspelt_later.nml"
refuse misspelt_later "misspelt_later.nml:8: &solver windw: unknown key: did you mean window?"
same_place misspelt_later
printf "&chain n_granules = 20 /\n&fit model = 'power',\n  k_mn = 3 /\n" > "$tmp/misspelt_fit.nml"
refuse misspelt_fit "misspelt_fit.nml:3: &fit k_mn: unknown key: did you mean k_min?"
same_place misspelt_fit
[ "$bad" -eq 0 ] || exit 1
echo "taper_nml refuses garbage, empty files, nan, inf and misspelt keys like taper (FILE:LINE: &group key:)"
