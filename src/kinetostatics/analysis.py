"""``analyze``: the pipeline from a model to a :class:`~kinetostatics.results.Result`.

Read top to bottom: schedule → positions → velocities/accelerations → load
events → loads → reactions → friction → power → result columns.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, replace

import numpy as np

from . import friction as fr
from ._checks import real_array
from .differences import difference_derivatives
from .errors import AssemblyError, Location, SingularConfigurationError, StructureError
from .forces import angle_band, external_forces, gravity_forces, inertia_forces, mass_vector
from .model import Condition, Model, MotionLaw
from .positions import (
    PositionSolution,
    Singularity,
    condition_number,
    derivatives,
    group_condition,
    reachable_range,
    solve_positions,
    state_at,
)
from .reactions import (
    EFFORT_SPEED_TOL,
    effort_joints,
    effort_speed_ratio,
    equilibrium_matrix,
    ground_reaction,
    invert_equilibrium,
    solve_equilibrium,
)
from .results import Result, build_columns
from .system import System, build_system

__all__ = [
    "analyze",
    "kinetics",
    "Kinetics",
    "Schedule",
    "Event",
    "numerical_mobility",
    "travel_extremes",
    "whole_motion",
]


@dataclass(frozen=True)
class Schedule:
    """Motion drivers' laws: ψ_d(t) = start_d + speed_d·t + ½·acceleration_d·t² (constant
    speed or acceleration), or the driver's motion law (``laws[d]``,
    :mod:`kinetostatics.motion`) where one is given."""

    start: np.ndarray  # (n_d,) ψ(0)
    speed: np.ndarray  # (n_d,) speed at t = 0, or a law's signed reference speed
    laws: tuple = ()  # per driver: a motion law, or None for constant speed; () if none
    acceleration: np.ndarray | None = None  # (n_d,); None: constant speeds

    def __call__(self, t):
        t = np.asarray(t, dtype=float)[..., None]
        psi = self.start + self.speed * t
        psi_d = np.broadcast_to(self.speed, t.shape[:-1] + self.speed.shape)
        psi_dd = np.zeros(t.shape[:-1] + self.speed.shape)
        if self.acceleration is not None:
            a = self.acceleration
            psi, psi_d, psi_dd = psi + 0.5 * a * t * t, psi_d + a * t, psi_dd + a
        if self.laws:
            psi_d = psi_d.copy()
            for k, law in enumerate(self.laws):
                if law is not None:
                    psi[..., k], psi_d[..., k], psi_dd[..., k] = law.value(0.0, t[..., 0])
        return psi, psi_d, psi_dd

    @property
    def reference(self) -> float:
        """|speed| of the first driver (a law's largest |ψ̇|), rad/s or m/s."""
        return float(abs(self.speed[0]))

    @property
    def law(self):
        """The first driver's motion law, or None for constant speed."""
        return self.laws[0] if self.laws else None

    def turning_times(self, lo: float, hi: float) -> np.ndarray:
        """Times in [lo, hi] where a driver's law turns back (ψ̇ = 0); none at constant speed."""
        from .motion import turning_times

        return np.concatenate(
            [np.zeros(0)] + [turning_times(law, lo, hi) for law in self.laws if law is not None]
        )

    @property
    def period(self) -> float:
        """Time of one cycle (s): one turn at constant speed, a cyclic law's duration."""
        if self.law is not None:
            return self.law.duration if self.law.cyclic else np.inf
        return 2 * np.pi / self.reference


@dataclass(frozen=True)
class Event:
    """A load switching on or off, located exactly."""

    t: float
    coordinate: float  # driver coordinate, rad (or m)
    load: str
    condition: str
    switch: str  # "on" or "off"


def _schedule(system: System) -> Schedule:
    from .positions import initial_guess

    drivers = system.motion_drivers
    q0 = initial_guess(system)
    starts = []
    for k, d in enumerate(drivers):
        if d.driver.motion.start is not None:  # a constant-speed law's own start, or a law's
            starts.append(d.driver.motion.start)
        elif k == 0:
            starts.append(system.model.analysis.start)
        else:
            qe = np.concatenate((q0, np.zeros(3)))
            i, j = system.ends[system.constraints.index(d)]
            starts.append(float(d.coordinate(qe[3 * i : 3 * i + 3], qe[3 * j : 3 * j + 3])))
    laws = tuple(
        None if isinstance(d.driver.motion, MotionLaw) else d.driver.motion for d in drivers
    )
    accel = np.array(
        [
            getattr(d.driver.motion, "acceleration", 0.0) if law is None else 0.0
            for d, law in zip(drivers, laws)
        ]
    )
    return Schedule(
        np.array(starts),
        np.array([d.driver.motion.speed for d in drivers]),
        laws if any(law is not None for law in laws) else (),
        accel if np.any(accel) else None,
    )


def _times(
    system: System, sched: Schedule, coordinates: np.ndarray | None
) -> tuple[np.ndarray, bool]:
    """Times of the requested positions; whether they cover a full cycle."""
    a = system.model.analysis
    if sched.law is not None:
        if coordinates is not None:
            raise ValueError(
                f"driver '{system.motion_drivers[0].name}' follows a {sched.law.kind} "
                "motion law: give the positions as times, analyze(..., times=...)"
            )
        n, law = a.positions, sched.law
        t = (
            np.arange(n) * law.duration / n
            if law.cyclic
            else np.linspace(0.0, law.duration, n)
            if n > 1
            else np.zeros(1)
        )
        return t, law.cyclic
    w = sched.speed[0]
    period = 2 * np.pi if system.motion_drivers[0].joint.angular else np.inf
    if coordinates is not None:
        d = (np.asarray(coordinates, dtype=float) - a.start) * np.sign(w)
        if np.isfinite(period):
            d = np.mod(d, period)
        return d / abs(w), False
    step = a.sweep / a.positions
    d = np.arange(a.positions) * step
    extra = np.array([(c - a.start) * np.sign(w) for c in a.at])
    if np.isfinite(period) and extra.size:
        extra = np.mod(extra, period)
    full = np.isfinite(period) and abs(a.sweep - period) < 1e-9
    return np.concatenate((d, extra)) / abs(w), full


def _condition_rate(system: System, c: Condition, q, qd, qdd, psi, extremes):
    """(value, d value/dt) of a condition's switching function."""
    from .forces import point_state

    k = system.link_index(c.link)
    p = system.model.link(c.link).points[c.point] if c.point else np.zeros(2)
    pos, vel, acc = point_state(q, qd, qdd, k, p)
    if c.kind == "moving":
        return vel @ c.axis, acc @ c.axis
    return pos @ c.axis - extremes[id(c)], vel @ c.axis


def _refine(system, drive, f, t0, tn, qn, qdn, qddn, max_iter=12, bracket=None):
    """Newton on t for f(state) = 0, all roots at once.

    ``t0 (k,)`` first guesses, ``tn`` and ``qn``/``qdn``/``qddn`` the solved
    samples nearest to each (same branch).  ``bracket``, optional, is
    ``(lo, hi, sign_lo)``: each root lies in [lo, hi], where f has the sign
    ``sign_lo`` at lo and the other at hi; a Newton step that would leave the
    bracket (which shrinks with every evaluation) is replaced by bisection, so
    the iteration never wanders to another part of the motion.  Returns the
    roots ``(k,)`` and their states.
    """
    t = np.array(t0, dtype=float)
    live = np.ones(t.shape, dtype=bool)
    states = [qn.copy(), qdn.copy(), qddn.copy()]
    if bracket is not None:
        lo, hi, sign_lo = (np.array(x, dtype=float) for x in bracket)
        max_iter = max(max_iter, 64)  # bisection halves the bracket each time
    for _ in range(max_iter):
        if not live.any():
            break
        idx = np.nonzero(live)[0]
        q, qd, qdd = state_at(system, drive, t[idx], tn[idx], qn[idx], qdn[idx], qddn[idx])
        for store, new in zip(states, (q, qd, qdd)):
            store[idx] = new
        g, dg = f(q, qd, qdd)
        dt = np.divide(-g, dg, out=np.zeros_like(g), where=dg != 0)
        tol = 1e-14 * np.maximum(np.abs(t[idx]), 1.0)
        done = (np.abs(dt) <= tol) | (g == 0)
        if bracket is None:
            done |= dg == 0
            t[idx] += dt
        else:
            below = np.sign(g) == sign_lo[idx]
            lo[idx] = np.where(below, t[idx], lo[idx])
            hi[idx] = np.where(below, hi[idx], t[idx])
            step = t[idx] + dt
            out = ~((step > lo[idx]) & (step < hi[idx])) | (dg == 0)
            done |= hi[idx] - lo[idx] <= tol
            t[idx] = np.where(done, t[idx], np.where(out, 0.5 * (lo[idx] + hi[idx]), step))
        live[idx[done]] = False
    return t, states


def _find_roots(system, drive, t, q, qd, qdd, fvals, f, full, period_t):
    """Times where fvals changes sign between samples (cyclically if full), refined."""
    order = np.argsort(t)
    ts, fs_ = t[order], fvals[order]
    a = np.arange(len(ts) - 1)
    b = a + 1
    if full:
        a, b = np.append(a, len(ts) - 1), np.append(b, 0)
    sa, sb = np.sign(fs_[a]), np.sign(fs_[b])
    # a sign change, or a zero sample that starts one (a value held at zero is no switch)
    prev = np.sign(fs_[np.r_[a[:1] - 1, a[:-1]] % len(fs_)]) if full else np.r_[0.0, sa[:-1]]
    cross = np.nonzero((sa * sb < 0) | ((sa == 0) & (sb != 0) & (prev != sb)))[0]
    if not cross.size:
        return np.zeros(0), [np.zeros((0,) + q.shape[1:])] * 3
    a, b = a[cross], b[cross]
    wrap = (b == 0) * (period_t if full else 0.0)
    tb = ts[b] + wrap
    fa, fb = fs_[a], fs_[b]
    near_b = np.abs(fb) < np.abs(fa)
    n = np.where(near_b, order[b], order[a])
    tn = t[n] + np.where(near_b, wrap, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        guess = np.where(fa == 0.0, ts[a], ts[a] + (tb - ts[a]) * fa / (fa - fb))
    sign_a = np.where(fa == 0.0, -np.sign(fb), np.sign(fa))
    roots, states = _refine(
        system, drive, f, guess, tn, q[n], qd[n], qdd[n], bracket=(ts[a], tb, sign_a)
    )
    return (np.mod(roots, period_t) if full else roots), states


def travel_conditions(system: System):
    """(condition, link index, local point) of every ``travel`` condition of a load."""
    for load in system.model.loads:
        for c in load.active:
            if c.kind == "travel":
                p = system.model.link(c.link).points[c.point] if c.point else np.zeros(2)
                yield c, system.link_index(c.link), p


MOTION_GRID = 360
"""Samples of the whole motion (1° steps of a turn) that bracket the travel extremes and the
load switches; the grid is fixed, independent of the analysed positions, and every local
minimum and sign change on it is refined exactly."""

_MOTION: weakref.WeakKeyDictionary[System, _Motion] = weakref.WeakKeyDictionary()


def whole_motion(system: System, sched: Schedule | None = None):
    """The time span of the whole motion, on which travel extremes are taken:
    ``(t0, t1, periodic, drive)``.

    - constant speed, revolute first driver: one turn of it, t ∈ [0, 2π/|ω|) (periodic);
      a constant acceleration is dropped (for one driver the poses depend on ψ only);
    - a motion law: its run t ∈ [0, duration] (one period of a cyclic law);
    - constant speed, prismatic first driver: the file's run, ``analysis.sweep``.
    Where the linkage cannot follow it, :func:`travel_extremes` narrows it to the
    reachable range.
    """
    sched = _schedule(system) if sched is None else sched
    if sched.law is not None:
        return 0.0, float(sched.law.duration), False, sched
    drive = sched if sched.acceleration is None else Schedule(sched.start, sched.speed)
    w = abs(float(sched.speed[0]))
    if system.motion_drivers[0].joint.angular:
        return 0.0, 2 * np.pi / w, True, drive
    return 0.0, float(system.model.analysis.sweep) / w, False, drive


@dataclass
class _Motion:
    """The whole motion sampled on the fixed grid, and what is found on it (cached)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    periodic: bool
    drive: Schedule
    turns: np.ndarray  # (n_q,): 2π × turns of each link angle per period
    extremes: dict | None = None
    events: list | None = None  # [(Event, (q, qd, qdd))] over the grid's span


def _motion_grid(system: System, sched: Schedule | None) -> _Motion:
    m = _MOTION.get(system)
    if m is not None:
        return m
    t0, t1, periodic, drive = whole_motion(system, sched)
    n = MOTION_GRID
    t = t0 + (t1 - t0) * np.arange(n) / n if periodic else np.linspace(t0, t1, n + 1)
    try:
        sol = solve_positions(system, t, drive)
    except AssemblyError as exc:
        if isinstance(exc, SingularConfigurationError) or drive.law is not None:
            raise
        lo, hi = reachable_range(system, drive, t1)  # a crank that cannot turn fully
        margin = 1e-6 * (hi - lo)  # the limits themselves are singular
        t, periodic = np.linspace(lo + margin, hi - margin, n + 1), False
        sol = solve_positions(system, t, drive)
    q = sol.q
    _, psi_d, psi_dd = drive(t)
    qd, qdd, _ = derivatives(system, q, psi_d, psi_dd)
    turns = np.zeros(q.shape[-1])
    if periodic:  # q(t + T) = q(t) + turns on the angle slots
        h = t[1] - t[0]
        end = q[-1] + h * qd[-1] + 0.5 * h * h * qdd[-1]
        turns[2::3] = 2 * np.pi * np.round((end - q[0])[2::3] / (2 * np.pi))
    m = _Motion(t, q, qd, qdd, periodic, drive, turns)
    _MOTION[system] = m
    return m


def travel_extremes(system: System, sched: Schedule | None = None) -> dict:
    """Exact minima of p·axis of every ``travel`` condition over the whole motion
    (:func:`whole_motion`), ``{id(condition): value}``; computed once per system.

    The motion is sampled on a fixed grid (:data:`MOTION_GRID`), every discrete local
    minimum (and a motion law's turning points) is refined by Newton on t for v·axis = 0,
    and the least value is kept, so a row's loads never depend on which other rows an
    analysis asks for.
    """
    from .forces import point_state

    conds = list(travel_conditions(system))
    if not conds:
        return {}
    try:
        m = _motion_grid(system, sched)
    except AssemblyError as exc:
        exc.args = (
            f"{exc.args[0]}; a travel band is measured from its extreme over the whole "
            "motion (one turn of the driver, or a motion law's run), which must "
            "assemble",
        )
        raise
    if m.extremes is not None:
        return dict(m.extremes)
    t, q, qd, qdd, periodic, drive = m.t, m.q, m.qd, m.qdd, m.periodic, m.drive
    step = (t[-1] - t[0]) / (len(t) - 1)
    turning = drive.turning_times(t[0], t[-1]) if drive.laws else np.zeros(0)
    out: dict[int, float] = {}
    for c, k, p in conds:
        pos, vel, _ = point_state(q, qd, None, k, p)
        s, v = pos @ c.axis, vel @ c.axis
        best = float(s.min())
        flat = float(s.max()) - best <= 1e-12 * float(np.max(system.l_ref))
        if periodic:  # strict on one side: a plateau is not a row of minima
            low = (s < np.roll(s, 1)) & (s <= np.roll(s, -1))
        else:  # interior minima: an end of the span counts as sampled
            low = np.zeros(s.shape, dtype=bool)
            low[1:-1] = (s[1:-1] < s[:-2]) & (s[1:-1] <= s[2:])
        idx = np.nonzero(low & ~flat)[0]
        near = np.abs(turning[:, None] - t[None, :]).argmin(axis=1) if turning.size else idx[:0]

        def f(a, bb, cc, ax=c.axis, kk=k, pp=p):
            _, v, acc = point_state(a, bb, cc, kk, pp)
            return v @ ax, acc @ ax

        brackets = [_minimum_bracket(t, v, b, step, periodic) for b in idx]
        sets = [
            (
                t[idx[[i for i, br in enumerate(brackets) if br is not None]]],
                idx[[i for i, br in enumerate(brackets) if br is not None]],
                [br for br in brackets if br is not None],
            ),
            (
                np.concatenate(
                    (t[idx[[i for i, br in enumerate(brackets) if br is None]]], turning)
                ),
                np.concatenate((idx[[i for i, br in enumerate(brackets) if br is None]], near)),
                None,
            ),
        ]
        for t_start, b, br in sets:
            if not t_start.size:
                continue
            bracket = None if br is None else tuple(np.concatenate(x) for x in zip(*br))
            try:
                tm, (qm, _, _) = _refine(
                    system, drive, f, t_start, t[b], q[b], qd[b], qdd[b], bracket=bracket
                )
            except AssemblyError:  # Newton left the reachable poses: keep the samples
                continue
            sm = point_state(qm, qm, None, k, p)[0] @ c.axis
            inside = (np.abs(tm - t_start) <= 1.5 * step) & (
                periodic | ((t[0] <= tm) & (tm <= t[-1]))
            )
            ok = np.isfinite(sm) & inside  # stayed in its bracket
            if ok.any():
                best = min(best, float(np.min(sm[ok])))
        out[id(c)] = best
    m.extremes = out
    return dict(out)


def _minimum_bracket(t, v, b, step, periodic):
    """([lo], [hi], [−1]) around the sampled minimum ``b`` of a position whose rate is
    ``v``: the sample interval beside it where v turns from negative to positive, or
    None where the samples show no such turn (the refinement then stays unbracketed)."""
    n = len(t)
    if v[b] == 0.0:
        return None
    if v[b] > 0.0:  # the minimum lies before the sample
        a = b - 1
        if a < 0 and not periodic or v[a % n] >= 0.0:
            return None
        return np.array([t[b] - step]), np.array([t[b]]), np.array([-1.0])
    a = b + 1
    if a >= n and not periodic or v[a % n] <= 0.0:
        return None
    return np.array([t[b]]), np.array([t[b] + step]), np.array([-1.0])


def _extremes_and_events(system, drive, sched, t, q, qd, qdd, full, states=False):
    """Exact minima of travel conditions over the whole motion (:func:`travel_extremes`, not
    over the analysed rows) and the switching events of every load within the run (with
    ``states``: also the events' states, see :func:`_events_of_run`)."""
    extremes, events, at = _events_of_run(system, drive, sched, t, q, qd, qdd, full)
    return (extremes, events, at) if states else (extremes, events)


def _events_of_run(system, drive, sched, t, q, qd, qdd, full):
    """(extremes, events, states): the load switches of the whole motion (found once on its
    fixed grid) that fall within the run — every one for a full cycle — with their states
    (q, q̇, q̈); where the whole motion does not cover the run (a law or a prismatic
    driver's run left, several drivers, a constant acceleration), the switches found
    between the analysed rows, with states None."""
    extremes = travel_extremes(system, sched)
    m = None
    switching = any(c.kind != "angle" for load in system.model.loads for c in load.active)
    if switching and len(system.motion_drivers) == 1 and sched.acceleration is None:
        try:
            m = _motion_grid(system, sched)
        except AssemblyError:  # the whole motion does not assemble (a change point)
            m = None
    if m is not None and m.events is None:
        period_t = m.t[-1] - m.t[0] + (m.t[1] - m.t[0]) if m.periodic else np.inf
        found = _switches(
            system, m.drive, sched, m.t, m.q, m.qd, m.qdd, m.periodic, period_t, extremes
        )
        if not m.periodic:  # a reachable range: angle bands' edges within it, if any
            found = [(e, st) for e, st in (_into_span(m, e, st) for e, st in found) if e]
        m.events = [
            (
                e,
                st
                if st is not None
                else tuple(x[0] for x in _state_near(system, m.drive, e.t, m.t, m.q, m.qd, m.qdd)),
            )
            for e, st in found
        ]
    if m is not None:
        lo, hi = float(np.min(t)), float(np.max(t))
        tol = 1e-9 * (m.t[-1] - m.t[0])
        picked = []
        if m.periodic:
            period_t = m.t[-1] - m.t[0] + (m.t[1] - m.t[0])
            for e, (qe, qde, qdde) in m.events:
                if full:
                    picked.append((e, (qe, qde, qdde)))
                    continue
                for k in range(
                    int(np.ceil((lo - tol - e.t) / period_t)),
                    int(np.floor((hi + tol - e.t) / period_t)) + 1,
                ):
                    te = e.t + k * period_t
                    picked.append(
                        (
                            replace(e, t=te, coordinate=float(drive(np.array([te]))[0][0, 0])),
                            (qe + k * m.turns, qde, qdde),
                        )
                    )
        elif m.t[0] - tol <= lo and hi <= m.t[-1] + tol:
            top = m.t[-1] - tol if full else hi + tol  # a full cycle does not repeat its end
            picked = [
                (e, st) for e, st in m.events if lo - tol <= e.t <= top or (full and e.t < lo)
            ]
        else:
            m = None
        if m is not None:
            picked.sort(key=lambda x: x[0].t)
            return extremes, [e for e, _ in picked], [st for _, st in picked]
    period_t = sched.period if full else np.inf
    found = _switches(system, drive, sched, t, q, qd, qdd, full, period_t, extremes)
    return extremes, [e for e, _ in found], [None] * len(found)


def _into_span(m: _Motion, e: Event, st):
    """An angle band's switch (placed in the first turn, no state yet) moved by whole turns
    into the span of a motion that is not a full turn, or (None, None) where no turn of it
    falls there (the driver never reaches that angle)."""
    if st is not None or m.drive.law is not None or not (len(m.t) and m.t[-1] > m.t[0]):
        return e, st
    turn = 2 * np.pi / m.drive.reference
    k = np.ceil((m.t[0] - e.t) / turn)
    te = e.t + k * turn
    if te > m.t[-1]:
        return None, None
    return replace(e, t=float(te), coordinate=float(m.drive(np.array([te]))[0][0, 0])), None


def _switches(system, drive, sched, t, q, qd, qdd, full, period_t, extremes):
    """[(Event, state or None)]: angle-band switches (from the schedule) and the sign
    changes of the other conditions between the samples ``t``, refined, sorted by time."""
    psi = drive(t)[0][..., 0]
    events: list = []
    for load in system.model.loads:
        for c in load.active:
            if c.kind == "angle":
                start, width = angle_band(system, c)
                if width >= 2 * np.pi:
                    continue  # always on: no switch
                for bound, sw in ((start, "on"), (start + width * np.sign(sched.speed[0]), "off")):
                    tt = (
                        np.mod((bound - sched.start[0]) * np.sign(sched.speed[0]), 2 * np.pi)
                        / sched.reference
                    )
                    events.append(
                        (
                            Event(
                                float(tt),
                                float(drive(np.array([tt]))[0][0, 0]),
                                load.name,
                                "angle",
                                sw,
                            ),
                            None,
                        )
                    )
                continue
            funcs = (
                [(0.0, "moving")]
                if c.kind == "moving"
                else [(c.bounds[0], "travel from"), (c.bounds[1], "travel to")]
            )
            for offset, label in funcs:

                def f(a, b, cc, c=c, offset=offset):
                    g, dg = _condition_rate(system, c, a, b, cc, None, extremes)
                    return g - offset, dg

                vals = _condition_rate(system, c, q, qd, qdd, psi, extremes)[0] - offset
                noise = (
                    1e-12
                    * float(np.max(system.l_ref))
                    * (sched.reference if c.kind == "moving" else 1.0)
                )
                vals = np.where(np.abs(vals) <= noise, 0.0, vals)  # round-off is no switch
                roots, (qs, qds, qdds) = _find_roots(
                    system, drive, t, q, qd, qdd, vals, f, full, period_t
                )
                for r, qr, qdr, qddr in zip(roots, qs[:, None], qds[:, None], qdds[:, None]):
                    g, dg = f(qr[0], qdr[0], qddr[0])
                    psi_r = drive(np.array([r]))[0][..., 0]
                    if not _others_hold(system, load, c, qr, qdr, psi_r, extremes, sched):
                        continue
                    inside_up = dg > 0 if c.kind == "moving" or offset == c.bounds[0] else dg < 0
                    events.append(
                        (
                            Event(
                                float(r),
                                float(drive(np.array([r]))[0][0, 0]),
                                load.name,
                                label,
                                "on" if inside_up else "off",
                            ),
                            (qr[0], qdr[0], qddr[0]),
                        )
                    )
    events.sort(key=lambda e: e[0].t)
    return events


def _others_hold(system, load, cond, q, qd, psi, extremes, sched) -> bool:
    """Whether every other condition of ``load`` holds (bands inclusive) at a state."""
    from .forces import activity
    from .model import Load

    others = tuple(c for c in load.active if c is not cond)
    probe = Load(load.name, load.kind, load.link, load.value, load.point, load.axis, others)
    return bool(activity(system, probe, q, qd, psi, extremes, sched.reference)[0])


def _state_near(system, drive, r, t, q, qd, qdd):
    n = int(np.argmin(np.abs(t - r)))
    return state_at(
        system, drive, np.array([r]), t[n : n + 1], q[n : n + 1], qd[n : n + 1], qdd[n : n + 1]
    )


def analyze(
    model: Model | System,
    *,
    positions: np.ndarray | None = None,
    times: np.ndarray | None = None,
    friction: bool | None = None,
    events: bool | None = None,
    derivatives_by: str = "jacobian",
    step: float = np.radians(1.0),
    reachable: bool = False,
    kinematics_only: bool = False,
) -> Result:
    """Kinematics and kinetostatics over the positions of ``model.analysis``.

    Parameters
    ----------
    model : Model or System
        A loaded model, or a system built from one with ``build_system`` (reused).
    positions : array, optional
        Driver coordinates (rad, or m for a prismatic driver) to analyse instead
        of ``analysis.positions``/``at`` (constant-speed drivers only).
    times : array, optional
        Times (s, from the start of the run) to analyse instead — for any
        motion law; a non-monotone law is followed in time.
    friction : bool, optional
        Solve the friction solutions (default: when the model has friction).
    events : bool, optional
        Add rows at the exact positions where loads switch (default
        ``analysis.events``).
    derivatives_by : {"jacobian", "forward", "central"}
        Velocities and accelerations from the constraint Jacobian (exact), or
        — as a comparison mode only — by the source text's forward difference
        quotients or by central differences with driver step ``step`` (rad or m).
    reachable : bool
        If the linkage cannot follow the whole sweep (a crank that cannot fully
        rotate), analyse ``analysis.positions`` positions spread over the
        reachable range between its limit positions instead of raising.
    kinematics_only : bool
        Positions, velocities and accelerations only: no loads, events,
        reactions, friction or power are computed (and no such columns exist).

    Returns
    -------
    Result
        Named arrays over the positions (CSV names and units), raw arrays
        ``q``, ``qd``, ``qdd``, ``lam``, the events and the structure.

    Raises
    ------
    ValueError
        ``positions`` or ``times`` not a non-empty 1-D list of finite real numbers
        in range (times from 0; limits in docs/errors.md), naming the entry.
    NonFiniteResultError
        A NaN or infinity in the results that neither self-locking nor a singular
        position explains (a model built in Python beyond the file limits).
    """
    system = model if isinstance(model, System) else build_system(model)
    model = system.model
    n_motion = len(system.motion_drivers)
    if n_motion != system.structure.mobility or n_motion == 0:
        raise StructureError(
            [
                (
                    Location(model.source, path="drivers"),
                    f"analyze needs as many motion drivers as the mobility "
                    f"({system.structure.mobility}); the file has {n_motion}",
                )
            ]
        )
    sched = _schedule(system)
    if times is not None and positions is not None:
        raise ValueError("give positions (driver coordinates) or times, not both")
    if positions is not None:
        positions = _checked_positions(system, positions)
    if times is not None:
        t, full = _checked_times(system, sched, times), False
    else:
        t, full = _times(system, sched, positions)
    # rows given as driver coordinates (positions=, `at`), placed a turn ahead by _times
    given = np.zeros(len(t), dtype=bool)
    if positions is not None:
        given[:] = True
    elif times is None and model.analysis.at:
        given[len(t) - len(model.analysis.at) :] = True
        order = np.argsort(t, kind="stable")  # `at` rows take their place in the run
        t, given = t[order], given[order]
    closing = full and sched.law is not None  # one period of the law: does the pose repeat?
    try:
        sol: PositionSolution = solve_positions(
            system, np.append(t, sched.law.duration) if closing else t, sched
        )
    except AssemblyError as exc:
        if sched.law is not None:
            raise _law_out_of_reach(system, sched, exc) from None
        if isinstance(exc, SingularConfigurationError) or times is not None:
            raise
        behind = (
            _positions_behind(system, sched, t, given, exc, sort=positions is None)
            if given.any()
            else None
        )
        if behind is not None:
            t, sol = behind
        elif positions is not None:
            raise
        else:
            t, sol, full = _reachable_run(system, sched, t, exc, reachable)
    if closing:
        full = _same_pose(system, sol.q[-1], sol.q[0])
        sol = replace(
            sol, q=sol.q[:-1], signatures=sol.signatures[:-1], iterations=sol.iterations[:-1]
        )
    q = sol.q
    psi, psi_d, psi_dd = sched(t)
    if derivatives_by == "jacobian":
        qd, qdd, lu = derivatives(system, q, psi_d, psi_dd)
    else:  # no kinematic factors: the reactions build their own
        qd, qdd = difference_derivatives(system, sched, t, q, derivatives_by, step)
        lu = None
    if kinematics_only:
        return _kinematics_result(system, sol, t, psi, q, qd, qdd, lu, full)
    extremes, evts, states = _extremes_and_events(
        system, sched, sched, t, q, qd, qdd, full, states=True
    )
    want_events = model.analysis.events if events is None else events
    if want_events and evts:
        te = np.array([e.t for e in evts])
        qe, qde, qdde = zip(
            *(
                tuple(x[None] for x in st)
                if st is not None
                else _state_near(system, sched, e.t, t, q, qd, qdd)
                for e, st in zip(evts, states)
            )
        )
        t = np.concatenate((t, te))
        q, qd, qdd = (
            np.concatenate((a, np.concatenate(b))) for a, b in ((q, qe), (qd, qde), (qdd, qdde))
        )
        order = np.argsort(t, kind="stable")
        t, q, qd, qdd = t[order], q[order], qd[order], qdd[order]
        psi, psi_d, psi_dd = sched(t)
        lu = None
    kin = kinetics(
        system,
        q,
        qd,
        qdd,
        psi,
        lu=lu,
        extremes=extremes,
        ref_speed=sched.reference,
        friction=model.has_friction if friction is None else friction,
    )
    x0, fric, power = kin.x0, kin.friction, kin.power
    sol.singular.extend(
        Singularity("equilibrium", float(t[k]), float(psi[k, 0]), float(kin.condition[k]))
        for k in np.nonzero(kin.singular)[0]
    )
    cond = _conditions(system, q, lu)
    _warn_near_singular(system, cond, psi[..., 0])
    shaking = ground_reaction(system, q, x0)
    _check_finite(
        system, t, psi, cond, sol.singular, q=q, qd=qd, qdd=qdd, x0=x0, fric=fric, power=power
    )
    columns, units = build_columns(system, t, psi, q, qd, qdd, x0, fric, power, cond, shaking, full)
    return Result(
        system=system,
        t=t,
        coordinate=psi[..., 0],
        q=q,
        qd=qd,
        qdd=qdd,
        lam=x0,
        columns=columns,
        units=units,
        events=tuple(evts),
        singular=tuple(sol.singular),
        indeterminate=kin.indeterminate,
        full_cycle=full,
        extremes=extremes,
    )


def _reachable_run(
    system: System, sched: Schedule, t: np.ndarray, exc: AssemblyError, reachable: bool
):
    """The run of a crank that cannot follow the sweep: ``exc`` with the reachable range
    added, or (``reachable``) (t, solution, full) over that range."""
    try:
        lo, hi = reachable_range(system, sched, float(np.max(t)) + 1e-9)
    except AssemblyError:
        raise exc from None  # not even the start assembles
    if not reachable:
        exc.reachable = tuple(sched(np.array([lo, hi]))[0][:, 0])
        exc.args = (
            f"{exc.args[0]}; the reachable range is {_range_text(system, sched, lo, hi)}"
            " (analyze(..., reachable=True) analyses it)",
        )
        raise exc
    margin = 1e-6 * (hi - lo)  # the limits themselves are singular
    t = np.linspace(lo + margin, hi - margin, system.model.analysis.positions)
    sol = solve_positions(system, t, sched)
    plan = next(p for p in system.plans if p.group.label == exc.group)
    for k, tk in ((0, lo), (-1, hi)):  # the limit positions are singular positions
        sol.singular.append(
            Singularity(
                exc.group,
                tk,
                float(sched(np.array([tk]))[0][0, 0]),
                float(group_condition(system, sol.q[k], plan)),
            )
        )
    return t, sol, False


def _positions_behind(
    system: System,
    sched: Schedule,
    t: np.ndarray,
    given: np.ndarray,
    exc: AssemblyError,
    sort: bool,
):
    """Rows given as driver coordinates (``positions=``, ``at``) for a constant-speed crank
    that cannot turn fully: ``_times`` placed them up to a turn ahead of the start, where
    the linkage does not reach; a coordinate behind the start is reached running
    backwards on the same branch (a negative time).  Each given row beyond the reachable
    range [lo, hi] is moved a turn back when that lands inside it (otherwise to whichever
    of the two is nearer the start).  Returns (t, solution), sorted by time if ``sort``,
    or None where that does not apply (a full-turn crank, a prismatic driver); raises
    ``exc`` with the reachable range when a given row lies outside it either way."""
    if not system.motion_drivers[0].joint.angular or len(system.motion_drivers) != 1:
        return None
    period = 2 * np.pi / sched.reference
    try:
        lo, hi = reachable_range(system, sched, period)
    except AssemblyError:
        return None
    if hi - lo >= period:
        return None  # it turns fully: the failure is elsewhere
    tol = 1e-12 * period
    inside = lambda x: (x >= lo - tol) & (x <= hi + tol)  # noqa: E731
    back = t - period
    move = given & ~inside(t) & (inside(back) | (~inside(back) & (np.abs(back) < np.abs(t))))
    t = np.where(move, back, t)
    if np.any(~given & ~inside(t)):
        return None  # the grid itself leaves the range
    if np.any(given & ~inside(t)):
        k = int(np.argmax(given & ~inside(t)))
        far = float(sched(t[k : k + 1])[0][0, 0])
        exc.reachable = tuple(sched(np.array([lo, hi]))[0][:, 0])
        exc.args = (
            f"{system.motion_drivers[0].name} = {np.degrees(far) % 360:.6g}° is out of "
            f"reach ({exc.args[0]}); the reachable range is "
            f"{_range_text(system, sched, lo, hi)}, running forwards or backwards from "
            "analysis.start",
        )
        raise exc
    if sort:
        t = np.sort(t, kind="stable")
    return t, solve_positions(system, t, sched)


def _checked_positions(system: System, positions) -> np.ndarray:
    """``analyze(positions=...)``: finite driver coordinates within the file's limits (a revolute's
    |ψ| as an angle of the file, a prismatic's distance from ``analysis.start`` as its sweep)."""
    from .base.limits import MAGNITUDE, MAX_TRAVEL

    if system.motion_drivers[0].joint.angular:
        limit = MAGNITUDE["angle"][1]
        return real_array(
            "positions",
            positions,
            low=-limit,
            high=limit,
            why="rad; larger angles have lost their precision",
        )
    start, reach = system.model.analysis.start, MAX_TRAVEL * float(np.max(system.l_ref))
    return real_array(
        "positions",
        positions,
        low=start - reach,
        high=start + reach,
        why=f"m: at most {MAX_TRAVEL} times the largest link from analysis.start",
    )


def _checked_times(system: System, sched: Schedule, times) -> np.ndarray:
    """``analyze(times=...)``: finite times up to the time of the longest run a file may ask
    for (:data:`~kinetostatics.yaml_io.MAX_TURNS` periods of a law or turns of a crank,
    :data:`~kinetostatics.yaml_io.MAX_TRAVEL` times the largest link of a slider).  A motion
    law is not defined before its start: its times count from 0.  A constant-speed driver is:
    a negative time is a position before the start, reached by running the linkage backwards
    (as far back as forwards)."""
    from .base.limits import MAX_TRAVEL, MAX_TURNS

    if sched.law is not None:
        high, why = MAX_TURNS * sched.law.duration, f"s: {MAX_TURNS} times the law's duration"
    elif system.motion_drivers[0].joint.angular:
        high = MAX_TURNS * 2 * np.pi / sched.reference
        why = f"s: {MAX_TURNS} turns of the driver"
    else:
        high = MAX_TRAVEL * float(np.max(system.l_ref)) / sched.reference
        why = f"s: a travel of {MAX_TRAVEL} times the largest link"
    if sched.law is not None:
        return real_array(
            "times",
            times,
            low=0.0,
            high=high,
            why=why + "; a motion law's times count from its start, t = 0",
        )
    return real_array(
        "times",
        times,
        low=-high,
        high=high,
        why=why + " either side of the start of the run, t = 0",
    )


NONFINITE_COND = 1e15
"""A row whose group condition number is above this (or infinite) is at a singular
position: non-finite velocities or reactions there are explained, not a defect."""


def _check_finite(
    system: System, t, psi, cond: dict, singular, *, q, qd, qdd, x0=None, fric=None, power=None
) -> None:
    """The last guard of :func:`analyze`: a NaN or infinity that no status explains raises
    :class:`~kinetostatics.errors.NonFiniteResultError` naming the column and the row.

    Explained are the consistent friction solution where it self-locks
    (``friction.status`` 2: its columns are empty there) and every value at a
    singular position (a reported one, or a group condition number above
    :data:`NONFINITE_COND`).  Nothing else may be non-finite: the file's limits
    (``yaml_io.MAGNITUDE``) keep the products of a model far from overflow, so a
    NaN here comes from a model built in Python with values beyond them.
    """
    n = len(t)
    excused = np.zeros(n, dtype=bool)
    for c in cond.values():
        c = np.asarray(c, dtype=float).reshape(-1)
        if c.size == n:
            excused |= ~(c <= NONFINITE_COND)
    for sp in singular:
        excused |= np.isclose(t, sp.t, rtol=0.0, atol=1e-9 * max(1.0, abs(sp.t)))
    locked = excused.copy()
    if fric is not None:
        locked |= np.asarray(fric["solution"].status).reshape(-1) == 2
    names = [f"{name}.{label}" for name in system.links for label in ("x", "y", "theta")]
    rate = {"x": "vx", "y": "vy", "theta": "omega"}
    acc = {"x": "ax", "y": "ay", "theta": "alpha"}
    arrays = [
        (q, names, excused),
        (qd, [n.rsplit(".", 1)[0] + "." + rate[n.rsplit(".", 1)[1]] for n in names], excused),
        (qdd, [n.rsplit(".", 1)[0] + "." + acc[n.rsplit(".", 1)[1]] for n in names], excused),
    ]
    if x0 is not None:
        n_j = system.n_joint_rows
        labels = [""] * x0.shape[-1]
        for k, j in enumerate(system.model.joints):
            for r in range(x0.shape[-1])[system.rows_of(k)]:
                labels[r] = (
                    f"the reaction of joint {j.name} "
                    f"({', '.join(f'{j.name}.{x}' for x in j.reaction_labels)})"
                )
        for d_index, d in enumerate(system.motion_drivers):
            effort_joint = (
                system.model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
            )
            labels[n_j + d_index] = f"{d.name}.{'torque' if effort_joint.angular else 'force'}"
        arrays.append((x0, labels, excused))
    if fric is not None:
        sol = fric["solution"]
        arrays.append((sol.x, [f"{x} (with friction)" for x in labels], locked))
        arrays.append(
            (
                sol.e,
                [f"{system.model.joints[k].name}.friction" for k in fric["setup"].joints],
                locked,
            )
        )
        arrays.append((fric["x_approx"], [f"{x} (approximate friction)" for x in labels], excused))
    for key, value in (power or {}).items():
        late = key in ("friction", "input_friction", "residual_friction")
        arrays.append((np.asarray(value)[..., None], [f"power.{key}"], locked if late else excused))
    for arr, labels, ok in arrays:
        arr = np.asarray(arr, dtype=float)
        if arr.ndim != 2 or arr.shape[0] != n:
            continue  # stacked variants: not checked here
        bad = ~np.isfinite(arr) & ~ok[:, None]
        if bad.any():
            row, col = (int(i) for i in np.argwhere(bad)[0])
            label = labels[col] if col < len(labels) else f"column {col}"
            d = system.motion_drivers[0]
            where = (
                f"{d.name} = {np.degrees(psi[row, 0]) % 360:.6g}°"
                if d.joint.angular
                else f"{d.name} = {psi[row, 0] * 1e3:.6g} mm"
            )
            from .errors import NonFiniteResultError

            raise NonFiniteResultError(
                label,
                row,
                f"the analysis gave {arr[row, col]} in {label} at row {row} ({where}, t = "
                f"{t[row]:.6g} s), with no self-locking or singular position to explain it: "
                "the model's numbers overflow (masses, "
                "lengths, loads or gravity too large or too small; see the input limits in "
                "docs/errors.md)",
            )


def _same_pose(system: System, qa: np.ndarray, qb: np.ndarray) -> bool:
    """Whether two poses agree (lengths to 1e-9·L_ref, angles to 1e-9 rad, modulo 2π): a law
    that is periodic need not bring the linkage back (it may cross to the other assembly)."""
    d = qa - qb
    d[2::3] = (d[2::3] + np.pi) % (2 * np.pi) - np.pi
    d[0::3] /= system.l_ref
    d[1::3] /= system.l_ref
    return bool(np.max(np.abs(d)) <= 1e-9)


COND_WARN = 1e8
"""A group condition number above this is warned about: relative errors of
positions there can reach ~1e-16 × condition, and reactions grow like it."""


def _warn_near_singular(system: System, cond: dict, coord: np.ndarray) -> None:
    import warnings

    from .errors import NearSingularWarning

    for group, c in cond.items():
        bad = np.nonzero(c > COND_WARN)[0]
        if bad.size:
            k = bad[np.argmax(c[bad])]
            name = system.motion_drivers[0].name
            where = (
                f"{np.degrees(coord[k]) % 360:.4g}°"
                if system.motion_drivers[0].joint.angular
                else f"{coord[k] * 1e3:.6g} mm"
            )
            warnings.warn(
                f"{group.label} is nearly singular at {bad.size} position(s), worst at "
                f"{name} = {where} (condition {c[k]:.3g} > {COND_WARN:.0e}); "
                "reactions there are unreliable",
                NearSingularWarning,
                stacklevel=3,
            )


def _conditions(system: System, q: np.ndarray, lu) -> dict:
    return {
        p.group: (
            condition_number(system, p, lu.jac[..., p.rows[:, None], p.cols], lu.inv[g])
            if lu is not None
            else group_condition(system, q, p)
        )
        for g, p in enumerate(system.plans)
        if p.group.kind != "driven"
    }


def _kinematics_result(system, sol, t, psi, q, qd, qdd, lu, full) -> Result:
    cond = _conditions(system, q, lu)
    _warn_near_singular(system, cond, psi[..., 0])
    _check_finite(system, t, psi, cond, sol.singular, q=q, qd=qd, qdd=qdd)
    columns, units = build_columns(system, t, psi, q, qd, qdd, None, None, None, cond, None, full)
    return Result(
        system=system,
        t=t,
        coordinate=psi[..., 0],
        q=q,
        qd=qd,
        qdd=qdd,
        lam=np.zeros(q.shape[:-1] + (0,)),
        columns=columns,
        units=units,
        singular=tuple(sol.singular),
        full_cycle=full,
    )


def _law_out_of_reach(system: System, sched: Schedule, exc: AssemblyError) -> AssemblyError:
    """``exc`` with the law's range and the linkage's reachable range of the driver coordinate
    added (from a constant-speed sweep of the first driver from the law's start)."""
    law, d = sched.law, system.motion_drivers[0]
    psi = law.value(0.0, np.linspace(0.0, law.duration, 4097))[0]
    text = (
        f"{exc.args[0]}; following the {law.kind} law of {d.name} in time, the linkage "
        f"assembles up to t = {getattr(exc, 't_reached', float('nan')):.6g} s; the law spans "
        f"{_coordinate_range(d, psi.min(), psi.max())}"
    )
    if len(system.motion_drivers) == 1:
        sweep = Schedule(np.array([law.start]), np.array([1.0]))
        span = 2 * np.pi if d.joint.angular else 2 * float(np.ptp(psi)) + system.l_ref
        try:
            lo, hi = reachable_range(system, sweep, span)
        except AssemblyError:
            lo = hi = None
        if lo is not None:
            exc.reachable = (law.start + lo, law.start + hi)
            text += f", the linkage reaches only {_coordinate_range(d, *exc.reachable)}"
    exc.args = (text,)
    return exc


def _coordinate_range(d, a: float, b: float) -> str:
    if d.joint.angular:
        return f"{d.name} from {np.degrees(a):.4f}° to {np.degrees(b):.4f}°"
    return f"{d.name} from {a * 1e3:.6g} mm to {b * 1e3:.6g} mm"


def _range_text(system: System, sched: Schedule, lo: float, hi: float) -> str:
    a, b = sched(np.array([lo, hi]))[0][:, 0]
    d = system.motion_drivers[0]
    if d.joint.angular:
        return f"{d.name} from {np.degrees(a) % 360:.4f}° to {np.degrees(b) % 360:.4f}°"
    return f"{d.name} from {a * 1e3:.6g} mm to {b * 1e3:.6g} mm"


@dataclass
class Kinetics:
    """Loads, reactions, friction and power at given states (arrays over positions)."""

    q_gravity: np.ndarray
    q_inertia: np.ndarray
    q_external: np.ndarray
    a: np.ndarray  # equilibrium matrix A, (..., n_q, n_lam)
    x0: np.ndarray  # frictionless multipliers and driver efforts
    indeterminate: bool
    friction: dict | None  # setup, x_approx, e_approx, solution (see friction.py)
    power: dict
    singular: np.ndarray | None = None  # (...) A singular there: x0 NaN, friction.status 2
    condition: np.ndarray | None = None  # (...) scaled condition number of a square A

    @property
    def q_load(self) -> np.ndarray:
        return self.q_gravity + self.q_inertia + self.q_external


def kinetics(
    system: System,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    psi: np.ndarray,
    *,
    ref_speed: float,
    lu=None,
    extremes: dict | None = None,
    friction: bool = False,
) -> Kinetics:
    """Inverse dynamics at states (q, q̇, q̈) with driver coordinates ``psi (..., n_d)``.

    Loads (gravity, d'Alembert inertia, external loads active at these states),
    the frictionless reactions and driver efforts, the friction solutions when
    ``friction`` and the model has friction, and the power terms.  ``lu``: the
    kinematic factorisation of Φ_q at q, if at hand; ``extremes``: the extremes of
    ``travel`` conditions (``Result.extremes``; by default :func:`travel_extremes`, over
    the whole motion); ``ref_speed``: the driver speed that scales the zero-speed thresholds.
    """
    model = system.model
    if extremes is None:
        extremes = travel_extremes(system)
    q_grav = gravity_forces(system, q.shape[:-1])
    q_inert = inertia_forces(system, qdd)
    q_ext = external_forces(system, q, qd, psi[..., 0], extremes, ref_speed)
    q_load = q_grav + q_inert + q_ext
    own_efforts = all(d.driver.balance_at is None for d in system.motion_drivers)
    singular, condition, a_inv = np.zeros(q.shape[:-1], dtype=bool), None, None
    if lu is not None and own_efforts:
        a = np.swapaxes(lu.jac, -1, -2)  # A = Φ_qᵀ: reuse the kinematic factors
        x0, indeterminate = lu.solve_transposed(-q_load), False
    else:
        a = equilibrium_matrix(system, q)
        if a.shape[-1] == a.shape[-2]:  # singular positions: NaN rows, the rest intact
            a_inv, singular, condition = invert_equilibrium(a, system.l_ref)
            if not own_efforts and len(system.motion_drivers) == 1:
                # the effort's joint (nearly) at rest: no effort to round-off accuracy there
                near = effort_speed_ratio(system, q, qd) <= EFFORT_SPEED_TOL
                singular |= near
                a_inv[near] = np.nan
            bad = ~np.isfinite(a_inv[..., 0, 0])
            x0 = np.linalg.solve(
                np.where(bad[..., None, None], np.eye(a.shape[-1]), a), -q_load[..., None]
            )[..., 0]
            x0[bad], indeterminate = np.nan, False
            if singular.any():
                _warn_singular_equilibrium(system, singular, psi[..., 0])
        else:
            x0, indeterminate = solve_equilibrium(a, -q_load)
    fric = None
    if friction and model.has_friction and a.shape[-1] != a.shape[-2]:
        raise StructureError([(Location(model.source, path="joints"), _not_square(system, a))])
    if friction and model.has_friction:
        fs = fr.setup(system, q, qd, ref_speed)
        if lu is not None and own_efforts:
            solve_a = lu.solve_transposed  # A = Φ_qᵀ: back substitution over the groups
        else:
            if a_inv is None:
                a_inv = np.linalg.inv(a)
            solve_a = lambda rhs: np.einsum("...ij,...j->...i", a_inv, rhs)  # noqa: E731
        xa, ea = fr.approximate(system, fs, solve_a, q_load, x0)
        cons = fr.consistent(system, fs, a, solve_a, q_load, x0)
        fric = dict(setup=fs, x_approx=xa, e_approx=ea, solution=cons)
    eff = effort_joints(system)
    rel = np.stack([np.einsum("...n,...n->...", _grad(system, q, k), qd) for k in eff], axis=-1)
    n_j = system.n_joint_rows
    power = {
        "input": np.sum(x0[..., n_j:] * rel, axis=-1),
        "kinetic": np.einsum("...n,...n->...", qd, mass_vector(system) * qdd),
        "potential": -np.einsum("...n,...n->...", qd, q_grav),
        "external": -np.einsum("...n,...n->...", qd, q_ext),
    }
    power["residual"] = power["input"] - power["kinetic"] - power["potential"] - power["external"]
    if fric is not None:
        cons = fric["solution"]
        loss = np.sum(np.abs(cons.e * fric["setup"].speed), axis=-1)
        power["friction"] = loss
        power["input_friction"] = np.sum(cons.x[..., n_j:] * rel, axis=-1)
        power["residual_friction"] = (
            power["input_friction"]
            - power["kinetic"]
            - power["potential"]
            - power["external"]
            - loss
        )
    return Kinetics(q_grav, q_inert, q_ext, a, x0, indeterminate, fric, power, singular, condition)


def _not_square(system: System, a: np.ndarray) -> str:
    """Why friction cannot be solved with a non-square equilibrium matrix A (n_q × n_λ)."""
    n_q, n_lam = a.shape[-2:]
    n_m, mob = len(system.motion_drivers), system.structure.mobility
    if n_lam < n_q:
        return (
            f"friction needs the efforts of as many motion drivers as the mobility ({mob}); "
            f"there are {n_m}: the loads are not balanced by unknown efforts (the "
            f"equilibrium has {n_q} equations and {n_lam} unknowns)"
        )
    redundant = redundant_joints(system, a.reshape((-1,) + a.shape[-2:])[0])
    return (
        f"the linkage is overconstrained: joint(s) {', '.join(redundant) or '?'} "
        f"are redundant ({n_lam} unknown reactions and efforts for {n_q} equations), so "
        "their reactions are statically indeterminate (the frictionless analysis reports "
        "the minimum-norm ones, flagged indeterminate) and the friction that depends on "
        "them is not determined either: analyse without friction (friction=False) or "
        "remove the redundant joints"
    )


def redundant_joints(system: System, a: np.ndarray) -> list[str]:
    """Joints whose constraint columns of A (one position, ``(n_q, n_λ)``) add nothing to
    the rank of those before them (in file order): the redundant ones.  A is scaled as in
    :func:`~kinetostatics.reactions.invert_equilibrium` (moment rows / L_ref, unit
    columns); a column adds rank where its residual from the earlier ones exceeds 1e-9."""
    s = np.array(a, dtype=float)
    s[2::3, :] /= float(np.max(system.l_ref))
    norms = np.linalg.norm(s, axis=0)
    s /= np.where(norms > 0, norms, 1.0)
    basis = np.zeros((s.shape[0], 0))
    out = []
    for k, j in enumerate(system.model.joints):
        cols = s[:, system.rows_of(k)]
        if basis.shape[1]:
            cols = cols - basis @ (basis.T @ cols)
        u, sv, _ = np.linalg.svd(cols, full_matrices=False)
        keep = sv > 1e-9
        if not keep.all():
            out.append(j.name)
        basis = np.concatenate((basis, u[:, keep]), axis=1)
    return out


def _warn_singular_equilibrium(system: System, singular: np.ndarray, coord: np.ndarray) -> None:
    """Warn of the positions where no finite effort balances the loads, naming them."""
    import warnings

    from .errors import SingularEquilibriumWarning

    d = system.motion_drivers[0]
    at = np.broadcast_to(coord, singular.shape)[singular]
    where = ", ".join(
        f"{np.degrees(c) % 360:.6g}°" if d.joint.angular else f"{c * 1e3:.6g} mm" for c in at[:8]
    ) + (f" and {at.size - 8} more" if at.size > 8 else "")
    joints = sorted({(m.driver.balance_at or m.joint.name) for m in system.motion_drivers})
    warnings.warn(
        f"the equilibrium is singular at {d.name} = {where}: the effort at "
        f"{', '.join(joints)} cannot balance the loads there (a dead centre); the "
        "reactions and efforts there are NaN, friction.status 2, listed among the "
        "singular positions as 'equilibrium'",
        SingularEquilibriumWarning,
        stacklevel=3,
    )


def _grad(system, q, k):
    from .system import coordinate_gradient

    return coordinate_gradient(system, q, k)


def numerical_mobility(system: System) -> int:
    """n_q − rank Φ_q (joints only) at the first assembled position; warns if it
    differs from Grübler–Kutzbach (an overconstrained or special linkage)."""
    import warnings

    from .positions import initial_guess
    from .system import jacobian as _jac

    n_j = len(system.model.joints)
    q = initial_guess(system)
    if system.motion_drivers and len(system.motion_drivers) == system.structure.mobility:
        sched = _schedule(system)
        q = solve_positions(system, np.array([0.0]), sched).q[0]
    jac = _jac(system, q, range(n_j))
    s = np.linalg.svd(jac, compute_uv=False)
    rank = int(np.sum(s > 1e-9 * max(s.max(initial=0.0), 1.0)))
    n = system.n_q - rank
    if n != system.structure.mobility:
        warnings.warn(
            f"numerical mobility {n} differs from Grübler–Kutzbach "
            f"{system.structure.mobility}: the linkage is overconstrained or special",
            stacklevel=2,
        )
    return n
