"""summary.json: strokes, time ratios, limit positions, extremes, events, peaks."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis.cycle import cycle_stats
from ..errors import AssemblyError
from ..kinematics.events import output_strokes, state_near
from ..kinematics.schedule import schedule
from ..kinetics.inverse import kinetics

__all__ = ["summarize", "output_strokes", "locking_zones", "ROUND_OFF"]

ROUND_OFF = 1e-9
"""A value at most this times the largest |value| of its unit (among the columns) is
round-off: 0 in the extremes of summary.json and in the report's tables."""


def _at(result, k: int) -> float:
    return float(result["angle"][k]) if "angle" in result.columns else float(result["stroke"][k])


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
    import warnings

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


def _finite(f, arr) -> float:
    """``f`` over the finite values of ``arr`` (the rows that have them), NaN when there are
    none (a friction column of a machine that self-locks at every position)."""
    arr = np.asarray(arr, dtype=float)
    ok = np.isfinite(arr)
    return float(f(arr[ok])) if ok.any() else float("nan")


def _extremes(result) -> dict[str, dict[str, float]]:
    """Each column's largest and smallest finite value and where (the first row) they
    occur; a column without a finite value has none.  All columns at once.

    A value within round-off of zero (``ROUND_OFF`` of the largest |value| of its unit)
    counts as 0: a fixed pivot's x, zero but for ±1e-17 m, has extremes 0 at the first
    row, not a "largest" value of 2.8e-17 m somewhere in the cycle."""
    names = list(result.columns)
    if not names or not len(result):
        return {}
    data = np.column_stack([result.columns[name] for name in names])
    finite = np.isfinite(data)
    size = np.max(np.abs(np.where(finite, data, 0.0)), axis=0)
    units = [result.units.get(name, "") for name in names]
    scale = {u: 0.0 for u in units}
    for u, m in zip(units, size.tolist()):
        scale[u] = max(scale[u], m)
    floor = ROUND_OFF * np.array([scale[u] for u in units])
    data = np.where(np.abs(data) <= floor, 0.0, data)  # NaN stays NaN
    kmax = np.argmax(np.where(finite, data, -np.inf), axis=0).tolist()
    kmin = np.argmin(np.where(finite, data, np.inf), axis=0).tolist()
    extremes = {}
    for c, name in enumerate(names):
        if finite[:, c].any():
            extremes[name] = {
                "max": float(data[kmax[c], c]),
                "at_max": _at(result, kmax[c]),
                "min": float(data[kmin[c], c]),
                "at_min": _at(result, kmin[c]),
            }
    return extremes


def summarize(result, *, flywheel=None) -> dict[str, Any]:
    """The summary of ``result``; ``flywheel``: the model's flywheel design when the caller
    has already computed it (:func:`~kinetostatics.dynamics.flywheel.design` of ``result``
    with the file's settings), so that it is not computed again."""
    system = result.system
    extremes = _extremes(result)
    peaks = {}
    for j in system.model.joints:
        mag = np.hypot(result[f"{j.name}.Fx"], result[f"{j.name}.Fy"])
        k = int(np.argmax(np.where(np.isfinite(mag), mag, -np.inf)))  # NaN: singular rows
        peaks[j.name] = {"peak": float(mag[k]), "at": _at(result, k), "unit": "N"}
        if f"{j.name}.Fx_friction" in result.columns:
            magf = np.hypot(result[f"{j.name}.Fx_friction"], result[f"{j.name}.Fy_friction"])
            peaks[j.name]["peak_friction"] = _finite(np.max, magf)
    drivers = {}
    wanted = [
        f"{d.name}.{word}{suffix}"
        for d in system.motion_drivers
        for word in ("torque", "force")
        for suffix in ("", "_friction_approx", "_friction")
        if f"{d.name}.{word}{suffix}" in result.columns
    ]
    # over the cycle, integrated exactly between the load events (analysis/cycle.py)
    stats = cycle_stats(result, wanted) if wanted and len(result) else {}
    for d in system.motion_drivers:
        for word in ("torque", "force"):
            key = f"{d.name}.{word}"
            if key not in result.columns:
                continue
            entry = {"unit": result.units[key]}
            for suffix in ("", "_friction_approx", "_friction"):
                if key + suffix in stats:
                    s = stats[key + suffix]
                    entry["mean" + suffix] = s["mean"]
                    entry["rms" + suffix] = s["rms"]
                    entry["peak" + suffix] = s["peak"]
            drivers[d.name] = entry
    units = {"angle": "deg", "time": "s", "length": "m", "force": "N", "torque": "N*m"}
    return {
        "name": system.model.name,
        "positions": len(result),
        "units": units,
        "structure": {
            "mobility": system.structure.mobility,
            "groups": [p.group.label for p in system.plans],
        },
        "output": getattr(system.model, "output", None),
        "outputs": output_strokes(result),
        "events": [
            {
                "angle": float(np.degrees(e.coordinate) % 360),
                "time": e.t,
                "load": e.load,
                "condition": e.condition,
                "switch": e.switch,
            }
            for e in result.events
        ],
        "indeterminate_reactions": bool(result.indeterminate),
        "self_locking": locking_zones(result),
        "singular_positions": [
            {
                "group": s.group,
                "angle": float(np.degrees(s.coordinate) % 360),
                "time": float(s.t),
                "condition": s.condition,
            }
            for s in result.singular
        ],
        "reaction_peaks": peaks,
        "drivers": drivers,
        "extremes": extremes,
        "column_units": dict(result.units),
        "checks": result.checks.to_dict(),
    } | _dynamics(result, flywheel)


def _dynamics(result, given=None) -> dict[str, Any]:
    """``{"flywheel": ...}`` when the model asks for it (``flywheel:``), ``{"drive": ...}``
    when it has a motor (``drive:``); ``{}`` without either (nothing more is analysed)."""
    model = result.system.model
    out: dict[str, Any] = {}
    if getattr(model, "flywheel", None) is not None:
        if given is None:
            from ..dynamics.flywheel import design

            given = design(result)
        out["flywheel"] = given.to_dict()
    if getattr(model, "drive", None) is not None:
        from ..dynamics.drive import size

        out["drive"] = size(result, flywheel=given).to_dict()
    return out
