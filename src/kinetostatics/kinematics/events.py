"""Roots in time: where a function of the state changes sign, located exactly; and the rule
for the outputs built on them (the strokes and time ratios of the output slides).

Each comes in two forms side by side: over the rows of one run (each root continued from
the nearest solved row, :func:`~kinetostatics.kinematics.positions.state_at`), and stacked over
variants ``(V, N, ...)`` (:mod:`~kinetostatics.analysis.vectorised`), which evaluates the closed
forms (:func:`~kinetostatics.kinematics.closed_path.closed_form_near`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..structure.system import System, coordinate_gradient
from .closed_path import closed_form_near
from .continuation import time_step
from .newton import group_newton
from .plan import derivatives_at
from .positions import state_at
from .schedule import Schedule, schedule
from .state import joint_coordinate, joint_coordinate_bias

__all__ = [
    "refine",
    "find_roots",
    "find_roots_of",
    "state_near",
    "refine_stacked",
    "state_stacked",
    "output_slides",
    "output_members",
    "coordinate_rates",
    "output_strokes",
    "output_strokes_stacked",
]


# -- roots over the rows of one run ------------------------------------------------------
TIME_TOL = 1e-14
"""A root in time is refined until Newton's step is this fraction of its time, or of the
time the motion drivers take to move 1 rad (1 L_ref for a slider) where that is larger
(:func:`time_unit`): the same fraction of the motion at any speed and scale.  (It was of
1 s: at 20,000 rpm 3e-12 of a turn, and a batch row's time ratio differed from the single
run's by 1.1e-11.)"""


def time_unit(system: System, drive) -> float:
    """The time the motion drivers take to move 1 rad, or 1 L_ref for a slider, at their
    reference speeds (:func:`~.continuation.time_step` of 1; the least of stacked
    variants'), or 1 s for a drive without them."""
    return time_step(system, 0.0, drive, 1.0) if hasattr(drive, "speed") else 1.0


def refine(system, drive, f, t0, tn, qn, qdn, qddn, max_iter=12, bracket=None, owner=None):  # noqa: PLR0913  loose sample arrays: several callers' grids
    """Newton on t for f(state) = 0, all roots at once.

    ``t0 (k,)`` first guesses, ``tn`` and ``qn``/``qdn``/``qddn`` the solved
    samples nearest to each (same branch).  ``bracket``, optional, is
    ``(lo, hi, sign_lo)``: each root lies in [lo, hi], where f has the sign
    ``sign_lo`` at lo and the other at hi; a Newton step that would leave the
    bracket (which shrinks with every evaluation) is replaced by bisection, so
    the iteration never wanders to another part of the motion.  ``owner``, optional,
    ``(k,)`` ints: ``f`` is then a list of functions and root i is a root of
    ``f[owner[i]]`` (several functions' roots refined together, each root as it would be
    alone: every step is per root).  Returns the roots ``(k,)`` and their states.
    """
    t = np.array(t0, dtype=float)
    live = np.ones(t.shape, dtype=bool)
    states = [qn.copy(), qdn.copy(), qddn.copy()]
    unit = time_unit(system, drive)
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
        g, dg = f(q, qd, qdd) if owner is None else _each(f, owner[idx], q, qd, qdd)
        dt = np.divide(-g, dg, out=np.zeros_like(g), where=dg != 0)
        tol = TIME_TOL * np.maximum(np.abs(t[idx]), unit)
        # a zero slope (a follower at rest in a cam's dwell) gives no step, not a root
        done = ((np.abs(dt) <= tol) & (dg != 0)) | (g == 0)
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
            t[idx] = np.where(
                done, t[idx], np.where(out, _outside(t[idx], step, lo[idx], hi[idx]), step)
            )
        live[idx[done]] = False
    return t, states


def _outside(t: np.ndarray, step: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Where a Newton step from ``t`` leaves the bracket [lo, hi]: bisection, or, when it
    passes an end by less than a quarter of t's distance from that end (the root lies by
    that end: Newton converging on it from one side and overshooting it by its own error),
    the point that far inside.  A root on the bracket's end (a limit position at the start
    of the run) took ~15 bisections so; this way Newton's convergence is kept."""
    end = np.where(step <= lo, lo, hi)
    past, room = np.abs(step - end), np.abs(t - end)
    mirrored = end + np.sign(t - end) * past
    near = np.isfinite(step) & (past <= 0.25 * room) & (mirrored > lo) & (mirrored < hi)
    return np.where(near, mirrored, 0.5 * (lo + hi))


