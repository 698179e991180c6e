"""The free body and the force polygon of each Assur group, in the order of the solution.

A graphical course design (图解法) solves the forces group by group: the last Assur group
first, the driving link last; for each group it draws the free body (the loads, weights,
inertia forces and couples of its links, the reactions from the groups already solved,
known, and the reactions at its outer pairs, solved) and the force polygon, the vectors
chained tip to tail, which closes because the group is in equilibrium
(docs/methods.md, "Force polygons of the Assur groups").

Every force comes from the kinetostatic solution, nothing here knows a joint type: with A
the equilibrium matrix (:func:`~kinetostatics.kinetics.reactions.equilibrium_matrix`, the
constraint gradients Φ_qᵀ and the efforts' gradients) and λ the result's multipliers, the
generalized force of joint c on link k is ``A[k's columns, c's rows] · λ[c's rows]`` =
(F_x, F_y, M about k's centre of mass): for joint ``[i, j]`` on j it is the reaction of i
on j, the ``<joint>.Fx/.Fy`` columns (docs/conventions.md); on i its opposite.  It is drawn
on its line of action, through the point of that line nearest the joint's anchor on the
link (the pin of a revolute; a prismatic pair's force moved along the slide by M/N), or
at the anchor with a couple where it has no force or its line passes far away.  The
loads' generalized forces are itemized the same way
(:mod:`~kinetostatics.kinetics.forces`), so the polygon's closure and the group's moment
balance about a point check the solution, each independently of the other.

The forces are the frictionless solution's, or with ``friction=True`` the consistent
solution's with friction: each pair's reaction with its friction effort (the generalized
force g_k e_k of :mod:`~kinetostatics.kinetics.friction`), whose line is tangent to the
friction circle of a turning pair.
:func:`force_polygons` is the stage; :class:`ForcePolygons` its record.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.results import Result
from ..base.units import nice_scale
from ..kinematics.schedule import schedule
from ..kinematics.state import point_state
from ..kinetics import friction as fr
from ..kinetics.elements import element_states
from ..kinetics.forces import applied_loads, effort_forces
from ..kinetics.reactions import effort_joints, equilibrium_matrix
from ..structure.system import System
from .records import asked_rows, json_float

__all__ = ["GroupForce", "GroupPolygon", "PolygonPosition", "ForcePolygons", "force_polygons"]

FAR = 2.0
"""A force whose line passes farther than FAR·L_ref from its anchor is drawn at the anchor
with the moment it leaves as a couple (L_ref: the mechanism's size, docs/conventions.md)."""

POLYGON_SIZE_MM = 60.0
"""The drawn polygon's size the scale μ_F aims at: the largest extent ≤ this, in mm."""


def _pair(v) -> list[float | None]:
    return [json_float(v[0]), json_float(v[1])]


@dataclass(frozen=True)
class GroupForce:
    """One force (or couple) on a group's free body at one position.

    ``kind``: ``load``, ``weight``, ``inertia_force``, ``inertia_couple``, ``element``
    (springs and dampers), ``effort`` (an effort driver), ``reaction`` or ``balancing``
    (the driver's effort M_b, or F_b for a force); ``link`` the link it acts on, ``by`` the
    link that exerts a reaction (``joint`` its pair); ``status``: ``known`` (a load, or a
    reaction from a group solved before) or ``solved`` (found with this group).  The
    force ``vector`` (N) acts along the line through ``point`` (m, global); ``couple``
    (N·m, CCW) is what is left of the generalized force as a couple (a pure couple's
    vector is zero).  ``offset_point``: an inertia force moved off the centre of mass so
    that it carries the inertia couple too (the offset inertia force), else None.  A
    reaction with friction: ``offset``, the distance of its line from the pair's point
    ``pin`` (m), and where the pair turns ``friction_radius``, its friction circle's radius (m):
    the line is tangent to the circle (offset = radius) where the pair slides."""

    name: str
    kind: str
    link: str
    status: str
    point: tuple[float, float]
    vector: tuple[float, float]
    couple: float = 0.0
    by: str = ""
    joint: str = ""
    offset_point: tuple[float, float] | None = None
    offset: float | None = None
    friction_radius: float | None = None
    pin: tuple[float, float] | None = None

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "name": self.name,
            "kind": self.kind,
            "link": self.link,
            "status": self.status,
            "point": _pair(self.point),
            "vector": _pair(self.vector),
            "couple": json_float(self.couple),
        }
        if self.by:
            out.update(by=self.by, joint=self.joint)
        if self.offset_point is not None:
            out["offset_point"] = _pair(self.offset_point)
        if self.offset is not None:
            out.update(offset=json_float(self.offset), pin=_pair(self.pin))
        if self.friction_radius is not None:
            out["friction_radius"] = json_float(self.friction_radius)
        return out


