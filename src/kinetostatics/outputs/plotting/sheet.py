"""The 12-position drawing: the mechanism at every course position on one sheet, true scale.

:func:`sheet_layout` chooses the sheet and the scale: the mechanism at the course positions
(:func:`~.rows.course_positions`), the limit positions and the traced paths fit inside the
frame of an A2 sheet (594 × 420 mm, landscape; a 25 mm binding margin on the left, 10 mm on
the other sides) above its title block, at the round scale 1:n of :func:`~.style.nice_scale`
(1, 2, 2.5, 4, 5 × 10^k); when the shortest link would be drawn shorter than
``MIN_LINK_MM`` there and A1 (841 × 594 mm) draws it larger, on A1 at its round scale.
The working position (position 1 unless asked) is drawn heavy (0.7 mm), the other course
positions thin (0.25 mm) and numbered at the crank pin, the limit positions
(the caller gives them as rows: where the output stops) in the phantom line (双点画线) of a
moving part's extreme position, the paths thin and coloured.  The title block holds the mechanism's
name, the scale, the date and "drawn by kinetostatics".

:func:`sheet_figure` draws it with matplotlib on a figure of the sheet's size (1 mm of the
figure is 1 mm of the sheet: a PDF printed at 100 %), :func:`export_sheet_dxf` as DXF in
the sheet's millimetres (``$INSUNITS`` mm) through :func:`~.export.write_geometry`, each
entity of a position tagged ``("link" | "block" | "joint" | …, name, position label)``.
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...base.optional import require
from ..lang import tr
from .export import APP, write_geometry
from .rows import course_positions, row_at
from .scene import _Scene, _to_global
from .style import MM, PictureError, _rc, nice_scale

__all__ = [
    "SHEETS",
    "SheetLayout",
    "sheet_layout",
    "sheet_figure",
    "export_sheet_dxf",
    "limit_rows",
    "output_paths",
]

SHEETS = {"A2": (594.0, 420.0), "A1": (841.0, 594.0)}  # landscape, mm
FRAME = (25.0, 10.0, 10.0, 10.0)  # margins of the frame: left (binding), right, bottom, top
TITLE_BLOCK = (140.0, 32.0)  # width, height (mm) in the frame's lower right corner
MARGIN = 8.0  # between the frame and the drawing (mm)
MIN_LINK_MM = 20.0  # the shortest link drawn at least this long, or the sheet is A1
HEAVY, THIN, LIMIT = 0.7, 0.25, 0.35  # line widths, mm
SIZE_MM = 60.0  # the reference size of the joint circles and pivots on the sheet (mm)


@dataclass(frozen=True)
class SheetLayout:
    """Where everything goes on the sheet (lengths on the sheet in mm).

    ``n``: the scale 1:n (a length of the mechanism is ``n`` times its drawing);
    ``origin``: the sheet point (mm) of the mechanism's origin; ``positions`` the course
    positions ``(label, row)``; ``working`` the heavy one; ``limits`` the limit positions
    ``(label, row)``; ``paths`` the traced points ``"link.point"``.
    """

    size: str
    width: float
    height: float
    n: float
    origin: tuple[float, float]
    positions: tuple[tuple[str, int], ...]
    working: tuple[str, int]
    limits: tuple[tuple[str, int], ...]
    paths: tuple[str, ...]

    @property
    def mu_l(self) -> float:
        """The length scale μ_l, m of the mechanism per mm of the sheet."""
        return self.n * 1e-3

    def to_sheet(self, p) -> np.ndarray:
        """Points in m (…, 2) → the sheet, mm."""
        return np.asarray(self.origin) + np.asarray(p, float) * (1e3 / self.n)

    def scale_text(self) -> str:
        """``1:4`` (a reduction), ``2:1`` (an enlargement)."""
        if self.n >= 1.0:
            return f"1:{self.n:g}"
        return f"{1.0 / self.n:g}:1"


def _area(size: str) -> tuple[float, float, float, float]:
    """The drawing area (x0, y0, x1, y1) inside the frame, above the title block."""
    w, h = SHEETS[size]
    left, right, bottom, top = FRAME
    return (
        left + MARGIN,
        bottom + TITLE_BLOCK[1] + MARGIN,
        w - right - MARGIN,
        h - top - MARGIN,
    )


def _shortest_link(scene: _Scene, row: int) -> float:
    """The shortest bar (two points) of the mechanism, m (inf without one)."""
    geo = scene.geometry(row)
    lengths = [
        float(np.hypot(*np.subtract(pts[-1], pts[0])))
        for name, pts in geo.outlines.items()
        if len(pts) == 2 and name not in geo.plates
    ]
    return min([v for v in lengths if v > 0] or [np.inf])


def sheet_layout(result, *, working: str | None = None, limits=(), paths=(), size=None):
    """The sheet, scale and positions of the 12-position drawing of ``result``.

    Parameters
    ----------
    result : Result
        An analysis holding the course positions (``analyze_for_pictures(…, course=True)``)
        and the limit positions' rows.
    working : str, optional
        The course-position label of the working position (default the first, ``"1"``).
    limits : sequence of (str, int)
        The limit positions as ``(label, row)``.
    paths : sequence of str
        Points ``"link.point"`` whose paths are drawn.
    size : {"A2", "A1"}, optional
        The sheet; default A2, or A1 when the shortest link would be drawn shorter than
        ``MIN_LINK_MM`` on A2 and A1's round scale is finer.

    Raises
    ------
    PictureError
        No course positions (not a whole turn of an angular driver), or no course
        position named ``working``.
    """
    positions = tuple(course_positions(result))
    if not positions:
        raise PictureError("the 12-position drawing needs a whole turn of an angular driver")
    labels = [lab for lab, _ in positions]
    key = (working or labels[0]).replace("'", "′")
    if key not in labels:
        raise PictureError(
            f"--working {working}: no course position of that label (have {', '.join(labels)})"
        )
    scene = _Scene(result, paths)
    # mm of the mechanism: its extent over the cycle without the screen drawing's padding
    lo, hi = (scene.lo + scene.pad) * 1e3, (scene.hi - scene.pad) * 1e3
    shortest = _shortest_link(scene, positions[0][1]) * 1e3
    chosen = {}
    for name in (size,) if size else ("A2", "A1"):
        x0, y0, x1, y1 = _area(name)
        room = (x1 - x0 - 2 * MARGIN, y1 - y0 - 2 * MARGIN)  # the numbers around it
        n = nice_scale(max((hi[0] - lo[0]) / room[0], (hi[1] - lo[1]) / room[1]))
        chosen[name] = (n, (x0, y0, x1, y1))
    name = size or "A2"
    if not size and shortest / chosen["A2"][0] < MIN_LINK_MM and chosen["A1"][0] < chosen["A2"][0]:
        name = "A1"  # the shortest link too short on A2, and A1 draws it larger
    n, (x0, y0, x1, y1) = chosen[name]
    centre = 0.5 * (lo + hi)
    origin = (0.5 * (x0 + x1) - centre[0] / n, 0.5 * (y0 + y1) - centre[1] / n)
    return SheetLayout(
        size=name,
        width=SHEETS[name][0],
        height=SHEETS[name][1],
        n=float(n),
        origin=(float(origin[0]), float(origin[1])),
        positions=positions,
        working=next(p for p in positions if p[0] == key),
        limits=tuple((str(a), int(b)) for a, b in limits),
        paths=tuple(paths),
    )


def limit_rows(result, angles) -> list[tuple[str, int]]:
    """The limit positions as ``(label, row)``, one per row: the course label of a row
    that is a course position, else ``φ = …°``.  ``angles``: the driver's angle (deg) at
    each limit position (``output_strokes``' ``limit_positions``), each a row of
    ``result`` (``analyze_for_pictures(…, positions=angles)``)."""
    course = dict((k, lab) for lab, k in course_positions(result))
    out: dict[int, str] = {}
    for a in angles:
        row = row_at(result, float(a))
        out.setdefault(row, course.get(row, f"φ = {float(a) % 360.0:.1f}°"))
    return [(lab, k) for k, lab in out.items()]


def output_paths(result, links) -> list[str]:
    """For each output link, its named point that travels farthest over the rows."""
    model = result.system.model
    out = []
    for link in dict.fromkeys(links):
        spans = {
            p: float(np.ptp(_to_global(result, link, xy), axis=0).max())
            for p, xy in model.link(link).points.items()
        }
        if spans:
            out.append(f"{link}.{max(spans, key=spans.get)}")
    return out


def _moving_point(result, scene: _Scene):
    """The (link, local point) where the position numbers are written: the point of the
    driven link's outline that moves most (the crank pin, numbered round its circle as
    a drawing does), or of any link's when the driven link's points do not move."""
    system = result.system
    driven = [n for n in system.motion_drivers[0].joint.links if n != system.model.ground.name]
    best, spread = None, -1.0
    for only in (driven, list(scene.outline_local)):
        for link in only:
            for p in scene.outline_local.get(link, ()):
                s = float(np.ptp(_to_global(result, link, p), axis=0).max())
                if s > spread:
                    best, spread = (link, p), s
        if spread > 1e-9:
            break
    return best


def _title_lines(result, layout: SheetLayout, date: str, lang: str) -> list[tuple[str, str]]:
    return [
        (tr("name", lang), result.system.model.name),
        (tr("scale", lang), layout.scale_text()),
        (tr("date", lang), date),
        (tr("drawn by", lang), "kinetostatics"),
    ]


def _today(date: str | None) -> str:
    return date or datetime.date.today().isoformat()


def _pt(mm: float) -> float:
    return mm / 25.4 * 72.0


def _draw_geometry(ax, layout, geo, width, style, colour) -> None:
    """One position: the links, the blocks and the joints, on the sheet."""
    kw = {"lw": _pt(width), "color": colour, "ls": style, "solid_capstyle": "round"}
    for name, pts in geo.outlines.items():
        if len(pts) < 2:
            continue
        xy = layout.to_sheet(pts)
        if name in geo.plates:
            xy = np.vstack([xy, xy[:1]])
        ax.plot(xy[:, 0], xy[:, 1], **kw)
    for b in geo.blocks:
        u = np.asarray(b.direction, float)
        n = np.array([-u[1], u[0]])
        c = np.asarray(b.centre, float)
        corners = [
            c + a * 0.5 * b.length * u + w * 0.5 * b.height * n
            for a, w in ((-1, -1), (1, -1), (1, 1), (-1, 1), (-1, -1))
        ]
        xy = layout.to_sheet(corners)
        ax.plot(xy[:, 0], xy[:, 1], **kw)
    for kind, _name, _link, p, _q in geo.wheels:
        if kind == "curve":
            xy = layout.to_sheet(p)
            ax.plot(xy[:, 0], xy[:, 1], **{**kw, "lw": _pt(THIN)})
    joints = layout.to_sheet(np.array(list(geo.joints.values()), float).reshape(-1, 2))
    r = 0.015 * SIZE_MM
    for x, y in joints:
        ax.add_patch(_circle((x, y), r, colour, width))


def _circle(xy, r, colour, width):
    from matplotlib.patches import Circle

    return Circle(xy, r, fc="white", ec=colour, lw=_pt(min(width, LIMIT)), zorder=5)


def _draw_frame_parts(ax, layout, geo) -> None:
    """The guides and the frame pivots, once (they do not move)."""
    for g in geo.guides:
        a, b = layout.to_sheet([g.start, g.end])
        ax.plot([a[0], b[0]], [a[1], b[1]], lw=_pt(THIN), color="0.3", ls=(0, (12, 3, 2, 3)))
        u = (b - a) / max(float(np.hypot(*(b - a))), 1e-300)
        nrm = np.array([-u[1], u[0]]) * g.half_width * 1e3 / layout.n
        for w in (-1, 1):
            ax.plot(
                [a[0] + w * nrm[0], b[0] + w * nrm[0]],
                [a[1] + w * nrm[1], b[1] + w * nrm[1]],
                lw=_pt(HEAVY),
                color="black",
            )
    for p in geo.pivots.values():
        x, y = layout.to_sheet(p)
        s = SIZE_MM
        tri = np.array([(x, y), (x - 0.04 * s, y - 0.06 * s), (x + 0.04 * s, y - 0.06 * s), (x, y)])
        ax.plot(tri[:, 0], tri[:, 1], lw=_pt(THIN), color="black")
        ax.plot([x - 0.07 * s, x + 0.07 * s], [y - 0.06 * s] * 2, lw=_pt(HEAVY), color="black")


def _border_and_title(ax, result, layout, date, lang) -> None:
    """The sheet's edge, its frame and the title block with its four rows."""
    W, H = layout.width, layout.height
    left, right, bottom, top = FRAME
    ax.plot([0, W, W, 0, 0], [0, 0, H, H, 0], lw=_pt(THIN), color="black")
    fx0, fy0, fx1, fy1 = left, bottom, W - right, H - top
    ax.plot([fx0, fx1, fx1, fx0, fx0], [fy0, fy0, fy1, fy1, fy0], lw=_pt(HEAVY), color="black")
    tw, th = TITLE_BLOCK
    bx0, by1 = fx1 - tw, fy0 + th
    ax.plot([bx0, bx0, fx1], [fy0, by1, by1], lw=_pt(HEAVY), color="black")
    rows = _title_lines(result, layout, date, lang)
    h = th / len(rows)
    for k, (what, value) in enumerate(rows):
        y = by1 - (k + 1) * h
        if k:
            ax.plot([bx0, fx1], [y + h, y + h], lw=_pt(THIN), color="black")
        ax.text(bx0 + 3, y + h / 2, what, fontsize=9, va="center")
        ax.text(bx0 + 40, y + h / 2, value, fontsize=11 if k == 0 else 10, va="center")
    ax.plot([bx0 + 37, bx0 + 37], [fy0, by1], lw=_pt(THIN), color="black")


