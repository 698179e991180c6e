"""Each picture drawn once: a PNG laid out around its texts by cropping one drawing.

A picture is sized around everything it draws (:func:`.style._fit_sheet`: the sheet
around its axes, whose size in mm holds the scale; :func:`.style._grow_to_fit`: a figure
of curves grown by whatever would fall off an edge).  Done as the picture is made, that
is a pass that lays out and measures every text and tick (a tight bounding box) at one
size, then the drawing at the final size by a new renderer: two passes.

Inside :func:`drawn_once` (the ``plot`` and ``report`` commands) the two functions only
note what they would do, and :func:`save_png` draws the picture once on a canvas with
:data:`ROOM` mm more on every side, takes the box of what was drawn from that drawing's
pixels (every pixel that is not the background, and the axes' boxes), and crops the
canvas to it with the layout's margin.  The box of the ink is up to a few pixels inside
the box matplotlib's layout measures (a text's box holds its line's whole height), so a
picture's margins may be that much narrower; the drawing itself is the same.  The
figure is left at that size and place, as the layout would have left it (the report
reads its size in mm).  A picture whose drawing reaches beyond the room, one saved any
other way (SVG, PDF: ``Sheet.savefig``), and one whose size is asked before it is saved
(a polygon choosing its scale: :func:`.style._lay_out`) is laid out as before, in two
passes.
"""

from __future__ import annotations

import contextlib

import numpy as np

from .style import _DEFER, MM, _move

__all__ = ["ROOM", "drawn_once", "save_png"]

ROOM = 60.0  # mm of canvas added on each side for the one drawing


@contextlib.contextmanager
def drawn_once():
    """Within it, the pictures made are laid out when saved (:func:`save_png`)."""
    _DEFER.append(True)
    try:
        yield
    finally:
        _DEFER.pop()


def _movable(fig) -> bool:
    """Whether moving the axes and the figure's texts moves everything of ``fig``."""
    return (
        all(t.get_transform() == fig.transFigure for t in fig.texts)
        and not fig.legends
        and not fig.lines
        and not fig.patches
        and not fig.images
    )


def _drawn(pixels, fig, dpi: float, Hb: float) -> tuple[float, float, float, float]:
    """The box (x0, y0, x1, y1 in inches from the lower left) of what was drawn: every
    pixel other than the background (the room's corner), and every axes' box (blank
    where no grid line reaches its edge)."""
    # one 32-bit word a pixel: one comparison each, not four and a reduction over them
    words = np.ascontiguousarray(pixels).view(np.uint32)[..., 0]
    ink = words != words[0, 0]
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    H_px = Hb * dpi
    boxes = [a.get_window_extent().extents for a in fig.axes if a.get_visible()]
    if rows.size:  # pixel edges: the ink's first and last pixels whole
        boxes.append((cols[0], H_px - rows[-1] - 1, cols[-1] + 1, H_px - rows[0]))
    x0, y0 = min(b[0] for b in boxes), min(b[1] for b in boxes)
    x1, y1 = max(b[2] for b in boxes), max(b[3] for b in boxes)
    return x0 / dpi, y0 / dpi, x1 / dpi, y1 / dpi


PNG_LEVEL = 3  # zlib's level: 2/3 of the time of matplotlib's 6, files ~1 % larger


def _write_png(path, rgba, dpi: float) -> None:
    """The pixels as a PNG: RGB when every pixel is opaque (a picture on its white
    sheet; ~10 % smaller, and the PDF report embeds it without an alpha mask), with the
    metadata matplotlib writes."""
    import matplotlib
    from PIL import Image, PngImagePlugin

    info = PngImagePlugin.PngInfo()
    info.add_text(
        "Software", f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/"
    )
    opaque = bool((rgba[..., 3] == 255).all())
    image = Image.fromarray(np.ascontiguousarray(rgba[..., :3] if opaque else rgba))
    image.save(path, format="png", dpi=(dpi, dpi), pnginfo=info, compress_level=PNG_LEVEL)


def save_png(fig, path, dpi: float) -> None:
    """Write ``fig`` as a PNG at ``dpi``, laid out (if its layout was noted) from one
    drawing cropped to the picture."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    todo = getattr(fig, "_layout_todo", None)
    if todo is not None and not _movable(fig):
        fig.savefig(path, dpi=dpi, format="png")  # laid out first, in two passes
        return
    if todo is None:  # a picture of a fixed size: drawn and written as it is
        fig.set_dpi(dpi)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        _write_png(path, np.asarray(canvas.buffer_rgba()), dpi)
        return

    kind, _ax, pad = todo
    fig._layout_todo = None
    fig.set_dpi(dpi)
    Wi, Hi = fig.get_size_inches()
    room = round(ROOM * MM * dpi) / dpi  # whole pixels: the drawing's own pixels cropped
    pad *= MM
    _move(fig, room, room, Wi + 2 * room, Hi + 2 * room)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    pixels = np.asarray(canvas.buffer_rgba())
    Wb, Hb = fig.get_size_inches()
    x0, y0, x1, y1 = _drawn(pixels, fig, dpi, Hb)
    if kind == "sheet":
        box = [x0 - pad, y0 - pad, x1 + pad, y1 + pad]
    else:  # grown by what falls off an edge, never shrunk
        box = [min(room, x0 - pad), min(room, y0 - pad)]
        box += [max(room + Wi, x1 + pad), max(room + Hi, y1 + pad)]
    if box[0] < 0 or box[1] < 0 or box[2] > Wb or box[3] > Hb:  # beyond the room
        _move(fig, -room, -room, Wi, Hi)
        fig._layout_todo = todo
        fig.savefig(path, dpi=dpi, format="png")  # laid out in two passes
        return
    # whole pixels as matplotlib sizes a canvas (the size truncated), rows from the top
    left, bottom = round(box[0] * dpi), round((Hb - box[1]) * dpi)
    right, top = left + int((box[2] - box[0]) * dpi), bottom - int((box[3] - box[1]) * dpi)
    _write_png(path, pixels[top:bottom, left:right], dpi)
    W, H = (right - left) / dpi, (bottom - top) / dpi
    _move(fig, -left / dpi, -(Hb * dpi - bottom) / dpi, W, H)  # as the layout leaves it
