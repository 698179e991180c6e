"""Scale factors from a model file's ``units:`` block to SI.

Each quantity kind in :data:`QUANTITY_KINDS` has its own key in the
``units:`` block; every kind defaults to its SI unit and none is derived from
another (e.g. choosing ``length: mm`` does not change the torque unit).

The ``speed`` kind is the driver speed. For a revolute driver it is angular
(``rad/s``, ``rpm``, ``deg/s``, ``rev/s``, ``rps``) and converts to rad/s; for
a prismatic driver it is linear (``m/s``, ``mm/s``, ``cm/s``) and converts to
m/s. Use :func:`is_angular_speed` to tell which.

Unit strings may be written with ``*`` or ``·`` for products, ``^2`` or ``²``
for squares, ``u``, ``µ`` or ``μ`` for micro; a space between factors
means a product (``"kg mm^2"``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from types import MappingProxyType

from ..errors import did_you_mean

__all__ = [
    "nice_scale",
    "QUANTITY_KINDS",
    "SI_UNITS",
    "UNITS",
    "UnitError",
    "factor",
    "is_angular_speed",
    "unit_table",
    "unit_pattern",
]


class UnitError(ValueError):
    """A unit or quantity kind in the ``units:`` block is unknown or malformed."""


QUANTITY_KINDS: tuple[str, ...] = (
    "length",
    "angle",
    "speed",
    "time",
    "mass",
    "force",
    "torque",
    "inertia",
)
"""Quantity kinds accepted as keys of the ``units:`` block."""

SI_UNITS: Mapping[str, str] = MappingProxyType(
    {
        "length": "m",
        "angle": "rad",
        "speed": "rad/s",
        "time": "s",
        "mass": "kg",
        "force": "N",
        "torque": "N*m",
        "inertia": "kg*m^2",
    }
)
"""SI (default) unit of each quantity kind; linear driver speeds convert to m/s instead."""

_ANGULAR_SPEEDS: dict[str, float] = {
    "rad/s": 1.0,
    "rpm": 2.0 * math.pi / 60.0,
    "deg/s": math.pi / 180.0,
    "rev/s": 2.0 * math.pi,
    "rps": 2.0 * math.pi,
}
_LINEAR_SPEEDS: dict[str, float] = {"m/s": 1.0, "mm/s": 1e-3, "cm/s": 1e-2}

# Canonical units of each kind (shown in error messages) with their factors to SI.
_CANONICAL: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "km": 1e3, "um": 1e-6, "in": 0.0254, "ft": 0.3048},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0, "rev": 2.0 * math.pi},
    "speed": {**_ANGULAR_SPEEDS, **_LINEAR_SPEEDS},
    "time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0},
    "mass": {"kg": 1.0, "g": 1e-3, "t": 1e3, "lb": 0.45359237},
    "force": {"N": 1.0, "kN": 1e3, "mN": 1e-3, "lbf": 4.4482216152605, "kgf": 9.80665},
    "torque": {"N*m": 1.0, "kN*m": 1e3, "N*mm": 1e-3},
    "inertia": {"kg*m^2": 1.0, "kg*mm^2": 1e-6, "kg*cm^2": 1e-4, "g*cm^2": 1e-7},
}

# Extra spellings that normalisation alone does not produce: alias -> canonical.
_ALIASES: dict[str, dict[str, str]] = {
    "length": {"µm": "um", "μm": "um"},
    "torque": {
        "N·m": "N*m",
        "Nm": "N*m",
        "kN·m": "kN*m",
        "kNm": "kN*m",
        "N·mm": "N*mm",
        "Nmm": "N*mm",
    },
    "inertia": {
        "kg·m²": "kg*m^2",
        "kg*m²": "kg*m^2",
        "kg·m^2": "kg*m^2",
        "kg·mm²": "kg*mm^2",
        "kg*mm²": "kg*mm^2",
        "kg·mm^2": "kg*mm^2",
        "kg·cm²": "kg*cm^2",
        "kg*cm²": "kg*cm^2",
        "kg·cm^2": "kg*cm^2",
        "g·cm²": "g*cm^2",
        "g*cm²": "g*cm^2",
        "g·cm^2": "g*cm^2",
    },
}

UNITS: Mapping[str, Mapping[str, float]] = MappingProxyType(
    {
        kind: MappingProxyType(
            {
                **units,
                **{alias: units[canon] for alias, canon in _ALIASES.get(kind, {}).items()},
            }
        )
        for kind, units in _CANONICAL.items()
    }
)
"""Factor to SI of every accepted spelling of every unit, by quantity kind."""


def _normalise(unit: str) -> str:
    """Reduce spelling variants of a unit string to one form."""
    text = re.sub(r"\s*([*·⋅/^])\s*", r"\1", unit.strip())
    text = re.sub(r"\s+", "*", text)
    for src, dst in (("·", "*"), ("⋅", "*"), ("**2", "^2"), ("²", "^2"), ("µ", "u"), ("μ", "u")):
        text = text.replace(src, dst)
    return text


_ANGULAR_NORMALISED = frozenset(_normalise(u) for u in _ANGULAR_SPEEDS)

_NORMALISED: dict[str, dict[str, float]] = {
    kind: {_normalise(u): f for u, f in units.items()} for kind, units in UNITS.items()
}


def _check_kind(kind: object) -> str:
    if not isinstance(kind, str) or kind not in UNITS:
        hint = did_you_mean(str(kind), QUANTITY_KINDS)
        raise UnitError(f"unknown quantity kind '{kind}'{hint}; known: {', '.join(QUANTITY_KINDS)}")
    return kind


def factor(kind: str, unit: str) -> float:
    """Factor converting a value in ``unit`` to SI for a quantity kind.

    Parameters
    ----------
    kind : str
        One of :data:`QUANTITY_KINDS`.
    unit : str
        Unit string, e.g. ``"mm"``, ``"rpm"`` or ``"kg·mm²"``.

    Returns
    -------
    float
        Multiply a value in ``unit`` by this to get SI (rad/s for angular and
        m/s for linear speeds).

    Raises
    ------
    UnitError
        For an unknown kind or unit (the message suggests a close match).
    """
    _check_kind(kind)
    if not isinstance(unit, str):
        raise UnitError(f"{kind} unit must be a string, got {type(unit).__name__}")
    units = UNITS[kind]
    if unit in units:
        return units[unit]
    normalised = _normalise(unit)
    if normalised in _NORMALISED[kind]:
        return _NORMALISED[kind][normalised]
    hint = did_you_mean(unit, units)
    known = ", ".join(sorted(_CANONICAL[kind]))
    raise UnitError(f"unknown {kind} unit '{unit}'{hint}; known: {known}")


def is_angular_speed(unit: str) -> bool:
    """Whether a driver speed unit is angular (True) or linear (False).

    Parameters
    ----------
    unit : str
        A ``speed`` unit, e.g. ``"rpm"`` or ``"mm/s"``.

    Returns
    -------
    bool
        True for angular units (converted to rad/s), False for linear ones
        (converted to m/s).

    Raises
    ------
    UnitError
        If ``unit`` is not a known speed unit.
    """
    factor("speed", unit)
    return _normalise(unit) in _ANGULAR_NORMALISED


def unit_table(spec: Mapping[str, str] | None) -> dict[str, float]:
    """Full table of SI factors for a ``units:`` block.

    Parameters
    ----------
    spec : mapping of str to str, or None
        The ``units:`` block (kind -> unit); missing kinds default to SI.

    Returns
    -------
    dict of str to float
        Factor to SI for every kind in :data:`QUANTITY_KINDS`.

    Raises
    ------
    UnitError
        If ``spec`` is not a mapping or any entry is unknown.
    """
    table = {kind: 1.0 for kind in QUANTITY_KINDS}
    if spec is None:
        return table
    if not isinstance(spec, Mapping):
        raise UnitError(
            f"units must be a mapping of quantity kind to unit, got {type(spec).__name__}"
        )
    for kind, unit in spec.items():
        table[_check_kind(kind)] = factor(kind, unit)
    return table


# how each character of a normalised unit may be written (the inverse of _normalise)
_WRITTEN = {
    "*": r"(?:\s*[*·⋅]\s*|\s+)",
    "/": r"\s*/\s*",
    "u": "[uµμ]",
}
_SQUARE = r"(?:\s*\^\s*2|\s*\*\s*\*\s*2|²)"


def unit_pattern(kind: str) -> str:
    """A regular expression (JSON Schema ``pattern``: ECMA-262 and Python alike) that
    matches exactly the spellings of a ``kind``'s units that :func:`factor` accepts:
    every unit of :data:`UNITS` with the freedom :func:`_normalise` allows (spaces,
    ``*`` ``·`` ``⋅`` or a space for a product, ``^2`` ``**2`` ``²``, ``u`` ``µ`` ``μ``)."""
    forms = sorted(_NORMALISED[_check_kind(kind)], key=lambda u: (-len(u), u))
    alternatives = []
    for form in forms:
        parts = form.split("^2")
        written = _SQUARE.join(
            "".join(_WRITTEN.get(ch, re.escape(ch)) for ch in part) for part in parts
        )
        alternatives.append(written)
    return r"^\s*(?:" + "|".join(alternatives) + r")\s*$"


def nice_scale(x: float) -> float:
    """The smallest of 1, 2, 2.5, 4, 5 × 10^k that is ≥ ``x`` (a drawing scale).

    >>> nice_scale(0.0017), nice_scale(0.031), nice_scale(7.0)
    (0.002, 0.04, 10.0)
    """
    if not math.isfinite(x) or x <= 0:
        return 1.0
    k = math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 4.0, 5.0, 10.0):
        v = round(m * 10.0**k, 12 - k if k < 0 else 12)
        if v >= x * (1 - 1e-12):
            return v
    return 10.0 ** (k + 1)
