"""Force elements: springs and dampers between two links (``elements:``).

An element acts along one scalar coordinate s of the linkage: the distance between two
points (``spring``, ``damper``) or the relative rotation θ_j − θ_i at a revolute
(``torsion_spring``, ``rotary_damper``).  Its force f (N, or N·m) acts to reduce s when
positive (a spring in tension), so its generalized force is Q = −f ∇_q s, and the power it
takes from the linkage is f ṡ: for a spring the rate of its stored energy E(s) (f = dE/ds),
for a damper (f = c ṡ) the power it dissipates, c ṡ² ≥ 0.  Both are terms of the power
balance (``power.elastic``, ``power.damping``; :mod:`.inverse`), and a spring's energy is a
term of the energy of forward dynamics (``energy.elastic``).

Every function broadcasts over leading position axes (and a stacked variant axis: a
stiffness may be an array ``(V, 1)``).  A table spring's force is interpolated linearly and
held constant outside the table; its energy is the exact integral of that force from the
first table value of s.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..base.geometry import perp, rotate
from ..model import Element
from ..structure.system import System, coordinate_gradient

__all__ = [
    "ElementStates",
    "element_states",
    "coordinate",
    "coordinate_rate",
    "force",
    "force_kinks",
    "energy",
]


@dataclass
class ElementStates:
    """The elements at states (q, q̇): per element name its coordinate ``s``, rate ``rate``,
    force ``f``, stored energy ``energy`` (0 for a damper) and power ``power`` = f ṡ; and
    ``q`` = Σ −f ∇s, the generalized force of all elements ``(..., n_q)``."""

    q: np.ndarray
    s: dict = field(default_factory=dict)
    rate: dict = field(default_factory=dict)
    f: dict = field(default_factory=dict)
    energy: dict = field(default_factory=dict)
    power: dict = field(default_factory=dict)
    spring: dict = field(default_factory=dict)  # name -> whether a spring (else a damper)

    def total(self, what: str, springs: bool) -> np.ndarray:
        """Σ of ``power`` or ``energy`` over the springs (``springs``) or the dampers."""
        vals = [getattr(self, what)[n] for n, sp in self.spring.items() if sp == springs]
        return sum(vals, np.zeros(self.q.shape[:-1]))


def _point(system: System, q: np.ndarray, link: str, point: str):
    """(position, ∂position/∂θ or None, link index or None) of ``link.point``."""
    model = system.model
    local = model.link(link).points[point]
    if link == model.ground.name:
        return np.broadcast_to(local, q.shape[:-1] + (2,)), None, None
    k = system.link_index(link)
    arm = rotate(q[..., 3 * k + 2], local)
    return q[..., 3 * k : 3 * k + 2] + arm, perp(arm), k


def coordinate(system: System, e: Element, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(s, ∇_q s) of element ``e`` at ``q``: ``(...)``, ``(..., n_q)``."""
    if e.rotational:
        k = [j.name for j in system.model.joints].index(e.joint)
        grad = coordinate_gradient(system, q, k)
        i, j = e.links
        th = [
            np.zeros(q.shape[:-1])
            if name == system.model.ground.name
            else q[..., 3 * system.link_index(name) + 2]
            for name in (i, j)
        ]
        return th[1] - th[0], grad
    (pa, da, ka), (pb, db, kb) = (
        _point(system, q, link, point) for link, point in zip(e.links, e.points)
    )
    d = pb - pa
    length = np.hypot(d[..., 0], d[..., 1])
    u = np.divide(d, length[..., None], out=np.zeros_like(d), where=length[..., None] > 0)
    grad = np.zeros(q.shape)
    for sign, dth, k in ((-1.0, da, ka), (1.0, db, kb)):
        if k is None:
            continue
        grad[..., 3 * k : 3 * k + 2] += sign * u
        grad[..., 3 * k + 2] += sign * np.sum(u * dth, axis=-1)
    return length, grad


def _table_energy(at: np.ndarray, values: np.ndarray, s: np.ndarray) -> np.ndarray:
    """∫ f ds from ``at[0]`` to s of the piecewise-linear f, held constant outside."""
    nodes = np.concatenate(([0.0], np.cumsum(0.5 * np.diff(at) * (values[1:] + values[:-1]))))
    x = np.clip(s, at[0], at[-1])
    k = np.clip(np.searchsorted(at, x, side="right") - 1, 0, len(at) - 2)
    h = x - at[k]
    slope = (values[k + 1] - values[k]) / (at[k + 1] - at[k])
    inside = nodes[k] + values[k] * h + 0.5 * slope * h * h
    return (
        inside
        + np.where(s < at[0], values[0] * (s - at[0]), 0.0)
        + np.where(s > at[-1], values[-1] * (s - at[-1]), 0.0)
    )


def force(e: Element, s: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """The element's force f (N or N·m; positive reduces s) at coordinate s and rate ṡ."""
    if not e.spring:
        return e.damping * rate
    if e.table is not None:
        return np.interp(s, *e.table)
    return e.preload + e.stiffness * (s - e.free)


def force_kinks(e: Element) -> np.ndarray:
    """The coordinates s where the element's force has a kink: a table spring's entries
    (linear between them, held constant outside); none for a linear spring or a damper.
    The cycle's quadrature is cut where s passes one."""
    if e.spring and e.table is not None:
        return np.asarray(e.table[0], dtype=float)
    return np.zeros(0)


def coordinate_rate(system: System, e: Element, q, qd) -> tuple[np.ndarray, np.ndarray]:
    """(s, ṡ) of element ``e`` at states (q, q̇), ``(...)`` each."""
    s, grad = coordinate(system, e, q)
    return s, np.einsum("...n,...n->...", grad, qd)


def energy(e: Element, s: np.ndarray) -> np.ndarray:
    """The energy stored in a spring at coordinate s (J; 0 at s = ``free``, or at the first
    table value); 0 for a damper."""
    if not e.spring:
        return np.zeros(np.shape(s))
    if e.table is not None:
        return _table_energy(*e.table, s)
    x = s - e.free
    return e.preload * x + 0.5 * e.stiffness * x * x


def element_states(system: System, q: np.ndarray, qd: np.ndarray | None) -> ElementStates:
    """All elements at states (q, q̇) (q̇ None: at rest)."""
    out = ElementStates(np.zeros(q.shape))
    for e in system.model.elements:
        s, grad = coordinate(system, e, q)
        rate = np.zeros(s.shape) if qd is None else np.einsum("...n,...n->...", grad, qd)
        f = force(e, s, rate)
        out.q = out.q - f[..., None] * grad
        out.s[e.name], out.rate[e.name], out.f[e.name] = s, rate, f
        out.energy[e.name] = energy(e, s)
        out.power[e.name] = f * rate
        out.spring[e.name] = e.spring
    return out
