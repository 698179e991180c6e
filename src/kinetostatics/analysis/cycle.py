"""Means, RMS and peaks over the cycle: the one place every output takes them from.

A mean over the cycle is an integral over time, divided by the span: for a crank at
constant speed the mean over the crank angle.  The quantities jump where a load switches
(a cutting force coming on at its travel band), so a trapezoid rule across the rows is
off by O(step) at every switch.  Here the span is cut wherever a quantity may jump or
kink (:func:`_breaks`), each piece into sub-intervals of at most 1/36 of the span, and
each sub-interval integrated by Gauss–Legendre quadrature with :data:`NODES` nodes, at
which the pipeline is run once (all nodes in one
:func:`~kinetostatics.analysis.pipeline.analyze`).  Between the cuts the quantities are
smooth, so the quadrature is exact to round-off (for a polynomial of degree 2·NODES − 1
on each sub-interval: a few 1e-15 relative).

The cuts: the jumps — the load events the analysis located exactly
(:class:`~kinetostatics.kinetics.conditions.Event`), the reversals of the resisting
loads and, with friction, of the joints with friction — and the corners of the tables,
each located exactly on the motion (Newton on the time from the nearest row); and the
kinks of quantities only the whole pipeline gives (a driving effort through zero, a
friction law's normal force through zero, a cam law's segment end), each bracketed by the
rows, the brackets split at the jumps, and located by secant steps on the pipeline at
single times continued from the nearest row
(:func:`~kinetostatics.analysis.pipeline.analyze_near`): never by interpolating across a
jump.

:func:`cycle_stats` serves ``summary.json`` (``run``), the report, the pictures and the
flywheel: their means agree to round-off.  Its nodes are computed once per result.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from ..base.arrays import sorted_distinct
from ..errors import AssemblyError, JointWarning
from ..structure.system import link_pair
from .pipeline import analyze, analyze_near
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


def _in_time(result: Result):
    """(t, order, period): the rows' times sorted (``order`` sorts the rows) and the period
    of a full cycle (None otherwise)."""
    from ..kinematics.schedule import schedule

    t = np.asarray(result.t, dtype=float)
    order = np.argsort(t, kind="stable")
    period = float(schedule(result.system).period) if result.full_cycle else None
    return t[order], order, period


def _columns(result: Result, fns: list) -> np.ndarray:
    """The kink functions' values at the rows of ``result``, side by side, ``(N, m)``."""
    n = len(result)
    cols = [np.asarray(fn(result), dtype=float).reshape(n, -1) for fn in fns]
    return np.concatenate(cols, axis=1) if cols else np.zeros((n, 0))


def _motion_breaks(result: Result) -> list:
    """Kink functions (of a result, ``(N, m)``) of the pairs' kinematics, whose zeros are
    jumps in a derivative (:meth:`Joint.motion_breaks`, e.g. a cam law's segment ends)."""
    system = result.system
    return [
        lambda r, k=k, joint=joint: joint.motion_breaks(*link_pair(system, r.q, k))
        for k, joint in enumerate(system.model.joints)
        if joint.motion_breaks(*link_pair(system, result.q[:1], k)).shape[-1]
    ]


def _effort_zeros(result: Result) -> list:
    """Kink functions: the motion drivers' efforts (frictionless and with friction, as the
    result has them), whose zeros are where the power flow through a reduction turns, a
    kink of the motor-side torque (dynamics/drive.py)."""
    out = []
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            for tail in ("", "_friction", "_friction_approx"):
                name = f"{d.name}.{word}{tail}"
                if name in result.columns:
                    out.append(lambda r, name=name: r[name])
    return out


def _friction_kinks(result: Result) -> list:
    """Kink functions: the arguments of the absolute values in the joints' friction laws
    (:meth:`Joint.friction_kinks`, e.g. a slide's normal force), of the frictionless λ,
    which the approximate solution uses, and of the consistent solution's λ."""
    system = result.system
    out = []
    for k, joint in enumerate(system.model.joints):
        if not joint.has_friction:
            continue
        rows = system.rows_of(k)
        for which in ("lam", "lam_friction"):
            lam = getattr(result, which)
            if lam is None or lam.shape[-1] == 0:
                continue

            def f(r, k=k, rows=rows, which=which, joint=joint):
                lam = getattr(r, which)
                return joint.friction_kinks(lam[..., rows], *link_pair(system, r.q, k))

            out.append(f)
    return out


JUMP_GAP = 1e-8  # of the span: a jump's sides are sampled this far from it


