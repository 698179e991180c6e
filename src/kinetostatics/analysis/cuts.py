"""Where the cycle integral is cut (analysis/cycle.py): the span of a run and the times
at which a quantity may jump or kink, each located exactly.

The cuts: the jumps — the load events the analysis located exactly
(:class:`~kinetostatics.kinetics.conditions.Event`), the reversals of the resisting
loads and, with friction, of the joints with friction — and the corners of the tables,
each located exactly on the motion (Newton on the time from the nearest row); and the
kinks of quantities only the whole pipeline gives (a driving effort through zero, a
friction law's normal force through zero, a cam law's segment end), each bracketed by the
rows, the brackets split at the jumps and at the tables' corners, and located by secant
steps on the pipeline at single times continued from the nearest row
(:func:`~kinetostatics.analysis.pipeline.analyze_near`): never by interpolating across a
jump.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from ..base.arrays import sorted_distinct
from ..base.legendre import inner_roots, padded_roots, piece_series
from ..errors import AssemblyError, ElementWarning, JointWarning, NearSingularWarning
from ..kinematics.schedule import schedule
from ..structure.system import link_pair
from .pipeline import analyze, analyze_near, with_friction
from .results import Result
from .switches import (
    condition_rates,
    exact_roots,
    exact_roots_of,
    friction_rates,
    reversal_rates,
    table_rates,
)

__all__ = [
    "breaks",
    "effort_zeros",
    "merged_cuts",
    "missed_cuts",
    "quiet_analyze",
    "quiet_friction",
    "quiet_near",
    "roundoff_floor",
    "span",
]


def span(result: Result) -> tuple[float, float]:
    """(t_a, t_b) the run covers: one period for a full cycle, else the rows' range."""
    t = np.asarray(result.t, dtype=float)
    if result.full_cycle:
        period = schedule(result.system).period
        t0 = float(np.min(t))
        return t0, t0 + float(period)
    return float(np.min(t)), float(np.max(t))


def _in_time(result: Result):
    """(t, order, period): the rows' times sorted (``order`` sorts the rows) and the period
    of a full cycle (None otherwise)."""

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


def _reaction_scale(result: Result) -> float:
    """The run's largest finite |joint reaction| (λ's joint rows, without and with
    friction): the scale of a reaction's round-off, which no unit or frame of the run
    changes (the system is in SI)."""
    n_j = result.system.n_joint_rows
    top = 0.0
    for lam in (result.lam, result.lam_friction):
        if lam is not None and n_j:
            v = np.abs(np.asarray(lam, dtype=float)[..., :n_j])
            top = max(top, float(np.max(v[np.isfinite(v)], initial=0.0)))
    return top


def _size(system) -> float:
    """The mechanism's size: the largest distance of a link's point from its frame."""
    return max(
        (float(np.linalg.norm(p)) for link in system.model.links for p in link.points.values()),
        default=1.0,
    )


def _above_roundoff(fns: list, floor: float) -> list:
    """The kink functions with every value within ``floor`` of zero set to 0: a round-off
    zero is no sign.  (A column that is zero in exact arithmetic — the tooth force of a
    gear whose second crank turns steadily with nothing on it, ±1e-15 N — otherwise
    changes sign at random, and its "zeros" were cut in one run and not in the same run
    in other units, moving the nodes and the sampled peaks: issue 36, seed 1002093.)"""
    if not floor > 0:
        return fns

    def zeroed(fn):
        def f(r):
            v = np.asarray(fn(r), dtype=float)
            return np.where(np.abs(v) <= floor, 0.0, v)

        return f

    return [zeroed(fn) for fn in fns]


def roundoff_floor(result: Result) -> float:
    """Below this a reaction (a normal force, a tooth force) or a driving effort is a
    round-off zero: 1e-12 of the run's largest reaction, times the mechanism's size where
    that exceeds 1 m (a torque's lever, as for the efficiency's idle effort; for a force
    the floor is then larger than it need be, and still far below any real zero's
    neighbourhood)."""
    return 1e-12 * _reaction_scale(result) * max(1.0, _size(result.system))


JUMP_GAP = 1e-8  # of the span: a jump's sides are sampled this far from it (at most)


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


