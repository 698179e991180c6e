"""Positions: Newton per Assur group, batched over positions, with branch tracking.

The path is parametrised by time t (the drivers' laws give ψ(t)).  The solve:

1. *Start*: the sketch gives a rough pose; each group is solved by Newton in
   solve order and its branch signature sign(det Φ_q,group) recorded.  A
   sketch whose signature differs from its Newton solution's, or that sits on
   a singular pose, is ambiguous: a model error names the group.
2. *Coarse pass*: sequential continuation over the whole time range with
   driver steps ≤ 30°, a second-order Taylor predictor from the exact q̇, q̈,
   and step halving where Newton fails, the correction is large compared
   with the step (a jump), or the signature changes.  A signature change that
   persists as the step shrinks to ``MIN_STEP`` while the path stays smooth,
   and where the located determinant really vanishes (condition ≥
   ``SINGULAR_COND``), is a *singular position*: recorded with its coordinate
   and condition number.
3. *Batch*: all requested positions predicted by cubic Hermite interpolation
   between the coarse nodes, one vectorised Newton per group over all of
   them, signatures checked against the enclosing nodes.  Positions that fail
   are solved by continuation from the nearest node with steps ≤ 5°.

Where every group has a closed form (:mod:`kinetostatics.kinematics.dyads`) the fast
path :func:`closed_form_path` replaces 2.–3.: the branch is decided by the
dyads' discriminants along the whole path, independently of the rows
(:func:`_change_points`).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..base.geometry import rotate, wrap_angle
from ..base.linalg import BlockFactor
from ..errors import AssemblyError, KinetostaticsError, ModelError, SingularConfigurationError
from ..structure.drivers import DriverConstraint
from ..structure.system import GroupPlan, System, gamma, jacobian, nu, phi
from .state import point_state

__all__ = [
    "Drive",
    "PositionSolution",
    "Singularity",
    "solve_positions",
    "initial_guess",
    "group_condition",
    "velocities",
    "accelerations",
    "derivatives",
    "start_pose",
    "positions_near",
    "reachable_range",
    "TOL",
    "SKETCH_TOL",
    "SketchPoint",
    "sketch_distances",
]

TOL = 1e-12  # Newton tolerance relative to L_ref (and 1 rad)
MAX_ITER = 25
COARSE_STEP = np.radians(30.0)
FINE_STEP = np.radians(5.0)
MIN_STEP = 1e-7  # rad of driver coordinate (or × L_ref for a prismatic)
JUMP_RATIO = 0.35  # |corrector| / |step| above which a step is a suspected jump
SKETCH_TOL = 0.25  # a sketched point may lie this × L_ref from where it assembled
DISC_TOL = 100 * TOL  # a closed-form dyad's normalised discriminant D at or below which it
# is singular (its lengths within ~50·TOL of its own scale of a toggle)
DISC_SCAN = np.radians(5.0)  # sample spacing of the discriminants along a closed-form path
DISC_NEAR = 1e-3  # a local minimum of D is refined if a sample beside it is this low
SINGULAR_COND = DISC_TOL**-0.5  # a group's condition number from which a located sign change of
# its determinant is a singular position (a dyad's: ~1/√D)

Drive = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
"""t (...) -> (ψ, ψ̇, ψ̈), each (..., n_motion_drivers)."""


@dataclass(frozen=True)
class Singularity:
    """A sign change of a group's determinant along the smooth path."""

    group: str
    t: float
    coordinate: float  # driver coordinate of the first motion driver
    condition: float


@dataclass
class PositionSolution:
    q: np.ndarray  # (n, n_q)
    signatures: np.ndarray  # (n, n_groups) of ±1
    iterations: np.ndarray  # (n,) Newton iterations of the batch
    singular: list[Singularity] = field(default_factory=list)
    fallback: int = 0  # positions solved by the sequential fallback


def _scales(system: System, jac: np.ndarray, plan: GroupPlan) -> tuple[np.ndarray, np.ndarray]:
    """Column (unit) and row (equilibration) scales of a group block."""
    l_ref = np.asarray(system.l_ref)[..., None]  # (V, 1, 1) for stacked variants
    col = np.where(np.arange(len(plan.cols)) % 3 == 2, 1.0, l_ref)  # d/d(x/L) = L d/dx
    norm = np.max(np.abs(jac * col[..., None, :]), axis=-1)
    return col, 1.0 / np.where(norm > 0, norm, 1.0)


def _scaled_group_jacobian(system: System, q: np.ndarray, plan: GroupPlan) -> np.ndarray:
    jac = jacobian(system, q, plan.constraints, plan.cols)
    col, row = _scales(system, jac, plan)
    return jac * col[..., None, :] * row[..., None]


def condition_number(
    system: System, plan: GroupPlan, jac: np.ndarray, inv: np.ndarray
) -> np.ndarray:
    """Frobenius-norm condition number ‖S‖_F ‖S⁻¹‖_F of the group's scaled block
    S = D_r J D_c (lengths over L_ref, rows equilibrated), from J and J⁻¹, ``(...)``.

    It bounds the 2-norm condition number from above by at most the block size.
    """
    col, row = _scales(system, jac, plan)
    s = jac * col[..., None, :] * row[..., None]
    s_inv = inv / col[..., :, None] / row[..., None, :]
    with np.errstate(over="ignore", invalid="ignore"):
        c = np.linalg.norm(s, axis=(-2, -1)) * np.linalg.norm(s_inv, axis=(-2, -1))
    return np.where(np.isfinite(c), c, np.inf)


