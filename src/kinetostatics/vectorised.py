"""All variants of one topology in one pass: the stage functions on ``(V, N, ...)``.

:func:`analyze_stacked` runs the analysis of :func:`kinetostatics.analyze`
for many variants at once on a model stacked by
:func:`kinetostatics.stacking.stack`, for the common case it can vectorise:
one constant-speed motion driver over a full cycle, every Assur group with
a closed form (RRR, RRP, RPR dyads and driven links) that passes no
singular position, no event rows.  Variants it cannot take — they do not
assemble at the start, pass a singular position, or the model is
outside that case — are returned as *left over*, for the per-variant
analysis, which reports or handles them exactly as a single run would.

Per variant the results are those of a single run to rounding: the same
functions evaluate the same formulas, only over one more leading axis.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .analysis import Schedule, _times, kinetics
from .dyads import closed_form
from .forces import point_state
from .model import Model, MotionLaw
from .positions import (
    SKETCH_TOL,
    TOL,
    _signature,
    closed_form_near,
    closed_form_path,
    derivatives,
    group_condition,
    initial_guess,
    sketch_distances,
)
from .stacking import is_stacked, stack
from .system import System, build_system, jacobian, phi

__all__ = ["analyze_stacked", "Stacked"]

MAX_ITER = 25


@dataclass
class Stacked:
    """The arrays of a stacked analysis; ``ok (V,)`` marks the variants analysed."""

    system: System
    t: np.ndarray  # (N,)
    psi: np.ndarray  # (V, N, 1)
    q: np.ndarray  # (V, N, n_q)
    qd: np.ndarray
    qdd: np.ndarray
    lu: object
    kin: object  # analysis.Kinetics
    extremes: dict
    ok: np.ndarray  # (V,) bool
    sched: Schedule
    solvers: list


class Unsupported(Exception):
    """The model is outside the vectorised case (the reason is the message)."""


class LeftOver(Unsupported):
    """Some variants do not assemble at the start or leave the closed forms' path;
    ``ok (V,)`` marks the others.  Raised before the costly stages (derivatives,
    loads, friction solutions), which a failing variant would only slow down (its
    NaN rows send the friction solution into its homotopy): analyse the ``ok``
    variants again on their own, the others one by one."""

    def __init__(self, ok: np.ndarray):
        self.ok = ok
        super().__init__(
            f"{int(np.count_nonzero(~ok))} of {len(ok)} variants leave the vectorised path"
        )


def _schedule(system: System) -> Schedule:
    model = system.model
    drivers = system.motion_drivers
    if len(drivers) != 1 or system.structure.mobility != 1:
        raise Unsupported("more than one motion driver")
    motion = drivers[0].driver.motion
    if (
        not isinstance(motion, MotionLaw)
        or getattr(motion, "acceleration", 0.0)
        or getattr(motion, "start", None) is not None
    ):
        raise Unsupported("a motion law other than constant speed")
    speed = motion.speed
    start = model.analysis.start
    if np.ndim(speed) or np.ndim(start) or np.ndim(model.analysis.sweep):
        raise Unsupported("the driver's speed or the analysed range differs between variants")
    return Schedule(np.array([start]), np.array([speed]))


def _newton(system: System, q: np.ndarray, psi: np.ndarray, plan) -> tuple[np.ndarray, np.ndarray]:
    """Newton on one group for every entry of ``q (V, M, n_q)`` (no subsets: the
    variant axis must stay aligned with the stacked parameters)."""
    cols = plan.cols
    ang = np.arange(len(cols)) % 3 == 2
    l_ref = np.asarray(system.l_ref)[..., None] if np.ndim(system.l_ref) else system.l_ref
    step_tol = np.where(ang, TOL, TOL * l_ref)
    q = q.copy()
    for _ in range(MAX_ITER):
        r = phi(system, q, psi, plan.constraints)
        jac = jacobian(system, q, plan.constraints, cols)
        with np.errstate(all="ignore"):
            try:
                dx = np.linalg.solve(jac, -r[..., None])[..., 0]
            except np.linalg.LinAlgError:
                dx = (np.linalg.pinv(jac) @ -r[..., None])[..., 0]
        dx = np.where(np.isfinite(dx), dx, 0.0)
        q[..., cols] += dx
        if np.all(np.abs(dx) <= step_tol):
            break
    res = np.max(np.abs(phi(system, q, psi, plan.constraints)), axis=-1)
    return q, res <= TOL * np.asarray(system.l_ref)


def _start(system: System, models: Sequence[Model], sched: Schedule):
    """(q0 (V, 1, n_q), ok (V,)): each variant's sketch solved group by group on
    its branch; a variant whose sketch is ambiguous or that does not assemble is
    not ok (the per-variant analysis reports it)."""
    q = np.broadcast_to(initial_guess(system), (len(models), system.n_q))[:, None].copy()
    psi = sched(np.zeros(1))[0][None]
    ok = np.ones(len(models), dtype=bool)
    for plan in system.plans:
        s0 = _signature(system, q, plan)[:, 0]
        cond0 = group_condition(system, q, plan)[:, 0]
        qn, conv = _newton(system, q, psi, plan)
        s1 = _signature(system, qn, plan)[:, 0]
        ok &= (s0 != 0) & (cond0 <= 1e10) & conv[:, 0] & (s1 == s0)
        q = np.where(ok[:, None, None], qn, q)
    tol = SKETCH_TOL * np.broadcast_to(system.l_ref, (len(models), 1))
    for sp in sketch_distances(system, q):  # assembled far from the sketch: refused
        ok &= np.broadcast_to(sp.distance, (len(models), 1))[:, 0] <= tol[:, 0]
    return q, ok


def _state(system: System, solvers, sched: Schedule, t: np.ndarray, guess: np.ndarray):
    """(q, q̇, q̈) at times ``t (V, M)`` by the closed forms, angles nearest ``guess``."""
    psi, psi_d, psi_dd = sched(t)
    q, _ = closed_form_near(solvers, guess, psi)
    qd, qdd, _ = derivatives(system, q, psi_d, psi_dd)
    return q, qd, qdd


def refine_roots(system, solvers, sched, f, t0, q0, qd0, qdd0, max_iter: int = 12):
    """Newton on t for ``f(q, q̇, q̈) = (g, ġ) = 0``, all variants and roots at once.

    ``t0 (V, M)`` first guesses, ``q0, qd0, qdd0 (V, M, n_q)`` solved states
    near them (same branch); returns (t, (q, q̇, q̈)) at the roots.
    """
    t = np.array(t0, dtype=float)
    h = (t - t0)[..., None]
    guess = q0 + h * qd0 + 0.5 * h * h * qdd0
    for _ in range(max_iter):
        q, qd, qdd = _state(system, solvers, sched, t, guess)
        g, dg = f(q, qd, qdd)
        dt = np.divide(-g, dg, out=np.zeros_like(g), where=dg != 0)
        t = t + dt
        guess = q + dt[..., None] * qd + 0.5 * (dt * dt)[..., None] * qdd
        if np.all(np.abs(dt) <= 1e-14 * np.maximum(np.abs(t), 1.0)):
            break
    return t, _state(system, solvers, sched, t, guess)


def _extremes(system, solvers, sched, t, q, qd, qdd) -> dict:
    """Exact minima over the cycle of the ``travel`` conditions' p·axis, ``(V, 1)``."""
    from .analysis import travel_conditions

    extremes: dict[int, np.ndarray] = {}
    for c, k, p in travel_conditions(system):
        pos = point_state(q, qd, None, k, p)[0]
        s = np.sum(pos * c.axis, axis=-1)
        n = np.argmin(s, axis=-1)
        take = lambda a: np.take_along_axis(a, n[:, None, None], axis=1)  # noqa: E731
        _, (qm, _, _) = refine_roots(
            system,
            solvers,
            sched,
            lambda a, b, cc: (
                np.sum(point_state(a, b, cc, k, p)[1] * c.axis, axis=-1),
                np.sum(point_state(a, b, cc, k, p)[2] * c.axis, axis=-1),
            ),
            t[n][:, None],
            take(q),
            take(qd),
            take(qdd),
        )
        sm = np.sum(point_state(qm, qm, None, k, p)[0] * c.axis, axis=-1)
        extremes[id(c)] = np.minimum(sm, np.min(s, axis=-1, keepdims=True))
    return extremes


