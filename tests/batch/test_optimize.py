"""Counterweights, the shaking quantities of the batch row, and ``optimize``
(docs/optimisation.md).  Expected values from closed forms: Newton's law for the whole
mechanism, the parallel-axis theorem, the Berkof–Lowen balance of a four-bar and the
geometry of a centred slider-crank."""

from __future__ import annotations

import math
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.batch.objectives import Constraint, OptimizeError
from kinetostatics.batch.variants import Template, analyze_variants
from kinetostatics.cli import main

ROOT = Path(__file__).resolve().parents[2]

# links in frames along their lines: crank A0→A, coupler A→B, rocker B0→B (metres, kg)
A2, A3, A4, D = 0.10, 0.35, 0.25, 0.30
M2, S2 = 1.0, (0.04, 0.01)
M3, C3 = 2.0, (0.15, 0.02)
M4, S4 = 1.5, (0.10, -0.01)
MC1, MC2 = 1.0, 2.0  # the counter-masses

# the shipped example of docs/optimisation.md, written with the numbers above
FOURBAR_FILE = ROOT / "mechanisms" / "fourbar_balancing.yaml"
FOURBAR = FOURBAR_FILE.read_text(encoding="utf-8")


SLIDER_CRANK = """
name: centred slider-crank
units: {length: mm, angle: deg, speed: rpm}
parameters:
  a: 80         # crank
  b: 300        # rod
links:
  ground: {points: {O: [0, 0], guide: [0, 0]}}
  crank: {points: {O: [0, 0], A: [a, 0]}, com: [a/2, 0], mass: 1, inertia: 0.001}
  rod: {points: {A: [0, 0], B: [b, 0]}, com: [b/2, 0], mass: 2, inertia: 0.01}
  slider: {points: {B: [0, 0]}, mass: 1}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, rod]}
  B: {type: revolute, links: [rod, slider]}
  slide: {type: prismatic, links: [ground, slider], axis: {point: guide, direction: [1, 0]},
          point: B}
drivers:
  motor: {joint: O, motion: {speed: 60}}
sketch: {A: [a, 0], B: [a + b, 0]}
analysis: {start: 0, sweep: 360, positions: 36}
"""


def balance_closed_form():
    """The counter-mass places that balance the four-bar's shaking force exactly.

    With complex numbers in the ground frame, the total centre of mass is
    M·r_G = m₂'s₂'e^{iθ₂} + m₃(a₂e^{iθ₂} + c₃e^{iθ₃}) + m₄'(d + s₄'e^{iθ₄}), where
    s₂', s₄' are the crank's and rocker's centres of mass (with their counter-masses,
    m₂' = m₂ + m_c1, m₄' = m₄ + m_c2) and c₃ the coupler's, each as a complex number in
    its link's frame (the frames lie along A0→A, A→B, B0→B).  The loop
    a₂e^{iθ₂} + a₃e^{iθ₃} = d + a₄e^{iθ₄} gives e^{iθ₃} = (d + a₄e^{iθ₄} − a₂e^{iθ₂})/a₃,
    so M·r_G = const + e^{iθ₂}[m₂'s₂' + m₃a₂(1 − c₃/a₃)] + e^{iθ₄}[m₄'s₄' + m₃c₃a₄/a₃].
    For a crank-rocker e^{iθ₂} and e^{iθ₄} are linearly independent functions of time
    (the method of linearly independent vectors, Berkof & Lowen 1969), so r_G is
    stationary — the shaking force −M·r̈_G is zero at every instant — iff both brackets
    vanish: m₂'s₂' = m₃a₂(c₃/a₃ − 1) and m₄'s₄' = −m₃(a₄/a₃)c₃.  With
    m₂'s₂' = m₂s₂ + m_c1·p₁ (and likewise on the rocker), the places are
    p₁ = [m₃a₂(c₃/a₃ − 1) − m₂s₂]/m_c1, p₂ = [−m₃(a₄/a₃)c₃ − m₄s₄]/m_c2."""
    s2, c3, s4 = complex(*S2), complex(*C3), complex(*S4)
    p1 = (M3 * A2 * (c3 / A3 - 1) - M2 * s2) / MC1
    p2 = (-M3 * (A4 / A3) * c3 - M4 * s4) / MC2
    return {"x1": p1.real, "y1": p1.imag, "x2": p2.real, "y2": p2.imag}


