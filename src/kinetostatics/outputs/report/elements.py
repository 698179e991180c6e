"""The section on springs and dampers (``elements:``): each element's data and a table of
its length (angle), force (moment), stored energy and power at the course-design positions,
in the units of the file (energy J, power W), from the element columns of results.csv."""

from __future__ import annotations

import numpy as np

from ...base.units import SI_UNITS, factor
from ..lang import tr
from .blocks import _Heading, _Para, _Table
from .results import Column, _table, _unit


def file_units(model) -> dict[str, tuple[str, float]]:
    """Per quantity kind (length, angle, time, force, torque) the file's unit and its size
    in SI (``{"length": ("mm", 1e-3), …}``; SI where the file names none)."""
    given = model.units or {}
    out = {}
    for kind in ("length", "angle", "time", "force", "torque"):
        u = given.get(kind, SI_UNITS[kind])
        out[kind] = (u, factor(kind, u))
    return out


def _g(v: float) -> str:
    return f"{v:.6g}"


def _element_row(e, units, T) -> list[str]:
    (lu, lf), (au, af), (tu, tf) = units["length"], units["angle"], units["time"]
    (fu, ff), (mu, mf) = units["force"], units["torque"]
    r = e.rotational
    s_u, s_f = (au, af) if r else (lu, lf)
    f_u, f_f = (mu, mf) if r else (fu, ff)
    ends = (
        T("at revolute {joint}: {j} relative to {i}", joint=e.joint, i=e.links[0], j=e.links[1])
        if r
        else f"{e.links[0]}.{e.points[0]} – {e.links[1]}.{e.points[1]}"
    )
    per = f_f / s_f  # SI per file unit of stiffness
    stiffness = free = preload = table = damping = ""
    if not e.spring:
        damping = f"{_g(e.damping / (per * tf))} {_unit(f_u)}·{tu}/{s_u}"
    elif e.table is not None:
        at, values = e.table
        pairs = [f"{_g(s / s_f)} → {_g(f / f_f)}" for s, f in zip(at, values)]
        table = f"{s_u} → {_unit(f_u)}: " + "; ".join(pairs)
    else:
        stiffness = f"{_g(e.stiffness / per)} {_unit(f_u)}/{s_u}"
        free = f"{_g(e.free / s_f)} {s_u}"
        preload = f"{_g(e.preload / f_f)} {_unit(f_u)}"
    return [e.name, e.kind, ends, stiffness, free, preload, table, damping]


def element_blocks(result, rows, number: int, lang: str = "en") -> list:
    """Section ``number``: the model's elements, or nothing when it has none."""
    model = result.system.model
    if not model.elements:
        return []
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    units = file_units(model)
    (lu, lf), (au, af) = units["length"], units["angle"]
    (fu, ff), (mu, mf) = units["force"], units["torque"]
    blocks: list = [
        _Heading(2, T("{n}. Springs and dampers", n=number)),
        _Para(
            T(
                "A spring or damper acts between two points along the line that joins them "
                "(its length s), a torsion spring or rotary damper at a revolute on the "
                "rotation of link j relative to link i (its angle s). Its force (moment) f "
                "reduces s when positive (a spring in tension): a spring's is preload + "
                "stiffness·(s − free length), or its table interpolated linearly and held "
                "constant outside; a damper's is damping·ds/dt. Stored energy: 0 at the free "
                "length (at the first value of a table); power f·ds/dt: stored by a spring, "
                "dissipated by a damper. Values in the units of the file."
            )
        ),
        _Table(
            [
                T("element"),
                T("type"),
                T("between"),
                T("stiffness"),
                T("free length or angle"),
                T("preload"),
                T("table (s → f)"),
                T("damping"),
            ],
            [_element_row(e, units, T) for e in model.elements],
            T("Elements"),
        ),
    ]
    cols: list[Column] = []
    for e in model.elements:
        r = e.rotational
        s_name, f_name = (
            (f"{e.name}.angle", f"{e.name}.M") if r else (f"{e.name}.length", f"{e.name}.F")
        )
        s = np.asarray(result[s_name], dtype=float)
        s = np.radians(s) / af if r else s / lf
        f = np.asarray(result[f_name], dtype=float) / (mf if r else ff)
        cols += [Column(s_name, au if r else lu, s), Column(f_name, _unit(mu if r else fu), f)]
        if e.spring:
            cols.append(Column(f"{e.name}.energy", "J", np.asarray(result[f"{e.name}.energy"])))
        cols.append(Column(f"{e.name}.power", "W", np.asarray(result[f"{e.name}.power"])))
    blocks += _table(
        result,
        rows,
        cols,
        T(
            "Springs and dampers at the course-design positions: length or angle s, force "
            "or moment f (positive reduces s), stored energy (J) and power f·ds/dt (W)"
        ),
        lang,
    )
    return blocks
