"""summary.json: strokes, time ratios, limit positions, extremes, events, peaks."""

from __future__ import annotations

from typing import Any

import numpy as np

from .joints import Prismatic

__all__ = ["summarize", "output_strokes"]


def _at(result, k: int) -> float:
    return float(result["angle"][k]) if "angle" in result.columns else float(result["stroke"][k])


def output_strokes(result) -> dict[str, dict[str, Any]]:
    """Stroke, limit positions and time ratio of every undriven prismatic pair.

    Limit positions are the exact zeros of the sliding speed (the events
    machinery refines them); the time ratio K is the slower stroke's time
    over the faster's, from those exact positions (full cycles only).
    """
    system = result.system
    out: dict[str, dict[str, Any]] = {}
    driven = {d.joint.name for d in system.motion_drivers}
    if not result.full_cycle or "angle" not in result.columns:
        return out
    for k, j in enumerate(system.model.joints):
        if not isinstance(j, Prismatic) or j.name in driven:
            continue
        from .system import coordinate_gradient
        s = _coordinate(system, result.q, k)
        ds = np.einsum("...n,...n->...", coordinate_gradient(system, result.q, k), result.qd)
        from .analysis import _find_roots, _schedule
        sched = _schedule(system)
        period = sched.period

        def f(q, qd, qdd, k=k):
            g = coordinate_gradient(system, q, k)
            return (np.einsum("...n,...n->...", g, qd),
                    np.einsum("...n,...n->...", g, qdd) + _bias(system, q, qd, k))

        roots, (qr, _, _) = _find_roots(system, sched, result.t, result.q, result.qd, result.qdd,
                                        ds, f, True, period)
        if len(roots) != 2:
            continue
        vals = [float(v) for v in _coordinate(system, qr, k)]
        lo, hi = (0, 1) if vals[0] < vals[1] else (1, 0)
        t_up = (roots[hi] - roots[lo]) % period           # from the low to the high extreme
        t_down = period - t_up
        coord = lambda r: float(np.degrees(sched(np.array([r]))[0][0, 0]) % 360.0)
        out[j.name] = {
            "stroke": vals[hi] - vals[lo],
            "limit_positions": {"min": {"angle": coord(roots[lo]), "s": vals[lo]},
                                "max": {"angle": coord(roots[hi]), "s": vals[hi]}},
            "time_ratio": max(t_up, t_down) / min(t_up, t_down),
            "time_increasing_s": t_up, "time_decreasing_s": t_down,
        }
        del s
    return out


def _coordinate(system, q, k):
    qe = np.concatenate((q, np.zeros(q.shape[:-1] + (3,))), axis=-1)
    i, j = system.ends[k]
    return system.constraints[k].coordinate(qe[..., 3 * i:3 * i + 3], qe[..., 3 * j:3 * j + 3])


def _bias(system, q, qd, k):
    qe = np.concatenate((q, np.zeros(q.shape[:-1] + (3,))), axis=-1)
    ve = np.concatenate((qd, np.zeros(qd.shape[:-1] + (3,))), axis=-1)
    i, j = system.ends[k]
    return system.constraints[k].coordinate_bias(qe[..., 3 * i:3 * i + 3], qe[..., 3 * j:3 * j + 3],
                                                  ve[..., 3 * i:3 * i + 3], ve[..., 3 * j:3 * j + 3])


def _finite(f, arr) -> float:
    """``f`` over the finite values of ``arr`` (the rows that have them), NaN when there are
    none (a friction column of a machine that self-locks at every position)."""
    arr = np.asarray(arr, dtype=float)
    ok = np.isfinite(arr)
    return float(f(arr[ok])) if ok.any() else float("nan")


def summarize(result) -> dict[str, Any]:
    system = result.system
    extremes = {}
    for name, arr in result.columns.items():
        finite = np.isfinite(arr)
        if not finite.any():
            continue
        kmax = int(np.nanargmax(np.where(finite, arr, -np.inf)))
        kmin = int(np.nanargmin(np.where(finite, arr, np.inf)))
        extremes[name] = {"max": float(arr[kmax]), "at_max": _at(result, kmax),
                          "min": float(arr[kmin]), "at_min": _at(result, kmin)}
    peaks = {}
    for j in system.model.joints:
        mag = np.hypot(result[f"{j.name}.Fx"], result[f"{j.name}.Fy"])
        k = int(np.argmax(mag))
        peaks[j.name] = {"peak": float(mag[k]), "at": _at(result, k), "unit": "N"}
        if f"{j.name}.Fx_friction" in result.columns:
            magf = np.hypot(result[f"{j.name}.Fx_friction"], result[f"{j.name}.Fy_friction"])
            peaks[j.name]["peak_friction"] = _finite(np.max, magf)
    drivers = {}
    for d in system.motion_drivers:
        for word in ("torque", "force"):
            key = f"{d.name}.{word}"
            if key not in result.columns:
                continue
            entry = {"unit": result.units[key]}
            for suffix in ("", "_friction_approx", "_friction"):
                if key + suffix in result.columns:
                    arr = result[key + suffix]
                    entry["mean" + suffix] = _finite(np.mean, arr)
                    entry["peak" + suffix] = _finite(np.max, np.abs(arr))
            drivers[d.name] = entry
    units = {"angle": "deg", "time": "s", "length": "m", "force": "N", "torque": "N*m"}
    return {
        "name": system.model.name,
        "positions": len(result),
        "units": units,
        "structure": {"mobility": system.structure.mobility,
                      "groups": [p.group.label for p in system.plans]},
        "outputs": output_strokes(result),
        "events": [{"angle": float(np.degrees(e.coordinate) % 360), "time": e.t, "load": e.load,
                    "condition": e.condition, "switch": e.switch} for e in result.events],
        "indeterminate_reactions": bool(result.indeterminate),
        "singular_positions": [{"group": s.group, "angle": float(np.degrees(s.coordinate) % 360),
                                "time": float(s.t),
                                "condition": s.condition} for s in result.singular],
        "reaction_peaks": peaks,
        "drivers": drivers,
        "extremes": extremes,
        "column_units": dict(result.units),
    } | _flywheel(result)


def _flywheel(result) -> dict[str, Any]:
    """``{"flywheel": ...}`` when the model asks for it (``flywheel:``), else ``{}``."""
    if getattr(result.system.model, "flywheel", None) is None:
        return {}
    from .flywheel import design
    return {"flywheel": design(result).to_dict()}
