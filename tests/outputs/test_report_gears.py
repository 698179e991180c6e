"""The gear chapter's blocks (outputs/report/gears.py) from methods.json's ``gears`` entry,
in English and Chinese: every formula of the record in its table with its quantity's name,
the notes translated, a file without gears without a chapter."""

from __future__ import annotations

import json
import math

import kinetostatics as ks
from kinetostatics.joints.gearing import GearData
from kinetostatics.methods.gears import Gears, gear_geometry, pair_geometry
from kinetostatics.outputs import lang
from kinetostatics.outputs.report.blocks import _Heading, _List, _Para, _Table, _to_markdown
from kinetostatics.outputs.report.gears import gear_blocks
from tests.helpers import variant


def _entry(source) -> dict:
    """methods.json's ``gears`` entry, through JSON as the report reads it."""
    gears = source if isinstance(source, Gears) else gear_geometry(source)
    return json.loads(json.dumps(gears.to_dict()))


def _texts(blocks) -> list[str]:
    out = []
    for b in blocks:
        if isinstance(b, _Table):
            out += b.header + [c for row in b.rows for c in row] + [b.caption]
        elif isinstance(b, _List):
            out += b.items
        else:
            out.append(b.text)
    return out


def test_the_chapter_lists_every_formula_with_its_quantity(tmp_path):
    entry = _entry(ks.load("mechanisms/jaw_crusher.yaml"))
    blocks = gear_blocks(entry, number=12)
    assert blocks[0] == _Heading(2, "12. Gears")
    (table,) = [b for b in blocks if isinstance(b, _Table)]
    rows = dict((formula, name) for name, formula in table.rows)
    assert len(table.rows) == len(entry["pairs"]["mesh"]["formulas"])
    assert rows["r_b1 = r_1 cos α = 46.985 mm"] == "base radius of gear 1"
    assert rows["z_1 = 20"] == "number of teeth of gear 1 (pinion)"
    assert rows["a = m(z_1 + z_2)/2 = 250 mm"] == "standard centre distance"
    assert any(name == "contact ratio" for name in rows.values())
    text = _to_markdown(blocks, tmp_path / "report.md")
    assert "46.985 mm" in text and "external mesh" in text


def test_the_chinese_chapter_has_every_text_translated():
    lang.MISSING.clear()
    undercut = Gears((pair_geometry(GearData("mesh", "external", ("a", "b"), (12, 40),
                                             (0.03, 0.1), math.radians(20.0))),))  # fmt: skip
    for entry in (_entry(ks.load("mechanisms/rack_rocker.yaml")), _entry(undercut)):
        texts = _texts(gear_blocks(entry, lang="zh"))
        assert not lang.MISSING, sorted(lang.MISSING)
        assert "11. 齿轮传动" in texts
    assert "齿轮 1 的基圆半径" in texts and "r_b1 = r_1 cos α = 28.191 mm" in texts
    assert any(t.startswith("齿轮 1（a）发生根切：x_1 = 0 < x_min1 = 0.29412") for t in texts)


def test_the_notes_and_the_incomplete_pairs():
    entry = _entry(Gears((pair_geometry(GearData("m", "internal", ("p", "ring"), (20, 60),
                                                 (0.05, 0.15), math.radians(20.0))),)))  # fmt: skip
    blocks = gear_blocks(entry)
    assert "number of teeth of gear 2 (ring, annulus)" in _texts(blocks)
    (notes,) = [b for b in blocks if isinstance(b, _List)]
    assert notes.items == [entry["pairs"]["m"]["notes"][0]["text"]]
    assert "internal mesh" in blocks[2].text
    model = variant(
        "rack_rocker", module=(r"module: m\n", "radius: r\n"), z=(r"    teeth: z\n", "")
    )
    para = gear_blocks(_entry(model), lang="zh")[-1]
    assert isinstance(para, _Para) and para.text.startswith("mesh：未给出齿轮的齿数")


def test_no_gears_no_chapter():
    assert gear_blocks(_entry(ks.load("mechanisms/slider_crank.yaml"))) == []