def sheet_figure(result, layout: SheetLayout, *, date: str | None = None, lang: str = "en"):
    """The 12-position drawing on a figure of the sheet's size (1 mm = 1 mm of the sheet).

    Returns
    -------
    matplotlib.figure.Figure
        One axes covering the sheet, its data in the sheet's mm; save it as PDF and print
        at 100 %.
    """
    from matplotlib.figure import Figure

    scene = _Scene(result, layout.paths)
    with _rc(lang):
        fig = Figure(figsize=(layout.width * MM, layout.height * MM))
        ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
        ax.set_xlim(0.0, layout.width)
        ax.set_ylim(0.0, layout.height)
        ax.set_axis_off()
        _border_and_title(ax, result, layout, _today(date), lang)
        _draw_frame_parts(ax, layout, scene.geometry(layout.working[1]))
        for _label, row in layout.positions:
            if row != layout.working[1]:
                _draw_geometry(ax, layout, scene.geometry(row), THIN, "-", "0.35")
        for _label, row in layout.limits:
            _draw_geometry(
                ax, layout, scene.geometry(row), LIMIT, (0, (10, 2, 1.5, 2, 1.5, 2)), "#1f4e9c"
            )
        _draw_geometry(ax, layout, scene.geometry(layout.working[1]), HEAVY, "-", "black")
        for _ref, pts in scene.paths.items():
            xy = layout.to_sheet(pts)
            ax.plot(xy[:, 0], xy[:, 1], lw=_pt(THIN), color="#b2182b", zorder=2)
        _position_numbers(ax, result, scene, layout)
        _caption(ax, layout, lang)
    return fig


