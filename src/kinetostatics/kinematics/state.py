"""The state of points and joints at link coordinates q (and their rates).

Every function broadcasts over leading position axes; ground enters as zeros.
"""

from __future__ import annotations

import numpy as np

from ..base.geometry import perp, rotate
from ..structure.system import System

__all__ = ["point_state", "local_point", "joint_coordinate", "joint_coordinate_bias"]


def point_state(q, qd, qdd, k: int, p: np.ndarray):
    """Global position, velocity, acceleration of local point ``p`` of moving link ``k``."""
    th, w = q[..., 3 * k + 2], qd[..., 3 * k + 2]
    rp = rotate(th, p)
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


def _with_ground(x: np.ndarray) -> np.ndarray:
    return np.concatenate((x, np.zeros(x.shape[:-1] + (3,))), axis=-1)


def joint_coordinate(system: System, q: np.ndarray, k: int) -> np.ndarray:
    """The relative coordinate of constraint ``k`` (a joint's angle or distance), ``(...)``."""
    qe = _with_ground(q)
    i, j = system.ends[k]
    return system.constraints[k].coordinate(qe[..., 3 * i : 3 * i + 3], qe[..., 3 * j : 3 * j + 3])


def joint_coordinate_bias(system: System, q: np.ndarray, qd: np.ndarray, k: int) -> np.ndarray:
    """b in c̈ = g·q̈ + b of constraint ``k``'s relative coordinate c, ``(...)``."""
    qe, ve = _with_ground(q), _with_ground(qd)
    i, j = system.ends[k]
    return system.constraints[k].coordinate_bias(
        qe[..., 3 * i : 3 * i + 3],
        qe[..., 3 * j : 3 * j + 3],
        ve[..., 3 * i : 3 * i + 3],
        ve[..., 3 * j : 3 * j + 3],
    )
