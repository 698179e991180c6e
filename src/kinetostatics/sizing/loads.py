"""The loads on a link with a section, in its beam axes, from a Result's columns
(:class:`~kinetostatics.sizing.beams.BeamLoads`; docs/sizing.md, "Links").

A link is read as a beam when it has exactly two joints and both are pins: the beam joins
them (a ternary link, or a link on a slide, is reported and left out).  Its loads at each
position: the reactions of its two joints (the frictionless solution, whose joints put
no couple on the link), the external loads where they act (a couple at its joint, or at
the centre of mass), the driving torque of a motion driver at its joint, and the weight
and d'Alembert inertia — distributed along the axis when the link is uniform (its centre
of mass at mid-span), else lumped at its centre of mass.  What the link's equilibrium
leaves over (a spring, a damper, an effort driver: loads this module does not place) is
lumped at the centre of mass and reported.
"""

from __future__ import annotations

import numpy as np

from ..analysis.results import Result
from ..kinematics.schedule import schedule
from ..kinetics.forces import applied_loads
from .beams import BeamLoads

__all__ = ["beam_loads", "beam_axis"]

UNIFORM = 1e-6  # |CoM − mid-span| / L below which a link is uniform
BALANCE = 1e-7  # a residual above this share of the largest load is reported


def beam_axis(result: Result, name: str):
    """(joints, (a0, a1)) of link ``name``: its two pins and their local places (relative
    to the CoM, link frame), or (problem text, None)."""
    model = result.system.model
    joints = [j for j in model.joints if name in j.links]
    if len(joints) != 2 or not all(j.pin for j in joints):
        return (
            f"link '{name}' has {len(joints)} joints"
            + ("" if len(joints) != 2 else ", not both pins")
            + ": only a link between two pins is read as a beam",
            None,
        )
    if any(f"{j.name}.Fx" not in result.columns for j in joints):
        return f"link '{name}': a joint of it has no reaction in the result", None
    places = []
    for j in joints:
        a = next(a for a in j.anchors() if a.link == name and a.at_joint)
        places.append(np.asarray(a.xy, float))
    if not np.hypot(*(places[1] - places[0])) > 0.0:
        return f"link '{name}': its two pins coincide", None
    return joints, tuple(places)


def _col(result: Result, name: str, n: int) -> np.ndarray:
    return np.asarray(result.columns[name], float) if name in result.columns else np.zeros(n)


def beam_loads(result: Result, name: str) -> tuple[BeamLoads | None, str | None]:
    """(loads, note) of link ``name`` over ``result``'s rows: ``loads`` None with the
    reason in ``note`` where the link is not a beam; a note also where loads the module
    does not place were lumped at the centre of mass."""
    joints, places = beam_axis(result, name)
    if places is None:
        return None, joints
    model, system = result.system.model, result.system
    link, n = model.link(name), len(result)
    a0, a1 = places
    length = float(np.hypot(*(a1 - a0)))
    e_loc = (a1 - a0) / length
    n_loc = np.array([-e_loc[1], e_loc[0]])
    th = np.radians(_col(result, f"{name}.theta", n))
    c, s = np.cos(th), np.sin(th)
    e = np.stack([c * e_loc[0] - s * e_loc[1], s * e_loc[0] + c * e_loc[1]], axis=-1)
    nn = np.stack([-e[:, 1], e[:, 0]], axis=-1)

    def axes(f):  # a global force (n, 2) in the beam's axes
        return np.stack([np.sum(f * e, -1), np.sum(f * nn, -1)], axis=-1)

    def at(r):  # a local place (rel. CoM) in the beam's axes
        d = np.asarray(r, float) - a0
        return float(d @ e_loc), float(d @ n_loc)

    points, couples = [], []
    pin_of = {j.name: at(p) for j, p in zip(joints, places)}
    for k, j in enumerate(joints):
        f = np.stack([_col(result, f"{j.name}.Fx", n), _col(result, f"{j.name}.Fy", n)], -1)
        sign = 1.0 if name == j.links[1] else -1.0  # the column is i's force on j
        points.append((*pin_of[j.name], axes(sign * f), k == 1))
    _applied(result, name, pin_of, at, axes, points, couples)
    for d in system.motion_drivers:
        col = f"{d.name}.torque"
        if name in d.joint.links and col in result.columns and d.joint.name in pin_of:
            sign = 1.0 if name == d.joint.links[1] else -1.0
            couples.append((pin_of[d.joint.name][0], sign * _col(result, col, n)))
    g = np.asarray(model.gravity, float)
    m, J = link.mass, link.inertia
    acc = np.stack([_col(result, f"{name}.ax", n), _col(result, f"{name}.ay", n)], -1)
    alpha, omega = _col(result, f"{name}.alpha", n), _col(result, f"{name}.omega", n)
    distributed = None
    if m > 0 and np.hypot(*((a0 + a1) / 2)) <= UNIFORM * length:
        r0 = np.stack([c * a0[0] - s * a0[1], s * a0[0] + c * a0[1]], -1)  # CoM -> pin 0
        a_0 = acc + alpha[:, None] * np.stack([-r0[:, 1], r0[:, 0]], -1) - omega[:, None] ** 2 * r0
        distributed = (m / length, axes(g - a_0), alpha, omega**2)
        couples.append((length / 2, -(J - m * length**2 / 12) * alpha))
    elif m > 0 or J > 0:
        points.append((*at(np.zeros(2)), axes(m * (g - acc)), False))
        couples.append((at(np.zeros(2))[0], -J * alpha))
    loads = BeamLoads(length, tuple(points), tuple(couples), distributed)
    return _balanced(loads, at(np.zeros(2)), name)


