#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""cite.py TAPER SOURCE_DIR -- `taper --cite` prints valid BibTeX naming what
the runs use: the paper always (journal reference and arXiv number), SUNDIALS
only where CVODE integrates, GSL where the theory, rk8 or a fit runs, the
contact models' papers where a scene switches them on; one list for several
scenes; bad input refused with status 2.  CITATION.cff and the taper entry
name the same version and year.  Standard library only."""

import re
import subprocess
import sys

taper, source = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


# Fields an entry of each type needs (BibTeX's standard styles).
REQUIRED = {"article": {"author", "title", "journal", "year"},
            "book": {"author", "title", "publisher", "year"},
            "misc": {"title"}}
ENTRY = re.compile(r"@(\w+)\s*\{\s*([^,\s]+)\s*,")


def parse_bibtex(text):
    """{key: (type, {field: value})}; raises ValueError on malformed input:
    unbalanced braces, a field without '= {value}', a duplicate key, text
    other than comments between entries."""
    entries, i = {}, 0
    while True:
        at = text.find("@", i)
        between = text[i:] if at < 0 else text[i:at]
        for line in between.splitlines():
            if line.strip() and not line.lstrip().startswith("%"):
                raise ValueError(f"stray text between entries: {line!r}")
        if at < 0:
            return entries
        m = ENTRY.match(text, at)
        if not m:
            raise ValueError(f"malformed entry head at {text[at:at + 40]!r}")
        kind, key = m.group(1).lower(), m.group(2)
        if key in entries:
            raise ValueError(f"duplicate key {key}")
        depth, j = 1, text.index("{", at) + 1
        while depth:
            if j >= len(text):
                raise ValueError(f"{key}: unbalanced braces")
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        body = text[m.end():j - 1]
        fields = {}
        for f in re.finditer(r"\s*(\w+)\s*=\s*\{", body):
            depth, k = 1, f.end()
            while depth:
                depth += {"{": 1, "}": -1}.get(body[k], 0)
                k += 1
            fields[f.group(1).lower()] = body[f.end():k - 1]
        rest = re.sub(r"\s*\w+\s*=\s*\{(?:[^{}]|\{(?:[^{}]|\{[^{}]*\})*\})*\}\s*,?", "", body)
        if rest.strip():
            raise ValueError(f"{key}: unreadable fields {rest.strip()!r}")
        missing = REQUIRED.get(kind, set()) - set(fields)
        if missing:
            raise ValueError(f"{key}: @{kind} without {sorted(missing)}")
        entries[key] = (kind, fields)
        i = j


def cite(*args):
    p = subprocess.run([taper, *args, "--cite"], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def keys(*args):
    rc, out, err = cite(*args)
    check(rc == 0, f"taper {' '.join(args)} --cite: status {rc} ({err.strip()})")
    try:
        return parse_bibtex(out)
    except ValueError as e:
        check(False, f"taper {' '.join(args)} --cite: invalid BibTeX: {e}")
        return {}


SUNDIALS = {"gardner2022sundials", "hindmarsh2005sundials"}

# The default scene: CVODE integrates, the theory describes the chain.
default = keys()
check({"taper", "harbola2009tapered", "galassi2009gsl"} | SUNDIALS <= set(default),
      f"default: {sorted(default)}")
paper = default.get("harbola2009tapered", ("", {}))[1]
check(paper.get("journal") == "Physical Review E" and paper.get("volume") == "80"
      and paper.get("pages") == "031303" and paper.get("eprint") == "0905.4512",
      f"the paper's record: {paper}")
check(not {"prince1981high", "kuwabara1987restitution", "nesterenko2001dynamics"} & set(default),
      f"default cites a model it does not use: {sorted(default)}")

# rk8: GSL's rk8pd, no SUNDIALS.
rk8 = keys("solver.method='rk8'")
check(not SUNDIALS & set(rk8) and {"galassi2009gsl", "prince1981high"} <= set(rk8),
      f"rk8: {sorted(rk8)}")
# BDF is CVODE too.
check(SUNDIALS <= set(keys("solver.method='bdf'")), "bdf without SUNDIALS")
# The theory alone: GSL, no SUNDIALS.
theory = keys("solver.numerics=.false.")
check(not SUNDIALS & set(theory) and "galassi2009gsl" in theory, f"theory only: {sorted(theory)}")
# Damping: Kuwabara-Kono; the theory does not describe a damped chain and
# CVODE runs: no GSL.
damped = keys("losses.damping=0.1")
check({"kuwabara1987restitution", "brilliantov1996model"} <= set(damped)
      and "galassi2009gsl" not in damped, f"damping: {sorted(damped)}")
# A load: Nesterenko's book.
check("nesterenko2001dynamics" in keys("chain.load=1"), "load without Nesterenko")
# A decorated chain whose theory applies: the effective chain's paper.
decorated = keys(f"{source}/share/scenes/physics/decorated.nml")
check("harbola2009decorated" in decorated, f"decorated: {sorted(decorated)}")
# Several scenes: one list, each work once (parse_bibtex refuses duplicates).
both = keys(f"{source}/share/scenes/physics/damped.nml",
            f"{source}/share/scenes/physics/precompressed.nml")
check({"kuwabara1987restitution", "nesterenko2001dynamics"} <= set(both),
      f"two scenes: {sorted(both)}")

# Bad input: status 2, the key named, nothing on standard output.
rc, out, err = cite("chain.n_granules=1")
check(rc == 2 and "n_granules" in err and not out, f"bad override: {rc} {out!r} {err!r}")
rc, out, err = cite(f"{source}/no/such/scene.nml")
check(rc == 2 and not out, f"missing scene: {rc} {out!r}")

# CITATION.cff and `taper --cite` name one version and year.
cff = open(f"{source}/CITATION.cff").read()
version = subprocess.run([taper, "--version"], capture_output=True, text=True).stdout.split()[-1]
cff_version = re.search(r"^version:\s*(\S+)", cff, re.M).group(1)
cff_year = re.search(r"^date-released:\s*\"?(\d{4})", cff, re.M).group(1)
entry = default.get("taper", ("", {}))[1]
check(cff_version == version and version in entry.get("note", ""),
      f"versions: CITATION.cff {cff_version}, taper {version}, entry {entry.get('note')}")
check(entry.get("year") == cff_year, f"years: CITATION.cff {cff_year}, entry {entry.get('year')}")

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