def _solved_kinks(
    rows: Result, fns: list, jumps: list[float], ta: float, tb: float, corners=()
) -> list:
    """Times where a kink function (``fn(result) -> (N, m)``) changes sign, each located
    on the solved state, as the events are: bracketed by the rows, the brackets split at
    the ``jumps`` (the load events and reversals, where the function may jump: each side
    sampled :data:`JUMP_GAP` of the span from it) and at the ``corners`` (the cuts where
    it may kink: a table's corners, a motion table's knots; sampled there), and the zero
    found by safeguarded secant steps on the function of :func:`analyze` at single times —
    never by interpolating across a jump.  (A corner can turn an effort back through
    zero: a pair of zeros between two rows, one each side of it, seen by neither the rows
    nor the nodes; issue 36, seed 1002123.)"""
    if not fns or len(rows) < 2:
        return []
    t, order, period = _in_time(rows)
    span = tb - ta
    gap = JUMP_GAP * span
    at = _evaluator(rows, fns, ta, period, rows.lam_friction is not None)
    vals = _columns(rows, fns)[order]
    jumps = sorted_distinct([j for j in jumps if ta < j < tb])
    near, sides = _samples(t, jumps, corners, ta, tb, gap)
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
    return _located(at, (lo, hi, flo, fhi, x0, slope, col, scales), span)


def _samples(t, jumps, corners, ta: float, tb: float, gap: float):
    """(near, times): which rows ``t`` lie on a jump (event rows: their side unknown), and
    the times the kink functions are sampled at besides the rows — each side of a jump
    ``gap`` from it, or halfway to the next jump if that is nearer (a moving condition's
    event and its zero-speed band's edge lie 1e-10 apart), and each corner not on a row
    or beside a jump."""
    tol = 1e-12 * (tb - ta)
    near = np.zeros(len(t), dtype=bool)
    for j in jumps:
        near |= np.abs(t - j) <= tol
    room = np.diff(np.concatenate(([ta], jumps, [tb]))) / 2
    left, right = np.minimum(gap, room[:-1]), np.minimum(gap, room[1:])
    sides = np.ravel(np.column_stack((jumps - left, jumps + right)))
    corners = [
        c
        for c in sorted_distinct([c for c in corners if ta < c < tb])
        if np.min(np.abs(t - c), initial=np.inf) > tol
        and np.min(np.abs(jumps - c), initial=np.inf) > gap
    ]
    return near, np.concatenate((sides, corners))


def _evaluator(rows: Result, fns: list, ta: float, period: float | None, friction: bool):
    """``at(times) -> (len(times), m)``: the kink functions on the pipeline at single
    times (with the friction solutions or without), each continued from the nearest row of
    ``rows`` (times taken into the period of a full cycle)."""

    def at(times) -> np.ndarray:
        times = np.asarray(times, dtype=float)
        if period is not None:
            times = ta + np.mod(times - ta, period)
        try:  # each continued from its nearest row
            res = quiet_near(rows, times, friction=friction)
        except AssemblyError:  # too far from the rows for Newton: the whole run's way
            uniq, inv = np.unique(times, return_inverse=True)
            res = quiet_analyze(rows.system, times=uniq, friction=friction, events=False)
            return _columns(res, fns)[inv.ravel()]
        return _columns(res, fns)

    return at


def _located(at, brackets, span: float) -> list[float]:
    """The zeros in the brackets ``(lo, hi, flo, fhi, guess, slope, column, scale)`` (lists,
    one entry a bracket), found by :func:`_secant` on ``at``."""
    if not brackets[0]:
        return []
    lo, hi, flo, fhi, x, slope, col, scales = (np.array(z) for z in brackets)
    f = lambda tt, cc: at(tt)[np.arange(len(tt)), cc]  # noqa: E731
    roots = _secant(f, lo, hi, flo, fhi, x, slope, col, span, 1e-13 * scales)
    return [float(r) for r in roots]


def _stretch_changes(ts: np.ndarray, vals: np.ndarray, seg: np.ndarray):
    """Per column of ``vals`` (samples at the sorted times ``ts``, each in the stretch
    ``seg`` between two cuts), the samples ``a`` after which the sign changes before the
    next sample of the same stretch (round-off, 1e-12 of the column's largest |value|, is
    no sign): ``[(column, a, scale)]``."""
    out = []
    for m in range(vals.shape[1]):
        v = vals[:, m]
        ok = np.isfinite(v)
        scale = np.max(np.abs(v[ok]), initial=0.0)
        sign = np.where(ok & (np.abs(v) > 1e-12 * scale), np.sign(v), 0.0)
        for a in np.flatnonzero((sign[:-1] * sign[1:] < 0) & (seg[:-1] == seg[1:])):
            out.append((m, int(a), scale))
    return out


