"""One consistent look: matplotlib on first use, the figure and rc style, drawing
scales, paper layout and the drawing primitives (hatched lines, arrows, arcs,
labels)."""

from __future__ import annotations

import contextlib
import re

import numpy as np

from ...base.units import nice_scale  # noqa: F401  (re-exported: plotting's helper)
from ...errors import KinetostaticsError
from ..fonts import math_fallback, rc_fonts
from .mathtext import share


class PictureError(KinetostaticsError, ValueError):
    """A picture cannot be made as asked (unknown name, missing column, no ffmpeg …)."""


# -- one consistent look ----------------------------------------------------------
STYLE = {
    "font.size": 8.5,
    "axes.titlesize": 9.5,
    "axes.labelsize": 8.5,
    "axes.grid": True,
    "grid.color": "#d9d9d9",
    "grid.linewidth": 0.5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "legend.fontsize": 7.5,
    "legend.frameon": False,
    "lines.linewidth": 1.4,
    "xtick.labelsize": 7.5,
    "ytick.labelsize": 7.5,
    "mathtext.default": "regular",
}
LINK_COLORS = (
    "#1f5fa8",
    "#d9641e",
    "#2e8b57",
    "#8e44ad",
    "#b8860b",
    "#c0392b",
    "#16a5a5",
    "#7f7f7f",
    "#e377c2",
    "#4b5563",
)
FORCE_COLORS = {
    "reaction": "#1f5fa8",
    "inertia": "#c0392b",
    "gravity": "#6b6b6b",
    "external": "#2e8b57",
    "effort": "#8e44ad",
}
CURVE_COLORS = (
    "#1f5fa8",
    "#d9641e",
    "#2e8b57",
    "#c0392b",
    "#8e44ad",
    "#b8860b",
    "#16a5a5",
    "#7f7f7f",
    "#e377c2",
    "#4b5563",
)
EVENT_COLOR = "#c0392b"
ELEMENT_COLOR = "#7f8c8d"  # springs and dampers
MM = 1.0 / 25.4  # inches per mm
# the room for a picture on an A4 page of the PDF report (report/pdf.py: 14 mm margins,
# 14 mm kept for the caption): a true-scale picture this small prints at 100 %
A4_TEXT_MM = (182.0, 255.0)
ROUND_OFF = 1e-9  # a value ≤ this times its scale is round-off: drawn and printed as 0
DPI = 110


def _mpl():
    """matplotlib pieces, imported on first use (``run`` never imports them)."""
    import matplotlib
    from matplotlib.figure import Figure

    return matplotlib, Figure


def _mend_math(fig) -> None:
    """Each mathtext label of ``fig`` drawn as :func:`..fonts.math_fallback` says: its
    plain text is drawn from one font alone, not along the chain of families (for
    ``--lang zh`` the CJK font, which may lack ², ≤ …; in English DejaVu Sans, which
    lacks the Chinese of a name).  Done before the figure's texts are measured or drawn."""
    from matplotlib.font_manager import findfont

    for t in _texts(fig, []):
        text = t.get_text()
        if "$" not in text or t.get_usetex():
            continue
        prop = t.get_fontproperties()
        families = list(prop.get_family())
        paths = []
        for family in families:
            one = prop.copy()
            one.set_family(family)
            paths.append(findfont(one))
        best, mended = math_fallback(text, paths)
        if best:  # the family that has the text first, the others after it
            t.set_fontfamily([families[best], *families[:best], *families[best + 1 :]])
        if mended != text:
            t.set_text(mended)


def _texts(artist, out: list) -> list:
    """The texts of ``artist`` and of the artists below it, as ``findobj(Text)`` finds them
    but without making an axis's ticks: ``Axis.get_children`` makes every tick its locator
    asks for, each with its (still empty) labels, and a figure's draw then asks the
    locator again; here an axis gives its label, its offset text and the ticks it has
    made so far (a label is given its text when the ticks are drawn)."""
    from matplotlib.axis import Axis
    from matplotlib.text import Text

    if isinstance(artist, Text):
        out.append(artist)
    if isinstance(artist, Axis):
        kids = [artist.label, artist.offsetText]
        for made in ("majorTicks", "minorTicks"):  # a lazy list: absent until first asked
            for tick in artist.__dict__.get(made, ()):
                kids += tick.get_children()
    else:
        kids = artist.get_children()
    for kid in kids:
        _texts(kid, out)
    return out


_SHEET = []  # the Figure class below, made on first use


