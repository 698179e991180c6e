"""Seed files for the fuzz test and the key walk: the shipped mechanisms plus variants of
them that use every section and option the loader accepts (motion laws, effort drivers,
``balance_at``, a flywheel with ``ratio``, a drive, clearances with contact, load tables and
conditions, the gear and rack alternatives).  ``tests/io/test_hostile_keys.py`` checks that
together they give every key the loader accepts (the batch's top-level ``sweep:``
section excepted: ``tests/batch/test_batch.py`` covers it)."""

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
UNITS = {"length": "mm", "angle": "deg", "speed": "rpm", "mass": "kg", "force": "N",
         "torque": "N*m", "inertia": "kg*m^2"}  # fmt: skip
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
    # cams with springs, dampers, table laws, counterweights and a drive: every kind of
    # follower and placement the cam joint takes, mutated with its elements and the drive
    out["cam rocker, spring and drive"] = {
        "name": "cam with roller rocker, return spring and a motor",
        "units": UNITS,
        "parameters": {
            "rb": 40,
            "rr": 15,
            "d": 120,
            "l": 100,
            "n": 600,
            "xc": "((rb + rr)**2 - l**2 + d**2)/(2*d)",
            "yc": "sqrt((rb + rr)**2 - xc**2)",
        },  # fmt: skip
        "gravity": [0, -9.81],
        "links": {
            "ground": {"points": {"O": [0, 0], "A": ["d", 0], "S": [66.6, -100]}},
            "cam": {
                "points": {"O": [0, 0], "K": [30, 0]},
                "com": [0, 0],
                "mass": 1.5,
                "inertia": 0.0015,
                "counterweights": {"cw": {"at": [-10, 0], "mass": 0.2}},
            },  # fmt: skip
            "arm": {
                "points": {"A": [0, 0], "E": [60, 0], "C": ["l", 0], "T": [130, 0]},
                "com": [50, 0],
                "mass": 0.6,
                "inertia": 0.0006,
            },  # fmt: skip
        },
        "joints": {
            "O": {"type": "revolute", "links": ["ground", "cam"], "friction": {"radius": 4}},
            "A": {"type": "revolute", "links": ["ground", "arm"]},
            "contact": {
                "type": "cam",
                "links": ["cam", "arm"],
                "centre": "O",
                "point": "C",
                "follower": "roller",
                "radius": "rr",
                "base_radius": "rb",
                "rotation": "ccw",
                "oscillating": {"pivot": ["d", 0], "arm": "l", "rise": "cw"},
                "motion": [
                    {"rise": 20, "over": 120, "law": "cycloidal"},
                    {"dwell": 60},
                    {"return": 20, "over": 120, "law": "harmonic"},
                    {"dwell": 60},
                ],
                "friction": {"coefficient": 0.01},
                "design": {"pressure_angle_max": 40},
            },  # fmt: skip
        },
        "drivers": {"motor": {"joint": "O", "points": ["x", "K"], "motion": {"speed": "n"}}},
        "loads": {"lift_load": {"type": "force", "link": "arm", "point": "T", "value": [0, 15]}},
        "elements": {
            "return_spring": {
                "type": "spring",
                "between": ["ground.S", "arm.E"],
                "stiffness": 1,
                "free_length": 80,
                "preload": 40,
            },
            "shock": {"type": "damper", "between": ["ground.S", "arm.T"], "damping": 0.01},
            "hinge": {"type": "rotary_damper", "joint": "A", "damping": 1e-5},
        },  # fmt: skip
        "drive": {
            "reduction": {"ratio": 5, "efficiency": 0.9, "inertia": 1e-4},
            "motor": {"rated_torque": 1, "peak_torque": 3, "rated_speed": 3000, "inertia": 1e-4},
        },
        "flywheel": {"delta": 0.05},
        "sketch": {"arm.C": ["xc", "yc"]},
        "analysis": {"start": 0, "sweep": 360, "positions": 8},
    }
    out["cam knife, table law and springs"] = _variant(
        "cam_roller.yaml",
        joints__contact__follower="knife",
        joints__contact__radius=None,
        joints__contact__motion={
            "angle": [0, 60, 120, 180, 240, 300],
            "lift": [0, 5, 15, 20, 12, 4],
        },
        links__ground__points={"O": [0, 0], "G": ["e", 0], "S": [60, 150]},
        sketch={"follower.C": ["e", "sqrt(rb**2 - e**2)"]},
        elements={
            "spring": {
                "type": "spring",
                "between": ["ground.S", "follower.T"],
                "table": {"length": [50, 80, 120], "force": [10, 30, 90]},
            },
            "damper": {"type": "damper", "between": ["ground.O", "follower.T"], "damping": 0.02},
        },
        drive={"motor": {"rated_torque": 2, "inertia": 1e-4}},
        analysis=FEW,
    )
    out["cam flat face, torsion springs"] = _variant(
        "cam_flat_oscillating.yaml",
        elements={
            "hinge": {
                "type": "torsion_spring",
                "joint": "A",
                "stiffness": 0.02,
                "free_angle": -10,
                "preload": 0.5,
            },
            "hinge_table": {
                "type": "torsion_spring",
                "joint": "A",
                "table": {"angle": [-30, 0, 30], "torque": [-1, 0.2, 2]},
            },
            "drag": {"type": "rotary_damper", "joint": "O", "damping": 1e-4},
        },
        drive={"reduction": {"ratio": 3}, "friction": False},
        flywheel={"delta": 0.1},
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
        swing,
        joints__mesh__module=None,
        joints__mesh__teeth=None,
        joints__mesh__radius="m*z/2",
        joints__mesh__shift=0.1,  # the tooth form (the gear chapter's keys)
    )
    gear = "geared_fivebar.yaml"
    out["gear radii"] = _variant(
        gear,
        joints__mesh__module=None,
        joints__mesh__radii=["m*z/2", "m*z/2"],
        joints__mesh__addendum=0.8,
        joints__mesh__clearance=0.3,
        joints__mesh__shift=[0.2, -0.1],
    )
    sized = "slider_crank_sized.yaml"  # the shapes the shipped file has not (docs/sizing.md)
    out["tube and circle sections"] = _variant(
        sized,
        links__crank__section={"shape": "circle", "diameter": 20},
        links__rod__section={"shape": "tube", "diameter": 25, "thickness": 3},
    )
    return out


SEEDS = _seeds()
"""name -> document (as ``yaml.safe_load`` gives it)."""
