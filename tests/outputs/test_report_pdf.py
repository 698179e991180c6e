"""The report as a paginated PDF, read back with pypdf: every column header of every
table and every course position is on paper, for each shipped mechanism with motion
drivers; several turns (two motors, 60 : −90 rpm, sweep 720°) name the turn of each
position and serve each driver; Chinese labels need a CJK font and say so when there is
none (with the zh extra, part of test, the Chinese report always runs)."""

import importlib.util
import math
import re

import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT, motion_driven
from tests.outputs.test_report import _md_tables

pypdf = pytest.importorskip("pypdf")
pytest.importorskip("fpdf")

SHIPPED = sorted(p.stem for p in (ROOT / "mechanisms").glob("*.yaml"))
MOTION = motion_driven()  # the effort-driven files are simulated, not analysed
FAST = {"slider_crank"}

TWO_MOTORS = """
name: two-motor five-bar
units: {length: mm, angle: deg, speed: rpm, mass: kg, force: N, torque: N*m, inertia: kg*m^2}
gravity: [0, -9.81]
links:
  ground: {points: {O1: [0, 0], O2: [150, 0]}}
  crank1: {points: {O1: [0, 0], A: [60, 0]}, com: [30, 0], mass: 1.0, inertia: 0.002}
  crank2: {points: {O2: [0, 0], B: [50, 0]}, com: [25, 0], mass: 1.0, inertia: 0.002}
  coupler1: {points: {A: [0, 0], C: [150, 0]}, com: [75, 0], mass: 0.8, inertia: 0.0015}
  coupler2: {points: {B: [0, 0], C: [130, 0]}, com: [65, 0], mass: 0.7, inertia: 0.0010}
joints:
  O1: {type: revolute, links: [ground, crank1]}
  O2: {type: revolute, links: [ground, crank2]}
  A: {type: revolute, links: [crank1, coupler1]}
  B: {type: revolute, links: [crank2, coupler2]}
  C: {type: revolute, links: [coupler1, coupler2]}
drivers:
  m1: {joint: O1, motion: {speed: 60}}
  m2: {joint: O2, motion: {speed: -90}}
loads:
  process: {type: force, link: coupler1, point: C, value: [0, -150]}
sketch: {A: [60, 0], B: [200, 0], C: [124.6, 135.4]}
analysis: {start: 0, sweep: 720, positions: 240}
"""


def _squash(text: str) -> str:
    return re.sub(r"\s+", "", text)


def _report(path, out, *extra):
    code = main(
        ["report", str(path), "--out", str(out), "--dpi", "40", "--format", "md", "pdf", *extra]
    )
    assert code == 0
    md = (out / "report.md").read_text(encoding="utf-8")
    reader = pypdf.PdfReader(str(out / "report.pdf"))
    text = "\n".join(page.extract_text() for page in reader.pages)
    return md, text, reader


def _check_on_paper(md: str, text: str) -> int:
    """Every header cell and every first-column cell of every Markdown table is in the PDF."""
    flat = _squash(text)
    checked = 0
    for t in _md_tables(md):
        for cell in t[0]:
            assert _squash(cell) in flat, cell
            checked += 1
        if t[0][:2] == ["pos.", "CSV row"]:
            for row in t[1:]:
                assert _squash(f"{row[0]}{row[1]}") in flat or _squash(row[0]) in flat, row[0]
    return checked


@pytest.mark.parametrize(
    "name", [pytest.param(m, marks=() if m in FAST else pytest.mark.slow) for m in MOTION]
)
def test_every_column_and_position_is_on_paper(name, tmp_path):
    md, text, reader = _report(ROOT / "mechanisms" / f"{name}.yaml", tmp_path)
    assert _check_on_paper(md, text) > 40
    assert len(reader.pages) >= 5
    width, height = (float(v) for v in reader.pages[0].mediabox[2:])
    assert (width, height) == pytest.approx((595.28, 841.89), abs=0.5)  # A4 portrait
    positions = next(t for t in _md_tables(md) if t[0][:2] == ["pos.", "CSV row"])
    for row in positions[1:]:  # each position with its angle, as printed in the table
        assert _squash(f"{row[0]}{row[1]}{row[2]}") in _squash(text), row[:3]


