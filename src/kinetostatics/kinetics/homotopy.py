"""The consistent friction solution's homotopy σ: 0 → 1, all its positions at once.

Where the fixed point of :func:`~kinetostatics.kinetics.friction.consistent` does not
converge, the branch connected to the frictionless x₀ is followed from σ = 0 (no
friction) to σ = 1 with the friction efforts scaled by σ, in projective coordinates
x = y/t (ĉ·y = 1, ĉ the direction of the last point, so the chart follows the path),
where it stays smooth as the reactions grow without bound: μ is positively homogeneous
of degree 1 in λ, so A x + Σ g e(x) + Q = 0 reads

    A y + σ Σ g e(y) + Q t = 0,   ĉ·y = 1,

and the reactions diverge exactly where t crosses 0 — self-locking, decided by the sign
of t, however close to the edge of a locked zone the position is.  The path is continued
past such a crossing to σ = 1 where it can be, so ``reach`` = sign(t)·|x₀|/|x| at σ = 1
is a signed margin that changes sign at the edge (1 without friction, → 0 at the edge,
< 0 past it; NaN where unknown).  A fold (det of the Jacobian changing sign with t > 0)
is self-locking too.

Each position has its own σ, step and chart, and makes the choices it would make alone
(the step doubled after a success up to 0.25, halved after a failure down to 1e-7);
the positions only share the NumPy calls: every continuation step is tried at all the
positions still on their way at once, and each Newton iteration at those of them still
iterating — one call of each operation per iteration for all of them, where a
position followed alone paid its ~15 calls for each of its hundreds of iterations.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["NEWTON", "CYCLING", "follow"]

NEWTON = 30
CYCLING = (12, 1e-6)
"""A homotopy step's Newton gives up after :data:`NEWTON` iterations, or after the first
of ``CYCLING`` while its step is still above the second (relative to y): it is then
cycling between the pieces of the friction laws' |·|, which it does not leave (the step
halves and tries again).  On the self-locking hard case at 360 and at 1,000 positions
every Newton that converged had its step below 1e-7 of y by its 8th iteration and below
1e-11 from its 12th on, and all but one of those that did not were still above 1e-6 at
their 12th (5.6e-6 to 32 at their 25th to 30th): each cost 30 iterations, three
quarters of the consistent solution's time there (tests/kinetics/test_friction.py holds
the first)."""

TOL = 1e-13  # a Newton step's convergence, relative to y and to t (the fixed point's)

FULL_ROWS = 8
"""Up to this many positions in a step, each Newton iteration evaluates them all, not only
those still iterating: then the rows the equations are evaluated at stay the same for
the whole step, and gathering the joints' terms at the live ones each iteration cost
more than evaluating a few more (the others' values are dropped: each position's own
numbers are unchanged)."""
FIRST_STEP, LONGEST_STEP, SHORTEST_STEP = 0.05, 0.25, 1e-7

Friction = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]


def follow(
    a: np.ndarray, q_load: np.ndarray, x0: np.ndarray, friction: Friction, jacobian: Friction
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Follow σ: 0 → 1 at m positions: A ``a (m, n, n)``, Q ``q_load (m, n)`` and the
    frictionless ``x0 (m, n)``; ``friction(rows, y, σ)`` the friction efforts' generalized
    force Σ g e(y)·σ at the positions ``rows`` (indices of the m, ``y (r, n)``, ``σ (r,
    1)``) and ``jacobian(rows, y, σ)`` the derivative of A y + that by y ``(r, n, n)``.
    Returns (x, status 1 or 2, Newton iterations, reach), one row or value a position."""
    m, n = x0.shape
    qs = np.maximum(np.max(np.abs(q_load), axis=-1), 1e-300)
    qh = q_load / qs[:, None]  # t scaled by |Q|: τ = t·|Q|, x = y·|Q|/τ
    n0 = np.linalg.norm(x0, axis=-1)
    y, tau = x0 / n0[:, None], qs / n0  # A y + Q̂ τ = 0 at σ = 0, |y| = 1
    det0 = np.sign(np.linalg.det(a))
    sigma, h = np.zeros(m), np.full(m, FIRST_STEP)
    iters, crossed = np.zeros(m, dtype=int), np.zeros(m, dtype=bool)
    x, status, reach = np.full((m, n), np.nan), np.full(m, 2), np.full(m, np.nan)
    on = np.flatnonzero(sigma < 1.0)  # the positions still on their way
    while on.size:
        h[on] = np.minimum(h[on], 1.0 - sigma[on])
        s = sigma[on] + h[on]
        yn, tn, ok = _newton(a, qh, y[on], tau[on], s, on, iters, friction, jacobian)
        with np.errstate(all="ignore"):  # the rows whose Newton failed: not read below
            norm = np.linalg.norm(yn, axis=-1)
            yn, tn = yn / norm[:, None], tn / norm
        # t changing sign with a large turn of y is a jump of the chart, not a crossing
        chart = ((tn > 0.0) == (tau[on] > 0.0)) | (np.max(np.abs(yn - y[on]), axis=-1) <= 0.1)
        ask = np.flatnonzero(ok & chart & (tn > 0.0) & ~crossed[on])
        folded = np.zeros(on.size, dtype=bool)
        if ask.size:
            j = jacobian(on[ask], yn[ask], s[ask, None])
            folded[ask] = np.sign(np.linalg.det(j)) != det0[on[ask]]
        step = ok & chart & ~folded
        took, missed = on[step], on[~step]
        crossed[took] |= tn[step] <= 0.0  # the reactions went through infinity
        sigma[took], y[took], tau[took] = s[step], yn[step], tn[step]
        h[took] = np.minimum(2.0 * h[took], LONGEST_STEP)
        h[missed[h[missed] > SHORTEST_STEP]] *= 0.5
        lost = missed[~(h[missed] > SHORTEST_STEP)]  # no step left: self-locking, unknown
        sigma[lost] = np.inf
        on = np.flatnonzero(sigma < 1.0)
    done = np.isfinite(sigma)
    reach[done] = tau[done] * n0[done] / qs[done]  # sign(t)·|x₀|/|x|, |y| = 1
    free = done & ~crossed
    x[free] = y[free] * (qs[free] / tau[free])[:, None]
    status[free] = 1
    return x, status, iters, reach


