"""Positions: Newton per Assur group, batched over positions, with branch tracking.

The path is parametrised by time t (the drivers' laws give ψ(t)).  The solve:

1. *Start*: the sketch gives a rough pose; each group is solved by Newton in
   solve order and its branch signature sign(det Φ_q,group) recorded
   (:mod:`.start`; Newton per group in :mod:`.newton`).
2. *Coarse pass*: sequential continuation over the whole time range with
   driver steps ≤ 30°, locating the singular positions it passes
   (:mod:`.continuation`).
3. *Batch*: all requested positions predicted by cubic Hermite interpolation
   between the coarse nodes, one vectorised Newton per group over all of
   them, signatures checked against the enclosing nodes.  Positions that fail
   are solved by continuation from the nearest node with steps ≤ 5°.

Where every group has a closed form (:mod:`kinetostatics.kinematics.dyads`) the fast
path :func:`~.closed_path.closed_form_path` replaces 2.–3.: the branch is decided by
the dyads' discriminants along the whole path, independently of the rows.

This module also gives the names of those modules that users import from here
(velocities and accelerations are in :mod:`.derivatives`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import AssemblyError, SingularConfigurationError
from ..structure.system import System
from .closed_path import closed_form_near, closed_form_path
from .continuation import (
    COARSE_STEP,
    FINE_STEP,
    Drive,
    Singularity,
    continue_path,
    coordinate_text,
    hermite,
    time_step,
)
from .derivatives import accelerations, derivatives, velocities
from .newton import TOL, condition_number, group_condition, group_newton, group_signature
from .start import (
    SKETCH_TOL,
    SketchPoint,
    assemble_start,
    closed_form_solvers,
    initial_guess,
    joint_points,
    sketch_distances,
    start_pose,
)

__all__ = [
    "Drive",
    "PositionSolution",
    "Singularity",
    "solve_positions",
    "reachable_range",
    "positions_near",
    "state_at",
    "closed_form_path",
    "closed_form_near",
    "initial_guess",
    "start_pose",
    "assemble_start",
    "joint_points",
    "group_condition",
    "condition_number",
    "group_newton",
    "group_signature",
    "velocities",
    "accelerations",
    "derivatives",
    "TOL",
    "SKETCH_TOL",
    "SketchPoint",
    "sketch_distances",
]


@dataclass
class PositionSolution:
    q: np.ndarray  # (n, n_q)
    signatures: np.ndarray  # (n, n_groups) of ±1
    iterations: np.ndarray  # (n,) Newton iterations of the batch
    singular: list[Singularity] = field(default_factory=list)
    fallback: int = 0  # positions solved by the sequential fallback
    poses: np.ndarray | None = None  # the rows' poses and frames where a pass gave them


def reachable_range(system: System, drive: Drive, t_span: float) -> tuple[float, float]:
    """(t_min, t_max): how far the path assembles from t = 0 backwards and forwards
    within ± ``t_span`` (the limit positions of a crank that cannot fully rotate)."""
    q0, sig0 = start_pose(system, drive)
    coarse = time_step(system, 0.0, drive, COARSE_STEP)
    ends = []
    for sign in (-1.0, 1.0):
        try:
            continue_path(system, q0, sig0, 0.0, sign * t_span, drive, coarse, [])
            ends.append(sign * t_span)
        except AssemblyError as exc:
            if isinstance(exc, SingularConfigurationError):
                raise
            ends.append(exc.t_reached)
    return ends[0], ends[1]


def solve_positions(system: System, t: np.ndarray, drive: Drive) -> PositionSolution:
    """Positions at times ``t (n,)`` on the sketch's branch.

    ``t`` need not be sorted; the path runs from ``t.min()`` (the sketch's
    pose is taken at ``t = 0``, which must lie in the range) to ``t.max()``.
    """
    t = np.asarray(t, dtype=float)
    t_lo, t_hi = min(0.0, float(t.min())), max(0.0, float(t.max()))
    q0, sig0 = start_pose(system, drive)
    fast = _closed_form_path(system, q0, sig0, t, drive)
    if fast is not None:
        return fast
    singular: list[Singularity] = []
    coarse = time_step(system, 0.0, drive, COARSE_STEP)
    parts = []
    if t_lo < 0.0:
        ts, qs, qds, sgs = continue_path(system, q0, sig0, 0.0, t_lo, drive, coarse, singular)
        parts.append(tuple(x[::-1][:-1] for x in (ts, qs, qds, sgs)))
    ts, qs, qds, sgs = continue_path(system, q0, sig0, 0.0, t_hi, drive, coarse, singular)
    parts.append((ts, qs, qds, sgs))
    ts, qs, qds, sgs = (np.concatenate(x) for x in zip(*parts))
    if len(ts) == 1:
        ts, qs, qds, sgs = (np.concatenate((x, x)) for x in (ts, qs, qds, sgs))
        ts = ts + np.array([0.0, 1.0])
    guess, k = hermite(ts, qs, qds, t)
    psi = drive(t)[0]
    q = guess
    ok_all = np.ones(len(t), dtype=bool)
    iters = np.zeros(len(t), dtype=int)
    sig = np.zeros((len(t), len(system.plans)))
    node = np.where(t - ts[k] <= ts[k + 1] - t, k, k + 1)
    width = 1e-6 * coarse  # a row this close to a singular position: either sign
    for g, plan in enumerate(system.plans):
        q, ok, it = group_newton(system, q, psi, plan)
        iters += it
        sig[:, g] = group_signature(system, q, plan)
        expected, at_singular = sgs[node, g].copy(), np.zeros(len(t), dtype=bool)
        for s_ in singular:  # the node's signature, changed by the singular
            if s_.group == plan.group.label:  # positions between the node and the row
                between = (np.minimum(ts[node], t) < s_.t) & (s_.t < np.maximum(ts[node], t))
                expected[between] *= -1
                at_singular |= np.abs(t - s_.t) <= width
        ok_all &= ok & ((sig[:, g] == expected) | at_singular)
    singular.sort(key=lambda s_: s_.t)  # backward part first: in time order
    bad = np.nonzero(~ok_all)[0]
    fine = time_step(system, 0.0, drive, FINE_STEP)
    for n in bad:  # sequential fallback
        a = k[n] if abs(t[n] - ts[k[n]]) <= abs(ts[k[n] + 1] - t[n]) else k[n] + 1
        _, qf, _, sf = continue_path(system, qs[a], sgs[a], ts[a], t[n], drive, fine, [])
        q[n], sig[n] = qf[-1], sf[-1]
    return PositionSolution(q, sig, iters, singular, len(bad))


def _closed_form_path(
    system: System, q0: np.ndarray, sig0: np.ndarray, t: np.ndarray, drive: Drive
) -> PositionSolution | None:
    """All positions at once by closed-form dyads, or None where they do not apply.

    Applies when every group has a closed form and every group assembles along
    the path (see :func:`closed_form_path`, which also locates the change points
    the path passes: they are the singular positions); any doubt returns None
    (Newton path).
    """
    solvers = closed_form_solvers(system, drive)
    if solvers is None:
        return None
    singular: list[Singularity] = []
    q, ok, signs, pe = closed_form_path(system, solvers, q0[None, None], t, drive, singular)
    if not ok[0]:
        return None
    iterations = np.zeros(len(t), dtype=int)
    return PositionSolution(q[0], sig0 * signs[0], iterations, singular, poses=pe)


def state_at(
    system: System,
    drive: Drive,
    t: np.ndarray,
    t_near: np.ndarray,
    q_near: np.ndarray,
    qd_near: np.ndarray,
    qdd_near: np.ndarray,
):
    """(q, q̇, q̈) at times ``t`` close to solved states at ``t_near`` (same branch).

    Taylor prediction from the near state, then Newton per group.  Used to
    refine event positions.  Where Newton does not converge from the prediction (a
    coarse grid puts a root far from its row), the state is walked there from the
    near state in 2, 4, … 64 equal steps, each predicted from the last; raises
    AssemblyError if a group does not converge even so.
    """
    try:
        return _state_step(system, drive, t, t_near, q_near, qd_near, qdd_near)
    except AssemblyError as exc:
        error = exc
    states = [np.empty_like(q_near), np.empty_like(qd_near), np.empty_like(qdd_near)]
    for i in np.ndindex(np.shape(t)):
        state = _state_by_steps(system, drive, t[i], t_near[i], q_near[i], qd_near[i], qdd_near[i])
        if state is None:
            raise error
        for store, new in zip(states, state):
            store[i] = new[0]
    return tuple(states)


def _state_step(system, drive, t, t_near, q_near, qd_near, qdd_near):  # noqa: PLR0913  state_at's arrays
    """One Taylor prediction from the near state, then Newton (state_at's first try)."""
    h = (t - t_near)[..., None]
    guess = q_near + h * qd_near + 0.5 * h * h * qdd_near
    psi, psi_d, psi_dd = drive(t)
    q = positions_near(system, psi, guess, drive)
    qd, qdd, _ = derivatives(system, q, psi_d, psi_dd)
    return q, qd, qdd


def _state_by_steps(system, drive, t, t_near, q, qd, qdd):  # noqa: PLR0913  state_at's arrays
    """The state at the one time ``t`` walked from ``t_near`` in ever more steps, or None."""
    for m in (2, 4, 8, 16, 32, 64):
        state = (q[None], qd[None], qdd[None])
        ts = np.linspace(t_near, t, m + 1)
        try:
            for a, b in zip(ts[:-1], ts[1:]):
                state = _state_step(system, drive, np.array([b]), np.array([a]), *state)
        except AssemblyError:
            continue
        return state
    return None


def positions_near(
    system: System,
    psi: np.ndarray,
    q_guess: np.ndarray,
    drive: Drive,
    reference: np.ndarray | None = None,
    *,
    changes: bool = True,
) -> np.ndarray:
    """Positions at driver coordinates ``psi (..., n_d)`` on the branch of a nearby
    guess ``q_guess (..., n_q)`` (closed-form dyads where they apply, else Newton
    per group).  Raises AssemblyError naming the group where Newton fails.

    ``reference (..., n_q)``: the solved states the guesses were continued from; a
    position must then be on the same branch as its reference, every group's signature
    (the sign of its Jacobian's determinant) the same.  The closed forms take the sketch's
    branch, which a path leaves at a change point (a parallelogram's), so where a
    signature differs Newton from the guesses is tried; where one still differs (a guess
    too far from its state beside a dead point, where two branches come close, or a
    singular position between them) AssemblyError is raised: the caller continues
    along the whole run instead.  ``changes=False``: the path of the references passes
    no change point, so the closed forms' branch is theirs (not checked).

    For stepping methods (forward dynamics): the guess is the previous state,
    ideally advanced by q̇ h + ½ q̈ h².  ``drive``: the run's schedule
    (:func:`~kinetostatics.kinematics.schedule.schedule`), whose start pose the closed forms share.
    """
    q = _closed_form_at(system, drive, q_guess, psi)
    if q is not None and not changes:
        return q
    if q is None or (reference is not None and _off_branch(system, q, reference)):
        q = q_guess
        for plan in system.plans:
            q, ok, _ = group_newton(system, q, psi, plan)
            if not np.all(ok):
                raise AssemblyError(
                    plan.group.label,
                    coordinate_text(system, psi.reshape(-1)[:1]),
                    "Newton did not converge from the given guess",
                )
    off = None if reference is None else _off_branch(system, q, reference)
    if off:
        plan, where = off
        raise AssemblyError(
            plan.group.label,
            coordinate_text(system, psi.reshape(-1, psi.shape[-1])[where][0]),
            "another branch than the state it was continued from",
        )
    return q


def _off_branch(system: System, q: np.ndarray, reference: np.ndarray):
    """(plan, positions) of the first group whose signature at ``q`` differs from that at
    ``reference`` (positions: a mask over the leading axes, flattened), or None."""
    flat = reference.reshape(-1, reference.shape[-1])
    rows, back = np.unique(flat, axis=0, return_inverse=True)  # the states continued from
    for plan in system.plans:
        if plan.group.kind == "driven":  # a link its driver turns or slides: one branch
            continue
        ref = group_signature(system, rows, plan)[np.ravel(back)]
        off = group_signature(system, q, plan).reshape(-1) != ref
        if np.any(off):
            return plan, np.ravel(off)
    return None


def _closed_form_at(system: System, drive: Drive, guess: np.ndarray, psi: np.ndarray):
    """Closed-form positions near ``guess`` (angles taken nearest to it), or None."""
    solvers = closed_form_solvers(system, drive)
    if solvers is None:
        return None
    q, ok = closed_form_near(solvers, guess, psi)
    return q if np.all(ok) else None
