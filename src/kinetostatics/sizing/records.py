"""The sizing stage's frozen records and their sizing.json (docs/sizing.md).

Arrays are over the result's rows (the analysed positions); the peaks are over the rows
and the cycle's quadrature nodes; the means and the bearing life over the nodes.  A
number that cannot be given is null in the JSON (:func:`json_float`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..methods.records import json_float

__all__ = ["BearingSizing", "PinSizing", "LinkSizing", "Sizing"]


def _list(a) -> list[float | None]:
    return [json_float(x) for x in np.asarray(a, float).ravel()]


def _opt(x) -> float | None:
    """A scalar as it is (json_text writes a non-finite one as null and names it in the
    file's ``non_finite``), None where not computed."""
    return None if x is None else float(x)


@dataclass(frozen=True, eq=False)
class BearingSizing:
    """One bearing: its load spectrum at the rows — ``force`` |F| (N), its direction on
    each link in that link's frame ``direction`` (deg, (i, j)), the links' relative angle
    (deg) and speed (rad/s) — and the cycle's numbers: ``P`` the equivalent dynamic load
    (N), ``life`` (L10 in revolutions, in hours), ``speed`` the mean relative speed
    (rev/s), ``motion`` rotating or oscillating with its ``swing`` (deg); a plain
    bearing's ``plain`` {p, v, pv: (rows, peak, mean, limit)}."""

    joint: str
    kind: str
    links: tuple[str, str]
    force: np.ndarray
    direction: tuple[np.ndarray, np.ndarray]
    relative_angle: np.ndarray
    relative_speed: np.ndarray
    peak_force: float
    motion: str
    swing: float
    speed: float
    C: float | None = None
    exponent: float | None = None
    P: float | None = None
    life: tuple[float, float] | None = None
    plain: dict | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "type": self.kind,
            "links": list(self.links),
            "peak_force": json_float(self.peak_force),
            "motion": self.motion,
            "swing_deg": json_float(self.swing),
            "speed_rev_per_s": json_float(self.speed),
        }
        if self.kind != "plain":
            out.update(
                C=_opt(self.C),
                exponent=_opt(self.exponent),
                equivalent_load=_opt(self.P),
                L10_revolutions=_opt(self.life[0]) if self.life else None,
                L10_hours=_opt(self.life[1]) if self.life else None,
            )
        else:
            out.update(
                {
                    k: {"peak": json_float(peak), "mean": json_float(mean), "limit": _opt(limit)}
                    for k, (_, peak, mean, limit) in self.plain.items()
                }
            )
        out["positions"] = {
            "force": _list(self.force),
            "direction_on_" + self.links[0]: _list(self.direction[0]),
            "direction_on_" + self.links[1]: _list(self.direction[1]),
            "relative_angle": _list(self.relative_angle),
            "relative_speed": _list(self.relative_speed),
            **({k: _list(v[0]) for k, v in self.plain.items()} if self.plain else {}),
        }
        return out


@dataclass(frozen=True, eq=False)
class PinSizing:
    """One pin: the shear stress ``shear`` (Pa) and the bearing pressure on the eyes
    ``eye_pressure`` (Pa; None without an eye width) at the rows, and their peaks."""

    joint: str
    diameter: float
    planes: int
    shear: np.ndarray
    peak_shear: float
    eye_pressure: np.ndarray | None = None
    peak_eye_pressure: float | None = None

    def to_json(self) -> dict[str, Any]:
        eye = {} if self.eye_pressure is None else {"eye_pressure": _list(self.eye_pressure)}
        return {
            "diameter": json_float(self.diameter),
            "shear_planes": self.planes,
            "peak_shear_stress": json_float(self.peak_shear),
            "peak_eye_pressure": _opt(self.peak_eye_pressure),
            "positions": {
                "shear_stress": _list(self.shear),
                **eye,
            },
        }


@dataclass(frozen=True, eq=False)
class LinkSizing:
    """One link read as a beam: ``stations`` (m from its first pin ``pins[0]``), the
    internal forces ``N``, ``V`` (N) and ``M`` (N·m) ``(rows, stations)``, the section's
    ``area`` and ``modulus``; the largest normal stress ``peak_stress`` (Pa) at station
    ``critical`` and the angle ``peak_angle`` (deg; None: between the rows); the fatigue
    cycle at the critical section (σ_m, σ_a) and the safety factors ``factors``
    {goodman, soderberg, yield} (None without the strengths)."""

    link: str
    pins: tuple[str, str]
    shape: str
    area: float
    modulus: float
    stations: np.ndarray
    N: np.ndarray
    V: np.ndarray
    M: np.ndarray
    critical: int
    peak_stress: float
    peak_angle: float | None
    cycle: tuple[float, float]
    factors: dict
    note: str | None = None

    @property
    def mid(self) -> int:
        return int(np.argmin(np.abs(self.stations - self.stations[-1] / 2)))

    def to_json(self) -> dict[str, Any]:
        def at(k):
            return {"station": json_float(self.stations[k]), "N": _list(self.N[:, k]),
                    "V": _list(self.V[:, k]), "M": _list(self.M[:, k])}  # fmt: skip

        return {
            "pins": list(self.pins),
            "shape": self.shape,
            "area": json_float(self.area),
            "section_modulus": json_float(self.modulus),
            "length": json_float(self.stations[-1]),
            "peak_stress": json_float(self.peak_stress),
            "critical_station": json_float(self.stations[self.critical]),
            "peak_angle": _opt(self.peak_angle),
            "peaks": {
                "N": json_float(np.max(np.abs(self.N))),
                "V": json_float(np.max(np.abs(self.V))),
                "M": json_float(np.max(np.abs(self.M))),
            },
            "stress_mean": json_float(self.cycle[0]),
            "stress_amplitude": json_float(self.cycle[1]),
            "safety_factors": {k: _opt(v) for k, v in self.factors.items()},
            "note": self.note,
            "mid_span": at(self.mid),
            "critical": at(self.critical),
        }


@dataclass(frozen=True, eq=False)
class Sizing:
    """The sizing of one result: its ``bearings``, ``pins`` and ``links`` (each a tuple
    of records), the angles of the rows (deg) and the ``warnings`` (one line each)."""

    angles: np.ndarray
    bearings: tuple[BearingSizing, ...] = ()
    pins: tuple[PinSizing, ...] = ()
    links: tuple[LinkSizing, ...] = ()
    warnings: tuple[str, ...] = ()

    def least(self) -> dict[str, Any]:
        """The least safety factor (Goodman) and the shortest L10 (hours), with their part."""
        out: dict[str, Any] = {}
        f = [(x.factors.get("goodman"), x.link) for x in self.links]
        f = [(v, n) for v, n in f if v is not None and np.isfinite(v)]
        if f:
            out["safety_factor"] = min(f)
        life = [(b.life[1], b.joint) for b in self.bearings if b.life and np.isfinite(b.life[1])]
        if life:
            out["L10_hours"] = min(life)
        return out

    def to_json(self) -> dict[str, Any]:
        return {
            "angles": _list(self.angles),
            "bearings": {b.joint: b.to_json() for b in self.bearings},
            "pins": {p.joint: p.to_json() for p in self.pins},
            "links": {x.link: x.to_json() for x in self.links},
            "warnings": list(self.warnings),
        }
