"""Load conditions: when a load acts (its ``active:`` list of
:class:`~kinetostatics.model.Condition`).

What each kind of condition is — ``moving`` (a point's speed along an axis is positive),
``travel`` (its position along an axis, from its least value over the whole motion, lies in
a band), ``angle`` (the first driver's coordinate lies in a band) — is its entry in
:data:`~kinetostatics.kinetics.kinds.CONDITION_KINDS`; this module applies them:

- their values and the activity of a load at given states (:func:`activity`);
- the travel extremes over the whole motion, sampled on a fixed grid and refined exactly
  (:func:`travel_extremes`; the stacked form :func:`travel_extremes_stacked`);
- the switching events of the loads within a run, located exactly (:func:`load_events`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import AssemblyError, SingularConfigurationError
from ..kinematics.derivatives import derivatives
from ..kinematics.events import find_roots, refine, refine_stacked, state_near
from ..kinematics.positions import reachable_range, solve_positions
from ..kinematics.schedule import Schedule, schedule
from ..kinematics.state import local_point, point_state
from ..model import Condition, Load
from ..structure.system import System
from .kinds import CONDITION_KINDS, ZERO_SPEED, angle_band

__all__ = [
    "ZERO_SPEED",
    "Event",
    "angle_band",
    "condition_state",
    "condition_values",
    "activity",
    "switch_levels",
    "travel_conditions",
    "MOTION_GRID",
    "whole_motion",
    "travel_extremes",
    "travel_extremes_stacked",
    "load_events",
]


@dataclass(frozen=True)
class Event:
    """A load switching on or off, located exactly."""

    t: float
    coordinate: float  # driver coordinate, rad (or m)
    load: str
    condition: str
    switch: str  # "on" or "off"


# -- the conditions at given states ------------------------------------------------------
def condition_state(system: System, cond: Condition, q, qd, qdd, psi, extremes):
    """(value, rate): the signed quantity whose sign or band decides a condition, ``(...)``,
    and its time derivative (None for an angle band, or for ``moving`` without ``qdd``).

    moving: v·axis (rate a·axis); travel: p·axis − min over the whole motion (rate v·axis);
    angle: the driver coordinate travelled from ``from`` in the sense of motion (mod 2π).
    """
    return CONDITION_KINDS[cond.kind].state(system, cond, q, qd, qdd, psi, extremes)


def condition_values(system: System, cond: Condition, q, qd, psi, extremes) -> np.ndarray:
    """The value of :func:`condition_state` at states (q, q̇) and driver coordinate ``psi``."""
    return condition_state(system, cond, q, qd, None, psi, extremes)[0]


def activity(system: System, load: Load, q, qd, psi, extremes, ref_speed: float) -> np.ndarray:
    """Boolean ``(...)``: all of the load's conditions hold (bands inclusive)."""
    active = np.ones(q.shape[:-1], dtype=bool)
    for c in load.active:
        v = condition_values(system, c, q, qd, psi, extremes)
        active &= CONDITION_KINDS[c.kind].holds(system, c, v, ref_speed)
    return active


def switch_levels(cond: Condition) -> list[tuple[float, str]]:
    """``[(level, label)]``: a ``moving`` or ``travel`` condition switches where its value
    (:func:`condition_state`) crosses a level: 0 (moving), or either edge of the band."""
    return CONDITION_KINDS[cond.kind].levels(cond)


# -- travel extremes over the whole motion ----------------------------------------------
def travel_conditions(system: System):
    """(condition, link index, local point) of every ``travel`` condition of a load."""
    for load in system.model.loads:
        for c in load.active:
            if CONDITION_KINDS[c.kind].extremes:
                yield c, system.link_index(c.link), local_point(system, c.link, c.point)


MOTION_GRID = 360
"""Samples of the whole motion (1° steps of a turn) that bracket the travel extremes and the
load switches; the grid is fixed, independent of the analysed positions, and every local
minimum and sign change on it is refined exactly."""


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
    sched = schedule(system) if sched is None else sched
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
    m = system.memo.get("motion")
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
    system.memo["motion"] = m
    return m


def travel_extremes(system: System, sched: Schedule | None = None) -> dict:
    """Exact minima of p·axis of every ``travel`` condition over the whole motion
    (:func:`whole_motion`), ``{id(condition): value}``; computed once per system.

    The motion is sampled on a fixed grid (:data:`MOTION_GRID`), every discrete local
    minimum (and a motion law's turning points) is refined by Newton on t for v·axis = 0,
    and the least value is kept, so a row's loads never depend on which other rows an
    analysis asks for.
    """
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
    t, drive = m.t, m.drive
    turning = drive.turning_times(t[0], t[-1]) if drive.laws else np.zeros(0)
    out = {id(cond[0]): _least_travel(system, m, cond, turning) for cond in conds}
    m.extremes = out
    return dict(out)


