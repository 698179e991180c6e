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

from ..analysis.cycle import Quadrature, cycle_quadrature, cycle_stats
from ..analysis.results import Result
from ..model import DriveSpec
from . import flywheel as flywheel_module
from .motor import (
    LIMIT,
    RPM,
    WHAT,
    check_lines,
    drive_warning,
    motor_torque,
    quadrant_data,
    ratio_of,
    reduce,
    shaft_curves,
)

__all__ = [  # the rows' formulas live in .motor; named here too for the old imports
    "DriveSizing",
    "LIMIT",
    "WHAT",
    "ratio_of",
    "RPM",
    "check_lines",
    "drive_warning",
    "motor_torque",
    "quadrant_data",
    "reduce",
    "size",
]


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
    nodes: Quadrature | None = None,
) -> DriveSizing:
    """The drive of ``result``'s model (``spec``: default ``drive:`` of the file) over the run.

    ``flywheel``: the model's flywheel design when the caller has it
    (:func:`~kinetostatics.dynamics.flywheel.design`), for the flywheel check's J_F.
    ``quadrature``, ``nodes``: the cycle integrator's rule and the nodes already computed,
    as for :func:`~kinetostatics.analysis.cycle.cycle_quadrature`."""
    system = result.system
    model = system.model
    spec = spec if spec is not None else model.drive
    if spec is None:
        raise ValueError("no drive: give drive: {...} in the file or spec=")
    friction = model.has_friction and bool(spec.friction is None or spec.friction)
    of, name, sense, i = shaft_curves(system, spec, friction)
    keys = ("torque", "power", "speed", "motor_torque", "motor_power", "motor_speed")
    what = {key: (lambda r, key=key: of(r)[key]) for key in keys + ("inertia_torque",)}
    quad = cycle_quadrature(result, friction=friction, quadrature=quadrature, given=nodes)
    stats = cycle_stats(result, what, friction=friction, quadrature=quadrature, given=quad)
    peak = {key: _peak(of, key, result, quad.nodes) for key in what}

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
        fw = _with_flywheel(result, spec, i, shaft, flywheel, quad)
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


def _with_flywheel(
    result: Result, spec: DriveSpec, i: float, shaft: dict, design, quad: Quadrature
) -> dict:
    """The ideal flywheel of δ (the energy method): the motor gives the constant cycle-mean
    torque, referred to the motor by :func:`reduce`; the speed reaches ω_m·(1 + δ/2); the
    flywheel the motor shaft still needs is (J_F − J_e)/i² less rotor and reduction."""
    model = result.system.model
    if design is None:
        design = flywheel_module.design(result, nodes=quad)  # looked up: tests count designs
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
