"""The report speaks the textbook's language (孙桓《机械原理》): Assur groups by their class
(RPR 型Ⅱ级杆组), the crank angle between the limit positions θ (极位夹角) beside K, the
balancing torque M_b (平衡力矩), total reactions F_R (总反力), the inertia couple M_I
(惯性力偶矩), a load event by where the point is in its travel, and no "peak |·|"; it
states assumptions, never the program's files or numerical rules."""

import math
import re

import pytest
from scipy.optimize import brentq

from kinetostatics.cli import main
from kinetostatics.dynamics.flywheel import ASSUMPTIONS as FLYWHEEL_ASSUMPTIONS
from kinetostatics.dynamics.stages import full_summary
from kinetostatics.outputs import lang
from kinetostatics.outputs import plotting as pl
from kinetostatics.outputs.loading import load
from kinetostatics.outputs.report.drive import ASSUMPTIONS as DRIVE_ASSUMPTIONS
from kinetostatics.outputs.report.results import _summary_blocks, crank_angle_between
from tests.helpers import ROOT, motion_driven, variant

# what a student's report must not name: the program's files, modules and numerical rules
IMPLEMENTATION = re.compile(
    r"\.py\b|analysis/|Gauss|Legendre|quadrature|brentq|numpy|scipy|高斯|勒让德|求积",
    re.IGNORECASE,
)


def _report(path, out, lang_code):
    args = ["report", str(path), "--out", str(out), "--format", "md", "--dpi", "30"]
    assert main(args + ["--lang", lang_code]) == 0
    return (out / "report.md").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def slotting(slotting_reports):
    return {c: (d / "report.md").read_text(encoding="utf-8") for c, d in slotting_reports.items()}


def _items(model, lang_code):
    """The list items of the results chapter (section 3) of a model's report."""
    result = pl.analyze_for_pictures(model, course=True, events=True)
    blocks = _summary_blocks(result, full_summary(result), lang_code)
    return next(b.items for b in blocks if hasattr(b, "items"))


def test_assur_groups_by_class(slotting):
    zh, en = slotting["zh"], slotting["en"]
    assert "| RPR 型Ⅱ级杆组 {block, bar} |" in zh and "| RRP 型Ⅱ级杆组 {rod, ram} |" in zh
    assert "机构级别：Ⅱ级机构" in zh and "二杆组" not in zh
    assert "| RPR dyad (class II) {block, bar} |" in en
    assert "class of the mechanism: class II" in en


def test_a_class_three_group_in_the_report():
    model = load(ROOT / "mechanisms" / "stephenson_sixbar.yaml")
    result = pl.analyze_for_pictures(model, course=True, events=True)
    from kinetostatics.outputs.report.data import _structure_blocks

    text = str(_structure_blocks(result.system, "zh"))
    assert "Ⅲ级杆组（4 个构件）{rod, beam, upper, lower}" in text and "Ⅲ级机构" in text


def test_crank_angle_between_the_limit_positions(slotting):
    """θ printed beside K: the guide-bar mechanism's θ is its swing, 2·asin(O2A/O2O3) =
    60°; from the limit positions directly, it is 180°(K − 1)/(K + 1) of the printed K."""
    zh = re.findall(r"行程速比系数 K = ([\d.]+)，极位夹角 θ = ([\d.]+)°", slotting["zh"])
    en = re.findall(
        r"time ratio K = ([\d.]+), crank angle between the limit positions θ = ([\d.]+)°",
        slotting["en"],
    )
    assert len(zh) == 2 and zh == en
    for k, theta in zh:
        assert float(theta) == pytest.approx(2 * math.degrees(math.asin(75 / 150)), abs=5e-4)
        assert float(theta) == pytest.approx(180 * (float(k) - 1) / (float(k) + 1), abs=1e-3)


