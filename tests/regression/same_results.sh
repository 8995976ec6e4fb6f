#!/bin/sh
# same_results.sh -- does a restructured taper still write the same results?
#
#   sh tests/regression/same_results.sh TAPER_BINARY [REFERENCE_COMMIT]
#
# Issue 12 restructures the source tree (the architecture only): it must not
# change any result.  This script proves it for the shipped scenes.  It
#  - builds REFERENCE_COMMIT (default bc35120) from the git history of the
#    checkout it lives in (git archive, meson setup -Dtests=false, the driver
#    target only), cached in $TAPER_REGRESSION_CACHE/COMMIT_HASH (default
#    ${TMPDIR:-/tmp}/taper-regression) so that later calls do not rebuild;
#  - runs the reference driver and TAPER_BINARY, one after the other, on every
#    scene of the reference's tree (share/scenes/*.nml, share/scenes/paper/*.nml;
#    scenes only in this checkout, or only at the reference, are reported);
#  - compares, recursively (a sweep writes one directory per run), every
#    granules.tsv, sweep.tsv, fits.tsv and table.tsv of the two output
#    directories byte for byte, and the exit statuses of the two runs.
# Ignored: only the line naming the taper version, the first line of each of
# those files ("# taper 0.1.0 granules: ...", "# taper 0.1.0 sweep over s: ...").
# Not compared: figures (figure.png, figure.gp, figure.tsv, inset.tsv), stdout.
# A run that ends early (granules.partial.tsv) shows as a different exit
# status and a missing granules.tsv.  Outputs and per-run stderr logs are kept
# when a scene differs.
# Both runs get the same scene path and the same relative "-o out" (each in a
# working directory of its own), so the echoed "# scene file:" and "dir = "
# header lines agree without being ignored.
# Build TAPER_BINARY with the default buildtype (release), as the reference is:
# other compiler flags may change the last digits.
#
# Output: one line per scene, "same   SCENE (N files)" or
# "DIFFER SCENE : FILE line L" with a short excerpt, then "N scenes same, M differ".
# Exit status: 0 every scene same, 1 some scene differs, 2 usage or build error.
set -u

usage='usage: sh tests/regression/same_results.sh TAPER_BINARY [REFERENCE_COMMIT]'

die() {
    printf 'same_results.sh: %s\n' "$*" >&2
    exit 2
}

case ${1-} in
    -h | --help)
        echo "$usage"
        exit 0
        ;;