@dataclass(frozen=True)
class GroupPolygon:
    """The free body of one group (``name``, its ``links``, ``driving`` for the driving
    link), the reactions at its ``inner`` pairs (of link i on link j, not on the free
    body: they cancel there) and its force polygon: the ``forces`` of non-zero vector
    chained tip to tail
    from the origin (``vertices``, N; the known forces first), its ``closure`` error
    |Σ F| (N) beside its ``largest`` force (N), the moment about ``pivot`` of every force
    and couple, ``moment`` (N·m, zero in equilibrium), and the round scale ``mu_F``
    (N/mm) that draws the polygon at most :data:`POLYGON_SIZE_MM` across; the group's
    ``kind`` (``driven``, ``dyad``, ``triad``, ``group``) and a dyad's pair ``letters``
    (``RPR``) for the outputs to name it in their language (``label`` is the English)."""

    name: str
    label: str
    links: tuple[str, ...]
    driving: bool
    forces: tuple[GroupForce, ...]
    inner: tuple[GroupForce, ...]
    vertices: tuple[tuple[float, float], ...]
    closure: float
    largest: float
    pivot: tuple[float, float]
    moment: float
    moment_scale: float
    mu_F: float
    kind: str = ""
    letters: str = ""

    @property
    def closure_error(self) -> float:
        """|Σ F| over the largest force (0 for a group without forces)."""
        return self.closure / self.largest if self.largest > 0 else 0.0

    @property
    def moment_error(self) -> float:
        """|Σ M about the pivot| over the moments' scale (0 without any)."""
        return abs(self.moment) / self.moment_scale if self.moment_scale > 0 else 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "group": self.name,
            "label": self.label,
            "kind": self.kind,
            "letters": self.letters,
            "links": list(self.links),
            "driving": self.driving,
            "forces": [f.to_dict() for f in self.forces],
            "inner": [f.to_dict() for f in self.inner],
            "vertices": [_pair(v) for v in self.vertices],
            "closure": json_float(self.closure),
            "largest": json_float(self.largest),
            "closure_error": json_float(self.closure_error),
            "pivot": _pair(self.pivot),
            "moment": json_float(self.moment),
            "moment_error": json_float(self.moment_error),
            "mu_F": json_float(self.mu_F),
        }


@dataclass(frozen=True)
class PolygonPosition:
    """The groups' free bodies and polygons at one row, in the order of the solution
    (the last group first, the driving link last)."""

    row: int
    label: str
    groups: tuple[GroupPolygon, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "row": self.row,
            "label": self.label,
            "groups": [g.to_dict() for g in self.groups],
        }


@dataclass(frozen=True)
class ForcePolygons:
    """The record of :func:`force_polygons`: the ``positions`` asked for; ``friction``:
    the note that the file has friction and the frictionless forces are drawn;
    ``with_friction``: the forces are the consistent solution's with friction."""

    positions: tuple[PolygonPosition, ...]
    friction: str = ""
    with_friction: bool = False

    @property
    def max_closure_error(self) -> float:
        return max((g.closure_error for p in self.positions for g in p.groups), default=0.0)

    def to_dict(self) -> dict[str, Any]:
        return {
            "frictionless": not self.with_friction,
            "friction": self.friction,
            "max_closure_error": json_float(self.max_closure_error),
            "positions": [p.to_dict() for p in self.positions],
        }


# -- a generalized force as a force on its line, or a couple ------------------------------
def _on_line(gen, centre, anchor, far: float) -> tuple[tuple, tuple, float]:
    """(point, vector, couple) of the generalized force ``gen`` = (F_x, F_y, M about
    ``centre``): the force through the point of its line nearest ``anchor``; where that
    line passes farther than ``far`` (m) from the anchor (a force nil beside its moment, a
    slide's small normal force with a large couple), the force at the anchor and the
    moment it leaves as a couple."""
    f = np.asarray(gen[:2], dtype=float)
    anchor = np.asarray(anchor, dtype=float)
    arm = anchor - centre
    rest = float(gen[2] - (arm[0] * f[1] - arm[1] * f[0]))  # the moment left about anchor
    f2 = float(f @ f)
    vector = (float(f[0]), float(f[1]))
    if abs(rest) >= far * math.sqrt(f2):  # the line is beyond reach (or there is no force)
        return (float(anchor[0]), float(anchor[1])), vector, rest
    t = -rest / f2  # anchor + t·perp(F): its moment about anchor is −t|F|²
    point = anchor + t * np.array([-f[1], f[0]])
    return (float(point[0]), float(point[1])), vector, 0.0