def _least_travel(system: System, m: _Motion, cond: tuple, turning: np.ndarray) -> float:
    """The least p·axis of one travel condition ``cond`` (condition, link, point) over the
    whole motion ``m``: the samples' least, and each sampled local minimum and the law's
    ``turning`` times refined by Newton on t for v·axis = 0 (kept where it stayed in its
    bracket)."""
    c, k, p = cond
    t, q, qd, qdd, periodic, drive = m.t, m.q, m.qd, m.qdd, m.periodic, m.drive
    step = (t[-1] - t[0]) / (len(t) - 1)
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
            np.concatenate((t[idx[[i for i, br in enumerate(brackets) if br is None]]], turning)),
            np.concatenate((idx[[i for i, br in enumerate(brackets) if br is None]], near)),
            None,
        ),
    ]
    for t_start, b, br in sets:
        if not t_start.size:
            continue
        bracket = None if br is None else tuple(np.concatenate(x) for x in zip(*br))
        try:
            tm, (qm, _, _) = refine(
                system, drive, f, t_start, t[b], q[b], qd[b], qdd[b], bracket=bracket
            )
        except AssemblyError:  # Newton left the reachable poses: keep the samples
            continue
        sm = point_state(qm, qm, None, k, p)[0] @ c.axis
        inside = (np.abs(tm - t_start) <= 1.5 * step) & (periodic | ((t[0] <= tm) & (tm <= t[-1])))
        ok = np.isfinite(sm) & inside  # stayed in its bracket
        if ok.any():
            best = min(best, float(np.min(sm[ok])))
    return best


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


def travel_extremes_stacked(system, solvers, sched, t, q, qd, qdd) -> dict:
    """Exact minima over the cycle of the ``travel`` conditions' p·axis for stacked variants
    over a full cycle ``q (V, N, n_q)`` (the closed forms), ``{id(condition): (V, 1)}``."""
    extremes: dict[int, np.ndarray] = {}
    for c, k, p in travel_conditions(system):
        pos = point_state(q, qd, None, k, p)[0]
        s = np.sum(pos * c.axis, axis=-1)
        n = np.argmin(s, axis=-1)
        take = lambda a, n=n: np.take_along_axis(a, n[:, None, None], axis=1)

        def f(a, b, cc, c=c, k=k, p=p):
            return (
                np.sum(point_state(a, b, cc, k, p)[1] * c.axis, axis=-1),
                np.sum(point_state(a, b, cc, k, p)[2] * c.axis, axis=-1),
            )

        _, (qm, _, _) = refine_stacked(
            system, solvers, sched, f, t[n][:, None], take(q), take(qd), take(qdd)
        )
        sm = np.sum(point_state(qm, qm, None, k, p)[0] * c.axis, axis=-1)
        extremes[id(c)] = np.minimum(sm, np.min(s, axis=-1, keepdims=True))
    return extremes


# -- the load switches of a run ---------------------------------------------------------
def _on_the_motion(system: System) -> bool:
    """Some load acts under a condition on the motion (its switches are found on the whole
    motion's grid), not only on the schedule (an angle band)."""
    loads = system.model.loads
    return any(not CONDITION_KINDS[c.kind].scheduled for load in loads for c in load.active)


def load_events(system, sched, motion, full):
    """(extremes, events, states): the exact minima of the travel conditions over the whole
    motion (:func:`travel_extremes`, not over the analysed rows), and the load switches of
    the whole motion (found once on its fixed grid) that fall within the run of ``motion``
    (a :class:`~kinetostatics.kinematics.motion.Motion`) — every one for a full cycle —
    with their states (q, q̇, q̈); where the whole motion does not cover the run (a law or
    a prismatic driver's run left, several drivers, a constant acceleration), the switches
    found between the analysed rows, with states None."""
    t, q, qd, qdd, drive = motion.t, motion.q, motion.qd, motion.qdd, sched
    extremes = travel_extremes(system, sched)
    m = None
    switching = _on_the_motion(system)
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
                else tuple(x[0] for x in state_near(system, m.drive, e.t, m.t, m.q, m.qd, m.qdd)),
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
    span = float(np.max(t) - np.min(t)) if len(t) > 1 else 1.0
    rows = (t, q, qd, qdd, psi)
    events: list = []
    for load in system.model.loads:
        for c in load.active:
            kind = CONDITION_KINDS[c.kind]
            if kind.scheduled:  # an angle band: switches at the schedule's times
                events += _band_switches(system, load, c, drive, sched)
                continue
            noise = 1e-12 * float(np.max(system.l_ref)) * kind.noise(sched.reference)
            for level, label in switch_levels(c):
                found = _crossings(system, drive, c, level, noise, rows, full, period_t, extremes)
                for r, (qr, qdr, qddr), inside_up in found:
                    # the others on the side the load switches to: just after an "on",
                    # just before an "off" (at the root itself another condition that
                    # changes at the same instant, a member at rest moving two points
                    # at once, is at its own zero, and the switch was lost)
                    tp = r + (span if inside_up else -span) * SIDE
                    qp, qdp, _ = state_near(system, drive, tp, t, q, qd, qdd)
                    psi_p = drive(np.array([tp]))[0][..., 0]
                    if not _others_hold(system, load, c, qp, qdp, psi_p, extremes, sched):
                        continue
                    events.append(
                        (
                            Event(
                                float(r),
                                float(drive(np.array([r]))[0][0, 0]),
                                load.name,
                                label,
                                "on" if inside_up else "off",
                            ),
                            (qr, qdr, qddr),
                        )
                    )
    return _merged(events, span)


