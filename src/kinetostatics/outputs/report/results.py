"""The results sections: the summary over the cycle (section 3), the tables at the
course-design positions (section 5: rows of results.csv to 5 significant digits) and
the flattened flywheel entry of the summary (section 9)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .blocks import _Heading, _List, _Table


# -- numbers -------------------------------------------------------------------------
def _fmt(v: float, scale: float) -> str:
    """5 significant digits; round-off below 1e-9 of the column's scale prints as 0;
    missing values (self-locking) as an empty cell."""
    if not np.isfinite(v):
        return ""
    if abs(v) <= 1e-9 * scale:
        return "0"
    return f"{v:.5g}"


def _header(result, name: str) -> str:
    unit = result.units[name].replace("*", "·").replace("^2", "²")
    return f"{name} ({unit})"


def _table(result, rows: list[tuple[str, int]], names: list[str], caption: str) -> _Table:
    names = [n for n in names if n in result.columns]
    header = ["pos.", "CSV row"] + [_header(result, n) for n in names]

    def size(n):
        v = np.abs(np.asarray(result[n], dtype=float))
        return float(np.max(v[np.isfinite(v)])) if np.any(np.isfinite(v)) else 0.0

    by_unit: dict[str, float] = {}
    for n in names:  # round-off is judged per unit, table-wide
        by_unit[result.units[n]] = max(by_unit.get(result.units[n], 0.0), size(n))
    scale = {n: by_unit[result.units[n]] for n in names}
    body = [
        [lab, str(k + 1)] + [_fmt(float(result[n][k]), scale[n]) for n in names] for lab, k in rows
    ]
    return _Table(header, body, caption)


def _distinct_points(result) -> list[str]:
    """Moving points with distinct paths: one of each pin, none at rest."""
    system = result.system
    kept: list[str] = []
    l_ref = system.l_ref
    for n in system.links:
        for p in system.model.link(n).points:
            ref = f"{n}.{p}"
            xy = np.column_stack((result[f"{ref}.x"], result[f"{ref}.y"]))
            if np.ptp(xy, axis=0).max() <= 1e-9 * l_ref:
                continue
            if any(
                np.allclose(
                    xy,
                    np.column_stack((result[f"{k}.x"], result[f"{k}.y"])),
                    rtol=0,
                    atol=1e-9 * l_ref,
                )
                for k in kept
            ):
                continue
            kept.append(ref)
    return kept


def _rotating_links(result) -> list[str]:
    return [
        n
        for n in result.system.links
        if np.max(np.abs(result[f"{n}.omega"]))
        > 1e-9 * max(1.0, abs(result.system.motion_drivers[0].driver.motion.speed))
    ]


def report_tables(result, rows: Sequence[tuple[str, int]]) -> list[_Table]:
    """The report's tables at ``rows`` ``[(label, row index)]``: positions,
    velocities, accelerations, reactions, driving torque and friction."""
    pts = _distinct_points(result)
    rot = _rotating_links(result)
    model = result.system.model
    first = (
        ["angle", "travel", "time"] if "angle" in result.columns else ["stroke", "travel", "time"]
    )
    tables = [
        _table(
            result,
            rows,
            first + [f"{n}.theta" for n in rot] + [f"{p}.{c}" for p in pts for c in ("x", "y")],
            "Positions: driver coordinate, link angles (deg, CCW from +x), points (m)",
        ),
        _table(
            result,
            rows,
            [f"{n}.omega" for n in rot] + [f"{p}.{c}" for p in pts for c in ("vx", "vy")],
            "Velocities: angular velocities (rad/s, CCW +) and point velocities (m/s)",
        ),
        _table(
            result,
            rows,
            [f"{n}.alpha" for n in rot] + [f"{p}.{c}" for p in pts for c in ("ax", "ay")],
            "Accelerations: angular accelerations (rad/s², CCW +) and point accelerations (m/s²)",
        ),
    ]
    reac = []
    for j in model.joints:
        reac += [f"{j.name}.{lab}" for lab in j.reaction_labels]
    tables.append(
        _table(
            result,
            rows,
            reac,
            "Joint reactions without friction: force of link i "
            "on link j (N); prismatic pairs also N (normal force) and M (couple, N·m)",
        )
    )
    drv = []
    for d in result.system.motion_drivers:
        for word in ("torque", "force"):
            for suffix in ("", "_friction_approx", "_friction"):
                drv.append(f"{d.name}.{word}{suffix}")
        drv.append(f"{d.name}.efficiency")
    drv += ["friction.status", "power.input", "power.friction"]
    tables.append(
        _table(
            result,
            rows,
            drv,
            "Driving effort without friction, with the approximate "
            "and the consistent friction solution, efficiency, friction status (0 "
            "converged, 1 by homotopy, 2 self-locking, 3 a relative speed is zero), "
            "input power and friction loss (W)",
        )
    )
    if model.has_friction:
        fr = []
        for j in model.joints:
            fr += [f"{j.name}.{lab}_friction" for lab in j.reaction_labels]
        tables.append(
            _table(
                result,
                rows,
                fr,
                "Joint reactions with friction (consistent "
                "solution), force of link i on link j (N)",
            )
        )
    return tables


def _summary_blocks(result, summary) -> list:
    blocks: list = [_Heading(2, "3. Results over the cycle")]
    items = [
        f"{len(result)} positions analysed (a full cycle: {'yes' if result.full_cycle else 'no'})"
    ]
    for name, o in summary["outputs"].items():
        lo, hi = o["limit_positions"]["min"], o["limit_positions"]["max"]
        if o.get("kind") == "swing":
            size = f"swing {o['swing']:.4f}° of {o['link']}"
            at = (
                f"{lo['angle']:.3f}° ({o['link']} at {lo['theta']:.3f}°) and "
                f"{hi['angle']:.3f}° ({o['link']} at {hi['theta']:.3f}°)"
            )
        else:
            size = f"stroke {o['stroke'] * 1e3:.4f} mm"
            at = f"{lo['angle']:.3f}° and {hi['angle']:.3f}°"
        items.append(
            f"output {name}: {size}, time ratio K = {o['time_ratio']:.4f}; limit positions at {at}"
        )
    for e in summary["events"]:
        items.append(
            f"event: {e['load']} switches {e['switch']} at {e['angle']:.4f}° ({e['condition']})"
        )
    for name, d in summary["drivers"].items():
        line = f"driver {name}: mean {d['mean']:.4g} {d['unit']}, peak |·| {d['peak']:.4g}"
        if "mean_friction" in d and not math.isfinite(d["mean_friction"]):
            line += (
                f"; with friction: no consistent solution at any position (self-locking; "
                f"approximate mean {d['mean_friction_approx']:.4g})"
            )
        elif "mean_friction" in d:
            line += (
                f"; with friction mean {d['mean_friction']:.4g} (approximate "
                f"{d['mean_friction_approx']:.4g}), peak {d['peak_friction']:.4g}"
            )
        items.append(line + " (over the cycle, integrated between the load events)")
    if "friction.status" in result.columns:
        locked = int(np.sum(result["friction.status"] == 2))
        if locked:
            items.append(
                f"self-locking at {locked} of {len(result)} positions (friction.status "
                "2): the consistent friction columns are empty there and the means and "
                "peaks with friction are over the other rows"
                + (" — here there are none" if locked == len(result) else "")
            )
    for sp in summary["singular_positions"]:
        items.append(
            f"singular position: {sp['group']} at {sp['angle']:.4f}° "
            f"(condition {sp['condition']:.3g})"
        )
    if summary["indeterminate_reactions"]:
        items.append("redundant constraints: reactions are the minimum-norm solution")
    blocks.append(_List(items))
    rows = [
        [n, f"{p['peak']:.5g}", f"{p['at']:.4g}", _fmt(p.get("peak_friction", math.nan), 0.0)]
        for n, p in summary["reaction_peaks"].items()
    ]
    blocks.append(
        _Table(
            [
                "joint",
                "peak |F| without friction (N)",
                "at driver coordinate (deg)",
                "peak |F| with friction (N)",
            ],
            rows,
            "Peak joint reactions",
        )
    )
    return blocks


def _flatten(d: Any, prefix: str = "") -> list[tuple[str, str]]:
    if isinstance(d, dict):
        out = []
        for k, v in d.items():
            out += _flatten(v, f"{prefix}.{k}" if prefix else str(k))
        return out
    if isinstance(d, (list, tuple)):
        if all(not isinstance(v, (dict, list, tuple)) for v in d) and len(d) <= 12:
            return [(prefix, ", ".join(_scalar(v) for v in d))]
        out = []
        for k, v in enumerate(d):
            out += _flatten(v, f"{prefix}[{k}]")
        return out
    return [(prefix, _scalar(d))]


def _scalar(v) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)
