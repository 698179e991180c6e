"""Means, RMS and peaks over the cycle: the one place every output takes them from.

A mean over the cycle is an integral over time, divided by the span: for a crank at
constant speed the mean over the crank angle.  The quantities jump where a load switches
(a cutting force coming on at its travel band), so a trapezoid rule across the rows is
off by O(step) at every switch.  Here the span is cut at the load events the analysis
located exactly (:class:`~kinetostatics.kinetics.conditions.Event`), each piece into
sub-intervals of at most 1/36 of the span, and each sub-interval integrated by Gauss–Legendre
quadrature with :data:`NODES` nodes, at which the pipeline is run once (all nodes in one
:func:`~kinetostatics.analysis.pipeline.analyze`).  Between the events the quantities are
smooth, so the quadrature is exact to round-off (for a polynomial of degree 2·NODES − 1
on each sub-interval: a few 1e-15 relative).  Jumps that are not load events — a friction
couple flipping where a relative speed passes zero — are not cut at; there the error is
that of one sub-interval's quadrature of a step.

:func:`cycle_stats` serves ``summary.json`` (``run``), the report, the pictures and the
flywheel: their means agree to round-off.  Its nodes are computed once per result.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from ..base.arrays import sorted_distinct
from ..structure.system import link_pair
from .pipeline import analyze
from .results import Result

__all__ = ["NODES", "cycle_stats", "cycle_nodes", "cycle_pieces"]

NODES = 8  # Gauss–Legendre nodes per sub-interval
PIECES = 36  # sub-intervals per span at least (each ≤ span/36)


def _span(result: Result) -> tuple[float, float]:
    """(t_a, t_b) the run covers: one period for a full cycle, else the rows' range."""
    t = np.asarray(result.t, dtype=float)
    if result.full_cycle:
        from ..kinematics.schedule import schedule

        period = schedule(result.system).period
        t0 = float(np.min(t))
        return t0, t0 + float(period)
    return float(np.min(t)), float(np.max(t))


def _exact_roots(result: Result, rates: list) -> list[float]:
    """Times where the value of each ``rate(q, q̇, q̈) -> (value, its time derivative)``
    changes sign over the rows, located exactly (refined on the motion itself).  An entry
    may be a pair ``(rate, keep)``: ``keep(q, q̇, q̈)`` says which of its roots count."""
    from ..kinematics.events import find_roots
    from ..kinematics.schedule import schedule

    if not rates or len(result) < 2:
        return []
    system = result.system
    sched = schedule(system)
    period = float(sched.period) if result.full_cycle else np.inf
    out: list[float] = []
    for entry in rates:
        f, keep = entry if isinstance(entry, tuple) else (entry, None)
        vals = f(result.q, result.qd, result.qdd)[0]
        scale = np.max(np.abs(vals), initial=0.0)
        if not scale > 0:  # never moves: no reversal
            continue
        vals = np.where(np.abs(vals) <= 1e-12 * scale, 0.0, vals)  # round-off is no sign
        roots, states = find_roots(
            system, sched, result.t, result.q, result.qd, result.qdd, vals, f,
            result.full_cycle, period,
        )  # fmt: skip
        if keep is not None and len(roots):
            roots = np.asarray(roots)[np.asarray(keep(*states), dtype=bool)]
        out += [float(r) for r in roots]
    return out


def _level_rates(x, levels, period: float | None) -> list:
    """Rates for :func:`_exact_roots` whose roots are where the quantity ``x(q, q̇, q̈) ->
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


def _table_kinks(result: Result) -> list[float]:
    """Times where a table has a corner (each table's own module says where: a load's
    :meth:`~kinetostatics.model.Load.kinks` over the first motion driver's coordinate, an
    effort law's :meth:`~kinetostatics.model.EffortLaw.kinks` over its driver's coordinate
    or speed, a table spring's :func:`~kinetostatics.kinetics.elements.force_kinks` over
    its length or angle), located exactly on the motion as the reversals are.  A motion
    table's knots are times (:meth:`~kinetostatics.kinematics.schedule.Schedule.breaks`)."""
    from ..kinematics.events import coordinate_rates
    from ..kinematics.state import joint_coordinate
    from ..kinetics.elements import coordinate_rate, force_kinks
    from ..model import EffortLaw

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
        rates += _level_rates(coordinate, np.concatenate(levels), period)
    for d in model.drivers:
        if isinstance(d.effort, EffortLaw):
            variable, at = d.effort.kinks()
            if len(at):
                coordinate, speed, period = of(d)
                if variable == "coordinate":
                    rates += _level_rates(coordinate, at, period)
                else:
                    rates += _level_rates(speed, at, None)
    for e in model.elements:
        at = force_kinks(e)
        if at.size:
            rates += _level_rates(
                lambda q, qd, qdd, e=e: coordinate_rate(system, e, q, qd), at, None
            )
    return _exact_roots(result, rates)


