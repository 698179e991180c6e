"""Generic Newton–Euler assembly: joint reactions and driver efforts.

With Q the applied plus d'Alembert inertia loads, equilibrium of every
moving link reads ``A x = −Q`` where the columns of A are the constraint
gradients Φ_qᵀ of the joints (unknowns λ) followed by, for each motion
driver, the gradient of the coordinate of the joint that carries its effort
(the driver's own joint, or ``balance_at``).  Nothing here knows a joint type.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..kinematics.derivatives import velocities
from ..structure.system import (
    System,
    coordinate_gradient,
    coordinate_rate,
    ground_jacobian,
    jacobian,
)

__all__ = [
    "effort_joints",
    "effort_speeds",
    "effort_ratio",
    "equilibrium_matrix",
    "solve_equilibrium",
    "invert_equilibrium",
    "ground_reaction",
    "SINGULAR_RCOND",
    "EFFORT_SPEED_TOL",
    "effort_speed_ratio",
]

SINGULAR_RCOND = 1e-12
"""A square A whose scaled reciprocal condition number is at most this is
singular at that position (:func:`invert_equilibrium`)."""

EFFORT_SPEED_TOL = 1e-7
"""An effort moved by ``balance_at`` to a joint whose relative speed per unit driver
speed (:func:`effort_speed_ratio`) is at most this is not computed: the position is
a singular one of the equilibrium, as where A is exactly singular.  The effort
there is the loads' power divided by that joint's speed, τ ≈ P/(ratio·ψ̇), and the
relative speed, computed from positions and velocities exact to round-off, carries
an absolute error of ~1e-16; so τ's relative error, and the power balance's, is
~1e-16/ratio (measured on the jaw crusher balanced at its toggle and jaw pivots and
on the slider-crank driven from its slide): at most ~1e-9 beyond this tolerance,
ten times below the power self-check's 1e-8, but up to 1e-6 and more (a power
residual of watts) between it and the exact zero, where A's condition number
(~1/ratio) is still far from 1/:data:`SINGULAR_RCOND`."""


def effort_joints(system: System) -> list[int]:
    """For each motion driver, the index of the joint that carries its effort."""
    names = [j.name for j in system.model.joints]
    return [names.index(d.driver.balance_at or d.joint.name) for d in system.motion_drivers]


def effort_speeds(system: System, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """The relative speeds of the joints that carry the motion drivers' efforts at states
    (q, q̇), ``(..., n_d)`` (:func:`effort_joints`)."""
    return np.stack([coordinate_rate(system, q, qd, k) for k in effort_joints(system)], axis=-1)


def effort_ratio(system: System, q: np.ndarray, tangent: np.ndarray) -> np.ndarray:
    """For the first motion driver, the relative speed of the joint that carries its
    effort per unit driver speed, ``(...,)``: c_k,q · ∂q/∂ψ with ``tangent`` = ∂q/∂ψ
    (q̇ at ψ̇ = 1).  Exactly 1 when the effort is the driver's own (no ``balance_at``).

    By virtual power the effort τ at that joint is the effort τ·ratio at the driver's
    joint: e.g. −4 for a pinion (z = 20) driving the crank's gear (z = 80) through an
    external mesh, dx_B/dφ for a slider-crank driven from the slide."""
    d = system.motion_drivers[0]
    if d.driver.balance_at is None or d.driver.balance_at == d.joint.name:
        return np.ones(np.shape(q)[:-1])
    k = effort_joints(system)[0]
    return coordinate_rate(system, q, tangent, k)


def effort_speed_ratio(system: System, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """|relative speed of the first motion driver's effort joint| per unit driver speed,
    ``(...,)``, dimensionless (a prismatic joint's speed divided by L_ref, a prismatic
    driver's likewise): |c_eff·q̇| / |c_drv·q̇|, or from ∂q/∂ψ where the driver is at
    rest (a motion law's turning point).  1 where the effort is the driver's own."""
    d = system.motion_drivers[0]
    if d.driver.balance_at is None or d.driver.balance_at == d.joint.name:
        return np.ones(np.shape(q)[:-1])
    names = [j.name for j in system.model.joints]
    k_e, k_d = effort_joints(system)[0], names.index(d.joint.name)
    r_e, r_d = coordinate_rate(system, q, qd, k_e), coordinate_rate(system, q, qd, k_d)
    scale = (1.0 if system.model.joints[k_d].angular else np.asarray(system.l_ref)) / (
        1.0 if system.model.joints[k_e].angular else np.asarray(system.l_ref)
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.abs(r_e / r_d) * scale
    rest = ~np.isfinite(ratio)
    if np.any(rest):  # the driver at rest: the tangent ∂q/∂ψ
        n_d = len(system.motion_drivers)
        unit = np.zeros(np.shape(q)[:-1] + (n_d,))
        unit[..., 0] = 1.0
        try:
            tangent = velocities(system, q, unit)
            ratio = np.where(rest, np.abs(effort_ratio(system, q, tangent)) * scale, ratio)
        except np.linalg.LinAlgError:  # a singular pose: left to the other tests
            pass
    return ratio


def equilibrium_matrix(system: System, q: np.ndarray, ground: bool = False) -> np.ndarray:
    """A, ``(..., n_q, n_lam)`` (``n_q + 3`` rows with the ground's)."""
    n_j = len(system.model.joints)
    jac = jacobian(system, q, range(n_j), ground=ground)
    cols = [coordinate_gradient(system, q, k, ground=ground) for k in effort_joints(system)]
    return np.concatenate([np.swapaxes(jac, -1, -2)] + [c[..., None] for c in cols], axis=-1)


def solve_equilibrium(a: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, bool]:
    """x with A x = rhs; minimum-norm when A has more columns than rank.

    Returns (x, indeterminate).
    """
    n_q, n_lam = a.shape[-2:]
    if n_q == n_lam:
        try:
            return np.linalg.solve(a, rhs[..., None])[..., 0], False
        except np.linalg.LinAlgError:
            warnings.warn(
                "the equilibrium equations are singular at some positions; "
                "minimum-norm reactions are reported there",
                stacklevel=2,
            )
    return (np.linalg.pinv(a) @ rhs[..., None])[..., 0], True


def invert_equilibrium(a: np.ndarray, l_ref) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position by position inverse of a square A, ``(A⁻¹, singular, condition)``.

    A position is *singular* where the scaled A — moment rows (the θ rows)
    divided by L_ref, columns normalised to unit length — has a reciprocal
    2-norm condition number ≤ :data:`SINGULAR_RCOND`: no finite effort
    balances the loads there (e.g. a dead centre of a linkage whose effort is
    balanced at a joint that does not move there).  Its A⁻¹ is NaN (also where
    A is not finite, unflagged), the other positions are untouched.
    ``condition`` is the scaled condition number, capped at 1/ε (beyond that it
    is not resolved).  ``l_ref``: a float, or ``(V, 1)`` for stacked variants.
    """
    finite = np.all(np.isfinite(a), axis=(-2, -1))
    eye = np.eye(a.shape[-1])
    s = np.where(finite[..., None, None], a, eye)
    s[..., 2::3, :] /= np.asarray(l_ref, dtype=float)[..., None, None]
    norms = np.linalg.norm(s, axis=-2, keepdims=True)
    s /= np.where(norms > 0, norms, 1.0)
    sv = np.linalg.svd(s, compute_uv=False)
    big, small = sv[..., 0], sv[..., -1]
    singular = finite & ~(small > SINGULAR_RCOND * big)
    eps = np.finfo(float).eps
    with np.errstate(divide="ignore", invalid="ignore"):
        condition = np.where(small > eps * big, big / small, 1.0 / eps)
    bad = singular | ~finite
    inv = np.linalg.inv(np.where(bad[..., None, None], eye, a))
    inv[bad] = np.nan
    return inv, singular, np.where(finite, condition, np.nan)


def ground_reaction(system: System, q: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Force and moment (about the ground origin) that the moving links exert
    on the ground through every joint and driver effort, ``(..., 3)``: the
    shaking force and moment."""
    ground = len(system.links)
    out = np.zeros(q.shape[:-1] + (3,))
    rows, jac = ground_jacobian(system, q)
    if rows.size:
        out += np.einsum("...ij,...i->...j", jac, x[..., rows])
    n_j = system.n_joint_rows
    for d, k in enumerate(effort_joints(system)):
        if ground in system.ends[k]:
            g = coordinate_gradient(system, q, k, ground=True)[..., -3:]
            out += g * x[..., n_j + d, None]
    return out
