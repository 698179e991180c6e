"""Sequential continuation along the path: a second-order Taylor predictor from the
exact q̇, q̈, Newton per group, and step halving where Newton fails, the correction is
large compared with the step (a jump), or a branch signature changes.

A signature change that persists as the step shrinks to ``MIN_STEP`` while the path
stays smooth, and where the located determinant really vanishes (condition ≥
``SINGULAR_COND``), is a *singular position* (:class:`Singularity`); a path that
cannot be continued ends at a limit position or a singular position (the error
names the group and the driver coordinate).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import AssemblyError, SingularConfigurationError
from ..structure.drivers import DriverConstraint
from ..structure.system import GroupPlan, System, jacobian, phi
from .derivatives import derivatives
from .newton import SINGULAR_COND, TOL, group_condition, group_newton, group_signature

__all__ = [
    "Drive",
    "Singularity",
    "COARSE_STEP",
    "FINE_STEP",
    "MIN_STEP",
    "JUMP_RATIO",
    "continue_path",
    "coordinate_text",
    "closing_miss",
    "hermite",
    "jump_ratio",
    "kink_ratio",
    "time_step",
]

COARSE_STEP = np.radians(30.0)
FINE_STEP = np.radians(5.0)
MIN_STEP = 1e-7  # rad of driver coordinate (or × L_ref for a prismatic)
JUMP_RATIO = 0.35  # |corrector| / |step| above which a step is a suspected jump

Drive = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
"""t (...) -> (ψ, ψ̇, ψ̈), each (..., n_motion_drivers)."""


@dataclass(frozen=True)
class Singularity:
    """A sign change of a group's determinant along the smooth path."""

    group: str
    t: float
    coordinate: float  # driver coordinate of the first motion driver
    condition: float


def coordinate_text(system: System, psi: np.ndarray) -> str:
    drivers = system.motion_drivers
    if not drivers:
        return "the start"
    parts = []
    for d, v in zip(drivers, np.atleast_1d(psi)):
        parts.append(
            f"{d.name} = {np.degrees(v) % 360:.6g}°"
            if d.joint.angular
            else f"{d.name} = {v * 1e3:.6g} mm"
        )
    return ", ".join(parts)


def closing_miss(system: System, q: np.ndarray, psi: np.ndarray, plan: GroupPlan) -> str:
    """How far the group is from closing: least-squares residual (Levenberg–Marquardt)."""
    q = q.copy()
    mu = 1e-3
    for _ in range(60):
        r = phi(system, q, psi, plan.constraints)
        jac = jacobian(system, q, plan.constraints, plan.cols)
        a = jac.T @ jac
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(r))):
            return "the constraints cannot be evaluated here (a degenerate joint geometry)"
        dx = np.linalg.lstsq(a + mu * np.diag(np.diag(a) + 1e-12), -jac.T @ r, rcond=None)[0]
        qn = q.copy()
        qn[plan.cols] += dx
        rn = phi(system, qn, psi, plan.constraints)
        if rn @ rn < r @ r:
            q, mu = qn, mu * 0.3
        else:
            mu *= 10.0
    r = phi(system, q, psi, plan.constraints)
    misses, row = [], 0
    for k in plan.constraints:  # a joint's gap: the norm of its residual
        c = system.constraints[k]
        if not isinstance(c, DriverConstraint):
            misses.append((float(np.linalg.norm(r[row : row + c.n_eq])), c.name))
        row += c.n_eq
    total = sum(m for m, _ in misses)
    if total <= TOL * 1e3 * system.l_ref:
        return "Newton did not converge (a singular position is near)"
    open_ = ", ".join(f"{name} {m * 1e3:.4g}" for m, name in misses if m > 1e-3 * total)
    return (
        f"the links cannot reach: they miss closing by {total * 1e3:.4g} mm "
        f"(least-squares gaps at joints {open_} mm)"
    )


def _step(
    system: System,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    t: float,
    h: float,
    drive: Drive,
    sig: np.ndarray,
):
    """One continuation step from t to t + h: (q, converged, signatures)."""
    qn = q + h * qd + 0.5 * h * h * qdd
    psi = drive(np.array([t + h]))[0][0]
    new_sig = sig.copy()
    for g, plan in enumerate(system.plans):
        qn, ok, _ = group_newton(system, qn, psi, plan)
        if not ok:
            return qn, False, new_sig
        new_sig[g] = group_signature(system, qn, plan)
    return qn, True, new_sig


