"""Closed-form dyads: a fast path behind the group-solver interface.

For RRR, RRP (slide axis on a known link) and RPR (slide axis on the dyad's
pivoted link) dyads, and for a link driven about a revolute on a known link,
the positions of every requested time follow in closed form from the known
links, vectorised over all positions at once.  The assembly branch is the
sign ``σ`` read off the Newton solution at the sketched pose; an optional
per-position factor ``sign`` (±1) multiplies it, so a path can change to the
other closed-form sign where it passes a change point (see
:func:`kinetostatics.kinematics.closed_path.closed_form_path`).  Each solver also returns
the dyad's *discriminant* ``D``, normalised to its scale: ``D > 0`` where the
dyad assembles, ``D = 0`` at its singular positions (the two assemblies
meet), ``D < 0`` where the links cannot reach.  ``D`` is a smooth function
of the known links' poses (no square root is taken), so it can be
interpolated and minimised along a path: ``√D`` is the distance of the
assembly from the singular pose (the margin).

A solver is ``f(q, psi, sign=None, frames=None) -> (q, D)`` filling the group's
columns of ``q``.  ``frames`` (a dict, one per pass of the solvers over one ``q``)
keeps each link's (cos θ, sin θ) once computed: a link placed by one group and read
by the next is turned with the same numbers, without evaluating cos and sin again
(at 36,000 positions each pair costs ~0.7–1 ms).

The closed forms are formulas of revolute and prismatic pairs by nature (like
pyslvs' PLLP), so this module names the joint classes and reads their
attributes (``p_i``, ``p_j``, ``a``, ``u``, ``p``); with the velocity polygons and
the clearance macro it is the only place outside ``joints/`` that does.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..base.geometry import cross, dot, perp, rotate, rotated, wrap_angle
from ..joints import Prismatic, Revolute
from ..structure.system import GroupPlan, System

__all__ = ["closed_form", "MARGIN"]

MARGIN = 1e-3  # below this margin √D a solve near a guess hands over to Newton

Solver = Callable[..., tuple[np.ndarray, np.ndarray]]


def _turned(frames: dict, link: str, theta: np.ndarray, p: np.ndarray) -> np.ndarray:
    """``rotate(theta, p)`` for ``link`` at angle ``theta``, its (cos θ, sin θ) kept in
    ``frames`` for the pass: a link's angle is set once per pass, so a later use turns
    with the same numbers."""
    cs = frames.get(link)
    if cs is None:
        cs = frames[link] = (np.cos(theta), np.sin(theta))
    return rotated(*cs, p)


def _world(system: System, q: np.ndarray, link: str, p: np.ndarray, frames: dict) -> np.ndarray:
    if link not in system.links:  # the ground (the moving links are the others)
        return np.broadcast_to(p, q.shape[:-1] + (2,))
    k = system.links.index(link)
    return q[..., 3 * k : 3 * k + 2] + _turned(frames, link, q[..., 3 * k + 2], p)


def _angle(system: System, q: np.ndarray, link: str):
    if link not in system.links:  # the ground
        return np.zeros(q.shape[:-1])
    return q[..., 3 * system.links.index(link) + 2]


def _place(
    system: System,
    q: np.ndarray,
    link: str,
    theta: np.ndarray,
    world: np.ndarray,
    local: np.ndarray,
    frames: dict,
) -> None:
    """Set link's pose so that local point ``local`` lies at ``world``."""
    k = system.links.index(link)
    q[..., 3 * k + 2] = theta
    q[..., 3 * k : 3 * k + 2] = world - _turned(frames, link, theta, local)


def _heading(v: np.ndarray) -> np.ndarray:
    return np.arctan2(v[..., 1], v[..., 0])


def _norm(v: np.ndarray) -> np.ndarray:
    return np.hypot(v[..., 0], v[..., 1])


def _pin(j: Revolute, link: str) -> np.ndarray:
    return j.p_i if link == j.links[0] else j.p_j


def _other(j, link: str) -> str:
    return j.links[1] if j.links[0] == link else j.links[0]


