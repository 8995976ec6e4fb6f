#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# long_dir.sh TAPER -- a scene whose &output dir is 3000 characters long (15
# nested folders) runs, and its echo -- on stdout, and in the '# ' scene
# block of granules.tsv -- reads back to the same scene: each echo, run
# again (--get, so nothing is recomputed), resolves to the same directory,
# and echoes itself unchanged.  (A fixed buffer once cut the echoed
# directory at 1020 characters.)
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_long_dir.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# 14 folders of 199 characters and one of 200, 14 slashes: 3000 characters.
folder() { printf "f%02d" "$1"; printf '%*s' "$(($2 - 3))" '' | tr ' ' x; }
dir=$(folder 1 199)
for i in 2 3 4 5 6 7 8 9 10 11 12 13 14; do dir=$dir/$(folder "$i" 199); done
dir=$dir/$(folder 15 200)
[ ${#dir} -eq 3000 ] || fail "the directory has ${#dir} characters, not 3000"

cat > long.nml <<EOF2
&chain profile = 'backward_linear', s = 0.1, n_granules = 20 /
&solver numerics = .false. /
&output dir = '$dir' /
EOF2
"$TAPER" long.nml > stdout.txt 2> err.txt || fail "the scene does not run: $(cat err.txt)"
[ -f "$dir/granules.tsv" ] || fail "no $dir/granules.tsv"
grep -v '^!' stdout.txt > echo.nml
sed -n 's/^# \(&.*\|  .*\|\/\)$/\1/p' "$dir/granules.tsv" > block.nml

for f in echo.nml block.nml; do
    grep -qF "dir = '$dir'" "$f" || fail "$f: the directory is not echoed whole"
    got=$("$TAPER" "$f" --get output.dir 2> err.txt) || { fail "$f does not read: $(cat err.txt)"; continue; }
    [ "$got" = "'$dir'" ] || fail "$f: &output dir reads back as ${#got} characters, not 3002 ('$dir')"
    # The same scene: its echo, run again, is the echo of the original.
    "$TAPER" "$f" > again.txt 2> err.txt || { fail "$f does not run: $(cat err.txt)"; continue; }
    grep -v '^!' again.txt | cmp -s - echo.nml || fail "$f: its echo differs from the original's"
done
cmp -s echo.nml block.nml || fail "the echo on stdout and the scene block of granules.tsv differ"

[ "$failures" -eq 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "long_dir: a 3000-character &output dir echoes and reads back whole"