def _label_spots(result, scene, layout):
    """(label, sheet point) of each course position's number, outward of its point."""
    link, p = _moving_point(result, scene)
    track = layout.to_sheet(_to_global(result, link, p))
    centre = track.mean(axis=0)
    out = []
    for label, row in layout.positions:
        q = track[row]
        d = q - centre
        d = d / max(float(np.hypot(*d)), 1e-9)
        out.append((label, q + 9.0 * d))
    return out


def _position_numbers(ax, result, scene, layout) -> None:
    for label, (x, y) in _label_spots(result, scene, layout):
        ax.text(x, y, label, fontsize=9, ha="center", va="center", zorder=6)


def _caption(ax, layout, lang) -> None:
    x0, y0, _, _ = _area(layout.size)
    text = tr(
        "heavy: working position {w}; thin: the course positions; phantom line: the limit "
        "positions {lim}; red: the paths of {paths}; μ_l = {mu:g} m/mm",
        lang,
        w=layout.working[0],
        lim=", ".join(lab for lab, _ in layout.limits) or "—",
        paths=", ".join(layout.paths) or "—",
        mu=layout.mu_l,
    )
    ax.text(x0, FRAME[2] + 3.0, text, fontsize=8, va="bottom")


_DXF_LAYERS = {  # name: (AutoCAD colour index, linetype, lineweight in 1/100 mm)
    "BORDER": (7, "CONTINUOUS", -3),
    "TITLE": (7, "CONTINUOUS", -3),
    "FRAME": (8, "CONTINUOUS", -3),
    "POSITIONS": (8, "CONTINUOUS", 25),
    "WORKING": (7, "CONTINUOUS", 70),
    "LIMITS": (5, "PHANTOM", 35),
    "PATHS": (1, "CONTINUOUS", 25),
    "LABELS": (7, "CONTINUOUS", -3),
}


