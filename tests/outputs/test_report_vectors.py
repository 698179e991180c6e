"""The report's chapter "Vector equations" (outputs/report/vectors.py): at each position of
the detailed chapters, each group's equations in the order of methods.json's
``vector_equations``, one table per equation whose columns are its terms, with the
direction, the magnitude ("?" for an unknown) and the value to the printed digits, in
English and in Chinese; a position not asked has none."""

from __future__ import annotations

import json
import re

import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT
from tests.outputs.test_report import _md_tables
from tests.outputs.test_report_methods import _chapter

TITLES = {"en": "Vector equations", "zh": "矢量方程图解法"}
ROWS = {"en": ("direction", "magnitude", "value"), "zh": ("方向", "大小", "数值")}


def _read(folder):
    md = (folder / "report.md").read_text(encoding="utf-8")
    graded = json.loads((folder / "methods.json").read_text(encoding="utf-8"))
    assert list(graded["vector_equations"]) == graded["positions"]
    return md, graded["vector_equations"]


def _check_position(section: str, p: dict, lang: str) -> None:
    tables = _md_tables(section)
    equations = [e for g in p["groups"] for e in g["equations"]]
    assert len(tables) == len(equations) > 0
    direction, magnitude, value = ROWS[lang]
    for table, e in zip(tables, equations):
        assert e["text"] in section
        terms = [*e["lhs"], *e["rhs"]]
        assert table[0] == ["", *(t["symbol"] for t in terms)]
        assert table[1][0] == direction and table[2][0] == magnitude
        assert table[3][0].startswith(value)
        unit = "m/s²" if e["kind"] == "acceleration" else "m/s"
        assert table[3][0].endswith(unit)
        largest = max(t["value"] for t in terms)
        for t, mag, cell in zip(terms, table[2][1:], table[3][1:]):
            assert (mag == "?") == (not t["known"])
            # 4 significant digits printed: half a unit of the 4th digit
            assert float(cell) == pytest.approx(t["value"], rel=6e-4, abs=1e-9 * largest)
    for g in p["groups"]:
        for s in g["solved"]:
            m = re.search(rf"{re.escape(s['symbol'])} = (\S+) {re.escape(s['unit'])}", section)
            assert m, s["symbol"]
            assert float(m[1]) == pytest.approx(s["value"], rel=6e-4, abs=1e-9)


@pytest.mark.parametrize("lang", ["en", "zh"])
def test_the_chapter_holds_each_equation_of_methods_json(slotting_reports, lang):
    md, entry = _read(slotting_reports[lang])
    chapter = _chapter(md, TITLES[lang])
    sections = re.split(r"^### ", chapter, flags=re.M)[1:]
    assert len(sections) == len(entry) > 2  # every course position of the file
    for section, (label, p) in zip(sections, entry.items()):
        assert re.match(rf"\S+ \S+ {re.escape(label)}\n", section), section[:40]
        _check_position(section, p, lang)
    # the slotting machine's slot writes the Coriolis term, its magnitude formula known
    assert "a^k_A2A3" in chapter and "2·ω3·v_A2A3" in chapter


def test_a_position_not_asked_has_no_equations(tmp_path):
    args = ["report", str(ROOT / "mechanisms" / "slotting_machine.yaml"), "--out"]
    args += [str(tmp_path), "--format", "md", "--dpi", "30", "--positions", "2,7"]
    assert main(args) == 0
    md, entry = _read(tmp_path)
    assert list(entry) == ["2", "7"]
    chapter = _chapter(md, TITLES["en"])
    headings = re.findall(r"^### \S+ Position (\S+)$", chapter, flags=re.M)
    assert headings == ["2", "7"]
    for section, p in zip(re.split(r"^### ", chapter, flags=re.M)[1:], entry.values()):
        _check_position(section, p, "en")


def test_a_cams_terms_are_written_in_chinese(tmp_path):
    """The roller cam's contact writes its terms (the roller centre along the pitch curve,
    the normal term of its path, the Coriolis term of the turning cam): the follower's group
    has a velocity and an acceleration equation at the contact, and the Chinese chapter
    names their directions in Chinese, no English word of them left."""
    args = ["report", str(ROOT / "mechanisms" / "cam_roller.yaml"), "--out"]
    args += [str(tmp_path), "--format", "md", "--dpi", "20", "--positions", "2", "--lang", "zh"]
    assert main(args) == 0
    md, entry = _read(tmp_path)
    assert not [n for g in entry["2"]["groups"] for n in g["notes"]]
    follower = next(g for g in entry["2"]["groups"] if g["links"] == ["follower"])
    kinds = [(e["kind"], e["joint"]) for e in follower["equations"]]
    assert kinds == [("velocity", "contact"), ("acceleration", "contact")]
    chapter = _chapter(md, TITLES["zh"])
    assert "理论廓线的切线" in chapter and "其曲率中心" in chapter
    for words in ("the tangent", "centre of curvature", "the pitch curve"):
        assert words not in chapter
    _check_position(re.split(r"^### ", chapter, flags=re.M)[1], entry["2"], "zh")
