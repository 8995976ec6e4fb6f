#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# installed_prefix.sh BUILD_DIR SOURCE_DIR -- a real installation, as
# docs/api.md tells a user to make one: a fresh build directory configured
# with `meson setup DIR --prefix=PREFIX` (an empty temporary prefix, the
# same SUNDIALS as BUILD_DIR), `meson install` into it (no --destdir: the
# RUNPATHs name real files), then the build directory is deleted and, with
# a clean environment (no LD_LIBRARY_PATH, no PKG_CONFIG_PATH of ours):
#   1. the installed `taper` runs an installed scene (PREFIX/share/taper/scenes);
#   2. the installed `taper_nml` (if built) runs it too;
#   3. the installed example PREFIX/share/taper/examples/c/pulse.c compiles with
#      `pkg-config --cflags --libs taper` and runs;
# and every one of them loads libtaper and SUNDIALS from under PREFIX (ldd),
# never from the source or build tree.  installed_example.sh checks the
# staged (--destdir) install; this one the installed programs themselves.
# Compiles the library and drivers once more (without tests): ~1 min.
set -eu
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
CC=${CC:-cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
fresh=$tmp/build

# The SUNDIALS of BUILD_DIR: the same choice, the same bundled build.
options=$(meson introspect --buildoptions "$build")
option() {
    printf '%s' "$options" | python3 -c 'import json, sys
print(next((str(o["value"]) for o in json.load(sys.stdin) if o["name"] == sys.argv[1]), ""))' "$1"
}
sundials=$(option sundials)
sundials_prefix=$(option sundials_prefix)
if [ -z "$sundials_prefix" ]; then
    sundials_prefix=$build/sundials
    [ "$sundials" != build ] || sundials_prefix=$build/sundials-static
fi
args="-Dsundials=$sundials"
# (-Dsundials=build: its prefix again, whose stamp spares a second SUNDIALS build.)
if [ "$sundials" = build ] || { [ "$sundials" != system ] && [ -e "$sundials_prefix/lib/libsundials_cvode.so" ]; }; then
    args="$args -Dsundials_prefix=$sundials_prefix"
elif [ "$sundials" = auto ]; then
    sundials=system     # auto without a bundled build links the system SUNDIALS
fi

# shellcheck disable=SC2086
if ! meson setup "$fresh" "$src" --prefix="$prefix" -Dtests=false -Dpython=disabled \
        -Dmpi=disabled $args >"$tmp/setup.log" 2>&1 ||
   ! meson compile -C "$fresh" >"$tmp/compile.log" 2>&1 ||
   ! meson install -C "$fresh" --no-rebuild --quiet >"$tmp/install.log" 2>&1; then
    cat "$tmp/setup.log" "$tmp/compile.log" "$tmp/install.log" 2>/dev/null | tail -n 40 >&2
    echo "FAIL: meson setup --prefix / compile / install into a fresh prefix" >&2
    exit 1
fi
rm -rf "$fresh"     # an installation must not need its build directory

clean_env() { env -i PATH=/usr/bin:/bin HOME="$tmp" "$@"; }
fail=0
# Every library a program loads resolves, and libtaper and SUNDIALS come from PREFIX.
loads_from_prefix() { # PROGRAM
    clean_env ldd "$1" >"$tmp/ldd" 2>&1 || :
    if grep -q "not found" "$tmp/ldd"; then
        echo "FAIL: $1 misses libraries:" >&2; grep "not found" "$tmp/ldd" >&2; fail=1
    fi
    for lib in libtaper.so libsundials_cvode.so; do
        where=$(awk -v l="$lib" 'index($1, l) == 1 { print $3 }' "$tmp/ldd")
        [ -n "$where" ] || continue      # taper_nml may reach SUNDIALS through libtaper only
        case $where in
            "$prefix"/*) ;;
            /usr/lib/*|/lib/*) [ "$lib" = libsundials_cvode.so ] && [ "$sundials" = system ] ||
                { echo "FAIL: $1 loads $lib from $where, not from $prefix" >&2; fail=1; } ;;
            *) echo "FAIL: $1 loads $lib from $where, not from $prefix" >&2; fail=1 ;;
        esac
    done
}

scene=$prefix/share/taper/scenes/default.nml
[ -f "$scene" ] || { echo "FAIL: $scene not installed" >&2; exit 1; }
taper=$prefix/bin/taper
[ -x "$taper" ] || { echo "FAIL: $taper not installed" >&2; exit 1; }
loads_from_prefix "$taper"

# 1. The installed driver on an installed scene.
status=0
clean_env "$taper" "$scene" -o "$tmp/out" >"$tmp/taper.out" 2>"$tmp/taper.err" || status=$?
if [ "$status" -ne 0 ] || [ ! -s "$tmp/out/granules.tsv" ]; then
    echo "FAIL: installed taper on $scene: exit $status" >&2; cat "$tmp/taper.err" >&2; fail=1
else
    rows=$(grep -vc '^#' "$tmp/out/granules.tsv" || :)
    grep -q '^# complete' "$tmp/out/granules.tsv" ||
        { echo "FAIL: installed taper: granules.tsv is not a complete run" >&2; fail=1; }
    echo "installed taper ran $(basename "$scene"): $rows lines in granules.tsv"
fi

# 2. The installed Fortran driver, where it was built.
if [ -x "$prefix/bin/taper_nml" ]; then
    loads_from_prefix "$prefix/bin/taper_nml"
    status=0
    (cd "$tmp" && clean_env "$prefix/bin/taper_nml" "$scene" >"$tmp/nml.out" 2>"$tmp/nml.err") ||
        status=$?
    if [ "$status" -ne 0 ] || ! grep -q 'complete T' "$tmp/nml.out"; then
        echo "FAIL: installed taper_nml on $scene: exit $status" >&2; cat "$tmp/nml.err" >&2; fail=1
    else
        echo "installed taper_nml ran $(basename "$scene")"
    fi
fi

# 3. The installed example, built as docs/api.md says, run without LD_LIBRARY_PATH.
example=$prefix/share/taper/examples/c/pulse.c
pc=$(find "$prefix" -name taper.pc | head -n 1)
if [ ! -f "$example" ] || [ -z "$pc" ]; then
    echo "FAIL: the example ($example) or taper.pc is not installed" >&2
    exit 1
fi
pcdir=$(dirname "$pc")
libdir=$(PKG_CONFIG_PATH=$pcdir pkg-config --variable=libdir taper)
# shellcheck disable=SC2046
if ! "$CC" -std=c11 -Wall -Wextra -Werror -o "$tmp/pulse" "$example" \
        $(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs taper) -Wl,-rpath,"$libdir" -lm; then
    echo "FAIL: the installed example does not compile with pkg-config" >&2
    exit 1
fi
loads_from_prefix "$tmp/pulse"
status=0
clean_env "$tmp/pulse" >"$tmp/pulse.out" 2>"$tmp/pulse.err" || status=$?
if [ "$status" -ne 0 ] || ! grep -Eq '^#   complete += 1' "$tmp/pulse.out"; then
    echo "FAIL: the installed example: exit $status" >&2; cat "$tmp/pulse.err" >&2; fail=1
else
    echo "installed example ran against $(readlink -f "$libdir/libtaper.so")"
fi
[ "$fail" -eq 0 ] || exit 1
echo "real install into $prefix: taper, taper_nml and the example run from it alone"