def _split(plan, joints):
    """(a, b, inner joint, a's external joint, b's external joint), or None."""
    a, b = plan.group.links
    gj = [joints[n] for n in plan.group.joints]
    inner = [j for j in gj if set(j.links) == {a, b}]
    ext_a = [j for j in gj if a in j.links and j not in inner]
    ext_b = [j for j in gj if b in j.links and j not in inner]
    if not (len(inner) == len(ext_a) == len(ext_b) == 1):
        return None
    return a, b, inner[0], ext_a[0], ext_b[0]


def _rrr(system, plan, joints, q0) -> Solver | None:
    parts = _split(plan, joints)
    if parts is None or not all(isinstance(j, Revolute) for j in parts[2:]):
        return None
    a, b, m, ja, jb = parts
    la_vec, lb_vec = _pin(m, a) - _pin(ja, a), _pin(m, b) - _pin(jb, b)
    la, lb = _norm(la_vec), _norm(lb_vec)
    alpha_a, alpha_b = _heading(la_vec), _heading(lb_vec)
    if np.any(la == 0) or np.any(lb == 0):
        return None

    def points(q, frames):
        return (
            _world(system, q, _other(ja, a), _pin(ja, _other(ja, a)), frames),
            _world(system, q, _other(jb, b), _pin(jb, _other(jb, b)), frames),
        )

    pa0, pb0 = points(q0, {})
    pm0 = _world(system, q0, a, _pin(m, a), {})
    sigma = np.sign(cross(pb0 - pa0, pm0 - pa0))

    def solve(q, psi, sign=None, frames=None):
        sg = sigma if sign is None else sigma * sign
        frames = {} if frames is None else frames
        pa, pb = points(q, frames)
        dv = pb - pa
        d2 = dot(dv, dv)
        d = np.sqrt(d2)
        x = (la * la - lb * lb + d2) / (2 * d)
        h2 = la * la - x * x
        h = np.sqrt(np.maximum(h2, 0.0))
        e = dv / d[..., None]
        pm = pa + x[..., None] * e + (sg * h)[..., None] * perp(e)
        ta = _heading(pm - pa) - alpha_a
        tb = _heading(pm - pb) - alpha_b
        _place(system, q, a, ta, pa, _pin(ja, a), frames)
        _place(system, q, b, tb, pb, _pin(jb, b), frames)
        return q, h2 / np.minimum(la, lb) ** 2

    return solve


def _rrp(system, plan, joints, q0) -> Solver | None:
    """R (a, known) – R (a, b) – P (known link i carries the axis, b slides)."""
    parts = _split(plan, joints)
    if parts is None:
        return None
    a, b, m, ja, s = parts
    if not (
        isinstance(m, Revolute)
        and isinstance(ja, Revolute)
        and isinstance(s, Prismatic)
        and s.links[1] == b
    ):
        return None
    k = s.links[0]  # known link carrying the axis
    la_vec = _pin(m, a) - _pin(ja, a)
    la = _norm(la_vec)
    alpha_a = _heading(la_vec)
    offset = _pin(m, b) - s.p  # from the sliding point to the pin, b's frame

    def frame(q, frames):  # b's angle is set to tb in this pass: its frame is kept
        tk = _angle(system, q, k)
        tb = tk + s.angle
        u = _turned(frames, k, tk, s.u)
        w = (
            _world(system, q, k, s.a, frames)
            + _turned(frames, b, tb, offset)
            - _world(system, q, _other(ja, a), _pin(ja, _other(ja, a)), frames)
        )
        return tb, u, w

    tb0, u0, w0 = frame(q0, {})
    pm0 = _world(system, q0, a, _pin(m, a), {})
    pa0 = _world(system, q0, _other(ja, a), _pin(ja, _other(ja, a)), {})
    wu0 = dot(w0, u0)
    s0 = dot(pm0 - pa0 - w0, u0)
    sigma = np.sign(s0 + wu0)

    def solve(q, psi, sign=None, frames=None):
        sg = sigma if sign is None else sigma * sign
        frames = {} if frames is None else frames
        tb, u, w = frame(q, frames)
        wu = dot(w, u)
        disc = wu * wu - dot(w, w) + la * la
        sval = -wu + sg * np.sqrt(np.maximum(disc, 0.0))
        pa = _world(system, q, _other(ja, a), _pin(ja, _other(ja, a)), frames)
        pm = pa + w + sval[..., None] * u
        ta = _heading(pm - pa) - alpha_a
        _place(system, q, a, ta, pa, _pin(ja, a), frames)
        _place(system, q, b, tb, pm, _pin(m, b), frames)
        return q, disc / (la * la)

    return solve


