"""The drive's quantities at given rows: the shaft and the motor through the reduction.

Formulas over the rows of a result (no cycle, nothing solved): the load torque through a
reduction (:func:`reduce`), the motor's torque with its inertia (:func:`motor_torque`),
the shaft's and motor's curves of a result (:func:`shaft_curves`), the four-quadrant
picture's data (:func:`quadrant_data`) and the check's words (:func:`check_lines`,
:func:`drive_warning`).  The cycle's sizing that uses them is :mod:`.drive`; the report
and the pictures read them from here (they may not import a solver).  Signs and the
reduction's rule: docs/drive.md and :mod:`.drive`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis.results import Result
from ..errors import Location, StructureError
from ..kinematics.schedule import schedule
from ..model import DriveSpec

__all__ = [
    "LIMIT",
    "RPM",
    "WHAT",
    "check_lines",
    "drive_driver",
    "drive_warning",
    "motor_torque",
    "quadrant_data",
    "ratio_of",
    "reduce",
    "shaft_curves",
]

RPM = 30.0 / np.pi  # rad/s -> rpm


def reduce(torque, speed, ratio: float = 1.0, efficiency: float = 1.0) -> np.ndarray:
    """The load torque of a driven shaft (``torque``, ``speed`` in one sense) at the motor
    through a reduction: T/(i·η) where the shaft takes power (T·ω ≥ 0), T·η/i where it gives
    it back (T·ω < 0)."""
    torque = np.asarray(torque, dtype=float)
    back = torque * np.asarray(speed, dtype=float) < 0.0
    return np.where(back, torque * efficiency / ratio, torque / (ratio * efficiency))


def motor_torque(torque, speed, acceleration, spec: DriveSpec, ratio: float) -> np.ndarray:
    """The motor's torque: :func:`reduce` plus the inertia of rotor and reduction,
    (J_m + J_r)·i·α."""
    inertia = spec.motor_inertia + spec.gear_inertia
    return reduce(torque, speed, ratio, spec.efficiency) + inertia * ratio * np.asarray(
        acceleration, dtype=float
    )


def drive_driver(system, spec: DriveSpec):
    """(the motion driver a drive turns, its index): ``drive.driver``, else the first."""
    drivers = system.motion_drivers
    chosen = [d for d in drivers if spec.driver in (None, d.name)]
    if not chosen or not chosen[0].joint.angular:
        raise StructureError(
            [
                (
                    Location(system.model.source, path="drive"),
                    "a drive needs a revolute motion driver",
                )
            ]
        )
    d = chosen[0]
    return d, drivers.index(d)


def ratio_of(model) -> float:
    """i: ``drive.reduction.ratio``, else ``flywheel.ratio``, else 1."""
    spec = model.drive
    if spec is not None and spec.ratio is not None:
        return float(spec.ratio)
    if model.flywheel is not None and model.flywheel.ratio is not None:
        return float(model.flywheel.ratio)
    return 1.0


def shaft_curves(system, spec: DriveSpec, friction: bool):
    """A function Result -> dict of arrays over its rows: the driven shaft's ``torque``,
    ``speed``, ``acceleration``, ``power`` and the motor's ``motor_torque``,
    ``motor_speed``, ``motor_power``, ``inertia_torque``."""
    d, k = drive_driver(system, spec)
    sched = schedule(system)
    sense = 1.0 if sched.speed[k] >= 0 else -1.0
    column = f"{d.name}.torque_friction" if friction else f"{d.name}.torque"
    i = ratio_of(system.model)

    def of(r: Result) -> dict[str, np.ndarray]:
        _, psi_d, psi_dd = sched(np.asarray(r.t, dtype=float))
        w, a = sense * psi_d[..., k], sense * psi_dd[..., k]
        t = sense * np.asarray(r[column], dtype=float)
        tm = motor_torque(t, w, a, spec, i)
        out = {
            "torque": t,
            "speed": w,
            "acceleration": a,
            "power": t * w,
            "motor_torque": tm,
            "motor_speed": i * w,
            "motor_power": tm * i * w,
            "inertia_torque": (spec.motor_inertia + spec.gear_inertia) * i * a,
        }
        return out

    return of, d.name, sense, i


WHAT = {"rms_torque": "RMS torque", "peak_torque": "peak torque", "speed": "speed"}
LIMIT = {"rms_torque": "rated torque", "peak_torque": "peak torque rating", "speed": "rated speed"}


def _item_text(key: str, item: dict) -> str:
    """``RMS torque 1.07 N*m <= rated torque 1.6 N*m`` (speeds in rpm)."""
    scale, unit = (RPM, "rpm") if key == "speed" else (1.0, "N*m")
    text = f"{WHAT[key]} {item['value'] * scale:.4g} {unit}"
    if item["ok"] is None:
        return text + " (not checked)"
    sign = "<=" if item["ok"] else ">"
    return text + f" {sign} {LIMIT[key]} {item['limit'] * scale:.4g} {unit}"


def check_lines(d: dict) -> list[str]:
    """The checks of a drive's summary entry as lines: one per check, the verdict's marked."""
    lines = []
    for name, c in d["checks"].items():
        how = (
            "rigid drive" if name == "rigid" else f"with flywheel, delta {d['flywheel']['delta']:g}"
        )
        items = "; ".join(_item_text(k, it) for k, it in c["items"].items())
        mark = " (the verdict)" if name == d["verdict_from"] else ""
        lines.append(f"drive check ({how}): {items}: {c['verdict']}{mark}")
    return lines


def drive_warning(d: dict) -> str | None:
    """One line naming what the motor of a drive's summary entry lacks; None when the
    verdict is not ``undersized``."""
    c = d["checks"][d["verdict_from"]]
    if c["verdict"] != "undersized":
        return None
    parts = [_item_text(k, it) for k, it in c["items"].items() if it["ok"] is False]
    how = "with the flywheel" if d["verdict_from"] == "flywheel" else "rigid drive"
    return f"drive '{d['driver']}': motor undersized ({how}): " + "; ".join(parts)


def quadrant_data(result: Result, spec: DriveSpec | None = None) -> dict[str, Any]:
    """The four-quadrant picture's data over the rows (in time order): motor ``speed``
    (rpm) and ``torque`` (N·m) in the sense of motion, and the ratings (rpm, N·m; None
    when not given)."""
    system = result.system
    model = system.model
    spec = spec if spec is not None else model.drive
    friction = bool(model.has_friction if spec.friction is None else spec.friction)
    friction = (
        friction
        and model.has_friction
        and f"{drive_driver(system, spec)[0].name}.torque_friction" in result.columns
    )
    of, name, sense, i = shaft_curves(system, spec, friction)
    order = np.argsort(result.t, kind="stable")
    c = of(result)
    return {
        "driver": name,
        "speed": c["motor_speed"][order] * RPM,
        "torque": c["motor_torque"][order],
        "rated_torque": spec.rated_torque,
        "peak_torque": spec.peak_torque,
        "rated_speed": None if spec.rated_speed is None else spec.rated_speed * RPM,
        "friction": friction,
        "ratio": i,
    }