@pytest.mark.parametrize(
    "name, closed",
    [
        # the offset slider-crank (a = 100, b = 350, e = 20): the crank's two positions in
        # line with the rod, θ = asin(e/(b − a)) − asin(e/(b + a))
        ("slider_crank", math.degrees(math.asin(20 / 250) - math.asin(20 / 450))),
        # the shaper's lever tangent to the crank circle: θ = 2·asin(O2A/O2O3)
        ("shaper", 2 * math.degrees(math.asin(110 / 380))),
    ],
)
def test_theta_from_the_limit_positions_is_the_closed_form_and_agrees_with_k(name, closed):
    result = pl.analyze_for_pictures(load(ROOT / "mechanisms" / f"{name}.yaml"), course=True)
    outputs = full_summary(result)["outputs"]
    assert outputs
    for o in outputs.values():
        lo, hi = o["limit_positions"]["min"]["angle"], o["limit_positions"]["max"]["angle"]
        theta = crank_angle_between(lo, hi)
        assert theta == pytest.approx(closed, abs=1e-9 * 360)
        k = o["time_ratio"]
        assert theta == pytest.approx(180 * (k - 1) / (k + 1), abs=1e-9 * 360)


# the offset slider-crank, its resistance acting over a band of the slider's travel: B at
# (x, e), x(φ) = a·cos φ + √(b² − (e − a·sin φ)²), between x_min = √((b − a)² − e²) and
# x_max = √((a + b)² − e²)
A, B, E = 100.0, 350.0, -20.0


def _x(phi):
    return A * math.cos(phi) + math.sqrt(B**2 - (E - A * math.sin(phi)) ** 2)


@pytest.mark.parametrize("axis", [-1, 1])
def test_a_load_event_says_where_the_point_is_in_its_travel(axis):
    """Travel along (−1, 0) is measured from the rightmost position, along (1, 0) from the
    leftmost: the band [30, 150] mm switches where x = x_max − 30, x_max − 150 (x_min + 30,
    x_min + 150), at the closed form's crank angles."""
    model = variant(
        "slider_crank",
        act=(r"- moving: \[1, 0\] .*", f"- travel: [30, 150]\n        along: [{axis}, 0]"),
    )
    x_max, x_min = math.sqrt((A + B) ** 2 - E**2), math.sqrt((B - A) ** 2 - E**2)
    extended, folded = math.atan2(E, x_max), math.atan2(E, x_min) + math.pi
    middle = extended if axis < 0 else folded
    angles = {}
    for s in (30.0, 150.0):
        target = x_max - s if axis < 0 else x_min + s
        for side in (-1, 1):
            end = middle + side * math.pi * 0.99
            phi = brentq(lambda p, t=target: _x(p) - t, *sorted((middle, end)))
            angles[round(math.degrees(phi) % 360.0, 4)] = s
    end = "rightmost" if axis < 0 else "leftmost"
    got = [i for i in _items(model, "en") if i.startswith("event:")]
    assert len(got) == 4
    for item in got:
        m = re.fullmatch(
            rf"event: resistance switches (on|off) at φ = ([\d.]+)° \(slider\.B (\d+) mm "
            rf"from its {end} position\)",
            item,
        )
        assert m, item
        near = min(angles, key=lambda a: abs(a - float(m[2])))
        assert abs(near - float(m[2])) <= 1.5e-4 and float(m[3]) == angles[near]
    zh = [i for i in _items(model, "zh") if i.startswith("事件")]
    word = "最右" if axis < 0 else "最左"
    assert len(zh) == 4 and all(f"slider.B 距其{word}位置" in i for i in zh)


def test_the_slotting_machine_cuts_from_near_its_top(slotting):
    """The ram cuts downwards from 5 % of its stroke below the top (the travel is measured
    down from the top): the event is near the top, never called the stroke's lower limit."""
    assert "cutting 在 φ = 270.4218° 处开始作用（ram.tool 距其最高位置 5 mm）" in slotting["zh"]
    assert "行程下限" not in slotting["zh"] and "行程上限" not in slotting["zh"]
    assert "(ram.tool 5 mm from its highest position)" in slotting["en"]