def _check_supported(sm: Model, friction: bool) -> None:
    """Refuse what the stacked stages do not broadcast (the loop takes it)."""
    if is_stacked(sm.gravity) or any(
        is_stacked(d.offset) or is_stacked(d.effort) for d in sm.drivers
    ):
        raise Unsupported("gravity or a driver's constants differ between variants")
    for load in sm.loads:
        if load.table is not None:
            at, vals = load.table
            if np.ndim(at) > 1 or np.ndim(vals) > (2 if load.kind == "force" else 1):
                raise Unsupported(f"the table of load '{load.name}' differs between variants")
        if is_stacked(load.axis) or any(
            is_stacked(c.axis) or c.kind == "angle" and is_stacked(c.bounds) for c in load.active
        ):
            raise Unsupported(
                f"the directions or angle band of load '{load.name}' differ between variants"
            )
    if friction and any(is_stacked(c) for j in sm.joints for c in j.friction_constants()):
        raise Unsupported("friction coefficients differ between variants")


def analyze_stacked(
    models: Sequence[Model], *, friction: bool | None = None, stacked: Model | None = None
) -> Stacked:
    """The analysis of every variant at once (see the module's text); ``stacked``:
    ``stack(models)`` if at hand.  Raises :class:`Unsupported` if the model is
    outside the vectorised case."""
    sm = stack(models) if stacked is None else stacked
    if sm.analysis.at or sm.analysis.events:
        raise Unsupported("extra positions or event rows")
    _check_supported(sm, sm.has_friction if friction is None else friction)
    system = build_system(sm)
    sched = _schedule(system)
    t, full = _times(system, sched, None)
    if not full:
        raise Unsupported("not a full cycle")
    q0, ok = _start(system, models, sched)
    solvers = [closed_form(system, plan, q0) for plan in system.plans]
    if any(s is None for s in solvers):
        raise Unsupported("a group without a closed form")
    q, ok_path, _ = closed_form_path(system, solvers, q0, t, sched)
    ok &= ok_path
    if not ok.all():
        raise LeftOver(ok)
    psi, psi_d, psi_dd = sched(t)
    psi, psi_d, psi_dd = (np.broadcast_to(x, q.shape[:-1] + (1,)) for x in (psi, psi_d, psi_dd))
    qd, qdd, lu = derivatives(system, q, psi_d, psi_dd)
    extremes = _extremes(system, solvers, sched, t, q, qd, qdd)
    kin = kinetics(
        system,
        q,
        qd,
        qdd,
        psi,
        lu=lu,
        extremes=extremes,
        ref_speed=sched.reference,
        friction=sm.has_friction if friction is None else friction,
    )
    return Stacked(system, t, psi, q, qd, qdd, lu, kin, extremes, ok, sched, solvers)


