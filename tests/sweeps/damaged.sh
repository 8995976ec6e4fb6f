#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# damaged.sh TAPER -- a sweep never reuses or summarises a result that is not
# the one its run wrote (issue 36, item 3).  Each run's granules.tsv ends
# with a footer (row count, byte count, CRC-32) and its scene.hash records
# it: a granules.tsv cut by ten lines, another run's granules.tsv copied in,
# a binary file and a changed number are each found on resume, said on
# stdout, and computed again; the sweep then ends exactly as an undamaged
# one (every file byte for byte).  Temporary files a killed sweep left are
# removed, and said.
set -u
TAPER=$1
. "$(dirname "$0")/same_result.sh"
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

cat > sweep.nml <<'NML'
&chain profile = 'backward_linear', s = 0.1, 0.2, 0.3, 0.4, n_granules = 40 /
&fit model = 'power', y = 'v', k_min = 5 /
&output progress = .false. /
NML
mkdir ref run
(cd ref && "$TAPER" ../sweep.nml -o out > out.txt 2> err.txt) || fail "undamaged sweep: $(cat ref/err.txt)"
cp -r ref/out run/out
d=run/out
sed -i '$d' "$d/s=0.1/granules.tsv"                                  # the footer and
head -n -10 "$d/s=0.1/granules.tsv" > cut && mv cut "$d/s=0.1/granules.tsv"  # ten rows cut
cp "$d/s=0.4/granules.tsv" "$d/s=0.2/granules.tsv"                   # another run's, whole
head -c 4000 /dev/urandom > "$d/s=0.3/granules.tsv"                  # binary
sed -i 's/^7\t/7\t1/' "$d/s=0.4/granules.tsv"                        # a number changed
: > "$d/.sweep.tsv.AbC123"                                           # a killed sweep's
: > "$d/s=0.1/.granules.tsv.XyZ789"                                  # and run's temporaries
(cd run && "$TAPER" ../sweep.nml -o out > out.txt 2> err.txt)
status=$?
[ $status -eq 0 ] || fail "resume over damaged results: exit status $status: $(cat run/err.txt)"
grep -q '^! resuming' run/out.txt && fail "damaged runs counted as reused: $(grep '^!' run/out.txt)"
grep -q '^! removed 2 temporary files a killed taper left in out$' run/out.txt ||
    fail "the temporaries removed are not said: $(grep '^!' run/out.txt)"
ls -a run/out run/out/s=0.1 | grep -q '\.XyZ789$\|\.AbC123$' && fail "a temporary stayed"
for s in 0.1 0.2 0.3 0.4; do
    grep -q "^! run s=$s: .*s=$s.*: computed again$" run/out.txt ||
        fail "s=$s: the damage is not said: $(grep '^! run' run/out.txt)"
done
grep -q "run s=0.2: .*its result files are not those its scene.hash vouches for" run/out.txt ||
    fail "the copied file: $(grep 's=0.2' run/out.txt)"
(cd ref/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.ref
(cd run/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.run
diff files.ref files.run >&2 || fail "files differ from the undamaged sweep's"
while read -r f; do
    same_result "ref/out/$f" "run/out/$f" || fail "$f differs from the undamaged sweep's"
done < files.ref
[ $failures -eq 0 ] && echo "damaged results: found, said and computed again"
[ $failures -eq 0 ]
