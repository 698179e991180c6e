"""Positions of stacked variants by Newton, where a group has no closed form (a triad, a
link closed by a gear, rack or cam pair): every variant continued from its start pose
at the same steps of the driver, then each row solved from the path's interpolation —
:func:`~.positions.solve_positions`'s Newton path, with the variants along a leading
axis and each step taken for all of them at once.

A variant whose path one analysis would treat with care — a step that does not
converge or jumps even at the fine step, a group whose determinant changes sign (a
singular position on the way), a row off its branch — is not ok: it leaves the
stacked analysis and is analysed on its own, where the single run's continuation
handles (and reports) it.  The rows of the others are Newton's roots from other
guesses than the single run's: the same roots to Newton's tolerance.
"""

from __future__ import annotations

import numpy as np

from ..structure.system import System, jacobian
from .continuation import (
    COARSE_STEP,
    FINE_STEP,
    JUMP_RATIO,
    Drive,
    jump_ratio,
    kink_ratio,
    time_step,
)
from .newton import group_newton
from .plan import derivatives_at

__all__ = ["newton_path"]


def newton_path(
    system: System, q0: np.ndarray, t: np.ndarray, drive: Drive
) -> tuple[np.ndarray, np.ndarray]:
    """``(q (V, N, n_q), ok (V,))``: the rows at times ``t (N,)`` (from 0 on) of the
    variants of a stacked ``system`` from their start poses ``q0 (V, 1, n_q)``."""
    sig0 = [_sign(system, q0, plan) for plan in system.plans]  # (V, 1) each
    ts, qs, qds, qdds, ok = _nodes(system, q0, sig0, float(np.max(t)), drive)
    q = _quintic(ts, qs, qds, qdds, t)
    psi = drive(t)[0][None]
    with np.errstate(all="ignore"):
        for plan, s0 in zip(system.plans, sig0):
            q, conv, _ = group_newton(system, q, psi, plan)
            ok &= np.all(conv & (_sign(system, q, plan) == s0), axis=-1)
    return np.ascontiguousarray(q), ok


def _nodes(system: System, q: np.ndarray, sig0: list, t_hi: float, drive: Drive):
    """The path's nodes ``(ts (K,), qs, q̇s, q̈s (V, K, n_q) each, ok (V,))``: steps of
    at most 30° of the driver, halved for every variant while one of them fails a step
    and the step is above 5° (so down to 3.75°; a variant that fails there is not ok and
    is carried along unsolved)."""
    coarse = time_step(system, 0.0, drive, COARSE_STEP)
    fine = coarse * FINE_STEP / COARSE_STEP
    ok = np.ones(len(q), dtype=bool)
    qd, qdd = _rates(system, q, 0.0, drive)
    t, h = 0.0, coarse
    ts, qs, qds, qdds = [0.0], [q], [qd], [qdd]
    with np.errstate(all="ignore"):
        while t_hi - t > 1e-12 * max(t_hi, 1e-300):
            h = min(h, t_hi - t)
            qp = q + h * qd + 0.5 * h * h * qdd
            qn, good = _step(system, qp, t + h, drive, sig0)
            qdn, qddn = _rates(system, qn, t + h, drive)
            good &= jump_ratio(system, q, qp, qn) <= JUMP_RATIO
            good &= kink_ratio(system, qd + h * qdd, qdn, qd) <= JUMP_RATIO
            if np.any(ok & ~good) and h > fine * (1 + 1e-9):
                h *= 0.5
                continue
            ok &= good
            keep = ok[:, None, None]  # the others: their last node, never NaN
            q, qd, qdd = (np.where(keep, a, b) for a, b in ((qn, q), (qdn, qd), (qddn, qdd)))
            t += h
            ts.append(t), qs.append(q), qds.append(qd), qdds.append(qdd)
            h = min(coarse, 2.0 * h)
    if len(ts) == 1:  # a single row at the start: a second node beside it
        ts, qs, qds, qdds = [0.0, 1.0], qs * 2, qds * 2, qdds * 2
    return (np.array(ts), *(np.concatenate(x, axis=1) for x in (qs, qds, qdds)), ok)


def _quintic(ts, qs, qds, qdds, t) -> np.ndarray:
    """The quintic Hermite interpolation of the nodes' q, q̇, q̈ ``(V, K, n_q)`` at the
    times ``t (N,)``: ``(V, N, n_q)``."""
    k = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, len(ts) - 2)
    h = (ts[k + 1] - ts[k])[:, None]
    s = ((t - ts[k]) / (ts[k + 1] - ts[k]))[:, None]
    s2, s3 = s * s, s * s * s
    s4, s5 = s3 * s, s3 * s2
    basis = (
        (1 - 10 * s3 + 15 * s4 - 6 * s5, qs),
        ((s - 6 * s3 + 8 * s4 - 3 * s5) * h, qds),
        ((0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5) * h * h, qdds),
    )
    out = sum(w * x[:, k] for w, x in basis)
    ends = (
        (10 * s3 - 15 * s4 + 6 * s5, qs),
        ((-4 * s3 + 7 * s4 - 3 * s5) * h, qds),
        ((0.5 * s3 - s4 + 0.5 * s5) * h * h, qdds),
    )
    return out + sum(w * x[:, k + 1] for w, x in ends)


def _step(system: System, q: np.ndarray, t: float, drive: Drive, sig0: list):
    """(q, ok (V,)): Newton group by group from the prediction ``q (V, 1, n_q)`` at ``t``,
    each group converged on its start's branch."""
    psi = drive(np.array([t]))[0][None]
    ok = np.ones(len(q), dtype=bool)
    for plan, s0 in zip(system.plans, sig0):
        q, conv, _ = group_newton(system, q, psi, plan)
        ok &= conv[:, 0] & (_sign(system, q, plan) == s0)[:, 0]
    return q, ok


def _sign(system: System, q: np.ndarray, plan) -> np.ndarray:
    """The sign of the group's Jacobian determinant at ``q (..., n_q)``: its branch.  That
    of :func:`~.newton.group_signature`'s scaled block (positive row and column scales
    leave it), without the scaling's passes."""
    return np.sign(np.linalg.det(jacobian(system, q, plan.constraints, plan.cols)))


def _rates(system: System, q: np.ndarray, t: float, drive: Drive):
    """(q̇, q̈) at ``q (V, 1, n_q)`` at the time ``t``."""
    _, psi_d, psi_dd = drive(np.array([t]))
    psi_d, psi_dd = (np.broadcast_to(x, q.shape[:-1] + x.shape[-1:]) for x in (psi_d, psi_dd))
    qd, qdd, _ = derivatives_at(system, q, psi_d, psi_dd)
    return qd, qdd
