"""Model -> YAML text (SI): the writer, whose output reads back to an equal model."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import yaml

from ..model import Condition, EffortLaw, Element, Load, Model

__all__ = ["dump"]


def _effort_spec(law: EffortLaw) -> dict[str, Any]:
    if law.kind == "constant":
        return law.value
    if law.kind == "motor":
        return {"motor": {"torque": law.value, "speed": law.speed, "slip": law.slip}}
    keys = ("at", "value") if law.kind == "table" else ("speed", "torque")
    return {law.kind: {keys[0]: list(law.at), keys[1]: list(law.values)}}


def _element_spec(e: Element) -> dict[str, Any]:
    """An element's keys in SI (rad for angles; io/elements.py reads them back)."""
    spec: dict[str, Any] = {"type": e.kind}
    if e.rotational:
        spec["joint"] = e.joint
    else:
        spec["between"] = [f"{link}.{point}" for link, point in zip(e.links, e.points)]
    if not e.spring:
        spec["damping"] = float(e.damping)
    elif e.table is not None:
        s_key, f_key = ("angle", "torque") if e.rotational else ("length", "force")
        spec["table"] = {
            s_key: [float(v) for v in e.table[0]],
            f_key: [float(v) for v in e.table[1]],
        }
    else:
        spec["stiffness"] = float(e.stiffness)
        spec["free_angle" if e.rotational else "free_length"] = float(e.free)
        spec["preload"] = float(e.preload)
    return spec


def _floats(a) -> float | list:
    """An array's numbers as YAML numbers (nested lists; a float for a scalar)."""
    return np.asarray(a, dtype=float).tolist()


def _condition_spec(c: Condition) -> dict[str, Any]:
    """An ``active:`` condition in SI; its point written out (the load's, when it had none)."""
    if c.kind == "angle":
        return {"angle": _floats(c.bounds)}
    spec: dict[str, Any] = (
        {"moving": _floats(c.axis)}
        if c.kind == "moving"
        else {"travel": _floats(c.bounds), "along": _floats(c.axis)}
    )
    spec["point"] = f"{c.link}.{c.point}" if c.point else c.link
    return spec


def _load_spec(load: Load) -> dict[str, Any]:
    """A load's keys in SI (io/loads.py reads them back)."""
    spec: dict[str, Any] = {"type": load.kind, "link": load.link}
    if load.table is None:
        spec["value"] = _floats(load.value)
    else:
        spec["table"] = {"at": _floats(load.table[0]), "value": _floats(load.table[1])}
    if load.point is not None:
        spec["point"] = load.point
    if load.axis is not None:
        spec["axis"] = _floats(load.axis)
    if load.joint is not None:
        spec["joint"] = load.joint
    if load.active:
        spec["active"] = [_condition_spec(c) for c in load.active]
    return spec


