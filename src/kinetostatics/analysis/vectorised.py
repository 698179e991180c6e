"""All variants of one topology in one pass: the stage functions on ``(V, N, ...)``.

:func:`analyze_stacked` runs the analysis of :func:`kinetostatics.analyze`
for many variants at once on a model stacked by
:func:`kinetostatics.model.stacking.stack`, for the common case it can vectorise:
one constant-speed motion driver over a full cycle whose groups pass no singular
position, no event rows.  The rows come from the groups' closed forms where every
group has one (RRR, RRP, RPR dyads and driven links), else by Newton along the path,
every variant continued at the same steps (a triad, a link closed by a gear, rack or
cam pair: :func:`~kinetostatics.kinematics.stacked_path.newton_path`).  Variants it
cannot take — they do not assemble at the start or pass a singular position — are
left out of ``Stacked.members``; when the model is outside that case,
:class:`Unsupported` is raised.  Either way the per-variant analysis takes them, and
reports or handles them exactly as a single run would.

Per variant the results are those of a single run to rounding: the same
functions evaluate the same formulas, only over one more leading axis (the rows by
Newton: the same roots, from other guesses, to Newton's tolerance).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..kinematics.closed_path import closed_form_path
from ..kinematics.dyads import ClosedForms, closed_forms
from ..kinematics.events import output_strokes_stacked
from ..kinematics.motion import Motion
from ..kinematics.newton import group_condition, group_newton, group_signature
from ..kinematics.plan import derivatives_at
from ..kinematics.schedule import Schedule, sample_times, schedule
from ..kinematics.stacked_path import newton_path
from ..kinematics.start import (
    SKETCH_TOL,
    initial_guess,
    sketch_distances,
    sketch_far_error,
    sketch_step,
    start_joint_error,
)
from ..kinetics.conditions import travel_extremes_stacked
from ..kinetics.inverse import inverse_dynamics
from ..kinetics.kinds import CONDITION_KINDS, LOAD_KINDS
from ..kinetics.reactions import ground_reaction
from ..model import Model
from ..model.stacking import is_stacked, stack, subset
from ..structure.system import System, build_system
from .columns import build_columns
from .results import Result

__all__ = ["analyze_stacked", "Stacked"]


@dataclass
class Stacked:
    """The arrays of a stacked analysis of the variants ``members`` (indices into the models
    given, in order); ``ok`` marks those whose rows stand (a stroke may still fail);
    ``failed`` maps variants left out to the error their own analysis raises."""

    members: np.ndarray  # (V,) int
    system: System
    t: np.ndarray  # (N,)
    psi: np.ndarray  # (V, N, 1)
    q: np.ndarray  # (V, N, n_q)
    qd: np.ndarray
    qdd: np.ndarray
    lu: object
    kin: object  # inverse.Kinetics
    extremes: dict
    ok: np.ndarray  # (V,) bool
    sched: Schedule
    solvers: ClosedForms | None  # None: a group without one (the rows by Newton)
    failed: dict[int, Exception] = field(default_factory=dict)


class Unsupported(Exception):
    """The model is outside the vectorised case (the reason is the message)."""


class LeftOver(Unsupported):
    """Fewer than two variants assemble at the start and stay on the closed forms' path;
    ``ok (V,)`` marks them: analyse every variant one by one."""

    def __init__(self, ok: np.ndarray):
        self.ok = ok
        super().__init__(
            f"{int(np.count_nonzero(~ok))} of {len(ok)} variants leave the vectorised path"
        )


def _schedule(system: System) -> Schedule:
    """The schedule (:func:`~kinetostatics.kinematics.schedule.schedule`) of the one constant-speed
    motion driver that the stacked stages take, alike in every variant."""
    model = system.model
    drivers = system.motion_drivers
    if len(drivers) != 1 or system.structure.mobility != 1:
        raise Unsupported("more than one motion driver")
    motion = drivers[0].driver.motion
    if motion.own_run or motion.acceleration or motion.start is not None:
        raise Unsupported("a motion law other than constant speed")
    speed = motion.speed
    start = model.analysis.start
    if np.ndim(speed) or np.ndim(start) or np.ndim(model.analysis.sweep):
        raise Unsupported("the driver's speed or the analysed range differs between variants")
    return schedule(system)


def _assemble(system: System, q: np.ndarray, psi: np.ndarray, ok: np.ndarray):
    """(q, ok): group by group Newton from ``q (V, 1, n_q)`` at ``psi``, each group on the
    branch of its start pose, as :func:`~kinetostatics.kinematics.start.assemble_start` does
    for one; a variant not ``ok`` (or whose group is ambiguous, does not converge or changes
    branch) keeps its pose from there on and is not ok."""
    for plan in system.plans:
        s0 = group_signature(system, q, plan)[:, 0]
        cond0 = group_condition(system, q, plan)[:, 0]
        qn, conv, _ = group_newton(system, q, psi, plan)
        s1 = group_signature(system, qn, plan)[:, 0]
        ok = ok & (s0 != 0) & (cond0 <= 1e10) & conv[:, 0] & (s1 == s0)
        q = np.where(ok[:, None, None], qn, q)
    return q, ok


def _near_sketch(system: System, q: np.ndarray) -> np.ndarray:
    """(V,): every sketched point within ``SKETCH_TOL``·L_ref of where ``q`` put it."""
    v = len(q)
    tol = SKETCH_TOL * np.broadcast_to(system.l_ref, (v, 1))[:, 0]
    near = np.ones(v, dtype=bool)
    for sp in sketch_distances(system, q):
        near &= np.broadcast_to(sp.distance, (v, 1))[:, 0] <= tol
    return near


def _start(system: System, models: Sequence[Model], sched: Schedule):
    """(q0 (V, 1, n_q), ok (V,), failed): each variant's sketch solved group by group on
    its branch.  A variant that does not assemble there, or whose sketch is ambiguous, is
    not ok (the per-variant analysis reports it).  One that assembles far from its sketch
    is tried where the sketch is, as one analysis does
    (:func:`~kinetostatics.kinematics.start.assemble_start`): if it does not assemble
    there either (or the sketch is of the start), ``failed`` maps it to the error one
    analysis raises; if it does, it is not ok (the per-variant analysis carries it along
    its branch)."""
    v = len(models)
    guess = np.broadcast_to(initial_guess(system), (v, system.n_q))
    psi = sched(np.zeros(1))[0][None]
    q, ok = _assemble(system, guess[:, None].copy(), psi, np.ones(v, dtype=bool))
    far = ok & ~_near_sketch(system, q)
    failed: dict[int, Exception] = {}
    if far.any():
        ok &= ~far
        psi_s, _, same = sketch_step(system, guess, psi[0, 0])
        q_s, there = _assemble(system, guess[:, None].copy(), psi_s[:, None], far & ~same)
        there &= _near_sketch(system, q_s)
        for k in np.flatnonzero(far & ~there):
            failed[int(k)] = sketch_far_error(system, q, variant=int(k))
    for k in np.flatnonzero(ok):  # a joint out of its definition (a cam out of phase)
        exc = start_joint_error(system, q, variant=int(k))
        if exc is not None:
            ok[k] = False
            failed[int(k)] = exc
    return q, ok, failed


def _check_supported(sm: Model, friction: bool) -> None:
    """Refuse what the stacked stages do not broadcast (the loop takes it)."""
    if is_stacked(sm.gravity) or any(
        is_stacked(d.offset) or is_stacked(d.effort) for d in sm.drivers
    ):
        raise Unsupported("gravity or a driver's constants differ between variants")
    for load in sm.loads:
        if load.table is not None:
            at, vals = load.table
            if np.ndim(at) > 1 or np.ndim(vals) > (2 if LOAD_KINDS[load.kind].vector else 1):
                raise Unsupported(f"the table of load '{load.name}' differs between variants")
        if is_stacked(load.axis) or any(
            is_stacked(c.axis) or CONDITION_KINDS[c.kind].scheduled and is_stacked(c.bounds)
            for c in load.active
        ):
            raise Unsupported(
                f"the directions or angle band of load '{load.name}' differ between variants"
            )
    if friction and any(is_stacked(c) for j in sm.joints for c in j.friction_constants()):
        raise Unsupported("friction coefficients differ between variants")
    for j in sm.joints:
        if any(is_stacked(c) for c in j.shape_constants()):
            raise Unsupported(f"the geometry of joint '{j.name}' differs between variants")


def analyze_stacked(
    models: Sequence[Model], *, friction: bool | None = None, stacked: Model | None = None
) -> Stacked:
    """The analysis of the variants at once (see the module's text); ``stacked``:
    ``stack(models)`` if at hand.  Raises :class:`Unsupported` if the model is
    outside the vectorised case.

    The variants that do not assemble at the start or leave the closed forms' path are
    taken out before the costly stages (derivatives, loads, friction solutions), which
    they would only slow down (NaN rows send the friction solution into its homotopy):
    the others go on with their start poses and paths as solved (each variant is solved
    on its own axis, so these are what they would be alone), on the model stacked
    without them; ``Stacked.members`` lists the variants analysed."""
    sm = stack(models) if stacked is None else stacked
    if sm.analysis.at or sm.analysis.events:
        raise Unsupported("extra positions or event rows")
    _check_supported(sm, sm.has_friction if friction is None else friction)
    system = build_system(sm)
    sched = _schedule(system)
    t, full = sample_times(system, sched, None)
    if not full:
        raise Unsupported("not a full cycle")
    q0, ok, failed = _start(system, models, sched)
    solvers = closed_forms(system, q0)
    if solvers is None:  # a group without a closed form: Newton along the path
        q, ok_path = newton_path(system, q0, t, sched)
    else:
        q, ok_path, _, _ = closed_form_path(system, solvers, q0, t, sched)
    ok &= ok_path
    members = np.arange(len(models))
    if not ok.all():
        members = np.flatnonzero(ok)
        if members.size < 2:
            raise LeftOver(ok)
        sm = subset(sm, models, members)
        system = build_system(sm)
        sched = _schedule(system)
        if not np.array_equal(sample_times(system, sched, None)[0], t):
            raise LeftOver(ok)  # pragma: no cover - the times are the file's, alike in all
        q0, q = q0[members], q[members]
        solvers = closed_forms(system, q0)
        ok = ok[members]
    psi, psi_d, psi_dd = sched(t)
    psi, psi_d, psi_dd = (np.broadcast_to(x, q.shape[:-1] + (1,)) for x in (psi, psi_d, psi_dd))
    qd, qdd, lu = derivatives_at(system, q, psi_d, psi_dd)
    extremes = travel_extremes_stacked(system, solvers, sched, t, q, qd, qdd)
    for m in extremes.values():  # a state Newton did not reach: that variant alone
        ok &= np.all(np.isfinite(m), axis=-1)
    kin = inverse_dynamics(
        system,
        Motion(t, psi, q, qd, qdd, psi_d, psi_dd, lu),
        extremes=extremes,
        ref_speed=sched.reference,
        friction=sm.has_friction if friction is None else friction,
    )
    return Stacked(
        members, system, t, psi, q, qd, qdd, lu, kin, extremes, ok, sched, solvers, failed
    )


def output_strokes(st: Stacked) -> dict[str, dict[str, np.ndarray]]:
    """Stroke and time ratio of every output slide, ``(V,)`` each
    (:func:`~kinetostatics.kinematics.events.output_strokes_stacked`); a variant whose slide
    does not stop exactly twice per cycle is marked not ok."""
    out, ok = output_strokes_stacked(st.system, st.solvers, st.sched, st.t, st.q, st.qd, st.qdd)
    st.ok &= ok
    return out


def as_result(st: Stacked):
    """A :class:`~kinetostatics.analysis.results.Result` whose columns are ``(V, N)``."""
    kin = st.kin
    with np.errstate(invalid="ignore"):  # a variant's singular rows: NaN shaking
        shaking = ground_reaction(st.system, st.q, kin.x0)
    motion = Motion(st.t, st.psi, st.q, st.qd, st.qdd, lu=st.lu)
    columns, units = build_columns(st.system, motion, kin, cond={}, shaking=shaking)
    return Result(
        system=st.system,
        t=st.t,
        coordinate=st.psi[..., 0],
        q=st.q,
        qd=st.qd,
        qdd=st.qdd,
        lam=kin.x0,
        columns=columns,
        units=units,
        indeterminate=kin.indeterminate,
        full_cycle=True,
        extremes=st.extremes,
    )
