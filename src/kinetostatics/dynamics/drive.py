"""Drive sizing: the torque, speed and power a motor sees over the cycle, through a reduction,
and the check of a motor's ratings against them (docs/drive.md).

Signs: every quantity here is in the **sense of motion** of the driven joint (the sign of
its nominal speed; for a motion law, of the law's reference speed): the driven shaft turns
at ω = s·ψ̇ and takes the torque T = s·τ (τ the driver's torque column, ``<driver>.torque``
or ``<driver>.torque_friction``), so that its power P = T·ω = τ·ψ̇ > 0 where the motor
drives the machine (motoring) and < 0 where the machine drives the motor back (braking).

The reduction (ratio i = motor speed / driven shaft speed, efficiency η in both power
directions, its inertia J_r referred to the motor shaft) and the rotor (J_m):

    ω_M = i·ω
    T_M = T/(i·η)            where P ≥ 0 (the motor delivers power: the losses add to it)
    T_M = T·η/i              where P < 0 (power flows back: the losses take from it)
          + (J_m + J_r)·i·α  (the inertia of rotor and reduction, α = s·ψ̈ of the driven shaft)

At P = 0 with T ≠ 0 (the shaft at rest, a holding torque) the first line holds.  The means,
RMS values of the cycle come from :func:`~kinetostatics.analysis.cycle.cycle_stats` (exact
between the load events); the peaks are the largest |value| at the analysed rows and at its
quadrature nodes.

Two checks: **rigid** (the motor follows the kinetostatic torque at the nominal speed) and,
when the file has ``flywheel:``, **with flywheel** (the energy method's ideal flywheel of
δ: the motor gives the constant mean torque of the cycle, referred by the rule above, the
rotor and the reduction turn with the speed fluctuation and are part of the flywheel, and
the motor speed reaches i·ω_m·(1 + δ/2)).  The verdict is the flywheel check's when the
file has a flywheel, the rigid one's otherwise.  The rules: RMS torque ≤ rated torque,
peak |torque| ≤ peak torque, largest |speed| ≤ rated speed; a rating not given is not
checked.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis.cycle import cycle_nodes, cycle_stats
from ..analysis.results import Result
from ..errors import Location, StructureError
from ..kinematics.schedule import schedule
from ..model import DriveSpec
from .flywheel import design as flywheel_design

__all__ = [
    "DriveSizing",
    "RPM",
    "check_lines",
    "drive_warning",
    "motor_torque",
    "quadrant_data",
    "reduce",
    "size",
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


def _driver(system, spec: DriveSpec):
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


def _curves(system, spec: DriveSpec, friction: bool):
    """A function Result -> dict of arrays over its rows: the driven shaft's ``torque``,
    ``speed``, ``acceleration``, ``power`` and the motor's ``motor_torque``,
    ``motor_speed``, ``motor_power``, ``inertia_torque``."""
    d, k = _driver(system, spec)
    sched = schedule(system)
    sense = 1.0 if sched.speed[k] >= 0 else -1.0
    column = f"{d.name}.torque_friction" if friction else f"{d.name}.torque"
    i = ratio_of(system.model)
    memo: dict[int, tuple[Result, dict]] = {}

    def of(r: Result) -> dict[str, np.ndarray]:
        if id(r) in memo and memo[id(r)][0] is r:
            return memo[id(r)][1]
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
        memo[id(r)] = (r, out)
        return out

    return of, d.name, sense, i


@dataclass(frozen=True)
class DriveSizing:
    """The drive's numbers over the cycle and the motor check (:func:`size`)."""

    spec: DriveSpec
    driver: str
    sense: float
    ratio: float
    friction: bool
    shaft: dict  # torque {mean, rms, peak}, power {mean, peak}, speed {max}
    motor: dict  # the same at the motor, and inertia_torque {rms, peak}
    covered: float  # the part of the cycle where the torque exists (self-locking: < 1)
    flywheel: dict | None = None  # the ideal-flywheel numbers at the motor
    checks: dict = field(default_factory=dict)  # {"rigid": ..., "flywheel": ...}
    verdict_from: str = "rigid"

    @property
    def verdict(self) -> str:
        return self.checks[self.verdict_from]["verdict"]

    def warning(self) -> str | None:
        """One line naming what the motor lacks, None when it is not undersized."""
        return drive_warning(self.to_dict())

    def to_dict(self) -> dict[str, Any]:
        s = self.spec
        return {
            "driver": self.driver,
            "sense": "ccw" if self.sense > 0 else "cw",
            "torque": "with friction (consistent)" if self.friction else "frictionless",
            "reduction": {
                "ratio": self.ratio,
                "efficiency": s.efficiency,
                "inertia": s.gear_inertia,
            },
            "motor_data": {
                "inertia": s.motor_inertia,
                "rated_torque": s.rated_torque,
                "peak_torque": s.peak_torque,
                "rated_speed": s.rated_speed,
            },
            "shaft": self.shaft,
            "motor": self.motor,
            "covered": self.covered,
            "flywheel": self.flywheel,
            "checks": self.checks,
            "verdict_from": self.verdict_from,
            "verdict": self.verdict,
            "units": {
                "torque": "N*m",
                "power": "W",
                "speed": "rad/s",
                "speed_rpm": "rpm",
                "inertia": "kg*m^2",
                "rated_speed": "rad/s",
            },
        }


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