def missed_cuts(
    rows: Result, nodes: Result, edges: np.ndarray, friction: bool, per_piece: int = 0
) -> list[float]:
    """Switches and kinks the rows did not bracket — a pair of them between two rows: a
    rocker reversing and turning back, an effort through zero and back — that the
    quadrature ``nodes`` see: a sign change between two consecutive nodes with no cut
    (``edges``, sorted, the span's ends included) between them.  First the switches on the
    motion (:mod:`.switches`: the reversals of the resisting loads and, with ``friction``,
    of the joints with friction, the loads' conditions, the tables' corners), located
    exactly; where none is new (off the cuts), the kinks the pipeline gives (a cam law's
    segment ends, the drivers' efforts), located as :func:`_solved_kinks` does, continued
    from the ``nodes`` (nearer than the rows); with ``per_piece`` (the nodes of a piece of
    the quadrature, consecutive in time), a kink function whose piece's interpolant has
    two roots between two nodes is sampled between them too (:func:`_dips`).  Empty, and
    nothing solved, when the nodes see nothing new."""
    if len(nodes) < 2:
        return []
    ts, order, _ = _in_time(nodes)
    seg = np.searchsorted(edges, ts)  # the stretch between two cuts of each node
    rates = reversal_rates(rows) + condition_rates(rows) + table_rates(rows)
    if friction and rows.system.model.has_friction:
        rates += friction_rates(rows)
    q, qd, qdd = nodes.q[order], nodes.qd[order], nodes.qdd[order]
    seen = []
    for entry in rates:
        f, keep = entry if isinstance(entry, tuple) else (entry, None)
        v = np.asarray(f(q, qd, qdd)[0], dtype=float)
        if keep is not None:  # the roots that do not count: no sign there
            v = np.where(keep(q, qd, qdd), v, 0.0)
        if _stretch_changes(ts, v[:, None], seg):
            seen.append(entry)
    span = float(edges[-1] - edges[0])
    new = [r for r in exact_roots(nodes, seen) if np.min(np.abs(edges - r)) > 1e-12 * span]
    if new:
        return new
    fns = _motion_breaks(nodes) + _above_roundoff(effort_zeros(nodes), roundoff_floor(nodes))
    if not fns:
        return []
    vals = _columns(nodes, fns)[order]
    at = _evaluator(nodes, fns, float(edges[0]), None, nodes.lam_friction is not None)
    dips = _dips(ts, vals, per_piece)
    if dips.size:
        ts, o = np.concatenate((ts, dips)), np.argsort(np.concatenate((ts, dips)), kind="stable")
        ts, vals = ts[o], np.vstack((vals, at(dips)))[o]
        seg = np.searchsorted(edges, ts)
    brackets: tuple[list, ...] = ([], [], [], [], [], [], [], [])
    for m, a, scale in _stretch_changes(ts, vals, seg):
        v = vals[:, m]
        guess = _guess(ts, v, seg, a)
        for z, value in zip(brackets, (ts[a], ts[a + 1], v[a], v[a + 1], *guess, m, scale)):
            z.append(value)
    return _located(at, brackets, span)


def _dips(ts: np.ndarray, vals: np.ndarray, per_piece: int) -> np.ndarray:
    """Times between two consecutive nodes where a piece's interpolant (the Legendre series
    through its ``per_piece`` node values, :mod:`~kinetostatics.base.legendre`) of a kink
    function has two roots: the function dips through zero and back between the nodes, a
    pair of kinks no sign of theirs shows (issue 36, seed 1005331: an effort 5e-5 of its
    scale below zero for 1/700 of the cycle).  The midpoint of each such pair."""
    n = per_piece
    if n < 3 or len(ts) % n:
        return np.zeros(0)
    x = np.polynomial.legendre.leggauss(n)[0]
    t = ts.reshape(-1, n)
    half = (t[:, -1] - t[:, 0]) / (x[-1] - x[0])
    centre = t[:, 0] - half * x[0]
    v = vals.T.reshape(-1, n)  # every column's pieces, column after column
    v = np.where(np.all(np.isfinite(v), axis=1)[:, None], v, 0.0)  # no series there
    inner = inner_roots(padded_roots(piece_series(len(v), v.ravel())))
    slot = np.searchsorted(x, np.nan_to_num(inner, nan=2.0))  # the nodes each lies between
    row, k = np.nonzero(
        np.isfinite(inner[:, :-1]) & np.isfinite(inner[:, 1:]) & (slot[:, :-1] == slot[:, 1:])
    )
    p = row % len(t)
    return centre[p] + half[p] * 0.5 * (inner[row, k] + inner[row, k + 1])


