"""Where the loads, the tables and the friction switch on the motion: rate functions
``rate(q, q̇, q̈) -> (value, its time derivative)`` whose roots are those switches — a
table's corners, a load that opposes a velocity reversing, a joint with friction
reversing, a load's condition coming true or false — and :func:`exact_roots`, which
locates their roots on the motion itself (Newton on the time from the nearest sample).
The cycle integral cuts there (:mod:`.cuts`).
"""

from __future__ import annotations

import numpy as np

from ..base.arrays import sorted_distinct
from ..kinematics.events import coordinate_rates, find_roots_of
from ..kinematics.schedule import schedule
from ..kinematics.state import joint_coordinate
from ..kinetics.conditions import ZERO_SPEED, condition_state
from ..kinetics.elements import coordinate_rate, force_kinks
from ..kinetics.kinds import CONDITION_KINDS, LOAD_KINDS
from ..model import EffortLaw
from .results import Result

__all__ = [
    "condition_rates",
    "dead_band",
    "exact_roots",
    "exact_roots_of",
    "friction_rates",
    "level_rates",
    "reversal_rates",
    "table_rates",
]


def exact_roots(result: Result, rates: list) -> list[float]:
    """Times where the value of each ``rate(q, q̇, q̈) -> (value, its time derivative)``
    changes sign over the rows, located exactly (refined on the motion itself).  An entry
    may be a pair ``(rate, keep)``: ``keep(q, q̇, q̈)`` says which of its roots count."""
    return exact_roots_of(result, [rates])[0]


def exact_roots_of(result: Result, groups: list[list]) -> list[list[float]]:
    """:func:`exact_roots` of each list of rates in ``groups``, all the rates' roots
    refined together (:func:`~kinetostatics.kinematics.events.find_roots_of`: one state
    per Newton step for every root, each root's steps its own); one list per group."""
    out: list[list[float]] = [[] for _ in groups]
    if len(result) < 2 or not any(groups):
        return out
    system = result.system
    sched = schedule(system)
    period = float(sched.period) if result.full_cycle else np.inf
    pairs, keeps, owner = [], [], []
    for g, rates in enumerate(groups):
        for entry in rates:
            f, keep = entry if isinstance(entry, tuple) else (entry, None)
            vals, rates = f(result.q, result.qd, result.qdd)
            scale = np.max(np.abs(vals), initial=0.0)
            if not scale > 0:  # never moves: no reversal
                continue
            vals = np.where(np.abs(vals) <= 1e-12 * scale, 0.0, vals)  # round-off is no sign
            pairs.append((vals, f, np.broadcast_to(rates, np.shape(vals))))
            keeps.append(keep)
            owner.append(g)
    if not pairs:
        return out
    found = find_roots_of(
        system, sched, result.t, result.q, result.qd, result.qdd, pairs,
        result.full_cycle, period,
    )  # fmt: skip
    for (roots, states), keep, g in zip(found, keeps, owner):
        if keep is not None and len(roots):
            roots = np.asarray(roots)[np.asarray(keep(*states), dtype=bool)]
        out[g] += [float(r) for r in roots]
    return out


def level_rates(x, levels, period: float | None) -> list:
    """Rates for :func:`exact_roots` whose roots are where the quantity ``x(q, q̇, q̈) ->
    (value, its time derivative)`` passes one of ``levels``: x − L; with a ``period`` (a
    revolute's coordinate: the level again every turn), sin(x − L), whose other zeros
    (x − L = π) are not kept."""
    out: list = []
    if period is None:
        for level in sorted_distinct(levels):
            out.append(lambda q, qd, qdd, level=level: _shifted(x(q, qd, qdd), level))
        return out
    for level in sorted_distinct(np.mod(np.asarray(levels, dtype=float), period)):

        def f(q, qd, qdd, level=level):
            v, dv = x(q, qd, qdd)
            return np.sin(v - level), np.cos(v - level) * dv

        out.append((f, lambda q, qd, qdd, level=level: np.cos(x(q, qd, qdd)[0] - level) > 0))
    return out


def _shifted(pair, level):
    return pair[0] - level, pair[1]


