"""docs/glossary_zh.md holds every textbook term the Chinese report uses.

The Chinese texts of the report and its pictures are the values of the translation table
(``outputs/zh.py``).  Wherever one of them uses a term of the textbook — recognised by
its head word (副, 杆组, 反力, 多边形, 飞轮 …, the list below) — the occurrence lies inside
a term of the glossary's first column.  A new text with a term the glossary lacks (say
"压力角" with the head "角" added here, or "速度瞬心" with "瞬心") fails this test until the
glossary has a row for it; each row gives the English of the English report and where the
textbook defines it."""

import re

from kinetostatics.outputs.lang import ZH
from tests.helpers import ROOT

PAGE = ROOT / "docs" / "glossary_zh.md"

# the head words of the textbook's terms (孙桓《机械原理》): pairs, groups, members, the
# polygons, the loads of the kinetostatic analysis, the flywheel, the linkage's stroke
HEADS = (
    "副",
    "杆组",
    "级机构",
    "原动件",
    "从动件",
    "机架",
    "构件",
    "自由度",
    "运动简图",
    "比例尺",
    "多边形",
    "极点",
    "科氏",
    "重合点",
    "惯性力",
    "力偶矩",
    "反力",
    "平衡力",
    "法向力",
    "摩擦圆",
    "自锁",
    "效率",
    "等效",
    "转动惯量",
    "飞轮",
    "盈功",
    "亏功",
    "盈亏功",
    "能量指示图",
    "速度波动",
    "速比",
    "极位",
    "极限位置",
    "摆角",
    "行程",
    "线图",
    "极坐标图",
    "凸轮",
    "基圆",
    "运动规律",
    "传动比",
    "减速器",
    "达朗贝尔",
    "动态静力",
    "阿苏尔",
    "工作阻力",
    "导路",
    "一致解",
    "近似解",
    "冗余约束",
)
CJK = re.compile(r"[\u4e00-\u9fffⅠ-Ⅻ]+")


def glossary() -> list[list[str]]:
    """The rows (中文, English, 教材出处) of the page's tables."""
    rows = []
    for line in PAGE.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and len(cells) == 3 and cells[0] not in ("中文", "---"):
            rows.append(cells)
    return rows


def _terms() -> set[str]:
    """The Chinese terms of the first column: 盈功、亏功 is two, 阿苏尔杆组（基本杆组）
    two, RPR 型Ⅱ级杆组 its Chinese part."""
    return {t for row in glossary() for t in CJK.findall(row[0])}


def _uncovered(text: str, terms: set[str]) -> list[str]:
    covered = [False] * len(text)
    for t in terms:
        for m in re.finditer(re.escape(t), text):
            covered[m.start() : m.end()] = [True] * len(t)
    out = []
    for h in HEADS:
        for m in re.finditer(re.escape(h), text):
            if not all(covered[m.start() : m.end()]):
                out.append(text[max(0, m.start() - 6) : m.end() + 4])
    return out


def test_every_row_has_its_english_and_where_the_textbook_defines_it():
    rows = glossary()
    assert len(rows) >= 60
    for zh, en, where in rows:
        assert CJK.search(zh) and re.search(r"[A-Za-z]", en), (zh, en)
        assert re.fullmatch(r"(第\d+章 \S+(（[^）]*）)?(；|$))+|— （docs/\w+\.md）", where), where


def test_every_term_of_the_chinese_report_is_in_the_glossary():
    terms = _terms()
    texts = [t.replace("{c}", "Ⅱ") for t in ZH.values()]  # a class: RPR 型{c}级杆组
    missing = {u for text in texts for u in _uncovered(text, terms)}
    assert not missing, sorted(missing)


def test_the_check_finds_a_missing_term():
    assert _uncovered("机构自锁时", _terms() - {"自锁"}) == ["机构自锁时"]
    assert _uncovered("机构自锁时", _terms()) == []
