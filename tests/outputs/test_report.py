"""The course-design report: its tables are the rows of its results.csv (parsed
back from the Markdown and from the HTML), it holds the course-design
positions 1…12, 1′ and 8′, the HTML is self-contained, and a flywheel entry of
the summary gets its own section."""

import csv
import json
import re
from html.parser import HTMLParser

import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT

# a ``name:`` that would be HTML, a comment, links and a table cell if copied raw
HOSTILE = (
    "<script>alert(1)</script><img src=x onerror=alert(2)> ](javascript:alert(3)) | col | "
    "<!-- x [a](javascript:alert(4)) \\<b>"
)


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


_LENGTH = {"m": 1.0, "mm": 1e-3, "cm": 1e-2}


def _csv_values(header, rows, name, unit):
    """The CSV values behind a report column: a column itself (lengths converted from m
    to the printed unit, link angles to [0, 360)), or the magnitude |v|, |a|, |F| of the
    two components named before it (computed here from the CSV)."""
    import math

    def col(n):
        c = header.index(n)
        return [float(r[c]) if r[c] != "" else math.nan for r in rows]

    for mag, (a, b) in (("|v|", ("vx", "vy")), ("|a|", ("ax", "ay")), ("|F|", ("Fx", "Fy"))):
        if mag in name:
            base, _, rest = name.partition("." + mag)
            return [
                math.hypot(x, y) for x, y in zip(col(f"{base}.{a}{rest}"), col(f"{base}.{b}{rest}"))
            ]
    vals = col(name)
    if unit in _LENGTH and name.rsplit(".", 1)[-1] in ("x", "y"):
        vals = [v / _LENGTH[unit] for v in vals]
    if name.endswith(".theta"):
        vals = [v % 360.0 for v in vals]
    return vals


def _check_against_csv(tables, header, rows):
    """Every table with a 'CSV row' column equals those CSV rows, column by column."""
    import math

    checked = 0
    for t in tables:
        if len(t[0]) < 2 or t[0][1] != "CSV row":
            continue
        names = [h.rsplit(" (", 1)[0] for h in t[0][2:]]
        units = [h.rsplit(" (", 1)[1].rstrip(")") for h in t[0][2:]]
        values = [_csv_values(header, rows, n, u) for n, u in zip(names, units)]
        scale = {}  # "0" stands for round-off: ≤ 1e-9 of the unit's largest
        for u, vals in zip(units, values):
            finite = [abs(v) for v in vals if math.isfinite(v)]
            scale[u] = max(scale.get(u, 0.0), max(finite) if finite else 0.0)
        for line in t[1:]:
            k = int(line[1]) - 1
            for n, u, vals, cell in zip(names, units, values, line[2:]):
                v = vals[k]
                if cell == "":
                    assert not math.isfinite(v), (n, line[0])
                    continue
                if cell == "0":
                    assert abs(v) <= 1e-9 * scale[u] or (
                        n.endswith(".theta") and abs(v - 360.0) < 1e-9
                    ), (n, line[0])
                else:
                    assert float(cell) == pytest.approx(v, rel=5.01e-5), (n, line[0])
                checked += 1
    return checked