def _sheet_class():
    """matplotlib's Figure, mending its mathtext labels (:func:`_mend_math`) whenever it
    is drawn, whatever saves or shows it (``plot``, ``report``, the SVG export)."""
    if not _SHEET:
        matplotlib, Figure = _mpl()

        class Sheet(Figure):
            def __init__(self, *args, **kwargs):
                super().__init__(*args, **kwargs)
                # the style the figure is made and laid out in (:func:`_rc`)
                self._style = dict(_STYLES[-1]) if _STYLES else {}
                self._layout_todo = None  # a layout noted to be done when saved (crop.py)

            def savefig(self, *args, **kwargs):
                _lay_out(self)  # saved other than by crop.save_png: laid out as it was
                return super().savefig(*args, **kwargs)

            def draw(self, renderer):
                _mend_math(self)
                # drawn in the style it was laid out in: a figure saved after the
                # style's context was drawn in matplotlib's defaults, its formulas in
                # the italic face (wider or narrower than their layout, and each parsed
                # again: the shared parser's key holds the settings), its axes' ticks
                # spaced for 10 pt labels where the layout had measured 7.5 pt ones
                with matplotlib.rc_context(self._style):
                    share(renderer)  # each formula parsed, each text measured, once
                    super().draw(renderer)

        _SHEET.append(Sheet)
    return _SHEET[0]


def _figure(width_mm: float, height_mm: float, dpi: float = DPI):
    return _sheet_class()(figsize=(width_mm * MM, height_mm * MM), dpi=dpi)


_STYLES: list[dict] = []  # the styles of the :func:`_rc` contexts entered, innermost last


@contextlib.contextmanager
def _rc(lang: str = "en"):
    """The style (and for ``lang="zh"`` a font with Chinese glyphs) while a figure is
    made and laid out; a figure made inside it is drawn in it too, wherever it is saved."""

    matplotlib, _ = _mpl()
    style = {**STYLE, **rc_fonts(lang)}
    with matplotlib.rc_context(style):
        _STYLES.append(style)
        try:
            yield
        finally:
            _STYLES.pop()


def _fmt_scale(x: float) -> str:
    return f"{x:.6g}"


def _tex(label: str) -> str:
    """``a2'`` -> mathtext: upright a, subscript 2, a prime; underscores escaped."""
    m = re.match(r"^(.*?)(\d+)?('*)$", label)
    base, digits, primes = m.group(1), m.group(2) or "", m.group(3)
    if not base.isascii():  # a name in another script (刀尖): mathtext's fonts lack it
        return base + digits.translate(_SUBSCRIPT) + "′" * len(primes)
    base = base.replace("_", r"\_").replace(" ", r"\ ")
    out = rf"\mathrm{{{base}}}" + (f"_{{{digits}}}" if digits else "") + "'" * len(primes)
    return f"${out}$"


MU = {"l": r"$\mu_l$", "v": r"$\mu_v$", "a": r"$\mu_a$", "F": r"$\mu_F$"}


# -- drawing primitives -----------------------------------------------------------
class _Paper:
    """Data (mm of the mechanism) ↔ paper (mm) for true-scale drawings."""

    def __init__(self, mu_l: float):
        self.mu_l = mu_l  # m of mechanism per mm of paper
        self.k = mu_l * 1e3  # data mm per paper mm


def _layout(  # noqa: PLR0913  matplotlib's layout arguments
    xlim,
    ylim,
    per_mm: float,
    *,
    left=17.0,
    right=6.0,
    bottom=13.0,
    top=11.0,
    extra_right=0.0,
    dpi=DPI,
    min_mm=(40.0, 30.0),
):
    """A figure whose axes show ``xlim × ylim`` at ``per_mm`` data units per paper mm."""
    w = (xlim[1] - xlim[0]) / per_mm
    h = (ylim[1] - ylim[0]) / per_mm
    if w < min_mm[0]:
        c, half = 0.5 * (xlim[0] + xlim[1]), 0.5 * min_mm[0] * per_mm
        xlim, w = (c - half, c + half), min_mm[0]
    if h < min_mm[1]:
        c, half = 0.5 * (ylim[0] + ylim[1]), 0.5 * min_mm[1] * per_mm
        ylim, h = (c - half, c + half), min_mm[1]
    W, H = left + w + right + extra_right, bottom + h + top
    fig = _figure(W, H, dpi)
    ax = fig.add_axes([left / W, bottom / H, w / W, h / H])
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    ax.set_autoscale_on(False)
    return fig, ax