def _guess(ts, vs, seg, i) -> tuple[float, float]:
    """A first guess of the zero between samples i and i + 1 of one smooth stretch and the
    slope there: of the cubic through the four samples around them (fewer at the
    stretch's ends), else of the chord."""
    a, b = vs[i], vs[i + 1]
    h = ts[i + 1] - ts[i]
    chord = ts[i] + h * a / (a - b), (b - a) / h
    idx = [j for j in range(i - 1, i + 3) if 0 <= j < len(ts) and seg[j] == seg[i]]
    if len(idx) < 3:
        return chord
    p = np.polyfit(ts[idx] - ts[i], vs[idx], len(idx) - 1)
    inside = [r.real for r in np.roots(p) if abs(r.imag) <= 1e-9 * h and 0 < r.real < h]
    if not inside:
        return chord
    x = min(inside, key=lambda x: abs(x + ts[i] - chord[0]))
    return float(x + ts[i]), float(np.polyval(np.polyder(p), x))


def _solved_kinks(rows: Result, fns: list, jumps: list[float], ta: float, tb: float) -> list:
    """Times where a kink function (``fn(result) -> (N, m)``) changes sign, each located
    on the solved state, as the events are: bracketed by the rows, the brackets split at
    the ``jumps`` (the load events and reversals, where the function may jump: each side
    sampled :data:`JUMP_GAP` of the span from it), and the zero found by safeguarded
    secant steps on the function of :func:`analyze` at single times — never by
    interpolating across a jump."""
    if not fns or len(rows) < 2:
        return []
    system = rows.system
    friction = rows.lam_friction is not None
    t, order, period = _in_time(rows)
    span = tb - ta
    gap = JUMP_GAP * span

    def at(times) -> np.ndarray:
        times = np.asarray(times, dtype=float)
        if period is not None:
            times = ta + np.mod(times - ta, period)
        try:  # each continued from its nearest row
            res = analyze_near(rows, times, friction=friction)
        except AssemblyError:  # too far from the rows for Newton: the whole run's way
            uniq, inv = np.unique(times, return_inverse=True)
            res = _quiet_analyze(system, times=uniq, friction=friction, events=False)
            return _columns(res, fns)[inv.ravel()]
        return _columns(res, fns)

    vals = _columns(rows, fns)[order]
    jumps = sorted_distinct([j for j in jumps if ta < j < tb])
    near = np.zeros(len(t), dtype=bool)  # rows on a jump (event rows): their side unknown
    for j in jumps:
        near |= np.abs(t - j) <= 1e-12 * span
    sides = np.concatenate([(j - gap, j + gap) for j in jumps]) if len(jumps) else np.zeros(0)
    ts = np.concatenate((t[~near], sides))
    vs = np.concatenate((vals[~near], at(sides) if sides.size else np.zeros((0, vals.shape[1]))))
    o = np.argsort(ts, kind="stable")
    ts, vs = ts[o], vs[o]
    seg = np.searchsorted(jumps, ts)  # the smooth stretch of each sample
    cyclic = period is not None and len(ts) > 1
    if cyclic:  # the wrap-around bracket: the first samples again, a period on
        ts = np.append(ts, ts[0] + period)
        vs = np.vstack((vs, vs[:1]))
        seg = np.append(seg, 0 if len(jumps) else seg[0])
        if len(jumps):  # the stretch after the last jump runs on into the first
            seg = np.where(seg == len(jumps), 0, seg)
    lo, hi, flo, fhi, x0, slope, col, scales = [], [], [], [], [], [], [], []
    for m in range(vs.shape[1]):
        v = vs[:, m]
        ok = np.isfinite(v)
        scale = np.max(np.abs(v[ok]), initial=0.0)
        if not scale > 0:
            continue
        keep = ok & (np.abs(v) > 1e-12 * scale)  # round-off is no sign
        idx = np.flatnonzero(keep)
        for a, b in zip(idx[:-1], idx[1:]):
            if seg[a] != seg[b] or v[a] * v[b] > 0:
                continue
            if np.any(seg[a:b] != seg[a]):
                continue
            lo.append(ts[a])
            hi.append(ts[b])
            flo.append(v[a])
            fhi.append(v[b])
            g = _guess(ts, v, seg, a) if b == a + 1 else None
            if g is None:  # zeros between: the chord
                g = (ts[a] + (ts[b] - ts[a]) * v[a] / (v[a] - v[b]), 0.0)
            x0.append(g[0])
            slope.append(g[1])
            col.append(m)
            scales.append(scale)
    if not lo:
        return []
    lo, hi, flo, fhi, x, slope, col, scales = (
        np.array(z) for z in (lo, hi, flo, fhi, x0, slope, col, scales)
    )
    f = lambda tt, cc: at(tt)[np.arange(len(tt)), cc]  # noqa: E731
    roots = _secant(f, lo, hi, flo, fhi, x, slope, col, span, 1e-13 * scales)
    return [float(r) for r in roots]