def _reversals(result: Result) -> list[float]:
    """Times where a load that opposes a velocity reverses (a ``resistance`` whose point's
    velocity along its axis, a ``resisting_torque`` whose angular velocity changes sign):
    switching events too."""
    from ..kinematics.state import local_point, point_state
    from ..kinetics.forces import resisting_torque_other

    system = result.system
    rates = []
    for load in system.model.loads:
        if load.kind not in ("resistance", "resisting_torque"):
            continue
        k = system.link_index(load.link)
        if load.kind == "resisting_torque":
            other = resisting_torque_other(system, load)

            def f(q, qd, qdd, k=k, other=other):
                w, a = qd[..., 3 * k + 2], qdd[..., 3 * k + 2]
                if other is not None:
                    w, a = w - qd[..., 3 * other + 2], a - qdd[..., 3 * other + 2]
                return w, a

        else:
            p = local_point(system, load.link, load.point)

            def f(q, qd, qdd, k=k, p=p, axis=load.axis):
                _, vel, acc = point_state(q, qd, qdd, k, p)
                return vel @ axis, acc @ axis

        rates.append(f)
    return _exact_roots(result, rates)


def _friction_reversals(result: Result) -> list[float]:
    """Times where a joint with friction reverses its relative motion: its friction effort
    −sign(ċ)·μ jumps there, so the quadrature is cut there too."""
    from ..kinematics.events import coordinate_rates

    system = result.system
    return _exact_roots(
        result,
        [
            lambda q, qd, qdd, k=k: coordinate_rates(system, q, qd, qdd, k)
            for k, j in enumerate(system.model.joints)
            if j.has_friction
        ],
    )


def _crossings(t: np.ndarray, v: np.ndarray, period: float | None) -> list[float]:
    """Times where the sampled ``v(t)`` (t increasing) changes sign, each from the cubic
    through the four samples around it (the two beside it at a run's end; cyclic over a
    ``period``): O(h⁴), enough for a kink, where a break misplaced by δ costs O(δ²)."""
    n = len(t)
    if period is not None:  # cyclic: the first rows again, a period on
        t, v = (
            np.concatenate((t[-2:] - period, t, t[:2] + period)),
            np.concatenate((v[-2:], v, v[:2])),
        )
        lo, hi = 2, 2 + n  # brackets (k, k + 1) for k in [lo, hi)
    else:
        lo, hi = 0, n - 1
    a_, b_ = v[lo:hi], v[lo + 1 : hi + 1]  # the brackets with a sign change (or a zero start)
    with np.errstate(invalid="ignore"):
        brackets = np.isfinite(a_) & np.isfinite(b_) & (a_ * b_ <= 0) & ((a_ != 0) | (b_ != 0))
    out = []
    for k in lo + np.flatnonzero(brackets):
        a, b = v[k], v[k + 1]
        if a == 0:
            out.append(float(t[k]))
            continue
        if b == 0:
            continue  # the next bracket starts at it
        idx = np.arange(max(k - 1, 0), min(k + 3, len(t)))
        tt, vv = t[idx] - t[k], v[idx]
        guess = float(t[k] + (t[k + 1] - t[k]) * a / (a - b))
        if len(idx) >= 3 and np.all(np.isfinite(vv)):
            roots = np.roots(np.polyfit(tt, vv, len(idx) - 1))
            h = t[k + 1] - t[k]
            inside = [r.real + t[k] for r in roots if abs(r.imag) <= 1e-9 * h and 0 <= r.real <= h]
            if inside:
                guess = min(inside, key=lambda x: abs(x - guess))
        out.append(guess)
    return out