def merged_cuts(ta: float, tb: float, times) -> np.ndarray:
    """The span's ends and the ``times`` inside it, sorted; a time within round-off
    (1e-12 of the span) of another is that one, the span's end kept."""
    inner = [te for te in times if ta < te < tb]
    edges = sorted_distinct(np.concatenate(([ta], inner, [tb])))
    keep = np.append(True, np.diff(edges) > 1e-12 * (tb - ta))
    if not keep[-1]:  # the span's end stays, the cut beside it goes
        keep[-1], keep[-2] = True, False
    return edges[keep]


def _secant(  # noqa: PLR0913  the brackets' arrays of one vectorised root search
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
    where a ``moving`` condition's speed leaves the zero-speed band, the reversals of the
    resisting loads, a motion law's turning points and, with friction, the reversals of
    the joints with friction: these two at the edges of the zero-speed band), the
    corners of the tables and the motion tables' knots, all located exactly; and the
    kinks located on the solved state (:func:`_solved_kinks`): the breaks of the pairs'
    motion (a cam law's segment ends), the zeros of the drivers' efforts (kinks of a
    motor's torque behind a reduction) and, with friction, the kinks of the friction
    laws."""

    sched = schedule(result.system)
    full = result.full_cycle
    rows = result
    # a motion law turning back (ψ̇ = 0): the power through a reduction changes sign
    # there with the effort ≠ 0, a jump of the motor's torque (dynamics/drive.py)
    turns = list(sched.turning_times(ta, tb))
    jumps = [float(e.t) for e in result.events] + turns
    switching = reversal_rates(result) + condition_rates(result)
    if friction and result.system.model.has_friction:
        if rows.lam_friction is None:  # rows without the friction solutions: solve them
            # there, for the kinks of the consistent solution and its effort's zeros
            rows = replace(
                quiet_analyze(result.system, times=result.t, friction=True, events=False),
                full_cycle=result.full_cycle,
            )
        switching += friction_rates(rows)  # of the motion alone: the rows' is the result's
    # every switch on the motion located in one refine (their roots' steps are each their own)
    switches, corners = exact_roots_of(result, [switching, table_rates(result)])
    jumps = [ta + np.mod(te - ta, tb - ta) if full else te for te in jumps + switches]
    kinks = corners + list(sched.breaks(ta, tb))
    floor = roundoff_floor(rows)  # a round-off zero of an effort or reaction: no sign
    fns = _above_roundoff(effort_zeros(rows), floor)
    if friction and result.system.model.has_friction:
        fns += _above_roundoff(_friction_kinks(rows), floor)
    # a cam law's segment end first: an acceleration may jump there, and the efforts with
    # it, so their zeros are sought on each side of it (a zero just after it, the effort
    # jumping back across zero at it, leaves the rows' signs equal: issue 36, seed 1005308)
    ends = _solved_kinks(rows, _motion_breaks(rows), jumps, ta, tb, corners=kinks)
    kinks += ends + _solved_kinks(rows, fns, jumps + ends, ta, tb, corners=kinks + ends)
    times = [ta + np.mod(te - ta, tb - ta) if full else te for te in jumps + kinks]
    return merged_cuts(ta, tb, times)


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


def quiet_friction(result: Result) -> Result:
    """:func:`~.pipeline.with_friction` (the rows again with the friction solutions, on
    the same motion) without the warnings (as :func:`quiet_analyze`)."""
    with warnings.catch_warnings():
        for kind in QUIET:
            warnings.simplefilter("ignore", kind)
        return with_friction(result)