def test_counterweight_is_the_link_edited_by_hand():
    """A disc on the crank gives the results of the crank's mass, centre of mass and
    inertia edited by hand (the parallel-axis theorem worked out here)."""
    m0, c0, j0 = M2, np.array(S2), 0.001
    mc, p, jc = 0.7, np.array([-0.06, 0.015]), 0.0003
    m = m0 + mc
    c = (m0 * c0 + mc * p) / m
    j = j0 + m0 * np.sum((c0 - c) ** 2) + jc + mc * np.sum((p - c) ** 2)
    disc = FOURBAR.replace(
        "{cw1: {at: [x1, y1], mass: 1.0}}",
        f"{{cw1: {{at: [{p[0]}, {p[1]}], mass: {mc}, inertia: {jc}}}}}",
    ).replace("{cw2: {at: [x2, y2], mass: 2.0}}", "{}")
    by_hand = (
        FOURBAR.replace(f"com: [{S2[0]}, {S2[1]}]", f"com: [{float(c[0])!r}, {float(c[1])!r}]")
        .replace(f"mass: {M2}\n", f"mass: {float(m)!r}\n", 1)
        .replace("inertia: 0.001", f"inertia: {float(j)!r}")
        .replace("counterweights: {cw1: {at: [x1, y1], mass: 1.0}}", "")
        .replace("counterweights: {cw2: {at: [x2, y2], mass: 2.0}}", "")
    )
    assert "cw1: {at: [-0.06" in disc and "cw1" not in by_hand and "cw2" not in by_hand
    ra = ks.analyze(ks.loads(disc), friction=False)
    rb = ks.analyze(ks.loads(by_hand), friction=False)
    assert set(ra.columns) == set(rb.columns)
    for name in ra.columns:
        a, b = np.asarray(ra[name], float), np.asarray(rb[name], float)
        scale = max(1.0, float(np.max(np.abs(b))))
        assert np.max(np.abs(a - b)) <= 1e-12 * scale, name


def test_shaking_quantities_are_newtons_law():
    """With no gravity and no loads the frame feels −Σ mᵢaᵢ (the motor's reaction is a
    couple): the row's shaking force peak and RMS are those of |Σ mᵢaᵢ| over the rows."""
    model = ks.loads(FOURBAR)
    result = ks.analyze(model, friction=False)
    fx = sum(lk.mass * result[f"{lk.name}.ax"] for lk in model.links if not lk.ground)
    fy = sum(lk.mass * result[f"{lk.name}.ay"] for lk in model.links if not lk.ground)
    np.testing.assert_allclose(result["shaking.Fx"], -fx, atol=1e-9 * np.max(np.abs(fx)))
    mag = np.hypot(fx, fy)
    row = analyze_variants(Template.loads(FOURBAR), [{}])[0]
    assert row["shaking.force_peak"] == pytest.approx(np.max(mag), rel=1e-9)
    assert row["shaking.force_rms"] == pytest.approx(np.sqrt(np.mean(mag**2)), rel=1e-9)
    assert row["shaking.moment_peak"] == pytest.approx(np.max(np.abs(result["shaking.M"])))


def test_the_shipped_fourbar_has_the_numbers_of_the_closed_form():
    """The closed form's inputs are the file's: lengths, centres of mass, masses."""
    model = ks.load(FOURBAR_FILE)
    assert model.gravity.tolist() == [0.0, 0.0] and not model.loads
    lines = [
        f"B0: [{D}, 0]",
        f"A: [{A2}, 0]",
        f"B: [{A3}, 0]",
        f"B: [{A4}, 0]",
        f"com: [{S2[0]}, {S2[1]}]",
        f"com: [{C3[0]}, {C3[1]}]",
        f"com: [{S4[0]}, {S4[1]}]",
        f"mass: {M2}\n",
        f"mass: {M3},",
        f"mass: {M4}\n",
        f"{{cw1: {{at: [x1, y1], mass: {MC1}}}}}",
        f"{{cw2: {{at: [x2, y2], mass: {MC2}}}}}",
    ]
    for line in lines:
        assert line in FOURBAR, line