def _anchor(system: System, joint, link: int, q) -> np.ndarray:
    """The global point of ``joint``'s anchor on moving link ``link`` (its first named
    point on that link, at the joint if one is), else the link's centre of mass."""
    name = system.links[link]
    own = [a for a in joint.anchors() if a.link == name]
    own.sort(key=lambda a: not a.at_joint)
    local = own[0].xy if own else np.zeros(2)
    return point_state(q, q * 0, None, link, np.asarray(local, dtype=float))[0]


# -- the forces on each link ---------------------------------------------------------------
def _link_loads(system: System, result: Result, k: int, ref_speed: float, far: float) -> dict:
    """Every load on each moving link at row ``k``: ``{link: [GroupForce]}`` (an inertia
    force offset by at most ``far``, m)."""
    q, qd, qdd = result.q[k], result.qd[k], result.qdd[k]
    out: dict[int, list] = {n: [] for n in range(len(system.links))}
    g = np.asarray(system.model.gravity, dtype=float)
    for n, name in enumerate(system.links):
        link = system.model.link(name)
        m, j = float(link.mass), float(link.inertia)
        c, _, acc = point_state(q, qd, qdd, n, np.zeros(2))
        cm = (float(c[0]), float(c[1]))
        if m and np.any(g):
            w = (float(m * g[0]), float(m * g[1]))
            out[n].append(GroupForce(f"G_{name}", "weight", name, "known", cm, w))
        couple = -j * float(qdd[3 * n + 2])
        if m:
            f = -m * acc
            moved = _on_line((f[0], f[1], couple), c, c, far)
            offset = moved[0] if couple and not moved[2] else None
            out[n].append(
                GroupForce(
                    f"F_I_{name}", "inertia_force", name, "known", cm,
                    (float(f[0]), float(f[1])), offset_point=offset,
                )
            )  # fmt: skip
        if j:
            out[n].append(
                GroupForce(f"M_I_{name}", "inertia_couple", name, "known", cm, (0.0, 0.0), couple)
            )
    _applied(system, result, k, ref_speed, out)
    _generalized(system, q, qd, out)
    return out


def _applied(system: System, result: Result, k: int, ref_speed: float, out) -> None:
    """The external loads of the model as they act at row ``k``, into ``out``."""
    q, qd = result.q[k], result.qd[k]
    for a in applied_loads(system, q, qd, np.asarray(result.coordinate[k]), result.extremes,
                           ref_speed):  # fmt: skip
        name = system.links[a.link]
        pos = point_state(q, qd, None, a.link, a.point)[0]
        point = (float(pos[0]), float(pos[1]))
        if a.couple is None:
            f = (float(a.force[0]), float(a.force[1]))
            out[a.link].append(GroupForce(a.name, "load", name, "known", point, f))
            continue
        out[a.link].append(GroupForce(a.name, "load", name, "known", point, (0.0, 0.0),
                                      float(a.couple)))  # fmt: skip
        if a.other is not None:
            other = system.links[a.other]
            c = point_state(q, qd, None, a.other, np.zeros(2))[0]
            out[a.other].append(GroupForce(f"{a.name}'", "load", other, "known",
                                           (float(c[0]), float(c[1])), (0.0, 0.0),
                                           -float(a.couple)))  # fmt: skip


def _generalized(system: System, q, qd, out) -> None:
    """The springs' and dampers' and the effort drivers' generalized forces on each link,
    as a force through its centre of mass and a couple, into ``out``."""
    parts = []
    if system.model.elements:
        parts.append(("elements", "element", element_states(system, q, qd).q))
    if any(d.effort is not None for d in system.model.drivers):
        parts.append(("efforts", "effort", effort_forces(system, q, qd)))
    for label, kind, gen in parts:
        for n, name in enumerate(system.links):
            g = gen[3 * n : 3 * n + 3]
            if not np.any(g):
                continue
            c = q[3 * n : 3 * n + 2]
            cm = (float(c[0]), float(c[1]))
            out[n].append(
                GroupForce(f"{label}_{name}", kind, name, "known", cm,
                           (float(g[0]), float(g[1])), float(g[2]))
            )  # fmt: skip