@pytest.fixture(scope="module")
def slotting_report(tmp_path_factory):
    """The shipped slotting machine's report, the file's ``name:`` made hostile (HOSTILE)."""
    out = tmp_path_factory.mktemp("report")
    text = (ROOT / "mechanisms" / "slotting_machine.yaml").read_text(encoding="utf-8")
    text, n = re.subn(r"(?m)^name: .*$", lambda m: "name: " + json.dumps(HOSTILE), text)
    assert n == 1
    path = tmp_path_factory.mktemp("file") / "slotting_machine.yaml"
    path.write_text(text, encoding="utf-8")
    assert (
        main(
            [
                "report",
                str(path),
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
    assert all(len(t[0]) <= 12 for t in tables if t[0][1:2] == ["CSV row"])  # column groups
    assert all(
        t[0][:3] == ["pos.", "CSV row", "angle (deg)"] for t in tables if t[0][1:2] == ["CSV row"]
    )
    theta = positions[0].index("crank.theta (deg)")
    assert all(0 <= float(r[theta]) < 360 for r in positions[1:])  # not the CSV's −390
    assert "crank.A.x (mm)" in positions[0]
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
        "RPR dyad (class II) {block, bar}",
        "RRP dyad (class II) {rod, ram}",
        "Velocity and acceleration polygons",
        "Polar diagrams",
    ):
        assert section in md
    assert "## 9. Flywheel" in md  # the file asks for a flywheel
    assert "img/energy.png" in md and "img/moments.png" in md
    assert "units." not in md and "| ratio |" not in md  # no raw dump of summary.json
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


def test_flywheel_chapter_states_the_energy_swing_of_its_own_diagram(slotting_report):
    """The chapter's tables carry the summary's numbers, and the ΔW column at the course
    positions is ∫ (M_d − M_r) dφ of the tabulated moments: its range over positions that
    straddle the extremes is within the swing, and M_d is the mean of M_r over the cycle
    (the work per cycle / 2π)."""
    import json

    fw = json.loads((slotting_report / "summary.json").read_text())["flywheel"]
    tables = _md_tables((slotting_report / "report.md").read_text())
    result = next(
        t
        for t in tables
        if t[0][:2] == ["quantity", "symbol"] and any(r[1] == "ΔW_max" for r in t[1:])
    )
    got = {r[1]: r[2] for r in result[1:]}
    assert float(got["ΔW_max"]) == pytest.approx(fw["energy_swing"], rel=1e-5)
    assert float(got["J_F"]) == pytest.approx(
        fw["energy_swing"] / (fw["speed"]["omega_m"] ** 2 * fw["delta"]), rel=1e-5
    )
    assert float(got["M_d"]) == pytest.approx(
        fw["work_per_cycle"] / (2 * 3.141592653589793), rel=1e-5
    )
    energy = next(t for t in tables if t[0][-1] == "ΔW (J)")
    w = [float(r[-1]) for r in energy[1:]]
    assert w[0] == 0.0 and max(w) - min(w) <= fw["energy_swing"] * (1 + 1e-6)
    assert max(w) - min(w) > 0.7 * fw["energy_swing"]


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


class _Tags(HTMLParser):
    """The tags, comments and h1 text of an HTML text."""

    def __init__(self):
        super().__init__()
        self.tags, self.comments, self.h1, self._in_h1 = [], [], [], False

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        self._in_h1 = self._in_h1 or tag == "h1"

    def handle_endtag(self, tag):
        self._in_h1 = self._in_h1 and tag != "h1"

    def handle_data(self, data):
        if self._in_h1:
            self.h1.append(data)

    def handle_comment(self, data):
        self.comments.append(data)


def _check_rendered(html_text: str, title: str) -> None:
    parsed = _Tags()
    parsed.feed(html_text)
    assert "".join(parsed.h1) == title  # shown as written
    assert not parsed.comments
    for tag, attrs in parsed.tags:
        assert tag not in ("script", "a", "iframe"), (tag, attrs)
        assert not any(k.startswith("on") for k in attrs), (tag, attrs)
        if tag == "img":
            assert attrs["src"].startswith(("img/", "data:image/png;base64,")), attrs


def test_report_escapes_the_name_in_markdown_and_html(slotting_report):
    """The report of a ``name:`` holding HTML, a comment, links and a table pipe (issue 36):
    text in report.md (rendered by a CommonMark renderer with raw HTML on) and in
    report.html; no tag, link or comment comes of it, and the heading shows it as written."""
    markdown_it = pytest.importorskip("markdown_it")
    title = "Course-design report: " + HOSTILE
    md = (slotting_report / "report.md").read_text(encoding="utf-8")
    _check_rendered(markdown_it.MarkdownIt("commonmark").render(md), title)
    _check_rendered((slotting_report / "report.html").read_text(encoding="utf-8"), title)
