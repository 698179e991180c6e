"""The report's sizing chapter (outputs/report/sizing.py, outputs/zh_sizing.py): its tables
hold the record's numbers, in English and Chinese, every text translated."""

from __future__ import annotations

import pytest

import kinetostatics as ks
from kinetostatics.outputs import lang
from kinetostatics.outputs.report.blocks import _Heading, _Table
from kinetostatics.outputs.report.sizing import sizing_blocks
from kinetostatics.outputs.zh import ZH
from kinetostatics.outputs.zh_sizing import ZH as SIZING_ZH
from kinetostatics.sizing import sizing_stage
from tests.helpers import ROOT


@pytest.fixture(scope="module")
def sizing():
    return sizing_stage(ks.analyze(ks.load(ROOT / "mechanisms" / "slider_crank_sized.yaml")))


def _image(fig, name, caption):
    import matplotlib.pyplot as plt

    plt.close(fig)
    return ("image", name, caption)


@pytest.mark.parametrize("language", ["en", "zh"])
def test_the_chapter_holds_the_records_numbers(sizing, language):
    lang.MISSING.clear()
    blocks = sizing_blocks(sizing, _image, language, 13, dpi=40)
    assert isinstance(blocks[0], _Heading) and blocks[0].text.startswith("13. ")
    tables = [b for b in blocks if isinstance(b, _Table)]
    assert len(tables) == 4  # rolling, plain, pins, links
    rolling = {r[0]: r for r in tables[0].rows}
    o = next(b for b in sizing.bearings if b.joint == "O")
    assert rolling["O"][-1] == f"{o.life[1]:.4g}"
    links = {r[0]: r for r in tables[3].rows}
    crank = next(x for x in sizing.links if x.link == "crank")
    assert links["crank"][7] == f"{crank.peak_stress * 1e-6:.4g}"
    assert links["crank"][11] == f"{crank.factors['goodman']:.4g}"
    assert any(b == ("image", "sizing_envelopes", b[2]) for b in blocks if isinstance(b, tuple))
    if language == "zh":
        assert not lang.MISSING, sorted(lang.MISSING)
        assert blocks[0].text == "13. 零件尺寸校核：轴承、销轴与构件"


def test_the_chinese_table_keeps_the_other_translations():
    """zh_sizing.py adds texts; it changes none that zh.py or zh_methods.py gives."""
    for key, text in SIZING_ZH.items():
        assert ZH[key] == text
    assert ZH["oscillating"] == "摆动" and ZH["roller"] == "滚子"