def _in_time(result: Result):
    """(t, order, period): the rows' times sorted (``order`` sorts the rows) and the period
    of a full cycle (None otherwise)."""
    from ..kinematics.schedule import schedule

    t = np.asarray(result.t, dtype=float)
    order = np.argsort(t, kind="stable")
    period = float(schedule(result.system).period) if result.full_cycle else None
    return t[order], order, period


def _motion_breaks(result: Result) -> list[float]:
    """Times where a pair's kinematics has a jump in a derivative (:meth:`Joint.motion_breaks`
    through zero, e.g. a cam law's segment ends), located on the rows."""
    if len(result) < 4:
        return []
    t, order, period = _in_time(result)
    q = result.q[order]
    out: list[float] = []
    for k, joint in enumerate(result.system.model.joints):
        vals = joint.motion_breaks(*link_pair(result.system, q, k))
        for m in range(vals.shape[-1]):
            out += _crossings(t, vals[..., m], period)
    return out


def _effort_zeros(result: Result) -> list[float]:
    """Times where a motion driver's effort (frictionless and with friction) passes through
    zero: the power flow through a reduction turns there, a kink of the motor-side torque
    (dynamics/drive.py), located on the rows."""
    if len(result) < 4:
        return []
    t, order, period = _in_time(result)
    out: list[float] = []
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            for tail in ("", "_friction", "_friction_approx"):
                name = f"{d.name}.{word}{tail}"
                if name in result.columns:
                    out += _crossings(t, np.asarray(result[name])[order], period)
    return out


def _friction_kinks(result: Result) -> list[float]:
    """Times where a joint's friction law has a kink (:meth:`Joint.friction_kinks` through
    zero, e.g. a slide's normal force): of the frictionless λ, which the approximate
    solution uses, and of the consistent solution's λ, located on the rows."""
    system = result.system
    joints = [k for k, j in enumerate(system.model.joints) if j.has_friction]
    if not joints or len(result) < 4:
        return []
    t, order, period = _in_time(result)
    q = result.q[order]
    out: list[float] = []
    for k in joints:
        qi, qj = link_pair(system, q, k)
        for lam in (result.lam, result.lam_friction):
            if lam is None or lam.shape[-1] == 0:
                continue
            vals = system.model.joints[k].friction_kinks(lam[order][..., system.rows_of(k)], qi, qj)
            for m in range(vals.shape[-1]):
                out += _crossings(t, vals[..., m], period)
    return out


def _breaks(result: Result, ta: float, tb: float, friction: bool) -> np.ndarray:
    """The span's ends, the load events, the reversals of the resisting loads, the corners
    of the tables and the motion tables' knots, the breaks of the pairs' motion (a cam
    law's segment ends), the zeros of the drivers' efforts (kinks of a motor's torque
    behind a reduction) and, with friction, the reversals of the joints with friction and
    the kinks of their laws inside it (times), sorted."""
    from ..kinematics.schedule import schedule

    inner = []
    full = result.full_cycle
    reversals = _reversals(result) + _motion_breaks(result) + _effort_zeros(result)
    reversals += _table_kinks(result) + list(schedule(result.system).breaks(ta, tb))
    if friction and result.system.model.has_friction:
        rows = result
        if rows.lam_friction is None:  # rows without the friction solutions: solve them
            # there, for the kinks of the consistent solution and its effort's zeros
            rows = replace(
                analyze(result.system, times=result.t, friction=True, events=False),
                full_cycle=result.full_cycle,
            )
            reversals += _effort_zeros(rows)
        reversals += _friction_reversals(rows) + _friction_kinks(rows)
    for te in [float(e.t) for e in result.events] + reversals:
        if full:
            te = ta + np.mod(te - ta, tb - ta)
        if ta < te < tb:
            inner.append(te)
    return sorted_distinct(np.concatenate(([ta], inner, [tb])))