def group_condition(system: System, q: np.ndarray, plan: GroupPlan) -> np.ndarray:
    """Condition number of a group at positions q (see :func:`condition_number`)."""
    jac = jacobian(system, q, plan.constraints, plan.cols)
    try:
        inv = np.linalg.inv(jac)
    except np.linalg.LinAlgError:
        inv = np.full(jac.shape, np.inf)
    return condition_number(system, plan, jac, inv)


def _signature(system: System, q: np.ndarray, plan: GroupPlan) -> np.ndarray:
    return np.sign(np.linalg.det(_scaled_group_jacobian(system, q, plan)))


def _newton(
    system: System, q: np.ndarray, psi: np.ndarray, plan: GroupPlan, max_iter: int = MAX_ITER
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Batched Newton on one group (other columns fixed).

    Returns (q, converged (...), iterations (...)).  Positions that converge
    stop updating; the batch iterates until all converged or ``max_iter``.
    """
    shape = q.shape
    q = q.reshape(-1, shape[-1]).copy()
    psi = np.broadcast_to(psi, shape[:-1] + psi.shape[-1:]).reshape(len(q), -1)
    cols = plan.cols
    ang = np.arange(len(cols)) % 3 == 2
    step_tol = np.where(ang, TOL, TOL * system.l_ref)
    res_tol = TOL * system.l_ref
    batch = q.shape[:-1]
    done = np.zeros(batch, dtype=bool)
    iters = np.zeros(batch, dtype=int)
    active = np.ones(batch, dtype=bool)
    for _ in range(max_iter):
        idx = np.nonzero(active & ~done)
        if not idx[0].size:
            break
        qa = q[idx]
        r = phi(system, qa, psi[idx], plan.constraints)
        jac = jacobian(system, qa, plan.constraints, cols)
        try:
            dx = np.linalg.solve(jac, -r[..., None])[..., 0]
        except np.linalg.LinAlgError:  # a singular matrix somewhere in the batch
            dx = (np.linalg.pinv(jac) @ -r[..., None])[..., 0]
        bad = ~np.all(np.isfinite(dx), axis=-1)
        dx[bad] = 0.0
        qa[..., cols] += dx
        q[idx] = qa
        iters[idx] += 1
        small = np.all(np.abs(dx) <= step_tol, axis=-1) & (
            np.max(np.abs(r), axis=-1) <= res_tol * 1e3
        )
        big = np.max(np.abs(dx) / np.where(ang, 1.0, system.l_ref), axis=-1) > 1e3
        sub_done = small & ~bad
        d = done[idx]
        d |= sub_done
        done[idx] = d
        a = active[idx]
        a &= ~(bad | big)
        active[idx] = a
    # final residual check
    r = np.max(np.abs(phi(system, q, psi, plan.constraints)), axis=-1)
    converged = r <= res_tol
    return q.reshape(shape), converged.reshape(shape[:-1]), iters.reshape(shape[:-1])


# -- initial guess from the sketch ----------------------------------------------
def _known_points(system: System) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:
    """For each moving link, (local point, rough global position) pairs from the sketch."""
    model = system.model
    out: dict[str, list] = {name: [] for name in system.links}
    ground = model.ground
    for j in model.joints:
        pts = _joint_points(j)
        if j.name in model.sketch:
            for link, p in pts:
                if link in out:
                    out[link].append((p, model.sketch[j.name]))
        fixed = [p for link, p in pts if link == ground.name]
        if fixed and len(pts) > 1:  # a pin on ground is known exactly
            gp = fixed[0]
            for link, p in pts:
                if link in out:
                    out[link].append((p, gp))
    for ref, pos in model.sketch.items():
        link, dot, pname = ref.partition(".")
        if dot and link in out:
            out[link].append((model.link(link).points[pname], pos))
    return out


def _joint_points(j) -> list[tuple[str, np.ndarray]]:
    """(link, local point) of the points at the joint, which its sketch entry places."""
    return [(a.link, a.xy) for a in j.anchors() if a.at_joint]


def initial_guess(system: System) -> np.ndarray:
    """q from the sketch: each link's pose fitted to its sketched points.

    Raises ModelError naming the group of a link the sketch does not place.
    """
    known = _known_points(system)
    poses, missing = [], []  # (x, y, θ) per link: (3,), or (V, 3) for variants
    for name in system.links:
        pairs = known[name]
        if not pairs:
            missing.append(name)
            poses.append(np.zeros(3))
            continue
        local, world = (
            np.stack(np.broadcast_arrays(*x), axis=-2)[..., 0, :, :]
            if any(np.ndim(v) > 1 for v in x)
            else np.array(x)
            for x in ([p for p, _ in pairs], [w for _, w in pairs])
        )
        theta = np.zeros(np.broadcast_shapes(local.shape, world.shape)[:-2])
        if len(pairs) >= 2:
            lc = local - local.mean(-2, keepdims=True)
            wc = world - world.mean(-2, keepdims=True)
            theta = np.arctan2(
                np.sum(lc[..., 0] * wc[..., 1] - lc[..., 1] * wc[..., 0], axis=-1),
                np.sum(lc[..., 0] * wc[..., 0] + lc[..., 1] * wc[..., 1], axis=-1),
            )
        xy = np.mean(world - rotate(theta[..., None], local), axis=-2)
        poses.append(np.concatenate((xy, theta[..., None]), axis=-1))
    q = np.concatenate(np.broadcast_arrays(*poses), axis=-1)
    if missing:
        groups = {n: p.group.label for p in system.plans for n in p.group.links}
        raise ModelError(
            [
                (
                    _where(system),
                    f"the sketch places no point of link '{n}' ({groups[n]}): "
                    "give the rough position of one of its joints",
                )
                for n in missing
            ]
        )
    return q


def _where(system: System):
    from ..errors import Location

    return Location(system.model.source, path="sketch")


# -- the solve ----------------------------------------------------------------
def _coordinate_text(system: System, psi: np.ndarray) -> str:
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


def _assemble_start(system: System, t0: float, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
    """The pose at ``t0`` on the sketched branch.  The sketch is a rough pose at
    ``analysis.start``; when the pose assembled there lies far from it (the start was
    moved, or the sketch is of another position), the linkage is assembled where the
    sketch is — at the driver coordinates of the sketched pose — checked against the
    sketch there, and carried along its branch to ``t0``."""
    guess = initial_guess(system)
    psi = drive(np.array([t0]))[0][0]
    try:
        return _assemble_at(system, guess, psi, check=True)
    except ModelError as exc:
        if not getattr(exc, "sketch_far", False):
            raise
        psi_s = _sketch_coordinates(system, guess)
        step = psi - psi_s
        angular = np.array([d.joint.angular for d in system.motion_drivers])
        step = np.where(angular, wrap_angle(step), step)
        if np.all(np.abs(step) <= 1e-9 * np.where(angular, 1.0, np.max(system.l_ref))):
            raise  # the sketched pose is the start: refused
        try:
            q, sig = _assemble_at(system, guess, psi_s, check=True)
        except KinetostaticsError:
            raise exc from None

        def homotopy(t):  # noqa: E306 — ψ from the sketch's to ψ(t0)
            t = np.asarray(t, dtype=float)[..., None]
            return (
                psi_s + t * step,
                np.broadcast_to(step, t.shape[:-1] + step.shape),
                np.zeros(t.shape[:-1] + step.shape),
            )

        max_dt = COARSE_STEP / max(
            float(np.max(np.abs(np.where(angular, step, step / np.max(system.l_ref))))), COARSE_STEP
        )
        try:
            _, qs, _, sigs = _continue(system, q, sig, 0.0, 1.0, homotopy, max_dt, [])
        except AssemblyError:
            raise exc from None
        return qs[-1], np.array([float(_signature(system, qs[-1], p)) for p in system.plans])


def _sketch_coordinates(system: System, q: np.ndarray) -> np.ndarray:
    """The motion drivers' coordinates at the pose ``q`` (the sketched pose)."""
    qe = np.concatenate((q, np.zeros(3)))
    out = []
    for d in system.motion_drivers:
        i, j = system.ends[system.constraints.index(d)]
        out.append(float(d.coordinate(qe[3 * i : 3 * i + 3], qe[3 * j : 3 * j + 3])))
    return np.array(out)


def _assemble_at(
    system: System, q: np.ndarray, psi: np.ndarray, *, check: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Group by group Newton from the pose ``q`` at driver coordinates ``psi``, each group
    on the branch the sketch gives; then the sketched points checked (``check``)."""
    sig = []
    for plan in system.plans:
        s0 = _signature(system, q, plan)
        cond0 = group_condition(system, q, plan)
        if s0 == 0 or cond0 > 1e10:
            raise ModelError(
                [
                    (
                        _where(system),
                        f"the sketch does not decide the assembly branch of "
                        f"{plan.group.label}: it sketches a singular pose; "
                        "sketch its joints closer to the intended pose",
                    )
                ]
            )
        qn, ok, _ = _newton(system, q, psi, plan)
        if not ok:
            raise AssemblyError(
                plan.group.label, _coordinate_text(system, psi), _miss(system, q, psi, plan)
            )
        s1 = _signature(system, qn, plan)
        if s1 != s0:
            raise ModelError(
                [
                    (
                        _where(system),
                        f"the sketch does not decide the assembly branch of "
                        f"{plan.group.label}: sketch its joints closer to the intended pose",
                    )
                ]
            )
        q = qn
        sig.append(float(s1))
    if check:
        _check_sketch(system, q)
    return q, np.array(sig)


@dataclass(frozen=True)
class SketchPoint:
    """A sketched point at an assembled pose: its sketch key, how far (m) it was
    assembled from its sketched position, and the Assur group that placed it."""

    key: str
    distance: float | np.ndarray
    group: str


def sketch_distances(system: System, q: np.ndarray) -> list[SketchPoint]:
    """How far each sketched point lies from where it is at the pose ``q``.

    A joint key is measured at its point on the moving link solved first (that
    link's group placed it); a ``link.point`` key at that point.  Keys that name
    no point of a moving link (a gear) are left out."""
    model = system.model
    order = {n: g for g, p in enumerate(system.plans) for n in p.group.links}
    out = []
    for key, pos in model.sketch.items():
        link, dot, pname = key.partition(".")
        if dot:
            pairs = [(link, model.link(link).points[pname])] if link in order else []
        else:
            pairs = [(n, p) for n, p in _joint_points(model.joint(key)) if n in order]
        if not pairs:
            continue
        link, p = min(pairs, key=lambda pair: order[pair[0]])
        x = point_state(q, q, None, system.link_index(link), p)[0]
        out.append(
            SketchPoint(
                key, np.linalg.norm(x - pos, axis=-1), system.plans[order[link]].group.label
            )
        )
    return out


def _check_sketch(system: System, q: np.ndarray) -> None:
    """A sketched point farther than ``SKETCH_TOL``·L_ref from where the start pose put
    it is a model error: the linkage assembled on a branch other than the sketched one
    (the sketch was not specific enough: e.g. one revolute of a pin shared by three
    links left unsketched)."""
    from ..base.units import factor
    from ..errors import Location

    model = system.model
    unit = model.units.get("length", "m")
    scale = factor("length", unit)
    tol = SKETCH_TOL * np.asarray(system.l_ref)
    worst: dict = {}
    for sp in sketch_distances(system, q):
        where = model.sketch_where.get(sp.key, Location(model.source, path=f"sketch.{sp.key}"))
        if np.all(sp.distance <= tol) or (
            where in worst and np.max(worst[where].distance) >= np.max(sp.distance)
        ):
            continue
        worst[where] = sp
    if worst:
        exc = ModelError(
            [
                (
                    where,
                    f"{where.path.removeprefix('sketch.')} is assembled "
                    f"{np.max(sp.distance) / scale:.4g} {unit} from its sketched position "
                    f"(placed by {sp.group}; the tolerance is {SKETCH_TOL:g} L_ref = "
                    f"{np.max(tol) / scale:.4g} {unit}): the linkage assembled on another "
                    "branch than sketched; sketch the joints of that group (every revolute "
                    "of a pin shared by three links) closer to the intended pose at "
                    "analysis.start",
                )
                for where, sp in worst.items()
            ]
        )
        exc.sketch_far = True
        raise exc


def _miss(system: System, q: np.ndarray, psi: np.ndarray, plan: GroupPlan) -> str:
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
        qn, ok, _ = _newton(system, qn, psi, plan)
        if not ok:
            return qn, False, new_sig
        new_sig[g] = _signature(system, qn, plan)
    return qn, True, new_sig


def _jump(system: System, q0: np.ndarray, qp: np.ndarray, qn: np.ndarray) -> float:
    scale = np.tile([1.0 / system.l_ref, 1.0 / system.l_ref, 1.0], len(system.links))
    corr = np.max(np.abs((qn - qp) * scale))
    move = np.max(np.abs((qn - q0) * scale))
    return corr / max(move, 1e-12)


def _kink(system: System, qd_pred: np.ndarray, qd_new: np.ndarray, qd_old: np.ndarray) -> float:
    """Velocity mismatch relative to the velocities' size (a kink in the path)."""
    scale = np.tile([1.0 / system.l_ref, 1.0 / system.l_ref, 1.0], len(system.links))
    size = max(np.max(np.abs(qd_old * scale)), np.max(np.abs(qd_new * scale)), 1e-300)
    with np.errstate(invalid="ignore"):
        mismatch = np.max(np.abs((qd_new - qd_pred) * scale)) / size
    return float(mismatch) if np.isfinite(mismatch) else np.inf


def _derivs(system: System, q: np.ndarray, t: float, drive: Drive):
    _, psi_d, psi_dd = (x[0] for x in drive(np.array([t])))
    qd, qdd, _ = derivatives(system, q[None], psi_d[None], psi_dd[None])
    qd, qdd = qd[0], qdd[0]
    return qd, qdd


def _continue(
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
        jump = _jump(system, q, qp, qn) if ok else np.inf
        if ok and jump <= JUMP_RATIO:  # C¹: the velocity must continue too
            qdn, qddn = _derivs(system, qn, t + h, drive)
            jump = max(jump, _kink(system, qd + h * qdd, qdn, qd))
        flipped = ok and np.any(new_sig != sig)
        smooth = ok and jump <= JUMP_RATIO and (not flipped or abs(h) <= fine_h)
        found = [
            _locate_singular(system, drive, g, t, q, qd, t + h, qn, qdn)
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
                _miss(system, qp, psi, plan)
                if not ok
                else ("the motion cannot be continued smoothly (singular position)")
            )
            err = AssemblyError if not ok else SingularConfigurationError
            if ok:  # a limit position (a fold: ψ turns back)?
                fold = _fold_beyond(system, q, t, direction * fine_h * 1e-3, drive)
                if fold is not None:
                    err, (plan, reason, psi) = AssemblyError, fold
            exc = err(plan.group.label, _coordinate_text(system, psi), reason)
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
        qn, ok, _ = _newton(system, qn, psi, plan)
        if ok:
            continue
        reason = _miss(system, qn, psi, plan)
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


def _locate_singular(
    system: System,
    drive: Drive,
    g: int,
    ta: float,
    qa: np.ndarray,
    qda: np.ndarray,
    tb: float,
    qb: np.ndarray,
    qdb: np.ndarray,
) -> Singularity:
    """Bisect the sign change of group g's determinant between two path points."""
    plan = system.plans[g]
    ts, qs, qds = np.array([ta, tb]), np.array([qa, qb]), np.array([qda, qdb])
    sa = _signature(system, qa, plan)
    lo, hi = ta, tb
    q_mid = qa
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        guess, _ = _hermite(ts, qs, qds, np.array([mid]))
        psi = drive(np.array([mid]))[0]
        q_mid = guess[0]
        for p in system.plans:
            q_mid, _, _ = _newton(system, q_mid[None], psi, p)
            q_mid = q_mid[0]
        if _signature(system, q_mid, plan) == sa:
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
        qn, ok, _ = _newton(system, q, psi, plan)
        if not ok:
            return plan
        q = qn
    return system.plans[-1]


def _hermite(ts, qs, qds, t):
    """Cubic Hermite interpolation of q between the nodes, at times t."""
    k = np.clip(np.searchsorted(ts, t, side="right") - 1, 0, len(ts) - 2)
    h = ts[k + 1] - ts[k]
    s = ((t - ts[k]) / h)[:, None]
    h = h[:, None]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return h00 * qs[k] + h10 * h * qds[k] + h01 * qs[k + 1] + h11 * h * qds[k + 1], k


def _max_dt(system: System, t0: float, drive: Drive, step: float) -> float:
    """The time step in which no driver moves by more than ``step`` (rad, or × L_ref):
    from the drivers' reference speeds (a motion law's largest |ψ̇|), else from ψ̇(t0)."""
    speeds = getattr(drive, "speed", None)
    psi_d = np.atleast_1d(speeds) if speeds is not None else drive(np.array([t0]))[1][0]
    rates = [
        abs(v) if d.joint.angular else abs(v) / system.l_ref
        for d, v in zip(system.motion_drivers, psi_d)
    ]
    rate = max(rates, default=0.0)
    return step / rate if rate > 0 else step


_STARTS: weakref.WeakKeyDictionary[System, tuple] = weakref.WeakKeyDictionary()


def start_pose(system: System, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
    """(q, branch signatures) at t = 0 from the sketch; computed once per system
    and driver start (the pose depends on the model only)."""
    key = tuple(np.ravel(drive(np.array([0.0]))[0]))
    cached = _STARTS.get(system)
    if cached is None or cached[0] != key:
        cached = (key, *_assemble_start(system, 0.0, drive))
        _STARTS[system] = cached
    return cached[1].copy(), cached[2].copy()


def reachable_range(system: System, drive: Drive, t_span: float) -> tuple[float, float]:
    """(t_min, t_max): how far the path assembles from t = 0 backwards and forwards
    within ± ``t_span`` (the limit positions of a crank that cannot fully rotate)."""
    q0, sig0 = start_pose(system, drive)
    coarse = _max_dt(system, 0.0, drive, COARSE_STEP)
    ends = []
    for sign in (-1.0, 1.0):
        try:
            _continue(system, q0, sig0, 0.0, sign * t_span, drive, coarse, [])
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
    coarse = _max_dt(system, 0.0, drive, COARSE_STEP)
    parts = []
    if t_lo < 0.0:
        ts, qs, qds, sgs = _continue(system, q0, sig0, 0.0, t_lo, drive, coarse, singular)
        parts.append(tuple(x[::-1][:-1] for x in (ts, qs, qds, sgs)))
    ts, qs, qds, sgs = _continue(system, q0, sig0, 0.0, t_hi, drive, coarse, singular)
    parts.append((ts, qs, qds, sgs))
    ts, qs, qds, sgs = (np.concatenate(x) for x in zip(*parts))
    if len(ts) == 1:
        ts, qs, qds, sgs = (np.concatenate((x, x)) for x in (ts, qs, qds, sgs))
        ts = ts + np.array([0.0, 1.0])
    guess, k = _hermite(ts, qs, qds, t)
    psi = drive(t)[0]
    q = guess
    ok_all = np.ones(len(t), dtype=bool)
    iters = np.zeros(len(t), dtype=int)
    sig = np.zeros((len(t), len(system.plans)))
    node = np.where(t - ts[k] <= ts[k + 1] - t, k, k + 1)
    width = 1e-6 * coarse  # a row this close to a singular position: either sign
    for g, plan in enumerate(system.plans):
        q, ok, it = _newton(system, q, psi, plan)
        iters += it
        sig[:, g] = _signature(system, q, plan)
        expected, at_singular = sgs[node, g].copy(), np.zeros(len(t), dtype=bool)
        for s_ in singular:  # the node's signature, changed by the singular
            if s_.group == plan.group.label:  # positions between the node and the row
                between = (np.minimum(ts[node], t) < s_.t) & (s_.t < np.maximum(ts[node], t))
                expected[between] *= -1
                at_singular |= np.abs(t - s_.t) <= width
        ok_all &= ok & ((sig[:, g] == expected) | at_singular)
    singular.sort(key=lambda s_: s_.t)  # backward part first: in time order
    bad = np.nonzero(~ok_all)[0]
    fine = _max_dt(system, 0.0, drive, FINE_STEP)
    for n in bad:  # sequential fallback
        a = k[n] if abs(t[n] - ts[k[n]]) <= abs(ts[k[n] + 1] - t[n]) else k[n] + 1
        _, qf, _, sf = _continue(system, qs[a], sgs[a], ts[a], t[n], drive, fine, [])
        q[n], sig[n] = qf[-1], sf[-1]
    return PositionSolution(q, sig, iters, singular, len(bad))


def path_times(system: System, t: np.ndarray, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
    """``t``, then t = 0 (the start pose), then auxiliary times every ≤ 30° of the
    driver over the range, and the order that sorts them: the closed-form angles
    are unwrapped along it."""
    coarse = _max_dt(system, 0.0, drive, COARSE_STEP)
    lo, hi = min(0.0, float(t.min())), max(0.0, float(t.max()))
    aux = np.linspace(lo, hi, int(np.ceil((hi - lo) / coarse)) + 2)
    if getattr(drive, "laws", ()):  # where a law turns back, a group may touch a toggle
        aux = np.concatenate((aux, drive.turning_times(lo, hi)))
    tt = np.concatenate((t, [0.0], aux))
    return tt, np.argsort(tt, kind="stable")


def _closed_form_path(
    system: System, q0: np.ndarray, sig0: np.ndarray, t: np.ndarray, drive: Drive
) -> PositionSolution | None:
    """All positions at once by closed-form dyads, or None where they do not apply.

    Applies when every group has a closed form and every group assembles along
    the path (see :func:`closed_form_path`, which also locates the change points
    the path passes: they are the singular positions); any doubt returns None
    (Newton path).
    """
    solvers = _solvers(system, drive)
    if solvers is None:
        return None
    singular: list[Singularity] = []
    q, ok, signs = closed_form_path(system, solvers, q0[None, None], t, drive, singular)
    if not ok[0]:
        return None
    return PositionSolution(q[0], sig0 * signs[0], np.zeros(len(t), dtype=int), singular)


def closed_form_path(
    system: System,
    solvers,
    q0: np.ndarray,
    t: np.ndarray,
    drive: Drive,
    singular: list | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closed-form positions at times ``t (N,)`` from start poses ``q0 (V, 1, n_q)``
    (V variants, stacked or not): ``(q (V, N, n_q), ok (V,), signs (V, N, n_groups))``.

    Each group is solved with the closed-form sign of its start pose times
    ``signs``: the sign changes at every *change point* of the group, where its
    discriminant D touches zero (:func:`_change_points`, located between the rows
    and independently of them), so that the path is C¹.  With ``singular`` a list
    (one model, V = 1) the change points are appended to it as singular
    positions; without, a variant that passes one is not ok (its own analysis
    reports it).  ``ok`` also needs D ≥ −``DISC_TOL`` along the path (the links
    reach; else the Newton path reports where they do not) and a sample of the
    positions to satisfy Φ = 0.  Auxiliary points every ≤ 30° of the driver
    (:func:`path_times`) let the angles be unwrapped continuously from the start pose.
    """
    n_v = len(q0)
    lo, hi = min(0.0, float(t.min())), max(0.0, float(t.max()))
    flips, ok = _change_points(system, solvers, q0, lo, hi, drive)
    tt, order = path_times(system, t, drive)
    psi = drive(tt)[0]
    signs = _branch_signs(flips, np.broadcast_to(tt, (n_v, len(tt))))
    q, disc = _closed_forms(solvers, np.broadcast_to(q0, (n_v, len(tt), q0.shape[-1])), psi, signs)
    ok &= np.all(disc >= -DISC_TOL, axis=(-2, -1))
    ang = slice(2, None, 3)  # angles nearest the start pose, as the guess
    q[..., ang] += 2 * np.pi * np.round((q0[..., ang] - q[..., ang]) / (2 * np.pi))
    start = len(t)
    for k in range(len(system.links)):  # unwrap angles along the path
        col = 3 * k + 2
        q[:, order, col] = np.unwrap(q[:, order, col], axis=-1)
        q[:, :, col] += (2 * np.pi * np.round((q0[:, 0, col] - q[:, start, col]) / (2 * np.pi)))[
            :, None
        ]
    q = q[:, :start]
    probe = slice(None, None, max(1, start // 32))
    res = np.max(np.abs(phi(system, q[:, probe], psi[:start][probe])), axis=(-2, -1))
    ok &= res <= 1e3 * TOL * np.ravel(np.broadcast_to(system.l_ref, (n_v, 1)))
    if singular is None:
        for f in flips:
            ok &= np.all(np.isnan(f), axis=-1)
    else:
        found = [(ts, g) for g, f in enumerate(flips) for ts in f[0] if not np.isnan(ts)]
        for ts, g in sorted(found):
            at = np.array([[ts]])
            qs, _ = _closed_forms(solvers, q0, drive(at)[0], _branch_signs(flips, at))
            coord = float(drive(at)[0][0, 0, 0]) if system.motion_drivers else ts
            singular.append(
                Singularity(
                    system.plans[g].group.label,
                    float(ts),
                    coord,
                    float(group_condition(system, qs[0, 0], system.plans[g])),
                )
            )
    return q, ok, signs[:, :start]


def _closed_forms(
    solvers, q: np.ndarray, psi: np.ndarray, signs: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The closed forms in solve order, group g on its start sign × ``signs[..., g]``:
    (q, the groups' discriminants D ``(..., n_groups)``)."""
    q = np.array(q, dtype=float)
    disc = []
    for g, solve in enumerate(solvers):
        q, d = solve(q, psi, signs[..., g])
        disc.append(np.broadcast_to(d, q.shape[:-1]))
    return q, np.stack(disc, axis=-1)


def _branch_signs(flips: list, t: np.ndarray) -> np.ndarray:
    """±1 per group at times ``t (V, M)``: −1 where an odd number of the group's
    change points ``flips[g] (V, K)`` (NaN: none) lie between t = 0 and t."""
    out = []
    for f in flips:
        f, tt = f[:, None, :], t[..., None]
        with np.errstate(invalid="ignore"):
            n = np.sum(((f > 0) & (f <= tt)) | ((f < 0) & (f >= tt)), axis=-1)
        out.append(np.where(n % 2, -1.0, 1.0))
    return np.stack(out, axis=-1) if out else np.ones(t.shape + (0,))


def _change_points(
    system: System, solvers, q0: np.ndarray, lo: float, hi: float, drive: Drive
) -> tuple[list, np.ndarray]:
    """The change points of every group over ``[lo, hi]``: ``(flips, ok)``, flips[g]
    ``(V, K)`` their times (NaN padding), ``ok (V,)`` where no local minimum of a
    discriminant lies below −``DISC_TOL`` (the links reach everywhere).

    A group's discriminant D(t) is smooth along the path.  It is sampled every
    ≤ ``DISC_SCAN`` of the driver (plus t = 0 and the times a motion law turns
    back), never at the output rows, with slopes by central differences; the
    interior minima of the cubic Hermite interpolant between samples are added
    as samples where they are low (so a sample lies next to every low minimum,
    to the interpolant's O(h⁴) error), and every sign change − to + of the slope with a sample
    beside it at D ≤ ``DISC_NEAR`` brackets a local minimum of D, refined by a
    safeguarded Newton iteration on D' = 0.  A
    minimum with |D| ≤ ``DISC_TOL`` is a change point: D touches zero there
    (D ≈ c (t − t*)²), the two assemblies meet, and the C¹ continuation is the
    other closed-form sign (√D ∝ |t − t*| changes its signed form).  A minimum
    above ``DISC_TOL``, however small (a near-toggle), keeps the sign.
    Groups are taken in solve order: a group's change points enter the
    closed forms of the later groups.
    """
    n_v = len(q0)
    fine = _max_dt(system, 0.0, drive, DISC_SCAN)
    eta = 1e-4 * fine
    ts = np.linspace(lo, hi, int(np.ceil((hi - lo) / fine)) + 1)
    if getattr(drive, "laws", ()):
        ts = np.concatenate((ts, drive.turning_times(lo, hi)))
    ts = np.broadcast_to(np.unique(np.append(ts, 0.0)), (n_v, len(np.unique(np.append(ts, 0.0)))))
    flips = [np.full((n_v, 0), np.nan) for _ in solvers]
    ok = np.ones(n_v, dtype=bool)

    def disc(t):  # D, D', D'' of every group at times t (V, M): (V, M, G) each
        at = t[None] + np.array([-eta, 0.0, eta])[:, None, None]
        at = np.moveaxis(at, 0, -1).reshape(n_v, -1)
        _, d = _closed_forms(
            solvers,
            np.broadcast_to(q0, at.shape + q0.shape[-1:]),
            drive(at)[0],
            _branch_signs(flips, at),
        )
        d = d.reshape(t.shape + (3, -1))
        return (
            d[..., 1, :],
            (d[..., 2, :] - d[..., 0, :]) / (2 * eta),
            (d[..., 2, :] - 2 * d[..., 1, :] + d[..., 0, :]) / eta**2,
        )

    g0 = 0
    while g0 < len(solvers):  # again from a group past which the signs changed
        d, m, _ = disc(ts)
        h = np.diff(ts, axis=-1)[..., None]
        d0, d1, m0, m1 = d[:, :-1], d[:, 1:], m[:, :-1] * h, m[:, 1:] * h
        b = -6 * d0 - 4 * m0 + 6 * d1 - 2 * m1  # Hermite p'(s) = a s² + b s + c, p'' > 0 root
        a = 6 * d0 + 3 * m0 - 6 * d1 + 3 * m1
        with np.errstate(all="ignore"):
            s = 2 * m0 / (-b - np.sqrt(b * b - 4 * a * m0))
        low = (
            (s * s * (2 * s - 3) + 1) * d0
            + s * (s - 1) ** 2 * m0
            + s * s * (3 - 2 * s) * d1
            + s * s * (s - 1) * m1
        )  # the interpolant's minimum
        inner = (s > 0) & (s < 1) & (low <= 10 * DISC_NEAR)
        inner[..., :g0] = False
        tg = ts
        if inner.any():
            extra = np.where(inner, ts[:, :-1, None] + np.where(inner, s, 0.0) * h, np.nan)
            extra = np.sort(extra.reshape(n_v, -1), axis=-1)[:, : int(inner.sum((-2, -1)).max())]
            tg = np.sort(
                np.concatenate((ts, np.where(np.isnan(extra), hi, extra)), axis=-1), axis=-1
            )
            d, m, _ = disc(tg)
        ok &= np.all(d[..., g0:] >= -DISC_TOL, axis=(-2, -1))
        for g in range(g0, len(solvers)):
            dg, mg = d[..., g], m[..., g]
            br = (
                (mg[:, :-1] < 0)
                & (mg[:, 1:] >= 0)
                & (np.minimum(dg[:, :-1], dg[:, 1:]) <= DISC_NEAR)
            )
            n_k = int(br.sum(axis=-1).max())
            if n_k == 0:
                continue
            idx = np.argsort(~br, axis=-1, kind="stable")[:, :n_k]
            valid = np.take_along_axis(br, idx, -1)
            a_t = np.take_along_axis(tg[:, :-1], idx, -1)
            b_t = np.take_along_axis(tg[:, 1:], idx, -1)
            tm = 0.5 * (a_t + b_t)
            for _ in range(MAX_ITER):  # safeguarded Newton on D'(t) = 0
                _, mm, c = (x[..., g] for x in disc(tm))
                a_t, b_t = np.where(mm < 0, tm, a_t), np.where(mm < 0, b_t, tm)
                with np.errstate(all="ignore"):
                    tn = tm - mm / c
                inside = (c > 0) & (tn > a_t) & (tn < b_t)
                tn = np.where(inside, tn, 0.5 * (a_t + b_t))
                done = np.all(np.abs(tn - tm) <= 1e-9 * fine)
                tm = tn
                if done:
                    break
            dm = disc(tm)[0][..., g]
            ok &= np.all(~valid | (dm >= -DISC_TOL), axis=-1)
            flips[g] = np.where(valid & (np.abs(dm) <= DISC_TOL), tm, np.nan)
            if not np.all(np.isnan(flips[g])):
                break  # the later groups see these change points
        g0 = g + 1
    return flips, ok


# -- velocities and accelerations ----------------------------------------------------
def derivatives(
    system: System, q: np.ndarray, psi_d: np.ndarray, psi_dd: np.ndarray
) -> tuple[np.ndarray, np.ndarray, BlockFactor]:
    """(q̇, q̈, factorised Φ_q): Φ_q q̇ = ν and Φ_q q̈ = γ by block forward
    substitution over the Assur groups, ``(..., n_q)`` each."""
    lu = BlockFactor(jacobian(system, q), [(p.rows, p.cols) for p in system.plans])
    qd = lu.solve(nu(system, psi_d))
    return qd, lu.solve(gamma(system, q, qd, psi_dd)), lu


def velocities(system: System, q: np.ndarray, psi_d: np.ndarray) -> np.ndarray:
    """q̇ from Φ_q q̇ = ν, ``(..., n_q)``."""
    return np.linalg.solve(jacobian(system, q), nu(system, psi_d)[..., None])[..., 0]


def accelerations(system: System, q: np.ndarray, qd: np.ndarray, psi_dd: np.ndarray) -> np.ndarray:
    """q̈ from Φ_q q̈ = γ, ``(..., n_q)``."""
    return np.linalg.solve(jacobian(system, q), gamma(system, q, qd, psi_dd)[..., None])[..., 0]


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
    refine event positions; raises AssemblyError if a group does not converge.
    """
    h = (t - t_near)[..., None]
    guess = q_near + h * qd_near + 0.5 * h * h * qdd_near
    psi, psi_d, psi_dd = drive(t)
    q = positions_near(system, psi, guess, drive)
    qd, qdd, _ = derivatives(system, q, psi_d, psi_dd)
    return q, qd, qdd


def positions_near(
    system: System, psi: np.ndarray, q_guess: np.ndarray, drive: Drive
) -> np.ndarray:
    """Positions at driver coordinates ``psi (..., n_d)`` on the branch of a nearby
    guess ``q_guess (..., n_q)`` (closed-form dyads where they apply, else Newton
    per group).  Raises AssemblyError naming the group where Newton fails.

    For stepping methods (forward dynamics): the guess is the previous state,
    ideally advanced by q̇ h + ½ q̈ h².  ``drive``: the run's schedule
    (:func:`~kinetostatics.kinematics.schedule.schedule`), whose start pose the closed forms share.
    """
    q = _closed_form_at(system, drive, q_guess, psi)
    if q is not None:
        return q
    q = q_guess
    for plan in system.plans:
        q, ok, _ = _newton(system, q, psi, plan)
        if not np.all(ok):
            raise AssemblyError(
                plan.group.label,
                _coordinate_text(system, psi.reshape(-1)[:1]),
                "Newton did not converge from the given guess",
            )
    return q


def _closed_form_at(system: System, drive: Drive, guess: np.ndarray, psi: np.ndarray):
    """Closed-form positions near ``guess`` (angles taken nearest to it), or None."""
    solvers = _solvers(system, drive)
    if solvers is None:
        return None
    q, ok = closed_form_near(solvers, guess, psi)
    return q if np.all(ok) else None


def closed_form_near(solvers, guess: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q, ok): the closed-form solvers applied in solve order at driver coordinates
    ``psi``, angles taken nearest to ``guess``; ``ok (...)`` where every group's
    margin √D stays above ``dyads.MARGIN``."""
    from .dyads import MARGIN

    q = guess.copy()
    ok = np.ones(guess.shape[:-1], dtype=bool)
    for solve in solvers:
        q, disc = solve(q, psi)
        ok &= disc >= MARGIN**2
    ang = slice(2, None, 3)
    q[..., ang] += 2 * np.pi * np.round((guess[..., ang] - q[..., ang]) / (2 * np.pi))
    return q, ok


def _solvers(system: System, drive: Drive):
    """The closed-form solvers of every group (cached with the start pose), or None."""
    from .dyads import closed_form

    start_pose(system, drive)
    cached = _STARTS[system]
    if len(cached) == 3:
        solvers = [closed_form(system, plan, cached[1]) for plan in system.plans]
        cached = cached + (None if any(s is None for s in solvers) else solvers,)
        _STARTS[system] = cached
    return cached[3]
