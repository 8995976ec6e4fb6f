#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# scene_agree.sh TAPER_NML SCENE_DUMP SCENES_DIR -- every shipped scene is a
# real Fortran namelist: gfortran's namelist READ (taper_nml --dump) and our
# C parser (scene_dump) resolve it to the same values, bit for bit (see the
# canonical form in tests/bindings/scene_dump.c), in every group: &chain, &solver,
# &output, the analysis groups &fit, &table, &figure of the paper scenes, and
# the groups beyond the paper (&ends, &striker, &losses, &material, &sensors) and
# &chain's pattern, disorder, seed (a list: its first), load and radii_file
# (resolved against the scene's folder, its radii read) of the physics scenes.
# Also checks that both list the same variables, so a variable (or a group)
# added to drivers/scenes/scene/scene.c's table without the Fortran driver learning it fails
# here.
set -eu
fortran=$1
cdump=$2
dir=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
n=0
fail=0
for scene in "$dir"/*.nml "$dir"/paper/*.nml "$dir"/physics/*.nml "$dir"/optimise/*.nml; do
    [ -f "$scene" ] || continue
    n=$((n + 1))
    if ! "$cdump" "$scene" >"$tmp/c" 2>"$tmp/c.err"; then
        echo "C parser rejects $scene:" >&2; cat "$tmp/c.err" >&2; fail=1; continue
    fi
    if ! "$fortran" --dump "$scene" >"$tmp/f" 2>"$tmp/f.err"; then
        echo "gfortran's namelist READ rejects $scene:" >&2; cat "$tmp/f.err" >&2; fail=1; continue
    fi
    if ! diff "$tmp/c" "$tmp/f" >"$tmp/diff"; then
        echo "$scene: C parser (<) and gfortran (>) disagree:" >&2
        cat "$tmp/diff" >&2
        fail=1
    fi
done
[ $n -gt 0 ] || { echo "no scenes in $dir" >&2; exit 1; }
[ $fail -eq 0 ] && echo "$n scenes: gfortran's namelist READ and the C parser agree on every value"
exit $fail