def _each(fs, owner, q, qd, qdd):
    """(g, ġ) of the functions ``fs``, each at the states whose ``owner`` it is."""
    g, dg = np.empty(len(owner)), np.empty(len(owner))
    for i in np.flatnonzero(np.bincount(owner)):  # np.unique would import numpy.ma
        sel = owner == i
        g[sel], dg[sel] = fs[i](q[sel], qd[sel], qdd[sel])
    return g, dg


def find_roots(system, drive, t, q, qd, qdd, fvals, f, full, period_t):  # noqa: PLR0913  loose sample arrays: several callers' grids
    """Times where fvals changes sign between samples (cyclically if full), refined."""
    return find_roots_of(system, drive, t, q, qd, qdd, [(fvals, f)], full, period_t)[0]


def find_roots_of(system, drive, t, q, qd, qdd, pairs, full, period_t):  # noqa: PLR0913  loose sample arrays: several callers' grids
    """:func:`find_roots` of several functions at once, ``pairs`` ``[(fvals, f)]``: the
    brackets of all concatenated and refined in one :func:`refine` (one state per
    iteration for all of them, not one refine per function); ``[(roots, states)]``, one
    per pair, each as :func:`find_roots` gives it.  A pair may be ``(fvals, f, dvals)``,
    with the time derivatives at the samples: each root's first guess is then the root of
    the cubic Hermite interpolant of the bracket's ends (:func:`_hermite_guess`), not the
    chord's (a follower leaving a dwell, f ~ (t − t₀)³, took 20 Newton steps from the
    chord); the root is located to the same tolerance either way."""
    found = [_crossings(t, p[0], full, period_t, *p[2:]) for p in pairs]
    empty = np.zeros(0), [np.zeros((0,) + q.shape[1:])] * 3
    sizes = [0 if c is None else len(c[0]) for c in found]
    if not sum(sizes):
        return [empty] * len(pairs)
    guess, tn, n, lo, hi, sign = (
        np.concatenate([c[i] for c in found if c is not None]) for i in range(6)
    )
    owner = np.repeat(np.arange(len(pairs)), sizes)
    fs = [p[1] for p in pairs]
    roots, states = refine(
        system, drive, fs, guess, tn, q[n], qd[n], qdd[n], bracket=(lo, hi, sign), owner=owner
    )
    if full:
        roots = np.mod(roots, period_t)
    out = []
    for i in range(len(pairs)):
        sel = owner == i
        out.append((roots[sel], [s[sel] for s in states]) if sizes[i] else empty)
    return out


def _crossings(t, fvals, full, period_t, dvals=None):
    """(guess, t_near, near row, lo, hi, sign at lo) of each bracket where ``fvals``
    changes sign between samples (cyclically if full), or None.  ``dvals``: the time
    derivatives at the samples (the guess then :func:`_hermite_guess`'s)."""
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
        return None
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
    if dvals is not None:
        ds = dvals[order]
        hermite = _hermite_guess(ts[a], tb, fa, fb, ds[a], ds[b], sign_a)
        guess = np.where((fa == 0.0) | ~np.isfinite(hermite), guess, hermite)
    return guess, tn, n, ts[a], tb, sign_a


HERMITE_STEPS = 10, 4  # bisection steps (to 1e-3 of the bracket), then Newton steps


