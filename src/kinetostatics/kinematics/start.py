"""The start pose from the sketch: each link's pose fitted to its sketched points
(:func:`initial_guess`), each group solved by Newton in solve order on the branch the
sketch gives (its signature sign(det Φ_q,group) recorded), and the sketched points
checked against the assembled pose (``SKETCH_TOL``).  A sketch whose signature differs
from its Newton solution's, or that sits on a singular pose, is ambiguous: a model
error names the group.  The start pose is cached per system (:func:`start_pose`), and
with it the groups' closed-form solvers (:func:`closed_form_solvers`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..base.geometry import rotate, wrap_angle
from ..base.units import factor
from ..errors import AssemblyError, KinetostaticsError, Location, ModelError
from ..joints.base import Shaped
from ..structure.system import System, link_pair
from . import dyads
from .continuation import COARSE_STEP, Drive, closing_miss, continue_path, coordinate_text
from .newton import group_condition, group_newton, group_signature
from .state import joint_coordinate, point_state

__all__ = [
    "SKETCH_TOL",
    "SketchPoint",
    "initial_guess",
    "joint_points",
    "sketch_distances",
    "sketch_far_error",
    "sketch_step",
    "assemble_start",
    "start_joint_error",
    "start_pose",
    "closed_form_solvers",
]

SKETCH_TOL = 0.25  # a sketched point may lie this × L_ref from where it assembled


def _known_points(system: System) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:
    """For each moving link, (local point, rough global position) pairs from the sketch."""
    model = system.model
    out: dict[str, list] = {name: [] for name in system.links}
    ground = model.ground
    for j in model.joints:
        pts = joint_points(j)
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


def joint_points(j) -> list[tuple[str, np.ndarray]]:
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
    return Location(system.model.source, path="sketch")


def assemble_start(system: System, t0: float, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
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
        psi_s, step, same = sketch_step(system, guess, psi)
        if same:
            raise  # the sketched pose is the start: refused
        angular = _angular(system)
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
            _, qs, _, sigs = continue_path(system, q, sig, 0.0, 1.0, homotopy, max_dt, [])
        except AssemblyError:
            raise exc from None
        return qs[-1], np.array([float(group_signature(system, qs[-1], p)) for p in system.plans])


def _angular(system: System) -> np.ndarray:
    return np.array([d.joint.angular for d in system.motion_drivers])


def sketch_step(
    system: System, guess: np.ndarray, psi: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ψ_s, ψ − ψ_s, same): the motion drivers' coordinates ψ_s at the sketched pose
    ``guess`` (:func:`initial_guess`), the step from them to ``psi`` (angles wrapped), and
    whether that step is nil (the sketched pose is the start's).  ``guess (..., n_q)``:
    ``(..., n_drivers)`` and ``(...)`` for a stacked system's variants."""
    psi_s = np.stack(
        [
            np.asarray(joint_coordinate(system, guess, system.constraints.index(d)))
            for d in system.motion_drivers
        ],
        axis=-1,
    ).astype(float)
    angular = _angular(system)
    step = psi - psi_s
    step = np.where(angular, wrap_angle(step), step)
    same = np.all(np.abs(step) <= 1e-9 * np.where(angular, 1.0, system.l_ref), axis=-1)
    return psi_s, step, same


def _assemble_at(
    system: System, q: np.ndarray, psi: np.ndarray, *, check: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Group by group Newton from the pose ``q`` at driver coordinates ``psi``, each group
    on the branch the sketch gives; then the sketched points checked (``check``)."""
    sig = []
    for plan in system.plans:
        s0 = group_signature(system, q, plan)
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
        qn, ok, _ = group_newton(system, q, psi, plan)
        if not ok:
            raise AssemblyError(
                plan.group.label, coordinate_text(system, psi), closing_miss(system, q, psi, plan)
            )
        s1 = group_signature(system, qn, plan)
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
        exc = start_joint_error(system, q)
        if exc is not None:
            raise exc
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
            pairs = [(n, p) for n, p in joint_points(model.joint(key)) if n in order]
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
    """Raise :func:`sketch_far_error` if there is one."""
    exc = sketch_far_error(system, q)
    if exc is not None:
        raise exc


def sketch_far_error(
    system: System, q: np.ndarray, variant: int | None = None
) -> ModelError | None:
    """A sketched point farther than ``SKETCH_TOL``·L_ref from where the pose ``q`` put it
    is a model error: the linkage assembled on a branch other than the sketched one (the
    sketch was not specific enough: e.g. one revolute of a pin shared by three links left
    unsketched).  That error (``sketch_far`` set), or None.  ``variant``: of a stacked
    system, the error of that variant (``q (V, 1, n_q)``)."""
    model = system.model
    unit = model.units.get("length", "m")
    scale = factor("length", unit)
    tol = SKETCH_TOL * np.asarray(system.l_ref)
    points = sketch_distances(system, q)
    if variant is not None:
        tol = tol[variant]
        points = [replace(sp, distance=sp.distance[variant]) for sp in points]
    worst: dict = {}
    for sp in points:
        where = model.sketch_where.get(sp.key, Location(model.source, path=f"sketch.{sp.key}"))
        if np.all(sp.distance <= tol) or (
            where in worst and np.max(worst[where].distance) >= np.max(sp.distance)
        ):
            continue
        worst[where] = sp
    if not worst:
        return None
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
    return exc


def start_joint_error(
    system: System, q: np.ndarray, variant: int | None = None
) -> ModelError | None:
    """A model error at each joint whose assembled pose ``q`` contradicts its own
    definition (:meth:`~kinetostatics.joints.base.Joint.start_problem`: a cam out of phase
    with its law), or None.  ``variant``: of a stacked system (``q (V, 1, n_q)``), that
    variant's."""
    if variant is not None:
        q = q[variant]
    problems = []
    for k, joint in enumerate(system.joints):
        if type(joint).start_problem is Shaped.start_problem:  # none: nothing to ask
            continue
        qi, qj = (np.reshape(x, (-1, 3)) for x in link_pair(system, q, k))
        for a, b in zip(qi, qj):
            if text := joint.start_problem(a, b):
                problems.append((joint.where, text))
                break
    return ModelError(problems) if problems else None


def start_pose(system: System, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
    """(q, branch signatures) at t = 0 from the sketch; computed once per system
    and driver start (the pose depends on the model only)."""
    key = tuple(np.ravel(drive(np.array([0.0]))[0]))
    cached = system.memo.get("start")
    if cached is None or cached[0] != key:
        cached = (key, *assemble_start(system, 0.0, drive))
        system.memo["start"] = cached
    return cached[1].copy(), cached[2].copy()


def closed_form_solvers(system: System, drive: Drive) -> dyads.ClosedForms | None:
    """The closed forms of every group as one generated pass (:class:`~.dyads.ClosedForms`,
    cached with the start pose), or None where a group has none.

    ``dyads.closed_form`` is looked up at the call (a benchmark switches it off)."""
    start_pose(system, drive)
    cached = system.memo["start"]
    if len(cached) == 3:
        cached = cached + (dyads.closed_forms(system, cached[1]),)
        system.memo["start"] = cached
    return cached[3]