def output_strokes(st: Stacked) -> dict[str, dict[str, np.ndarray]]:
    """Stroke and time ratio of every undriven prismatic pair, ``(V,)`` each, from
    the exact zeros of its sliding speed (as :func:`kinetostatics.summary.output_strokes`).
    A variant whose slide does not stop exactly twice per cycle is marked not ok."""
    from .summary import _bias, _coordinate
    from .system import coordinate_gradient

    system, out = st.system, {}
    driven = {d.joint.name for d in system.motion_drivers}
    period = 2 * np.pi / st.sched.reference
    n = st.q.shape[1]
    for k, j in enumerate(system.model.joints):
        if not j.reports_stroke or j.name in driven:
            continue

        def f(q, qd, qdd, k=k):
            g = coordinate_gradient(system, q, k)
            return (
                np.einsum("...n,...n->...", g, qd),
                np.einsum("...n,...n->...", g, qdd) + _bias(system, q, qd, k),
            )

        ds = f(st.q, st.qd, st.qdd)[0]
        a = np.arange(n)
        b = (a + 1) % n  # a full cycle: the last pairs with the first
        fa, fb = ds[:, a], ds[:, b]
        cross = (np.sign(fa) * np.sign(fb) < 0) | (fa == 0.0)
        two = np.count_nonzero(cross, axis=-1) == 2
        st.ok &= two
        idx = np.argsort(~cross, axis=-1, kind="stable")[:, :2]  # the first two crossings
        ia, ib = idx, (idx + 1) % n
        ta, tb = st.t[ia], st.t[ib] + np.where(ib == 0, period, 0.0)
        fa, fb = np.take_along_axis(ds, ia, -1), np.take_along_axis(ds, ib, -1)
        near_b = np.abs(fb) < np.abs(fa)
        nn = np.where(near_b, ib, ia)
        with np.errstate(invalid="ignore", divide="ignore"):
            guess = np.where(fa == 0.0, ta, ta + (tb - ta) * fa / (fa - fb))
        take = lambda x: np.take_along_axis(x, nn[..., None], axis=1)  # noqa: E731
        roots, (qr, _, _) = refine_roots(
            system, st.solvers, st.sched, f, guess, take(st.q), take(st.qd), take(st.qdd)
        )
        roots = np.mod(roots, period)
        vals = _coordinate(system, qr, k)
        lo = np.argmin(vals, axis=-1)[:, None]
        hi = 1 - lo
        r_lo = np.take_along_axis(roots, lo, -1)[:, 0]
        r_hi = np.take_along_axis(roots, hi, -1)[:, 0]
        t_up = np.mod(r_hi - r_lo, period)
        t_down = period - t_up
        stroke = np.abs(vals[:, 1] - vals[:, 0])
        out[j.name] = {
            "stroke": np.where(two, stroke, np.nan),
            "time_ratio": np.where(
                two, np.maximum(t_up, t_down) / np.minimum(t_up, t_down), np.nan
            ),
        }
    return out


def as_result(st: Stacked):
    """A :class:`~kinetostatics.results.Result` whose columns are ``(V, N)``."""
    from .results import Result, build_columns

    kin = st.kin
    columns, units = build_columns(
        st.system,
        st.t,
        st.psi,
        st.q,
        st.qd,
        st.qdd,
        kin.x0,
        kin.friction,
        kin.power,
        {},
        None,
        True,
    )
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