def dump(model: Model) -> str:
    """The model as YAML text in SI (a round trip through :func:`loads` gives an equal model:
    every field but ``parameters`` and ``units``, whose values are written evaluated, in SI).

    A model expanded with clearances is written as its ideal model plus the
    ``clearance:`` section that expands it again (a model as read, not yet expanded,
    is written the same way).
    """
    if model.ideal is not None or model.clearances:  # expanded, or as read (io.read)
        base = model.ideal if model.ideal is not None else replace(model, clearances=())
        doc = yaml.safe_load(dump(base))
        doc["clearance"] = {}
        for c in model.clearances:
            spec = {
                "size": c.size,
                "model": c.model,
                "speed": c.speed,
                "acceleration": c.acceleration,
            }
            if c.angle is not None:
                spec["angle"] = c.angle
            if c.contact is not None:
                law = c.contact
                spec["contact"] = {
                    "journal_radius": law.journal_radius,
                    "young": list(law.young),
                    "poisson": list(law.poisson),
                    "restitution": law.restitution,
                    "floor": law.floor,
                    **({"stiffness": law.stiffness} if law.stiffness else {}),
                }
            doc["clearance"][c.joint] = spec
        return yaml.safe_dump(doc, sort_keys=False)
    doc: dict[str, Any] = {
        "name": model.name,
        "gravity": [float(g) for g in model.gravity],
        "ground": model.ground.name,
        "links": {},
        "joints": {},
    }
    for link in model.links:
        spec: dict[str, Any] = {
            "points": {k: [float(c) for c in v + link.com] for k, v in link.points.items()}
        }
        if not link.ground:
            spec.update(mass=link.mass, inertia=link.inertia, com=[float(c) for c in link.com])
        if link.number is not None:
            spec["number"] = link.number
        doc["links"][link.name] = spec
    for j in model.joints:
        doc["joints"][j.name] = {"type": j.kind, "links": list(j.links), **j.to_spec()}
    if model.sizing is not None:
        _sizing_specs(model.sizing, doc)
    if model.drivers:
        doc["drivers"] = {}
        for d in model.drivers:
            spec = {"joint": d.joint}
            if d.motion is not None:
                spec["motion"] = d.motion.to_spec()
            if isinstance(d.effort, EffortLaw):
                spec["effort"] = _effort_spec(d.effort)
            elif d.effort is not None:
                spec["effort"] = d.effort
            if d.points != (None, None):
                spec["points"] = [p or "x" for p in d.points]
            if d.balance_at:
                spec["balance_at"] = d.balance_at
            doc["drivers"][d.name] = spec
    if model.loads:
        doc["loads"] = {load.name: _load_spec(load) for load in model.loads}
    if model.elements:
        doc["elements"] = {e.name: _element_spec(e) for e in model.elements}
    if model.sketch:
        doc["sketch"] = {k: [float(c) for c in v] for k, v in model.sketch.items()}
    a = model.analysis
    motion = [d for d in model.drivers if d.motion is not None]
    if motion and motion[0].motion.own_run:  # the law fixes start and span
        doc["analysis"] = {"positions": a.positions, "events": a.events}
    else:
        doc["analysis"] = {
            "start": a.start,
            "sweep": a.sweep,
            "positions": a.positions,
            "at": list(a.at),
            "events": a.events,
        }
    if model.loops is not None:
        doc["loops"] = [list(loop) for loop in model.loops]
    if model.flywheel is not None:
        f = model.flywheel
        doc["flywheel"] = {
            "delta": f.delta,
            "friction": f.friction,
            **({"ratio": f.ratio} if f.ratio is not None else {}),
        }
    if getattr(model, "drive", None) is not None:
        doc["drive"] = _drive_spec(model.drive)
    if getattr(model, "output", None) is not None:
        doc["output"] = model.output
    return yaml.safe_dump(doc, sort_keys=False)


def _sizing_specs(sizing, doc: dict) -> None:
    """The sizing keys of the links and joints (docs/sizing.md), in SI, into ``doc``."""

    def given(**values):
        return {k: v for k, v in values.items() if v is not None}

    for name, b in sizing.bearings.items():
        doc["joints"][name]["bearing"] = given(
            type=b.kind, C=b.C, width=b.width, diameter=b.diameter,
            p_max=b.p_max, v_max=b.v_max, pv_max=b.pv_max,
        )  # fmt: skip
    for name, p in sizing.pins.items():
        pin = given(diameter=p.diameter, shear=p.shear, eye_width=p.eye_width)
        doc["joints"][name]["pin"] = pin
    for name, sec in sizing.sections.items():
        doc["links"][name]["section"] = {"shape": sec.shape, **dict(sec.dimensions)}
    for name, m in sizing.materials.items():
        doc["links"][name]["material"] = given(S_ut=m.S_ut, S_y=m.S_y, S_e=m.S_e)


def _drive_spec(d) -> dict:
    """``drive:`` in SI (the dump writes SI units)."""
    out: dict = {}
    if d.driver is not None:
        out["driver"] = d.driver
    if d.friction is not None:
        out["friction"] = bool(d.friction)
    red = {"efficiency": d.efficiency, "inertia": d.gear_inertia}
    if d.ratio is not None:
        red = {"ratio": d.ratio, **red}
    out["reduction"] = red
    motor = {"inertia": d.motor_inertia}
    for key in ("rated_torque", "peak_torque", "rated_speed"):
        if getattr(d, key) is not None:
            motor[key] = getattr(d, key)
    out["motor"] = motor
    return out
