#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""same_results.py TAPER_BINARY [REFERENCE_COMMIT] [--set GROUP.KEY=VALUE]...
[--rtol X] [--ignore NAME]... -- does this taper write the same results as a
reference commit, for every shipped scene?

    python3 tests/regression/same_results.py build/drivers/taper/taper 043b797
    python3 tests/regression/same_results.py build/drivers/taper/taper 043b797 --set "solver.method='rk8'"
    python3 tests/regression/same_results.py build/drivers/taper/taper 043b797 --rtol 1e-9 --ignore root_evals

The reference is built from the git history of this checkout (git archive,
meson setup -Dtests=false, the driver target only), against the same
optimised SUNDIALS as TAPER_BINARY (the sundials_prefix its build directory
was configured with, else the `sundials` folder of that build directory,
when there is one), and cached in $TAPER_REGRESSION_CACHE/HASH (default
${TMPDIR:-/tmp}/taper-regression; a reference built against another SUNDIALS
is another entry).  Every scene of share/scenes/**/*.nml that both trees
have is run by the reference driver (its own copy of the scene) and by
TAPER_BINARY (this checkout's copy: a scene rewritten here, for example to
give its inputs in SI, is compared with what it was), each in a working
directory of its own with `-o out` and every `--set GROUP.KEY=VALUE` given
(the driver's own override, passed to both: another method, tolerance, ...).

Compared: the exit statuses, the set of result files (granules.tsv,
granules.partial.tsv, sweep.tsv, runs.tsv, fits.tsv, table.tsv,
sensors.tsv, walls.tsv, spacetime.tsv), and each file line by line: the
column header exactly, every data row and every "# name = value"
statistics line number by number.  Ignored: the version line, the echo of
the scene (the "# &group ... /" block: a rewritten scene echoes what it
says) and the lines naming the scene file or the output directory.  A
file's footer ("# end: rows N, bytes N, crc32 X", docs/scene.md, "Result
files") is checked against the file (a footer that does not match is a
difference) and not compared: only one side may have it.  A table whose
header gained columns (runs.tsv's per-run statistics) is compared on the
reference's columns, by name, and the added ones are named; so are
statistics lines ("# pulse_speed = ...") a header gained.  runs.tsv's
cpu_time[s], the CPU time each run took, is never compared: it is a
measurement of the machine, not a result.

Each scene gets one line:
    same     every compared line identical as text
    equal    every number equal as a double (the text differs: formatting)
    agree    every number within 1e-12 relative (the largest difference is
             given, and where)
    DIFFER   a difference beyond that, a missing file or another status
and the last line counts them.  `--rtol X` sets the relative difference
that still agrees (1e-12 by default): a change meant to alter results
within the integrator's tolerance is checked at that tolerance.  `--ignore
NAME` (repeatable) leaves out a statistics line or a column of that name
(without its unit), for counters that measure the work rather than the
physics (`root_evals`, `steps`) when a change is meant to alter them; the
ignored names are printed.  A comment line the new file has and the
reference does not (a note a header gained) is named, not a difference.  Exit status 0 when no scene differs, 1
otherwise, 2 for a usage or build error.  Standard library only.
"""

import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zlib

RESULT_FILES = ("granules.tsv", "granules.partial.tsv", "sweep.tsv", "runs.tsv", "fits.tsv",
                "table.tsv", "sensors.tsv", "walls.tsv", "spacetime.tsv")
RTOL = 1e-12
NUMBER = re.compile(r"^[-+]?(\d+\.?\d*([eE][-+]?\d+)?|\.\d+([eE][-+]?\d+)?|nan|inf)$",
                    re.IGNORECASE)


def die(message):
    print(f"same_results.py: {message}", file=sys.stderr)
    sys.exit(2)


def git(top, *args):
    return subprocess.run(["git", "-C", top, *args], check=True, capture_output=True,
                          text=True).stdout.strip()


def sundials_of(binary):
    """The install prefix of the SUNDIALS the binary's build links, or None
    (the system's): the build directory's sundials_prefix, else its own
    `sundials` folder."""
    build = os.path.dirname(os.path.dirname(os.path.dirname(binary)))
    prefix = os.path.join(build, "sundials")
    try:
        with open(os.path.join(build, "meson-info", "intro-buildoptions.json")) as f:
            options = {o["name"]: o["value"] for o in json.load(f)}
        if options.get("sundials") != "system" and options.get("sundials_prefix"):
            prefix = options["sundials_prefix"]
    except (OSError, ValueError, KeyError):
        pass
    return prefix if os.path.exists(os.path.join(prefix, "lib")) else None


def build_reference(top, commit, binary):
    """The reference driver's path, building it once into the cache."""
    try:
        full = git(top, "rev-parse", "--verify", commit + "^{commit}")
    except subprocess.CalledProcessError:
        die(f"'{commit}' is not a commit of {top}")
    cache = os.environ.get("TAPER_REGRESSION_CACHE",
                           os.path.join(os.environ.get("TMPDIR", "/tmp"), "taper-regression"))
    # The same SUNDIALS as the binary under test: another build of it
    # (Debian's, unoptimised) changes the last digits.
    sundials = sundials_of(binary)
    ref = os.path.join(cache, full + ("" if sundials is None else
                                      "-" + re.sub(r"[^\w.-]", "_", sundials.strip("/"))))
    ok = os.path.join(ref, "ok")
    if os.path.exists(ok):
        with open(ok) as f:
            return full, os.path.join(ref, f.read().strip())
    os.makedirs(cache, exist_ok=True)
    work = tempfile.mkdtemp(prefix=full + ".building.", dir=cache)
    log = os.path.join(cache, full + ".build.log")
    print(f"building reference {full[:7]} in {ref} (log: {log})", flush=True)
    with open(log, "w") as out:
        archive = subprocess.run(["git", "-C", top, "archive", "--format=tar", full],
                                 check=True, capture_output=True).stdout
        os.makedirs(os.path.join(work, "src"))
        subprocess.run(["tar", "-xf", "-", "-C", os.path.join(work, "src")], input=archive,
                       check=True)
        setup = ["meson", "setup", "-Dtests=false", os.path.join(work, "build"),
                 os.path.join(work, "src")]
        if sundials is not None:
            setup[2:2] = ["-Dsundials=bundled", "-Dsundials_prefix=" + sundials]
        for cmd in (setup, ["meson", "compile", "-C", os.path.join(work, "build")]):
            if subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT).returncode != 0:
                die(f"{' '.join(cmd[:2])} of {full[:7]} failed: see {log}")
    exe = os.path.join("build", "drivers", "taper", "taper")
    if not os.path.exists(os.path.join(work, exe)):
        die(f"no driver in the reference build {work}: see {log}")
    with open(os.path.join(work, "ok"), "w") as f:
        f.write(exe)
    if os.path.exists(ref):
        shutil.rmtree(ref)
    os.rename(work, ref)
    return full, os.path.join(ref, exe)


def scenes(root):
    found = []
    for d, _, files in os.walk(os.path.join(root, "share", "scenes")):
        found += [os.path.relpath(os.path.join(d, f), root) for f in files if f.endswith(".nml")]
    return sorted(found)


def run(binary, scene, where, overrides):
    os.makedirs(where)
    sets = [a for o in overrides for a in ("--set", o)]
    p = subprocess.run([binary, scene, "-o", "out", *sets], cwd=where, stdin=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return p.returncode, p.stderr


def check_overrides(binaries, scene, overrides):
    """Every override is one the drivers take (their --get reads it back):
    a refused one would fail every scene alike in both, which compares as
    the same."""
    for binary in binaries:
        for o in overrides:
            key = o.split("=", 1)[0]
            p = subprocess.run([binary, scene, "--set", o, "--get", key], stdin=subprocess.DEVNULL,
                               capture_output=True, text=True)
            if p.returncode != 0:
                die(f"{binary} refuses --set {o}: {p.stderr.strip()[-300:]}")


def results(out):
    found = {}
    for d, _, files in os.walk(out):
        for f in files:
            if f in RESULT_FILES:
                found[os.path.relpath(os.path.join(d, f), out)] = os.path.join(d, f)
    return found


FOOTER = re.compile(rb"# end: rows (\d+), bytes (\d+), crc32 ([0-9a-f]{8})\n")


def footer_problem(path):
    """None when the file has no footer or a footer that matches it, else
    what is wrong."""
    with open(path, "rb") as f:
        data = f.read()
    cut = data.rfind(b"\n", 0, len(data) - 1) + 1
    m = FOOTER.fullmatch(data[cut:])
    if not m:
        return None
    body = data[:cut]
    rows = sum(1 for i, line in enumerate(body.split(b"\n")[:-1])
               if i > 0 and line and not line.startswith(b"#"))
    if int(m.group(2)) != len(body) or int(m.group(3), 16) != zlib.crc32(body) or \
            int(m.group(1)) != rows:
        return f"its footer does not match it ({data[cut:].decode().strip()})"
    return None


def compared_lines(path):
    """(line number, text) of the lines compared: no version line, no echo,
    no line naming the scene file or the output directory, no footer."""
    with open(path) as f:
        lines = f.read().splitlines()
    if lines and FOOTER.fullmatch((lines[-1] + "\n").encode()):
        lines = lines[:-1]
    keep, echo = [], False
    for i, line in enumerate(lines, 1):
        body = line[2:] if line.startswith("# ") else None
        if body is not None and re.match(r"&\w+$", body):
            echo = True
        if echo:
            echo = body != "/"
            continue
        if re.match(r"# taper \S+ ", line) or line.startswith("# scene file") or \
                re.match(r"#\s*dir = ", line):
            continue
        if statistic_name(line) in IGNORED:
            continue
        keep.append((i, line))
    return keep


def fields(line):
    if line.startswith("#"):
        m = re.match(r"#\s*(.*?)\s*=\s*(.*)$", line)
        return [m.group(1)] + m.group(2).split() if m else [line]
    return line.split("\t")


def number(text):
    return float(text) if NUMBER.match(text) else None


ADDED = {}  # file -> the columns and statistics it has beyond the reference's
# Columns that measure the machine, not the physics: never compared.
UNCOMPARED = {"cpu_time[s]"}
IGNORED = set()  # names given with --ignore: statistics or columns, without unit
STATISTIC = re.compile(r"#\s*([a-z_0-9]+)(\[[^]]*\])?\s*=\s*\S+$")


def statistic_name(line):
    m = STATISTIC.match(line)
    return m.group(1) if m else None


def is_note(line):
    """A comment line that is neither a statistic nor a "name = value"
    line: prose a header carries (what a column means, how it is
    measured)."""
    return line.startswith("#") and not re.match(r"#\s*\S+\s*=", line)


def common_statistics(la, lb):
    """Both files' lines without the notes only one of them has (prose a
    header gained, lost or reworded) and b's without the statistics lines
    ("# name = value") whose name a does not have; and what was left out:
    the statistics' names and each note's first words."""
    have = {statistic_name(line) for _, line in la} - {None}
    notes_a = {line for _, line in la if is_note(line)}
    notes_b = {line for _, line in lb if is_note(line)}
    left_out = []
    for _, line in la:
        if is_note(line) and line not in notes_b:
            left_out.append("note '" + " ".join(line[1:].split()[:2]) + " ...' reworded or gone")
    la = [(i, line) for i, line in la if not (is_note(line) and line not in notes_b)]
    kept = []
    for i, line in lb:
        name = statistic_name(line)
        if name is not None and name not in have:
            left_out.append(name)
        elif is_note(line) and line not in notes_a:
            left_out.append("note '" + " ".join(line[1:].split()[:2]) + " ...'")
        else:
            kept.append((i, line))
    return la, kept, left_out


def drop_uncompared(lines):
    """The lines of a table without the UNCOMPARED columns (by the header's
    names)."""
    if not lines or lines[0][1].startswith("#"):
        return lines
    header = lines[0][1].split("\t")
    drop = {k for k, name in enumerate(header)
            if name in UNCOMPARED or re.sub(r"\[.*\]$", "", name) in IGNORED}
    if not drop:
        return lines
    out = []
    for i, line in lines:
        cells = line.split("\t")
        if line.startswith("#") or len(cells) != len(header):
            out.append((i, line))
        else:
            out.append((i, "\t".join(c for k, c in enumerate(cells) if k not in drop)))
    return out


def common_columns(la, lb):
    """When b's header line (the first compared line) has a's columns and
    more: both files' lines cut to a's columns, by name, and the names
    added.  Otherwise the lines as they are and no names."""
    if not la or not lb or la[0][1] == lb[0][1] or la[0][1].startswith("#"):
        return la, lb, []
    ha, hb = la[0][1].split("\t"), lb[0][1].split("\t")
    if not set(ha) < set(hb) or len(set(hb)) != len(hb):
        return la, lb, []
    pick = [hb.index(name) for name in ha]
    cut = []
    for i, line in lb:
        cells = line.split("\t")
        if line.startswith("#") or len(cells) != len(hb):
            cut.append((i, line))
        else:
            cut.append((i, "\t".join(cells[k] for k in pick)))
    return la, cut, [name for name in hb if name not in ha]


def compare_file(a, b):
    """('same' | 'equal' | 'agree' | 'differ', largest relative difference,
    where)."""
    for path in (a, b):
        problem = footer_problem(path)
        if problem:
            return "differ", math.inf, problem
    la, lb = compared_lines(a), compared_lines(b)
    header_a = la[0][1].split("\t") if la else []
    added_uncompared = [name for name in (lb[0][1].split("\t") if lb else [])
                        if name in UNCOMPARED and name not in header_a]
    la, lb = drop_uncompared(la), drop_uncompared(lb)
    la, lb, added_statistics = common_statistics(la, lb)
    la, lb, added = common_columns(la, lb)
    added += added_uncompared + added_statistics
    if len(la) != len(lb):
        return "differ", math.inf, f"{len(lb)} lines compared, the reference {len(la)}"
    verdict, worst, where = "same", 0.0, ""
    ADDED[b] = added
    for (i, x), (_, y) in zip(la, lb):
        if x == y:
            continue
        fx, fy = fields(x), fields(y)
        if len(fx) != len(fy):
            return "differ", math.inf, f"line {i}: {y[:80]!r}, the reference {x[:80]!r}"
        for u, v in zip(fx, fy):
            if u == v:
                continue
            nu, nv = number(u), number(v)
            if nu is None or nv is None:
                return "differ", math.inf, f"line {i}: '{v}', the reference '{u}'"
            if nu == nv or (math.isnan(nu) and math.isnan(nv)):
                verdict = "equal" if verdict == "same" else verdict
                continue
            rel = abs(nu - nv) / max(abs(nu), abs(nv))
            if rel > worst:
                worst, where = rel, f"line {i}: {v}, the reference {u}"
            verdict = "agree" if rel <= RTOL else "differ"
            if verdict == "differ":
                return verdict, rel, where
    return verdict, worst, where


def arguments(argv):
    """(binary, commit, overrides) from the command line; --rtol and
    --ignore set RTOL and IGNORED."""
    global RTOL
    positional, overrides = [], []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print("\n".join(__doc__.strip().splitlines()[4:7]))
            sys.exit(0)
        if a in ("--rtol", "--ignore") or a.startswith(("--rtol=", "--ignore=")):
            name, _, value = a.partition("=")
            if not _:
                i += 1
                value = argv[i] if i < len(argv) else ""
            if name == "--rtol":
                try:
                    RTOL = float(value)
                except ValueError:
                    RTOL = math.nan
                if not 0 <= RTOL < 1:
                    die(f"--rtol needs a relative difference in [0, 1), not '{value}'")
            elif not re.fullmatch(r"[a-z_0-9]+", value):
                die(f"--ignore needs a statistic's or column's name without its unit (root_evals), not '{value}'")
            else:
                IGNORED.add(value)
        elif a == "--set" or a.startswith("--set="):
            value = a[len("--set="):] if a.startswith("--set=") else None
            if value is None:
                i += 1
                value = argv[i] if i < len(argv) else ""
            if not re.match(r"\w+\.\w+=", value):
                die(f"--set needs GROUP.KEY=VALUE (--set \"solver.method='rk8'\"), not '{value}'")
            overrides.append(value)
        else:
            positional.append(a)
        i += 1
    if len(positional) not in (1, 2):
        print("\n".join(__doc__.strip().splitlines()[4:7]), file=sys.stderr)
        sys.exit(2)
    return positional[0], positional[1] if len(positional) == 2 else "043b797", overrides


def main():
    given, commit, overrides = arguments(sys.argv[1:])
    binary = os.path.abspath(given)
    if not os.access(binary, os.X_OK):
        die(f"TAPER_BINARY '{given}' is not an executable file")
    top = git(os.path.dirname(os.path.abspath(__file__)), "rev-parse", "--show-toplevel")
    full, refbin = build_reference(top, commit, binary)
    refsrc = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(refbin))))
    refsrc = os.path.join(refsrc, "src")
    common = sorted(set(scenes(refsrc)) & set(scenes(top)))
    for only in sorted(set(scenes(top)) - set(scenes(refsrc))):
        print(f"note: {only} is not at {full[:7]}: not compared")
    if common:
        check_overrides([refbin, binary], os.path.join(top, common[0]), overrides)
    print(f"reference: {full[:7]} ({refbin})\nbinary:    {binary}\nscenes:    {len(common)}")
    print(f"overrides: {' '.join(overrides) if overrides else 'none'}")
    print(f"ignored:   {' '.join(sorted(IGNORED)) if IGNORED else 'none'}\n")
    tally = {"same": 0, "equal": 0, "agree": 0, "differ": 0}
    work = tempfile.mkdtemp(prefix="taper-same-results.")
    keep = False
    for n, scene in enumerate(common):
        d = os.path.join(work, f"{n:02d}")
        rc_ref, _ = run(refbin, os.path.join(refsrc, scene), os.path.join(d, "ref"), overrides)
        rc_new, err = run(binary, os.path.join(top, scene), os.path.join(d, "new"), overrides)
        ra, rb = results(os.path.join(d, "ref", "out")), results(os.path.join(d, "new", "out"))
        verdict, worst, where = "same", 0.0, ""
        if rc_ref != rc_new:
            verdict, where = "differ", f"exit status {rc_new}, the reference {rc_ref}: {err[-200:]}"
        elif set(ra) != set(rb):
            verdict, where = "differ", f"files {sorted(set(ra) ^ set(rb))}"
        else:
            order = {"same": 0, "equal": 1, "agree": 2, "differ": 3}
            for f in sorted(ra):
                v, w, at = compare_file(ra[f], rb[f])
                if order[v] > order[verdict] or (v == verdict and w > worst):
                    verdict, worst, where = v, w, f"{f} {at}" if at else f
                if verdict == "differ":
                    break
        tally[verdict] += 1
        files = f"{len(ra)} file{'s' if len(ra) != 1 else ''}"
        added = sorted({f"{os.path.basename(f)}: {' '.join(ADDED[rb[f]])}"
                        for f in rb if ADDED.get(rb[f])})
        if added:
            files += f"; not compared (added or reworded): {', '.join(added)}"
        if verdict == "same":
            print(f"same     {scene} ({files})")
        elif verdict == "equal":
            print(f"equal    {scene} ({files}; numbers bit for bit, text differs: {where})")
        elif verdict == "agree":
            print(f"agree    {scene} ({files}; at most {worst:.1e} relative: {where})")
        else:
            keep = True
            print(f"DIFFER   {scene}: {where} (outputs in {d})")
    print(f"\n{tally['same']} same, {tally['equal']} equal, {tally['agree']} agree within "
          f"{RTOL:g}, {tally['differ']} differ")
    if not keep:
        shutil.rmtree(work)
    sys.exit(1 if tally["differ"] else 0)


if __name__ == "__main__":
    main()
