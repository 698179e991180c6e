"""The mechanism at one position as a CAD drawing (DXF) or a vector picture (SVG).

DXF (:func:`export_dxf`, needs ``pip install 'kinetostatics[dxf]'``): the geometry of
:class:`~.scene.MechanismGeometry` — the same that :func:`~.draw.draw_mechanism` draws —
in the file's length unit (``units.length``; ``$INSUNITS`` set to match), global axes,
one layer per kind: ``LINKS`` (bars and plates), ``SLIDERS`` (blocks), ``FRAME`` (guides
and their rails, frame pivots), ``WHEELS`` (pitch circles and lines), ``JOINTS`` (a circle
at each joint's point), ``POINTS`` (every named point), ``COM`` (centres of mass),
``LABELS`` and, with ``forces``, ``FORCES`` (the loads of :func:`~.draw._loads_at` to one
force scale, stated in a note).  Each joint circle, point and link outline carries its
name as extended data of the application ``KINETOSTATICS`` (``("joint", "A")``), so a
program reading the file finds them by name.

SVG (:func:`export_svg`): the picture of ``kinetostatics plot --what drawing`` (true
scale on paper, mm), through matplotlib's SVG backend: no second renderer to keep in
step and no further dependency.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...base import units
from ...base.optional import require
from .draw import _force_scale, _loads_at, draw_mechanism
from .rows import _position_title
from .scene import _Scene

__all__ = ["export_dxf", "export_svg", "write_geometry", "APP"]

APP = "KINETOSTATICS"  # the extended-data application name
# $INSUNITS by the unit's factor to m: m, mm, cm, km, µm, in, ft (0: unitless)
_INSUNITS = {1.0: 6, 1e-3: 4, 1e-2: 5, 1e3: 7, 1e-6: 13, 0.0254: 1, 0.3048: 2}
_LAYERS = {  # name: AutoCAD colour index
    "LINKS": 5,
    "SLIDERS": 5,
    "FRAME": 8,
    "WHEELS": 3,
    "JOINTS": 1,
    "POINTS": 7,
    "COM": 6,
    "LABELS": 7,
    "FORCES": 30,
}


def _tag(entity, what: str, name: str) -> None:
    entity.set_xdata(APP, [(1000, what), (1000, name)])


def export_dxf(result, row: int, path: str | Path, *, forces: bool = False, friction=False):
    """Write the mechanism at ``row`` as DXF to ``path``, lengths in the file's unit."""
    ezdxf = require("ezdxf", "dxf", "the DXF export")
    model = result.system.model
    unit = model.units.get("length", "m")
    to_m = units.factor("length", unit)
    s = 1.0 / to_m  # m -> the file's unit
    scene = _Scene(result)
    geo = scene.geometry(row)
    l_ref = result.system.l_ref * s
    doc = ezdxf.new("R2010", setup=True)
    doc.header["$INSUNITS"] = _INSUNITS.get(to_m, 0)
    doc.appids.add(APP)
    for name, colour in _LAYERS.items():
        doc.layers.add(name, color=colour)
    msp = doc.modelspace()

    def xy(p) -> tuple[float, float]:
        return float(p[0]) * s, float(p[1]) * s

    text_h = 0.03 * l_ref
    write_geometry(msp, geo, xy, l_ref)
    title = f"{model.name}: {_position_title(result, row)}; lengths in {unit}"
    if forces:
        title += _dxf_forces(msp, result, row, s, l_ref, text_h, friction)
    note = msp.add_text(title, height=text_h, dxfattribs={"layer": "LABELS"})
    note.set_placement((float(scene.lo[0]) * s, float(scene.hi[1]) * s + 2 * text_h))
    doc.saveas(str(path))


_CORNERS = ((-1, -1), (1, -1), (1, 1), (-1, 1))