def _tagger(label: str):
    """``tag(entity, what, name)`` writing ``(what, name, label)`` as the entity's data."""

    def tag(entity, what, name):
        entity.set_xdata(APP, [(1000, what), (1000, name), (1000, label)])

    return tag


def export_sheet_dxf(
    result, layout: SheetLayout, path: str | Path, *, date: str | None = None, lang: str = "en"
) -> None:
    """Write the 12-position drawing as DXF, in the sheet's mm (``$INSUNITS`` = 4)."""
    ezdxf = require("ezdxf", "dxf", "the DXF export")
    doc = ezdxf.new("R2010", setup=True)
    doc.header["$INSUNITS"] = 4
    doc.appids.add(APP)
    for name, (colour, linetype, weight) in _DXF_LAYERS.items():
        doc.layers.add(name, color=colour, linetype=linetype, lineweight=weight)
    msp = doc.modelspace()
    scene = _Scene(result, layout.paths)

    def xy(p) -> tuple[float, float]:
        x, y = layout.to_sheet(p)
        return float(x), float(y)

    work = layout.working
    drawn = [(work, "WORKING", True)]
    drawn += [((lab, k), "POSITIONS", False) for lab, k in layout.positions if k != work[1]]
    drawn += [(pos, "LIMITS", False) for pos in layout.limits]
    for (label, row), layer, frame in drawn:
        geo = scene.geometry(row)
        write_geometry(msp, geo, xy, SIZE_MM, layer=layer, tag=_tagger(label), frame=frame)
    for ref, pts in scene.paths.items():
        e = msp.add_lwpolyline([xy(p) for p in pts], dxfattribs={"layer": "PATHS"})
        e.set_xdata(APP, [(1000, "path"), (1000, ref)])
    for label, (x, y) in _label_spots(result, scene, layout):
        t = msp.add_text(label, height=3.5, dxfattribs={"layer": "LABELS"})
        t.set_placement((float(x), float(y)))
    _dxf_border(msp, result, layout, _today(date), lang)
    doc.saveas(str(path))


