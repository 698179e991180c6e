"""The loads' switching state on an integration piece and the switching functions.

An integration piece of :func:`~kinetostatics.dynamics.simulate` holds the loads'
switching state it started with (:func:`load_mode`): the system with those loads
held fixed (:func:`frozen_loads`) has a smooth right-hand side that continues smoothly
past the next switch, which is a root of one of the :func:`switching_functions`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ..kinematics.state import point_state
from ..kinetics.conditions import ZERO_SPEED, activity, condition_values, switch_levels
from ..kinetics.forces import resisting_torque_other, zero_speed
from ..structure.system import System, coordinate_gradient

__all__ = ["load_mode", "frozen_loads", "switching_functions"]


def load_mode(
    system: System,
    loads: Sequence,
    q: np.ndarray,
    qd: np.ndarray,
    psi: np.ndarray,
    extremes: dict,
    ref_speed: float,
) -> tuple:
    """The loads' switching state at a state (q, qd, psi): per load, whether it is
    active and (a resistance) the sign of the velocity it opposes."""
    out = []
    for load in loads:
        on = bool(activity(system, load, q, qd, psi[0], extremes, ref_speed))
        sign = 0.0
        if load.kind == "resistance":
            k = system.link_index(load.link)
            p = system.model.link(load.link).points[load.point] if load.point else np.zeros(2)
            v = float(point_state(q, qd, None, k, p)[1] @ load.axis)
            sign = float(np.sign(v)) if abs(v) > zero_speed(system, ref_speed) else 0.0
        elif load.kind == "resisting_torque":
            w = float(_relative_omega(system, load, qd))
            sign = float(np.sign(w)) if abs(w) > ZERO_SPEED * ref_speed else 0.0
        out.append((on, sign))
    return tuple(out)


def frozen_loads(system: System, loads: Sequence, mode: tuple) -> System:
    """The system whose loads are those of ``mode``, held fixed: an active load
    without its conditions (a resistance as the constant force it is on this
    piece), an inactive one left out; so the right-hand side is smooth on a piece
    and continues smoothly past its end (where the events are located)."""
    out = []
    for load, (on, sign) in zip(loads, mode):
        if not on or (load.kind in ("resistance", "resisting_torque") and sign == 0.0):
            continue
        if load.kind == "resisting_torque":  # the couple −M·sign on the link, +M·sign on
            # the other link of its joint
            table = None if load.table is None else (load.table[0], -sign * load.table[1])
            torque = replace(
                load, kind="torque", active=(), table=table, value=-sign * load.value, joint=None
            )
            out.append(torque)
            if resisting_torque_other(system, load) is not None:
                j = system.model.joint(load.joint)
                other = next(x for x in j.links if x != load.link)
                reaction = replace(
                    torque,
                    name=f"{load.name}_reaction",
                    link=other,
                    value=-torque.value,
                    table=None if table is None else (table[0], -table[1]),
                )
                out.append(reaction)
            continue
        if load.kind == "resistance":
            direction = -sign * np.asarray(load.axis, dtype=float)
            table = (
                None
                if load.table is None
                else (
                    load.table[0],
                    np.asarray(load.table[1], dtype=float)[..., None] * direction,
                )
            )
            load = replace(
                load,
                kind="force",
                active=(),
                table=table,
                value=np.asarray(load.value, dtype=float)[..., None] * direction,
            )
        else:
            load = replace(load, active=())
        out.append(load)
    return replace(system, model=replace(system.model, loads=tuple(out)))


def switching_functions(
    system: System, loads: Sequence, extremes: dict, ref_speed: float, friction: bool
) -> list[tuple[str, Callable, float]]:
    """(label, f(q, qd, psi) -> value, zero threshold) of every load switch."""
    out = []
    vthr = ZERO_SPEED * ref_speed * system.l_ref
    for load in loads:
        for c in load.active:
            if c.kind == "angle":
                for b in c.bounds:
                    out.append(
                        (
                            f"{load.name}: angle {np.degrees(b):g}°",
                            lambda q, qd, psi, b=b: np.sin(psi[0] - b),
                            1e-12,
                        )
                    )
                continue
            for level, _ in switch_levels(c):  # the condition's value crosses a level
                what = "moving" if c.kind == "moving" else f"travel {level * 1e3:g} mm"
                out.append(
                    (
                        f"{load.name}: {what}",
                        lambda q, qd, psi, c=c, level=level: (
                            condition_values(system, c, q, qd, psi, extremes) - level
                        ),
                        vthr if c.kind == "moving" else 1e-9 * system.l_ref,
                    )
                )
        if load.kind == "resistance":
            k = system.link_index(load.link)
            p = system.model.link(load.link).points[load.point] if load.point else np.zeros(2)
            out.append(
                (
                    f"{load.name}: reverses",
                    lambda q, qd, psi, k=k, p=p, a=load.axis: point_state(q, qd, None, k, p)[1] @ a,
                    vthr,
                )
            )
        if load.kind == "resisting_torque":
            out.append(
                (
                    f"{load.name}: reverses",
                    lambda q, qd, psi, load=load: _relative_omega(system, load, qd),
                    ZERO_SPEED * ref_speed,
                )
            )
    if friction:
        for k, j in enumerate(system.model.joints):
            if j.has_friction:
                thr = ZERO_SPEED * ref_speed * (1.0 if j.angular else system.l_ref)
                out.append(
                    (
                        f"{j.name}: friction reverses",
                        lambda q, qd, psi, k=k: coordinate_gradient(system, q, k) @ qd,
                        thr,
                    )
                )
    return out


def _relative_omega(system: System, load, qd: np.ndarray) -> np.ndarray:
    """The angular velocity a resisting torque opposes: its link's, less that of the
    other link of its ``joint``."""
    w = qd[..., 3 * system.link_index(load.link) + 2]
    other = resisting_torque_other(system, load)
    return w if other is None else w - qd[..., 3 * other + 2]
