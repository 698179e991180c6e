"""Each picture drawn once (outputs/plotting/crop.py): inside ``drawn_once`` a picture's
layout is noted and done when its PNG is saved, by cropping its one drawing; the PNG
holds the same picture as the two-pass layout, to a few pixels of margin, and the figure
is left at the size the layout gives it."""

import numpy as np
import pytest

pytest.importorskip("matplotlib")


def _picture(kind: str, lang: str = "en"):
    from kinetostatics.outputs.plotting.style import _figure, _fit_sheet, _grow_to_fit, _rc

    with _rc(lang):
        fig = _figure(80, 50)
        ax = fig.add_axes([0.2, 0.2, 0.6, 0.6])
        ax.plot([0, 1, 2], [0, 1, 4])
        ax.set_title(r"a title with $\mu_l$ = 0.004 m/mm, wider than its axes")
        ax.set_xlabel("x, mm")
        ax.text(2.1, 2.0, "a note beyond the axes' right edge", clip_on=False)
        if kind == "sheet":
            _fit_sheet(fig, ax)
        else:
            _grow_to_fit(fig)
    return fig


def _pixels(path):
    from PIL import Image

    return np.asarray(Image.open(path).convert("L")).astype(float) / 255.0


@pytest.mark.parametrize("kind", ["sheet", "grow"])
def test_one_drawing_cropped_is_the_picture_of_the_two_pass_layout(tmp_path, kind):
    from kinetostatics.outputs.plotting.crop import drawn_once, save_png

    dpi = 110
    two = _picture(kind)
    save_png(two, tmp_path / "two.png", dpi)  # made outside drawn_once: laid out at once
    with drawn_once():
        one = _picture(kind)
        assert one._layout_todo is not None  # noted, not done
        before = one.get_size_inches().copy()
        save_png(one, tmp_path / "one.png", dpi)
    assert one._layout_todo is None
    from PIL import Image

    assert Image.open(tmp_path / "one.png").mode == "RGB"  # opaque: no alpha to embed
    a, b = _pixels(tmp_path / "two.png"), _pixels(tmp_path / "one.png")
    px = 25.4 / dpi  # mm per pixel
    # the same size to a few pixels (the ink's box vs the texts' boxes), larger than the
    # figure was made: the title and the note are inside
    assert np.allclose(a.shape, b.shape, atol=4), (a.shape, b.shape)
    assert (np.array(b.shape[::-1]) > before * dpi).any()
    # the figure left as the layout leaves it: its size is the PNG's
    assert np.allclose(one.get_size_inches() * dpi, b.shape[::-1], atol=1.0)
    # the same ink: as many dark pixels, to the antialiasing of the edges
    assert abs((a < 0.5).sum() - (b < 0.5).sum()) <= 0.03 * (a < 0.5).sum()
    # a margin of white all round (nothing cut at an edge): 1 mm at least
    edge = int(1.0 / px)
    for side in (b[:edge], b[-edge:], b[:, :edge], b[:, -edge:]):
        assert side.min() > 0.95


def test_a_picture_saved_otherwise_is_laid_out_as_before(tmp_path):
    """An SVG (or any save but save_png) of a picture whose layout was noted is laid out
    first, in two passes: its size is the layout's."""
    from kinetostatics.outputs.plotting.crop import drawn_once

    ref = _picture("sheet")
    with drawn_once():
        fig = _picture("sheet")
    fig.savefig(tmp_path / "p.svg", format="svg")
    assert fig._layout_todo is None
    assert np.allclose(fig.get_size_inches(), ref.get_size_inches(), atol=1e-6)


def test_a_picture_of_a_fixed_size_is_written_as_savefig_draws_it(tmp_path):
    from kinetostatics.outputs.plotting.crop import drawn_once, save_png
    from kinetostatics.outputs.plotting.style import _figure, _rc

    with drawn_once(), _rc("en"):
        fig = _figure(60, 40)
        fig.add_axes([0.2, 0.2, 0.7, 0.7]).plot([0, 1], [1, 0])
    fig.savefig(tmp_path / "mpl.png", dpi=110, format="png")
    save_png(fig, tmp_path / "one.png", 110)
    assert np.array_equal(_pixels(tmp_path / "mpl.png"), _pixels(tmp_path / "one.png"))


def test_a_polygon_is_laid_out_before_its_scale_is_chosen():
    """A polygon's scale is the next coarser one while its sheet is larger than the text
    area of an A4 page: inside drawn_once its sheet is still laid out when its size is
    asked, so it gets the scale and size it gets outside."""
    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.loading import load
    from kinetostatics.outputs.plotting.crop import drawn_once
    from tests.helpers import ROOT

    result = pl.analyze_for_pictures(load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    ref = pl.polygon_figure(result, "acceleration", row=1)
    with drawn_once():
        fig = pl.polygon_figure(result, "acceleration", row=1)
    assert fig._layout_todo is None
    assert np.allclose(fig.get_size_inches(), ref.get_size_inches(), atol=1e-6)


def test_a_layout_done_after_its_style_measures_the_texts_drawn(tmp_path):
    """A picture laid out once its style's context is left (a polygon choosing its scale,
    a save by ``savefig``) is measured in the style it is drawn in: the Chinese list of a
    cam's acceleration polygon keeps the layout's margin at the right edge (measured in
    matplotlib's defaults, whose math and sans-serif fonts are not the pictures', and
    drawn in the pictures' style, it touched the edge: 0 px of margin)."""
    import warnings

    import kinetostatics as ks
    from kinetostatics.outputs import fonts
    from kinetostatics.outputs.plotting.crop import drawn_once, save_png
    from kinetostatics.outputs.plotting.polygons import polygon_figure
    from kinetostatics.outputs.plotting.style import MM

    try:
        fonts.cjk_font()
    except Exception as exc:  # no font with Chinese glyphs here
        pytest.skip(str(exc))
    dpi = 110
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = ks.analyze(ks.load("mechanisms/cam_roller.yaml"))
    with drawn_once():
        fig = polygon_figure(result, "acceleration", row=0, dpi=dpi, lang="zh")
        save_png(fig, tmp_path / "p.png", dpi)
    b = _pixels(tmp_path / "p.png")
    ink = np.flatnonzero((b < 0.9).any(axis=0))
    pad = 2.0 * MM * dpi  # _fit_sheet's margin, px
    assert b.shape[1] - 1 - ink[-1] >= 0.5 * pad
