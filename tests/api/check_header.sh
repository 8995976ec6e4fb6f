#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# check_header.sh TAPER.h -- the public header stands alone: it includes
# only standard C headers and names no SUNDIALS or GSL type, so that users
# need neither library's headers (and we may change either without breaking
# the API).
set -eu
header=$1
CC=${CC:-cc}
status=0
# Every header it pulls in (-H lists them on stderr, one per line).
included=$(printf '#include "%s"\n' "$(basename "$header")" |
    "$CC" -x c - -E -H -I "$(dirname "$header")" -o /dev/null 2>&1 | sed -n 's/^\.\+ //p')
bad=$(echo "$included" | grep -Ei '/(gsl|sundials|cvode|nvector|sunmatrix|sunlinsol|sunnonlinsol)[/_]' || true)
if [ -n "$bad" ]; then
    echo "$header includes solver headers:" >&2
    echo "$bad" | sed 's/^/  /' >&2
    status=1
fi
# Types and identifiers of the two libraries, outside comments.
code=$(sed -e 's://.*$::' "$header" | perl -0pe 's:/\*.*?\*/::gs')
hits=$(echo "$code" | grep -nE '\b(gsl_[a-z_]+|GSL_[A-Z_]+|N_Vector|SUNContext|SUNMatrix|SUNLinearSolver|SUNNonlinearSolver|realtype|sunrealtype|sunindextype|booleantype|CV[A-Za-z]+Fn|CVode[A-Za-z]*)\b' || true)
if [ -n "$hits" ]; then
    echo "$header names SUNDIALS or GSL identifiers:" >&2
    echo "$hits" | sed 's/^/  /' >&2
    status=1
fi
[ $status -eq 0 ] && echo "$(basename "$header"): standard headers only, no SUNDIALS or GSL types"
exit $status
