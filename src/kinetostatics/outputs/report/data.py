"""The data sections of the mechanism: parameters, links, joints (from
``Joint.describe()``), drivers and loads (section 1), and its structure (section 2)."""

from __future__ import annotations

import math

import numpy as np

from ..plotting import link_numbers
from .blocks import _Heading, _List, _Para, _Table


def _mm(v) -> str:
    return ", ".join(f"{1e3 * float(c):.6g}" for c in v)


def _data_blocks(model, system) -> list:
    nums = link_numbers(system)
    blocks: list = [_Heading(2, "1. Data")]
    units = ", ".join(f"{k}: {v}" for k, v in model.units.items()) or "SI"
    blocks.append(
        _Para(
            f"Source: `{model.source}`. Units of the file: {units}. Everything below "
            "is in SI unless stated (lengths of points in mm). Gravity: "
            f"({model.gravity[0]:g}, {model.gravity[1]:g}) m/s²."
        )
    )
    if model.parameters:
        blocks.append(
            _Table(
                ["parameter", "value (as in the file)"],
                [[k, f"{v:.6g}"] for k, v in model.parameters.items()],
                "Parameters",
            )
        )
    rows = []
    for lk in model.links:
        pts = "; ".join(f"{p}: ({_mm(np.asarray(v) + lk.com)})" for p, v in lk.points.items())
        rows.append(
            [
                lk.name,
                str(nums[lk.name]),
                "frame" if lk.ground else f"{lk.mass:.6g}",
                "" if lk.ground else f"{lk.inertia:.6g}",
                "" if lk.ground else f"({_mm(lk.com)})",
                pts,
            ]
        )
    blocks.append(
        _Table(
            [
                "link",
                "no.",
                "mass (kg)",
                "J_S (kg·m²)",
                "centre of mass (mm)",
                "points (mm, in the link's own frame)",
            ],
            rows,
            "Links (numbers as in the pictures; the frame last)",
        )
    )
    rows = []
    for j in model.joints:
        text = j.describe()
        rows.append(
            [
                j.name,
                j.kind,
                f"{j.links[0]} → {j.links[1]}",
                f"F{nums[j.links[0]]}{nums[j.links[1]]}",
                text.get("where", ""),
                text.get("friction", ""),
            ]
        )
    blocks.append(
        _Table(
            ["joint", "type", "links i → j", "reaction", "where", "friction"],
            rows,
            "Joints (the reaction is the force of link i on link j)",
        )
    )
    rows = []
    for d in model.drivers:
        if d.motion is not None:
            sp = d.motion.speed
            speed = (
                f"{sp:+.6g} rad/s ({sp * 30 / math.pi:+.6g} rpm)"
                if model.joint(d.joint).angular
                else f"{sp:+.6g} m/s"
            )
            law = getattr(d.motion, "kind", None)
            rows.append(
                [
                    d.name,
                    d.joint,
                    f"{law} law, peak speed {speed}" if law else speed,
                    d.balance_at or d.joint,
                ]
            )
        else:
            rows.append([d.name, d.joint, f"effort {d.effort}", ""])
    blocks.append(
        _Table(["driver", "joint", "motion (+ counter-clockwise)", "effort at"], rows, "Drivers")
    )
    if model.loads:
        rows = []
        for ld in model.loads:
            conds = []
            for c in ld.active:
                if c.kind == "moving":
                    conds.append(
                        f"{c.link}.{c.point or 'CoM'} moving along ({c.axis[0]:g}, {c.axis[1]:g})"
                    )
                elif c.kind == "travel":
                    conds.append(
                        f"travel of {c.link}.{c.point or 'CoM'} along ({c.axis[0]:g}, "
                        f"{c.axis[1]:g}) in [{c.bounds[0] * 1e3:.4g}, {c.bounds[1] * 1e3:.4g}] mm"
                    )
                else:
                    conds.append(
                        f"driver coordinate in [{math.degrees(c.bounds[0]):.4g}, "
                        f"{math.degrees(c.bounds[1]):.4g}]°"
                    )
            value = np.asarray(ld.value)
            val = (
                f"({', '.join(f'{v:g}' for v in value)}) N"
                if value.ndim
                else f"{float(value):g} {'N·m' if 'torque' in ld.kind else 'N'}"
            )
            if ld.table is not None:
                val += " (tabulated)"
            rows.append(
                [
                    ld.name,
                    ld.kind,
                    f"{ld.link}" + (f".{ld.point}" if ld.point else ""),
                    val,
                    "; ".join(conds) or "always",
                ]
            )
        blocks.append(_Table(["load", "kind", "acts on", "value", "active while"], rows, "Loads"))
    return blocks


def _structure_blocks(system) -> list:
    st = system.structure
    items = [
        f"mobility (Grübler–Kutzbach): {st.mobility}",
        f"independent loops: {len(st.loops)}"
        + ("" if not st.loops else " — " + "; ".join(" – ".join(lp) for lp in st.loops)),
    ]
    blocks: list = [_Heading(2, "2. Structure"), _List(items)]
    rows = []
    for k, plan in enumerate(system.plans, 1):
        g = plan.group
        rows.append([str(k), g.label, ", ".join(g.joints + g.drivers)])
    blocks.append(
        _Table(
            ["step", "Assur group (class and members)", "joints and drivers"],
            rows,
            "Assur groups in solve order",
        )
    )
    return blocks