def cycle_nodes(result: Result, *, friction: bool | None = None) -> tuple[np.ndarray, Result]:
    """(weights, node result): the quadrature weights (s, summing to the span) and the
    result of the pipeline at the nodes.  ``friction``: solve the friction solutions at
    the nodes (default: when the result has them).  Cached on the result."""
    return cycle_pieces(result, friction=friction)[:2]


def cycle_pieces(
    result: Result, *, friction: bool | None = None
) -> tuple[np.ndarray, Result, np.ndarray | None]:
    """(weights, node result, pieces): :func:`cycle_nodes` with the pieces ``(P, 2)``, each
    (t₀, t₁) holding :data:`NODES` consecutive nodes (None for a run of one row)."""
    if friction is None:
        friction = "friction.status" in result.columns
    cache = result.__dict__.setdefault("_cycle_nodes", {})
    if friction in cache:
        return cache[friction]
    if True in cache:  # the nodes with friction carry every frictionless column too
        return cache[True]
    ta, tb = _span(result)
    if not tb > ta:  # one row: its values
        cache[friction] = (np.ones(len(result.t)), result, None)
        return cache[friction]
    x, w = np.polynomial.legendre.leggauss(NODES)
    edges = _breaks(result, ta, tb, friction)
    times, weights, pieces = [], [], []
    for a, b in zip(edges[:-1], edges[1:]):
        m = max(1, int(np.ceil((b - a) / ((tb - ta) / PIECES) - 1e-9)))
        cuts = np.linspace(a, b, m + 1)
        for c0, c1 in zip(cuts[:-1], cuts[1:]):
            half = 0.5 * (c1 - c0)
            times.append(c0 + half * (x + 1.0))
            weights.append(half * w)
            pieces.append((c0, c1))
    times, weights = np.concatenate(times), np.concatenate(weights)
    nodes = analyze(result.system, times=times, friction=friction, events=False)
    order = np.argsort(times, kind="stable")  # the pipeline returns rows in time order
    grouped = np.array(pieces)
    if not np.allclose(nodes.t, times[order], rtol=0, atol=1e-9 * (tb - ta)):
        order, grouped = np.arange(len(times)), None
    cache[friction] = (weights[order], nodes, grouped)
    return cache[friction]


def cycle_stats(
    result: Result,
    what: Mapping[str, str | Callable[[Result], np.ndarray]] | list[str],
    *,
    friction: bool | None = None,
) -> dict[str, dict[str, Any]]:
    """Mean, RMS and peak |·| over the run (a full cycle: one period) of each quantity.

    ``what``: column names, or ``{label: column name or function(Result) -> values}``
    (a function is evaluated on the result at the quadrature nodes).  Returns ``{label:
    {"mean", "rms", "peak", "covered"}}``: ``covered`` is the fraction of the span where
    the value exists; a mean and RMS are over that part (NaN when it is empty: a friction
    column of a machine self-locked everywhere); ``peak`` is the largest |value| at the
    analysed rows (as the batch table's), at the nodes for a function the rows lack.
    """
    if not isinstance(what, Mapping):
        what = {name: name for name in what}
    weights, nodes = cycle_nodes(result, friction=friction)
    out = {}
    for label, source in what.items():
        if callable(source):
            v = np.asarray(source(nodes), dtype=float)
            try:
                rows = np.asarray(source(result), dtype=float)
            except KeyError:  # a column the rows lack (friction asked of a frictionless run)
                rows = np.zeros(0)
        else:
            v = np.asarray(nodes[source], dtype=float)
            rows = np.asarray(result[source], dtype=float)
        ok = np.isfinite(v)
        total = float(np.sum(weights))
        covered = float(np.sum(weights[ok])) / total if total > 0 else 0.0
        if ok.any():
            wk = weights[ok]
            mean = float(np.sum(wk * v[ok]) / np.sum(wk))
            rms = float(np.sqrt(np.sum(wk * v[ok] ** 2) / np.sum(wk)))
        else:
            mean = rms = float("nan")
        # the peak at the analysed rows (the batch table's too): the rows are where the
        # values are reported; with no finite row, at the nodes
        finite = rows[np.isfinite(rows)] if rows.size else v[ok]
        peak = float(np.max(np.abs(finite))) if finite.size else float("nan")
        out[label] = {"mean": mean, "rms": rms, "peak": peak, "covered": covered}
    return out
