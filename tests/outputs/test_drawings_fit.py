"""Pictures never clip: for every shipped mechanism with motion drivers, every text and
arrow of the drawing (with and without the loads), the polygons and the curves lies inside
its figure (matplotlib's renderer extents within ``fig.bbox``), the loads' arrows and labels
inside the axes and the labels of the loads clear of each other; the title states μ_l (and
μ_F); the drawing area is at least 120 × 80 mm whatever the mechanism's aspect; no label
prints a value below round-off; GIF frames are large enough for the loads."""

import re

import numpy as np
import pytest

from tests.helpers import ROOT, motion_driven

pytest.importorskip("matplotlib")

SHIPPED = sorted(p.stem for p in (ROOT / "mechanisms").glob("*.yaml"))
MOTION = motion_driven()  # the effort-driven files are simulated, not analysed


@pytest.fixture(scope="module")
def results():
    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.loading import load

    return {
        m: pl.analyze_for_pictures(load(ROOT / "mechanisms" / f"{m}.yaml"), course=True)
        for m in MOTION
    }


def _renderer(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()  # legends and tick labels take their places when drawn
    return canvas.get_renderer()


def _artists(fig):
    from matplotlib.patches import FancyArrowPatch
    from matplotlib.text import Text

    ticks = {
        id(t)
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
        for tick in axis.get_major_ticks() + axis.get_minor_ticks()
        for t in (tick.label1, tick.label2)
    }
    out = []
    for a in fig.findobj(lambda a: isinstance(a, (Text, FancyArrowPatch))):
        if id(a) in ticks:  # tick labels: checked through the axes' tight box
            continue
        if not a.get_visible() or (isinstance(a, Text) and not a.get_text().strip()):
            continue
        out.append(a)
    return out


def _inside(inner, outer, tol=1.0):
    return (
        inner.x0 >= outer.x0 - tol
        and inner.y0 >= outer.y0 - tol
        and inner.x1 <= outer.x1 + tol
        and inner.y1 <= outer.y1 + tol
    )


_NUMBER = re.compile(r"[-+−]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _no_round_off(texts):
    """No printed number is tiny next to the largest number of its figure (≤ 1e-9 of it)
    unless printed as 0, and none is printed with an exponent below −9."""
    values = []
    for t in texts:
        for m in _NUMBER.findall(t.replace("−", "-")):
            assert not re.search(r"e-(1\d|[2-9]\d)", m), (m, t)
            values.append(abs(float(m)))
    big = max(values, default=0.0)
    for v in values:
        assert v == 0.0 or v > 1e-9 * big


def _check_figure(fig):
    r = _renderer(fig)
    box = fig.bbox
    arts = _artists(fig)
    for a in arts:
        e = a.get_window_extent(r)
        assert _inside(e, box), (a, e, box)
    for ax in fig.axes:  # the drawn ticks and their labels
        assert _inside(ax.get_tightbbox(r), box), ax
    _no_round_off([a.get_text() for a in arts if hasattr(a, "get_text")])
    return r, arts


@pytest.mark.parametrize("name", MOTION)
def test_drawings_keep_everything_on_the_sheet(name, results):
    from kinetostatics.outputs import plotting as pl

    result = results[name]
    course = dict(pl.course_positions(result))
    rows = [course[p] for p in ("1", "4", "7", "10") if p in course] or [0]
    for forces in (False, True):
        for k in rows if forces else rows[:1]:
            fig = pl.draw_mechanism(result, row=k, forces=forces, dpi=40)
            r, arts = _check_figure(fig)
            ax = fig.axes[0]
            title = ax.get_title(loc="left")
            assert "μ_l" in title.replace("$\\mu_l$", "μ_l")
            assert ("mu_F" in title) == forces
            w_mm, h_mm = (ax.get_window_extent(r).size / fig.dpi) * 25.4
            assert w_mm >= 120 - 0.5 and h_mm >= 80 - 0.5
            axes_box = ax.get_window_extent(r)
            loads = [a for a in arts if getattr(a, "get_gid", lambda: None)() == "load-label"]
            arrows = [a for a in arts if type(a).__name__ == "FancyArrowPatch"]
            for a in loads + arrows:
                assert _inside(a.get_window_extent(r), axes_box), a
            boxes = [a.get_window_extent(r) for a in loads]
            for i in range(len(boxes)):
                for j in range(i):
                    overlap = (
                        min(boxes[i].x1, boxes[j].x1) - max(boxes[i].x0, boxes[j].x0),
                        min(boxes[i].y1, boxes[j].y1) - max(boxes[i].y0, boxes[j].y0),
                    )
                    assert min(overlap) <= 1.0, (loads[i].get_text(), loads[j].get_text())


@pytest.mark.parametrize("name", MOTION)
def test_polygons_and_curves_keep_everything_on_the_sheet(name, results):
    from kinetostatics.outputs import plotting as pl

    result = results[name]
    figs = [pl.polygon_figure(result, kind, row=0, dpi=40) for kind in ("velocity", "acceleration")]
    figs += [pl.torque_curves(result, d.name, dpi=40) for d in result.system.motion_drivers]
    figs += [pl.motion_diagram(result, dpi=40), pl.reaction_curves(result, dpi=40)]
    for fig in figs:
        _check_figure(fig)


def test_a_tall_narrow_mechanism_gets_a_legible_sheet():
    """A vertical slider-crank (100 mm wide, 600 mm tall): the sheet is at least 120 mm
    of drawing area wide at the drawing's scale, not a strip."""
    import kinetostatics as ks
    from kinetostatics.outputs import plotting as pl

    text = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    model = ks.loads(text, file="slider_crank.yaml")
    result = pl.analyze_for_pictures(model)
    fig = pl.draw_mechanism(result, row=0, forces=True, dpi=40)
    r, _ = _check_figure(fig)
    w, h = fig.get_size_inches() * 25.4
    assert w >= 120 and h >= 80


def test_a_moment_below_round_off_is_not_printed():
    """The slider of a slider-crank has no inertia couple (it does not turn): its
    MI is round-off at most, and no label shows it."""
    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.loading import load

    result = pl.analyze_for_pictures(load(ROOT / "mechanisms" / "stephenson_sixbar.yaml"))
    for k in (0, 90, 200):
        fig = pl.draw_mechanism(result, row=k, forces=True, dpi=40)
        _, arts = _check_figure(fig)
        for a in arts:
            if hasattr(a, "get_text") and "N·m" in a.get_text():
                value = float(a.get_text().split()[-2])
                assert value == 0 or abs(value) > 1e-6


def test_gif_frames_are_large_enough_for_the_loads(tmp_path):
    from PIL import Image

    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.loading import load

    model = load(ROOT / "mechanisms" / "slotting_machine.yaml")
    result = pl.analyze_for_pictures(model, frames=4, events=False)
    path = pl.animate(result, tmp_path / "a.gif", forces=True)
    with Image.open(path) as im:
        w, h = im.size
    assert w >= 600 and h >= 400
    assert np.isfinite(w)