def _rpr(system, plan, joints, q0) -> Solver | None:
    """R (a, known) – P (axis on b, a slides) – R (b, known)."""
    parts = _split(plan, joints)
    if parts is None or not isinstance(parts[2], Prismatic):
        return None
    s = parts[2]
    b, a = s.links  # b carries the axis, a slides on it
    ja, jb = (parts[3], parts[4]) if parts[0] == a else (parts[4], parts[3])
    if not (isinstance(ja, Revolute) and isinstance(jb, Revolute)):
        return None
    delta = s.p - _pin(ja, a)  # a's frame: pin -> sliding point
    e = s.a - _pin(jb, b)  # b's frame: pivot -> axis point
    n_l = perp(s.u)
    nu_ang = _heading(n_l)
    k_const = dot(n_l, e - rotate(s.angle, delta))

    def ends(q, frames):
        return (
            _world(system, q, _other(ja, a), _pin(ja, _other(ja, a)), frames),
            _world(system, q, _other(jb, b), _pin(jb, _other(jb, b)), frames),
        )

    pa0, pb0 = ends(q0, {})
    dv0 = pa0 - pb0
    beta0 = _heading(dv0)
    tb0 = _angle(system, q0, b)
    sigma = -np.sign(wrap_angle(beta0 - nu_ang - tb0))

    def solve(q, psi, sign=None, frames=None):
        sg = sigma if sign is None else sigma * sign
        frames = {} if frames is None else frames
        pa, pb = ends(q, frames)
        dv = pa - pb
        d = np.hypot(dv[..., 0], dv[..., 1])
        beta = np.arctan2(dv[..., 1], dv[..., 0])
        c = k_const / d
        tb = beta - nu_ang + sg * np.arccos(np.clip(c, -1.0, 1.0))
        ta = tb + s.angle
        _place(system, q, b, tb, pb, _pin(jb, b), frames)
        _place(system, q, a, ta, pa, _pin(ja, a), frames)
        return q, 1.0 - c * c

    return solve


def _driven(system, plan, joints, q0) -> Solver | None:
    """A single link on a revolute to a known link, its angle set by a driver."""
    if len(plan.group.links) != 1 or len(plan.group.drivers) != 1 or len(plan.group.joints) != 1:
        return None
    (link,) = plan.group.links
    j = joints[plan.group.joints[0]]
    drivers = system.motion_drivers
    d_index = [d.name for d in drivers].index(plan.group.drivers[0])
    d = drivers[d_index]
    if not isinstance(j, Revolute) or d.joint is not j:
        return None
    other = _other(j, link)
    turn = 1.0 if j.links[1] == link else -1.0  # coordinate θ_j − θ_i

    def solve(q, psi, sign=None, frames=None):
        frames = {} if frames is None else frames
        theta = _angle(system, q, other) + turn * (psi[..., d_index] - d.driver.offset)
        at = _world(system, q, other, _pin(j, other), frames)
        _place(system, q, link, theta, at, _pin(j, link), frames)
        return q, np.ones(q.shape[:-1])

    return solve


def closed_form(system: System, plan: GroupPlan, q0: np.ndarray) -> Solver | None:
    """The closed-form solver of a group, given its Newton solution ``q0`` at
    the sketched pose (which fixes the branch), or ``None``."""
    joints = {j.name: j for j in system.model.joints}
    if plan.group.kind == "driven":
        return _driven(system, plan, joints, q0)
    if plan.group.kind != "dyad":
        return None
    return {"RRR": _rrr, "RRP": _rrp, "RPR": _rpr}.get(plan.group.letters, lambda *a: None)(
        system, plan, joints, q0
    )