def test_balancing_torque_total_reactions_inertia_couple(slotting):
    zh, en = slotting["zh"], slotting["en"]
    for term in ("平衡力矩 M_b", "总反力 F_R", "惯性力偶矩 M_I", "极位夹角 θ", "绝对值最大"):
        assert term in zh, term
    for term in ("balancing torque M_b", "total reactions F_R", "inertia couples M_I"):
        assert term in en, term
    for text in (zh, en):
        assert "|·|" not in text and "峰值" not in text and "的驱动力矩" not in text


def _implementation(text: str) -> list[str]:
    return [m.group(0) for m in IMPLEMENTATION.finditer(text)]


def test_the_translation_table_names_no_implementation():
    """Every text the report and its pictures print, in both languages: the table's
    English keys and Chinese values, and the assumptions of the flywheel and the drive."""
    texts = list(lang.ZH) + list(lang.ZH.values())
    texts += list(FLYWHEEL_ASSUMPTIONS) + list(DRIVE_ASSUMPTIONS)
    assert not [t for t in texts if _implementation(t)]


def test_no_peak_of_a_bar_in_the_table():
    """'峰值 |·|', '峰值 |转矩|' are not notation: the largest magnitude (绝对值最大)."""
    texts = list(lang.ZH) + list(lang.ZH.values())
    assert not [t for t in texts if "|·|" in t or re.search(r"峰值 ?\|", t)]


def test_the_slotting_report_names_no_implementation(slotting):
    for text in slotting.values():
        assert not _implementation(text)


@pytest.mark.slow
@pytest.mark.parametrize("name", motion_driven())
def test_no_shipped_report_names_its_implementation(name, tmp_path):
    path = ROOT / "mechanisms" / f"{name}.yaml"
    for code in ("en", "zh"):
        text = _report(path, tmp_path / code, code)
        assert not _implementation(text), (code, _implementation(text))


def test_the_loads_drawn_name_the_balancing_torque():
    """The drawing of the loads at a position labels the driver's torque M_b."""
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    result = pl.analyze_for_pictures(load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    fig = pl.draw_mechanism(result, row=30, forces=True, dpi=30)
    texts = [t.get_text() for t in fig.findobj(Text)]
    plt.close(fig)
    assert any(t.startswith("M_b") for t in texts), texts
    assert not any("M_motor" in t for t in texts)


def test_the_output_is_named_by_the_member_that_moves():
    """The shaper's output is the ram, link 6 in the guide's numbering (frame 1, crank 2,
    block 3, guide bar 4, link 5, ram 6), measured at its slide `guide`: the report names
    the member (构件6 ram), not the pair, in the results and the motion diagram's caption."""
    model = load(ROOT / "mechanisms" / "shaper.yaml")
    zh = [i for i in _items(model, "zh") if i.startswith("输出")]
    en = [i for i in _items(model, "en") if i.startswith("output")]
    assert len(zh) == len(en) == 1
    assert zh[0].startswith("输出 构件6 ram：行程")
    assert en[0].startswith("output link 6 ram: stroke")


def test_captions_name_friction_solutions_only_where_a_joint_has_friction(tmp_path, slotting):
    """The balancing torque's table and picture of a file without friction (the balanced
    four-bar) say so, instead of promising friction columns and curves it has not; the
    table of the largest reactions has no (empty) column with friction."""
    md = _report(ROOT / "mechanisms" / "fourbar_balancing.yaml", tmp_path / "out", "en")
    assert "consistent friction solution" not in md
    assert md.count("no joint has friction") >= 2  # the table's caption and the picture's
    assert "largest |F_R| with friction" not in md.replace("\\|", "|")  # no empty column
    assert "consistent friction solution" in slotting["en"]  # the slotting machine has it