def _hatch_line(ax, a, b, side, depth, color="black", lw=0.8, n=None, zorder=2):  # noqa: PLR0913  a drawing primitive's style keywords
    """A line a–b with short hatch strokes on ``side`` (unit normal), depth in data units."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    L = float(np.hypot(*(b - a)))
    artists = ax.plot(
        [a[0], b[0]], [a[1], b[1]], color=color, lw=lw, zorder=zorder, solid_capstyle="butt"
    )
    if L == 0:
        return artists
    n = n or max(3, int(L / depth * 1.2))
    u = (b - a) / L
    side = np.asarray(side, float)
    segs = []
    for t in np.linspace(0, L, n + 1)[1:]:
        p = a + t * u
        q = p + depth * side - depth * u
        segs.append([p, q])
    from matplotlib.collections import LineCollection

    lc = LineCollection(segs, colors=color, linewidths=0.6, zorder=zorder)
    ax.add_collection(lc)
    return artists + [lc]


def _arrow(ax, tail, vec, color, *, lw=1.2, head=2.2, zorder=6, ls="-"):
    """An arrow in data units; ``head`` in paper mm."""
    from matplotlib.patches import FancyArrowPatch

    tip = np.asarray(tail, float) + np.asarray(vec, float)
    pts_per_mm = 72 / 25.4
    a = FancyArrowPatch(
        tuple(tail),
        tuple(tip),
        arrowstyle=f"-|>,head_length={head * pts_per_mm:.2f},"
        f"head_width={head * pts_per_mm * 0.38:.2f}",
        color=color,
        lw=lw,
        shrinkA=0,
        shrinkB=0,
        zorder=zorder,
        linestyle=ls,
        mutation_scale=1,
    )
    _add(ax, a)
    return a


def _moment_arc(ax, centre, radius, moment, color, zorder=6):
    from matplotlib.patches import FancyArrowPatch
    from matplotlib.path import Path as MPath

    sgn = 1.0 if moment >= 0 else -1.0
    t = np.radians(np.linspace(200, 200 + sgn * 250, 30))
    pts = np.column_stack((centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)))
    pts_per_mm = 72 / 25.4
    a = FancyArrowPatch(
        path=MPath(pts),
        arrowstyle=f"-|>,head_length={2.2 * pts_per_mm:.2f},"
        f"head_width={2.2 * pts_per_mm * 0.38:.2f}",
        color=color,
        lw=1.1,
        zorder=zorder,
        mutation_scale=1,
    )
    _add(ax, a)
    return a


def _add(ax, patch):
    """Add a patch without updating data limits (the drawings' limits are fixed)."""
    ax.add_artist(patch)
    return patch


_SUBSCRIPT = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def _sub(label: str) -> str:
    """Trailing digits as Unicode subscripts: ``F12`` -> ``F₁₂`` (plain text, fast)."""
    m = re.match(r"^(.*?)(\d+)$", label)
    return label if not m else m.group(1) + m.group(2).translate(_SUBSCRIPT)


def _label_offset(p, centre, dist):
    d = np.asarray(p, float) - centre
    n = float(np.hypot(*d))
    u = d / n if n > 1e-12 else np.array([0.7071, 0.7071])
    return p + dist * u


# -- nothing drawn outside the paper -------------------------------------------------
MIN_AXES_MM = (120.0, 80.0)  # the smallest drawing area of a true-scale drawing


def _renderer(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    _mend_math(fig)  # before any text is measured
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    renderer = canvas.get_renderer()
    share(renderer)
    return renderer


def _axes_mm(fig, ax) -> list[float]:
    """[left, bottom, width, height] of the axes on the sheet, mm."""
    W, H = fig.get_size_inches() / MM
    x0, y0, w, h = ax.get_position().bounds
    return [x0 * W, y0 * H, w * W, h * H]


def _place(fig, ax, left, bottom, w, h, W, H) -> None:
    fig.set_size_inches(W * MM, H * MM)
    ax.set_position([left / W, bottom / H, w / W, h / H])


def _inside_axes(fig, ax, artists, pad_mm: float = 1.5, rounds: int = 4) -> None:
    """Grow the data limits (and the axes with them, so the scale stays) until every
    artist of ``artists`` (labels, arrows) lies inside the axes."""
    for _ in range(rounds):
        r = _renderer(fig)
        box = ax.get_window_extent(r)
        ext = [a.get_window_extent(r) for a in artists if a.get_visible()]
        ext = [e for e in ext if np.all(np.isfinite(e.extents)) and e.width >= 0]
        if not ext:
            return
        px_mm = fig.dpi * MM  # pixels per paper mm
        pad = pad_mm * px_mm
        over = [
            max(0.0, box.x0 + pad - min(e.x0 for e in ext)),
            max(0.0, max(e.x1 for e in ext) - box.x1 + pad),
            max(0.0, box.y0 + pad - min(e.y0 for e in ext)),
            max(0.0, max(e.y1 for e in ext) - box.y1 + pad),
        ]
        if max(over) < 0.5:
            return
        over_mm = [o / px_mm for o in over]
        left, bottom, w, h = _axes_mm(fig, ax)
        W, H = fig.get_size_inches() / MM
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        per_mm = (x1 - x0) / w  # data units per paper mm
        ax.set_xlim(x0 - over_mm[0] * per_mm, x1 + over_mm[1] * per_mm)
        ax.set_ylim(y0 - over_mm[2] * per_mm, y1 + over_mm[3] * per_mm)
        w2, h2 = w + over_mm[0] + over_mm[1], h + over_mm[2] + over_mm[3]
        _place(fig, ax, left, bottom, w2, h2, W + w2 - w, H + h2 - h)


_DEFER: list[bool] = []  # inside crop.drawn_once(): the layouts below noted, done when saved


def _noted(fig, kind: str, ax, pad_mm: float) -> bool:
    """Inside :func:`.crop.drawn_once`, note the layout on ``fig`` (a Sheet) for
    :func:`.crop.save_png` instead of doing it now."""
    if not _DEFER or not hasattr(fig, "_layout_todo"):
        return False
    fig._layout_todo = (kind, ax, pad_mm)
    return True


def _lay_out(fig) -> None:
    """Do the layout noted on ``fig`` now (two passes: measured, then drawn), its texts
    measured in the style it is drawn in (:class:`Sheet`), wherever it is laid out: a
    polygon choosing its scale, or ``savefig``, after the style's context was left, had
    its sheet sized around texts in matplotlib's defaults (10 pt, another math face, no
    CJK font), not around the ones drawn."""
    todo = getattr(fig, "_layout_todo", None)
    if todo is None:
        return
    fig._layout_todo = None
    kind, ax, pad = todo
    matplotlib, _ = _mpl()
    with matplotlib.rc_context(getattr(fig, "_style", None) or {}):
        if kind == "sheet":
            _fit_sheet(fig, ax, pad, now=True)
        else:
            _grow_to_fit(fig, pad, now=True)


def _fit_sheet(fig, ax, pad_mm: float = 2.0, *, now: bool = False) -> None:
    """Size the sheet around everything drawn (title, tick and axis labels, texts),
    keeping the axes' size in mm: nothing is cut and the true scale holds.  Inside
    :func:`.crop.drawn_once` (unless ``now``) noted, and done when the PNG is saved."""
    if not now and _noted(fig, "sheet", ax, pad_mm):
        return
    r = _renderer(fig)
    tight = fig.get_tightbbox(r)  # inches
    W, H = fig.get_size_inches() / MM
    left, bottom, w, h = _axes_mm(fig, ax)
    tx0, ty0, tx1, ty1 = (v / MM for v in tight.extents)
    new_left = left - tx0 + pad_mm
    new_bottom = bottom - ty0 + pad_mm
    new_W = new_left + (tx1 - left) + pad_mm
    new_H = new_bottom + (ty1 - bottom) + pad_mm
    _place(fig, ax, new_left, new_bottom, w, h, new_W, new_H)


def _wrap(text: str, width_mm: float, size_pt: float) -> str:
    """Break a plain text line into lines of about ``width_mm`` at ``size_pt``."""
    import textwrap

    chars = max(20, int(width_mm / (0.52 * size_pt * 25.4 / 72)))
    return "\n".join("\n".join(textwrap.wrap(line, chars) or [""]) for line in text.split("\n"))


def _dodge(fig, ax, labels, fixed=(), step_mm: float = 2.0) -> None:
    """Move each label of ``labels`` (in order) around its anchor until it overlaps no
    label placed before it nor any of ``fixed``, and stays inside the axes if it can."""
    r = _renderer(fig)
    box = ax.get_window_extent(r)
    placed = [a.get_window_extent(r).expanded(1.02, 1.08) for a in fixed if a.get_visible()]
    px = fig.dpi * MM * step_mm
    moves = [(0, 0)] + [
        (dx * s, dy * s)
        for s in (1, 2, 3, 4.5, 6, 8, 10)
        for dx, dy in ((0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (-1, 1), (1, -1), (-1, -1))
    ]
    for t in labels:
        x, y = t.get_position()
        home = ax.transData.transform((x, y))
        best = None
        for dx, dy in moves:
            t.set_position(ax.transData.inverted().transform(home + (dx * px, dy * px)))
            e = t.get_window_extent(r)
            inside = box.x0 <= e.x0 and e.x1 <= box.x1 and box.y0 <= e.y0 and e.y1 <= box.y1
            clear = not any(e.overlaps(p) for p in placed)
            if clear and inside:
                best = (dx, dy)
                break
            if clear and best is None:
                best = (dx, dy)
        dx, dy = best if best is not None else (0, 0)
        t.set_position(ax.transData.inverted().transform(home + (dx * px, dy * px)))
        placed.append(t.get_window_extent(r).expanded(1.02, 1.08))


def _grow_to_fit(fig, pad_mm: float = 1.5, *, now: bool = False) -> None:
    """Grow a figure of curves by whatever of its labels would fall off an edge, moving
    every axes by the same amount and keeping its size.  Inside :func:`.crop.drawn_once`
    (unless ``now``) noted, and done when the PNG is saved."""
    if not now and _noted(fig, "grow", None, pad_mm):
        return
    r = _renderer(fig)
    tight = fig.get_tightbbox(r)  # inches
    Wi, Hi = fig.get_size_inches()
    pad = pad_mm * MM
    left = max(0.0, pad - tight.x0)
    bottom = max(0.0, pad - tight.y0)
    right = max(0.0, tight.x1 - Wi + pad)
    top = max(0.0, tight.y1 - Hi + pad)
    if max(left, bottom, right, top) <= 0.01 * MM:
        return
    _move(fig, left, bottom, Wi + left + right, Hi + bottom + top)


def _move(fig, dx: float, dy: float, W: float, H: float) -> None:
    """Resize ``fig`` to ``W × H`` inches, moving its axes and texts by ``dx, dy`` inches
    and keeping their sizes."""
    Wi, Hi = fig.get_size_inches()
    boxes = [(a, a.get_position().bounds) for a in fig.axes]
    texts = [(t, t.get_position()) for t in fig.texts]
    fig.set_size_inches(W, H)
    for a, (x0, y0, w, h) in boxes:
        a.set_position([(x0 * Wi + dx) / W, (y0 * Hi + dy) / H, w * Wi / W, h * Hi / H])
    for t, (x, y) in texts:
        t.set_position(((x * Wi + dx) / W, (y * Hi + dy) / H))


COURSE_TICKS = (2.0, 1.0, 6.5, 2.0)  # tick length, label pad, font size, axis label pad (pt)


def _course_axis(ax, numbered, label: str) -> None:
    """The course positions numbered along the top edge of ``ax`` as a secondary x axis
    there draws them — the top spine, ticks 2 pt out, labels 1 pt above the ticks, the
    axis label 2 pt above the labels — from one line of tick marks and plain texts: a
    secondary axis is an axes of its own, with a tick object per position (a tenth of
    making and saving the torque curves)."""
    import matplotlib
    from matplotlib import lines as mlines

    if not numbered:
        return
    length, pad, size, labelpad = COURSE_TICKS
    rc = matplotlib.rcParams
    out = rc["xtick.direction"] != "in"
    ax.spines["top"].set_visible(True)
    xs = [x for x, _ in numbered]
    marks = mlines.Line2D(
        xs,
        np.ones(len(xs)),
        transform=ax.get_xaxis_transform(),
        linestyle="none",
        marker=mlines.TICKUP if out else mlines.TICKDOWN,
        markersize=length,
        markeredgewidth=rc["xtick.major.width"],
        color=rc["xtick.color"],
        clip_on=False,
    )
    ax.add_artist(marks)
    # the labels where a tick's second label goes: pad (+ length) above the edge
    at, va, ha = ax.get_xaxis_text2_transform(pad + (length if out else 0.0))
    color = rc["xtick.color"] if rc["xtick.labelcolor"] == "inherit" else rc["xtick.labelcolor"]
    texts = [
        ax.text(x, 1.0, t, transform=at, va=va, ha=ha, fontsize=size, color=color)
        for x, t in numbered
    ]
    # the axis label centred, its baseline labelpad above the labels' top (as an x axis
    # sets its label on top; the labels all of one height)
    ax.annotate(
        label,
        xy=(0.5, 1.0),
        xycoords=(ax.transAxes, texts[0]),
        xytext=(0.0, labelpad),
        textcoords="offset points",
        va="baseline",
        ha="center",
        fontsize=size,
        annotation_clip=False,
    )
