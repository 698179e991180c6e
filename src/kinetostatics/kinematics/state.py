"""The state of points and joints at link coordinates q (and their rates).

Every function broadcasts over leading position axes; ground enters as zeros.
"""

from __future__ import annotations

import numpy as np

from ..base.geometry import perp, rotate, turn
from ..structure.system import System, link_pair

__all__ = ["point_state", "local_point", "joint_coordinate", "joint_coordinate_bias"]


def point_state(q, qd, qdd, k: int, p: np.ndarray, pose: np.ndarray | None = None):
    """Global position, velocity, acceleration of local point ``p`` of moving link ``k``;
    ``pose``: the link's pose with its frame ``(..., 5)`` when the caller has it (the
    same numbers, without evaluating cos θ and sin θ again)."""
    th, w = q[..., 3 * k + 2], qd[..., 3 * k + 2]
    rp = rotate(th, p) if pose is None else turn(pose, p)
    pos = q[..., 3 * k : 3 * k + 2] + rp
    vel = qd[..., 3 * k : 3 * k + 2] + w[..., None] * perp(rp)
    if qdd is None:
        return pos, vel, None
    acc = (
        qdd[..., 3 * k : 3 * k + 2] + qdd[..., 3 * k + 2, None] * perp(rp) - (w**2)[..., None] * rp
    )
    return pos, vel, acc


def local_point(system: System, link: str, point: str | None) -> np.ndarray:
    """The local coordinates of a named point of ``link`` (its CoM, the origin, if None)."""
    return system.model.link(link).points[point] if point else np.zeros(2)


def joint_coordinate(system: System, q: np.ndarray, k: int) -> np.ndarray:
    """The relative coordinate of constraint ``k`` (a joint's angle or distance), ``(...)``."""
    return system.constraints[k].coordinate(*link_pair(system, q, k))


def joint_coordinate_bias(system: System, q: np.ndarray, qd: np.ndarray, k: int) -> np.ndarray:
    """b in c̈ = g·q̈ + b of constraint ``k``'s relative coordinate c, ``(...)``."""
    return system.constraints[k].coordinate_bias(
        *link_pair(system, q, k), *link_pair(system, qd, k)
    )
