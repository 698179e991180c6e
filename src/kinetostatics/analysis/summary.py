"""The summary of a result (summary.json): formatted from what the result holds and the
cycle records its caller passes; it solves nothing.

What the rows hold is always there: the extremes of every column, the reaction peaks,
the events, the singular positions, the self-checks, and each driving effort's unit and
peak at the rows.  The cycle's quantities are stages
(:func:`~kinetostatics.dynamics.stages.cycle_stage`), each solving again between the
rows; a caller that wants them computes them and passes the record:

    cycle = cycle_stage(result)          # the means, strokes, locked zones, flywheel, drive
    summarize(result, cycle)             # summary.json as ``kinetostatics run`` writes it

Each part of the record given adds its keys: ``drivers`` (the means and RMS of the
driving efforts over the cycle), ``outputs`` (strokes and time ratios), ``self_locking``
(the locked zones' edges), ``flywheel`` and ``drive``.  This module imports nothing of the
package, so that :meth:`~kinetostatics.analysis.results.Result.summary` can call it
without an upward import.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

import numpy as np

__all__ = ["summarize", "ROUND_OFF", "CycleRecords", "driver_columns"]


class Record(Protocol):
    """A record the summary reports as it is (a flywheel design, a drive sizing)."""

    def to_dict(self) -> dict[str, Any]: ...


class CycleRecords(Protocol):
    """What :func:`summarize` reads of the cycle's records
    (:class:`~kinetostatics.dynamics.stages.Cycle`); a part that is None is left out."""

    @property
    def drivers(self) -> Mapping[str, Mapping[str, float]] | None: ...
    @property
    def outputs(self) -> Mapping[str, Any] | None: ...
    @property
    def self_locking(self) -> tuple[Mapping[str, Any], ...] | None: ...
    @property
    def flywheel(self) -> Record | None: ...
    @property
    def drive(self) -> Record | None: ...


ROUND_OFF = 1e-9
"""A value at most this times the largest |value| of its unit (among the columns) is
round-off: 0 in the extremes of summary.json and in the report's tables."""

SUFFIXES = ("", "_friction_approx", "_friction")
"""The driving effort's columns: frictionless, approximate and consistent friction."""


def _at(result, k: int) -> float:
    return float(result["angle"][k]) if "angle" in result.columns else float(result["stroke"][k])


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


def driver_columns(result) -> list[str]:
    """The driving effort columns of ``result`` whose cycle means summary.json gives
    (``<driver>.torque`` or ``.force``, without and with friction)."""
    return [
        f"{d.name}.{word}{suffix}"
        for d in result.system.motion_drivers
        for word in ("torque", "force")
        for suffix in SUFFIXES
        if f"{d.name}.{word}{suffix}" in result.columns
    ]


def _plain(value):
    """A record's read-only mappings (and tuples) as JSON's dicts and lists."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    return value


def _row_peak(values) -> float:
    """The largest |value| at the rows (NaN without a finite one)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.max(np.abs(v))) if v.size else float("nan")


def _drivers(result, stats) -> dict[str, dict[str, Any]]:
    """``{driver: {"unit", "mean", "rms", "peak", … per suffix}}`` from the cycle
    statistics ``stats`` (``{column: {"mean", "rms", "peak"}}``); without them, the unit
    and the peaks at the rows."""
    drivers = {}
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            key = f"{d.name}.{word}"
            if key not in result.columns:
                continue
            entry = {"unit": result.units[key]}
            for suffix in SUFFIXES:
                if stats is None:
                    if key + suffix in result.columns:
                        entry["peak" + suffix] = _row_peak(result[key + suffix])
                elif key + suffix in stats:
                    s = stats[key + suffix]
                    entry["mean" + suffix] = s["mean"]
                    entry["rms" + suffix] = s["rms"]
                    entry["peak" + suffix] = s["peak"]
            drivers[d.name] = entry
    return drivers


def summarize(
    result: Any, cycle: CycleRecords | None = None, *, flywheel: Record | None = None
) -> dict[str, Any]:
    """The summary of ``result`` as a JSON-safe dict (summary.json).

    Parameters
    ----------
    result : Result
        The analysis to summarise (typed ``Any`` here: :mod:`.results` imports this
        module, and an import back would be a cycle).
    cycle : Cycle, optional
        The cycle's records (:func:`~kinetostatics.dynamics.stages.cycle_stage`); each
        part it holds adds its keys (``drivers``' means and RMS, ``outputs``,
        ``self_locking``, ``flywheel``, ``drive``).  Without it, the summary holds what
        the rows hold, and nothing is solved.
    flywheel : FlywheelDesign, optional
        A flywheel design to report under ``flywheel`` (the record's, when both are
        given, is the one reported).

    Returns
    -------
    dict
        The summary; its keys in the order of summary.json.
    """
    system = result.system
    peaks = {}
    for j in system.model.joints:
        mag = np.hypot(result[f"{j.name}.Fx"], result[f"{j.name}.Fy"])
        k = int(np.argmax(np.where(np.isfinite(mag), mag, -np.inf)))  # NaN: singular rows
        peaks[j.name] = {"peak": float(mag[k]), "at": _at(result, k), "unit": "N"}
        if f"{j.name}.Fx_friction" in result.columns:
            magf = np.hypot(result[f"{j.name}.Fx_friction"], result[f"{j.name}.Fy_friction"])
            peaks[j.name]["peak_friction"] = _finite(np.max, magf)
    part = (lambda name: None) if cycle is None else (lambda name: getattr(cycle, name))
    stats = part("drivers")
    units = {"angle": "deg", "time": "s", "length": "m", "force": "N", "torque": "N*m"}
    out: dict[str, Any] = {
        "name": system.model.name,
        "positions": len(result),
        "units": units,
        "structure": {
            "mobility": system.structure.mobility,
            "groups": [p.group.label for p in system.plans],
        },
        "output": getattr(system.model, "output", None),
    }
    if part("outputs") is not None:
        out["outputs"] = _plain(part("outputs"))
    out["events"] = [
        {
            "angle": float(np.degrees(e.coordinate) % 360),
            "time": e.t,
            "load": e.load,
            "condition": e.condition,
            "switch": e.switch,
        }
        for e in result.events
    ]
    out["indeterminate_reactions"] = bool(result.indeterminate)
    if part("self_locking") is not None:
        out["self_locking"] = _plain(part("self_locking"))
    out["singular_positions"] = [
        {
            "group": s.group,
            "angle": float(np.degrees(s.coordinate) % 360),
            "time": float(s.t),
            "condition": s.condition,
        }
        for s in result.singular
    ]
    out["reaction_peaks"] = peaks
    out["drivers"] = _drivers(result, stats)
    out["extremes"] = _extremes(result)
    out["column_units"] = dict(result.units)
    out["checks"] = result.checks.to_dict()
    design = part("flywheel") if part("flywheel") is not None else flywheel
    if design is not None:
        out["flywheel"] = design.to_dict()
    if part("drive") is not None:
        out["drive"] = part("drive").to_dict()
    return out
