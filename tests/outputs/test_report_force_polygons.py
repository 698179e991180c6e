"""The report's chapter "Force polygons of the Assur groups": its tables carry the numbers
of methods.json's ``force_polygons`` (and ``force_polygons_friction``), its pictures are
drawn at the polygon positions only, in English and in Chinese."""

from __future__ import annotations

import math
import re

import pytest

from tests.outputs.test_report import _md_tables
from tests.outputs.test_report_methods import _chapter, _pair, _read

HEADER_EN = ["force", "link", "P, mm", "vector, N", "known/solved"]
HEADER_ZH = ["力", "构件", "P, mm", "矢量，N", "已知/待求"]
DRAWN = ["2", "7"]  # the report's default polygon positions


def _groups(graded: dict, key: str) -> list[tuple[str, dict]]:
    return [
        (p["label"], g) for p in graded[key]["positions"] if p["label"] in DRAWN
        for g in p["groups"]
    ]  # fmt: skip


def _check_table(table: list, group: dict, known: str, solved: str) -> None:
    assert len(table) - 1 == len(group["forces"])
    scale = group["largest"]
    for row, f in zip(table[1:], group["forces"], strict=True):
        assert row[1] == f["link"]
        assert row[4] == (known if f["status"] == "known" else solved)
        x, y = (1e3 * v for v in f["point"])
        px, py = _pair(row[2])
        assert px == pytest.approx(x, abs=1e-3 * max(abs(x), 1.0))  # mm, 5 digits
        assert py == pytest.approx(y, abs=1e-3 * max(abs(y), 1.0))
        vector = row[3].split("; ")[0]
        if vector.startswith("M ="):  # a couple only: no force
            assert math.hypot(*f["vector"]) <= 1e-9 * scale
        else:
            fx, fy = _pair(vector)
            assert fx == pytest.approx(f["vector"][0], abs=1e-4 * scale)
            assert fy == pytest.approx(f["vector"][1], abs=1e-4 * scale)
        if f["couple"]:
            couple = float(re.search(r"M = (\S+) N·m", row[3]).group(1))
            assert couple == pytest.approx(f["couple"], rel=1e-4)


def test_the_chapter_tables_every_group_at_the_polygon_positions(slotting_reports):
    folder = slotting_reports["en"]
    md, graded = _read(folder)
    chapter = _chapter(md, "Force polygons of the Assur groups")
    tables = [t for t in _md_tables(chapter) if t[0] == HEADER_EN]
    groups = _groups(graded, "force_polygons") + _groups(graded, "force_polygons_friction")
    assert "force_polygons_friction" in graded  # the slotting machine has friction
    assert len(tables) == len(groups) == 2 * 2 * 3  # 2 versions, 2 positions, 3 groups
    for table, (_, g) in zip(tables, groups, strict=True):
        _check_table(table, g, "known", "solved")
    # last group first, the driving link last; μ_F and the closure error under each table
    for label in DRAWN:
        p = next(p for p in graded["force_polygons"]["positions"] if p["label"] == label)
        assert [g["driving"] for g in p["groups"]] == [False, False, True]
        crank = p["groups"][-1]
        mb = next(f["couple"] for f in crank["forces"] if f["kind"] == "balancing")
        assert f"M_b = {mb:.5g} N·m." in chapter
    mus = [float(m) for m in re.findall(r"μ_F = (\S+) N/mm; closure error", chapter)]
    assert mus == pytest.approx([g["mu_F"] for _, g in groups])
    # drawn at the polygon positions only, the friction version after the frictionless one
    names = sorted(p.name for p in (folder / "img").glob("polygon_*.png"))
    assert names == sorted(
        f"polygon_{pos}{v}_{i}.png" for pos in DRAWN for v in ("", "_f") for i in (1, 2, 3)
    )
    assert chapter.index("polygon_2_1.png") < chapter.index("polygon_2_f_1.png")


def test_the_chinese_chapter_has_the_same_numbers(slotting_reports):
    md, graded = _read(slotting_reports["zh"])
    chapter = _chapter(md, "各杆组的力多边形")
    tables = [t for t in _md_tables(chapter) if t[0] == HEADER_ZH]
    groups = _groups(graded, "force_polygons") + _groups(graded, "force_polygons_friction")
    assert len(tables) == len(groups)
    for table, (_, g) in zip(tables, groups, strict=True):
        _check_table(table, g, "已知", "待求")
    assert "封闭误差" in chapter and "closure error" not in chapter
    assert "（计摩擦）" in chapter