def write_geometry(
    msp, geo, xy, size: float, *, layer: str | None = None, tag=_tag, frame: bool = True
) -> None:
    """Write the mechanism's geometry ``geo`` (:class:`~.scene.MechanismGeometry`) into
    the DXF modelspace ``msp``: ``xy`` maps a point in m to drawing units, ``size`` is
    the drawing's reference length in those units (the joint circles, pivots and labels
    are drawn to it).  ``layer``: every entity on that layer (default: one layer per
    kind, ``_LAYERS``, and the joints' labels, the named points and the centres of mass
    too); ``tag(entity, what, name)`` names each entity; ``frame``: the guides and frame
    pivots too."""
    extras = layer is None
    lay = (lambda kind: layer) if layer else (lambda kind: kind)
    text_h = 0.03 * size
    k = float(np.hypot(*np.subtract(xy((1.0, 0.0)), xy((0.0, 0.0)))))  # units per m
    for name, pts in geo.outlines.items():
        if len(pts) < 2:
            continue
        closed = name in geo.plates
        e = msp.add_lwpolyline(
            [xy(p) for p in pts], close=closed, dxfattribs={"layer": lay("LINKS")}
        )
        tag(e, "link", name)
    for b in geo.blocks:
        u, n = np.asarray(b.direction, float), np.array([-b.direction[1], b.direction[0]])
        c = np.asarray(b.centre, float)
        corners = [c + a * 0.5 * b.length * u + w * 0.5 * b.height * n for a, w in _CORNERS]
        e = msp.add_lwpolyline(
            [xy(p) for p in corners], close=True, dxfattribs={"layer": lay("SLIDERS")}
        )
        tag(e, "block", b.joint)
    if frame:
        _write_frame(msp, geo, xy, size, lay("FRAME"), tag)
    for kind, name, _link, p, q in geo.wheels:
        if kind == "circle":
            e = msp.add_circle(xy(p), float(q) * k, dxfattribs={"layer": lay("WHEELS")})
        elif kind == "curve":  # a cam's profile or pitch curve: points, closed
            e = msp.add_lwpolyline(
                [xy(r) for r in np.asarray(p, float)],
                close=bool(q),
                dxfattribs={"layer": lay("WHEELS")},
            )
        else:
            e = msp.add_line(xy(p), xy(q), dxfattribs={"layer": lay("WHEELS")})
        tag(e, "pitch", name)
    for name, p in geo.joints.items():
        p = np.asarray(p, float)
        tag(msp.add_circle(xy(p), 0.015 * size, dxfattribs={"layer": lay("JOINTS")}), "joint", name)
        if extras:
            label = msp.add_text(name, height=text_h, dxfattribs={"layer": lay("LABELS")})
            label.set_placement((xy(p)[0] + 0.02 * size, xy(p)[1] + 0.02 * size))
    if not extras:
        return
    for name, p in geo.points.items():
        tag(msp.add_point(xy(p), dxfattribs={"layer": lay("POINTS")}), "point", name)
    for name, p in geo.com.items():
        tag(msp.add_point(xy(p), dxfattribs={"layer": lay("COM")}), "com", name)


def _write_frame(msp, geo, xy, size, layer, tag) -> None:
    """The frame's guides (axis and rails) and pivots (a triangle under each pin)."""
    for g in geo.guides:
        u = (g.end - g.start) / max(float(np.hypot(*(g.end - g.start))), 1e-300)
        n = np.array([-u[1], u[0]])
        msp.add_line(xy(g.start), xy(g.end), dxfattribs={"layer": layer, "linetype": "CENTER"})
        for w in (-1.0, 1.0):
            off = w * g.half_width * n
            msp.add_line(xy(g.start + off), xy(g.end + off), dxfattribs={"layer": layer})
    for name, p in geo.pivots.items():
        x, y = xy(p)
        tri = [(x, y), (x - 0.04 * size, y - 0.06 * size), (x + 0.04 * size, y - 0.06 * size)]
        tag(msp.add_lwpolyline(tri, close=True, dxfattribs={"layer": layer}), "pivot", name)


def _dxf_forces(msp, result, row, s, l_ref, text_h, friction) -> str:
    """The loads at ``row`` as lines with a head (forces) or an arc (couples); the note."""
    arrows = _loads_at(result, row, friction=friction)
    mu = _force_scale(arrows, target_mm=1.0) / (0.25 * l_ref)  # N per drawing unit
    for a in arrows:
        x, y = float(a.at[0]) * s, float(a.at[1]) * s
        if a.force is None and a.moment == 0.0 or a.force is not None and not np.any(a.force):
            continue
        if a.force is None:
            r = 0.06 * l_ref
            start, end = (30.0, 300.0) if a.moment >= 0 else (240.0, 150.0)
            e = msp.add_arc((x, y), r, start, end, dxfattribs={"layer": "FORCES"})
            _tag(e, a.kind, a.label)
            msp.add_text(
                f"{a.label} {a.moment:.4g} N*m", height=0.7 * text_h, dxfattribs={"layer": "FORCES"}
            ).set_placement((x + r, y + r))
            continue
        f = np.asarray(a.force, float) / mu
        tip = np.array([x, y]) + f
        _tag(msp.add_line((x, y), tuple(tip), dxfattribs={"layer": "FORCES"}), a.kind, a.label)
        size = float(np.hypot(*f))
        if size > 0:
            u = f / size
            n = np.array([-u[1], u[0]])
            h = min(0.03 * l_ref, 0.4 * size)
            for w in (-1, 1):
                msp.add_line(
                    tuple(tip),
                    tuple(tip - h * u + w * 0.35 * h * n),
                    dxfattribs={"layer": "FORCES"},
                )
        msp.add_text(
            f"{a.label} {np.hypot(*a.force):.4g} N",
            height=0.7 * text_h,
            dxfattribs={"layer": "FORCES"},
        ).set_placement(tuple(tip))
    return f"; forces: 1 drawing unit = {mu:.4g} N" + (" (with friction)" if friction else "")


def export_svg(result, row: int, path: str | Path, *, forces: bool = False, friction=False):
    """Write the drawing of :func:`~.draw.draw_mechanism` at ``row`` as SVG to ``path``."""
    fig = draw_mechanism(result, row=row, forces=forces, friction=friction)
    fig.savefig(str(path), format="svg")
