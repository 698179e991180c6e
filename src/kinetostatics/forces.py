"""Applied and inertia loads as generalized forces, and load activity.

Every function broadcasts over leading position axes.  The generalized force
on link k is (Fx, Fy, M about the CoM) in q's slots.  Sign convention:
``Q = Q_applied + Q_inertia`` with the d'Alembert inertia ``−m a_S``,
``−J_S α``, so that the Newton–Euler equations read ``Φ_qᵀ λ = −Q``.
"""

from __future__ import annotations

import numpy as np

from ._geometry import perp, rotate
from .model import Condition, Load
from .system import System

__all__ = [
    "point_state",
    "mass_vector",
    "gravity_forces",
    "inertia_forces",
    "external_forces",
    "effort_forces",
    "condition_values",
    "angle_band",
    "activity",
    "zero_speed",
]

ZERO_SPEED = 1e-9  # relative speeds below this × x_ref count as zero (SPEC.md)


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


def mass_vector(system: System) -> np.ndarray:
    """Diagonal of the mass matrix, ``(n_q,)``: m, m, J per moving link
    (``(V, 1, n_q)`` for stacked variants)."""
    model = system.model
    values = [v for n in system.links for v in (model.link(n).mass,) * 2 + (model.link(n).inertia,)]
    return np.stack(np.broadcast_arrays(*values), axis=-1).astype(float)


def gravity_forces(system: System, shape: tuple[int, ...]) -> np.ndarray:
    """m g on each link's CoM, ``shape + (n_q,)``."""
    m = mass_vector(system)
    g = np.tile(np.append(system.model.gravity, 0.0), len(system.links))
    return np.broadcast_to(m * g, shape + (system.n_q,))


def inertia_forces(system: System, qdd: np.ndarray) -> np.ndarray:
    """d'Alembert −M q̈."""
    return -mass_vector(system) * qdd


def _reference_point(system: System, link: str, point: str | None) -> np.ndarray:
    return system.model.link(link).points[point] if point else np.zeros(2)


def _sense(system: System) -> float:
    d = system.motion_drivers
    return float(np.sign(d[0].driver.motion.speed)) if d else 1.0


def angle_band(system: System, cond: Condition) -> tuple[float, float]:
    """(from, width) of an angle condition, measured in the sense of motion (rad)."""
    width = (cond.bounds[1] - cond.bounds[0]) * _sense(system)
    return cond.bounds[0], (width if width >= 2 * np.pi else np.mod(width, 2 * np.pi))


def condition_values(system: System, cond: Condition, q, qd, psi, extremes) -> np.ndarray:
    """The signed quantity whose sign or band decides a condition, ``(...)``.

    moving: v·axis; travel: p·axis − min over the cycle; angle: the driver
    coordinate travelled from ``from`` in the sense of motion (mod 2π).
    """
    if cond.kind == "angle":
        return np.mod((psi - cond.bounds[0]) * _sense(system), 2 * np.pi)
    k = system.link_index(cond.link)
    pos, vel, _ = point_state(q, qd, None, k, _reference_point(system, cond.link, cond.point))
    if cond.kind == "moving":
        return vel @ cond.axis
    return pos @ cond.axis - extremes[id(cond)]


def activity(system: System, load: Load, q, qd, psi, extremes, ref_speed: float) -> np.ndarray:
    """Boolean ``(...)``: all of the load's conditions hold (bands inclusive)."""
    active = np.ones(q.shape[:-1], dtype=bool)
    tol = ZERO_SPEED * system.l_ref
    for c in load.active:
        v = condition_values(system, c, q, qd, psi, extremes)
        if c.kind == "moving":
            active &= v > ZERO_SPEED * ref_speed * system.l_ref
        elif c.kind == "travel":
            active &= (v >= c.bounds[0] - tol) & (v <= c.bounds[1] + tol)
        else:
            active &= v <= angle_band(system, c)[1] + 1e-12
    return active


def effort_forces(system: System, q: np.ndarray, qd: np.ndarray | None = None) -> np.ndarray:
    """Generalized forces of the ``effort:`` drivers (applied by i on j): constants, or
    laws (:class:`~kinetostatics.model.EffortLaw`) of the driver coordinate and speed."""
    from .model import EffortLaw
    from .system import coordinate_gradient

    out = np.zeros(q.shape)
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


def zero_speed(system: System, ref_speed: float) -> float:
    return ZERO_SPEED * ref_speed * system.l_ref


def external_forces(system: System, q, qd, psi, extremes, ref_speed: float) -> np.ndarray:
    """Generalized external forces of all loads, ``(..., n_q)``."""
    out = effort_forces(system, q, qd)
    period = 2 * np.pi if system.motion_drivers and system.motion_drivers[0].joint.angular else None
    for load in system.model.loads:
        value = load.value_at(psi, period)
        k = system.link_index(load.link)
        p = _reference_point(system, load.link, load.point)
        pos, vel, _ = point_state(q, qd, None, k, p)
        on = activity(system, load, q, qd, psi, extremes, ref_speed)
        if load.kind == "torque":
            out[..., 3 * k + 2] += np.where(on, value, 0.0)
            continue
        if load.kind == "force":
            force = value
        else:
            v = vel @ load.axis
            sign = np.where(np.abs(v) > zero_speed(system, ref_speed), np.sign(v), 0.0)
            force = -(value * sign)[..., None] * load.axis
        force = np.where(on[..., None], force, 0.0)
        arm = rotate(q[..., 3 * k + 2], p)
        out[..., 3 * k : 3 * k + 2] += force
        out[..., 3 * k + 2] += arm[..., 0] * force[..., 1] - arm[..., 1] * force[..., 0]
    return out
