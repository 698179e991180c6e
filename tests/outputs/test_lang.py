"""Chinese (``--lang zh``): no visible text of any shipped mechanism's pictures is left in
English; the CJK font is found in the documented order (KINETOSTATICS_CJK_FONT, system
fonts, the fonts of the ``zh`` extra ``mplfonts``), registered with matplotlib and
embedded in the PDF; the flywheel's assumptions are translated around their numbers; the
report designs the flywheel once.

With the ``zh`` extra installed (it is part of ``test``) these tests run; they skip only
where there is neither mplfonts nor a system CJK font."""

import importlib.util
import math
import re
import sys

import matplotlib.text
import pytest

from kinetostatics.cli import main
from kinetostatics.outputs import fonts, lang
from kinetostatics.outputs import plotting as pl
from kinetostatics.outputs.loading import load
from tests.helpers import ROOT, motion_driven

SHIPPED = sorted(p.stem for p in (ROOT / "mechanisms").glob("*.yaml"))
MOTION = motion_driven()  # the effort-driven files are simulated, not analysed
FAST = {"slider_crank", "slotting_machine"}
HAS_MPLFONTS = importlib.util.find_spec("mplfonts") is not None


def _need_cjk():
    """A CJK font; skip only when neither the zh extra nor a system font is there."""
    try:
        return fonts.cjk_font()
    except lang.LanguageError:
        if HAS_MPLFONTS:
            raise
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")


def _words(text: str) -> set[str]:
    """Latin words of a text (underscored symbols such as M_friction are one word), without
    the ``{fields}`` of a template."""
    return set(re.findall(r"[A-Za-z_]+", re.sub(r"\{[^}]*\}", " ", text)))


def _english_words() -> set[str]:
    """The words of the table's English texts that its Chinese texts do not keep (units,
    symbols, identifiers such as rad, CSV, J_F stay in both)."""
    english = set().union(*(_words(k) for k in lang.ZH))
    kept = set().union(*(_words(v) for v in lang.ZH.values()))
    return {w for w in english - kept if len(w) >= 2}


def _names(model) -> set[str]:
    """The words the user wrote as names: they stay as written in every language."""
    names = [model.name]
    names += [lk.name for lk in model.links] + [p for lk in model.links for p in lk.points]
    names += [j.name for j in model.joints] + [ld.name for ld in model.loads]
    names += [d.name for d in model.drivers]
    return _words(" ".join(names))


def _pictures(result, lang_code):
    model = result.system.model
    course = pl.course_positions(result)
    row = course[1][1] if len(course) > 1 else 0
    figs = {
        "drawing": pl.draw_mechanism(result, row=row, paths=(), lang=lang_code),
        "forces": pl.draw_mechanism(
            result, row=row, forces=True, friction=model.has_friction, lang=lang_code
        ),
        "motion": pl.motion_diagram(result, lang=lang_code),
        "reactions": pl.reaction_curves(result, friction=model.has_friction, lang=lang_code),
        "polar": pl.polar_diagrams(result, friction=model.has_friction, lang=lang_code),
        "velocity": pl.polygon_figure(result, "velocity", row=row, lang=lang_code),
        "acceleration": pl.polygon_figure(result, "acceleration", row=row, lang=lang_code),
    }
    for d in result.system.motion_drivers:
        figs[f"torque {d.name}"] = pl.torque_curves(result, d.name, lang=lang_code)
        if f"{d.name}.efficiency" in result.columns:
            figs[f"efficiency {d.name}"] = pl.efficiency_curve(result, d.name, lang=lang_code)
    if model.flywheel is not None:
        from kinetostatics.dynamics.flywheel import design

        dsg = design(result)
        figs["moments"] = pl.equivalent_moments(dsg, result, lang=lang_code)
        figs["energy"] = pl.energy_diagram(dsg, result, lang=lang_code)
    return figs


def _texts(fig) -> list[str]:
    return [t.get_text() for t in fig.findobj(matplotlib.text.Text) if t.get_visible()]


@pytest.mark.parametrize(
    "name", [pytest.param(m, marks=() if m in FAST else pytest.mark.slow) for m in MOTION]
)
def test_no_english_is_left_in_the_chinese_pictures(name):
    _need_cjk()
    english = _english_words()
    assert {"course", "positions", "reaction", "along", "acting", "pole"} <= english
    model = load(ROOT / "mechanisms" / f"{name}.yaml")
    result = pl.analyze_for_pictures(model, course=True, events=True)
    allowed = _names(model)
    left = []
    for what, fig in _pictures(result, "zh").items():
        for text in _texts(fig):
            bad = (_words(text) & english) - allowed
            if bad:
                left.append((what, sorted(bad), text))
    assert not left, left[:5]
    # the check can fail: the English pictures are full of these words
    en = " ".join(t for f in _pictures(result, "en").values() for t in _texts(f))
    assert len((_words(en) & english) - allowed) > 10


