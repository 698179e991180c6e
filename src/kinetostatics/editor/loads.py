"""The loads of the free-body view over every row at once: the drawing's
(:mod:`kinetostatics.outputs.plotting.draw`) reactions at the joints, d'Alembert inertia
forces and couples, weights, the external loads while they act and the balancing effort,
as arrays over the rows.

Each is an :class:`Arrow`: its kind (the drawing's colours), its label (``F_R61``,
``F_I3``, ``M_I3``, ``G5``, the load's name, ``M_b``), where it acts ``(n, 2)`` (m), its
force ``(n, 2)`` (N) or its couple ``(n,)`` (N·m), and the rows where it acts.  The forces
are the result's columns and the rows' formulas (:mod:`kinetostatics.kinetics.forces`),
as in the drawing; nothing is solved here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kinetics.forces import activity, point_state
from ..kinetics.kinds import LOAD_KINDS
from ..outputs.labels import reaction_symbol
from ..outputs.plotting.rows import link_numbers
from ..outputs.plotting.scene import _joint_point, _to_global

__all__ = ["Arrow", "arrows"]


@dataclass(frozen=True)
class Arrow:
    """One load over the rows (module docstring); ``force`` None for a couple."""

    kind: str
    label: str
    at: np.ndarray  # (n, 2) m
    force: np.ndarray | None  # (n, 2) N
    moment: np.ndarray | None  # (n,) N·m
    active: np.ndarray  # (n,) bool


def _column(result, name: str, suffix: str) -> np.ndarray:
    """The column ``name + suffix`` (with friction), or ``name`` where it has none."""
    key = f"{name}{suffix}" if f"{name}{suffix}" in result.columns else name
    return np.asarray(result[key], float)


def _reactions(result, suffix: str, on) -> list[Arrow]:
    nums = link_numbers(result.system)
    out = []
    for j in result.system.model.joints:
        at = _joint_point(result, j)
        if at is None or f"{j.name}.Fx" not in result.columns:
            continue
        F = np.stack(
            [_column(result, f"{j.name}.Fx", suffix), _column(result, f"{j.name}.Fy", suffix)], -1
        )
        out.append(Arrow("reaction", reaction_symbol(j.links, nums), np.asarray(at), F, None, on))
    return out


def _bodies(result, on) -> list[Arrow]:
    """Inertia forces and couples and the weights of the links with mass."""
    system, model = result.system, result.system.model
    nums = link_numbers(system)
    g = np.asarray(model.gravity, float)
    out = []
    for k, n in enumerate(system.links):
        lk = model.link(n)
        S = np.asarray(_to_global(result, n, np.zeros(2)))
        if lk.mass > 0:
            a = result.qdd[:, 3 * k : 3 * k + 2]
            out.append(Arrow("inertia", f"F_I{nums[n]}", S, -lk.mass * a, None, on))
            if np.any(g):
                out.append(
                    Arrow(
                        "gravity", f"G{nums[n]}", S, np.broadcast_to(lk.mass * g, S.shape), None, on
                    )
                )
        if lk.inertia > 0:
            M = -lk.inertia * result.qdd[:, 3 * k + 2]
            out.append(Arrow("inertia", f"M_I{nums[n]}", S, None, M, on))
    return out


def _external(result) -> list[Arrow]:
    system, model = result.system, result.system.model
    d = system.motion_drivers[0]
    ref = abs(d.driver.motion.speed)
    q, qd, psi = result.q, result.qd, result.coordinate
    period = 2 * math.pi if d.joint.angular else None
    out = []
    for load in model.loads:
        act = np.asarray(activity(system, load, q, qd, psi, result.extremes, ref), bool)
        value = np.asarray(load.value_at(psi, period))
        k = system.link_index(load.link)
        p = model.link(load.link).points[load.point] if load.point else np.zeros(2)
        pos = np.asarray(point_state(q, qd, None, k, p)[0])
        force, couple = LOAD_KINDS[load.kind].applied(system, load, q, qd, value, ref)
        if couple is not None:
            M = np.broadcast_to(np.asarray(couple, float), act.shape)
            out.append(Arrow("external", load.name, pos, None, M, act))
        else:
            F = np.broadcast_to(np.asarray(force, float), pos.shape)
            out.append(Arrow("external", load.name, pos, F, None, act))
    return out


def _efforts(result, suffix: str, on) -> list[Arrow]:
    system, model = result.system, result.system.model
    out = []
    for d in system.motion_drivers:
        joint = model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        at = _joint_point(result, joint)
        if not joint.angular or at is None:
            continue
        e = _column(result, f"{d.name}.torque", suffix)
        name = "M_b" if len(system.motion_drivers) == 1 else f"M_b {d.name}"
        out.append(Arrow("effort", name, np.asarray(at), None, e, on))
    return out


def arrows(result, *, friction: bool = False) -> list[Arrow]:
    """Every load of the drawing's free-body view over all rows (with friction: the
    reactions and efforts of the consistent friction solution)."""
    on = np.ones(len(result), bool)
    suffix = "_friction" if friction else ""
    return [
        *_reactions(result, suffix, on),
        *_bodies(result, on),
        *_external(result),
        *_efforts(result, suffix, on),
    ]