def _crossings(system, drive, c, level, noise, rows, full, period_t, extremes):  # noqa: PLR0913  the rows' arrays of one search
    """[(t, (q, q̇, q̈), on)]: where the value of condition ``c`` crosses ``level`` between
    the ``rows`` ``(t, q, q̇, q̈, ψ)``, refined; ``on``: the condition holds after it.

    Round-off (|value − level| ≤ ``noise``) is no sign.  A condition that holds only off a
    rest (``moving``) has rests: a crossing straight from one sign to the other is at the
    value's zero; a rest begun from the side where it holds switches it off where the
    value falls to the noise (the rest's start), a rest left to that side switches it on
    where the value rises past it; a rest and the other side are one state (no switch).
    (At rest the value is ±1e-17: its sign decided the switch, its time and its sense.)"""
    t, q, qd, qdd, psi = rows
    kind = CONDITION_KINDS[c.kind]
    raw = condition_state(system, c, q, qd, qdd, psi, extremes)[0] - level
    rest = np.abs(raw) <= noise
    searches = [(level, np.where(rest, 0.0, raw))]
    if kind.at_rest_band:
        searches = [
            (level, np.where(rest, np.nan, raw)),  # straight through the zero
            (level + noise, np.where(rest, -1.0, np.where(raw > 0, raw - noise, np.nan))),
        ]
    out = []
    for offset, vals in searches:

        def f(a, b, cc, offset=offset):
            g, dg = condition_state(system, c, a, b, cc, None, extremes)
            return g - offset, dg

        roots, (qs, qds, qdds) = find_roots(system, drive, t, q, qd, qdd, vals, f, full, period_t)
        for r, qr, qdr, qddr in zip(roots, qs, qds, qdds):
            _, dg = f(qr[None], qdr[None], qddr[None])
            out.append((r, (qr, qdr, qddr), bool(kind.rising(c, level, dg[0]))))
    return out


def _band_switches(system, load, c, drive, sched) -> list:
    """[(Event, None)]: where the angle band ``c`` of ``load`` switches it on and off, at
    the schedule's times (none for a band of a whole turn or more)."""
    start, width = angle_band(system, c)
    if width >= 2 * np.pi:
        return []  # always on: no switch
    out = []
    for bound, sw in ((start, "on"), (start + width * np.sign(sched.speed[0]), "off")):
        tt = np.mod((bound - sched.start[0]) * np.sign(sched.speed[0]), 2 * np.pi) / sched.reference
        coordinate = float(drive(np.array([tt]))[0][0, 0])
        out.append((Event(float(tt), coordinate, load.name, c.kind, sw), None))
    return out


def _merged(events: list, span: float) -> list:
    """``events`` sorted by time, one kept where two conditions switch a load the same way
    at the same instant (within ``SIDE`` of the run's ``span``)."""
    events = sorted(events, key=lambda e: e[0].t)
    out: list = []
    for e in events:
        if out and any(
            o.load == e[0].load and o.switch == e[0].switch and abs(o.t - e[0].t) <= SIDE * span
            for o, _ in out[-4:]
        ):
            continue
        out.append(e)
    return out


SIDE = 1e-8  # of the run's span: where the other conditions of a switch are looked at


def _others_hold(system, load, cond, q, qd, psi, extremes, sched) -> bool:
    """Whether every other condition of ``load`` holds (bands inclusive) at a state."""
    others = tuple(c for c in load.active if c is not cond)
    probe = Load(load.name, load.kind, load.link, load.value, load.point, load.axis, others)
    return bool(activity(system, probe, q, qd, psi, extremes, sched.reference)[0])