def _secant(
    f, lo, hi, flo, fhi, x, slope, col, span: float, small, max_iter: int = 40
) -> np.ndarray:
    """The zeros of ``f(times, columns)`` in the brackets [lo, hi] (values flo, fhi of
    opposite signs), all at once: from the first guesses ``x`` a Newton step with the
    guessed ``slope`` (0: none), then secant steps, each kept
    inside the bracket (which shrinks with every evaluation), else a regula falsi step
    with the stale end's value halved (Illinois), else bisection; done where |f| ≤
    ``small`` (round-off of the column), the bracket or a secant step ≤ 1e-13 of the
    ``span``."""
    px, pf = None, None
    stale_lo = np.zeros(len(x), dtype=int)
    live = np.ones(len(x), dtype=bool)
    tol = 1e-13 * span
    for _ in range(max_iter):
        idx = np.flatnonzero(live)
        if not idx.size:
            break
        fx = np.full(len(x), np.nan)
        fx[idx] = f(x[idx], col[idx])
        bad = ~np.isfinite(fx[idx])
        live[idx[bad]] = False
        idx = idx[~bad]
        same = np.sign(fx[idx]) == np.sign(flo[idx])
        zero = np.abs(fx[idx]) <= small[idx]
        lo[idx] = np.where(same, x[idx], lo[idx])
        flo[idx] = np.where(same, fx[idx], flo[idx])
        hi[idx] = np.where(same, hi[idx], x[idx])
        fhi[idx] = np.where(same, fhi[idx], fx[idx])
        # how many times in a row one end has stayed (> 0: lo, < 0: hi)
        run = stale_lo[idx]
        stale_lo[idx] = np.where(same, np.minimum(run, 0) - 1, np.maximum(run, 0) + 1)
        done = zero | (hi[idx] - lo[idx] <= tol)
        live[idx[done]] = False
        idx = idx[~done]
        if not idx.size:
            break
        # the secant through the last two iterates, if inside the bracket
        with np.errstate(divide="ignore", invalid="ignore"):
            new = x[idx] - fx[idx] / slope[idx]  # the first step
        if px is not None:
            d = fx[idx] - pf[idx]
            with np.errstate(divide="ignore", invalid="ignore"):
                new = x[idx] - fx[idx] * (x[idx] - px[idx]) / d
        a, b, fa, fb = lo[idx], hi[idx], flo[idx].copy(), fhi[idx].copy()
        # an end that has stayed n ≥ 2 times in a row: its value halved n − 1 times (Illinois)
        fa = fa * 0.5 ** np.maximum(stale_lo[idx] - 1, 0)
        fb = fb * 0.5 ** np.maximum(-stale_lo[idx] - 1, 0)
        falsi = (a * fb - b * fa) / (fb - fa)
        ok_new, ok_falsi = (np.isfinite(z) & (z > a) & (z < b) for z in (new, falsi))
        step = np.where(ok_new, new, np.where(ok_falsi, falsi, 0.5 * (a + b)))
        px, pf = x.copy(), fx.copy()
        # a secant step this small: converged (the zero is where it lands, to round-off)
        fine = ok_new & (np.abs(new - x[idx]) <= tol)
        x[idx] = step
        live[idx[fine]] = False
    return x


