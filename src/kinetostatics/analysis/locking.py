"""The self-locked zones of a run, their edges located (summary.json ``self_locking``).

A stage of the cycle (:mod:`~kinetostatics.dynamics.stages`): each edge is found by
solving the consistent friction solution at times between the rows, so it is computed
only when a caller asks for it (``run``, the report, a batch row), never by formatting a
summary.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..errors import AssemblyError
from ..kinematics.positions import state_at
from ..kinematics.schedule import schedule
from ..kinetics.inverse import kinetics

__all__ = ["locking_zones"]


def locking_zones(result) -> list[dict[str, Any]]:
    """The self-locked zones of the run (``friction.status`` 2), edges located.

    Each zone is a run of consecutive locked rows (cyclically on a full cycle)
    and its edges lie between its outer rows and their solved neighbours.
    There the consistent friction solution's signed margin sign(t)·|x₀|/|x|
    (``FrictionSolution.reach``: > 0 solved, → 0 as the reactions diverge at the
    edge, < 0 past it) is a smooth function of time, and the edge is its zero,
    found by regula falsi / secant steps from the solved side, bracketed by the
    status, to 1e-12 of the period (of the run's span if not a full cycle).
    Where the branch folds instead (the margin stays finite: no sign change to
    go by), the edge is bisected on the status to 1e-9 of the period, about
    the resolution of the homotopy's smallest σ step there.
    Each state is continued from the nearest row (the events' refinement);
    all the edges are searched side by side, each round one analysis of every
    edge's next time (:func:`_locking_edges`).  A zone's edge at the start or
    end of a run that is not a full cycle is None (the zone continues beyond
    the run).  Returns ``[{"from", "to",
    "rows", "unit"}]``: driver coordinates in deg (m for a prismatic driver),
    "from" the edge where the run enters the zone.
    """
    if "friction.status" not in result.columns or not len(result):
        return []
    system = result.system
    sched = schedule(system)
    order = np.argsort(result.t, kind="stable")
    locked = result["friction.status"][order] == 2
    n = len(order)
    if not locked.any():
        return []
    angular = system.motion_drivers[0].joint.angular
    unit = "deg" if angular else "m"

    def coord(t):
        c = float(sched(np.array([t]))[0][0, 0])
        return float(np.degrees(c) % 360.0) if angular else c

    if locked.all():
        return [{"from": None, "to": None, "rows": int(n), "unit": unit}]
    full = bool(result.full_cycle)
    period = sched.period if full else np.inf
    span = period if full else float(np.ptp(result.t)) or 1.0
    t = result.t[order]
    starts = [k for k in range(n) if locked[k] and not (locked[k - 1] if full or k > 0 else False)]
    zones, brackets = [], []  # brackets: (solved row's time, locked row's time) per edge
    for k0 in starts:
        k1 = k0
        while (full or k1 + 1 < n) and locked[(k1 + 1) % n]:
            k1 += 1
        entry = leave = None
        if full or k0 > 0:  # between rows k0 − 1 (solved) and k0
            entry = len(brackets)
            brackets.append((t[k0 - 1] - (period if k0 == 0 else 0.0), t[k0]))
        if full or k1 + 1 < n:  # between rows k1 and k1 + 1 (solved)
            leave = len(brackets)
            brackets.append((t[(k1 + 1) % n] + (period if k1 + 1 == n else 0.0), t[k1 % n]))
        zones.append((entry, leave, int(k1 - k0 + 1)))
    edges = _locking_edges(result, sched, brackets, span)
    return [
        {
            "from": None if a is None else coord(edges[a]),
            "to": None if b is None else coord(edges[b]),
            "rows": rows,
            "unit": unit,
        }
        for a, b, rows in zones
    ]


def _locking_edges(result, sched, brackets: list, span: float) -> list[float]:
    """The times of the edges of locked zones, each between a solved row's time and a
    locked one's (``brackets``), searched side by side: every round probes each edge's
    next time, all in one analysis, and each edge takes the steps it would take alone
    (:class:`_Edge`); at most 80 rounds."""
    tol = 1e-12 * span
    edges = [_Edge(float(ok), float(lock)) for ok, lock in brackets]
    if not edges:
        return []
    for edge, (_, reach) in zip(edges, _probe(result, sched, [e.lo for e in edges])):
        edge.r_lo, edge.solved = reach, [(edge.lo, reach)]
    for _ in range(80):
        asked = [(e, c) for e in edges if e.found is None and (c := e.next(tol)) is not None]
        if not asked:
            break
        for (edge, c), (status, reach) in zip(asked, _probe(result, sched, [c for _, c in asked])):
            edge.took(c, status, reach)
    return [0.5 * (e.lo + e.hi) if e.found is None else e.found for e in edges]


def _probe(result, sched, times: list) -> list[tuple[int, float]]:
    """(friction status, signed margin ``reach``) of the consistent friction solution at
    ``times``, each state continued from its nearest row (the events' refinement); (−1,
    NaN) where no state is found."""
    system, period = result.system, sched.period if result.full_cycle else np.inf
    tm = np.mod(times, period) if np.isfinite(period) else np.asarray(times, dtype=float)
    near = np.argmin(np.abs(result.t[None, :] - tm[:, None]), axis=1)
    try:
        q, qd, qdd = state_at(
            system, sched, tm, result.t[near], result.q[near], result.qd[near], result.qdd[near]
        )
    except AssemblyError:  # no state at one of them: each alone, (−1, NaN) where none
        if len(times) == 1:
            return [(-1, np.nan)]
        return [_probe(result, sched, [t])[0] for t in times]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kin = kinetics(
            system,
            q,
            qd,
            qdd,
            sched(tm)[0],
            ref_speed=sched.reference,
            extremes=result.extremes,
            friction=True,
        )
    sol = kin.friction["solution"]
    return list(zip(np.asarray(sol.status).tolist(), np.asarray(sol.reach).tolist()))


class _Edge:
    """One edge's search between ``lo`` (solved) and ``hi`` (locked): regula falsi in the
    bracket where the margin changes sign, else secant steps from the solved side, else
    bisection on the status (a fold of the branch: the homotopy's own resolution, ~1e-9),
    to ``tol`` (1e3 ``tol`` bisecting)."""

    def __init__(self, lo: float, hi: float):
        self.lo, self.hi, self.r_lo, self.r_hi = lo, hi, np.nan, np.nan
        self.solved: list[tuple[float, float]] = []
        self.last: float | None = None
        self.found: float | None = None

    def next(self, tol: float) -> float | None:
        """The next time to probe, or None with ``found`` set (the edge is located)."""
        lo, w, r_lo, r_hi = self.lo, self.hi - self.lo, self.r_lo, self.r_hi
        cand = None
        if np.isfinite(r_lo) and np.isfinite(r_hi) and r_hi < 0.0 < r_lo:
            cand = lo + w * r_lo / (r_lo - r_hi)  # regula falsi in the bracket
        elif len(self.solved) >= 2:  # secant from the solved side
            (t0, r0), (t1, r1) = self.solved[-2], self.solved[-1]
            if np.isfinite(r0) and np.isfinite(r1) and r1 != r0:
                cand = t1 - r1 * (t1 - t0) / (r1 - r0)
        halving = cand is None or not 0.0 < (cand - lo) / w < 1.0
        if halving:  # no margin to go by
            cand = lo + 0.5 * w
        if abs(w) <= (1e3 * tol if halving else tol) or (
            self.last is not None and abs(cand - self.last) <= tol
        ):
            self.found = cand
            return None
        return cand

    def took(self, cand: float, status: int, reach: float) -> None:
        """The probe at ``cand`` gave ``status`` and ``reach``."""
        if status < 0:  # no state there: the bracket's middle
            self.found = 0.5 * (self.lo + self.hi)
        elif status == 2:
            self.hi, self.r_hi = cand, (reach if reach < 0.0 else np.nan)
        else:
            self.lo, self.r_lo = cand, reach
            self.solved.append((cand, reach))
        self.last = cand
