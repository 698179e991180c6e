"""The balancing moment three ways: Joukowski's lever, the power method, the solution.

A course design checks the balancing moment M_b (平衡力矩) of its kinetostatic solution
twice (docs/methods.md, "The balancing moment, three ways"):

- **Joukowski's lever** (杠杆法): every load — the applied forces and couples, the weight
  and the d'Alembert inertia force −m a_S of each link at its centre of mass, its inertia
  couple −J_S α — turned by +90° (counter-clockwise) and applied at its point's image in
  the velocity polygon (the image of point P is v_P, in m/s, with the pole at the origin).
  The moment of a turned force F′ at image p about the pole is p × F′ = F·v_P; a couple M
  on link k maps to the couple M·ω_k on the polygon (the link's image is the link turned
  by 90° and scaled by ω_k).  The polygon, rigid, is in equilibrium: the moments sum to
  zero with the driving effort's, M_b·ċ, ċ the relative speed of the joint that carries
  the effort (ω_1 of a crank; a slide's speed for a prismatic driver, whose balancing
  effort is a force).
- **The power method** (功率法): M_b·ċ + Σ(F·v + M·ω) = 0 from the generalized forces of
  the loads against q̇ (:func:`~kinetostatics.kinetics.inverse.load_powers`, the pieces of
  the result's power balance), computed apart from the lever's points.
- **The solution**: the driver's frictionless effort column (``motor.torque``,
  ``motor.force``) of the Newton–Euler solution.

Both methods are frictionless rigid-body methods: with friction in the file the record
compares them with the frictionless column and says so.  With several motion drivers,
the other drivers' efforts are taken from the solution and their power counted as a load.
:func:`lever_stage` is the stage; :class:`BalancingMoment` its record.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.results import Result
from ..base.geometry import perp
from ..kinematics.motion import Motion
from ..kinematics.schedule import schedule
from ..kinematics.state import point_state
from ..kinetics.elements import element_states
from ..kinetics.forces import applied_loads, effort_forces
from ..kinetics.inverse import load_powers, loads
from ..kinetics.reactions import effort_joints, effort_speeds
from ..structure.system import System
from .records import asked_rows, json_float

__all__ = ["LeverTerm", "LeverPosition", "BalancingMoment", "lever_stage"]


def _pair(v) -> list[float | None] | None:
    return None if v is None else [json_float(v[0]), json_float(v[1])]


@dataclass(frozen=True)
class LeverTerm:
    """One load on Joukowski's lever at one position.

    A force: ``force`` (N) at ``point`` (m, global) of ``link``, ``turned`` (+90°), its
    ``image`` in the velocity polygon (m/s, pole at the origin); a couple: ``couple``
    (N·m) on ``link``, turning at ``omega`` (rad/s, relative to the other link of its
    joint for a resisting torque).  ``moment`` (W, the polygon's N·m·s⁻¹) about the pole:
    image × turned force, or couple·ω.  A spring's, damper's or effort driver's term has
    only its ``moment`` (its power, the pair of forces along it)."""

    name: str
    kind: str  # "force", "couple" or "power"
    link: str
    moment: float
    point: tuple[float, float] | None = None
    force: tuple[float, float] | None = None
    turned: tuple[float, float] | None = None
    image: tuple[float, float] | None = None
    couple: float | None = None
    omega: float | None = None

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"name": self.name, "kind": self.kind, "link": self.link}
        if self.kind == "force":
            out.update(
                point=_pair(self.point),
                force=_pair(self.force),
                turned=_pair(self.turned),
                image=_pair(self.image),
            )
        elif self.kind == "couple":
            out.update(couple=json_float(self.couple), omega=json_float(self.omega))
        out["moment"] = json_float(self.moment)
        return out


@dataclass(frozen=True)
class LeverPosition:
    """The balancing effort at one row: the lever's ``terms``, the effort joint's relative
    speed ``speed`` (rad/s or m/s), the other motion drivers' power ``others`` (W, from the
    solution), M_b by the ``lever``, by the ``power`` method and from the ``solution``,
    and their relative differences (over ``scale``: the largest of |M_b| of the solution
    there, Σ|term moments|/|speed| and the largest |M_b| over the result's rows); NaN
    where the effort joint is at rest (no M_b by power) or the solution has none (a
    singular position)."""

    row: int
    label: str
    coordinate: float  # the driver's coordinate, deg (mm for a prismatic driver)
    terms: tuple[LeverTerm, ...]
    speed: float
    others: float
    lever: float
    power: float
    solution: float
    scale: float

    @property
    def lever_error(self) -> float:
        return abs(self.lever - self.solution) / self.scale

    @property
    def power_error(self) -> float:
        return abs(self.power - self.solution) / self.scale

    @property
    def lever_power_error(self) -> float:
        return abs(self.lever - self.power) / self.scale

    def to_dict(self) -> dict[str, Any]:
        return {
            "row": self.row,
            "label": self.label,
            "coordinate": json_float(self.coordinate),
            "speed": json_float(self.speed),
            "others": json_float(self.others),
            "terms": [t.to_dict() for t in self.terms],
            "lever_sum": json_float(sum(t.moment for t in self.terms)),
            "M_b": {
                "lever": json_float(self.lever),
                "power": json_float(self.power),
                "solution": json_float(self.solution),
            },
            "relative_difference": {
                "lever_solution": json_float(self.lever_error),
                "power_solution": json_float(self.power_error),
                "lever_power": json_float(self.lever_power_error),
            },
        }


@dataclass(frozen=True)
class BalancingMoment:
    """The record of :func:`lever_stage`: the balancing effort of motion driver ``driver``
    (its solution column ``effort``, unit ``unit``: N·m, or N for a force), carried by
    joint ``joint``, at each position asked for; ``friction``: the note that the model
    has friction and the frictionless column is compared (empty without friction)."""

    driver: str
    effort: str
    unit: str
    joint: str
    positions: tuple[LeverPosition, ...]
    friction: str = ""

    @property
    def max_difference(self) -> float:
        """The largest relative difference of the three at the positions (NaN ignored)."""
        errs = [
            e
            for p in self.positions
            for e in (p.lever_error, p.power_error, p.lever_power_error)
            if math.isfinite(e)
        ]
        return max(errs, default=0.0)

    def to_dict(self) -> dict[str, Any]:
        return {
            "driver": self.driver,
            "effort": self.effort,
            "unit": self.unit,
            "joint": self.joint,
            "frictionless": True,
            "friction": self.friction,
            "max_relative_difference": json_float(self.max_difference),
            "positions": [p.to_dict() for p in self.positions],
        }


# -- the lever's terms ------------------------------------------------------------------
def _force_term(name, link, q, qd, k, local, force) -> LeverTerm:
    """A force at local point ``local`` of moving link ``k``, on the lever (one row)."""
    pos, vel, _ = point_state(q, qd, None, k, np.asarray(local, dtype=float))
    turned = perp(np.asarray(force, dtype=float))
    moment = vel[0] * turned[1] - vel[1] * turned[0]  # image × turned force about the pole
    return LeverTerm(
        name,
        "force",
        link,
        float(moment),
        point=(float(pos[0]), float(pos[1])),
        force=(float(force[0]), float(force[1])),
        turned=(float(turned[0]), float(turned[1])),
        image=(float(vel[0]), float(vel[1])),
    )


def _couple_term(name, link, couple, omega) -> LeverTerm:
    return LeverTerm(
        name, "couple", link, float(couple * omega), couple=float(couple), omega=float(omega)
    )


def _link_terms(system: System, q, qd, qdd) -> list[LeverTerm]:
    """Each moving link's weight and inertia force at its centre of mass, and its inertia
    couple (one row)."""
    model, out = system.model, []
    g = np.asarray(model.gravity, dtype=float)
    for k, name in enumerate(system.links):
        link = model.link(name)
        m, j = float(link.mass), float(link.inertia)
        _, _, acc = point_state(q, qd, qdd, k, np.zeros(2))
        if m and np.any(g):
            out.append(_force_term(f"{name}.weight", name, q, qd, k, (0.0, 0.0), m * g))
        if m:
            out.append(_force_term(f"{name}.inertia_force", name, q, qd, k, (0.0, 0.0), -m * acc))
        if j:
            alpha, omega = qdd[3 * k + 2], qd[3 * k + 2]
            out.append(_couple_term(f"{name}.inertia_couple", name, -j * alpha, omega))
    return out


def _load_terms(system: System, q, qd, psi: float, extremes, ref_speed) -> list[LeverTerm]:
    """The external loads as they act at the row, springs, dampers and effort drivers."""
    out = []
    for a in applied_loads(system, q, qd, np.asarray(psi), extremes, ref_speed):
        link = system.links[a.link]
        if a.couple is None:
            out.append(_force_term(a.name, link, q, qd, a.link, a.point, a.force))
            continue
        omega = qd[3 * a.link + 2] - (0.0 if a.other is None else qd[3 * a.other + 2])
        out.append(_couple_term(a.name, link, a.couple, omega))
    if system.model.elements:
        states = element_states(system, q, qd)
        for name, power in states.power.items():  # the force pair along it: −f ṡ
            out.append(LeverTerm(name, "power", "", -float(power)))
    if any(d.effort is not None for d in system.model.drivers):
        power = float(effort_forces(system, q, qd) @ qd)
        out.append(LeverTerm("efforts", "power", "", power))
    return out


# -- the stage ---------------------------------------------------------------------------


def _effort_column(result: Result, i: int) -> tuple[str, str, str]:
    """The solution's effort column of motion driver ``i``, its unit and joint."""
    system = result.system
    d = system.motion_drivers[i]
    joint = system.model.joints[effort_joints(system)[i]]
    col = f"{d.name}.{'torque' if joint.angular else 'force'}"
    return col, result.units[col], joint.name


def _power_method(result: Result, ks: np.ndarray, ref_speed: float) -> np.ndarray:
    """Σ(F·v + M·ω) of every load at rows ``ks``, from the loads' generalized forces."""
    system, t = result.system, np.asarray(result.t)[ks]
    psi = schedule(system)(t)[0]
    motion = Motion(t, psi, result.q[ks], result.qd[ks], result.qdd[ks])
    q_loads = loads(system, motion, result.extremes, ref_speed)
    taken = load_powers(system, motion, q_loads)  # what the drivers put in
    return -sum(v for v in taken.values() if v is not None)


def lever_stage(result: Result, rows: Sequence[int | tuple[str, int]], driver: int = 0):
    """The balancing effort of motion driver ``driver`` (its index, the first by default)
    by Joukowski's lever, by the power method and from the solution at ``rows``: row
    indices, or ``(label, row)`` pairs as ``course_positions(result)`` gives them (a
    caller resolves a course-position label with ``row_at(result, label=…)``).

    Returns a :class:`BalancingMoment`.  Raises ``ValueError`` for a result without
    efforts (kinematics only)."""
    system = result.system
    if not system.motion_drivers or result.lam.shape[-1] <= system.n_joint_rows:
        raise ValueError("the balancing effort needs a result with efforts (not kinematics only)")
    col, unit, joint = _effort_column(result, driver)
    asked = asked_rows(result, rows)
    ks = np.array([k for _, k in asked], dtype=int)
    ref_speed = schedule(system).reference
    speeds = effort_speeds(system, result.q[ks], result.qd[ks])  # the efforts' joints'
    efforts = result.lam[ks, system.n_joint_rows :]
    others = np.sum(np.delete(efforts * speeds, driver, axis=-1), axis=-1)
    loads_power = _power_method(result, ks, ref_speed)
    angular = system.motion_drivers[0].joint.angular
    coords = np.asarray(result.coordinate)[ks]
    coords = np.degrees(coords) if angular else coords * 1e3
    peak = float(np.nanmax(np.abs(result[col]), initial=0.0))  # the effort's scale
    positions = []
    for n, (label, k) in enumerate(asked):
        q, qd, qdd = result.q[k], result.qd[k], result.qdd[k]
        terms = _link_terms(system, q, qd, qdd)
        terms += _load_terms(system, q, qd, result.coordinate[k], result.extremes, ref_speed)
        moments = sum(t.moment for t in terms)
        speed = float(speeds[n, driver])
        with np.errstate(divide="ignore", invalid="ignore"):
            lever = -(moments + others[n]) / speed if speed else math.nan
            power = -(loads_power[n] + others[n]) / speed if speed else math.nan
            solution = float(result[col][k])
            spread = sum(abs(t.moment) for t in terms) / abs(speed) if speed else math.nan
        scale = max(abs(solution), spread, peak, np.finfo(float).tiny)
        positions.append(
            LeverPosition(
                k, label, float(coords[n]), tuple(terms), speed, float(others[n]),
                float(lever), float(power), solution, float(scale),
            )
        )  # fmt: skip
    friction = ""
    if system.model.has_friction:
        friction = (
            f"the model has friction; the lever and power methods are frictionless: "
            f"compared with the frictionless column {col}, not {col}_friction"
        )
    name = system.motion_drivers[driver].name
    return BalancingMoment(name, col, unit, joint, tuple(positions), friction)
