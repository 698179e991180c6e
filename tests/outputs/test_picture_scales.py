"""The report's true-scale pictures print at 100 % with a round scale, and the energy
diagram names its quantities apart (issue 37, items 4 and 5)."""

import math
import re

import matplotlib.text
import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.outputs import plotting as pl
from tests.helpers import ROOT

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"
# the picture's room on an A4 page of the PDF: 210 × 297 mm less 14 mm margins, and 14 mm
# below it for the caption
PAGE = (210.0 - 2 * 14.0, 297.0 - 2 * 14.0 - 14.0)
MM = 25.4  # mm per inch


def _round(mu: float) -> bool:
    """Whether ``mu`` is 1, 2, 2.5, 4 or 5 × 10^k."""
    k = math.floor(math.log10(mu))
    return any(math.isclose(mu, m * 10.0**k, rel_tol=1e-12) for m in (1, 2, 2.5, 4, 5, 10))


def _texts(fig) -> list[str]:
    return [t.get_text() for t in fig.findobj(matplotlib.text.Text) if t.get_visible()]


@pytest.fixture(scope="module")
def slotting():
    return ks.analyze(ks.load(SLOTTING))


@pytest.mark.parametrize("kind, sym", [("velocity", "v"), ("acceleration", "a")])
def test_the_polygons_at_position_7_fit_the_page_at_a_round_scale(slotting, kind, sym):
    row = dict(pl.course_positions(slotting))["7"]
    fig = pl.polygon_figure(slotting, kind, row=row, dpi=40)
    title = next(t for t in _texts(fig) if f"\\mu_{sym}$ = " in t)
    mu = float(re.search(rf"\\mu_{sym}\$ = ([0-9.e+-]+)", title).group(1))
    assert _round(mu), title
    width, height = fig.get_size_inches() * MM
    assert width <= PAGE[0] and height <= PAGE[1], (width, height)


def test_the_report_prints_every_drawing_and_polygon_at_100_percent(tmp_path):
    pypdf = pytest.importorskip("pypdf")
    pytest.importorskip("fpdf")
    from kinetostatics.cli import main

    out = tmp_path / "out"
    args = ["report", str(SLOTTING), "--out", str(out), "--dpi", "40", "--format", "pdf"]
    assert main([*args, "--polygons", "2,7"]) == 0
    reader = pypdf.PdfReader(str(out / "report.pdf"))
    text = re.sub(r"\s+", " ", " ".join(p.extract_text() for p in reader.pages))
    assert "reduced to" not in text
    for caption in ("Velocity polygon at position 7.", "Acceleration polygon at position 7."):
        assert f"{caption} (printed at 100 %" in text, caption


@pytest.mark.parametrize("lang", ["en", "zh"])
def test_the_energy_diagram_names_the_swing_once(slotting, lang):
    """ΔW_max is the swing E_max − E_min that sizes the flywheel; the extremes of the
    curve ΔW(φ) are marked with their own names, and the swing is their difference."""
    from kinetostatics.dynamics.flywheel import design

    if lang == "zh":
        from kinetostatics.outputs import fonts
        from kinetostatics.outputs import lang as language

        try:
            fonts.cjk_font()
        except language.LanguageError:
            pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    dsg = design(slotting)
    texts = _texts(pl.energy_diagram(dsg, slotting, dpi=40, lang=lang))
    named = [t for t in texts if "ΔW_max" in t]
    assert len(named) == 1, named
    swing = float(re.search(r"= ([0-9.e+-]+) J", named[0]).group(1))
    assert swing == pytest.approx(dsg.energy_swing, rel=1e-4)
    ext = {}
    for word in ("max", "min"):
        (t,) = [t for t in texts if t.startswith(f"E_{word}")]
        ext[word] = float(re.search(r"ΔW = ([0-9.e+-]+) J", t).group(1))
    assert ext["max"] > 0 > ext["min"]
    assert ext["max"] - ext["min"] == pytest.approx(swing, rel=1e-3)  # 4 digits each
    assert np.isfinite(swing)


def _scale_and_size(fig):
    title = next(t.get_text() for t in fig.findobj(matplotlib.text.Text) if "/mm" in t.get_text())
    return re.search(r"= (\S+) \(", title).group(1), tuple(np.round(fig.get_size_inches() * MM, 6))


def _polygons_by_both_ways(monkeypatch, path, rows, fits, langs=("en",)):
    """Each polygon's scale and sheet size with the scales that cannot fit skipped, and
    with every scale drawn and laid out (the skip turned off)."""
    from kinetostatics.outputs.plotting import polygons

    result = ks.analyze(ks.load(path))
    n = len(result.t)
    cases = [(kind, int(f * n), fit, lang) for kind in ("velocity", "acceleration")
             for f in rows for fit in fits for lang in langs]  # fmt: skip
    got = [_scale_and_size(pl.polygon_figure(result, k, row=r, fit_mm=fit, lang=lang, dpi=40))
           for k, r, fit, lang in cases]  # fmt: skip
    skipped = []
    real = polygons._too_large
    monkeypatch.setattr(polygons, "_too_large", lambda *a: skipped.append(real(*a)) and False)
    want = [_scale_and_size(pl.polygon_figure(result, k, row=r, fit_mm=fit, lang=lang, dpi=40))
            for k, r, fit, lang in cases]  # fmt: skip
    return got, want, skipped


@pytest.mark.parametrize("name", ["slotting_machine", "slider_crank"])
def test_a_scale_whose_sheet_cannot_fit_is_skipped_only_where_it_cannot(monkeypatch, name):
    """A polygon's scale is the first round one whose laid-out sheet fits ``fit_mm``;
    the scales whose sheet is larger whatever its texts (its axes and its list of vectors
    alone) are not drawn: every polygon gets the scale and the sheet it gets with every
    scale drawn and laid out, and some scales were skipped."""
    got, want, skipped = _polygons_by_both_ways(
        monkeypatch,
        ROOT / "mechanisms" / f"{name}.yaml",
        (0.0, 0.5),
        (None, (170.0, 200.0), (120.0, 100.0)),
    )
    assert got == want
    assert any(skipped)


@pytest.mark.slow
@pytest.mark.parametrize("path", sorted((ROOT / "mechanisms").glob("*.yaml")), ids=lambda p: p.stem)
def test_every_polygon_skips_only_the_scales_that_cannot_fit(monkeypatch, path):
    """The same for every shipped mechanism whose polygons the method draws, at four
    positions, three page sizes and both languages."""
    try:
        got, want, _ = _polygons_by_both_ways(
            monkeypatch, path, (0.0, 0.25, 0.5, 0.75), (None, (170.0, 257.0), (120.0, 100.0)),
            ("en", "zh"),
        )  # fmt: skip
    except (pl.PictureError, ks.StructureError) as exc:  # no polygon, or effort-driven
        pytest.skip(str(exc))
    assert got == want
