"""The kinds of load and of load condition: one entry per kind, all the code knows of it.

:data:`LOAD_KINDS` maps a :class:`~kinetostatics.model.Load`'s ``kind`` (``force``,
``torque``, ``resistance``, ``resisting_torque``) to a :class:`LoadKind`: the force or
couple it applies (:meth:`LoadKind.applied`), the rate it opposes and where that rate is
at rest (:meth:`LoadKind.rate`, :meth:`LoadKind.zero`), the loads it is on an
integration piece where that rate keeps its sign (:meth:`LoadKind.held`).
:data:`CONDITION_KINDS` maps a :class:`~kinetostatics.model.Condition`'s ``kind``
(``moving``, ``travel``, ``angle``) to a :class:`ConditionKind`: the quantity that decides
it (:meth:`ConditionKind.state`), whether it holds (:meth:`ConditionKind.holds`), the
levels where it switches (:meth:`ConditionKind.levels`) and its switching functions for
forward dynamics (:meth:`ConditionKind.switches`).

``kinetics/forces.py``, ``kinetics/conditions.py``, ``dynamics/switching.py``,
``analysis/switches.py`` and the pictures ask these entries, never the kind's name; a new
kind is one class here and its entry (``tests/kinetics/test_loads_and_differences.py`` checks that
every kind the loader accepts has one).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import replace
from typing import ClassVar

import numpy as np

from ..kinematics.state import local_point, point_state
from ..model import Condition, Load
from ..structure.system import System, kept_pose

__all__ = [
    "ZERO_SPEED",
    "LoadKind",
    "ConditionKind",
    "LOAD_KINDS",
    "CONDITION_KINDS",
    "zero_speed",
    "resisting_torque_other",
    "resisting_torque",
    "angle_band",
]

ZERO_SPEED = 1e-9  # relative speeds below this × x_ref count as zero (docs/conventions.md)


def zero_speed(system: System, ref_speed: float) -> float:
    """The point speed (m/s) at or below which a point is at rest: 1e-9·|driver speed|·L_ref."""
    return ZERO_SPEED * ref_speed * system.l_ref


def resisting_torque_other(system: System, load) -> int | None:
    """The index of the moving link a ``resisting_torque`` reacts on (the other link of
    its ``joint``), or None (no joint, or that link is the frame)."""
    if load.joint is None:
        return None
    j = system.model.joint(load.joint)
    other = next(x for x in j.links if x != load.link)
    return None if other == system.model.ground.name else system.link_index(other)


def resisting_torque(system: System, load, qd, value, ref_speed: float, other=None):
    """The couple on ``load.link`` of a resisting torque: −M·sign(ω_rel), ω_rel the link's
    angular velocity (relative to the other link of ``load.joint``); 0 where |ω_rel| is
    zero (≤ 1e-9 of the driver speed, docs/conventions.md)."""
    k = system.link_index(load.link)
    w = qd[..., 3 * k + 2]
    if other is not None:
        w = w - qd[..., 3 * other + 2]
    sign = np.where(np.abs(w) > ZERO_SPEED * ref_speed, np.sign(w), 0.0)
    return -value * sign


# -- loads ------------------------------------------------------------------------------
class LoadKind:
    """One kind of load.

    ``couple``: it is a couple on its link (N·m), not a force at its point (N).
    ``vector``: its value is a global vector (N), not a magnitude.
    ``opposes``: it acts against a rate (its sign switches where the rate crosses zero)."""

    name: ClassVar[str]
    couple: ClassVar[bool] = False
    vector: ClassVar[bool] = False
    opposes: ClassVar[bool] = False

    def applied(self, system: System, load: Load, q, qd, value, ref_speed: float):
        """``(force, couple)`` while the load acts: the force at its point ``(..., 2)`` or
        None, the couple on its link ``(...)`` or None; ``value`` from ``load.value_at``."""
        raise NotImplementedError

    def reacts_on(self, system: System, load: Load) -> int | None:
        """The index of a moving link on which the couple's reaction acts, or None."""
        return None

    def rate(self, system: System, load: Load, q, qd, qdd=None):
        """``(rate, its time derivative or None)``: what a load that opposes acts against."""
        return None, None

    def zero(self, system: System, ref_speed: float) -> float:
        """|rate| at or below which the rate counts as zero."""
        return 0.0

    def held(self, system: System, load: Load, sign: float) -> tuple[Load, ...]:
        """The loads it is, without conditions, on a piece where its rate has ``sign``."""
        return (replace(load, active=()),)


class _Force(LoadKind):
    name = "force"
    vector = True

    def applied(self, system, load, q, qd, value, ref_speed):
        return value, None


