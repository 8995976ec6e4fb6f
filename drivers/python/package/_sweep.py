# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.read_sweep -- a sweep as one table, a row per run: the driver's
per-run summary (DIR/runs.tsv, its footer checked), or the Results of
run_scene() of a sweep."""

from __future__ import annotations

import math
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _core
from ._columns import np
from ._variables import variables
from .result import Result, _unit_of, _verified

__all__ = ["read_sweep", "SweepTable"]

PathLike = Union[str, "os.PathLike[str]"]


class SweepTable(Dict[str, Any]):
    """A sweep's table without pandas: a dict of numpy columns of equal
    length, a row per run, named as the DataFrame of read_sweep() names
    them (``t_final[s]`` in SI), with the DataFrame's ``attrs`` as
    ``attrs`` and its units as ``units``.  ``to_numpy()`` gives a structured
    array."""

    def __init__(self, columns: Mapping[str, Any], attrs: Mapping[str, Any]) -> None:
        super().__init__(columns)
        self.attrs: Dict[str, Any] = dict(attrs)

    @property
    def units(self) -> Dict[str, str]:
        """The unit of each column that has one, by its bare name."""
        return self.attrs["units"]

    def to_numpy(self) -> "np.ndarray":
        dtype = [(c, a.dtype) for c, a in self.items()]
        n = len(next(iter(self.values()))) if self else 0
        out = np.empty(n, dtype=dtype)
        for c, a in self.items():
            out[c] = a
        return out

    def __repr__(self) -> str:
        n = len(next(iter(self.values()))) if self else 0
        return (f"<taper.SweepTable {n} runs over {', '.join(self.attrs['swept'])}: "
                f"{', '.join(self)}>")


def read_sweep(source: Union[PathLike, Sequence[Result]], *, verify: bool = True,
               pandas: Optional[bool] = None) -> Any:
    """A sweep as one table with a row per run.

    ``source`` is the output directory of a sweep run by the driver
    (``taper SCENE -o DIR``: its ``DIR/runs.tsv``, or that file's path), or
    the list of Results ``taper.run_scene(SCENE)`` returned for a sweep.

    The columns: ``run`` (the run's name, ``s=0.1`` or
    ``q=0.05,exponent=2.5``, its directory's), one per swept variable
    (int64 for an integer variable, float64 otherwise), ``status``
    (``complete``, ``untrusted``, ``partial``, ``refused``, ``failed``),
    every statistic of the runs (float64, NaN where a run has none: counts,
    ``t_final``, the conservation errors, the energy budget,
    ``pulse_speed``, the walls'), then from a directory ``cpu_time[s]`` and
    ``message`` (the reason of a run without rows), as runs.tsv has them.
    A column with a unit is named with it in brackets, as in the files
    (``t_final[s]``, ``wall_peak_force_right[N]``, ``pulse_speed[m/s]``).
    From Results the statistics are Result.stats' (those of a wall only
    where a run has the wall), with no CPU time; the values are the same
    doubles.

    With pandas installed (``pandas=None``, or True) a DataFrame, else (or
    ``pandas=False``) a SweepTable, a dict of numpy columns; either has
    ``attrs``: ``units`` (each column's unit by its bare name), ``swept``
    (the swept variables' names), ``source``.

    From a directory, runs.tsv's footer (``# end: rows N, bytes N, crc32
    X``) is checked first, as read_granules checks granules.tsv's: a file
    cut, changed after it was written, or not a runs.tsv of taper raises
    ValueError naming it (``verify=False``: a runs.tsv without footer).
    """
    if isinstance(source, (str, os.PathLike)):
        columns, attrs = _from_directory(os.fspath(source), verify)
    else:
        columns, attrs = _from_results(list(source))
    if pandas is None:
        try:
            import pandas as pd  # noqa: F401
            pandas = True
        except ImportError:
            pandas = False
    if not pandas:
        return SweepTable(columns, attrs)
    import pandas as pd
    df = pd.DataFrame(columns)
    df.attrs.update(attrs)
    return df


# ---- from the driver's files ---------------------------------------------------

def _from_directory(path: str, verify: bool) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    runs = os.path.join(path, "runs.tsv") if os.path.isdir(path) else path
    if not os.path.exists(runs):
        raise ValueError(f"{runs}: no such file: not the output directory of a sweep "
                         "(a single run writes granules.tsv alone: taper.read_granules)")
    if verify:
        data = _verified(runs)
    else:
        with open(runs, "rb") as f:
            data = f.read()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(f"{runs}: not a text file of taper ({e})") from None
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    if not lines:
        raise ValueError(f"{runs}: no header line")
    header = lines[0].split("\t")
    if header[:1] != ["run"] or "status" not in header or header[-1] != "message":
        raise ValueError(f"{runs}: not a runs.tsv of taper: its columns are "
                         f"{', '.join(header[:6])}{', ...' if len(header) > 6 else ''}")
    rows = [line.split("\t") for line in lines[1:]]
    for i, row in enumerate(rows):
        if len(row) != len(header):
            raise ValueError(f"{runs}: row {i + 1} has {len(row)} values, the header "
                             f"{len(header)} names")
    swept = header[1:header.index("status")]
    integer = _integer_variables()
    columns: Dict[str, Any] = {}
    units: Dict[str, str] = {}
    for j, name in enumerate(header):
        cells = [row[j] for row in rows]
        base, unit = _unit_of(name)
        if unit:
            units[base] = unit
        if name in ("run", "status", "message"):
            columns[name] = np.array(cells, dtype=object)
            continue
        try:
            values = np.array([float(c) for c in cells], dtype=np.float64)
        except ValueError as e:
            raise ValueError(f"{runs}: column {name}: {e}") from None
        if name in swept and name in integer:
            values = values.astype(np.int64)
        columns[name] = values
    return columns, {"units": units, "swept": swept, "source": runs}


def _integer_variables() -> set:
    return {v.name for v in variables() if v.type == "integer"}


def _header_order() -> List[str]:
    """Result.stats' names in the order of granules.tsv's header (and so of
    runs.tsv): the library's, the pulse's speed after the energy budget,
    the walls' last."""
    names = [s for s in _core.STATISTICS if s != "complete"]
    walls = [s for s in names if s.startswith("wall_")]
    return [s for s in names if s not in walls] + ["pulse_speed"] + walls


# ---- from run_scene's Results ---------------------------------------------------

def _status(r: Result) -> str:
    if not r.complete:
        return "partial"
    return "untrusted" if r.untrusted else "complete"


def _from_results(results: List[Result]) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    if not results:
        raise ValueError("read_sweep: no Results (give run_scene()'s list for a sweep)")
    for r in results:
        if not isinstance(r, Result) or r._scene is None:
            raise TypeError("read_sweep takes a directory, runs.tsv, or the Results of "
                            f"run_scene() (not {type(r).__name__}, nor a Result read from a file)")
    runs = [_core.scene_swept(r._scene, r._point) for r in results]
    swept = [name for name, _ in runs[0][1]]
    if not swept:
        raise ValueError("read_sweep: these Results are not runs of a sweep (their scene "
                         "sweeps no variable)")
    if any([name for name, _ in vars_] != swept for _, vars_ in runs):
        raise ValueError("read_sweep: the Results are runs of different sweeps")
    integer = _integer_variables()
    columns: Dict[str, Any] = {"run": np.array([name for name, _ in runs], dtype=object)}
    for k, name in enumerate(swept):
        values = np.array([vars_[k][1] for _, vars_ in runs], dtype=np.float64)
        columns[name] = values.astype(np.int64) if name in integer else values
    columns["status"] = np.array([_status(r) for r in results], dtype=object)
    units: Dict[str, str] = {}
    present = {name for r in results for name in r.stats}
    names = [name for name in _header_order() if name in present and not (
        name.startswith("wall_") and all(_missing(r.stats.get(name)) for r in results))]
    # (a wall statistic no run has: granules.tsv writes no line for it)
    for name in names:
        unit = next((r.units[name] for r in results if name in r.units), None)
        label = f"{name}[{unit}]" if unit else name
        if unit:
            units[name] = unit
        columns[label] = np.array([_float(r.stats.get(name)) for r in results],
                                  dtype=np.float64)
    source = results[0].source
    return columns, {"units": units, "swept": swept, "source": source}


def _missing(x: Any) -> bool:
    return x is None or (isinstance(x, float) and math.isnan(x))


def _float(x: Any) -> float:
    return math.nan if x is None else float(x)
