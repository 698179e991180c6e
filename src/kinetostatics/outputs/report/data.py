"""The data sections of the mechanism: parameters, links, joints (from
``Joint.describe()``), drivers and loads (section 1), and its structure (section 2)."""

from __future__ import annotations

import math

import numpy as np

from ..labels import link_numbers, numbered, reaction_symbol
from ..lang import tr
from .blocks import _Heading, _List, _Para, _Table
from .formulas import synthesis_rows
from .results import group_label, length_unit, roman


def _data_blocks(model, system, lang: str = "en") -> list:
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    nums = link_numbers(system)
    lu, lf = length_unit(model)

    def _mm(v) -> str:
        return ", ".join(f"{float(c) / lf:.6g}" for c in v)

    blocks: list = [_Heading(2, T("1. Data"))]
    units = ", ".join(f"{k}: {v}" for k, v in model.units.items()) or "SI"
    blocks.append(
        _Para(
            T(
                "Source: `{source}`. Units of the file: {units}. Everything below is in SI "
                "unless stated (lengths of points in {lu}). Gravity: ({gx}, {gy}) m/s².",
                source=model.source,
                units=units,
                lu=lu,
                gx=f"{model.gravity[0]:g}",
                gy=f"{model.gravity[1]:g}",
            )
        )
    )
    if model.parameters:
        blocks.append(
            _Table(
                [T("parameter"), T("value (as in the file)")],
                [[k, f"{v:.6g}"] for k, v in model.parameters.items()],
                T("Parameters"),
            )
        )
        synthesis = synthesis_rows(model.parameter_texts, model.parameters)
        if synthesis:
            blocks.append(
                _Table(
                    [T("parameter"), T("formula and value")],
                    synthesis,
                    T("Dimension synthesis: the parameters computed from others (file's units)"),
                )
            )
    rows = []
    links = list(model.links)
    if numbered(model):  # the textbook's order: 1 the frame, 2 the crank, …
        links.sort(key=lambda lk: nums[lk.name])
    for lk in links:
        pts = "; ".join(f"{p}: ({_mm(np.asarray(v) + lk.com)})" for p, v in lk.points.items())
        rows.append(
            [
                lk.name,
                str(nums[lk.name]),
                T("frame") if lk.ground else f"{lk.mass:.6g}",
                "" if lk.ground else f"{lk.inertia:.6g}",
                "" if lk.ground else f"({_mm(lk.com)})",
                pts,
            ]
        )
    blocks.append(
        _Table(
            [
                T("link"),
                T("no."),
                T("mass (kg)"),
                "J_S (kg·m²)",
                T("centre of mass ({lu})", lu=lu),
                T("points ({lu}, in the link's own frame)", lu=lu),
            ],
            rows,
            T("Links (numbers as in the file and the pictures)")
            if numbered(model)
            else T("Links (numbers as in the pictures; the frame last)"),
        )
    )
    rows = []
    for j in model.joints:
        text = j.describe(T)
        rows.append(
            [
                j.name,
                T(j.kind),
                f"{j.links[0]} → {j.links[1]}",
                reaction_symbol(j.links, nums),
                text.get("where", ""),
                text.get("friction", ""),
            ]
        )
    blocks.append(
        _Table(
            [T("joint"), T("type"), T("links i → j"), T("reaction"), T("where"), T("friction")],
            rows,
            T("Joints (the reaction is the force of link i on link j)"),
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
            law = d.motion.kind if d.motion.own_run else None
            rows.append(
                [
                    d.name,
                    d.joint,
                    T("{law} law, peak speed {speed}", law=T(law), speed=speed) if law else speed,
                    d.balance_at or d.joint,
                ]
            )
        else:
            rows.append([d.name, d.joint, T("effort {e}", e=d.effort), ""])
    blocks.append(
        _Table(
            [T("driver"), T("joint"), T("motion (+ counter-clockwise)"), T("effort at")],
            rows,
            T("Drivers"),
        )
    )
    if model.loads:
        rows = []
        for ld in model.loads:
            conds = []
            for c in ld.active:
                if c.kind == "moving":
                    conds.append(
                        T(
                            "{p} moving along ({x}, {y})",
                            p=f"{c.link}.{c.point or 'CoM'}",
                            x=f"{c.axis[0]:g}",
                            y=f"{c.axis[1]:g}",
                        )
                    )
                elif c.kind == "travel":
                    conds.append(
                        T(
                            "travel of {p} along ({x}, {y}) in [{a}, {b}] {lu}",
                            p=f"{c.link}.{c.point or 'CoM'}",
                            x=f"{c.axis[0]:g}",
                            y=f"{c.axis[1]:g}",
                            a=f"{c.bounds[0] / lf:.4g}",
                            b=f"{c.bounds[1] / lf:.4g}",
                            lu=lu,
                        )
                    )
                else:
                    conds.append(
                        T(
                            "driver angle φ in [{a}, {b}]°",
                            a=f"{math.degrees(c.bounds[0]):.4g}",
                            b=f"{math.degrees(c.bounds[1]):.4g}",
                        )
                    )
            value = np.asarray(ld.value)
            val = (
                f"({', '.join(f'{v:g}' for v in value)}) N"
                if value.ndim
                else f"{float(value):g} {'N·m' if 'torque' in ld.kind else 'N'}"
            )
            if ld.table is not None:
                val += T(" (tabulated)")
            rows.append(
                [
                    ld.name,
                    T(ld.kind),
                    f"{ld.link}" + (f".{ld.point}" if ld.point else ""),
                    val,
                    "; ".join(conds) or T("always"),
                ]
            )
        blocks.append(
            _Table(
                [T("load"), T("kind"), T("acts on"), T("value"), T("active while")],
                rows,
                T("Loads"),
            )
        )
    return blocks


def _structure_blocks(system, lang: str = "en") -> list:
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    st = system.structure
    items = [
        T("mobility (Grübler–Kutzbach): {m}", m=st.mobility),
        T("independent loops: {n}", n=len(st.loops))
        + ("" if not st.loops else " — " + "; ".join(" – ".join(lp) for lp in st.loops)),
    ]
    orders = [p.group.order for p in system.plans if p.group.kind != "driven"]
    if orders and None not in orders:  # the class of the mechanism: its highest group's
        items.append(T("class of the mechanism: class {c}", c=roman(max(orders), lang)))
    blocks: list = [_Heading(2, T("2. Structure")), _List(items)]
    rows = []
    for k, plan in enumerate(system.plans, 1):
        g = plan.group
        rows.append([str(k), group_label(g, lang), ", ".join(g.joints + g.drivers)])
    blocks.append(
        _Table(
            [T("step"), T("Assur group (class and members)"), T("joints and drivers")],
            rows,
            T("Assur groups in solve order"),
        )
    )
    return blocks
