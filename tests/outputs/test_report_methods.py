"""The report's chapters of the graded methods (outputs/report/methods.py): the balancing
moment three ways, the instant centres and the cam's design hold the numbers of
methods.json, which the report writes beside them, in English and in Chinese; the
centres of the pins are where results.csv puts the pins; a file without a cam has no cam
chapter; the cam is drawn at a round scale, true size on paper."""

from __future__ import annotations

import csv
import json
import math
import re

import numpy as np
import pytest

from kinetostatics.methods.stage import methods_stage
from kinetostatics.outputs import lang
from kinetostatics.outputs.plotting.cam import cam_drawing
from kinetostatics.outputs.plotting.style import MM
from kinetostatics.outputs.report import write_report
from tests.helpers import ROOT
from tests.outputs.test_report import _md_tables

LEVER_HEADER = ["load", "link", "F, N", "P, mm", "F′, N", "p, m/s", "M_p, W"]


def _read(folder):
    md = (folder / "report.md").read_text(encoding="utf-8")
    graded = json.loads((folder / "methods.json").read_text(encoding="utf-8"))
    return md, graded


def _csv(folder) -> list[dict[str, float]]:
    with open(folder / "results.csv", encoding="utf-8") as f:
        rows = [line for line in f if not line.startswith("#")]
    return [{k: float(v or "nan") for k, v in r.items()} for r in csv.DictReader(rows)]


def _pair(cell: str) -> tuple[float, float]:
    x, y = cell.split(", ")
    return float(x), float(y)


def _chapter(md: str, title: str) -> str:
    """The text of the level-2 chapter whose heading ends with ``title``."""
    m = re.search(rf"^## (\d+)\. {re.escape(title)}$", md, re.M)
    assert m, title
    rest = md[m.end() :]
    end = re.search(r"^## ", rest, re.M)
    return rest[: end.start()] if end else rest


def test_the_lever_chapter_holds_the_numbers_of_methods_json(slotting_reports):
    folder = slotting_reports["en"]
    md, graded = _read(folder)
    bm = graded["balancing_moment"]
    chapter = _chapter(md, "The balancing moment, three ways")
    tables = [t for t in _md_tables(chapter) if t[0] == LEVER_HEADER]
    assert len(tables) == len(bm["positions"]) == len(graded["positions"])
    csv_rows = _csv(folder)
    sections = re.split(r"^### ", chapter, flags=re.M)[1:]  # one per position
    assert len(sections) == len(tables)
    for table, p, section in zip(tables, bm["positions"], sections):
        rows = {r[0]: r for r in table[1:]}
        for term in p["terms"]:
            row = rows[term["name"]]
            assert float(row[6]) == pytest.approx(term["moment"], rel=1e-5, abs=1e-9)
            if term["kind"] == "force":  # turned by +90°: (Fx, Fy) → (−Fy, Fx)
                fx, fy = _pair(row[2])
                tx, ty = _pair(row[4])
                scale = max(abs(fx), abs(fy))
                assert tx == pytest.approx(-fy, abs=1e-3 * scale)
                assert ty == pytest.approx(fx, abs=1e-3 * scale)
        assert float(rows["sum"][6]) == pytest.approx(p["lever_sum"], rel=1e-5)
        speed = re.escape(f"{p['speed']:.5g}")
        line = re.search(
            r"M_b by the lever = (\S+) N·m, by the power method = (\S+) N·m, from the "
            rf"solution = (\S+) N·m \(ω₁ = {speed}\)",
            section,
        )
        assert line, p["label"]
        torque = csv_rows[p["row"]]["motor.torque"]  # the solution, from results.csv
        scale = max(abs(r["motor.torque"]) for r in csv_rows)
        for value in line.groups():
            assert float(value) == pytest.approx(torque, abs=1e-5 * scale)


def test_the_centres_chapter_tables_every_centre_and_draws_the_polygon_positions(
    slotting_reports,
):
    folder = slotting_reports["en"]
    md, graded = _read(folder)
    chapter = _chapter(md, "Instant centres")
    tables = [t for t in _md_tables(chapter) if t[0][0] == "P_ij"]
    centres = graded["instant_centres"]
    assert len(tables) == len(centres) == len(graded["positions"])
    csv_rows = _csv(folder)
    for table, ic in zip(tables, centres.values()):
        assert len(table) - 1 == ic["total"] == 15  # 6 bodies: 6·5/2
        for row, c in zip(table[1:], ic["centres"]):
            assert row[1] == " – ".join(c["bodies"])
            if c["xy"] is None:  # where Kennedy's lines are one line (a singular position)
                assert row[2].startswith("not found") and row[3:] == ["–", "–"]
                continue
            if c["at_infinity"]:
                assert row[3:] == ["∞", "∞"]
                continue
            x, y = (1e3 * v for v in c["xy"])
            assert float(row[3]) == pytest.approx(x, abs=1e-4 * max(abs(x), 1.0))
            assert float(row[4]) == pytest.approx(y, abs=1e-4 * max(abs(y), 1.0))
            if c["how"] == "joint" and c["joint"] == "A":  # the pin, where results.csv has it
                at = csv_rows[ic["row"]]
                assert float(row[3]) == pytest.approx(1e3 * at["crank.A.x"], abs=0.02)
                assert float(row[4]) == pytest.approx(1e3 * at["crank.A.y"], abs=0.02)
        assert f"{ic['found']} of {ic['total']} centres found" in chapter
    # drawn where the polygons are drawn (2 and 7 by default), tabled at every position
    assert sorted(p.name for p in (folder / "img").glob("centres_*.png")) == [
        "centres_2.png",
        "centres_7.png",
    ]
    assert "The cam's design" not in md and "cam_design" not in graded  # no cam, no chapter


