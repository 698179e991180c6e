"""``report --positions 2,7``: the student's assigned positions. The chapters at the
course-design positions (the tables, the loads drawn, the polygons) hold exactly those
positions; everything over the cycle is the full report's. An identity: the report for a
subset of the positions is the full report restricted to them, cell for cell."""

import json
import re

import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT
from tests.outputs.test_report import _md_tables

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"


def _run(out, *extra):
    args = ["report", str(SLOTTING), "--out", str(out), "--format", "md", "--dpi", "30"]
    assert main(args + list(extra)) == 0
    return out


@pytest.fixture(scope="module")
def reports(tmp_path_factory, slotting_reports):
    """The full report (conftest: default polygons 2 and 7) and the one for 7, 2."""
    return slotting_reports["en"], _run(tmp_path_factory.mktemp("part"), "--positions", "7,2")


def _by_position(table):
    """A table at the course positions: {position: its row}."""
    return {row[0]: row for row in table[1:]}


def test_only_the_assigned_positions_have_chapters(reports):
    full, part = reports
    md = (part / "report.md").read_text(encoding="utf-8")
    tables = [t for t in _md_tables(md) if t[0][1:2] == ["CSV row"]]
    assert len(tables) > 10
    for t in tables:
        assert [row[0] for row in t[1:]] == ["2", "7"]  # in the order of travel
    pictures = set(re.findall(r"\]\(img/(\w+)\.png\)", md))
    per_position = {p for p in pictures if re.match(r"(forces|velocity|acceleration)_", p)}
    assert per_position == {
        f"{k}_{n}" for k in ("forces", "velocity", "acceleration") for n in (2, 7)
    }
    assert "the positions assigned (2, 7)" in md
    full_tables = _md_tables((full / "report.md").read_text(encoding="utf-8"))
    assert all(len(t) == 15 for t in full_tables if t[0][1:2] == ["CSV row"])  # 1 … 12, 1′, 8′


def test_the_subset_is_the_full_report_restricted(reports):
    """Same analysis (results.csv, summary.json byte for byte), the same cycle tables and
    pictures of the cycle, and at positions 2 and 7 the same cells as the full report."""
    full, part = reports
    for name in ("results.csv", "summary.json"):
        assert (part / name).read_bytes() == (full / name).read_bytes(), name
    t_full = _md_tables((full / "report.md").read_text(encoding="utf-8"))
    t_part = _md_tables((part / "report.md").read_text(encoding="utf-8"))
    # the methods' chapters have a table per position: the part's are the full's at 2 and 7
    labels = json.loads((full / "methods.json").read_text(encoding="utf-8"))["positions"]
    per_position = (["load", "link", "F, N"], ["P_ij", "bodies", "found how"])
    for head in per_position:  # the lever's terms, the instant centres
        per_full = [t for t in t_full if t[0][:3] == head]
        per_part = [t for t in t_part if t[0][:3] == head]
        assert len(per_full) == len(labels) and len(per_part) == 2
        assert per_part == [per_full[labels.index(p)] for p in ("2", "7")]
    # the vector equations' tables (a blank first header cell), per equation at each position
    eq_full = [t for t in t_full if t[0][0] == ""]
    eq_part = [t for t in t_part if t[0][0] == ""]
    assert 0 < 2 * len(eq_part) < len(eq_full) and all(t in eq_full for t in eq_part)
    t_full = [t for t in t_full if t[0][:3] not in per_position and t[0][0] != ""]
    t_part = [t for t in t_part if t[0][:3] not in per_position and t[0][0] != ""]
    assert [t[0] for t in t_full] == [t[0] for t in t_part]  # the same tables, same columns
    checked = 0
    for a, b in zip(t_full, t_part):
        if a[0][1:2] == ["CSV row"]:
            rows = _by_position(a)
            assert len(rows) == 14
            for label, row in _by_position(b).items():
                assert row == rows[label], label
                checked += len(row)
        else:  # data, structure, largest reactions, the flywheel's tables over the cycle
            assert a == b
    assert checked > 200
    for name in ("motion", "torque", "reactions", "polar", "energy", "moments"):
        assert (part / "img" / f"{name}.png").is_file(), name


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--positions", "2,13"], ["--positions", "'13'", "have 1, 1′, 2"]),
        (["--positions", ","], ["--positions", "no position given"]),
        (["--positions", "2,7", "--polygons", "8'"], ["--polygons", "'8′'", "--positions"]),
    ],
)
def test_a_position_not_in_the_analysis_is_one_line(tmp_path, capsys, extra, words):
    out = tmp_path / "out"
    args = ["report", str(SLOTTING), "--out", str(out), "--format", "md", "--dpi", "30"]
    assert main(args + extra) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0]
    for w in words:
        assert w in err[0], (w, err[0])
    assert not (out / "report.md").exists() and not (out / "results.csv").exists()


def test_help_names_the_option(capsys):
    with pytest.raises(SystemExit):
        main(["report", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--positions LABELS" in text and "assigned course positions" in text