def _dxf_border(msp, result, layout, date, lang) -> None:
    W, H = layout.width, layout.height
    left, right, bottom, top = FRAME
    msp.add_lwpolyline([(0, 0), (W, 0), (W, H), (0, H)], close=True, dxfattribs={"layer": "BORDER"})
    fx0, fy0, fx1, fy1 = left, bottom, W - right, H - top
    msp.add_lwpolyline(
        [(fx0, fy0), (fx1, fy0), (fx1, fy1), (fx0, fy1)],
        close=True,
        dxfattribs={"layer": "BORDER", "lineweight": 70},
    )
    tw, th = TITLE_BLOCK
    bx0, by1 = fx1 - tw, fy0 + th
    msp.add_lwpolyline([(bx0, fy0), (bx0, by1), (fx1, by1)], dxfattribs={"layer": "TITLE"})
    rows = _title_lines(result, layout, date, lang)
    h = th / len(rows)
    for k, (what, value) in enumerate(rows):
        y = by1 - (k + 1) * h
        if k:
            msp.add_line((bx0, y + h), (fx1, y + h), dxfattribs={"layer": "TITLE"})
        msp.add_text(what, height=3.5, dxfattribs={"layer": "TITLE"}).set_placement(
            (bx0 + 3, y + h / 2 - 1.75)
        )
        msp.add_text(value, height=3.5, dxfattribs={"layer": "TITLE"}).set_placement(
            (bx0 + 40, y + h / 2 - 1.75)
        )
    msp.add_line((bx0 + 37, fy0), (bx0 + 37, by1), dxfattribs={"layer": "TITLE"})