def _applied(result, name, pin_of, at, axes, points, couples) -> None:
    """The external loads on link ``name`` as they act at the rows, into ``points`` and
    ``couples``."""
    system, model = result.system, result.system.model
    ref = schedule(system).reference
    coordinate = np.asarray(result.coordinate, float)
    for a in applied_loads(system, result.q, result.qd, coordinate, result.extremes, ref):
        on_link = system.links[a.link] == name
        on_other = a.other is not None and system.links[a.other] == name
        if not (on_link or on_other):
            continue
        if a.couple is None:
            points.append((*at(a.point), axes(np.asarray(a.force, float)), False))
            continue
        load = next(x for x in model.loads if x.name == a.name)
        x = pin_of[load.joint][0] if load.joint in pin_of else at(a.point)[0]
        couples.append((x, (1.0 if on_link else -1.0) * np.asarray(a.couple, float)))


def _balanced(loads: BeamLoads, com, name) -> tuple[BeamLoads, str | None]:
    """``loads`` with what the link's equilibrium leaves over lumped at its centre of mass
    ``com`` (beam axes), and a note when that is more than round-off."""
    L = loads.length
    fe = sum(f[:, 0] for _, _, f, _ in loads.points)
    fn = sum(f[:, 1] for _, _, f, _ in loads.points)
    mo = sum(x * f[:, 1] - y * f[:, 0] for x, y, f, _ in loads.points)
    mo = mo + sum(cp for _, cp in loads.couples)
    scale = max(float(np.max(np.abs(f))) for _, _, f, _ in loads.points)
    if loads.distributed is not None:
        q, u, alpha, w2 = loads.distributed
        fe = fe + q * (u[:, 0] * L + w2 * L**2 / 2)
        fn = fn + q * (u[:, 1] * L - alpha * L**2 / 2)
        mo = mo + q * (u[:, 1] * L**2 / 2 - alpha * L**3 / 3)
    left = max(float(np.max(np.abs(fe))), float(np.max(np.abs(fn))), float(np.max(np.abs(mo))) / L)
    if not left > BALANCE * max(scale, 1e-300):
        return loads, None
    x, y = com
    force = -np.stack([fe, fn], -1)
    couple = -(mo + (x * force[:, 1] - y * force[:, 0]))
    out = BeamLoads(
        L, (*loads.points, (x, y, force, False)), (*loads.couples, (x, couple)), loads.distributed
    )
    return out, (
        f"link '{name}': loads the beam does not place (springs, dampers, effort drivers; "
        f"up to {left:.3g} N) lumped at its centre of mass"
    )