def test_the_chinese_chapters_have_the_same_numbers(slotting_reports):
    md_en, graded = _read(slotting_reports["en"])
    md_zh, _ = _read(slotting_reports["zh"])
    lever = _chapter(md_zh, "平衡力矩的三种求法")
    centres = _chapter(md_zh, "速度瞬心")
    number = lambda md, t: int(re.search(rf"^## (\d+)\. {t}$", md, re.M).group(1))  # noqa: E731
    assert number(md_zh, "速度瞬心") == number(md_zh, "平衡力矩的三种求法") + 1
    assert number(md_zh, "平衡力矩的三种求法") == number(
        md_en, re.escape("The balancing moment, three ways")
    )
    positions = graded["balancing_moment"]["positions"]
    for p in positions:
        assert f"位置 {p['label']}（φ = {p['coordinate']:.5g}°）" in lever
    solutions = re.findall(r"动态静力分析解 M_b = (\S+) N·m", lever)
    lever_en = _chapter(md_en, "The balancing moment, three ways")
    assert solutions == re.findall(r"from the solution = (\S+) N·m", lever_en)
    scale = max(abs(p["M_b"]["solution"]) for p in positions)
    for value, p in zip(solutions, positions, strict=True):
        assert float(value) == pytest.approx(p["M_b"]["solution"], abs=1e-5 * scale)
    assert "三心定理：" in centres and "凸轮机构设计" not in md_zh
    assert "Kennedy" not in centres and "three ways" not in lever


@pytest.fixture(scope="module")
def cam_report(tmp_path_factory):
    """The cam file's report in Chinese at position 2 (Markdown, dpi 30)."""
    out = tmp_path_factory.mktemp("cam")
    lang.MISSING.clear()
    write_report(
        ROOT / "mechanisms" / "cam_roller.yaml",
        out,
        positions=["2"],
        dpi=30,
        formats=["md"],
        lang="zh",
        methods=methods_stage,
    )
    return out, set(lang.MISSING)


def test_the_cam_chapter_holds_the_design_of_methods_json(cam_report):
    folder, missing = cam_report
    assert not missing, sorted(missing)[:5]  # every text of the chapters translated
    md, graded = _read(folder)
    (cam,) = graded["cam_design"].values()
    chapter = _chapter(md, "凸轮机构设计")
    (table,) = [t for t in _md_tables(chapter) if t[0] == ["量", "符号", "数值", "单位"]]
    cells = {r[1]: r[2] for r in table[1:] if r[1]}
    assert float(cells["r_b"]) == pytest.approx(1e3 * cam["base_radius"], rel=1e-5)
    assert float(cells["r_r"]) == pytest.approx(1e3 * cam["roller_radius"], rel=1e-5)
    assert float(cells["|α|max"]) == pytest.approx(cam["peak"], rel=1e-5)
    assert float(cells["r_b,min"]) == pytest.approx(1e3 * cam["base_radius_min"], rel=1e-5)
    assert float(cells["ρ_min"]) == pytest.approx(1e3 * cam["curvature_min"], rel=1e-5)
    # the file's 40 mm base radius against r_b,min = 28.96 mm, the 12 mm roller against
    # ρ_min = 48.4 mm (docs/methods.md): both met
    said = {r[0][:8]: r[2] for r in table[1:]}
    assert said["文件的基圆半径满"] == "是" and said["文件的滚子半径小"] == "是"
    joint = cam["joint"]
    for name in (f"cam_{joint}_diagrams.png", f"cam_{joint}_profile.png"):
        assert (folder / "img" / name).is_file()
    numbers = [int(n) for n in re.findall(r"^## (\d+)\. ", md, re.M)]
    assert numbers == sorted(numbers) and len(set(numbers)) == len(numbers)
    assert re.search(r"^## \d+\. 平衡力矩的三种求法$", md, re.M)


def test_the_cam_is_drawn_at_a_round_scale_true_size(cam_report):
    folder, _ = cam_report
    _, graded = _read(folder)
    (cam,) = graded["cam_design"].values()
    fig = cam_drawing(cam, dpi=30)
    ax = fig.axes[0]
    mu = float(re.search(r"= ([\d.e-]+) m/mm", ax.get_title()).group(1))
    mantissa = mu / 10.0 ** math.floor(math.log10(mu))
    assert any(math.isclose(mantissa, m) for m in (1.0, 2.0, 2.5, 4.0, 5.0))
    width_mm = ax.get_position().width * fig.get_size_inches()[0] / MM
    x0, x1 = ax.get_xlim()  # mm of the cam
    assert (x1 - x0) / width_mm == pytest.approx(1e3 * mu, rel=1e-9)
    reach = 1e3 * np.max(np.abs(cam["profile"]))
    assert x0 < -reach and x1 > reach  # the whole profile on the sheet