def _hermite_guess(ta, tb, fa, fb, da, db, sign_a):
    """A root inside each bracket [ta, tb] of the cubic Hermite interpolant of the values
    ``fa``, ``fb`` (of opposite signs, ``sign_a`` at ta) and the slopes ``da``, ``db``:
    bisection on the cubic (which changes sign in the bracket), then Newton steps kept
    inside the bisection's bracket, all brackets at once."""
    h = tb - ta
    ma, mb = h * da, h * db  # p(u) = c0 + c1 u + c2 u² + c3 u³ on u ∈ [0, 1]
    c0, c1 = fa, ma
    c2 = 3 * (fb - fa) - 2 * ma - mb
    c3 = 2 * (fa - fb) + ma + mb
    lo, hi = np.zeros(len(ta)), np.ones(len(ta))
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        for _ in range(HERMITE_STEPS[0]):
            u = 0.5 * (lo + hi)
            same = np.sign(c0 + u * (c1 + u * (c2 + u * c3))) == sign_a
            lo, hi = np.where(same, u, lo), np.where(same, hi, u)
        u = 0.5 * (lo + hi)
        for _ in range(HERMITE_STEPS[1]):
            step = u - (c0 + u * (c1 + u * (c2 + u * c3))) / (c1 + u * (2 * c2 + 3 * u * c3))
            u = np.where((step >= lo) & (step <= hi), step, u)
        return ta + h * u


def state_near(system, drive, r, t, q, qd, qdd):
    """(q, q̇, q̈) at the time ``r``, continued from the row of ``t`` nearest to it, ``(1, n_q)``."""
    n = int(np.argmin(np.abs(t - r)))
    return state_at(
        system, drive, np.array([r]), t[n : n + 1], q[n : n + 1], qd[n : n + 1], qdd[n : n + 1]
    )


# -- roots over stacked variants ---------------------------------------------------------
def state_stacked(system: System, solvers, sched: Schedule, t: np.ndarray, guess: np.ndarray):
    """(q, q̇, q̈) at times ``t (V, M)`` by the closed forms, angles nearest ``guess``; with
    ``solvers`` None (a group without one) by Newton from ``guess``, group by group, NaN
    where a group does not converge (the variant then leaves the stacked analysis)."""
    psi, psi_d, psi_dd = sched(t)
    if solvers is not None:
        q, _ = closed_form_near(solvers, guess, psi)
        qd, qdd, _ = derivatives_at(system, q, psi_d, psi_dd)
        return q, qd, qdd
    q = guess
    with np.errstate(all="ignore"):
        for plan in system.plans:
            q, conv, _ = group_newton(system, q, psi, plan)
            q = np.where(conv[..., None], q, np.nan)
        qd, qdd, _ = derivatives_at(system, q, psi_d, psi_dd)
    return q, qd, qdd


def refine_stacked(system, solvers, sched, f, t0, q0, qd0, qdd0, max_iter=12, bracket=None):  # noqa: PLR0913  loose sample arrays of stacked variants
    """Newton on t for ``f(q, q̇, q̈) = (g, ġ) = 0``, all variants and roots at once.

    ``t0 (V, M)`` first guesses, ``q0, qd0, qdd0 (V, M, n_q)`` solved states
    near them (same branch); returns (t, (q, q̇, q̈)) at the roots.  ``bracket``,
    optional, ``(lo, hi, sign_lo)`` each ``(V, M)``, as :func:`refine`'s: a step that
    would leave the bracket is replaced as there (:func:`_outside`), so that a root
    between two rows is the one found (issue 36, seed 1008937: from a chord 30° wide,
    Newton went to another part of the cycle and a batch row's time ratio was 1.142
    against the single run's 1.0036).
    """
    t = np.array(t0, dtype=float)
    h = (t - t0)[..., None]
    guess = q0 + h * qd0 + 0.5 * h * h * qdd0
    unit = time_unit(system, sched)
    if bracket is not None:
        lo, hi, sign_lo = (np.array(x, dtype=float) for x in bracket)
        max_iter = max(max_iter, 64)  # bisection halves the bracket each time
    for _ in range(max_iter):
        q, qd, qdd = state_stacked(system, solvers, sched, t, guess)
        g, dg = f(q, qd, qdd)
        dt = np.divide(-g, dg, out=np.zeros_like(g), where=dg != 0)
        tol = TIME_TOL * np.maximum(np.abs(t), unit)
        if bracket is None:
            step = t + dt
            done = np.abs(dt) <= tol
        else:
            below = np.sign(g) == sign_lo
            lo, hi = np.where(below, t, lo), np.where(below, hi, t)
            step = t + dt
            out = ~((step > lo) & (step < hi)) | (dg == 0)
            step = np.where(out, _outside(t, step, lo, hi), step)
            done = ((np.abs(dt) <= tol) & ~out) | (hi - lo <= tol) | (g == 0)
            step = np.where(done, t, step)
        dt = step - t
        t = step
        guess = q + dt[..., None] * qd + 0.5 * (dt * dt)[..., None] * qdd
        if np.all(done):
            break
    return t, state_stacked(system, solvers, sched, t, guess)


