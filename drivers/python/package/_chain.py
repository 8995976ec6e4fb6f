"""taper.chain(): a chain's geometry as the library builds it, with the
reduced masses of its binary collisions (no theory times, no integration)."""

from __future__ import annotations

from typing import Any, Dict, Mapping, Optional, Sequence, Union

import numpy as np

from . import _core
from ._columns import Columns

__all__ = ["Chain", "chain", "CHAIN_COLUMNS", "BEYOND_PAPER"]

#: The chain settings beyond the paper (taper.h, issue 15), keywords of
#: simulate(), theory() and chain(), named as the library's error fields.
BEYOND_PAPER = ("left_end", "right_end", "left_wall_compliance", "right_wall_compliance",
                "striker_radius", "striker_density", "striker_compliance", "load", "damping",
                "drag", "pattern", "materials", "disorder", "disorder_amplitude",
                "disorder_seed", "piston_duration", "piston_compliance")

#: The columns of a Chain, in order.
CHAIN_COLUMNS = ("k", "R", "m", "X0", "r", "mu")

Real = Union[int, float]


class Chain(Columns):
    """A chain as taper_chain_alloc builds it.

    Columns (numpy arrays of length N, granule k at index k-1): ``k``
    (int64), ``R`` (radii R_k), ``m`` (masses m_k = R_k^3), ``X0`` (rest
    positions, X0(1) = 0), ``r`` (contact factors r_k =
    (2 R_k R_{k+1}/(R_k + R_{k+1}))^(1/2) of the pair (k, k+1)) and ``mu``
    (reduced masses mu_k = m_k m_{k+1}/(m_k + m_{k+1}), taper_theory_compute).
    With ``materials`` or mass disorder m_k is rho_k R_k^3 and r_k carries
    the compliances (taper.h, taper_chain_spec_set_materials).
    ``r`` and ``mu`` belong to pairs: their last entry is NaN.  Read them as
    attributes (``c.mu``) or items (``c["mu"]``).

    Attributes:
        profile: the profile's name (one of taper.PROFILES).
        exponent: the contact exponent n.
        settings: the chain settings, every default filled in.
        theory_note: None when the binary collision theory describes the
            chain, else why not (taper_chain_theory_note).
        striker_mass: the striker's mass (NaN: no striker).
    """

    def __init__(self, columns: Mapping[str, np.ndarray], *, profile: str, exponent: float,
                 settings: Optional[Dict[str, Any]] = None,
                 theory_note: Optional[str] = None, striker_mass: float = float("nan")) -> None:
        self._columns: Dict[str, np.ndarray] = {c: columns[c] for c in CHAIN_COLUMNS}
        self.profile = profile
        self.exponent = float(exponent)
        self.settings: Dict[str, Any] = dict(settings or {})
        self.theory_note = theory_note
        self.striker_mass = float(striker_mass)

    def __repr__(self) -> str:
        return f"<taper.Chain {self.profile} N={len(self)} exponent={self.exponent:g}>"


def chain(*, profile: Optional[str] = None, s: Optional[Real] = None, q: Optional[Real] = None,
          n_granules: Optional[int] = None, exponent: Optional[Real] = None,
          radii: Optional[Sequence[float]] = None, **beyond_paper: Any) -> Chain:
    """Builds a chain and returns its columns ``k R m X0 r mu`` (see Chain).
    Keywords as for taper.simulate()'s chain settings, each passed to the
    setter of its name; left out (or None): the library's default.

    Raises:
        InvalidArgumentError: a value or combination the library refuses
            (``.field`` names the argument), or a chain whose masses or
            theory leave double precision.
        TypeError: an argument of the wrong type (named).
    """
    for k in beyond_paper:
        if k not in BEYOND_PAPER:
            raise TypeError(f"chain() got an unexpected keyword argument '{k}'")
    kw = {k: v for k, v in dict(profile=profile, s=s, q=q, n_granules=n_granules,
                                exponent=exponent, radii=radii, **beyond_paper).items()
          if v is not None}
    d = _core.chain(**kw)
    return Chain(d["columns"], profile=d["profile"], exponent=d["exponent"],
                 settings=d["settings"], theory_note=d.get("theory_note"),
                 striker_mass=d.get("striker_mass", float("nan")))
