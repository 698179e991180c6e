"""The course-design report: its tables are the rows of its results.csv (parsed
back from the Markdown and from the HTML), it holds the course-design
positions 1…12, 1′ and 8′, the HTML is self-contained, and a flywheel entry of
the summary gets its own section."""

import csv
import re
from html.parser import HTMLParser

import pytest

from kinetostatics.cli import main
from tests.conftest import ROOT


def _csv(path):
    lines = path.read_text().splitlines()
    header = next(csv.reader([lines[1]]))
    rows = [next(csv.reader([ln])) for ln in lines[2:]]
    return header, rows


def _md_tables(text):
    tables, cur = [], None
    for line in text.splitlines():
        if line.startswith("|"):
            cells = [
                c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]
            ]
            if cur is None:
                cur = [cells]
            elif not set("".join(cells)) <= set("-"):
                cur.append(cells)
        elif cur is not None:
            tables.append(cur)
            cur = None
    if cur:
        tables.append(cur)
    return tables


class _Tables(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tables, self.row, self.cell, self.images = [], None, None, []

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.row = []
        elif tag in ("td", "th"):
            self.cell = ""
        elif tag == "img":
            self.images.append(dict(attrs)["src"])

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.row.append(self.cell.strip())
            self.cell = None
        elif tag == "tr":
            self.tables[-1].append(self.row)

    def handle_data(self, data):
        if self.cell is not None:
            self.cell += data


def _check_against_csv(tables, header, rows):
    """Every table with a 'CSV row' column equals those CSV rows, column by column."""
    checked = 0
    for t in tables:
        if len(t[0]) < 2 or t[0][1] != "CSV row":
            continue
        names = [h.rsplit(" (", 1)[0] for h in t[0][2:]]
        units = [h.rsplit(" (", 1)[1] for h in t[0][2:]]
        cols = [header.index(n) for n in names]
        scale = {}  # "0" stands for round-off: ≤ 1e-9 of the unit's largest
        for u, c in zip(units, cols):
            vals = [abs(float(r[c])) for r in rows if r[c] != ""]
            scale[u] = max(scale.get(u, 0.0), max(vals) if vals else 0.0)
        for line in t[1:]:
            row = rows[int(line[1]) - 1]
            for n, u, c, cell in zip(names, units, cols, line[2:]):
                if cell == "":
                    assert row[c] == "", (n, line[0])
                    continue
                v = float(row[c])
                if cell == "0":
                    assert abs(v) <= 1e-9 * scale[u], (n, line[0])
                else:
                    assert float(cell) == pytest.approx(v, rel=5.01e-5), (n, line[0])
                checked += 1
    return checked


@pytest.fixture(scope="module")
def slotting_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    assert (
        main(
            [
                "report",
                str(ROOT / "mechanisms" / "slotting_machine.yaml"),
                "--out",
                str(out),
                "--polygons",
                "8'",
                "--dpi",
                "30",
            ]
        )
        == 0
    )
    return out


def test_markdown_tables_are_the_csv_rows(slotting_report):
    header, rows = _csv(slotting_report / "results.csv")
    md = (slotting_report / "report.md").read_text()
    tables = _md_tables(md)
    assert _check_against_csv(tables, header, rows) > 500
    positions = next(t for t in tables if t[0][:2] == ["pos.", "CSV row"])
    assert [r[0] for r in positions[1:]] == [
        "1",
        "1′",
        "2",
        "3",
        "4",
        "5",
        "6",
        "7",
        "8",
        "8′",
        "9",
        "10",
        "11",
        "12",
    ]
    angle = positions[0].index("angle (deg)")
    got = {r[0]: float(r[angle]) for r in positions[1:]}
    assert got["7"] == pytest.approx(120) and got["1"] == pytest.approx(300)
    assert got["1′"] == pytest.approx(270.42, abs=0.01) and got["8′"] == pytest.approx(
        88.632, abs=1e-3
    )
    for section in (
        "Data",
        "Structure",
        "RPR dyad {block, bar}",
        "RRP dyad {rod, ram}",
        "Velocity and acceleration polygons",
        "Polar diagrams",
    ):
        assert section in md
    asks = "\nflywheel:" in (ROOT / "mechanisms" / "slotting_machine.yaml").read_text()
    assert ("## 9. Flywheel" in md) == asks  # the section follows the file's request
    for ref in re.findall(r"\]\((img/[^)]+)\)", md):
        assert (slotting_report / ref).is_file(), ref
    assert "img/velocity_8p.png" in md and "img/acceleration_8p.png" in md


def test_html_is_self_contained_and_equals_the_csv(slotting_report):
    header, rows = _csv(slotting_report / "results.csv")
    parser = _Tables()
    parser.feed((slotting_report / "report.html").read_text())
    assert _check_against_csv(parser.tables, header, rows) > 500
    assert parser.images and all(src.startswith("data:image/png;base64,") for src in parser.images)
    md_tables = _md_tables((slotting_report / "report.md").read_text())
    assert [t[0] for t in parser.tables] == [t[0] for t in md_tables]


def test_flywheel_section_when_the_summary_has_one(tmp_path, monkeypatch):
    from kinetostatics.analysis.results import Result

    original = Result.summary

    def with_flywheel(self):
        s = original(self)
        s["flywheel"] = {
            "delta": 0.04,
            "inertia": 1.2345,
            "unit": "kg*m^2",
            "omega": {"max": 31.9, "min": 30.9},
        }
        return s

    monkeypatch.setattr(Result, "summary", with_flywheel)
    from kinetostatics.outputs.report import write_report

    paths = write_report(
        ROOT / "mechanisms" / "slider_crank.yaml", tmp_path, polygons=["2"], dpi=30
    )
    md = paths["markdown"].read_text()
    assert "## 9. Flywheel" in md
    assert "| inertia | 1.2345 |" in md and "| omega.max | 31.9 |" in md
    assert "Flywheel" in paths["html"].read_text()
    header, rows = _csv(paths["csv"])
    assert _check_against_csv(_md_tables(md), header, rows) > 200


def test_unknown_polygon_position_is_one_line(tmp_path, capsys):
    assert (
        main(
            [
                "report",
                str(ROOT / "mechanisms" / "slider_crank.yaml"),
                "--out",
                str(tmp_path),
                "--polygons",
                "13",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no course position '13'" in err[0]
