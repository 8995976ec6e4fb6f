#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# fortran_binds_all.sh TAPER.h TAPER.f90 -- the Fortran module the build
# wrote (TAPER.f90: gen_module.c from drivers/fortran/module/
# taper_functions.def) binds every function the public header declares (an
# interface with bind(C, name="taper_...")) and no other, so that taper.h
# cannot grow (as the options beyond the paper grew it) without the list,
# and so the module, following.  The header's declarations are listed by the
# C compiler (-aux-info, as tests/api/check_exports.sh does); the C types of
# each row of the list are checked when gen_module.c compiles.
set -eu
header=$1
module=$2
CC=${CC:-cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '#include "%s"\n' "$(basename "$header")" >"$tmp/h.c"
"$CC" -fsyntax-only -aux-info "$tmp/aux" -I "$(dirname "$header")" "$tmp/h.c"
grep 'taper\.h:' "$tmp/aux" | sed -n 's/.*[ *]\([A-Za-z_][A-Za-z0-9_]*\) (.*/\1/p' | sort -u >"$tmp/declared"
grep -io 'name *= *"taper_[a-z0-9_]*"' "$module" | sed 's/.*"\(taper_[a-zA-Z0-9_]*\)"/\1/' | sort -u >"$tmp/bound"
[ -s "$tmp/declared" ] || { echo "no declarations found in $header" >&2; exit 1; }
missing=$(comm -23 "$tmp/declared" "$tmp/bound")
extra=$(comm -13 "$tmp/declared" "$tmp/bound")
status=0
if [ -n "$missing" ]; then
    echo "declared in $(basename "$header") but not bound in $(basename "$module"):" >&2
    echo "$missing" | sed 's/^/  /' >&2
    status=1
fi
if [ -n "$extra" ]; then
    echo "bound in $(basename "$module") but not declared in $(basename "$header"):" >&2
    echo "$extra" | sed 's/^/  /' >&2
    status=1
fi
[ $status -eq 0 ] && echo "$(wc -l <"$tmp/declared") functions of $(basename "$header"), every one bound in $(basename "$module")"
exit $status