def _weights(system: System, n_q: int) -> np.ndarray:
    """Each coordinate's weight in the step checks: 1/L_ref for x and y, 1 for θ, ``(n_q,)``
    (``(V, n_q)`` for a stacked system, whose L_ref are the variants')."""
    inv = 1.0 / np.asarray(system.l_ref)
    return np.where(np.arange(n_q) % 3 == 2, 1.0, inv if inv.ndim < 2 else inv[..., :1])


def _reduced(x: np.ndarray) -> np.ndarray:
    """The largest |x| over the coordinates and, for stacked rows ``(V, 1, n_q)``, the
    row: one number per path (per variant)."""
    return np.max(np.abs(x), axis=tuple(range(1, x.ndim)) if x.ndim > 2 else None)


def jump_ratio(system: System, q0: np.ndarray, qp: np.ndarray, qn: np.ndarray):
    """|corrector| over |step| of a continuation step from ``q0``, predicted ``qp``,
    solved ``qn`` (``(n_q,)``: a number; stacked ``(V, 1, n_q)``: one per variant)."""
    w = _weights(system, q0.shape[-1])
    w = w[:, None] if w.ndim > 1 else w  # (V, 1, n_q) against stacked rows
    return _reduced((qn - qp) * w) / np.maximum(_reduced((qn - q0) * w), 1e-12)


def kink_ratio(system: System, qd_pred: np.ndarray, qd_new: np.ndarray, qd_old: np.ndarray):
    """Velocity mismatch relative to the velocities' size (a kink in the path), shaped as
    :func:`jump_ratio`'s; infinite where it is not finite."""
    w = _weights(system, qd_old.shape[-1])
    w = w[:, None] if w.ndim > 1 else w
    size = np.maximum(np.maximum(_reduced(qd_old * w), _reduced(qd_new * w)), 1e-300)
    with np.errstate(invalid="ignore"):
        mismatch = _reduced((qd_new - qd_pred) * w) / size
    return np.where(np.isfinite(mismatch), mismatch, np.inf)


def _derivs(system: System, q: np.ndarray, t: float, drive: Drive):
    _, psi_d, psi_dd = (x[0] for x in drive(np.array([t])))
    qd, qdd, _ = derivatives(system, q[None], psi_d[None], psi_dd[None])
    qd, qdd = qd[0], qdd[0]
    return qd, qdd


def continue_path(
    system: System,
    q: np.ndarray,
    sig: np.ndarray,
    t0: float,
    t1: float,
    drive: Drive,
    max_dt: float,
    singular: list[Singularity],
):
    """Sequential continuation from t0 to t1; returns nodes (t, q, qd, sig) lists."""
    ts, qs, qds, sigs = [t0], [q], [], [sig]
    qd, qdd = _derivs(system, q, t0, drive)
    qds.append(qd)
    t = t0
    span = abs(t1 - t0)
    direction = np.sign(t1 - t0) or 1.0
    h = direction * min(max_dt, span)
    min_h = MIN_STEP * max_dt / COARSE_STEP
    fine_h = FINE_STEP * max_dt / COARSE_STEP
    while direction * (t1 - t) > 1e-12 * max(span, 1e-300):
        h = direction * min(abs(h), abs(t1 - t))
        qp = q + h * qd + 0.5 * h * h * qdd
        qn, ok, new_sig = _step(system, q, qd, qdd, t, h, drive, sig)
        jump = float(jump_ratio(system, q, qp, qn)) if ok else np.inf
        if ok and jump <= JUMP_RATIO:  # C¹: the velocity must continue too
            qdn, qddn = _derivs(system, qn, t + h, drive)
            jump = max(jump, float(kink_ratio(system, qd + h * qdd, qdn, qd)))
        flipped = ok and np.any(new_sig != sig)
        smooth = ok and jump <= JUMP_RATIO and (not flipped or abs(h) <= fine_h)
        found = [
            _locate_singular(system, drive, g, np.array([t, t + h]), (q, qn), (qd, qdn))
            for g in (np.nonzero(new_sig != sig)[0] if smooth and flipped else ())
        ]
        if smooth and all(f.condition >= SINGULAR_COND for f in found):
            singular.extend(found)  # a sign change only where det really vanishes
        elif abs(h) > min_h:
            h *= 0.5
            continue
        else:
            psi = drive(np.array([t + h]))[0][0]
            plan = _failing_plan(system, qp, psi)
            reason = (
                closing_miss(system, qp, psi, plan)
                if not ok
                else ("the motion cannot be continued smoothly (singular position)")
            )
            err = AssemblyError if not ok else SingularConfigurationError
            if ok:  # a limit position (a fold: ψ turns back)?
                fold = _fold_beyond(system, q, t, direction * fine_h * 1e-3, drive)
                if fold is not None:
                    err, (plan, reason, psi) = AssemblyError, fold
            exc = err(plan.group.label, coordinate_text(system, psi), reason)
            exc.t_reached = t  # the last assembled time on the path
            raise exc
        t = t + h
        q, sig, qd, qdd = qn, new_sig, qdn, qddn
        ts.append(t), qs.append(q), qds.append(qd), sigs.append(sig)
        h = direction * min(max_dt, abs(h) * 2.0)
    return np.array(ts), np.array(qs), np.array(qds), np.array(sigs)


