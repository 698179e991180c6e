"""The report's section on springs and dampers: each element's data as the file wrote it
(in its units), and at the course-design positions its length or angle, force or moment,
energy and power, equal to the result columns converted to the file's units by hand, the
energy of a linear spring equal to its closed form; the same numbers on the PDF's pages."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT
from tests.outputs.test_report import _md_tables

SLIDER = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
# forces in kN and moments in N·mm, so that every number of the section is converted
ELEMENTS = """elements:
  spring: {type: spring, between: [ground.O, slider.B], stiffness: 0.002, free_length: 300,
           preload: 0.05}
  table: {type: spring, between: [crank.A, ground.guide],
          table: {length: [60, 100, 140], force: [-0.1, 0.02, 0.5]}}
  damper: {type: damper, between: [ground.O, slider.B], damping: 0.0005}
  tors: {type: torsion_spring, joint: A, stiffness: 3000, free_angle: 10, preload: 2000}
  rd: {type: rotary_damper, joint: A, damping: 200}
"""
MM, KN, NMM, DEG = 1e-3, 1e3, 1e-3, math.pi / 180.0


def _text() -> str:
    text = SLIDER.replace("sketch:", ELEMENTS + "sketch:").replace(
        "force: N,", "force: kN, torque: N*mm,"
    )
    return text.replace("positions: 360", "positions: 72")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    path = out / "sprung.yaml"
    path.write_text(_text())
    formats = ["md", "pdf"] if _has_pdf() else ["md"]
    argv = ["report", str(path), "--out", str(out / "r"), "--dpi", "30", "--format", *formats]
    assert main(argv) == 0
    md = (out / "r" / "report.md").read_text(encoding="utf-8")
    import csv

    with open(out / "r" / "results.csv", newline="") as f:
        rows = list(csv.reader(f))
    k = next(i for i, r in enumerate(rows) if r and not r[0].startswith("#"))  # below units
    header, data = rows[k], rows[k + 1 :]
    return out / "r", md, header, data


def _has_pdf() -> bool:
    try:
        import fpdf  # noqa: F401
        import pypdf  # noqa: F401
    except ImportError:
        return False
    return True


def _column(header, data, name) -> np.ndarray:
    return np.array([float(r[header.index(name)]) for r in data])


def _section(md: str) -> str:
    start = md.index("## 9. Springs and dampers")
    return md[start:]


def test_element_data_in_the_units_of_the_file(report):
    _, md, _, _ = report
    data = _md_tables(_section(md))[0]
    assert data[0][:3] == ["element", "type", "between"]
    rows = {r[0]: r for r in data[1:]}
    assert set(rows) == {"spring", "table", "damper", "tors", "rd"}
    assert rows["spring"][1:7] == [
        "spring",
        "ground.O – slider.B",
        "0.002 kN/mm",
        "300 mm",
        "0.05 kN",
        "",
    ]
    assert rows["table"][6] == "mm → kN: 60 → -0.1; 100 → 0.02; 140 → 0.5"
    assert rows["damper"][7] == "0.0005 kN·s/mm"
    assert rows["tors"][2] == "at revolute A: rod relative to crank"
    assert rows["tors"][3:6] == ["3000 N·mm/deg", "10 deg", "2000 N·mm"]
    assert rows["rd"][7] == "200 N·mm·s/deg"


def test_values_at_the_course_positions_are_the_result_columns(report):
    _, md, header, data = report
    tables = [t for t in _md_tables(_section(md)) if t[0][:2] == ["pos.", "CSV row"]]
    assert tables
    # the file's units by hand: mm, kN, N·mm, deg
    convert = {"length": 1 / MM, "F": 1 / KN, "angle": 1.0, "M": 1 / NMM, "energy": 1.0}
    convert["power"] = 1.0
    expected_cols = (
        {
            f"{e}.{q}"
            for e in ("spring", "table", "damper")
            for q in ("length", "F", "power") + (("energy",) if e != "damper" else ())
        }
        | {f"{e}.{q}" for e in ("tors", "rd") for q in ("angle", "M", "power")}
        | {"tors.energy"}
    )
    seen, checked = set(), 0
    for t in tables:
        for c, head in enumerate(t[0][3:], start=3):
            name, unit = head.rsplit(" (", 1)
            unit = unit.rstrip(")")
            seen.add(name)
            quantity = name.rsplit(".", 1)[1]
            assert (
                unit
                == {
                    "length": "mm",
                    "F": "kN",
                    "angle": "deg",
                    "M": "N·mm",
                    "energy": "J",
                    "power": "W",
                }[quantity]
            )
            values = _column(header, data, name) * convert[quantity]
            scale = np.max(np.abs(values))
            for line in t[1:]:
                v = values[int(line[1]) - 1]
                if line[c] == "0":
                    assert abs(v) <= 1e-9 * max(scale, 1e-300)
                else:
                    assert float(line[c]) == pytest.approx(v, rel=5.01e-5), (name, line[0])
                checked += 1
    assert seen == expected_cols
    assert checked >= 12 * len(expected_cols)


def test_a_linear_spring_energy_is_its_closed_form(report):
    """E = p x + k x²/2, x = s − free, from the printed length (mm) and the file's data."""
    _, md, _, _ = report
    tables = [t for t in _md_tables(_section(md)) if t[0][:2] == ["pos.", "CSV row"]]
    t = next(t for t in tables if "spring.length (mm)" in t[0] and "spring.energy (J)" in t[0])
    s_col, e_col = t[0].index("spring.length (mm)"), t[0].index("spring.energy (J)")
    k, free, p = 0.002 * KN / MM, 300 * MM, 0.05 * KN
    for line in t[1:]:
        x = float(line[s_col]) * MM - free
        assert float(line[e_col]) == pytest.approx(p * x + 0.5 * k * x * x, rel=2e-4, abs=0.05)


def test_the_section_is_on_the_pdf_pages(report):
    if not _has_pdf():
        pytest.skip("fpdf2 and pypdf are needed for the PDF")
    import pypdf

    folder, md, _, _ = report
    reader = pypdf.PdfReader(str(folder / "report.pdf"))
    flat = re.sub(r"\s+", "", "\n".join(page.extract_text() for page in reader.pages))
    assert "9.Springsanddampers" in flat
    checked = 0
    for t in _md_tables(_section(md)):
        for cell in t[0]:
            assert re.sub(r"\s+", "", cell) in flat, cell
        for line in t[1:]:
            for cell in line[:2] + line[3:]:
                if cell:
                    assert re.sub(r"\s+", "", cell) in flat, cell
                    checked += 1
    assert checked > 100