# -- the outputs: strokes and swings, limit positions, time ratios ---------------------
def _on_frame(system: System, j) -> bool:
    return system.model.ground.name in j.links


def output_slides(system: System) -> list[tuple[int, Any]]:
    """``[(k, joint)]``: the undriven pairs on the frame whose type reports a stroke
    (``Joint.reports_stroke``: a prismatic pair), in file order; ``k`` indexes
    ``system.constraints``.  A slide between two moving links (a block in a slotted
    lever) is a relative motion, never the machine's output, and is not listed."""
    driven = {d.joint.name for d in system.motion_drivers}
    return [
        (k, j)
        for k, j in enumerate(system.model.joints)
        if j.reports_stroke and j.name not in driven and _on_frame(system, j)
    ]


def output_members(system: System) -> list[dict[str, Any]]:
    """The output members whose limit positions and time ratio ``output_strokes`` reports:
    the file's ``output:`` alone when it names one, else every output slide
    (:func:`output_slides`) and every undriven revolute on the frame (``reports_swing``:
    its link's swing).  Each is ``{"name", "kind" ("slide"|"swing"), "k" (constraint
    index, or None for a link), "link"}``."""
    model = system.model
    driven = {d.joint.name for d in system.motion_drivers}
    ground = model.ground.name
    named = getattr(model, "output", None)
    if named in system.links:  # a link: the pair that holds it on the frame, if any
        pair = [
            j.name
            for j in model.joints
            if named in j.links
            and ground in j.links
            and j.name not in driven
            and (j.reports_stroke or j.reports_swing)
        ]
        if len(pair) == 1:
            named = pair[0]
    out = []
    for k, j in enumerate(model.joints):
        if j.name in driven or (named is not None and j.name != named):
            continue
        link = next((x for x in j.links if x != ground), j.links[-1])
        if j.reports_stroke and (_on_frame(system, j) or named is not None):
            out.append({"name": j.name, "kind": "slide", "k": k, "link": link})
        elif j.reports_swing and (_on_frame(system, j) or named is not None):
            out.append({"name": j.name, "kind": "swing", "k": k, "link": link})
    if named is not None and not out and named in system.links:
        out.append({"name": named, "kind": "swing", "k": None, "link": named})
    return out


def coordinate_rates(system: System, q, qd, qdd, k: int) -> tuple[np.ndarray, np.ndarray]:
    """(ċ, c̈) of the relative coordinate c of constraint ``k`` (a slide's sliding speed
    and acceleration), ``(...)`` each."""
    g = coordinate_gradient(system, q, k)
    return (
        np.einsum("...n,...n->...", g, qd),
        np.einsum("...n,...n->...", g, qdd) + joint_coordinate_bias(system, q, qd, k),
    )


def _member_functions(system: System, member: dict[str, Any]):
    """(rates, value) of an output member: ``rates(q, q̇, q̈) = (ċ, c̈)`` and ``value(q)``:
    a slide's coordinate (m), a revolute on the frame's link angle θ (rad), another
    revolute's relative angle, a link's angle."""
    k = member["k"]
    if member["kind"] == "slide" or (
        k is not None and not _on_frame(system, system.model.joints[k])
    ):
        return (
            lambda q, qd, qdd: coordinate_rates(system, q, qd, qdd, k),
            lambda q: joint_coordinate(system, q, k),
        )
    n = 3 * system.link_index(member["link"]) + 2
    return (lambda q, qd, qdd: (qd[..., n], qdd[..., n]), lambda q: q[..., n])