class _Torque(LoadKind):
    name = "torque"
    couple = True

    def applied(self, system, load, q, qd, value, ref_speed):
        return None, value


class _Resistance(LoadKind):
    """Magnitude ``value`` along ``axis``, against the point's velocity along it."""

    name = "resistance"
    opposes = True

    def rate(self, system, load, q, qd, qdd=None):
        _, vel, acc = _point(system, load, q, qd, qdd)
        return vel @ load.axis, None if acc is None else acc @ load.axis

    def zero(self, system, ref_speed):
        return zero_speed(system, ref_speed)

    def applied(self, system, load, q, qd, value, ref_speed):
        v = self.rate(system, load, q, qd)[0]
        sign = np.where(np.abs(v) > self.zero(system, ref_speed), np.sign(v), 0.0)
        return -(value * sign)[..., None] * load.axis, None

    def held(self, system, load, sign):
        direction = -sign * np.asarray(load.axis, dtype=float)
        table = (
            None
            if load.table is None
            else (load.table[0], np.asarray(load.table[1], dtype=float)[..., None] * direction)
        )
        value = np.asarray(load.value, dtype=float)[..., None] * direction
        return (replace(load, kind="force", active=(), table=table, value=value),)


class _ResistingTorque(LoadKind):
    """Magnitude ``value`` against the link's angular velocity (relative to the other link
    of ``joint``, on which the reaction acts)."""

    name = "resisting_torque"
    couple = True
    opposes = True

    def reacts_on(self, system, load):
        return resisting_torque_other(system, load)

    def rate(self, system, load, q, qd, qdd=None):
        k, other = system.link_index(load.link), resisting_torque_other(system, load)
        w = qd[..., 3 * k + 2]
        a = None if qdd is None else qdd[..., 3 * k + 2]
        if other is not None:
            w = w - qd[..., 3 * other + 2]
            a = None if a is None else a - qdd[..., 3 * other + 2]
        return w, a

    def zero(self, system, ref_speed):
        return ZERO_SPEED * ref_speed

    def applied(self, system, load, q, qd, value, ref_speed):
        other = resisting_torque_other(system, load)
        return None, resisting_torque(system, load, qd, value, ref_speed, other)

    def held(self, system, load, sign):
        """The couple −M·sign on the link, and +M·sign on the other link of its joint."""
        table = None if load.table is None else (load.table[0], -sign * load.table[1])
        torque = replace(
            load, kind="torque", active=(), table=table, value=-sign * load.value, joint=None
        )
        if resisting_torque_other(system, load) is None:
            return (torque,)
        j = system.model.joint(load.joint)
        reaction = replace(
            torque,
            name=f"{load.name}_reaction",
            link=next(x for x in j.links if x != load.link),
            value=-torque.value,
            table=None if table is None else (table[0], -table[1]),
        )
        return torque, reaction


LOAD_KINDS: dict[str, LoadKind] = {
    k.name: k for k in (_Force(), _Torque(), _Resistance(), _ResistingTorque())
}


# -- conditions -------------------------------------------------------------------------
def _sense(system: System) -> float:
    d = system.motion_drivers
    return float(np.sign(d[0].driver.motion.speed)) if d else 1.0


def angle_band(system: System, cond: Condition) -> tuple[float, float]:
    """(from, width) of an angle condition, measured in the sense of motion (rad)."""
    width = (cond.bounds[1] - cond.bounds[0]) * _sense(system)
    return cond.bounds[0], (width if width >= 2 * np.pi else np.mod(width, 2 * np.pi))


Switch = tuple[str, Callable, float]  # (label, f(q, q̇, ψ) -> value, zero threshold)


class ConditionKind:
    """One kind of condition.

    ``extremes``: its value needs the point's travel extremes over the whole motion.
    ``at_rest_band``: it holds where its value leaves the zero-speed band (so the cycle's
    quadrature is cut at the band's edge as well as at the value's zero).
    ``scheduled``: it switches at times the schedule gives (no :meth:`levels`), so its
    bounds cannot differ between stacked variants."""

    name: ClassVar[str]
    extremes: ClassVar[bool] = False
    at_rest_band: ClassVar[bool] = False
    scheduled: ClassVar[bool] = False

    def state(self, system: System, cond: Condition, q, qd, qdd, psi, extremes):
        """``(value, rate)``: the quantity whose sign or band decides the condition and its
        time derivative (None where it has none, or without ``qdd``)."""
        raise NotImplementedError

    def holds(self, system: System, cond: Condition, value, ref_speed: float) -> np.ndarray:
        """Where the condition holds (bands inclusive), from :meth:`state`'s value."""
        raise NotImplementedError

    def levels(self, cond: Condition) -> list[tuple[float, str]]:
        """``[(level, label)]``: where the value switches the condition (none: by time)."""
        return []

    def rising(self, cond: Condition, level: float, rate) -> bool:
        """Whether the value crossing ``level`` at ``rate`` switches the condition on."""
        return rate > 0

    def noise(self, ref_speed: float) -> float:
        """The scale of the value's round-off per metre of L_ref."""
        return 1.0

    def switches(
        self, system: System, cond: Condition, extremes: dict, ref_speed: float
    ) -> list[Switch]:
        """The switching functions of forward dynamics, one per level."""
        raise NotImplementedError