def _fold_beyond(system: System, q: np.ndarray, t: float, delta: float, drive: Drive):
    """Whether the path that cannot be continued smoothly at t ends in a *limit position*
    (a fold: the driver coordinate turns back, as a crank that cannot fully rotate at
    its toggle) rather than a change point (where the branches cross and the linkage
    assembles beyond).  The pose at t lies within ~MIN_STEP/JUMP_RATIO of the singular
    position; a little beyond it, at t + ``delta`` (~1e-3 × FINE_STEP of the driver), a
    fold leaves no pose — the least-squares gap of the failing group is of order
    L_ref·|δψ| there, far above round-off — while a change point's branches still close.
    Returns (plan, reason, ψ) of the group that cannot reach, or None."""
    psi = drive(np.array([t + delta]))[0][0]
    qn = q.copy()
    for plan in system.plans:
        qn, ok, _ = group_newton(system, qn, psi, plan)
        if ok:
            continue
        reason = closing_miss(system, qn, psi, plan)
        if reason.startswith("the links cannot reach"):
            return (
                plan,
                (
                    "a limit position: the driver coordinate cannot go further (the path "
                    f"folds back there); {reason}"
                ),
                psi,
            )
        return None
    return None


def _locate_singular(system: System, drive: Drive, g: int, ts, qs, qds) -> Singularity:
    """Bisect the sign change of group g's determinant between two path points: at the
    times ``ts`` (ta, tb) the positions ``qs`` and velocities ``qds``."""
    plan = system.plans[g]
    (ta, tb), (qa, _) = ts, qs
    ts, qs, qds = np.asarray(ts, dtype=float), np.array(qs), np.array(qds)
    sa = group_signature(system, qa, plan)
    lo, hi = ta, tb
    q_mid = qa
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        guess, _ = hermite(ts, qs, qds, np.array([mid]))
        psi = drive(np.array([mid]))[0]
        q_mid = guess[0]
        for p in system.plans:
            q_mid, _, _ = group_newton(system, q_mid[None], psi, p)
            q_mid = q_mid[0]
        if group_signature(system, q_mid, plan) == sa:
            lo = mid
        else:
            hi = mid
        if abs(hi - lo) <= 1e-12 * max(abs(tb - ta), 1e-300) * 1e3:  # either direction
            break
    t_s = 0.5 * (lo + hi)
    coord = float(drive(np.array([t_s]))[0][0][0]) if system.motion_drivers else t_s
    return Singularity(plan.group.label, t_s, coord, float(group_condition(system, q_mid, plan)))


def _failing_plan(system: System, q: np.ndarray, psi: np.ndarray) -> GroupPlan:
    for plan in system.plans:
        qn, ok, _ = group_newton(system, q, psi, plan)
        if not ok:
            return plan
        q = qn
    return system.plans[-1]


def hermite(ts, qs, qds, t):
    """Cubic Hermite interpolation of q between the nodes, at times t."""
    k = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, len(ts) - 2)
    h = ts[k + 1] - ts[k]
    s = ((t - ts[k]) / h)[:, None]
    h = h[:, None]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return h00 * qs[k] + h10 * h * qds[k] + h01 * qs[k + 1] + h11 * h * qds[k + 1], k


def time_step(system: System, t0: float, drive: Drive, step: float) -> float:
    """The time step in which no driver moves by more than ``step`` (rad, or × L_ref):
    from the drivers' reference speeds (a motion law's largest |ψ̇|), else from ψ̇(t0).
    Over stacked variants whose L_ref differ, the least of theirs (one step for all)."""
    speeds = getattr(drive, "speed", None)
    psi_d = np.atleast_1d(speeds) if speeds is not None else drive(np.array([t0]))[1][0]
    rates = [
        abs(v) if d.joint.angular else float(np.max(abs(v) / np.asarray(system.l_ref)))
        for d, v in zip(system.motion_drivers, psi_d)
    ]
    rate = max(rates, default=0.0)
    return step / rate if rate > 0 else step
