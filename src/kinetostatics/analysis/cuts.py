"""Where the cycle integral is cut (analysis/cycle.py): the span of a run and the times
at which a quantity may jump or kink, each located exactly.

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
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from ..base.arrays import sorted_distinct
from ..errors import AssemblyError, ElementWarning, JointWarning, NearSingularWarning
from ..structure.system import link_pair
from .pipeline import analyze, analyze_near
from .results import Result

__all__ = ["breaks", "effort_zeros", "quiet_analyze", "quiet_near", "span"]


def span(result: Result) -> tuple[float, float]:
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


def effort_zeros(result: Result) -> list:
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
    stretch's ends or beside a singular row), else of the chord."""
    a, b = vs[i], vs[i + 1]
    h = ts[i + 1] - ts[i]
    chord = ts[i] + h * a / (a - b), (b - a) / h
    idx = [
        j
        for j in range(i - 1, i + 3)
        if 0 <= j < len(ts) and seg[j] == seg[i] and np.isfinite(vs[j])  # not a singular row
    ]
    if len(idx) < 3:
        return chord
    with warnings.catch_warnings():  # samples beside a jump lie close: a first guess only
        warnings.simplefilter("ignore", np.exceptions.RankWarning)
        p = np.polyfit((ts[idx] - ts[i]) / h, vs[idx], len(idx) - 1)  # in steps of h
    inside = [r.real for r in np.roots(p) if abs(r.imag) <= 1e-9 and 0 < r.real < 1]
    if not inside:
        return chord
    u = min(inside, key=lambda u: abs(ts[i] + u * h - chord[0]))
    return float(ts[i] + u * h), float(np.polyval(np.polyder(p), u) / h)


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
            res = quiet_near(rows, times, friction=friction)
        except AssemblyError:  # too far from the rows for Newton: the whole run's way
            uniq, inv = np.unique(times, return_inverse=True)
            res = quiet_analyze(system, times=uniq, friction=friction, events=False)
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


def breaks(result: Result, ta: float, tb: float, friction: bool) -> np.ndarray:
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
                quiet_analyze(result.system, times=result.t, friction=True, events=False),
                full_cycle=result.full_cycle,
            )
        jumps += _friction_reversals(rows)
    jumps = [ta + np.mod(te - ta, tb - ta) if full else te for te in jumps]
    kinks = _table_kinks(result) + list(sched.breaks(ta, tb))
    fns = _motion_breaks(rows) + effort_zeros(rows)
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


QUIET = (JointWarning, ElementWarning, NearSingularWarning)  # said once, by the run


def quiet_analyze(system, **kw) -> Result:
    """``analyze`` at times inside the run (its quadrature nodes, its rows again) without
    the warnings about them: the run has warned about its rows once."""
    with warnings.catch_warnings():
        for kind in QUIET:
            warnings.simplefilter("ignore", kind)
        return analyze(system, **kw)


def quiet_near(result: Result, times, **kw) -> Result:
    """:func:`analyze_near` without the warnings (as :func:`quiet_analyze`)."""
    with warnings.catch_warnings():
        for kind in QUIET:
            warnings.simplefilter("ignore", kind)
        return analyze_near(result, times, **kw)
