#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# check_exports.sh LIBTAPER.so TAPER.h [SOVERSION] -- the shared library
# exports exactly the functions the public header declares: every dynamic
# symbol it defines is a taper_ function declared in taper.h, and every
# declared function is exported.  Internal helpers (taper_fail, the
# SUNDIALS and GSL glue, the dynamics' internals) must stay hidden.  With
# SOVERSION, the library's SONAME is libtaper.so.SOVERSION.
set -eu
lib=$1
header=$2
soversion=${3:-}
CC=${CC:-cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Exported: defined dynamic symbols (functions and data alike).
nm -D --defined-only "$lib" | awk 'NF >= 3 { print $3 }' | sed 's/@.*//' | sort -u >"$tmp/exported"

# Declared: gcc lists the prototypes of every function the header declares
# (-aux-info); this sees multi-line declarations and ones missing TAPER_API.
printf '#include "%s"\n' "$(basename "$header")" >"$tmp/h.c"
"$CC" -fsyntax-only -aux-info "$tmp/aux" -I "$(dirname "$header")" "$tmp/h.c"
grep 'taper\.h:' "$tmp/aux" | sed -n 's/.*[ *]\([A-Za-z_][A-Za-z0-9_]*\) (.*/\1/p' | sort -u >"$tmp/declared"

status=0
if [ ! -s "$tmp/declared" ]; then
    echo "no function declarations found in $header" >&2
    exit 1
fi
bad=$(grep -v '^taper_' "$tmp/exported" || true)
if [ -n "$bad" ]; then
    echo "exported symbols without the taper_ prefix:" >&2
    echo "$bad" | sed 's/^/  /' >&2
    status=1
fi
extra=$(comm -23 "$tmp/exported" "$tmp/declared")
if [ -n "$extra" ]; then
    echo "exported but not declared in $header (should be hidden):" >&2
    echo "$extra" | sed 's/^/  /' >&2
    status=1
fi
missing=$(comm -13 "$tmp/exported" "$tmp/declared")
if [ -n "$missing" ]; then
    echo "declared in $header but not exported by $lib (missing TAPER_API or definition?):" >&2
    echo "$missing" | sed 's/^/  /' >&2
    status=1
fi
if [ -n "$soversion" ]; then
    soname=$(objdump -p "$lib" | awk '$1 == "SONAME" { print $2 }')
    if [ "$soname" != "libtaper.so.$soversion" ]; then
        echo "SONAME of $lib is '$soname', expected libtaper.so.$soversion" >&2
        status=1
    fi
fi
[ $status -eq 0 ] && echo "$(wc -l <"$tmp/exported") exported symbols = the functions of $(basename "$header")${soversion:+; SONAME libtaper.so.$soversion}"
exit $status
