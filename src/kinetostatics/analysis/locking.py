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
from ..kinematics.events import state_near
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
    Each state is continued from the nearest row (the events' refinement).
    A zone's edge at the start or end of a run that is not a full cycle is
    None (the zone continues beyond the run).  Returns ``[{"from", "to",
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
    zones = []
    for k0 in starts:
        k1 = k0
        while (full or k1 + 1 < n) and locked[(k1 + 1) % n]:
            k1 += 1
        entry = leave = None
        if full or k0 > 0:  # between rows k0 − 1 (solved) and k0
            tb = t[k0 - 1] - (period if k0 == 0 else 0.0)
            entry = _locking_edge(result, sched, tb, t[k0], span)
        if full or k1 + 1 < n:  # between rows k1 and k1 + 1 (solved)
            ta = t[(k1 + 1) % n] + (period if k1 + 1 == n else 0.0)
            leave = _locking_edge(result, sched, ta, t[k1 % n], span)
        zones.append(
            {
                "from": None if entry is None else coord(entry),
                "to": None if leave is None else coord(leave),
                "rows": int(k1 - k0 + 1),
                "unit": unit,
            }
        )
    return zones


def _locking_edge(result, sched, t_ok, t_lock, span) -> float:
    """Time of the edge of a locked zone between a solved row and a locked one."""
    system = result.system
    period = sched.period if result.full_cycle else np.inf

    def probe(tc):
        tm = tc % period if np.isfinite(period) else tc
        try:
            q, qd, qdd = state_near(system, sched, tm, result.t, result.q, result.qd, result.qdd)
        except AssemblyError:  # no state there: no margin either
            return -1, np.nan
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            kin = kinetics(
                system,
                q,
                qd,
                qdd,
                sched(np.array([tm]))[0],
                ref_speed=sched.reference,
                extremes=result.extremes,
                friction=True,
            )
        sol = kin.friction["solution"]
        return int(sol.status[0]), float(sol.reach[0])

    tol = 1e-12 * span
    lo, hi = float(t_ok), float(t_lock)
    r_lo, r_hi = probe(lo)[1], np.nan
    solved = [(lo, r_lo)]
    last = None
    for _ in range(80):
        w = hi - lo
        cand = None
        if np.isfinite(r_lo) and np.isfinite(r_hi) and r_hi < 0.0 < r_lo:
            cand = lo + w * r_lo / (r_lo - r_hi)  # regula falsi in the bracket
        elif len(solved) >= 2:  # secant from the solved side
            (t0, r0), (t1, r1) = solved[-2], solved[-1]
            if np.isfinite(r0) and np.isfinite(r1) and r1 != r0:
                cand = t1 - r1 * (t1 - t0) / (r1 - r0)
        halving = cand is None or not 0.0 < (cand - lo) / w < 1.0
        if halving:  # no margin to go by (a fold of the branch:
            cand = lo + 0.5 * w  # the homotopy's own resolution, ~1e-9)
        if abs(w) <= (1e3 * tol if halving else tol) or (
            last is not None and abs(cand - last) <= tol
        ):
            return cand
        status, reach = probe(cand)
        if status < 0:
            return 0.5 * (lo + hi)
        if status == 2:
            hi, r_hi = cand, (reach if reach < 0.0 else np.nan)
        else:
            lo, r_lo = cand, reach
            solved.append((cand, reach))
        last = cand
    return 0.5 * (lo + hi)