def _newton(a, qh, y, tau, s, on, iters, friction, jacobian):  # noqa: PLR0913  one step's state
    """Newton on A y + σ Σ g e(y) + Q̂ τ = 0, ĉ·y = 1 (ĉ = ``y``, the last point) at σ = ``s``
    from (``y``, ``tau``) at the positions ``on``, all at once, each until its step is
    below TOL, not finite, cycling (:data:`CYCLING`) or :data:`NEWTON` iterations long:
    (y, τ, converged), one row or value each; ``iters`` counts each one's iterations."""
    k, n = y.shape
    yn, tn, ok = y.copy(), tau.copy(), np.zeros(k, dtype=bool)
    live = np.arange(k)
    aug = np.zeros((k, n + 1, n + 1))
    aug[:, :n, n] = qh[on]
    aug[:, n, :n] = y  # chart ĉ = y (|y| = 1): ĉ·y = 1 at the start
    r = np.empty((k, n + 1))
    every = np.arange(k)
    for it in range(NEWTON):
        if not live.size:
            break
        rows = every if k <= FULL_ROWS else live  # evaluated: a few all, many the live
        at, yl, tl, sl = on[rows], yn[rows], tn[rows], s[rows, None]
        iters[on[live]] += 1
        with np.errstate(all="ignore"):  # the rows done may hold NaN: their values dropped
            r[rows, :n] = (
                (a[at] @ yl[..., None])[..., 0] + friction(at, yl, sl) + qh[at] * tl[:, None]
            )
            r[rows, n] = np.einsum("ij,ij->i", y[rows], yl) - 1.0
            aug[rows, :n, :n] = jacobian(at, yl, sl)
        dz, solved = _solved(aug[live], -r[live])
        good = solved & np.all(np.isfinite(dz), axis=-1)
        yl, tl = yn[live] + dz[:, :n], tn[live] + dz[:, n]
        yn[live[good]], tn[live[good]] = yl[good], tl[good]
        step, size = np.max(np.abs(dz[:, :n]), axis=-1), np.max(np.abs(yl), axis=-1)
        with np.errstate(invalid="ignore"):
            conv = good & (step <= TOL * size)
            conv &= np.abs(dz[:, n]) <= TOL * np.maximum(np.abs(tl), np.abs(tau[live]))
            cycling = (it + 1 >= CYCLING[0]) & (step > CYCLING[1] * size)
        ok[live[conv]] = True
        live = live[good & ~conv & ~cycling]
    return yn, tn, ok


def _solved(aug: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The solutions of the systems ``aug (k, n, n)`` for ``rhs (k, n)``, and where each
    was solved: LAPACK's for all at once, or, where one is exactly singular (NumPy then
    refuses the whole stack), each alone, the singular ones not solved."""
    try:
        return np.linalg.solve(aug, rhs[..., None])[..., 0], np.ones(len(aug), dtype=bool)
    except np.linalg.LinAlgError:
        out, solved = np.full(rhs.shape, np.nan), np.zeros(len(aug), dtype=bool)
        for p in range(len(aug)):
            try:
                out[p] = np.linalg.solve(aug[p], rhs[p])
                solved[p] = True
            except np.linalg.LinAlgError:
                pass
        return out, solved