def _breaks(result: Result, ta: float, tb: float, friction: bool) -> np.ndarray:
    """The span's ends and the cuts inside it (times), sorted: the jumps (the load events,
    the reversals of the resisting loads, a motion law's turning points and, with
    friction, the reversals of the joints with friction), the corners of the tables and
    the motion tables' knots, all located exactly; and the kinks located on the solved
    state (:func:`_solved_kinks`): the breaks of the pairs' motion (a cam law's segment
    ends), the zeros of the drivers' efforts (kinks of a motor's torque behind a
    reduction) and, with friction, the kinks of the friction laws."""
    from ..kinematics.schedule import schedule

    sched = schedule(result.system)
    full = result.full_cycle
    rows = result
    # a motion law turning back (ψ̇ = 0): the power through a reduction changes sign
    # there with the effort ≠ 0, a jump of the motor's torque (dynamics/drive.py)
    turns = list(sched.turning_times(ta, tb))
    jumps = [float(e.t) for e in result.events] + _reversals(result) + turns
    if friction and result.system.model.has_friction:
        if rows.lam_friction is None:  # rows without the friction solutions: solve them
            # there, for the kinks of the consistent solution and its effort's zeros
            rows = replace(
                _quiet_analyze(result.system, times=result.t, friction=True, events=False),
                full_cycle=result.full_cycle,
            )
        jumps += _friction_reversals(rows)
    jumps = [ta + np.mod(te - ta, tb - ta) if full else te for te in jumps]
    kinks = _table_kinks(result) + list(sched.breaks(ta, tb))
    fns = _motion_breaks(rows) + _effort_zeros(rows)
    if friction and result.system.model.has_friction:
        fns += _friction_kinks(rows)
    kinks += _solved_kinks(rows, fns, jumps, ta, tb)
    inner = []
    for te in jumps + kinks:
        if full:
            te = ta + np.mod(te - ta, tb - ta)
        if ta < te < tb:
            inner.append(te)
    edges = sorted_distinct(np.concatenate(([ta], inner, [tb])))
    # a kink found within round-off of another cut is that cut
    keep = np.append(True, np.diff(edges) > 1e-12 * (tb - ta))
    if not keep[-1]:  # the span's end stays, the cut beside it goes
        keep[-1], keep[-2] = True, False
    return edges[keep]