def _check(rms: float, peak: float, speed: float, spec: DriveSpec) -> dict[str, Any]:
    items = {}
    for key, value, limit in (
        ("rms_torque", rms, spec.rated_torque),
        ("peak_torque", peak, spec.peak_torque),
        ("speed", speed, spec.rated_speed),
    ):
        ok = None if limit is None or not np.isfinite(value) else bool(value <= limit)
        items[key] = {"value": float(value), "limit": limit, "ok": ok}
    oks = [it["ok"] for it in items.values()]
    if any(ok is False for ok in oks):
        verdict = "undersized"
    elif all(ok is None for ok in oks):
        verdict = "not checked"
    else:
        verdict = "adequate"
    return {"items": items, "verdict": verdict}


def _peak(of, key: str, result: Result, nodes: Result) -> float:
    """The largest finite |value| at the rows and at the quadrature nodes."""
    vals = np.concatenate([np.abs(of(result)[key]), np.abs(of(nodes)[key])])
    vals = vals[np.isfinite(vals)]
    return float(np.max(vals)) if vals.size else float("nan")


def size(
    result: Result,
    spec: DriveSpec | None = None,
    *,
    flywheel=None,
    quadrature: tuple[int, int] | None = None,
) -> DriveSizing:
    """The drive of ``result``'s model (``spec``: default ``drive:`` of the file) over the run.

    ``flywheel``: the model's flywheel design when the caller has it
    (:func:`~kinetostatics.dynamics.flywheel.design`), for the flywheel check's J_F.
    ``quadrature``: the cycle integrator's (nodes, pieces), another than the default only
    to check that the means have converged (:func:`~kinetostatics.analysis.cycle.cycle_nodes`)."""
    system = result.system
    model = system.model
    spec = spec if spec is not None else model.drive
    if spec is None:
        raise ValueError("no drive: give drive: {...} in the file or spec=")
    friction = bool(model.has_friction if spec.friction is None else spec.friction)
    friction = friction and model.has_friction
    of, name, sense, i = _curves(system, spec, friction)
    keys = ("torque", "power", "speed", "motor_torque", "motor_power", "motor_speed")
    what = {key: (lambda r, key=key: of(r)[key]) for key in keys + ("inertia_torque",)}
    stats = cycle_stats(result, what, friction=friction, quadrature=quadrature)
    _, nodes = cycle_nodes(result, friction=friction, quadrature=quadrature)
    peak = {key: _peak(of, key, result, nodes) for key in what}

    def side(prefix: str) -> dict:
        t, p, w = (prefix + x for x in ("torque", "power", "speed"))
        return {
            "torque": {"mean": stats[t]["mean"], "rms": stats[t]["rms"], "peak": peak[t]},
            "power": {"mean": stats[p]["mean"], "peak": peak[p]},
            "speed": {"max": peak[w], "max_rpm": peak[w] * RPM, "mean": stats[w]["mean"]},
        }

    shaft, motor = side(""), side("motor_")
    motor["inertia_torque"] = {
        "rms": stats["inertia_torque"]["rms"],
        "peak": peak["inertia_torque"],
    }
    checks = {
        "rigid": _check(motor["torque"]["rms"], motor["torque"]["peak"], peak["motor_speed"], spec)
    }
    fw = None
    if model.flywheel is not None:
        fw = _with_flywheel(result, spec, i, shaft, flywheel)
        checks["flywheel"] = _check(abs(fw["torque"]), abs(fw["torque"]), fw["speed_max"], spec)
    return DriveSizing(
        spec=spec,
        driver=name,
        sense=sense,
        ratio=i,
        friction=friction,
        shaft=shaft,
        motor=motor,
        covered=float(stats["torque"]["covered"]),
        flywheel=fw,
        checks=checks,
        verdict_from="flywheel" if fw is not None else "rigid",
    )


def _with_flywheel(result: Result, spec: DriveSpec, i: float, shaft: dict, design) -> dict:
    """The ideal flywheel of δ (the energy method): the motor gives the constant cycle-mean
    torque, referred to the motor by :func:`reduce`; the speed reaches ω_m·(1 + δ/2); the
    flywheel the motor shaft still needs is (J_F − J_e)/i² less rotor and reduction."""
    model = result.system.model
    if design is None:
        design = flywheel_design(result)
    delta = float(model.flywheel.delta)
    omega = float(design.omega_m)
    mean = float(shaft["torque"]["mean"])
    tm = float(reduce(mean, 1.0, i, spec.efficiency))
    top = i * omega * (1.0 + 0.5 * delta)
    net = float(design.inertia_net) / i**2
    return {
        "delta": delta,
        "torque": tm,
        "rms": abs(tm),
        "peak": abs(tm),
        "speed_max": top,
        "speed_max_rpm": top * RPM,
        "power_mean": tm * i * omega,
        "power_peak": abs(tm) * top,
        "inertia_motor_net": net,
        "inertia_rotor": spec.motor_inertia + spec.gear_inertia,
        "inertia_to_add": net - (spec.motor_inertia + spec.gear_inertia),
    }


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
        and f"{_driver(system, spec)[0].name}.torque_friction" in result.columns
    )
    of, name, sense, i = _curves(system, spec, friction)
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
