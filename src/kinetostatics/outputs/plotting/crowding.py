"""Labels of crowded points set apart by one deterministic rule (:func:`place_labels`).

The instant centres and the force polygons put many short labels (P13, F_R23) on few
points: a pin carries several centres, a polygon's vertices several arrows.  Each label is
set at its point, offset along its normal (an arrow's normal, or away from the point's
neighbours) by a few points, on the first side of eight whose box meets no box placed
before it (the primary labels first, then the secondary ones, each in the order given),
nor the texts already on the axes; where every side is taken, the side it meets least.
A label of the same text at the same point as one placed is skipped, and labels of
different texts at one point are written as one ("P14, P16").  Secondary labels take a
smaller font.  The sizes are estimated from the font size (no drawing is needed), so the
placement is the same on every machine.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Label", "place_labels"]

PRIMARY, SECONDARY = 7.0, 6.0  # font sizes, pt
SAME = 1.5  # points closer than this (pt) are one point
GAP = 2.5  # between a point and its label's box, pt


@dataclass(frozen=True)
class Label:
    """A label ``text`` (mathtext allowed) at ``xy`` (data), pushed along ``normal`` (a
    direction in data axes, or None: away from its neighbours); ``primary`` labels are
    placed first and larger."""

    text: str
    xy: tuple[float, float]
    color: str = "black"
    normal: tuple[float, float] | None = None
    primary: bool = True
    gid: str | None = None


def _plain(text: str) -> str:
    return text.replace("$", "").replace("{", "").replace("}", "").replace("_", "")


def _size(text: str, fs: float) -> tuple[float, float]:
    """(width, height) of a label's box in pt, with a margin: about 0.65 em a character
    (a CJK one 1 em)."""
    plain = _plain(text)
    wide = sum(1 for c in plain if ord(c) > 0x2E80)
    return fs * (0.65 * (len(plain) - wide) + wide) + 3.0, 1.5 * fs


def _overlap(a, b) -> float:
    """The area two boxes (x0, y0, x1, y1) share."""
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return w * h if w > 0 and h > 0 else 0.0


def _directions(normal, away) -> list[np.ndarray]:
    """Eight unit directions (pt), the preferred first: the normal, its opposite, then the
    others by their angle from it."""
    first = normal if normal is not None else away
    first = np.zeros(2) if first is None else np.asarray(first, float)
    if not np.any(first):
        first = np.array([1.0, -1.0])
    base = np.arctan2(first[1], first[0])
    turns = (0, 180, 45, -45, 135, -135, 90, -90) if normal is not None else (
        0, 45, -45, 90, -90, 135, -135, 180)  # fmt: skip
    return [np.array([np.cos(base + np.radians(t)), np.sin(base + np.radians(t))]) for t in turns]


def _merged(labels: list[Label], pts: np.ndarray) -> list[tuple[Label, np.ndarray]]:
    """Labels at one point as one; the same text twice once."""
    out: list[tuple[Label, np.ndarray, list[str]]] = []
    for lab, p in zip(labels, pts):
        for other, q, texts in out:
            if np.hypot(*(p - q)) <= SAME and other.primary == lab.primary:
                if lab.text not in texts:
                    texts.append(lab.text)
                break
        else:
            out.append((lab, p, [lab.text]))
    return [(Label(", ".join(t), o.xy, o.color, o.normal, o.primary, o.gid), p) for o, p, t in out]


def _renderer(fig):
    """A renderer that measures the texts on the figure (None where none is at hand)."""
    get = getattr(fig.canvas, "get_renderer", None) or getattr(fig, "_get_renderer", None)
    try:
        return get() if get is not None else None
    except (AttributeError, TypeError, RuntimeError):
        return None


def place_labels(ax, labels, obstacles: bool = True) -> list:
    """Annotate ``labels`` (:class:`Label`) on ``ax`` apart from each other (module
    docstring); returns the annotations, in the order placed.  ``obstacles``: also keep
    clear of the texts already on the axes."""
    labels = sorted(labels, key=lambda lab: not lab.primary)  # stable: primary first
    if not labels:
        return []
    fig = ax.figure
    to_pt = 72.0 / fig.dpi
    pts = ax.transData.transform(np.array([lab.xy for lab in labels], float)) * to_pt
    taken = []
    renderer = _renderer(fig) if obstacles else None
    if renderer is not None:
        for t in ax.texts:
            b = t.get_window_extent(renderer)
            taken.append((b.x0 * to_pt, b.y0 * to_pt, b.x1 * to_pt, b.y1 * to_pt))
    marks = pts.copy()
    out = []
    for lab, p in _merged(labels, pts):
        fs = PRIMARY if lab.primary else SECONDARY
        w, h = _size(lab.text, fs)
        near = [q for q in marks if 0 < np.hypot(*(p - q)) <= 4 * fs]
        away = sum((p - q) / max(np.hypot(*(p - q)), 1e-9) for q in near) if near else None
        normal = None
        if lab.normal is not None:
            tip = ax.transData.transform(np.array([lab.xy, np.add(lab.xy, lab.normal)]))
            normal = (tip[1] - tip[0]) * to_pt
        best, best_cost = None, np.inf
        for d in _directions(normal, away):
            reach = GAP + 0.5 * (abs(d[0]) * w + abs(d[1]) * h)
            c = p + reach * d
            box = (c[0] - w / 2, c[1] - h / 2, c[0] + w / 2, c[1] + h / 2)
            cost = sum(_overlap(box, o) for o in taken)
            cost += sum(8.0 for q in marks if box[0] < q[0] < box[2] and box[1] < q[1] < box[3])
            if cost < best_cost:
                best, best_cost = (reach * d, box), cost
            if cost == 0.0:
                break
        offset, box = best
        taken.append(box)
        out.append(
            ax.annotate(
                lab.text,
                lab.xy,
                xytext=tuple(offset),
                textcoords="offset points",
                ha="center",
                va="center",
                fontsize=fs,
                color=lab.color,
                zorder=7,
                gid=lab.gid,
            )  # fmt: skip
        )
    return out