def test_a_flywheel_chapter_is_tables_and_its_two_diagrams(tmp_path):
    md, text, _ = _report(
        ROOT / "mechanisms" / "slotting_machine.yaml", tmp_path, "--polygons", "7"
    )
    flat = _squash(text)
    for words in (
        "9. Flywheel",
        "Flywheel: data",
        "Flywheel: result",
        "ΔW_max",
        "energy diagram ΔW–φ",
        "equivalent driving moment",
    ):
        assert _squash(words) in flat or _squash(words).lower() in flat.lower(), words
    assert "units." not in text and "ratio | None" not in md


def test_two_motors_over_two_turns(tmp_path):
    path = tmp_path / "two.yaml"
    path.write_text(TWO_MOTORS)
    md, text, _ = _report(path, tmp_path / "out", "--polygons", "7/2")
    positions = next(t for t in _md_tables(md) if t[0][:2] == ["pos.", "CSV row"])
    labels = [r[0] for r in positions[1:]]
    assert labels == [f"{k}/{t}" for t in (1, 2) for k in range(1, 13)]
    travel = positions[0].index("travel (deg)")
    got = [float(r[travel]) for r in positions[1:]]
    assert got == pytest.approx([30.0 * k for k in range(24)])  # every 30°, both turns
    angle = [float(r[2]) for r in positions[1:]]
    assert angle == pytest.approx([(30.0 * k) % 360.0 for k in range(24)])
    # the second motor turns −90/60 as fast: its crank angle θ at each position
    theta = positions[0].index("crank2.theta (deg)")
    for k, r in enumerate(positions[1:]):
        assert float(r[theta]) == pytest.approx((-1.5 * 30.0 * k) % 360.0, abs=1e-6)
    assert "img/velocity_7_t2.png" in md and "img/acceleration_7_t2.png" in md
    assert "img/torque.png" in md and "img/torque_m2.png" in md  # each driver's torque
    assert _squash("7/2") in _squash(text)


def test_an_effort_driven_file_is_one_line(tmp_path, capsys):
    code = main(
        ["report", str(ROOT / "mechanisms" / "ammunition_swing.yaml"), "--out", str(tmp_path)]
    )
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "effort drivers" in err[0]


def test_chinese_without_a_font_says_what_to_install(tmp_path, capsys, monkeypatch):
    from kinetostatics.outputs import fonts

    not_a_font = tmp_path / "font.ttf"
    not_a_font.write_text("no glyphs here")
    monkeypatch.setenv("KINETOSTATICS_CJK_FONT", str(not_a_font))
    code = main(
        [
            "report",
            str(ROOT / "mechanisms" / "slider_crank.yaml"),
            "--out",
            str(tmp_path / "out"),
            "--lang",
            "zh",
        ]
    )
    assert code == 2
    err = capsys.readouterr().err
    assert "KINETOSTATICS_CJK_FONT" in err and "Chinese glyphs" in err
    assert not (tmp_path / "out" / "report.md").exists()
    assert "pip install 'kinetostatics[zh]'" in fonts._HINT  # when nothing is found
    assert "fonts-noto-cjk" in fonts._HINT and "KINETOSTATICS_CJK_FONT" in fonts._HINT


def test_chinese_report_when_a_font_is_there(tmp_path):
    from kinetostatics.outputs import fonts, lang

    try:
        fonts.cjk_font()
    except lang.LanguageError:
        if importlib.util.find_spec("mplfonts") is not None:
            raise  # the zh extra (part of test) is there: the test runs, never skips
        pytest.skip("no CJK font: pip install 'kinetostatics[zh]'")
    lang.MISSING.clear()
    md, text, _ = _report(ROOT / "mechanisms" / "slider_crank.yaml", tmp_path, "--lang", "zh")
    assert "原始数据" in md and "原始数据" in text  # "1. Data"
    assert not lang.MISSING, sorted(lang.MISSING)[:5]  # every text has its translation
    assert _check_on_paper(md, text) > 40
    assert math.isfinite(len(text))
