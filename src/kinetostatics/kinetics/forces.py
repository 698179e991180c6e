"""Applied and inertia loads as generalized forces (when a load acts: :mod:`.conditions`;
what each kind of load applies: :data:`.kinds.LOAD_KINDS`).

Every function broadcasts over leading position axes.  The generalized force
on link k is (Fx, Fy, M about the CoM) in q's slots.  Sign convention:
``Q = Q_applied + Q_inertia`` with the d'Alembert inertia ``−m a_S``,
``−J_S α``, so that the Newton–Euler equations read ``Φ_qᵀ λ = −Q``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.arrays import entries_last
from ..base.geometry import rotate, turn
from ..kinematics.state import local_point, point_state  # noqa: F401  (point_state: re-exported)
from ..model import EffortLaw
from ..structure.system import System, coordinate_gradient, kept_pose
from .conditions import activity
from .kinds import LOAD_KINDS, points_once, resisting_torque, resisting_torque_other, zero_speed

__all__ = [
    "mass_vector",
    "gravity_forces",
    "inertia_forces",
    "external_forces",
    "AppliedLoad",
    "applied_loads",
    "effort_forces",
    "zero_speed",
    "resisting_torque",
    "resisting_torque_other",
]


def mass_vector(system: System) -> np.ndarray:
    """Diagonal of the mass matrix, ``(n_q,)``: m, m, J per moving link
    (``(V, 1, n_q)`` for stacked variants)."""
    hit = system.memo.get("mass_vector")  # the system's own numbers: once per system
    if hit is None:
        model = system.model
        values = [
            v for n in system.links for v in (model.link(n).mass,) * 2 + (model.link(n).inertia,)
        ]
        hit = np.stack(np.broadcast_arrays(*values), axis=-1).astype(float)
        hit.flags.writeable = False
        system.memo["mass_vector"] = hit
    return hit


def gravity_forces(system: System, shape: tuple[int, ...]) -> np.ndarray:
    """m g on each link's CoM, ``shape + (n_q,)``."""
    weights = system.memo.get("weights")
    if weights is None:
        g = np.tile(np.append(system.model.gravity, 0.0), len(system.links))
        weights = system.memo["weights"] = mass_vector(system) * g
        weights.flags.writeable = False
    return np.broadcast_to(weights, shape + (system.n_q,))


def inertia_forces(system: System, qdd: np.ndarray) -> np.ndarray:
    """d'Alembert −M q̈."""
    return -mass_vector(system) * qdd


def effort_forces(system: System, q: np.ndarray, qd: np.ndarray | None = None) -> np.ndarray:
    """Generalized forces of the ``effort:`` drivers (applied by i on j): constants, or
    laws (:class:`~kinetostatics.model.EffortLaw`) of the driver coordinate and speed.
    Stored component-major, as d'Alembert's −M q̈ is (each coordinate's force one run over
    the positions: the loads' sum and the reactions' back substitution read them so)."""

    out = entries_last(np.zeros(q.shape[-1:] + q.shape[:-1]), 1)
    names = [j.name for j in system.model.joints]
    for d in system.model.drivers:
        if d.effort is None:
            continue
        k = names.index(d.joint)
        grad = coordinate_gradient(system, q, k)
        value = (
            np.asarray(d.effort, dtype=float)[..., None]
            if not isinstance(d.effort, EffortLaw)
            else d.effort
        )  # (V, 1, 1) for stacked variants
        if isinstance(value, EffortLaw):
            joint = system.model.joints[k]
            qe = np.concatenate((q, np.zeros(q.shape[:-1] + (3,))), axis=-1)
            i, j = system.ends[k]
            psi = (
                joint.coordinate(qe[..., 3 * i : 3 * i + 3], qe[..., 3 * j : 3 * j + 3]) + d.offset
            )
            speed = np.zeros(q.shape[:-1]) if qd is None else np.einsum("...n,...n->...", grad, qd)
            value = value(psi, speed, 2 * np.pi if joint.angular else None)[..., None]
        out += value * grad
    return out


@dataclass(frozen=True, eq=False)
class AppliedLoad:
    """One external load at the rows, as it acts there (zero where its conditions do not
    hold): ``force (..., 2)`` at the local ``point`` of moving link ``link`` (an index),
    or a ``couple (...)`` on it and, where ``other`` is a moving link's index, the
    opposite couple on that link (a resisting torque's reaction)."""

    name: str
    link: int
    point: np.ndarray
    force: np.ndarray | None
    couple: np.ndarray | None
    other: int | None = None


def applied_loads(system: System, q, qd, psi, extremes, ref_speed: float) -> list[AppliedLoad]:
    """Each external load of the model as it acts at the rows (:class:`AppliedLoad`), in
    the model's order: what :func:`external_forces` sums, and the lever method's terms.
    A point that conditions and loads share has its state computed once (``points_once``)."""
    with points_once(system):
        return list(_applied_loads(system, q, qd, psi, extremes, ref_speed))


def _applied_loads(system: System, q, qd, psi, extremes, ref_speed: float):
    period = 2 * np.pi if system.motion_drivers and system.motion_drivers[0].joint.angular else None
    for load in system.model.loads:
        value = load.value_at(psi, period)
        k = system.link_index(load.link)
        p = local_point(system, load.link, load.point)
        on = activity(system, load, q, qd, psi, extremes, ref_speed)
        kind = LOAD_KINDS[load.kind]
        force, couple = kind.applied(system, load, q, qd, value, ref_speed)
        if couple is not None:
            m = np.where(on, couple, 0.0)
            yield AppliedLoad(load.name, k, p, None, m, kind.reacts_on(system, load))
        else:
            yield AppliedLoad(load.name, k, p, np.where(on[..., None], force, 0.0), None)


def external_forces(system: System, q, qd, psi, extremes, ref_speed: float) -> np.ndarray:
    """Generalized external forces of all loads, ``(..., n_q)``."""
    out = effort_forces(system, q, qd)
    for load in applied_loads(system, q, qd, psi, extremes, ref_speed):
        k = load.link
        if load.couple is not None:
            out[..., 3 * k + 2] += load.couple
            if load.other is not None:  # the reaction on the joint's other (moving) link
                out[..., 3 * load.other + 2] -= load.couple
            continue
        force = load.force
        pose = kept_pose(system, q, k)
        arm = rotate(q[..., 3 * k + 2], load.point) if pose is None else turn(pose, load.point)
        out[..., 3 * k : 3 * k + 2] += force
        out[..., 3 * k + 2] += arm[..., 0] * force[..., 1] - arm[..., 1] * force[..., 0]
    return out
