#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""layering.py SOURCE_DIR -- the architecture rules, checked on
every #include of the tree, so that a change that breaks them fails a test
instead of waiting for a reviewer:

1. A library part (src/core, src/settings, src/chain, src/sim, src/analysis)
   includes only taper.h, its own folder's headers, src/core's (the shared
   base) and src/settings/specs.h (the layouts of the specs every part
   reads).
2. Outside src/, nothing includes a header of the library but taper.h,
   except the unit tests (tests/unit), which test internals by design.
3. A private header (*_impl.h, and src/sim/sim.h, the simulation's state) is
   included only by files of its own folder and by unit tests.
4. No two files include each other, directly or through others (no circle
   in the include graph).
5. Nothing under src/ includes a file outside src/: the library never
   reaches up into its callers (drivers/) or the tests.
6. No program under src/: no C file there defines main (build-time
   generators live with what they generate for, in drivers/), and no
   Fortran file is a PROGRAM.
7. drivers/scenes, the scenes' library that the programs and the Python
   package build on, includes nothing of theirs: only its own headers and
   taper.h.
8. The integrators are steppers (src/sim/stepper.h): only the run's loop
   (src/sim/solve.c) and the stepper files (src/sim/stepper.h, the table
   src/sim/steppers.c, src/sim/stepper_*.[ch]) include stepper.h, directly or through another
   header, so that nothing else in the library can ask which one runs.
9. SUNDIALS is the CVODE stepper's own: in src/, only its files include a
   SUNDIALS header (<sundials/...>, <cvode/...>, <nvector/...>, ...),
   directly or through another header: stepper_cvode*.[ch], the window's
   N_Vector (nvector_window.[ch]) and the SUNDIALS compatibility layer it
   uses (sundials_compat.[ch]).  The sim's state (sim.h), the loop and the
   other steppers see no SUNDIALS type.

Quoted includes are resolved as the build does: the including file's folder,
then src/, drivers/scenes, drivers/taper, drivers/bench, tests/ (the include roots of the
meson.build files)."""

import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "."
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
ROOTS = ["src", "drivers/scenes", "drivers/taper", "drivers/bench", "tests", "include"]
PARTS = ["src/core", "src/settings", "src/chain", "src/sim", "src/analysis"]
SHARED = {"src/settings/specs.h"}
PRIVATE = re.compile(r"(_impl\.h$|^src/sim/sim\.h$)")


SYSTEM_INCLUDE = re.compile(r"^\s*#\s*include\s*<([^>]+)>", re.M)
SUNDIALS_HEADER = re.compile(r"^(sundials|cvodes?|arkode|idas?|kinsol|nvector|sunlinsol|sunmatrix|"
                             r"sunnonlinsol|sunmemory|sunadaptcontroller)/")
STEPPER_HEADER = "src/sim/stepper.h"
STEPPER_FILE = re.compile(r"^src/sim/steppers?(_\w+)?\.[ch]$")
LOOP = "src/sim/solve.c"
CVODE_STEPPER_FILE = re.compile(r"^src/sim/(stepper_cvode(_\w+)?|nvector_window|sundials_compat)\.[ch]$")

MAIN = re.compile(r"^\s*int\s+main\s*\(", re.M)
FORTRAN_PROGRAM = re.compile(r"^\s*program\s+\w+", re.M | re.I)


def sources(suffixes=(".c", ".h"), tops=("src", "drivers", "tests")):
    for top in tops:
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if f.endswith(suffixes):
                    yield os.path.relpath(os.path.join(d, f), root)


def resolve(path, name):
    for base in [os.path.dirname(path)] + ROOTS:
        cand = os.path.normpath(os.path.join(base, name))
        if os.path.exists(os.path.join(root, cand)):
            return cand
    return None


graph, sundials, problems = {}, {}, []
for path in sorted(sources()):
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        text = f.read()
    names = INCLUDE.findall(text)
    sundials[path] = [h for h in SYSTEM_INCLUDE.findall(text) if SUNDIALS_HEADER.match(h)]
    graph[path] = []
    for name in names:
        target = resolve(path, name)
        if target is None or target == "include/taper.h":
            continue
        graph[path].append(target)
        here, there = os.path.dirname(path), os.path.dirname(target)
        unit_test = path.startswith("tests/unit/")
        part = next((p for p in PARTS if path.startswith(p + "/")), None)
        if part and there != here and there != "src/core" and target not in SHARED:
            problems.append(f"{path}: includes {target}, a header of another library part")
        if not path.startswith("src/") and target.startswith("src/") and not unit_test:
            problems.append(f"{path}: includes the library's internal {target} (use taper.h)")
        if PRIVATE.search(target) and there != here and not unit_test:
            problems.append(f"{path}: includes {target}, private to {there}")
        if path.startswith("src/") and not target.startswith("src/"):
            problems.append(f"{path}: includes {target}, outside the library's tree")
        if path.startswith("drivers/scenes/") and not target.startswith("drivers/scenes/"):
            problems.append(f"{path}: includes {target}, a caller of the scenes' library")

# The steppers (rules 8 and 9): what each file of src/ reaches through its
# quoted includes, itself included.
def reach(start):
    seen, todo = {start: [start]}, [start]
    while todo:
        node = todo.pop()
        for nxt in graph.get(node, []):
            if nxt not in seen:
                seen[nxt] = seen[node] + [nxt]
                todo.append(nxt)
    return seen


for path in sorted(p for p in graph if p.startswith("src/")):
    reached = reach(path)
    if STEPPER_HEADER in reached and path != LOOP and not STEPPER_FILE.match(path):
        problems.append(f"{path}: includes {STEPPER_HEADER} ("
                        + " -> ".join(reached[STEPPER_HEADER]) + "): only the loop ("
                        f"{LOOP}) and the stepper files drive the steppers")
    if CVODE_STEPPER_FILE.match(path):
        continue
    for node, chain in sorted(reached.items()):
        for header in sundials.get(node, []):
            problems.append(f"{path}: includes SUNDIALS' <{header}> ("
                            + " -> ".join(chain) + "): only the CVODE stepper's files "
                            "(stepper_cvode*, nvector_window, sundials_compat) may")

# Programs: none in the library's tree.
for path in sorted(sources((".c", ".f90", ".F90"), ("src",))):
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        text = f.read()
    if path.endswith(".c") and MAIN.search(text):
        problems.append(f"{path}: a program's main in the library's tree (programs go to drivers/)")
    if not path.endswith(".c") and FORTRAN_PROGRAM.search(text):
        problems.append(f"{path}: a Fortran PROGRAM in the library's tree (programs go to drivers/)")

# Circles: depth-first search over the include graph.
state = {}


def visit(node, stack):
    state[node] = 1
    for nxt in graph.get(node, []):
        if state.get(nxt) == 1:
            problems.append("include circle: " + " -> ".join(stack[stack.index(nxt):] + [nxt])
                            if nxt in stack else f"include circle through {nxt}")
        elif state.get(nxt) is None:
            visit(nxt, stack + [nxt])
    state[node] = 2


for node in graph:
    if state.get(node) is None:
        visit(node, [node])

for p in problems:
    print("FAIL:", p)
print(f"layering: {len(graph)} files, {sum(map(len, graph.values()))} includes, "
      f"{len(problems)} problems")
sys.exit(1 if problems else 0)
