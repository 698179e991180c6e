"""The 12-position drawing (outputs/plotting/sheet.py, ``plot --sheet``).

Read back independently of the code that wrote it: the PDF's page box (points → mm) is an
A2 or A1 sheet; the DXF (read with ezdxf) holds each link at each course position, whose
length on the sheet times the scale n is the length the file gives (the slotting
machine's crank L_O2A = 75 mm and rod L_BC = 100 mm, from its ``parameters:``); the scale
is one of 1, 2, 2.5, 4, 5 × 10^k.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.outputs.plotting.export import APP
from tests.helpers import ROOT

ezdxf = pytest.importorskip("ezdxf")

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"
SHAPER = ROOT / "mechanisms" / "shaper.yaml"
SHEETS_MM = {(594.0, 420.0), (841.0, 594.0)}
COURSE = [str(k) for k in range(1, 13)]


@pytest.fixture(scope="module")
def slotting_dxf(tmp_path_factory):
    out = tmp_path_factory.mktemp("sheet") / "slotting.dxf"
    assert main(["plot", str(SLOTTING), "--sheet", str(out)]) == 0
    return ezdxf.readfile(str(out))


def _round(n: float) -> bool:
    k = math.floor(math.log10(n))
    return any(abs(n - m * 10.0**k) < 1e-12 * n for m in (1.0, 2.0, 2.5, 4.0, 5.0, 10.0))


def _scale(doc) -> float:
    texts = [e.dxf.text for e in doc.modelspace().query("TEXT") if e.dxf.layer == "TITLE"]
    (scale,) = [t for t in texts if re.fullmatch(r"\d+(\.\d+)?:\d+(\.\d+)?", t)]
    a, b = (float(v) for v in scale.split(":"))
    return b / a  # 1:n


def _tags(entity):
    return [v for _, v in entity.get_xdata(APP)] if entity.has_xdata(APP) else []


def test_the_dxf_is_in_sheet_mm_and_the_scale_is_round(slotting_dxf):
    assert slotting_dxf.header["$INSUNITS"] == 4  # mm
    n = _scale(slotting_dxf)
    assert _round(n)
    border = [e for e in slotting_dxf.modelspace().query("LWPOLYLINE") if e.dxf.layer == "BORDER"]
    sizes = {tuple(np.ptp(np.array(e.get_points("xy")), axis=0)) for e in border}
    assert sizes & SHEETS_MM  # the sheet's edge


@pytest.mark.parametrize(("link", "length_mm"), [("crank", 75.0), ("rod", 100.0)])
def test_a_link_measured_on_the_drawing_times_the_scale_is_the_files(slotting_dxf, link, length_mm):
    n = _scale(slotting_dxf)
    found = 0
    for e in slotting_dxf.modelspace().query("LWPOLYLINE"):
        tags = _tags(e)
        if tags[:2] == ["link", link]:
            (p, q) = np.array(e.get_points("xy"))
            assert float(np.hypot(*(q - p))) * n == pytest.approx(length_mm, rel=1e-9)
            found += 1
    assert found >= 12


def test_every_course_position_is_drawn_and_the_working_one_heavy(slotting_dxf):
    model = ks.load(SLOTTING)
    moving = {lk.name for lk in model.links if not lk.ground}
    by_position: dict[str, set] = {}
    for e in slotting_dxf.modelspace():
        tags = _tags(e)
        if len(tags) == 3 and tags[0] in ("link", "block", "joint"):
            by_position.setdefault(tags[2], set()).add((tags[0], tags[1], e.dxf.layer))
    for label in COURSE:
        links = {name for what, name, _ in by_position[label] if what == "link"}
        assert links == moving - {"block"}, label  # each bar; the block is drawn as a block
        assert any(what == "block" for what, _, _ in by_position[label])
    layers = {lab: {layer for *_, layer in v} for lab, v in by_position.items()}
    # position 1 by default (here also a limit position: the ram at its top)
    assert layers["1"] - {"LIMITS"} == {"WORKING"}
    assert all(layers[lab] - {"LIMITS"} == {"POSITIONS"} for lab in COURSE[1:])


def test_the_pdf_is_an_a2_or_a1_sheet_at_true_size(tmp_path):
    out = tmp_path / "shaper.pdf"
    assert main(["plot", str(SHAPER), "--sheet", str(out), "--working", "7"]) == 0
    box = re.search(
        rb"/MediaBox\s*\[\s*([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)", out.read_bytes()
    )
    x0, y0, x1, y1 = (float(v) for v in box.groups())
    size = ((x1 - x0) / 72 * 25.4, (y1 - y0) / 72 * 25.4)
    assert any(abs(size[0] - w) < 0.1 and abs(size[1] - h) < 0.1 for w, h in SHEETS_MM), size


def test_the_working_position_and_the_limit_positions_are_on_their_layers(tmp_path):
    out = tmp_path / "shaper.dxf"
    assert main(["plot", str(SHAPER), "--sheet", str(out), "--working", "7"]) == 0
    doc = ezdxf.readfile(str(out))
    layers: dict[str, set] = {}
    for e in doc.modelspace():
        tags = _tags(e)
        if len(tags) == 3:
            layers.setdefault(e.dxf.layer, set()).add(tags[2])
    assert layers["WORKING"] == {"7"}
    assert "7" not in layers["POSITIONS"]
    assert len(layers["LIMITS"]) == 2  # the ram's two extreme positions
    assert doc.layers.get("LIMITS").dxf.linetype == "PHANTOM"


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["--sheet", "OUT.png"], "the sheet is written as .pdf or .dxf"),
        (["--sheet", "OUT.pdf", "--working", "13"], "--working 13: no course position"),
        (["--working", "3"], "--working: the heavy position of the --sheet"),
    ],
)
def test_a_mistake_is_one_line_and_exit_2(tmp_path, capsys, args, says):
    args = [a.replace("OUT", str(tmp_path / "out")) for a in args]
    assert main(["plot", str(SHAPER), "--out", str(tmp_path), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says in err[0]


LONG = """\
name: long slider-crank
units: {length: mm, angle: deg, speed: rpm}
links:
  ground: {points: {O: [0, 0], guide: [0, 0]}}
  crank: {points: {O: [0, 0], A: [30, 0]}, mass: 1}
  rod: {points: {A: [0, 0], B: [600, 0]}, mass: 1}
  slider: {points: {B: [0, 0]}, mass: 1}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, rod]}
  B: {type: revolute, links: [rod, slider]}
  slide: {type: prismatic, links: [ground, slider], axis: {point: guide, direction: [1, 0]},
          point: B}
drivers:
  motor: {joint: O, motion: {speed: 300}}
sketch: {A: [30, 0], B: [630, 0]}
analysis: {start: 0, sweep: 360, positions: 24}
"""


def test_a1_when_the_shortest_link_would_be_too_short_on_a2():
    """About 700 mm of travel: 1:2 on A2 draws the 30 mm crank 15 mm long (under 20 mm);
    A1 holds it at 1:1, the crank 30 mm.  Asked for, A2 is kept."""
    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.plotting.sheet import MIN_LINK_MM, sheet_layout

    result = pl.analyze_for_pictures(ks.loads(LONG), course=True, events=False)
    auto, a2 = sheet_layout(result), sheet_layout(result, size="A2")
    assert (a2.size, a2.width, a2.height, a2.n) == ("A2", 594.0, 420.0, 2.0)
    assert 30.0 / a2.n < MIN_LINK_MM
    assert (auto.size, auto.width, auto.height, auto.n) == ("A1", 841.0, 594.0, 1.0)
    assert auto.scale_text() == "1:1" and a2.scale_text() == "1:2"
