"""taper.result -- the result of a run: per-granule numpy columns named as in
granules.tsv, the run's statistics, its status; and read_granules, which
reads a granules.tsv (or sweep.tsv) written by the driver back as the same
type."""

from __future__ import annotations

import math
import os
from typing import Any, Dict, List, Mapping, Optional, Union

import numpy as np

from . import _core
from ._columns import Columns

__all__ = ["Result", "read_granules", "COLUMNS", "THEORY_COLUMNS"]

#: The columns of granules.tsv, in order (README, "What you get").
COLUMNS = ("k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
           "theory_v", "theory_T", "theory_t")
#: The columns of taper.theory(): the chain and the binary collision theory.
THEORY_COLUMNS = ("k", "R", "m", "X0", "theory_v", "theory_T", "theory_t")

PathLike = Union[str, "os.PathLike[str]"]


class Result(Columns):
    """One chain's per-granule columns and what the run reported.

    Columns are numpy arrays of length N, granule k at index k-1: ``k``
    (int64) and float64 ``R m X0 t_pass T_res v_peak t_peak X_pass theory_v
    theory_T theory_t`` (those of the run that exist: ``taper.theory()``
    has no ``t_pass ... X_pass``).  NaN marks a value that does not exist.
    Read them as attributes (``r.v_peak``) or items (``r["v_peak"]``).

    Attributes:
        stats: the run's statistics by their library names (``steps``,
            ``rhs_evals``, ..., ``energy_error``, ``momentum_error``,
            ``complete``); empty for the theory alone.
        settings: the resolved settings of the run (every default filled in),
            by scene variable name.
        complete: True when every requested observable is known.
        status: ``"ok"``, or why the run ended early: ``"solver"`` (the
            integrator failed), ``"limit"`` (t_max or max_steps reached).
        message: the library's message for a partial run, else "".
        warnings: the library's warnings during the run (nothing is printed).
        x_final, v_final: displacements and velocities where the run ended
            (None when the result was read from a file or is theory only).
        source: where the result came from ("simulate", "theory", a scene or
            a granules.tsv path).
    """

    def __init__(self, columns: Mapping[str, np.ndarray], *, stats: Optional[Dict[str, Any]] = None,
                 settings: Optional[Dict[str, Any]] = None, status: str = "ok", message: str = "",
                 warnings: Optional[List[str]] = None, x_final: Optional[np.ndarray] = None,
                 v_final: Optional[np.ndarray] = None, source: str = "",
                 complete: Optional[bool] = None,
                 samples: Optional[Dict[str, np.ndarray]] = None) -> None:
        ordered = [c for c in COLUMNS if c in columns] + [c for c in columns if c not in COLUMNS]
        self._columns: Dict[str, np.ndarray] = {c: columns[c] for c in ordered}
        self.stats: Dict[str, Any] = dict(stats or {})
        self.settings: Dict[str, Any] = dict(settings or {})
        self.status = status
        self.message = message
        self.warnings: List[str] = list(warnings or [])
        self.x_final = x_final
        self.v_final = v_final
        #: simulate(sample_interval=dt): {"t": (S,), "x": (S, N), "v": (S, N),
        #: "force": (S, N + 1)} at t = 0, dt, 2 dt, ...; None otherwise.
        self.samples = samples
        self.source = source
        if complete is None:
            complete = bool(self.stats.get("complete", status == "ok"))
        self.complete = bool(complete)
        #: why a driver's granules.tsv is UNTRUSTED (its "# UNTRUSTED:" line), else "".
        self.untrusted: str = ""

    @classmethod
    def _from_core(cls, d: Dict[str, Any], source: str) -> "Result":
        return cls(d["columns"], stats=d.get("stats"), settings=d.get("settings"),
                   status=d.get("status", "ok"), message=d.get("message", ""),
                   warnings=d.get("warnings"), x_final=d.get("x_final"),
                   v_final=d.get("v_final"), source=d.get("scene", source),
                   samples=d.get("samples"))

    # -- conservation ------------------------------------------------------------
    @property
    def energy_error(self) -> float:
        """|E(t_final) - E(0)| / E(0); NaN without a run."""
        return float(self.stats.get("energy_error", math.nan))

    @property
    def momentum_error(self) -> float:
        """Momentum error relative to the momentum in motion; NaN without a run."""
        return float(self.stats.get("momentum_error", math.nan))

    # -- conversions ---------------------------------------------------------------
    def to_numpy(self) -> np.ndarray:
        """The columns as one structured array (a row per granule)."""
        dtype = [(c, a.dtype) for c, a in self._columns.items()]
        out = np.empty(len(self), dtype=dtype)
        for c, a in self._columns.items():
            out[c] = a
        return out

    def to_pandas(self) -> Any:
        """The columns as a pandas.DataFrame indexed by k (needs pandas:
        ``pip install taper[pandas]``)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the installation
            raise ImportError("Result.to_pandas() needs pandas: pip install pandas") from e
        df = pd.DataFrame({c: a for c, a in self._columns.items()})
        if "k" in df:
            df = df.set_index("k", drop=False)
            df.index.name = None
        df.attrs["stats"] = dict(self.stats)
        df.attrs["settings"] = {k: v for k, v in self.settings.items() if not isinstance(v, np.ndarray)}
        return df

    def equals(self, other: "Result") -> bool:
        """True when both have the same columns with bit-identical values
        (NaN equal to NaN)."""
        if self.columns != other.columns:
            return False
        return all(np.array_equal(a, other[c], equal_nan=a.dtype.kind == "f")
                   for c, a in self._columns.items())

    def __repr__(self) -> str:
        s = self.settings
        what = ", ".join(f"{k}={s[k]!r}" for k in ("profile", "s", "q", "n_granules") if k in s)
        state = "complete" if self.complete else f"partial ({self.status}: {self.message})"
        return f"<taper.Result {what or self.source} N={len(self)} {state}>"


def _number(text: str) -> Any:
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def read_granules(path: PathLike) -> Result:
    """Reads a granules.tsv (or granules.partial.tsv, or sweep.tsv) written by
    the driver as a Result.

    Lines starting with '#' are comments, wherever they are: ``# name =
    value`` lines that name a statistic (``steps``, ``energy_error``, ...)
    fill ``stats``, ``# complete`` or ``# PARTIAL result (...): message`` the
    status, ``# UNTRUSTED: why`` sets ``untrusted``.  The header is the first
    line that is not a comment (the driver writes it as the file's first
    line, so that numpy.genfromtxt(names=True) and pandas read it too); every
    later line is a row.  The columns are those the file has (``&output
    columns``; a run without numerics has no t_pass ... X_pass), and ``k`` the
    granules its rows hold (``&output every`` thins them).  Integer columns
    (k) become int64 arrays, the others float64 (``nan`` is NaN), read back to
    the same doubles the driver computed (it writes 17 significant digits).
    """
    path = os.fspath(path)
    statistics = set(_core.STATISTICS)
    statuses = {desc: ident for ident, (_, desc) in _core.statuses().items()}
    stats: Dict[str, Any] = {}
    status, message, complete, untrusted = "ok", "", None, ""
    header: Optional[List[str]] = None
    rows: List[str] = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("#"):
                text = line[1:].strip()
                if text == "complete":
                    complete = True
                elif text.startswith("PARTIAL result"):
                    complete = False
                    inner, _, message = text.partition("): ")
                    desc = inner[len("PARTIAL result ("):]
                    status = statuses.get(desc, desc)
                elif text.startswith("UNTRUSTED: "):
                    untrusted = text[len("UNTRUSTED: "):]
                else:
                    name, eq, value = text.partition(" = ")
                    if eq and name in statistics:
                        stats[name] = _number(value.strip())
                continue
            if header is None:
                header = line.rstrip("\r\n").split("\t")
                continue
            if line.strip():
                rows.append(line)
    if header is None:
        raise ValueError(f"{path}: no header line (every line is a comment)")
    if rows:
        table = np.loadtxt(rows, delimiter="\t", dtype=str, ndmin=2, comments=None)
    else:
        table = np.empty((0, len(header)), dtype=str)
    if table.shape[1] != len(header):
        raise ValueError(f"{path}: {table.shape[1]} values per row, {len(header)} column names")
    columns: Dict[str, np.ndarray] = {}
    for i, name in enumerate(header):
        cell = table[:, i]
        try:
            columns[name] = cell.astype(np.int64) if name == "k" else cell.astype(np.float64)
        except ValueError as e:
            raise ValueError(f"{path}: column {name}: {e}") from None
    if "complete" in stats:
        stats["complete"] = bool(stats["complete"])
    if complete is None:
        complete = bool(stats.get("complete", True))
    result = Result(columns, stats=stats, status=status, message=message, source=path,
                    complete=complete)
    result.untrusted = untrusted
    return result