def _pair_forces(system: System, q, lam, a, far: float, fric: dict) -> list[tuple]:  # noqa: PLR0913  the row's arrays
    """``(joint index, on, by, point, vector, couple, kind, name)`` of every joint's and
    effort's force on each of its moving links at one row; ``fric``: each joint's friction
    effort as a generalized force ``(n_q,)`` (empty without friction)."""
    out = []
    ground, n_j = len(system.links), len(system.model.joints)
    for c in range(n_j):
        joint, rows = system.model.joints[c], system.rows_of(c)
        for on, by in (tuple(system.ends[c]), tuple(system.ends[c])[::-1]):
            if on == ground:
                continue
            gen = a[3 * on : 3 * on + 3, rows] @ lam[rows]
            extra = {}
            if c in fric:
                gen = gen + fric[c][3 * on : 3 * on + 3]
                extra = _circle(system, c, q, lam, gen, on)
            anchor = _anchor(system, joint, on, q)
            line = _on_line(gen, q[3 * on : 3 * on + 2], anchor, far)
            out.append((c, on, by, *line, "reaction", joint.name, extra))
    for d, c in enumerate(effort_joints(system)):
        joint = system.model.joints[c]
        symbol = "M_b" if joint.angular else "F_b"
        for on, by in (tuple(system.ends[c]), tuple(system.ends[c])[::-1]):
            if on == ground:
                continue
            gen = a[3 * on : 3 * on + 3, system.n_joint_rows + d] * lam[system.n_joint_rows + d]
            line = _on_line(gen, q[3 * on : 3 * on + 2], _anchor(system, joint, on, q), far)
            name = f"{symbol}:{system.motion_drivers[d].name}"
            out.append((c, on, by, *line, "balancing", name, {}))
    return out


def _circle(system: System, c: int, q, lam, gen, on: int) -> dict:
    """A reaction with friction: the distance of its line from the pair's point on link
    ``on`` (``offset``, m), and for a pair that turns, the radius of its friction circle
    (``friction_radius``, m): the joint's friction magnitude (ρ|F|) over |F|."""
    joint = system.model.joints[c]
    f = float(np.hypot(gen[0], gen[1]))
    if not f:
        return {}
    centre, pin = q[3 * on : 3 * on + 2], _anchor(system, joint, on, q)
    arm = pin - centre
    offset = abs(float(gen[2] - (arm[0] * gen[1] - arm[1] * gen[0]))) / f
    out: dict[str, Any] = {"offset": offset, "pin": (float(pin[0]), float(pin[1]))}
    if joint.angular:
        qe = np.concatenate((q, np.zeros(3)))
        i, j = system.ends[c]
        mag = joint.friction_magnitude(lam[system.rows_of(c)], qe[3 * i : 3 * i + 3],
                                       qe[3 * j : 3 * j + 3])  # fmt: skip
        out["friction_radius"] = float(mag) / f
    return out


# -- the groups ----------------------------------------------------------------------------
_ORDER = {"load": 0, "weight": 0, "element": 0, "effort": 0, "inertia_force": 1,
          "inertia_couple": 1, "reaction": 2, "balancing": 3}  # fmt: skip


def _body(system: System, p: int, loads: dict, pairs: list) -> tuple[list, list]:
    """The forces on plan ``p``'s free body, and the reactions at its inner pairs (of i
    on j, on link j: they cancel in the group's balance and are drawn apart)."""
    inside = {system.link_index(n) for n in system.plans[p].group.links}
    owner = {system.link_index(n): i for i, pl in enumerate(system.plans) for n in pl.group.links}
    names = [*system.links, system.model.ground.name]
    forces, inner = [f for n in sorted(inside) for f in loads[n]], []
    for c, on, by, point, vector, couple, kind, name, extra in pairs:
        if on not in inside:
            continue
        if by in inside:  # an inner pair: its two forces cancel in the group
            if kind == "reaction" and on == system.ends[c][1]:
                inner.append(GroupForce(name, kind, names[on], "solved", point, vector, couple,
                                        by=names[by], joint=name, **extra))  # fmt: skip
            continue
        known = kind == "reaction" and by in owner and owner[by] > p
        forces.append(
            GroupForce(name, kind, names[on], "known" if known else "solved", point, vector,
                       couple, by=names[by], joint=name.split(":")[0] if kind == "reaction"
                       else "", **extra)
        )  # fmt: skip
    return forces, inner


