# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.variables(): the scene variables, which are the keywords of
simulate(), theory() and chain(), read from the scene's own table (the one
`taper --defaults` and `taper --doc` print)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional, Tuple

from . import _core

__all__ = ["Variable", "variables"]


@dataclass(frozen=True)
class Variable:
    """One scene variable.

    Attributes:
        name: its one name: the keyword of simulate(), theory() and chain(),
            the library's error field (InvalidArgumentError.field).
        group: its group in a scene file (``chain``, ``ends``, ``striker``,
            ``losses``, ``material``, ``solver``, ``sensors``, ``output``,
            ``fit``, ``table``, ``figure``, ``sweep``).
        key: its key in that group: the name without the group's name in
            front, if it has it (``striker_radius`` is ``&striker radius``,
            ``fit_model`` is ``&fit model``, ``seed`` is ``&chain seed``).
        type: ``"real"``, ``"integer"``, ``"logical"``, ``"string"``,
            ``"choice"`` (a str, one of ``choices``) or ``"real list"``; the
            Python value is a float (or int), an int, a bool, a str, a str,
            a sequence of floats.
        sweep: True when a scene file may give it a list of values (a
            sweep: taper.run_scene; a call runs one chain and refuses one).
        default: the value simulate() uses when the keyword is left out
            (None: none; an empty list is None too).
        unit: the SI unit of its value when the scene has ``&material``
            (then every dimensional input is SI); None for a pure number.
            Without ``&material`` values are in the rescaled units of eq. (5)
            of arXiv:0905.4512.
        range: the values it allows, as ``taper --doc`` writes them
            (``"[2, 10000000]"``, ``"'adams', 'bdf'"``; "" when anything goes).
        choices: a choice's names, else None.
        description: one line, the table's.
        beyond_paper: not part of the paper's model (its default is the
            paper's idealisation).
        checked_by: who checks it: ``"scene"`` (the scene reader),
            ``"chain"`` or ``"solver"`` (the library's setters), ``"fit"``.
    """

    name: str
    group: str
    key: str
    type: str
    sweep: bool
    default: Any
    unit: Optional[str]
    range: str
    choices: Optional[Tuple[str, ...]]
    description: str
    beyond_paper: bool
    checked_by: str


def variables() -> Tuple[Variable, ...]:
    """Every scene variable, in the order of ``taper --defaults``: the
    keywords simulate(), theory() and chain() take, with their groups and
    keys, types, defaults, SI units, allowed values and descriptions."""
    return tuple(Variable(**d) for d in _core.variables())
