"""Difference quotients: the source text's scheme, kept as a comparison mode.

The exact velocities and accelerations come from the Jacobian
(:mod:`.derivatives`).  This module estimates them from positions
solved at neighbouring driver coordinates instead: ``forward`` (the source
text's scheme, first order: v ≈ (q(t+h) − q(t))/h, a ≈ (q(t+2h) − 2q(t+h) +
q(t))/h²) or ``central`` (second order).  ``docs/accuracy.md`` compares them.
"""

from __future__ import annotations

import numpy as np

from ..structure.system import System
from .continuation import Drive
from .positions import solve_positions

__all__ = ["SCHEMES", "difference_derivatives"]

SCHEMES = ("forward", "central")


def difference_derivatives(
    system: System, drive: Drive, t: np.ndarray, q: np.ndarray, scheme: str, step: float
) -> tuple[np.ndarray, np.ndarray]:
    """(q̇, q̈) by difference quotients with a driver step ``step`` (rad, or m).

    ``t (n,)`` and ``q (n, n_q)`` are the solved positions; the neighbours are
    solved on the same branch.  Angles are unwrapped against ``q``.
    """
    if scheme not in SCHEMES:
        raise ValueError(
            f"unknown difference scheme '{scheme}'; choose one of {', '.join(SCHEMES)}"
        )
    if not step > 0:
        raise ValueError(f"the difference step must be positive, got {step:g}")
    reference = getattr(drive, "reference", None)  # a motion law's largest |ψ̇|
    rate = reference if reference is not None else abs(float(drive(np.array([0.0]))[1][0, 0]))
    h = step / rate
    offsets = (1.0, 2.0) if scheme == "forward" else (-1.0, 1.0)
    tn = np.concatenate([t + o * h for o in offsets])
    qn = solve_positions(system, tn, drive).q.reshape(len(offsets), *q.shape)
    ang = slice(2, None, 3)
    for k in range(len(offsets)):  # same turn as the centre point
        qn[k][..., ang] += 2 * np.pi * np.round((q[..., ang] - qn[k][..., ang]) / (2 * np.pi))
    if scheme == "forward":
        q1, q2 = qn
        return (q1 - q) / h, (q2 - 2 * q1 + q) / (h * h)
    qm, qp = qn
    return (qp - qm) / (2 * h), (qp - 2 * q + qm) / (h * h)