def output_strokes(result) -> dict[str, dict[str, Any]]:
    """Stroke or swing, limit positions and time ratio of every output member
    (:func:`output_members`).

    Limit positions are the exact zeros of the member's speed (:func:`find_roots`); the
    time ratio K is the slower stroke's time over the faster's, from those exact
    positions (full cycles only), and ``theta_extreme`` = 180°(K − 1)/(K + 1) the crank
    angle between the limit positions.  A slide gives ``stroke`` (m) and its coordinate
    ``s`` at each limit; a swing gives ``swing`` (deg) and the link's angle ``theta``
    (deg, mod 360; a revolute between two moving links: the relative angle).  ``min`` is
    the limit where the coordinate is least (a swing: where the counter-clockwise swing
    starts).  A member that does not stop exactly twice per cycle (a link that turns
    fully) is left out.
    """
    system = result.system
    out: dict[str, dict[str, Any]] = {}
    if not result.full_cycle or "angle" not in result.columns:
        return out
    members = output_members(system)
    if not members:
        return out
    sched = schedule(system)
    period = sched.period
    for m in members:
        f, value = _member_functions(system, m)
        ds = f(result.q, result.qd, result.qdd)[0]
        roots, (qr, _, _) = find_roots(
            system, sched, result.t, result.q, result.qd, result.qdd, ds, f, True, period
        )
        if len(roots) != 2:
            continue
        vals = [float(v) for v in value(qr)]

        def coord(r):
            return float(np.degrees(sched(np.array([r]))[0][0, 0]) % 360.0)

        if m["kind"] == "slide":
            lo, hi = (0, 1) if vals[0] < vals[1] else (1, 0)
            size = {"stroke": vals[hi] - vals[lo]}
            at = {"s": vals}
        else:
            # the sense of the swing from root 0 to root 1: that of a row between them
            span = np.mod(result.t - roots[0], period)
            inside = span < np.mod(roots[1] - roots[0], period)
            sense = np.sign(np.sum(ds[inside])) if inside.any() else 1.0
            lo, hi = (0, 1) if sense >= 0 else (1, 0)
            swing = float(np.mod(vals[hi] - vals[lo], 2 * np.pi))
            size = {"swing": float(np.degrees(swing))}
            at = {"theta": [float(np.degrees(v) % 360.0) for v in vals]}
        t_up = (roots[hi] - roots[lo]) % period  # from the low to the high extreme
        t_down = period - t_up
        k_ratio = max(t_up, t_down) / min(t_up, t_down)
        key = next(iter(at))
        out[m["name"]] = {
            "kind": m["kind"],
            "link": m["link"],
            **size,
            "limit_positions": {
                "min": {"angle": coord(roots[lo]), key: at[key][lo]},
                "max": {"angle": coord(roots[hi]), key: at[key][hi]},
            },
            "time_ratio": k_ratio,
            "theta_extreme": 180.0 * (k_ratio - 1.0) / (k_ratio + 1.0),
            "time_increasing_s": t_up,
            "time_decreasing_s": t_down,
        }
    return out


REST = 1e-9
"""A row where an output slide's speed and its rate are both within this fraction of
their largest values over the cycle is at rest (a dwell, or a double zero on the row):
where its speed's sign changes is round-off, so the stacked strokes leave that variant to
its own analysis (:func:`output_strokes`)."""
REST_AT_ROOT = 1e-6
"""A limit position found where the slide's acceleration is within this fraction of its
largest value (the slide comes to rest, not back): its own analysis, too."""


