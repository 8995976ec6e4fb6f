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
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Tuple, Union

from . import _core
from ._columns import Columns, np

if TYPE_CHECKING:
    import numpy

__all__ = ["Result", "read_granules", "COLUMNS", "THEORY_COLUMNS"]

#: The columns of granules.tsv, in order (the driver's scene module names them).
COLUMNS = _core.COLUMNS
#: The columns of taper.theory(): the chain and the binary collision theory.
THEORY_COLUMNS = _core.THEORY_COLUMNS

PathLike = Union[str, "os.PathLike[str]"]

#: What the columns are, for labels (taper.plot) and the repr.
QUANTITY = {
    "k": "granule", "R": "radius", "m": "mass", "X0": "rest position",
    "t_pass": "time the pulse passes", "T_res": "residence time", "v_peak": "peak velocity",
    "t_peak": "time of the peak", "X_pass": "position as the pulse passes",
    "theory_v": "pulse amplitude (theory)", "theory_T": "residence time (theory)",
    "theory_t": "time the pulse passes (theory)",
}


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
        settings: every keyword of simulate() with its value in the run
            (defaults filled in), as the scene holds them (SI with
            &material); a sweep's run has its point's values.  Made when
            first read.
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

    def __init__(self, columns: Mapping[str, "numpy.ndarray"], *,
                 stats: Optional[Dict[str, Any]] = None,
                 settings: Optional[Dict[str, Any]] = None, status: str = "ok", message: str = "",
                 warnings: Optional[List[str]] = None, x_final: Optional["numpy.ndarray"] = None,
                 v_final: Optional["numpy.ndarray"] = None, source: str = "",
                 complete: Optional[bool] = None,
                 samples: Optional[Dict[str, "numpy.ndarray"]] = None,
                 units: Optional[Dict[str, str]] = None, theory_note: Optional[str] = None,
                 untrusted: str = "") -> None:
        ordered = [c for c in COLUMNS if c in columns] + [c for c in columns if c not in COLUMNS]
        self._columns: Dict[str, "numpy.ndarray"] = {c: columns[c] for c in ordered}
        self.stats: Dict[str, Any] = dict(stats or {})
        self._settings: Optional[Dict[str, Any]] = dict(settings or {})
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
        self._untrusted: Optional[str] = untrusted
        self._scene: Any = None
        self._point = 0

    @classmethod
    def _from_core(cls, d: Dict[str, Any]) -> "Result":
        """From the extension's dict (its columns already in granules.tsv's
        order): no copies, the settings and the verdict on conservation
        made when first read."""
        r = cls.__new__(cls)
        r._columns = d["columns"]
        r.stats = stats = d["stats"]
        r.units = d["units"]
        r.status = status = d["status"]
        r.message = d["message"]
        r.warnings = d["warnings"]
        r.x_final = d.get("x_final")
        r.v_final = d.get("v_final")
        r.samples = d.get("samples")
        r.theory_note = d["theory_note"]
        r.source = d["source"]
        r.complete = bool(stats.get("complete", status == "ok"))
        r._settings = r._untrusted = None
        r._scene, r._point = d["scene"], d["point"]
        return r

    @property
    def settings(self) -> Dict[str, Any]:
        if self._settings is None:
            self._settings = _keyword_settings(self._scene, self._point)
        return self._settings

    @settings.setter
    def settings(self, value: Dict[str, Any]) -> None:
        self._settings = dict(value)
        self._untrusted = None if self._scene is not None else self._untrusted

    @property
    def untrusted(self) -> str:
        if self._untrusted is None:
            self._untrusted = _distrust(self.stats, self.settings)
        return self._untrusted

    @untrusted.setter
    def untrusted(self, value: str) -> None:
        self._untrusted = value

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

    # -- headline observables ------------------------------------------------------
    def pulse_speed(self, first: Optional[int] = None, last: Optional[int] = None) -> float:
        """The pulse's mean speed from granule `first` to granule `last`:
        (X(last) - X(first)) / (t(last) - t(first)), the positions and times
        at which the pulse passes them (X_pass, t_pass; for the theory alone
        the rest positions X0 and the theory's t_k of eq. (19)).  By default
        over the last tenth of the granules the pulse passed (at least two),
        where a tapered chain has settled into its asymptotic law: for a run
        ``stats["pulse_speed"]``, the statistic granules.tsv's header and
        runs.tsv carry, computed by the same C function
        (drivers/scenes/results/pulse.h) from every granule's columns.  In
        the Result's units (``units["pulse_speed"]``, m/s, in SI); NaN where
        fewer than two granules were passed."""
        if first is None and last is None and "pulse_speed" in self.stats:
            return float(self.stats["pulse_speed"])
        x, t = ("X_pass", "t_pass") if "t_pass" in self._columns else ("X0", "theory_t")
        if x not in self._columns or t not in self._columns or "k" not in self._columns:
            return math.nan
        k, X, T = self._columns["k"], self._columns[x], self._columns[t]
        if first is None and last is None:
            return _core.pulse_speed(X, T, k)
        known = np.flatnonzero(np.isfinite(X) & np.isfinite(T))
        if len(known) < 2:
            return math.nan
        i1 = known[-1] if last is None else _row_of(k, last)
        if first is None:
            reached = int(k[known[-1]])
            i0 = known[np.searchsorted(k[known], reached - max(1, reached // 10))]
        else:
            i0 = _row_of(k, first)
        dt = T[i1] - T[i0]
        return float((X[i1] - X[i0]) / dt) if dt != 0 else math.nan

    # -- conversions ---------------------------------------------------------------
    def to_numpy(self) -> "numpy.ndarray":
        """The columns as one structured array (a row per granule)."""
        dtype = [(c, a.dtype) for c, a in self._columns.items()]
        out = np.empty(len(self), dtype=dtype)
        for c, a in self._columns.items():
            out[c] = a
        return out

    def to_pandas(self) -> Any:
        """The columns as a pandas.DataFrame indexed by k (needs pandas:
        ``pip install taper-chains[pandas]``).  In SI a column's name
        carries its unit as granules.tsv's header does (``t_pass[s]``,
        ``v_peak[m/s]``); rescaled columns have their bare names.
        ``df.attrs`` holds ``units`` (each column's, statistic's, sample's
        unit by its bare name; empty when rescaled), ``settings`` (every
        keyword's value; lists as lists), ``stats`` (the run's statistics),
        ``status``, ``complete``, ``untrusted`` and ``source``."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the installation
            raise ImportError("Result.to_pandas() needs pandas: pip install pandas") from e
        units = self.units
        df = pd.DataFrame({(f"{c}[{units[c]}]" if c in units else c): a
                           for c, a in self._columns.items()})
        if "k" in self._columns:
            df.index = pd.Index(self._columns["k"])
        df.attrs["units"] = dict(units)
        df.attrs["settings"] = {k: (v.tolist() if hasattr(v, "tolist") else v)
                                for k, v in self.settings.items()}
        df.attrs["stats"] = dict(self.stats)
        for name in ("status", "complete", "untrusted", "source"):
            df.attrs[name] = getattr(self, name)
        return df

    def equals(self, other: "Result") -> bool:
        """True when both have the same columns with bit-identical values
        (NaN equal to NaN)."""
        if self.columns != other.columns:
            return False
        return all(np.array_equal(a, other[c], equal_nan=a.dtype.kind == "f")
                   for c, a in self._columns.items())

    def __repr__(self) -> str:
        """What a physicist checks first: the chain, N, how the run ended,
        t_final, the energy error, the pulse's speed, a wall's peak force."""
        s, units = self.settings, self.units
        profile = s.get("profile")
        what = []
        if profile:
            what.append(profile)
            name = TAPER_PARAMETER.get(profile)
            if name and name in s:
                what.append(f"{name}={s[name]:g}")
        elif self.source and self.source not in ("simulate", "theory"):
            what.append(repr(self.source))
        what.append(f"N={len(self)}")
        if not self.stats:
            state = "theory only" if "theory_v" in self._columns else "no run"
        elif self.complete:
            state = "complete"
        else:
            state = f"PARTIAL ({self.status}: {self.message})" if self.message else \
                f"PARTIAL ({self.status})"
        parts = []
        if "t_final" in self.stats:
            parts.append(f"t_final={_with_unit(self.stats['t_final'], units.get('t_final'))}")
        if "energy_error" in self.stats:
            parts.append(f"energy error {self.energy_error:.2g}")
        if self.untrusted:
            parts.append("UNTRUSTED")
        speed = self.pulse_speed()
        if speed == speed:
            x_unit, t_unit = units.get("X_pass", units.get("X0")), units.get("t_pass")
            unit = units.get("pulse_speed", f"{x_unit}/{t_unit}" if x_unit and t_unit else None)
            parts.append(f"pulse speed {_with_unit(speed, unit)}")
        for side in ("left", "right"):
            force = self.stats.get(f"wall_peak_force_{side}", math.nan)
            if force == force:
                parts.append(f"{side} wall peak force "
                             f"{_with_unit(force, units.get(f'wall_peak_force_{side}'))}")
        return f"<taper.Result {' '.join(what)} {state}" + (f": {', '.join(parts)}>" if parts else ">")


#: The tapering parameter of each profile that has one.
TAPER_PARAMETER = {"backward_linear": "s", "forward_linear": "s",
                   "backward_exponential": "q", "forward_exponential": "q"}


def _with_unit(x: float, unit: Optional[str]) -> str:
    return f"{x:.4g} {unit}" if unit else f"{x:.4g}"


def _row_of(k: "numpy.ndarray", granule: int) -> int:
    """The row of granule k (columns thinned by &output every keep some)."""
    rows = np.flatnonzero(k == granule)
    if len(rows) != 1:
        raise ValueError(f"granule {granule} is not a row of this result")
    return int(rows[0])


def _keyword_settings(scene: Any, point: int) -> Dict[str, Any]:
    """The settings of a run of the extension's scene: every keyword of
    simulate() (the driver's own variables left out, as simulate() does)."""
    if scene is None:
        return {}
    from ._signature import driver_only_names
    skip = driver_only_names()
    return {k: v for k, v in _core.scene_settings(scene, point).items() if k not in skip}


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
    statistics = set(_core.STATISTICS) | {"pulse_speed"}  # the header's (results/pulse.h)
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
