"""The pictures' one mathtext parser (outputs/plotting/mathtext.py): a formula is parsed
once, and a parse is handed out again only under the settings it was made with."""

import pytest

pytest.importorskip("matplotlib")


def _glyphs(parse):
    return [
        (font.fname, size, index, dx, float(dy)) for font, size, _c, index, dx, dy in parse.glyphs
    ]


def test_a_formula_is_parsed_again_under_other_settings():
    """The sheets are laid out inside the pictures' style (``mathtext.default:
    regular``) and saved outside it: a parse made under one must not be drawn under the
    other (its primes came out small).  Under the same settings the kept parse is given
    again, and it is what a fresh parser makes."""
    import matplotlib
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import MathTextParser

    from kinetostatics.outputs.plotting.mathtext import shared_parser

    parser = shared_parser("path")
    if parser is None:
        pytest.skip("a matplotlib whose parser this module does not know keeps its own")
    prop = FontProperties(size=8.5)
    with matplotlib.rc_context({"mathtext.default": "regular"}):
        regular = parser.parse(r"$p'_{2}$", 110, prop)
        assert parser.parse(r"$p'_{2}$", 110, prop.copy()) is regular
    with matplotlib.rc_context({"mathtext.default": "it"}):
        italic = parser.parse(r"$p'_{2}$", 110, prop)
        fresh = MathTextParser("path").parse(r"$p'_{2}$", 110, prop)
    assert italic is not regular
    assert _glyphs(italic) != _glyphs(regular)
    assert _glyphs(italic) == _glyphs(fresh)


def test_every_renderer_of_a_picture_gets_the_one_parser():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from kinetostatics.outputs.plotting.mathtext import shared_parser
    from kinetostatics.outputs.plotting.style import _figure, _renderer

    if shared_parser("path") is None:
        pytest.skip("a matplotlib whose parser this module does not know keeps its own")
    fig = _figure(40, 30)
    first = _renderer(fig)
    fig.set_size_inches(3, 2)  # another size: another renderer
    second = _renderer(fig)
    assert second is not first
    assert first.mathtext_parser is second.mathtext_parser is shared_parser("path")
    assert isinstance(fig.canvas, FigureCanvasAgg)


def test_a_picture_is_drawn_in_the_settings_it_was_laid_out_in():
    """A picture is made and laid out inside the pictures' style and saved after it: it
    is drawn in the settings it was made in (each of its formulas in the face it was
    measured in), so its formulas are not parsed again when it is saved."""
    import io

    import matplotlib

    from kinetostatics.outputs.plotting.mathtext import shared_parser
    from kinetostatics.outputs.plotting.style import _figure, _rc, _renderer

    parser = shared_parser("path")
    if parser is None:
        pytest.skip("a matplotlib whose parser this module does not know keeps its own")
    with _rc("en"):
        fig = _figure(40, 30)
        fig.text(0.1, 0.5, r"$\mu_{laid\,out}$ = 1 m/mm")
        fig.get_tightbbox(_renderer(fig))  # the layout's pass: the formula measured
    parsed = parser._parsed.cache_info().misses
    fig.savefig(io.BytesIO(), format="png")
    assert parser._parsed.cache_info().misses == parsed
    assert matplotlib.rcParams["mathtext.default"] != "regular"  # the style given back


def test_a_text_is_measured_once_for_the_layout_and_the_drawing(monkeypatch):
    """A picture's texts are measured by its layout's pass; the renderer of its final
    size that draws it uses those sizes instead of measuring every text again, and
    under other settings a text is measured again."""
    import io

    import matplotlib
    from matplotlib.backends.backend_agg import RendererAgg

    from kinetostatics.outputs.plotting.style import _figure, _rc, _renderer

    measured = []
    own = RendererAgg.get_text_width_height_descent

    def counted(self, s, prop, ismath):
        measured.append(s)
        return own(self, s, prop, ismath)

    monkeypatch.setattr(RendererAgg, "get_text_width_height_descent", counted)
    text = "measured once: 12.345 N·m"
    with _rc("en"):
        fig = _figure(60, 30)
        fig.text(0.1, 0.5, text)
        layout = fig.get_tightbbox(_renderer(fig)).width
        fig.set_size_inches(3.0, 1.5)  # another size: another renderer
    fig.savefig(io.BytesIO(), format="png")
    assert measured.count(text) == 1
    with _rc("en"), matplotlib.rc_context({"text.hinting": "none"}):
        fig = _figure(60, 30)
        fig.text(0.1, 0.5, text)
        fig.get_tightbbox(_renderer(fig))
    assert measured.count(text) == 2
    assert layout > 0