def table_rates(result: Result) -> list:
    """Rates whose roots are where a table has a corner (each table's own module says
    where: a load's :meth:`~kinetostatics.model.Load.kinks` over the first motion
    driver's coordinate, an effort law's :meth:`~kinetostatics.model.EffortLaw.kinks`
    over its driver's coordinate or speed, a table spring's
    :func:`~kinetostatics.kinetics.elements.force_kinks` over its length or angle).  A
    motion table's knots are times
    (:meth:`~kinetostatics.kinematics.schedule.Schedule.breaks`)."""

    system = result.system
    model = system.model
    names = [j.name for j in model.joints]

    def of(driver):
        """(coordinate, speed, period) of a driver: each ``(q, q̇, q̈) -> (x, ẋ)``."""
        k = names.index(driver.joint)

        def coordinate(q, qd, qdd):
            return joint_coordinate(system, q, k) + driver.offset, coordinate_rates(
                system, q, qd, qdd, k
            )[0]

        def speed(q, qd, qdd):
            return coordinate_rates(system, q, qd, qdd, k)

        return coordinate, speed, (2 * np.pi if model.joints[k].angular else None)

    rates: list = []
    levels = [load.kinks() for load in model.loads]
    if system.motion_drivers and any(x.size for x in levels):
        coordinate, _, period = of(system.motion_drivers[0].driver)
        rates += level_rates(coordinate, np.concatenate(levels), period)
    for d in model.drivers:
        if isinstance(d.effort, EffortLaw):
            variable, at = d.effort.kinks()
            if len(at):
                coordinate, speed, period = of(d)
                if variable == "coordinate":
                    rates += level_rates(coordinate, at, period)
                else:
                    rates += level_rates(speed, at, None)
    for e in model.elements:
        at = force_kinks(e)
        if at.size:
            rates += level_rates(
                lambda q, qd, qdd, e=e: coordinate_rate(system, e, q, qd), at, None
            )
    return rates


def dead_band(result: Result, rate, angular: bool) -> list:
    """Rates for :func:`exact_roots` whose roots are where the relative speed ``rate``
    enters or leaves the band counted as zero speed, |x| ≤ 1e-9·x_ref (x_ref the driver
    speed, times L_ref for a speed of travel; docs/conventions.md): where the effort that
    opposes it switches on or off, at the rows and the nodes alike.  (Cut at the speed's
    zero instead, a speed that leaves 0 slowly — a follower after a cam's dwell — was
    cut up to 1e-4 s from where its effort switched.)"""

    system = result.system
    band = ZERO_SPEED * float(schedule(system).reference) * (1.0 if angular else system.l_ref)
    return level_rates(rate, [-band, band], None)


def reversal_rates(result: Result) -> list:
    """Rates whose roots are where a load that opposes a velocity reverses (a
    ``resistance`` whose point's velocity along its axis, a ``resisting_torque`` whose
    angular velocity changes sign: switching events too), at the edges of the zero-speed
    band (:func:`dead_band`)."""
    system = result.system
    rates = []
    for load in system.model.loads:
        kind = LOAD_KINDS[load.kind]
        if not kind.opposes:
            continue

        def f(q, qd, qdd, load=load, kind=kind):
            return kind.rate(system, load, q, qd, qdd)

        rates += dead_band(result, f, kind.couple)
    return rates


def friction_rates(result: Result) -> list:
    """Rates whose roots are where a joint with friction reverses its relative motion: its
    friction effort −sign(ċ)·μ jumps there, so the quadrature is cut there too (at the edges of the
    zero-speed band, :func:`dead_band`)."""

    system = result.system
    rates = []
    for k, j in enumerate(system.model.joints):
        if j.has_friction:
            rate = lambda q, qd, qdd, k=k: coordinate_rates(system, q, qd, qdd, k)  # noqa: E731
            rates += dead_band(result, rate, j.angular)
    return rates


def condition_rates(result: Result) -> list:
    """Rates whose roots are where a load's ``moving`` condition starts to hold: its
    point's speed along the axis leaves the zero-speed band (1e-9·|driver speed|·L_ref,
    docs/conventions.md), where :func:`~kinetostatics.kinetics.conditions.activity` sees
    the load come on or go off.  The load's event is at the speed's zero; a speed that
    crosses zero at a rate is out of the band within round-off, but one that leaves 0
    slowly — a follower after a cam's dwell — only up to 1e-4 s later."""
    system = result.system
    band = ZERO_SPEED * float(schedule(system).reference) * float(system.l_ref)
    rates: list = []
    for load in system.model.loads:
        for c in load.active:
            if CONDITION_KINDS[c.kind].at_rest_band:

                def x(q, qd, qdd, c=c):
                    return condition_state(system, c, q, qd, qdd, None, result.extremes)

                rates += level_rates(x, [band], None)
    return rates