esac
if [ $# -lt 1 ] || [ $# -gt 2 ] || [ -z "$1" ]; then
    echo "$usage" >&2
    exit 2
fi

# ---- the binary under test --------------------------------------------------
bin=$1
if [ ! -f "$bin" ]; then
    case $bin in
        */*) ;;
        *) bin=$(command -v "$bin") || bin=$1 ;;
    esac
fi
if [ ! -f "$bin" ] || [ ! -x "$bin" ]; then
    die "TAPER_BINARY '$1' is not an executable file"
fi
case $bin in
    /*) ;;
    *) bin=$(pwd)/$bin ;;
esac

# ---- the reference commit, from the history of this checkout ----------------
here=$(dirname "$0")
top=$(git -C "$here" rev-parse --show-toplevel 2>/dev/null) ||
    die "$here is not inside a git checkout (the reference is built from its history)"
ref=${2:-bc35120}
hash=$(git -C "$top" rev-parse --verify --quiet "$ref^{commit}") ||
    die "'$ref' is not a commit in $top"
short=$(git -C "$top" rev-parse --short "$hash")

cache=${TAPER_REGRESSION_CACHE:-${TMPDIR:-/tmp}/taper-regression}
refdir=$cache/$hash
building=
work=
keep_work=0
# shellcheck disable=SC2317 # run by the EXIT trap
cleanup() {
    if [ -n "$building" ]; then rm -rf "$building"; fi
    if [ -n "$work" ] && [ "$keep_work" = 0 ]; then rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 2' HUP INT TERM

# refdir/ok holds the driver's path relative to refdir; written last, so a
# directory without it is an interrupted build.
build_reference() {
    if [ -f "$refdir/ok" ]; then
        refbin=$refdir/$(cat "$refdir/ok")
        [ -x "$refbin" ] && return 0
    fi
    mkdir -p "$cache" || die "cannot create the cache directory $cache"
    log=$cache/$hash.build.log
    echo "building reference $short in $refdir (log: $log)"
    building=$(mktemp -d "$cache/$hash.building.XXXXXX") || die "cannot create a directory in $cache"
    b=$building
    {
        git -C "$top" archive --format=tar -o "$b/src.tar" "$hash" &&
            mkdir "$b/src" && tar -xf "$b/src.tar" -C "$b/src" && rm -f "$b/src.tar"
    } >"$log" 2>&1 || die "git archive $short failed: see $log"
    tests_opt=
    for f in "$b/src/meson_options.txt" "$b/src/meson.options"; do
        [ -f "$f" ] && grep -Eq "option\\(['\"]tests['\"]" "$f" && tests_opt=-Dtests=false
    done
    meson setup ${tests_opt:+"$tests_opt"} "$b/build" "$b/src" >>"$log" 2>&1 ||
        { tail -n 15 "$log" >&2; die "meson setup of $short failed: see $log"; }
    # The driver only ("taper" alone is ambiguous: libtaper is a target too).
    meson compile -C "$b/build" taper:executable >>"$log" 2>&1 ||
        meson compile -C "$b/build" >>"$log" 2>&1 ||
        { tail -n 15 "$log" >&2; die "meson compile of $short failed: see $log"; }
    exe=$(cd "$b" && find build -type f -name taper -perm -u+x | LC_ALL=C sort | head -n 1)
    [ -n "$exe" ] || die "no taper executable in the reference build $b/build: see $log"
    echo "$exe" >"$b/ok"
    if [ -f "$refdir/ok" ]; then
        rm -rf "$b" # built meanwhile by another call: use that one
    else
        rm -rf "$refdir"
        mv "$b" "$refdir" || die "cannot move $b to $refdir"
    fi
    building=
    refbin=$refdir/$exe
}
build_reference

version_of() { "$1" --version 2>/dev/null </dev/null | head -n 1; }
echo "reference: $short, $(version_of "$refbin") ($refbin)"
echo "binary:    $(version_of "$bin") ($bin)"

work=$(mktemp -d "${TMPDIR:-/tmp}/taper-same-results.XXXXXX") || die "cannot create a temporary directory"

# ---- the scene set: the reference's --------------------------------------------
list_scenes() {
    (cd "$1" && for f in share/scenes/*.nml share/scenes/paper/*.nml; do
        [ -f "$f" ] && echo "$f"
    done)
}
list_scenes "$refdir/src" >"$work/scenes.ref"
list_scenes "$top" >"$work/scenes.here"
LC_ALL=C sort "$work/scenes.ref" >"$work/scenes.ref.sorted"
LC_ALL=C sort "$work/scenes.here" >"$work/scenes.here.sorted"
LC_ALL=C comm -13 "$work/scenes.ref.sorted" "$work/scenes.here.sorted" | while IFS= read -r s; do
    echo "note: $s is in this checkout, not at $short: not compared"
done
LC_ALL=C comm -23 "$work/scenes.ref.sorted" "$work/scenes.here.sorted" | while IFS= read -r s; do
    echo "note: $s is at $short, not in this checkout: compared all the same"
done
[ -s "$work/scenes.ref" ] || die "no scene (share/scenes/*.nml) at $short"
echo "scenes:    $(wc -l <"$work/scenes.ref" | tr -d ' ') at $short"
echo

# ---- comparison ---------------------------------------------------------------
# The result files under DIR, relative paths, in the order of the pipeline
# (every granules.tsv, then sweep.tsv, fits.tsv, table.tsv): the first file
# that differs is the most upstream one.
list_results() {
    [ -d "$1" ] || return 0
    (cd "$1" && find . -type f \( -name granules.tsv -o -name sweep.tsv -o -name fits.tsv \
        -o -name table.tsv \) | sed 's|^\./||' | LC_ALL=C sort) >"$1.found"
    for name in granules.tsv sweep.tsv fits.tsv table.tsv; do
        grep -E "(^|/)$name\$" "$1.found"
    done
    rm -f "$1.found"
}

# FILE without its version line: the first line, when it is "# taper VERSION ...",
# becomes a fixed text (so line numbers stay those of the file).
strip_version() {
    sed '1s/^# taper [^ ][^ ]* .*$/# (taper version line: not compared)/' "$1"
}

# The first line number where files A and B differ.
first_diff_line() {
    awk -v other="$2" '
        { if ((getline b < other) <= 0 || b != $0) { print NR; found = 1; exit } }
        END { if (!found) print NR + 1 }' "$1"
}

# From diff -U 0 output: the first hunk's header and at most two lines of
# each side, cut to 150 characters.
excerpt() {
    awk '
        /^@@/ { if (hunk++) exit; print; next }
        hunk && /^-/ && minus++ < 2 { print }
        hunk && /^\+/ && plus++ < 2 { print }' | cut -c 1-150
}

# The column (name from the table header) where line L of A and B differ first.
first_diff_column() {
    awk -v other="$2" -v l="$3" -F '\t' '
        !/^#/ && header == "" { header = $0 }
        NR == l { a = $0; exit }
        END {
            while ((getline b < other) > 0) if (++n == l) break
            if (n != l || a ~ /^#/ || b ~ /^#/ || header == "") exit
            nh = split(header, h, "\t"); na = split(a, x, "\t"); split(b, y, "\t")
            for (i = 1; i <= na; i++) if (x[i] != y[i]) { if (i <= nh) print h[i]; exit }
        }' "$1"
}

same=0
differ=0
i=0
while IFS= read -r scene; do
    i=$((i + 1))
    d=$work/$(printf '%02d' "$i")_$(basename "$scene" .nml)
    mkdir -p "$d/ref" "$d/new"
    (cd "$d/ref" && exec "$refbin" "$refdir/src/$scene" -o out) </dev/null >"$d/ref.stdout" 2>"$d/ref.stderr"
    rc_ref=$?
    (cd "$d/new" && exec "$bin" "$refdir/src/$scene" -o out) </dev/null >"$d/new.stdout" 2>"$d/new.stderr"
    rc_new=$?

    list_results "$d/ref/out" >"$d/files.ref"
    list_results "$d/new/out" >"$d/files.new"
    nfiles=$(wc -l <"$d/files.ref" | tr -d ' ')
    why=
    detail=
    if [ "$rc_ref" != "$rc_new" ]; then
        why="exit status $rc_new, the reference $rc_ref"
    fi
    LC_ALL=C sort "$d/files.ref" >"$d/files.ref.sorted"
    LC_ALL=C sort "$d/files.new" >"$d/files.new.sorted"
    missing=$(LC_ALL=C comm -23 "$d/files.ref.sorted" "$d/files.new.sorted")
    extra=$(LC_ALL=C comm -13 "$d/files.ref.sorted" "$d/files.new.sorted")
    if [ -z "$why" ] && [ -n "$missing" ]; then
        why="$(echo "$missing" | head -n 1) missing ($(echo "$missing" | wc -l | tr -d ' ') of $nfiles files)"
    elif [ -z "$why" ] && [ -n "$extra" ]; then
        why="$(echo "$extra" | head -n 1) written, not by the reference"
    fi
    ndiff=0
    while IFS= read -r f; do
        [ -f "$d/new/out/$f" ] || continue
        strip_version "$d/ref/out/$f" >"$d/a"
        strip_version "$d/new/out/$f" >"$d/b"
        cmp -s "$d/a" "$d/b" && continue
        ndiff=$((ndiff + 1))
        [ "$ndiff" = 1 ] || continue
        line=$(first_diff_line "$d/a" "$d/b")
        col=$(first_diff_column "$d/a" "$d/b" "$line")
        first="$f line $line${col:+ (column $col)}"
        detail=$(diff -U 0 "$d/a" "$d/b" | excerpt)
    done <"$d/files.ref"
    if [ "$ndiff" -gt 0 ]; then
        more=
        [ "$ndiff" -gt 1 ] && more=", $((ndiff - 1)) more differ"
        if [ -z "$why" ]; then why="$first$more"; else why="$why; $first$more"; fi
    fi

    if [ -z "$why" ]; then
        same=$((same + 1))
        note=
        [ "$rc_ref" = 0 ] || note=", both exit $rc_ref"
        files='files'
        [ "$nfiles" = 1 ] && files='file'
        printf 'same   %s (%s %s%s)\n' "$scene" "$nfiles" "$files" "$note"
    else
        differ=$((differ + 1))
        keep_work=1
        printf 'DIFFER %s : %s\n' "$scene" "$why"
        [ -n "$detail" ] && printf '%s\n' "$detail" | sed 's/^/         /'
        printf '         logs: %s/ref.stderr (reference), new.stderr (TAPER_BINARY)\n' "$d"
    fi
done <"$work/scenes.ref"

echo
echo "$same scenes same, $differ differ"
if [ "$differ" -gt 0 ]; then
    echo "outputs kept in $work"
    exit 1
fi
exit 0
