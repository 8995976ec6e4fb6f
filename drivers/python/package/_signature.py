# SPDX-License-Identifier: GPL-3.0-or-later
"""The keywords of simulate(), theory() and chain() as Python sees them:
their signatures (inspect.signature, help(), Jupyter's completion) and the
parameter lines of their docstrings, made from the scene's own table
(taper.variables(), the rows ``taper --defaults`` prints) when the package
is imported, and the same parameters in the type stub ``__init__.pyi``,
written when the package is built (drivers/python/gen_stub.py).  Nothing
here lists a variable but those a call cannot use, below.

Every function takes the table as ``_core.variables()`` returns it (a
tuple of dicts), so that the build can call them before the package
exists."""

from __future__ import annotations

#: The scene variables that make no sense for one run in Python, each with
#: the reason (docs/python.md, "Keywords are the scene's variables"): whole
#: groups, and single variables.  A call refuses them with a TypeError
#: saying why; a scene file given to taper.run_scene may hold them.
DRIVER_ONLY_GROUPS = {
    "fit": "&fit is the driver's fit of every run, written to fits.tsv: fit a Result's "
           "columns with taper.fit()",
    "table": "&table tabulates a fitted parameter over the runs of a sweep (table.tsv); a "
             "call runs one chain",
    "figure": "&figure is the driver's gnuplot figure (figure.gp, figure.png): taper.plot() "
              "draws Results",
    "sweep": "&sweep says how the lists of a sweep combine; a call runs one chain (a sweep is "
             "taper.run_scene's, or a loop of calls)",
    "calibrate": "&calibrate fits settings to measurements over many runs: taper.calibrate() "
                 "takes it",
    "design": "&design optimises a result over many runs: taper.design() takes it",
}
DRIVER_ONLY_NAMES = {
    "dir": "&output dir is the driver's output directory; simulate() writes no files",
    "threads": "&output threads is how many runs of a sweep the driver computes at once; a "
               "call runs one chain (threads of your own can run calls in parallel)",
    "granules": "&sensors granules chooses the granules of the driver's sensors.tsv; "
                "Result.samples holds every granule",
    "spacetime": "&sensors spacetime draws the driver's space-time picture (spacetime.tsv, "
                 ".png); Result.samples holds v(k, t) of every granule",
    "spacetime_granules": "it thins the driver's space-time picture; Result.samples holds every "
                          "granule",
    "spacetime_times": "it thins the driver's space-time picture; Result.samples holds every "
                       "sample",
}

#: Python types by the table's type words.
_TYPES = {"real": "float", "integer": "int", "logical": "bool", "string": "str",
          "choice": "str", "real list": "Sequence[float]"}
#: What progress also takes in Python: a callable, called during the run.
PROGRESS_CALLABLE = "Callable[[int, int, float, float], object]"


def driver_only(rows) -> dict:
    """{name: reason} of the variables a call does not take."""
    out = {}
    for row in rows:
        reason = DRIVER_ONLY_NAMES.get(row["name"]) or DRIVER_ONLY_GROUPS.get(row["group"])
        if reason:
            out[row["name"]] = reason
    return out


_DRIVER_ONLY_NAMES = None


def driver_only_names() -> frozenset:
    """The names of driver_only() of the package's own table (once)."""
    global _DRIVER_ONLY_NAMES
    if _DRIVER_ONLY_NAMES is None:
        _DRIVER_ONLY_NAMES = frozenset(driver_only(_table()))
    return _DRIVER_ONLY_NAMES


def keyword_rows(rows, func: str) -> list:
    """The rows that are keywords of `func` ("simulate", "theory",
    "chain"), in the table's order: every variable but the driver's own;
    theory() has no numerics (it is the scene without them)."""
    skip = driver_only(rows)
    return [r for r in rows if r["name"] not in skip
            and not (func == "theory" and r["name"] == "numerics")]


def annotation_text(row) -> str:
    """The parameter's type as a stub writes it: None in it where the
    variable has no default."""
    text = _TYPES[row["type"]]
    if row["name"] == "progress":
        text = f"bool | {PROGRESS_CALLABLE}"
    return f"{text} | None" if row["default"] is None else text


def _annotation(row):
    """The same as a runtime object (no typing import: builtin types, the
    abc generics, X | None)."""
    from collections.abc import Callable, Sequence
    base = {"real": float, "integer": int, "logical": bool, "string": str, "choice": str,
            "real list": Sequence[float]}[row["type"]]
    if row["name"] == "progress":
        base = bool | Callable[[int, int, float, float], object]
    return base | None if row["default"] is None else base


def signature(rows, func: str, returns):
    """inspect.Signature of `func`: every keyword keyword-only, with its
    default (None where the variable has none) and type."""
    import inspect
    kw = inspect.Parameter.KEYWORD_ONLY
    return inspect.Signature(
        [inspect.Parameter(r["name"], kw, default=r["default"], annotation=_annotation(r))
         for r in keyword_rows(rows, func)],
        return_annotation=returns)


def _wrap(text: str, indent: str, width: int = 79) -> list:
    """text in lines of at most `width` characters, each after `indent`."""
    lines, line = [], ""
    for word in text.split():
        if line and len(indent) + len(line) + 1 + len(word) > width:
            lines.append(indent + line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    if line:
        lines.append(indent + line)
    return lines


def parameter_doc(rows, func: str) -> str:
    """The docstring's list of the keywords, by group: name, type, default,
    SI unit (with &material), then the table's description."""
    lines, group = [], None
    for r in keyword_rows(rows, func):
        if r["group"] != group:
            group = r["group"]
            lines += ["", f"    &{group}"]
        head = f"{r['name']}: {annotation_text(r)} = {r['default']!r}"
        if r["unit"]:
            head += f"  [{r['unit']} with &material]"
        lines.append("      " + head)
        description = r["description"]
        if r["name"] == "progress":
            description = ("a bar on stderr, when it is a terminal or a notebook, for a run that "
                           "lasts over half a second (tqdm when installed, else one line); False: "
                           "none; a callable: called with (granules passed, target granule, t, "
                           "granules per second) every 0.1 s of the run and once at its end (the "
                           "driver: " + description + ")")
        lines += _wrap(description, "          ")
    return "\n".join(lines)


def refuse_driver_only(func: str, keywords) -> None:
    """TypeError for the first keyword of `keywords` that the call does not
    take because it is the driver's own, saying why."""
    reasons = driver_only(_table())
    for name in keywords:
        if name in reasons:
            raise TypeError(f"{func}() does not take {name}: {reasons[name]} "
                            f"(docs/python.md, \"Keywords are the scene's variables\")")


def _table():
    from . import _core
    return _core.variables()
