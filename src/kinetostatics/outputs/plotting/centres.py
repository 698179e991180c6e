"""The instant centres drawn with the mechanism at their position (:func:`centres_figure`).

The picture reads the plain data of an instant-centres record (``InstantCentres.to_dict()``
of ``kinetostatics.methods.centres``, or the record itself): the mechanism is drawn at the
record's row by :func:`~.draw.draw_mechanism`, each centre inside the sheet as a point
labelled ``P_ij`` with the picture's link numbers, and those outside it, at infinity or not
found listed under it.  The labels are set apart by ``crowding.place_labels``: centres at
one point share one label (``P14, P16``), a pair's own centre (at its pin) is secondary,
smaller and lighter, the ones Kennedy's theorem found are placed first.
"""

from __future__ import annotations

import numpy as np

from ..labels import link_numbers
from ..lang import tr
from .crowding import Label, place_labels
from .draw import draw_mechanism
from .style import DPI, MM, _fit_sheet, _rc, _wrap

__all__ = ["centres_figure", "centre_label"]

CENTRE_COLOR = "#b2182b"
PIN_COLOR = "#d6604d"  # a centre at a pair's own pin: lighter, smaller (crowding.py)


def centre_label(bodies, numbers: dict[str, int]) -> str:
    """``P_ij`` of a pair of bodies, the smaller number first (P13 of links 1 and 3)."""
    a, b = sorted(numbers[n] for n in bodies)
    return f"P{a}{b}" if max(a, b) < 10 else f"P{a},{b}"


def _plain(record) -> dict:
    to_dict = getattr(record, "to_dict", None)
    return to_dict() if callable(to_dict) else dict(record)


def centres_figure(result, record, *, dpi: float = DPI, lang: str = "en"):
    """The mechanism at the record's row with its instant centres.

    Parameters
    ----------
    result : Result
        The analysis the record was computed from.
    record : InstantCentres or dict
        The instant centres at one row, or their ``to_dict()``.

    Returns
    -------
    matplotlib.figure.Figure
        The drawing of :func:`draw_mechanism` (axes in mm, true scale μ_l), the centres
        inside it marked and labelled ``P_ij``; a note under it lists the others.
    """
    data = _plain(record)
    fig = draw_mechanism(result, row=int(data["row"]), dpi=dpi, lang=lang)
    ax = fig.axes[0]
    numbers = link_numbers(result.system)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    far, infinite, missing, labels = [], [], [], []
    with _rc(lang):
        for c in data["centres"]:
            label = centre_label(c["bodies"], numbers)
            if c["xy"] is None:
                missing.append(label)
                continue
            x, y = (1e3 * v for v in c["xy"])
            if c["at_infinity"]:
                angle = np.degrees(np.arctan2(c["xy"][1], c["xy"][0])) % 180.0
                infinite.append(f"{label} ∞ ({angle:.1f}°)")
            elif x0 <= x <= x1 and y0 <= y <= y1:
                ax.plot([x], [y], "o", ms=4.0, mfc="white", mec=CENTRE_COLOR, zorder=6)
                primary = c["how"] != "joint"  # a pair's own centre is its pin: secondary
                color = CENTRE_COLOR if primary else PIN_COLOR
                labels.append(Label(label, (x, y), color, primary=primary, gid="instant-centre"))
            else:
                far.append(f"{label} ({x:.0f}, {y:.0f}) mm")
        place_labels(ax, labels)
        _note(ax, far, infinite, missing, lang)
    return fig


def _note(ax, far, infinite, missing, lang) -> None:
    """The centres not drawn, in lines under the axes."""
    lines = []
    if far:
        lines.append(tr("outside the drawing: {items}", lang, items="; ".join(far)))
    if infinite:
        lines.append(tr("at infinity (direction): {items}", lang, items="; ".join(infinite)))
    if missing:
        lines.append(tr("not found by Kennedy's theorem: {items}", lang, items=", ".join(missing)))
    if not lines:
        return
    width_mm = ax.get_window_extent().width / ax.figure.dpi / MM
    text = _wrap("\n".join(lines), width_mm, 6.5)
    ax.annotate(
        text,
        (0.0, 0.0),
        xycoords="axes fraction",
        xytext=(0, -26),
        textcoords="offset points",
        fontsize=6.5,
        va="top",
        gid="instant-centres-note",
    )
    _fit_sheet(ax.figure, ax)  # the sheet grows to hold the note; the axes keep their mm
