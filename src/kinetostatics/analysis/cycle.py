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
from typing import Any

import numpy as np

from ..base.arrays import sorted_distinct
from .pipeline import analyze
from .results import Result

__all__ = ["NODES", "cycle_stats", "cycle_nodes"]

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


def _reversals(result: Result) -> list[float]:
    """Times where a load that opposes a velocity reverses (a ``resistance`` whose point's
    velocity along its axis, a ``resisting_torque`` whose angular velocity changes sign):
    switching events too, located as exact roots over the rows."""
    from ..kinematics.events import find_roots
    from ..kinematics.schedule import schedule
    from ..kinematics.state import local_point, point_state
    from ..kinetics.forces import resisting_torque_other

    system = result.system
    loads = [ld for ld in system.model.loads if ld.kind in ("resistance", "resisting_torque")]
    if not loads or len(result) < 2:
        return []
    sched = schedule(system)
    period = float(sched.period) if result.full_cycle else np.inf
    out: list[float] = []
    for load in loads:
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

        vals = f(result.q, result.qd, result.qdd)[0]
        roots, _ = find_roots(
            system,
            sched,
            result.t,
            result.q,
            result.qd,
            result.qdd,
            vals,
            f,
            result.full_cycle,
            period,
        )
        out += [float(r) for r in roots]
    return out


def _breaks(result: Result, ta: float, tb: float) -> np.ndarray:
    """The span's ends, the load events and the reversals of the resisting loads inside
    it (times), sorted."""
    inner = []
    full = result.full_cycle
    for te in [float(e.t) for e in result.events] + _reversals(result):
        if full:
            te = ta + np.mod(te - ta, tb - ta)
        if ta < te < tb:
            inner.append(te)
    return sorted_distinct(np.concatenate(([ta], inner, [tb])))


def cycle_nodes(result: Result, *, friction: bool | None = None) -> tuple[np.ndarray, Result]:
    """(weights, node result): the quadrature weights (s, summing to the span) and the
    result of the pipeline at the nodes.  ``friction``: solve the friction solutions at
    the nodes (default: when the result has them).  Cached on the result."""
    if friction is None:
        friction = "friction.status" in result.columns
    cache = result.__dict__.setdefault("_cycle_nodes", {})
    if friction in cache:
        return cache[friction]
    if True in cache:  # the nodes with friction carry every frictionless column too
        return cache[True]
    ta, tb = _span(result)
    if not tb > ta:  # one row: its values
        cache[friction] = (np.ones(len(result.t)), result)
        return cache[friction]
    x, w = np.polynomial.legendre.leggauss(NODES)
    edges = _breaks(result, ta, tb)
    times, weights = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        m = max(1, int(np.ceil((b - a) / ((tb - ta) / PIECES) - 1e-9)))
        cuts = np.linspace(a, b, m + 1)
        for c0, c1 in zip(cuts[:-1], cuts[1:]):
            half = 0.5 * (c1 - c0)
            times.append(c0 + half * (x + 1.0))
            weights.append(half * w)
    times, weights = np.concatenate(times), np.concatenate(weights)
    nodes = analyze(result.system, times=times, friction=friction, events=False)
    order = np.argsort(times, kind="stable")  # the pipeline returns rows in time order
    if not np.allclose(nodes.t, times[order], rtol=0, atol=1e-9 * (tb - ta)):
        order = np.arange(len(times))
    cache[friction] = (weights[order], nodes)
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
