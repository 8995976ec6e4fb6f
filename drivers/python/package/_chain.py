# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.chain(): a chain's geometry as the library builds it, with the
reduced masses of its binary collisions (no theory times, no integration)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, Mapping, Optional

from . import _core
from ._columns import Columns

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Chain", "chain", "CHAIN_COLUMNS"]

#: The columns of a Chain, in order.
CHAIN_COLUMNS = ("k", "R", "m", "X0", "r", "mu")


class Chain(Columns):
    """A chain as taper_chain_alloc builds it.

    Columns (numpy arrays of length N, granule k at index k-1): ``k``
    (int64), ``R`` (radii R_k), ``m`` (masses m_k = R_k^3), ``X0`` (rest
    positions, X0(1) = 0), ``r`` (contact factors r_k =
    (2 R_k R_{k+1}/(R_k + R_{k+1}))^(1/2) of the pair (k, k+1)) and ``mu``
    (reduced masses mu_k = m_k m_{k+1}/(m_k + m_{k+1}), taper_theory_compute).
    With ``densities``/``compliances`` or mass disorder m_k is rho_k R_k^3
    and r_k carries the compliances (taper.h, taper_chain_spec_set_materials).
    ``r`` and ``mu`` belong to pairs: their last entry is NaN.  With
    ``&material`` R, X0 are in m, m and mu in kg (``units``); r stays
    relative (R in units of R_1).  Read them as attributes (``c.mu``) or
    items (``c["mu"]``).

    Attributes:
        profile: the profile's name (one of taper.PROFILES).
        exponent: the contact exponent n.
        settings: every scene variable by its name, defaults filled in.
        units: the SI unit of each converted column (and striker_mass); empty
            in rescaled units.
        theory_note: None when the binary collision theory describes the
            chain, else why not (taper_chain_theory_note).
        striker_mass: the striker's mass (NaN: no striker).
    """

    def __init__(self, columns: Mapping[str, np.ndarray], *, profile: str, exponent: float,
                 settings: Optional[Dict[str, Any]] = None,
                 theory_note: Optional[str] = None, striker_mass: float = float("nan"),
                 units: Optional[Dict[str, str]] = None) -> None:
        self._columns: Dict[str, np.ndarray] = {c: columns[c] for c in CHAIN_COLUMNS}
        self.profile = profile
        self.exponent = float(exponent)
        self._settings: Optional[Dict[str, Any]] = dict(settings or {})
        self.units: Dict[str, str] = dict(units or {})
        self.theory_note = theory_note
        self.striker_mass = float(striker_mass)
        self._scene: Any = None

    @property
    def settings(self) -> Dict[str, Any]:
        if self._settings is None:
            from .result import _keyword_settings
            self._settings = _keyword_settings(self._scene, 0)
        return self._settings

    def __repr__(self) -> str:
        return f"<taper.Chain {self.profile} N={len(self)} exponent={self.exponent:g}>"


def chain(**variables: Any) -> Chain:
    """Builds the chain of the scene of the keywords and returns its columns
    ``k R m X0 r mu`` (see Chain), without theory times or integration.
    Keywords as for taper.simulate() (every scene variable, checked as in a
    file; only the chain's matter here); left out (or None): the default.

    Raises:
        TypeError: an unknown keyword, a value of the wrong Python type.
        InvalidArgumentError: a value or combination the scene or the
            library refuses (``.field`` is the keyword), or a chain whose
            masses or theory leave double precision.
    """
    d = _core.chain(**variables)
    c = Chain(d["columns"], profile=d["profile"], exponent=d["exponent"],
              theory_note=d.get("theory_note"),
              striker_mass=d.get("striker_mass", float("nan")), units=d.get("units"))
    c._settings, c._scene = None, d["scene"]
    return c
