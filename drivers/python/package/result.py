# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.result -- the result of a run: per-granule numpy columns named as in
granules.tsv, the run's statistics, its status; and read_granules, which
reads a granules.tsv (or sweep.tsv) written by the driver back as the same
type."""

from __future__ import annotations

import math
import os
import re
import stat
import zlib
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np

from . import _core
from ._columns import Columns

__all__ = ["Result", "read_granules", "COLUMNS", "THEORY_COLUMNS"]

#: The columns of granules.tsv, in order (the driver's scene module names them).
COLUMNS = _core.COLUMNS
#: The columns of taper.theory(): the chain and the binary collision theory.
THEORY_COLUMNS = _core.THEORY_COLUMNS

PathLike = Union[str, "os.PathLike[str]"]


class Result(Columns):
    """One chain's per-granule columns and what the run reported.

    Columns are numpy arrays of length N, granule k at index k-1: ``k``
    (int64) and float64 ``R m X0 t_pass T_res v_peak t_peak X_pass theory_v
    theory_T theory_t`` (those of the run that exist: ``taper.theory()``
    has no ``t_pass ... X_pass``; ``&output columns`` and ``every`` choose
    columns and rows as they do granules.tsv's).  NaN marks a value that
    does not exist.  Read them as attributes (``r.v_peak``) or items
    (``r["v_peak"]``).

    Attributes:
        stats: the run's statistics by their library names (``steps``,
            ``rhs_evals``, ..., ``energy_error``, ``momentum_error``,
            ``complete``); empty for the theory alone.
        units: the SI unit of every column, statistic, sample and final
            state that has one (``{"t_pass": "s", "v_peak": "m/s", ...}``)
            when the results are in SI (a scene with ``&material``, unless
            ``units='rescaled'``); empty when they are in the rescaled units
            of eq. (5) of arXiv:0905.4512.
        settings: every scene variable of the run by its name (the keywords
            of simulate()), defaults filled in, as the scene holds them (SI
            with &material); a sweep's run has its point's values.
        complete: True when every requested observable is known.
        status: ``"ok"``, or why the run ended early: ``"solver"`` (the
            integrator failed), ``"limit"`` (t_max or max_steps reached).
        message: the library's message for a partial run, else "".
        untrusted: why the run is not to be trusted (its energy or momentum
            error beyond ``max_energy_error``, ``max_momentum_error``, as
            the driver's granules.tsv says), else "".
        warnings: the library's warnings during the run (nothing is printed).
        x_final, v_final: displacements and velocities where the run ended
            (None when the result was read from a file or is theory only).
        samples: with ``&sensors interval`` > 0, ``{"t": (S,), "x": (S, N),
            "v": (S, N), "force": (S, N + 1)}`` at t = 0, dt, 2 dt, ...
            (``force[:, 0]`` on granule 1 from the left, ``force[:, k]`` the
            contact (k, k+1), ``force[:, N]`` from the right); else None.
        theory_note: why the binary collision theory does not describe the
            chain (its columns are then NaN), else None.
        source: where the result came from ("simulate", "theory", a scene or
            a granules.tsv path).
    """

    def __init__(self, columns: Mapping[str, np.ndarray], *, stats: Optional[Dict[str, Any]] = None,
                 settings: Optional[Dict[str, Any]] = None, status: str = "ok", message: str = "",
                 warnings: Optional[List[str]] = None, x_final: Optional[np.ndarray] = None,
                 v_final: Optional[np.ndarray] = None, source: str = "",
                 complete: Optional[bool] = None,
                 samples: Optional[Dict[str, np.ndarray]] = None,
                 units: Optional[Dict[str, str]] = None, theory_note: Optional[str] = None,
                 untrusted: str = "") -> None:
        ordered = [c for c in COLUMNS if c in columns] + [c for c in columns if c not in COLUMNS]
        self._columns: Dict[str, np.ndarray] = {c: columns[c] for c in ordered}
        self.stats: Dict[str, Any] = dict(stats or {})
        self.settings: Dict[str, Any] = dict(settings or {})
        self.units: Dict[str, str] = dict(units or {})
        self.status = status
        self.message = message
        self.warnings: List[str] = list(warnings or [])
        self.x_final = x_final
        self.v_final = v_final
        self.samples = samples
        self.theory_note = theory_note
        self.source = source
        if complete is None:
            complete = bool(self.stats.get("complete", status == "ok"))
        self.complete = bool(complete)
        self.untrusted: str = untrusted
        self._scene: Any = None
        self._point = 0

    @classmethod
    def _from_core(cls, d: Dict[str, Any]) -> "Result":
        r = cls(d["columns"], stats=d.get("stats"), settings=d.get("settings"),
                status=d.get("status", "ok"), message=d.get("message", ""),
                warnings=d.get("warnings"), x_final=d.get("x_final"),
                v_final=d.get("v_final"), source=d.get("source", ""),
                samples=d.get("samples"), units=d.get("units"),
                theory_note=d.get("theory_note"))
        r._scene, r._point = d.get("scene"), d.get("point", 0)
        r.untrusted = _distrust(r.stats, r.settings)
        return r

    @property
    def scene(self) -> Optional[str]:
        """The resolved scene of the run as a namelist, as the driver echoes
        it in granules.tsv (a sweep's run: its point's values): saved to a
        file, ``taper FILE`` runs the same chain.  None for a result read
        from a file."""
        return None if self._scene is None else _core.scene_text(self._scene, self._point)

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


def _distrust(stats: Mapping[str, Any], settings: Mapping[str, Any]) -> str:
    """The driver's verdict on a run's conservation (&output
    max_energy_error, max_momentum_error): why it is not to be trusted, or
    "" (also for the theory alone)."""
    if "energy_error" not in stats or "max_energy_error" not in settings:
        return ""
    e, p = float(stats["energy_error"]), float(stats["momentum_error"])
    be, bp = settings["max_energy_error"], settings["max_momentum_error"]
    bad_e, bad_p = not e <= be, not p <= bp      # NaN is not trusted either
    if bad_e and bad_p:
        return (f"energy error {e:.2e} exceeds {be!r} and momentum error {p:.2e} exceeds "
                f"{bp!r} (&output max_energy_error, max_momentum_error)")
    if bad_e:
        return f"energy error {e:.2e} exceeds {be!r} (&output max_energy_error)"
    if bad_p:
        return f"momentum error {p:.2e} exceeds {bp!r} (&output max_momentum_error)"
    return ""


def _number(text: str) -> Any:
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


_FOOTER = re.compile(rb"# end: rows (\d+), bytes (\d+), crc32 ([0-9a-f]{8})\n")


def _verified(path: str) -> bytes:
    """The bytes of a result file above its footer, once the footer proves
    them whole (docs/scene.md, "Result files"): its byte count, the CRC-32
    of those bytes (zlib's), its count of data rows.  ValueError naming the
    file otherwise; a file that is not a regular one (a device, a FIFO) is
    refused before any byte is read."""
    st = os.stat(path)
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(f"{path}: not a regular file: not a result of taper")
    with open(path, "rb") as f:
        f.seek(max(0, st.st_size - 96))
        tail = f.read()
        cut = tail.rfind(b"\n", 0, len(tail) - 1) + 1
        if cut == 0 and st.st_size > len(tail):
            cut = -1
        m = _FOOTER.fullmatch(tail[cut:]) if cut >= 0 else None
        if not m:
            raise ValueError(f"{path}: no footer line (# end: rows N, bytes N, crc32 X): cut "
                             "short, or not written whole by taper (a file of an older taper: "
                             "read_granules(path, verify=False))")
        size = int(m.group(2))
        if size != st.st_size - (len(tail) - cut):
            raise ValueError(f"{path}: its footer counts {size} bytes above it, the file has "
                             f"{st.st_size - (len(tail) - cut)}: cut or extended after it was "
                             "written")
        f.seek(0)
        body = f.read(size)
    if zlib.crc32(body) != int(m.group(3), 16):
        raise ValueError(f"{path}: its content does not match its footer (crc32 "
                         f"{zlib.crc32(body):08x}, the footer says {m.group(3).decode()}): "
                         "changed after it was written")
    lines = body.split(b"\n")[:-1]
    rows = sum(1 for i, line in enumerate(lines) if i > 0 and line and not line.startswith(b"#"))
    if rows != int(m.group(1)):
        raise ValueError(f"{path}: {rows} data rows, its footer says {int(m.group(1))}")
    return body


def read_granules(path: PathLike, verify: bool = True) -> Result:
    """Reads a granules.tsv (or granules.partial.tsv, or sweep.tsv) written by
    the driver as a Result.

    The file's footer (``# end: rows N, bytes N, crc32 X``) is checked first:
    a file cut short, changed after it was written, or not a result of taper
    (a device, a binary file) raises ValueError naming it, before anything is
    parsed.  ``verify=False`` reads a file without the check (one written by
    a taper older than the footer).  A table of another kind (sensors.tsv,
    walls.tsv: no ``k`` column) raises ValueError saying what it is.

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
    A file in SI names units in brackets (``t_pass[s]``, ``# t_final[s] =
    ...``): the names go without them, the units to ``units``.
    """
    path = os.fspath(path)
    if verify:
        data = _verified(path)
    else:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise ValueError(f"{path}: not a regular file: not a result of taper")
        with open(path, "rb") as f:
            data = f.read()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not a text file of taper ({e})") from None
    statistics = set(_core.STATISTICS)
    statuses = {desc: ident for ident, (_, desc) in _core.statuses().items()}
    stats: Dict[str, Any] = {}
    units: Dict[str, str] = {}
    status, message, complete, untrusted = "ok", "", None, ""
    header: Optional[List[str]] = None
    rows: List[str] = []
    for line in text.splitlines(keepends=True):
        if line.startswith("#"):
            text_ = line[1:].strip()
            if text_ == "complete":
                complete = True
            elif text_.startswith("PARTIAL result"):
                complete = False
                inner, _, message = text_.partition("): ")
                desc = inner[len("PARTIAL result ("):]
                status = statuses.get(desc, desc)
            elif text_.startswith("UNTRUSTED: "):
                untrusted = text_[len("UNTRUSTED: "):]
            else:
                name, eq, value = text_.partition(" = ")
                name, unit = _unit_of(name)
                if eq and name in statistics:
                    stats[name] = _number(value.strip())
                    if unit:
                        units[name] = unit
            continue
        if header is None:
            header = []
            for cell in line.rstrip("\r\n").split("\t"):
                name, unit = _unit_of(cell)
                header.append(name)
                if unit:
                    units[name] = unit
            if "k" not in header:
                raise ValueError(f"{path}: not a granules.tsv: its columns are "
                                 f"{', '.join(header[:8])}{', ...' if len(header) > 8 else ''}, "
                                 "without k (a sensors.tsv, walls.tsv or runs.tsv is a plain "
                                 "table: numpy.genfromtxt(path, names=True) or "
                                 "pandas.read_csv(path, sep='\\t', comment='#') reads it)")
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
    return Result(columns, stats=stats, status=status, message=message, source=path,
                  complete=complete, units=units, untrusted=untrusted)


def _unit_of(name: str) -> Tuple[str, str]:
    """"t_pass[s]" -> ("t_pass", "s"); "k" -> ("k", "")."""
    if name.endswith("]") and "[" in name:
        base, _, unit = name[:-1].partition("[")
        return base, unit
    return name, ""