# -- the font ----------------------------------------------------------------------------
@pytest.fixture
def fresh(monkeypatch):
    """No font remembered from an earlier call, no KINETOSTATICS_CJK_FONT."""
    monkeypatch.setattr(fonts, "_FOUND", {})
    monkeypatch.delenv("KINETOSTATICS_CJK_FONT", raising=False)
    return monkeypatch


@pytest.mark.skipif(not HAS_MPLFONTS, reason="the zh extra (mplfonts) is not installed")
def test_the_font_order(fresh, tmp_path):
    from matplotlib import font_manager as fm

    shipped = fonts._mplfonts_font()
    assert shipped is not None and shipped.endswith("SimHei.ttf")  # TrueType first
    assert "mplfonts" not in sys.modules  # found, not imported (its init rewrites rc)
    # 1. the environment variable wins over everything
    fresh.setattr(fonts, "_system_font", lambda: "/no/such/system/font.ttf")
    fresh.setenv("KINETOSTATICS_CJK_FONT", shipped)
    family, path = fonts.cjk_font()
    assert path == shipped
    # 2. then a system font
    fresh.delenv("KINETOSTATICS_CJK_FONT")
    fresh.setattr(fonts, "_FOUND", {})
    fresh.setattr(fonts, "_system_font", lambda: shipped)  # stands for an installed font
    assert fonts.cjk_font()[1] == shipped
    # 3. then the fonts of mplfonts, registered with matplotlib's font manager
    fresh.setattr(fonts, "_FOUND", {})
    fresh.setattr(fonts, "_system_font", lambda: None)
    family, path = fonts.cjk_font()
    assert path == shipped and family == "SimHei"
    assert path in {f.fname for f in fm.fontManager.ttflist}
    assert fm.findfont(fm.FontProperties(family=family), fallback_to_default=False) == path
    # 4. nothing: the message says what to install
    fresh.setattr(fonts, "_FOUND", {})
    fresh.setattr(fonts, "_mplfonts_font", lambda: None)
    with pytest.raises(lang.LanguageError) as err:
        fonts.cjk_font()
    assert "pip install 'kinetostatics[zh]'" in str(err.value)
    assert "KINETOSTATICS_CJK_FONT" in str(err.value)


@pytest.mark.skipif(not HAS_MPLFONTS, reason="the zh extra (mplfonts) is not installed")
def test_the_pdf_embeds_the_font_of_the_zh_extra(fresh, tmp_path):
    pypdf = pytest.importorskip("pypdf")
    pytest.importorskip("fpdf")
    fresh.setattr(fonts, "_system_font", lambda: None)  # as on a machine without CJK fonts
    code = main(
        [
            "report",
            str(ROOT / "mechanisms" / "slider_crank.yaml"),
            "--out",
            str(tmp_path),
            "--dpi",
            "40",
            "--format",
            "pdf",
            "--lang",
            "zh",
        ]
    )
    assert code == 0
    reader = pypdf.PdfReader(str(tmp_path / "report.pdf"))
    text = "".join(page.extract_text() for page in reader.pages)
    for heading in ("1. 原始数据", "2. 机构结构分析", "6. 全周期曲线", "8. 运动副反力极坐标图"):
        assert re.sub(r"\s+", "", heading) in re.sub(r"\s+", "", text), heading
    assert "\x00" not in text  # a TrueType font: the text map extracts cleanly
    embedded = {
        str(f.get_object()["/BaseFont"])
        for page in reader.pages
        for f in page["/Resources"]["/Font"].values()
    }
    assert any(f.endswith("SimHei") for f in embedded), embedded


# -- the flywheel chapter ---------------------------------------------------------------
def test_flywheel_assumptions_in_chinese_and_one_design(tmp_path, monkeypatch):
    _need_cjk()
    from kinetostatics.dynamics import flywheel, stages

    calls = []
    design = flywheel.design
    counted = lambda *a, **k: calls.append(1) or design(*a, **k)  # noqa: E731
    monkeypatch.setattr(flywheel, "design", counted)
    monkeypatch.setattr(stages, "design", counted)  # the cycle stage's
    lang.MISSING.clear()
    code = main(
        [
            "report",
            str(ROOT / "mechanisms" / "slotting_machine.yaml"),
            "--out",
            str(tmp_path),
            "--dpi",
            "30",
            "--format",
            "md",
            "--lang",
            "zh",
        ]
    )
    assert code == 0
    assert len(calls) == 1  # the summary's numbers and the chapter's curve: one design
    md = (tmp_path / "report.md").read_text(encoding="utf-8")
    chapter = md[md.index("9. 飞轮设计") :]
    omega = 2 * math.pi * 60 / 60  # the file's motor: 60 rpm
    assert f"ω_m = {omega:.6g} rad/s" in chapter  # the number, in the Chinese sentence
    assert "平衡力矩按曲柄以额定转速" in chapter and "3600 个位置" in chapter
    assert "驱动力矩为常数，等于不计摩擦的平衡力矩的周期平均值" in chapter
    assert "balancing moment" not in chapter and "flywheel on" not in chapter
    assert not lang.MISSING, sorted(lang.MISSING)[:5]