def test_the_documented_command_balances_the_fourbar(tmp_path):
    """docs/optimisation.md's command finds the Berkof–Lowen places (to 1e-6 m) and a
    shaking force peak below 1e-6 of the unbalanced one, checked at 360 positions (the
    search saw 12)."""
    doc = (ROOT / "docs" / "optimisation.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```sh\n(.*?)```", doc, re.S)
    (command,) = [b for b in blocks if "fourbar_balancing.yaml" in b]
    argv = shlex.split(command.replace("\\\n", " "))
    assert argv[:2] == ["kinetostatics", "optimize"]
    out = tmp_path / "opt"
    argv[argv.index("--out") + 1] = str(out)
    argv[argv.index("mechanisms/fourbar_balancing.yaml")] = str(FOURBAR_FILE)
    assert main([*argv[1:], "--quiet"]) == 0
    best = ks.load(out / "best.yaml").parameters
    for name, value in balance_closed_form().items():
        assert best[name] == pytest.approx(value, abs=1e-6), name
    template = Template.load(FOURBAR_FILE)
    found = {n: best[n] for n in ("x1", "y1", "x2", "y2")}
    before, after = analyze_variants(template, [{}, found], positions=360)
    assert after["shaking.force_peak"] < 1e-6 * before["shaking.force_peak"]


def test_optimiser_finds_the_constrained_slider_crank(tmp_path):
    """Shortest crank + rod of a centred slider-crank with a stroke H = 100 mm and a
    pressure angle at most 30°: the stroke is 2a (so a ≥ H/2) and the largest pressure
    angle asin(a/b) (at 90°, a row) (so b ≥ a/sin 30° = 2a); a + b is least at a = 50,
    b = 100 mm, both constraints active."""
    path = tmp_path / "sc.yaml"
    path.write_text(SLIDER_CRANK)
    out = tmp_path / "out"
    code = main(
        [
            "optimize",
            str(path),
            "--vary",
            "a=20:120",
            "--vary",
            "b=60:400",
            "--minimize",
            "a + b",
            "--subject-to",
            "slide.stroke >= 0.1",
            "--subject-to",
            "rod_slider.pressure_angle_max <= 30",
            "--maxiter",
            "20",
            "--out",
            str(out),
            "--quiet",
        ]
    )
    assert code == 0
    best = ks.load(out / "best.yaml")
    assert best.parameters["a"] == pytest.approx(50.0, rel=1e-7)
    assert best.parameters["b"] == pytest.approx(100.0, rel=1e-7)
    text = (out / "best.yaml").read_text()
    assert "# crank" in text and "# rod" in text  # the file as written, values replaced
    designs = (out / "designs.csv").read_text()
    assert ",failed," in designs  # b < a cannot assemble: a design, not a crash
    assert (out / "convergence.png").read_bytes()[:4] == b"\x89PNG"


def test_bad_expressions_name_what_was_written(tmp_path):
    path = tmp_path / "sc.yaml"
    path.write_text(SLIDER_CRANK)
    with pytest.raises(OptimizeError, match="slide.strok'.*did you mean 'slide.stroke'"):
        ks.optimize(path, {"a": (20, 120)}, "slide.strok", maxiter=1, progress=False)
    with pytest.raises(OptimizeError, match="no parameter 'c'"):
        ks.optimize(path, {"c": (20, 120)}, "a", progress=False)
    with pytest.raises(OptimizeError, match="one comparison"):
        Constraint.parse("a == 3")
    with pytest.raises(OptimizeError, match="LO < HI"):
        ks.optimize(path, ["a=5:1"], "a", progress=False)
    assert math.isnan(Constraint.parse("x <= 1").violation({}))