def _group(system: System, p: int, loads: dict, pairs: list, l_ref: float) -> GroupPolygon:
    """The free body and polygon of plan ``p`` from the links' loads and the pairs' forces."""
    group = system.plans[p].group
    forces, inner = _body(system, p, loads, pairs)
    forces.sort(key=lambda f: (f.status == "solved", _ORDER[f.kind]))
    drawn = [np.array(f.vector) for f in forces if any(f.vector)]
    vertices = np.cumsum([np.zeros(2), *drawn], axis=0)
    largest = max((float(np.hypot(*v)) for v in drawn), default=0.0)
    pivot = next((f.point for f in forces if f.status == "solved"), forces[0].point if forces
                 else (0.0, 0.0))  # fmt: skip
    arms = [
        (f.point[0] - pivot[0]) * f.vector[1] - (f.point[1] - pivot[1]) * f.vector[0]
        for f in forces
    ]
    moment = sum(arms) + sum(f.couple for f in forces)
    moment_scale = max([largest * l_ref] + [abs(x) for x in arms] + [abs(f.couple) for f in forces])
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    span = float(max(hi - lo)) if len(drawn) else 0.0
    return GroupPolygon(
        group.name, group.label, group.links, group.kind == "driven", tuple(forces), tuple(inner),
        tuple((float(v[0]), float(v[1])) for v in vertices),
        float(np.hypot(*vertices[-1])), largest, (float(pivot[0]), float(pivot[1])),
        float(moment), float(moment_scale), nice_scale(span / POLYGON_SIZE_MM), group.kind,
        group.letters,
    )  # fmt: skip


def force_polygons(
    result: Result, rows: Sequence[int | tuple[str, int]], *, friction: bool = False
) -> ForcePolygons:
    """The free body and force polygon of each Assur group at ``rows`` (row indices, or
    ``(label, row)`` pairs as ``course_positions(result)`` gives them), the groups in the
    order of the kinetostatic solution: ``system.plans`` reversed, the driving link last
    with the balancing effort M_b.  ``friction``: the consistent solution with friction
    (``<joint>.Fx_friction``, ``<driver>.torque_friction``): each reaction with its
    friction effort, a turning pair's line tangent to its friction circle (NaN where the
    position self-locks).

    Returns a :class:`ForcePolygons`.  Raises ``ValueError`` for a result without
    efforts (kinematics only), or without friction solution when ``friction`` is asked."""
    system = result.system
    if not system.motion_drivers or result.lam.shape[-1] <= system.n_joint_rows:
        raise ValueError("the force polygons need a result with efforts (not kinematics only)")
    if friction and result.lam_friction is None:
        raise ValueError("the result has no friction solution (the file has no friction)")
    ref_speed = schedule(system).reference
    l_ref = float(np.max(system.l_ref))
    positions = []
    for label, k in asked_rows(result, rows):
        q = result.q[k]
        lam = result.lam_friction[k] if friction else result.lam[k]
        a = equilibrium_matrix(system, q)
        fric = _friction(system, q, result.qd[k], lam, ref_speed) if friction else {}
        loads = _link_loads(system, result, k, ref_speed, FAR * l_ref)
        pairs = _pair_forces(system, q, lam, a, FAR * l_ref, fric)
        groups = tuple(
            _group(system, p, loads, pairs, l_ref) for p in reversed(range(len(system.plans)))
        )
        positions.append(PolygonPosition(k, label, groups))
    note = ""
    if system.model.has_friction and not friction:
        note = (
            "the model has friction; the polygons are drawn with the frictionless "
            "reactions <joint>.Fx/.Fy, not <joint>.Fx_friction"
        )
    return ForcePolygons(tuple(positions), note, friction)


def _friction(system: System, q, qd, lam, ref_speed: float) -> dict:
    """Each joint's friction effort at one row as a generalized force, ``{joint: (n_q,)}``:
    g_k e_k with e_k = −sign(ċ_k)·μ_k(λ) (kinetics/friction.py)."""
    fs = fr.setup(system, q, qd, ref_speed)
    e = fr.efforts(system, fs, lam)
    return {c: fs.grad[n] * e[n] for n, c in enumerate(fs.joints)}
