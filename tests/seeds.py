"""Seed files for the fuzz test and the key walk: the shipped mechanisms plus variants of
them that use every section and option the loader accepts (motion laws, effort drivers,
``balance_at``, a flywheel with ``ratio``, a drive, clearances with contact, load tables and
conditions, the gear and rack alternatives).  ``tests/test_hostile_keys.py`` checks that
together they give every key the loader accepts (the batch's top-level ``sweep:``
section excepted: ``tests/test_batch.py`` covers it)."""

from __future__ import annotations

import copy
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
SHIPPED = {
    p.name: yaml.safe_load(p.read_text(encoding="utf-8"))
    for p in sorted((ROOT / "mechanisms").glob("*.yaml"))
}


def _variant(name: str, **edits) -> dict:
    doc = copy.deepcopy(SHIPPED[name])
    for path, value in edits.items():
        *head, last = path.split("__")
        node = doc
        for key in head:
            node = node.setdefault(key, {})
        if value is None:
            node.pop(last, None)
        else:
            node[last] = value
    return doc


SC = "slider_crank.yaml"
SLIDE = {"speed": "mm/s"}
FEW = {"positions": 8}


def _seeds() -> dict[str, dict]:
    out: dict[str, dict] = {}
    out["slider driven"] = _variant(
        SC,
        units__speed="mm/s",
        drivers={"motor": {"joint": "slide", "motion": {"speed": -100}}},
        analysis={"start": 440, "sweep": 150, "positions": 4, "at": [400, 300]},
    )
    out["harmonic law"] = _variant(
        SC,
        drivers__motor={
            "joint": "O",
            "motion": {
                "law": "harmonic",
                "centre": 90,
                "amplitude": 60,
                "period": 0.5,
                "phase": 10,
            },
        },
        analysis={"positions": 8, "events": True},
    )
    out["polynomial law"] = _variant(
        SC,
        drivers__motor={
            "joint": "O",
            "motion": {"law": "polynomial", "coefficients": [0, 2000, -500, 10], "duration": 0.25},
        },
        analysis=FEW,
    )
    out["periodic table law"] = _variant(
        SC,
        drivers__motor={
            "joint": "O",
            "motion": {
                "law": "table",
                "time": [0, 0.1, 0.2, 0.3],
                "value": [0, 60, 20, 0],
                "periodic": True,
            },
        },
        analysis=FEW,
    )
    out["table law"] = _variant(
        SC,
        drivers__motor={
            "joint": "O",
            "motion": {
                "law": "table",
                "time": [0, 0.1, 0.3],
                "value": [0, 30, 90],
                "periodic": False,
            },
        },
        analysis=FEW,
    )
    out["constant law"] = _variant(
        SC,
        drivers__motor={"joint": "O", "motion": {"law": "constant", "speed": 120}},
        analysis={"start": 10, "sweep": 90, "positions": 4, "at": [20, 45], "events": True},
    )
    out["slider harmonic law"] = _variant(
        SC,
        units__speed="mm/s",
        drivers={
            "motor": {
                "joint": "slide",
                "motion": {"law": "harmonic", "centre": 370, "amplitude": 50, "period": 1},
            }
        },
        analysis=FEW,
    )
    out["flywheel"] = _variant(
        SC,
        flywheel={"delta": 0.05, "ratio": 3, "friction": True},
        analysis={"positions": 12},
        output="slider",
    )
    out["drive"] = _variant(
        SC,
        drive={
            "driver": "motor",
            "friction": True,
            "reduction": {"ratio": 10, "efficiency": 0.95, "inertia": 1e-4},
            "motor": {"rated_torque": 2, "peak_torque": 6, "rated_speed": 3000, "inertia": 3e-4},
        },
        analysis={"positions": 12},
    )
    out["balance_at and efforts"] = _variant(
        SC,
        drivers={
            "motor": {
                "joint": "O",
                "motion": {"speed": 300},
                "points": ["x", "A"],
                "balance_at": "B",
            },
            "helper": {
                "joint": "A",
                "effort": {"table": {"at": [0, 180, 360], "value": [1, -1, 1]}},
            },
        },
        analysis=FEW,
    )
    out["effort motor"] = _variant(
        SC,
        drivers__helper={
            "joint": "A",
            "effort": {"motor": {"torque": 40, "speed": 300, "slip": 0.05}},
        },
        analysis=FEW,
    )
    out["effort curve"] = _variant(
        SC,
        drivers__helper={"joint": "A", "effort": {"curve": {"speed": [0, 300], "torque": [40, 0]}}},
        analysis=FEW,
    )
    out["loads and conditions"] = _variant(
        SC,
        loads={
            "resistance": {
                "type": "resistance",
                "link": "slider",
                "point": "B",
                "table": {"at": [0, 180, 360], "value": [1000, 500, 1000]},
                "axis": [1, 0],
                "active": [
                    {"travel": [200, 400], "along": [1, 0], "point": "slider.B"},
                    {"angle": [0, 180], "point": "crank"},
                ],
            },
            "push": {
                "type": "force",
                "link": "rod",
                "point": "A",
                "value": [10, 5],
                "active": [{"moving": [0, 1]}],
            },
            "twist": {"type": "torque", "link": "rod", "table": {"at": [0, 360], "value": [1, 2]}},
            "brake": {"type": "resisting_torque", "link": "rod", "joint": "A", "value": 0.5},
        },
        analysis=FEW,
    )
    out["weight, journal friction, guide"] = _variant(
        SC,
        links__rod__mass=None,
        links__rod__weight=29.4,
        links__ground__points={"O": [0, 0], "guide": [0, "e"], "far": [100, "e"]},
        joints__A={
            "type": "revolute",
            "links": ["crank", "rod"],
            "friction": {"journal_radius": 8, "coefficient": 0.1},
        },
        joints__slide={
            "type": "prismatic",
            "links": ["ground", "slider"],
            "axis": {"points": ["guide", "far"]},
            "point": "B",
            "angle": 0,
            "length": 40,
            "friction": {"coefficient": 0.1},
        },
        analysis=FEW,
    )
    out["loops"] = _variant(SC, loops=[["O", "A", "B", "slide"]], analysis=FEW)
    out["counterweights"] = _variant(
        SC,
        links__crank__counterweights={"cw": {"at": [-20, 0], "mass": 0.5, "inertia": 0.0001}},
        analysis=FEW,
    )
    out["springs and dampers"] = _variant(
        SC,
        elements={
            "spring": {
                "type": "spring",
                "between": ["ground.O", "slider.B"],
                "stiffness": 2,
                "free_length": 300,
                "preload": 50,
            },
            "table": {
                "type": "spring",
                "between": ["crank.A", "ground.guide"],
                "table": {"length": [60, 100, 140], "force": [-100, 20, 500]},
            },
            "damper": {"type": "damper", "between": ["ground.O", "slider.B"], "damping": 0.5},
            "tors": {
                "type": "torsion_spring",
                "joint": "A",
                "stiffness": 3,
                "free_angle": 10,
                "preload": 2,
            },
            "tors_table": {
                "type": "torsion_spring",
                "joint": "B",
                "table": {"angle": [-90, 0, 90], "torque": [-1, 0, 2]},
            },
            "rd": {"type": "rotary_damper", "joint": "O", "damping": 0.2},
        },
        analysis=FEW,
    )
    swing = "ammunition_swing.yaml"
    out["clearance contact"] = _variant(
        swing,
        clearance={
            "A": {"size": "e1", "model": "prescribed", "speed": 10, "acceleration": 0, "angle": 30},
            "B": {
                "size": "e2",
                "model": "contact",
                "contact": {
                    "journal_radius": 20,
                    "young": [2.07e11, 2.07e11],
                    "poisson": [0.3, 0.3],
                    "restitution": 0.9,
                    "stiffness": 1e9,
                    "floor": 1,
                },
            },
        },
    )
    out["rack radius"] = _variant(
        swing, joints__mesh__module=None, joints__mesh__teeth=None, joints__mesh__radius="m*z/2"
    )
    gear = "geared_fivebar.yaml"
    out["gear radii"] = _variant(
        gear, joints__mesh__module=None, joints__mesh__radii=["m*z/2", "m*z/2"]
    )
    return out


SEEDS = _seeds()
"""name -> document (as ``yaml.safe_load`` gives it)."""
