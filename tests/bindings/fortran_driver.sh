#!/bin/sh
# fortran_driver.sh TAPER_NML TAPER SCENE -- the Fortran driver (namelist
# READ + iso_c_binding) and the C driver run the same scene through the
# same library: the t_pass and v_peak the Fortran driver prints (8 digits)
# match the C driver's granules.tsv.
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