def _quiet_analyze(system, **kw) -> Result:
    """``analyze`` at rows of the run's own (its quadrature nodes, its rows again) without
    the joints' warnings about them: the run has warned about its rows once."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", JointWarning)
        return analyze(system, **kw)


def cycle_nodes(
    result: Result,
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
) -> tuple[np.ndarray, Result]:
    """(weights, node result): the quadrature weights (s, summing to the span) and the
    result of the pipeline at the nodes.  ``friction``: solve the friction solutions at
    the nodes (default: when the result has them); ``quadrature``: (nodes per piece,
    pieces per span at least), default (:data:`NODES`, :data:`PIECES`) — another only to
    check that the means have converged.  Cached on the result."""
    return cycle_pieces(result, friction=friction, quadrature=quadrature)[:2]


def cycle_pieces(
    result: Result,
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
) -> tuple[np.ndarray, Result, np.ndarray | None]:
    """(weights, node result, pieces): :func:`cycle_nodes` with the pieces ``(P, 2)``, each
    (t₀, t₁) holding :data:`NODES` consecutive nodes (None for a run of one row)."""
    if friction is None:
        friction = "friction.status" in result.columns
    n_nodes, n_pieces = quadrature if quadrature is not None else (NODES, PIECES)
    cache = result.__dict__.setdefault("_cycle_nodes", {})
    key = (friction, n_nodes, n_pieces)
    if key in cache:
        return cache[key]
    if (True, n_nodes, n_pieces) in cache:  # the nodes with friction carry every
        return cache[(True, n_nodes, n_pieces)]  # frictionless column too
    ta, tb = _span(result)
    if not tb > ta:  # one row: its values
        cache[key] = (np.ones(len(result.t)), result, None)
        return cache[key]
    x, w = np.polynomial.legendre.leggauss(n_nodes)
    edges = cache.get(("edges", friction))
    if edges is None:
        edges = cache[("edges", friction)] = _breaks(result, ta, tb, friction)
    pieces = []
    for a, b in zip(edges[:-1], edges[1:]):
        m = max(1, int(np.ceil((b - a) / ((tb - ta) / n_pieces) - 1e-9)))
        cuts = np.linspace(a, b, m + 1)
        pieces += list(zip(cuts[:-1], cuts[1:]))
    grouped = np.array(pieces)
    times, weights = _nodes_of(grouped, x, w)
    nodes = _quiet_analyze(result.system, times=times, friction=friction, events=False)
    order = np.argsort(times, kind="stable")  # the pipeline returns rows in time order
    if not np.allclose(nodes.t, times[order], rtol=0, atol=1e-9 * (tb - ta)):
        order, grouped = np.arange(len(times)), None
    elif len(grouped):
        finer = _resolved(result, nodes, grouped, x, w, friction)
        if finer is not None:  # pieces halved where the efforts were not resolved
            grouped = finer
            times, weights = _nodes_of(grouped, x, w)
            nodes = _quiet_analyze(result.system, times=times, friction=friction, events=False)
            order = np.argsort(times, kind="stable")
    cache[key] = (weights[order], nodes, grouped)
    return cache[key]


RESOLVED = 1e-13  # of an effort's largest |value|: a piece's predicted quadrature error
SPLITS = 5  # a piece is halved at most this many times (to 1/32 of it)


def _nodes_of(pieces: np.ndarray, x: np.ndarray, w: np.ndarray):
    """(times, weights) of the Gauss–Legendre rule (nodes ``x``, weights ``w`` on
    [−1, 1]) on each piece (t₀, t₁), piece after piece."""
    half = 0.5 * (pieces[:, 1] - pieces[:, 0])
    times = pieces[:, :1] + half[:, None] * (x + 1.0)
    return times.ravel(), (half[:, None] * w).ravel()


def _unresolved(nodes: Result, x: np.ndarray, scales: list[float]) -> np.ndarray:
    """Per piece of ``nodes`` (n consecutive nodes each), whether the quadrature may be off
    by more than :data:`RESOLVED` of an effort's scale: from the Legendre coefficients
    c_k of the interpolant through its n values, decaying like ρ^k from the head (c_0…c_2)
    to the tail (c_{n−2}, c_{n−1}), the rule's error is about that of c_{2n} ≈
    tail·ρ^{n+1}.  A smooth effort's pieces are resolved (ρ ~ 0.1); a sharp peak beside a
    singular position is not (ρ ~ 0.4, the two orders then differ by 1e-9)."""
    n = len(x)
    inv = np.linalg.inv(np.polynomial.legendre.legvander(x, n - 1))
    out = np.zeros(len(nodes) // n, dtype=bool)
    for fn, scale in zip(_effort_zeros(nodes), scales):
        v = np.asarray(fn(nodes), dtype=float).reshape(-1, n)
        c = np.abs(v @ inv.T)
        tail, head = np.max(c[:, -2:], axis=1), np.max(c[:, :3], axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = (tail / head) ** (1.0 / (n - 2))
            out |= np.isfinite(rho) & (tail * rho ** (n + 1) > RESOLVED * scale)
    return out


def _resolved(result: Result, nodes: Result, pieces, x, w, friction: bool):
    """The pieces halved (at most :data:`SPLITS` times) until the driving efforts are
    resolved on each (:func:`_unresolved`), or None when they already are."""
    scales = []
    for fn in _effort_zeros(nodes):
        v = np.abs(np.asarray(fn(nodes), dtype=float))
        scales.append(float(np.max(v[np.isfinite(v)], initial=0.0)))
    bad = _unresolved(nodes, x, scales)
    if not SPLITS or not bad.any():
        return None
    done, pending = [pieces[~bad]], pieces[bad]
    for level in range(SPLITS):
        mid = 0.5 * (pending[:, 0] + pending[:, 1])
        halves = np.column_stack(
            (
                np.ravel(np.column_stack((pending[:, 0], mid))),
                np.ravel(np.column_stack((mid, pending[:, 1]))),
            )
        )
        if level == SPLITS - 1:
            done.append(halves)
            break
        times = _nodes_of(halves, x, w)[0]
        try:  # each position continued from the nearest row
            part = analyze_near(result, times, friction=friction)
        except AssemblyError:
            part = _quiet_analyze(result.system, times=times, friction=friction, events=False)
        if len(part) != len(times) or not np.array_equal(part.t, times):
            done.append(halves)
            break
        bad = _unresolved(part, x, scales)
        done.append(halves[~bad])
        pending = halves[bad]
        if not len(pending):
            break
    out = np.concatenate(done)
    return out[np.argsort(out[:, 0], kind="stable")]


def cycle_stats(
    result: Result,
    what: Mapping[str, str | Callable[[Result], np.ndarray]] | list[str],
    *,
    friction: bool | None = None,
    quadrature: tuple[int, int] | None = None,
) -> dict[str, dict[str, Any]]:
    """Mean, RMS and peak |·| over the run (a full cycle: one period) of each quantity.

    ``what``: column names, or ``{label: column name or function(Result) -> values}``
    (a function is evaluated on the result at the quadrature nodes).  Returns ``{label:
    {"mean", "rms", "peak", "covered"}}``: ``covered`` is the fraction of the span where
    the value exists; a mean and RMS are over that part (NaN when it is empty: a friction
    column of a machine self-locked everywhere); ``peak`` is the largest |value| at the
    analysed rows (as the batch table's), at the nodes for a function the rows lack.
    ``quadrature``: as for :func:`cycle_nodes`.
    """
    if not isinstance(what, Mapping):
        what = {name: name for name in what}
    weights, nodes = cycle_nodes(result, friction=friction, quadrature=quadrature)
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
