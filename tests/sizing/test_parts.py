"""Pins, sections and fatigue (sizing/stage.py, sections.py, fatigue.py) by hand, and the
sizing keys' refusals: one line naming the key path and its line."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.model.sizing import SectionSpec
from kinetostatics.sizing import sizing_stage
from kinetostatics.sizing.fatigue import cycle_of, safety_factor
from kinetostatics.sizing.sections import section_properties
from tests.helpers import ROOT

SIZED = ROOT / "mechanisms" / "slider_crank_sized.yaml"


@pytest.fixture(scope="module")
def sized():
    result = ks.analyze(ks.load(SIZED))
    return result, sizing_stage(result)


def test_pin_shear_by_hand(sized):
    """τ = F/(k·πd²/4) for k shear planes; the eye's pressure F/(d·w)."""
    result, sizing = sized
    for joint, d, k, w in (("O", 0.020, 2, 0.015), ("A", 0.016, 2, 0.010), ("B", 0.012, 1, 0.014)):
        pin = next(p for p in sizing.pins if p.joint == joint)
        F = np.hypot(result[f"{joint}.Fx"], result[f"{joint}.Fy"])
        assert pin.planes == k
        assert np.allclose(pin.shear, F / (k * math.pi * d * d / 4), rtol=1e-12, atol=0)
        assert np.allclose(pin.eye_pressure, F / (d * w), rtol=1e-12, atol=0)
        assert pin.peak_shear >= pin.shear.max()


@pytest.mark.parametrize(
    "shape, dims, area, modulus",
    [
        ("rectangle", {"width": 12, "height": 30}, 360.0, 12 * 30**2 / 6),
        ("circle", {"diameter": 20}, math.pi * 100, math.pi * 8000 / 32),
        ("tube", {"diameter": 25, "thickness": 3}, math.pi * (625 - 361) / 4,
         math.pi * (25**4 - 19**4) / (32 * 25)),
        # I: two 14 x 4 flanges and a 16 x 4 web; I = (14·24³ − 10·16³)/12
        ("I", {"height": 24, "width": 14, "web": 4, "flange": 4}, 176.0,
         (14 * 24**3 - 10 * 16**3) / 12 / 12),
    ],
)  # fmt: skip
def test_section_properties_by_hand(shape, dims, area, modulus):
    A, Z = section_properties(SectionSpec(shape, {k: v * 1e-3 for k, v in dims.items()}))
    assert A == pytest.approx(area * 1e-6, rel=1e-12)
    assert Z == pytest.approx(modulus * 1e-9, rel=1e-12)


def test_goodman_and_soderberg_by_hand():
    """σ from −40 to 120 MPa: σ_m = 40, σ_a = 80; with S_e = 250, S_ut = 600, S_y = 350:
    Goodman 1/(80/250 + 40/600) = 2.586, Soderberg 1/(80/250 + 40/350) = 2.303; a
    compressive mean: S_e/σ_a."""
    m, a = cycle_of([-40.0, 0.0, 120.0, 30.0])
    assert (m, a) == (40.0, 80.0)
    assert safety_factor(m, a, 250.0, 600.0) == pytest.approx(1 / (0.32 + 40 / 600), rel=1e-14)
    assert safety_factor(m, a, 250.0, 350.0) == pytest.approx(1 / (0.32 + 40 / 350), rel=1e-14)
    assert safety_factor(-10.0, 50.0, 250.0, 600.0) == 5.0


def test_the_links_factors_come_from_their_critical_fibre(sized):
    """The crank's Goodman factor is the least of its two outer fibres' at the critical
    station, computed here from the stored N and M at the rows (the nodes may only lower
    it)."""
    _, sizing = sized
    crank = next(x for x in sizing.links if x.link == "crank")
    k = crank.critical
    sig = [crank.N[:, k] / crank.area + s * crank.M[:, k] / crank.modulus for s in (1, -1)]
    rows = min(safety_factor(*cycle_of(f), 250e6, 600e6) for f in sig)
    assert crank.factors["goodman"] <= rows * (1 + 1e-12)
    assert crank.factors["goodman"] >= rows * 0.95
    assert crank.factors["yield"] == pytest.approx(350e6 / crank.peak_stress, rel=1e-12)


def test_friction_radius_from_the_bearing():
    """A friction coefficient alone takes the bearing's bore: ρ = μ·d/2."""
    text = SIZED.read_text().replace("friction: {radius: 1.2}", "friction: {coefficient: 0.08}")
    model = ks.loads(text, file="mu.yaml")
    assert model.joint("A").rho == pytest.approx(0.08 * 0.016 / 2, rel=1e-12)


@pytest.mark.parametrize(
    "old, new, key, message",
    [
        ("thickness: 3", "thickness: 13", "links.rod.section.thickness",
         "a tube's wall (13 mm) is thicker than its radius (12.5 mm)"),
        ("C: 12700", "C: -12700", "joints.O.bearing.C", "must be positive, got -12700"),
        ("width: 20, p_max", "width: 0, p_max", "joints.A.bearing.width",
         "must be positive, got 0"),
        ("shape: circle", "shape: hexagon", "links.crank.section.shape",
         "unknown section shape 'hexagon'"),
        ("S_y: 350", "S_y: 700", "links.crank.material.S_y",
         "the yield strength S_y exceeds the ultimate strength S_ut (700 > 600)"),
        ("flange: 4", "flange: 12", "links.rod.section.flange",
         "an I section's two flanges are as deep as its height"),
        ("{type: ball, C: 12700, diameter: 20}", "{type: ball, diameter: 20}",
         "joints.O.bearing", "a ball bearing needs C"),
    ],
)  # fmt: skip
def test_impossible_data_is_one_line(old, new, key, message):
    text = SIZED.read_text()
    text = text.replace("section: {shape: rectangle, width: 12, height: 30}",
                        "section: {shape: circle, diameter: 20}")  # fmt: skip
    if "thickness" in old:
        text = text.replace("section: {shape: I, height: 24, width: 14, web: 4, flange: 4}",
                            "section: {shape: tube, diameter: 25, thickness: 3}")  # fmt: skip
    assert old in text
    with pytest.raises(ks.ModelError) as info:
        ks.loads(text.replace(old, new), file="bad.yaml")
    lines = str(info.value).strip().splitlines()
    assert len(lines) == 1, lines
    line_no = next(i for i, t in enumerate(text.replace(old, new).splitlines(), 1) if new in t)
    assert re.match(rf"bad\.yaml:{line_no}:\d+: {re.escape(key)}: ", lines[0]), lines[0]
    assert message in lines[0]
