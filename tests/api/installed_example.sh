#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# installed_example.sh BUILD_DIR SOURCE_DIR -- a user's view of libtaper:
# `meson install` into a temporary root, then every C example of
# share/examples/c (and, with gfortran, every Fortran one of
# share/examples/fortran, with the installed module sources) is compiled
# with nothing but the line its comment gives (`pkg-config ... taper` from
# there) and run against the installed libtaper.so (never the build tree's).  Checks the
# installed files, the versioned soname (libtaper.so.MAJOR: meson.build derives
# the soversion from the major version) and the example's output: the table close to the theory
# and the run's statistics, every one by its library name.
set -eu
build=$1
src=$2
CC=${CC:-cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
root=$tmp/root

meson install -C "$build" --no-rebuild --quiet --destdir "$root" >"$tmp/install.log" 2>&1 || {
    cat "$tmp/install.log" >&2
    exit 1
}
# An install says nothing it should not (Meson warns, for example, when it
# copies a symlink as its target).
if grep -i 'warning' "$tmp/install.log" >&2; then
    echo "meson install warns (above)" >&2
    exit 1
fi

pc=$(find "$root" -name taper.pc | head -n 1)
[ -n "$pc" ] || { echo "taper.pc was not installed" >&2; exit 1; }
# The .pc file names the final prefix; relocate it into the staging root.
prefix=$(sed -n 's/^prefix=//p' "$pc")
export PKG_CONFIG_PATH="$(dirname "$pc")"
export PKG_CONFIG_SYSROOT_DIR=
PC="pkg-config --define-variable=prefix=$root$prefix"
$PC --exists taper || { echo "pkg-config cannot use $pc" >&2; exit 1; }
version=$($PC --modversion taper)
libdir=$($PC --variable=libdir taper)
includedir=$($PC --variable=includedir taper)

fail=0
for h in taper.h taper_version.h; do
    [ -f "$includedir/$h" ] || { echo "$h not installed in $includedir" >&2; fail=1; }
done
soversion=${version%%.*}
for f in libtaper.so "libtaper.so.$soversion" "libtaper.so.$version"; do
    [ -e "$libdir/$f" ] || { echo "$libdir/$f not installed" >&2; fail=1; }
done
soname=$(objdump -p "$libdir/libtaper.so" | awk '$1 == "SONAME" { print $2 }')
[ "$soname" = "libtaper.so.$soversion" ] ||
    { echo "soname is '$soname', expected libtaper.so.$soversion" >&2; fail=1; }
[ $fail -eq 0 ] || exit 1

# Scenes, docs and the example are installed (docs/api.md).
datadir=$root$prefix/share/taper
for f in scenes/default.nml scenes/paper docs/scene.md docs/api.md examples/c/pulse.c \
    examples/fortran examples/python; do
    [ -e "$datadir/$f" ] || { echo "$datadir/$f not installed" >&2; fail=1; }
done
# libtaper finds the SUNDIALS it was built with: the bundled build is
# installed next to it and named by its RUNPATH (a destdir install keeps the
# final path: checked as text, the files under the staging root).
runpath=$(objdump -p "$libdir/libtaper.so" | awk '$1 == "RUNPATH" { print $2 }')
if [ -d "$build/sundials/lib" ] && [ ! -f "$build/sundials/fallback" ] &&
   grep -q "sundials: bundled" "$build/meson-logs/meson-log.txt" 2> /dev/null; then
    case $runpath in
        "$prefix"/*/taper/sundials) ;;
        *) echo "libtaper's RUNPATH is '$runpath', not PREFIX/LIBDIR/taper/sundials" >&2; fail=1 ;;
    esac
    for need in $(objdump -p "$libdir/libtaper.so" | awk '$1 == "NEEDED" && $2 ~ /sundials/ { print $2 }'); do
        [ -f "$root$runpath/$need" ] || { echo "$need not installed in $runpath" >&2; fail=1; }
    done
fi
[ $fail -eq 0 ] || exit 1

# Each example as its own comment says to build it (the lines after "Build
# against an installed libtaper", joined at their backslashes), word for word
# but for pkg-config, which here reads the staging root's taper.pc: with the
# rpath the line gives, it runs without LD_LIBRARY_PATH.  The installed copy
# is built, in a folder of its own.
pkg_config_staged() { $PC "$@"; }
sundials_path=${runpath:+$root$runpath}
examples=$root$prefix/share/taper/examples
# (Fortran: where gfortran is there and the build installed the module's sources.)
compilers="cc"
if command -v gfortran >/dev/null 2>&1 && [ -f "$root$prefix/share/taper/fortran/taper.f90" ]; then
    compilers="cc gfortran"
fi
for file in "$examples"/c/*.c "$examples"/fortran/*.f90; do
    name=$(basename "$file"); example=${name%.*}
    case $name in *.c) compiler=cc ;; *) compiler=gfortran ;; esac
    case " $compilers " in *" $compiler "*) ;; *) echo "$name: no $compiler, not built"; continue ;; esac
    line=$(awk '/Build against an installed libtaper/ { on = 1; next }
                on && /^( \*|!)/ { sub(/^( \*|!) */, ""); print; next }
                on { exit }' "$file" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' | grep "^$compiler ")
    [ -n "$line" ] || { echo "$name: no build line in its comment" >&2; exit 1; }
    mkdir "$tmp/$example"
    cp "$file" "$tmp/$example/"
    line=$(printf '%s\n' "$line" | sed 's/pkg-config/pkg_config_staged/g')
    (cd "$tmp/$example" && eval "$line") || { echo "$name: its build line failed: $line" >&2; exit 1; }
    env -u LD_LIBRARY_PATH ${sundials_path:+LD_LIBRARY_PATH=$sundials_path} "$tmp/$example/$example" \
        >"$tmp/$example.out" || { echo "$example: did not run as built by its comment" >&2; exit 1; }
    echo "$name: built by its comment's line and ran"
done
cp "$tmp/pulse.out" "$tmp/out"

# It ran against the installed library...
env -u LD_LIBRARY_PATH ldd "$tmp/pulse/pulse" | grep -q "$libdir/libtaper.so.$soversion" || {
    echo "pulse did not load $libdir/libtaper.so.$soversion:" >&2
    ldd "$tmp/pulse/pulse" >&2
    exit 1
}
# ...and printed the whole table with numerics close to the theory, and the
# statistics of a complete run.
awk -v version="$version" '
    /^# libtaper/ { if ($3 != version ":") { print "version " $3 " != " version; bad = 1 } }
    /^# Final statistics/ { in_stats = 1; next }
    in_stats && /^#   [a-z_]+ += / { stats++; value[$2] = $4 }
    !/^#/ { rows++; rel = ($2 - $3) / $3; if (rel < 0) rel = -rel
            if (rel > 0.05) { print "k = " $1 ": t_pass " $2 " vs theory " $3; bad = 1 }
            if (!($4 > 0 && $4 <= 1)) { print "k = " $1 ": v_peak " $4; bad = 1 } }
    END { if (rows < 10) { print rows " rows"; bad = 1 }
          if (stats < 14) { print stats " statistics"; bad = 1 }
          if (value["complete"] != 1 || !(value["steps"] > 0) || !(value["energy_error"] < 1e-6)) {
              print "statistics: complete " value["complete"] ", steps " value["steps"] \
                    ", energy_error " value["energy_error"]; bad = 1 }
          exit bad }' "$tmp/out" >&2
echo "installed examples OK (libtaper $version from $root$prefix)"