def _at_rest(ds: np.ndarray, dds: np.ndarray) -> np.ndarray:
    """(V,): some row of the speeds ``ds (V, N)`` and their rates ``dds`` at rest (:data:`REST`)."""
    still = np.abs(ds) <= REST * np.max(np.abs(ds), axis=-1, keepdims=True)
    return np.any(still & (np.abs(dds) <= REST * np.max(np.abs(dds), axis=-1, keepdims=True)), -1)


def output_strokes_stacked(
    system: System, solvers, sched: Schedule, t, q, qd, qdd
) -> tuple[dict[str, dict[str, np.ndarray]], np.ndarray]:
    """Stroke and time ratio of every output slide, ``(V,)`` each, over a full cycle of
    stacked variants ``q (V, N, n_q)`` (as :func:`output_strokes`), and ``ok (V,)``: false
    for a variant whose slide does not stop exactly twice per cycle, or comes to rest
    (:data:`REST`, :data:`REST_AT_ROOT`)."""
    out = {}
    ok = np.ones(q.shape[0], dtype=bool)
    period = 2 * np.pi / sched.reference
    n = q.shape[1]
    for k, j in output_slides(system):

        def f(q, qd, qdd, k=k):
            return coordinate_rates(system, q, qd, qdd, k)

        ds, dds = f(q, qd, qdd)
        a = np.arange(n)
        b = (a + 1) % n  # a full cycle: the last pairs with the first
        fa, fb = ds[:, a], ds[:, b]
        cross = (np.sign(fa) * np.sign(fb) < 0) | (fa == 0.0)
        two = np.count_nonzero(cross, axis=-1) == 2
        ok &= two & ~_at_rest(ds, dds)
        idx = np.argsort(~cross, axis=-1, kind="stable")[:, :2]  # the first two crossings
        ia, ib = idx, (idx + 1) % n
        ta, tb = t[ia], t[ib] + np.where(ib == 0, period, 0.0)
        fa, fb = np.take_along_axis(ds, ia, -1), np.take_along_axis(ds, ib, -1)
        near_b = np.abs(fb) < np.abs(fa)
        nn = np.where(near_b, ib, ia)
        with np.errstate(invalid="ignore", divide="ignore"):
            guess = np.where(fa == 0.0, ta, ta + (tb - ta) * fa / (fa - fb))

        def take(x, nn=nn):
            return np.take_along_axis(x, nn[..., None], axis=1)

        sign_a = np.sign(np.take_along_axis(ds, ia, -1))
        roots, (qr, qdr, qddr) = refine_stacked(
            system,
            solvers,
            sched,
            f,
            guess,
            take(q),
            take(qd),
            take(qdd),
            bracket=(ta, tb, np.where(sign_a == 0, -np.sign(fb), sign_a)),
        )
        scale = np.max(np.abs(dds), axis=-1, keepdims=True)  # a limit position: ċ = 0, c̈ ≠ 0
        ok &= np.all(np.abs(f(qr, qdr, qddr)[1]) > REST_AT_ROOT * scale, axis=-1)
        vals = joint_coordinate(system, qr, k)
        ok &= np.all(np.isfinite(vals), axis=-1)  # a state Newton did not reach (no closed form)
        out[j.name] = _stroke_and_ratio(np.mod(roots, period), vals, two, period)
    return out, ok


def _stroke_and_ratio(roots, vals, two, period: float) -> dict[str, np.ndarray]:
    """A slide's stroke and time ratio ``(V,)`` from the times ``roots (V, 2)`` of its
    limit positions in the period and its coordinates ``vals (V, 2)`` there (NaN where
    it does not stop exactly twice, ``two`` false)."""
    lo = np.argmin(vals, axis=-1)[:, None]
    r_lo = np.take_along_axis(roots, lo, -1)[:, 0]
    r_hi = np.take_along_axis(roots, 1 - lo, -1)[:, 0]
    t_up = np.mod(r_hi - r_lo, period)
    t_down = period - t_up
    ratio = np.maximum(t_up, t_down) / np.minimum(t_up, t_down)
    stroke = np.abs(vals[:, 1] - vals[:, 0])
    return {"stroke": np.where(two, stroke, np.nan), "time_ratio": np.where(two, ratio, np.nan)}