def _point(system, where, q, qd, qdd):
    """The state of the point a condition or a load names (``where.link``, ``where.point``)
    at (q, q̇, q̈): once per arrays inside :func:`points_once` (a load's conditions and its
    resistance read the same point)."""
    k = system.link_index(where.link)
    p = local_point(system, where.link, where.point)
    once = system.memo.get("point states")
    if once is None:
        return point_state(q, qd, qdd, k, p, kept_pose(system, q, k))
    key = (k, p.tobytes(), qdd is None)
    hit = once.get(key)
    if hit is None or hit[0] is not q or hit[1] is not qd or hit[2] is not qdd:
        hit = once[key] = (q, qd, qdd, point_state(q, qd, qdd, k, p, kept_pose(system, q, k)))
    return hit[3]


@contextlib.contextmanager
def points_once(system: System):
    """Within: a point's state at the same arrays (the very objects, held while inside)
    computed once by :func:`_point`; the scope of one evaluation of the loads."""
    if "point states" in system.memo:  # an outer scope holds it
        yield
        return
    system.memo["point states"] = {}
    try:
        yield
    finally:
        system.memo.pop("point states", None)


class _Moving(ConditionKind):
    """The point's velocity along ``axis`` is positive."""

    name = "moving"
    at_rest_band = True

    def state(self, system, cond, q, qd, qdd, psi, extremes):
        _, vel, acc = _point(system, cond, q, qd, qdd)
        return vel @ cond.axis, None if acc is None else acc @ cond.axis

    def holds(self, system, cond, value, ref_speed):
        return value > ZERO_SPEED * ref_speed * system.l_ref

    def levels(self, cond):
        return [(0.0, "moving")]

    def noise(self, ref_speed):
        return ref_speed

    def switches(self, system, cond, extremes, ref_speed):
        def f(q, qd, psi):
            return self.state(system, cond, q, qd, None, psi, extremes)[0] - 0.0

        return [("moving", f, ZERO_SPEED * ref_speed * system.l_ref)]


class _Travel(ConditionKind):
    """The point's position along ``axis``, from its least value over the whole motion,
    lies in ``bounds`` (m)."""

    name = "travel"
    extremes = True

    def state(self, system, cond, q, qd, qdd, psi, extremes):
        pos, vel, _ = _point(system, cond, q, qd, qdd)
        return pos @ cond.axis - extremes[id(cond)], vel @ cond.axis

    def holds(self, system, cond, value, ref_speed):
        tol = ZERO_SPEED * system.l_ref
        return (value >= cond.bounds[0] - tol) & (value <= cond.bounds[1] + tol)

    def levels(self, cond):
        return [(cond.bounds[0], "travel from"), (cond.bounds[1], "travel to")]

    def rising(self, cond, level, rate):
        return rate > 0 if level == cond.bounds[0] else rate < 0

    def switches(self, system, cond, extremes, ref_speed):
        out = []
        for level, _ in self.levels(cond):

            def f(q, qd, psi, level=level):
                return self.state(system, cond, q, qd, None, psi, extremes)[0] - level

            out.append((f"travel {level * 1e3:g} mm", f, 1e-9 * system.l_ref))
        return out


class _Angle(ConditionKind):
    """The first driver's coordinate lies in ``bounds`` (rad), in the sense of motion,
    modulo 2π; it switches at times the schedule gives, not at a level of its value."""

    name = "angle"
    scheduled = True

    def state(self, system, cond, q, qd, qdd, psi, extremes):
        return np.mod((psi - cond.bounds[0]) * _sense(system), 2 * np.pi), None

    def holds(self, system, cond, value, ref_speed):
        return value <= angle_band(system, cond)[1] + 1e-12

    def switches(self, system, cond, extremes, ref_speed):
        return [
            (f"angle {np.degrees(b):g}°", lambda q, qd, psi, b=b: np.sin(psi[0] - b), 1e-12)
            for b in cond.bounds
        ]


CONDITION_KINDS: dict[str, ConditionKind] = {k.name: k for k in (_Moving(), _Travel(), _Angle())}
