"""The dyads' transmission and pressure angles, from the poses (columns of a result)."""

from __future__ import annotations

import numpy as np

from ..kinematics.state import point_state
from ..structure.system import System

__all__ = ["dyad_angle_names", "dyad_angles", "angle_between"]


def _joint_position(system: System, q: np.ndarray, name: str) -> np.ndarray:
    """Global position of a pin: its point on link i."""
    j = system.model.joint(name)
    link = j.links[0]
    p = next(a.xy for a in j.anchors() if a.at_joint and a.link == link)
    if link == system.model.ground.name:
        return np.broadcast_to(p, q.shape[:-1] + (2,))
    k = system.link_index(link)
    return point_state(q, q, None, k, p)[0]


def _pose(system: System, q: np.ndarray, link: str) -> np.ndarray:
    """(x, y, θ) of a link, ``(..., 3)``; the frame's are zeros."""
    if link == system.model.ground.name:
        return np.zeros(q.shape[:-1] + (3,))
    k = system.link_index(link)
    return q[..., 3 * k : 3 * k + 3]


def dyad_angle_names(system: System) -> list[tuple[str, str]]:
    """(column prefix, label) of the dyads that have a transmission or pressure angle."""
    label = {"RRR": "transmission_angle", "RRP": "pressure_angle"}
    return [
        (p.group.column, label[p.group.letters])
        for p in system.plans
        if p.group.kind == "dyad" and p.group.letters in label
    ]


def angle_between(u: np.ndarray, v: np.ndarray, unsigned: bool = False) -> np.ndarray:
    """Angle between vectors ``u`` and ``v (..., 2)`` in deg, from 0 to 180° (to 90° between
    their lines when ``unsigned``); NaN where either is zero.

    atan2 of cross and dot keeps full relative precision at every angle; the arccos of
    their cosine loses half the digits near 0° and 180° (a pressure angle of 0.0007° came out
    5e-10° apart from two equal positions, 7e-7 of itself: net seed 1005175).
    """
    cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    dot = np.sum(u * v, axis=-1)
    ang = np.arctan2(np.abs(cross), np.abs(dot) if unsigned else dot)
    zero = (np.linalg.norm(u, axis=-1) == 0) | (np.linalg.norm(v, axis=-1) == 0)
    return np.degrees(np.where(zero, np.nan, ang))


def dyad_angles(system: System, q: np.ndarray) -> dict[str, tuple[str, np.ndarray]]:
    """Transmission angle of RRR dyads and pressure angle of RRP dyads, deg."""
    out = {}
    joints = {j.name: j for j in system.model.joints}
    for plan in system.plans:
        g = plan.group
        if g.kind != "dyad" or g.letters not in ("RRR", "RRP"):
            continue
        a, b = g.links
        inner = [n for n in g.joints if set(joints[n].links) == {a, b}][0]
        ext_a = [n for n in g.joints if a in joints[n].links and n != inner][0]
        ext_b = [n for n in g.joints if b in joints[n].links and n != inner][0]
        pa, pm = _joint_position(system, q, ext_a), _joint_position(system, q, inner)
        u = pa - pm
        if g.letters == "RRR":
            v = _joint_position(system, q, ext_b) - pm
            out[g.column] = ("transmission_angle", angle_between(u, v))
        else:
            s = joints[ext_b]
            qi, qj = (_pose(system, q, link) for link in s.links)
            axis = s.glyph(qi, qj).guide.direction  # the slide's axis
            out[g.column] = ("pressure_angle", angle_between(u, axis, unsigned=True))
    return out
