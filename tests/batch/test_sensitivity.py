"""Sensitivities and Monte Carlo tolerances (batch/sensitivity.py, batch/tolerance.py)
against independent truth: the offset slider-crank's stroke in closed form, the peak
torque of a massless in-line slider-crank under a constant force written here, the
linearised variance of the stroke (a χ² bound on the sample's), the assembly condition
of the offset slider-crank for the failed samples, and a sample's row against a single
analysis of its design."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from kinetostatics.batch.runner import BatchOptions
from kinetostatics.batch.sensitivity import (
    STEP_FACTOR,
    SensitivityError,
    parse_tolerances,
    sensitivity,
)
from kinetostatics.batch.tolerance import monte_carlo
from kinetostatics.batch.variants import Template, summary_row
from tests.helpers import ROOT

SLIDER = ROOT / "mechanisms" / "slider_crank.yaml"
SERIAL = BatchOptions(executor="serial", positions=36, friction=False)


def stroke(a, b, e):
    """The offset slider-crank's stroke (the file's mm → m): the slide's two dead
    centres, crank and rod in line and folded."""
    return (math.sqrt((a + b) ** 2 - e**2) - math.sqrt((b - a) ** 2 - e**2)) / 1000.0


def stroke_gradient(a, b, e):
    """∂(stroke)/∂(a, b, e) of :func:`stroke`, by hand (m per mm)."""
    r1, r2 = math.sqrt((a + b) ** 2 - e**2), math.sqrt((b - a) ** 2 - e**2)
    return (
        np.array([(a + b) / r1 + (b - a) / r2, (a + b) / r1 - (b - a) / r2, -e / r1 + e / r2])
        / 1000.0
    )


def test_the_stroke_sensitivities_are_the_closed_forms_derivatives():
    s = sensitivity(SLIDER, ["a=±1", "b=±1%", "e=±0.5"], ["slide.stroke"], options=SERIAL)
    a, b, e = 100.0, 350.0, -20.0
    assert s.nominal[0] == pytest.approx(stroke(a, b, e), rel=1e-12)
    truth = stroke_gradient(a, b, e)
    for d, want, p in zip(s.of("slide.stroke"), truth, (a, b, e)):
        assert d.step == pytest.approx(STEP_FACTOR * abs(p))  # every |p| > its tolerance
        # within its own error estimate (a few times it), and the estimate is small
        assert abs(d.value - want) <= 4 * d.error + 1e-12 * abs(want), d
        assert d.error <= 1e-7 * abs(want)
        assert not d.flagged
    # the tornado's ends are the stroke at p ± t (the file's a = 100 ± 1)
    da = s.of("slide.stroke")[0]
    assert da.low == pytest.approx(stroke(a - 1, b, e), rel=1e-12)
    assert da.high == pytest.approx(stroke(a + 1, b, e), rel=1e-12)
    assert da.elasticity == pytest.approx(truth[0] * a / stroke(a, b, e), rel=1e-7)
    assert s.variants == 1 + 6 * 3 and not s.failed


INLINE = """\
name: massless in-line slider-crank under a constant force
units: {length: mm, angle: deg, speed: rpm, force: N}
parameters: {a: 80, b: 300}
links:
  ground: {points: {O: [0, 0]}}
  crank: {points: {O: [0, 0], A: [a, 0]}}
  rod: {points: {A: [0, 0], B: [b, 0]}}
  slider: {points: {B: [0, 0]}}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, rod]}
  B: {type: revolute, links: [rod, slider]}
  slide: {type: prismatic, links: [ground, slider], axis: {point: O, direction: [1, 0]}, point: B}
drivers:
  motor: {joint: O, motion: {speed: 60}}
loads:
  push: {type: force, link: slider, point: B, value: [-500, 0]}
sketch: {A: [a, 0], B: [a + b, 0]}
analysis: {start: 0, sweep: 360, positions: 72}
"""


def torque(theta, a, b, force=500.0):
    """The driving torque (N·m) holding a force ``force`` along −x on the slider of a
    massless in-line slider-crank (virtual work: T = F·ds/dθ, s = a cos θ + √(b² − a² sin²θ),
    lengths in mm → m) and its derivative along ``a`` (by hand)."""
    sn, cs = np.sin(theta), np.cos(theta)
    root = np.sqrt(b**2 - a**2 * sn**2)
    ds = -a * sn - a**2 * sn * cs / root
    dds_da = -sn - (2 * a * sn * cs / root + a**3 * sn**3 * cs / root**3)
    return -force * ds / 1000.0, -force * dds_da / 1000.0


def test_the_peak_torques_sensitivity_is_the_closed_forms_at_its_row(tmp_path):
    path = tmp_path / "inline.yaml"
    path.write_text(INLINE, encoding="utf-8")
    opts = BatchOptions(executor="serial", friction=False)
    s = sensitivity(path, ["a=±0.5"], ["motor.torque_peak", "motor.torque_rms"], options=opts)
    theta = np.radians(np.arange(72) * 5.0)  # the rows: 0°, 5°, …, 355°
    t, dt_da = torque(theta, 80.0, 300.0)
    k = np.argmax(np.abs(t))
    assert s.nominal[0] == pytest.approx(abs(t[k]), rel=1e-9)  # the rows are the closed form's
    d = s.of("motor.torque_peak")[0]
    # the peak's derivative is that of its row's torque (its row does not change within ±2h)
    assert d.value == pytest.approx(np.sign(t[k]) * dt_da[k], rel=1e-7)
    assert abs(d.value - np.sign(t[k]) * dt_da[k]) <= 4 * d.error + 1e-12
    # RMS: d√(mean T²)/da = mean(T·∂T/∂a) / RMS
    rms = math.sqrt(np.mean(t**2))
    assert s.nominal[1] == pytest.approx(rms, rel=1e-9)
    assert s.of("motor.torque_rms")[0].value == pytest.approx(np.mean(t * dt_da) / rms, rel=1e-7)


@pytest.mark.parametrize(("dist", "sd_of"), [("normal", 1 / 3), ("uniform", 1 / math.sqrt(3))])
def test_the_monte_carlo_spread_is_the_linearised_one(dist, sd_of):
    """Small tolerances: the stroke is linear in them within the sample's error, so its
    sample variance S² over N designs has (N − 1)S²/σ² ~ χ²(N − 1) for a normal stroke
    (for the uniform one the sum of three uniforms: its variance's sampling error is
    smaller still), with σ² = Σ (∂s/∂p · σ_p)² of the closed form's gradient; the bound is
    the 0.05 % and 99.95 % points. The mean is the nominal stroke within 4σ/√N."""
    from scipy.stats import chi2

    a, b, e = 100.0, 350.0, -20.0
    tol = np.array([0.2, 0.5, 0.3])
    n = 300
    mc = monte_carlo(
        SLIDER,
        [f"a=±{tol[0]}", f"b=±{tol[1]}", f"e=±{tol[2]}"],
        ["slide.stroke"],
        samples=n,
        dist=dist,
        seed=7,
        options=replace(SERIAL, positions=12),  # the stroke is between exact stops
    )
    sigma = math.sqrt(np.sum((stroke_gradient(a, b, e) * tol * sd_of) ** 2))
    sp = mc.spreads[0]
    assert sp.n == n and mc.failed == 0
    ratio = (n - 1) * sp.sd**2 / sigma**2
    assert chi2.ppf(0.0005, n - 1) < ratio < chi2.ppf(0.9995, n - 1), (sp.sd, sigma)
    assert abs(sp.mean - stroke(a, b, e)) < 4 * sigma / math.sqrt(n)
    # each design's stroke is the closed form's at its drawn parameters
    want = [stroke(*p) for p in mc.parameters]
    np.testing.assert_allclose(mc.values[:, 0], want, rtol=1e-11)
    # the drawn designs: the seed's, and their spread that of the distribution asked for
    assert mc.parameters.shape == (n, 3)
    assert np.all(np.abs(mc.parameters - [a, b, e]) <= (tol if dist == "uniform" else 6 * tol))


def test_a_samples_row_is_the_single_analysis_of_its_design():
    quantities = ["slide.stroke", "motor.torque_peak", "A.reaction_peak", "slide.time_ratio"]
    mc = monte_carlo(SLIDER, ["a=±2", "e=±1"], quantities, samples=6, seed=3, options=SERIAL)
    template = Template.load(SLIDER)
    from kinetostatics.analysis.pipeline import analyze

    k = 4
    over = dict(zip(("a", "e"), mc.parameters[k]))
    row = summary_row(analyze(template.model(over, positions=36), friction=False), flywheel=False)
    for j, q in enumerate(quantities):
        assert mc.values[k, j] == pytest.approx(row[q], rel=1e-10), q


def long_crank(tmp_path):
    """The slider-crank with a = 300 (b = 350, e = −20), started at 90°: a design with
    a > 330 cannot assemble there (the rod cannot reach down a + 20 > b), which the batch
    finds at its start pose (cheaply: one past the dead centre costs ~1.5 s to locate)."""
    text = SLIDER.read_text(encoding="utf-8").replace("a: 100 ", "a: 300 ")
    path = tmp_path / "long_crank.yaml"
    path.write_text(text.replace("analysis: {start: 0,", "analysis: {start: 90,"), "utf-8")
    return path


def test_failed_designs_are_counted_with_their_reason_and_never_dropped(tmp_path):
    """An offset slider-crank's crank turns fully only where b ≥ a + |e|: with a = 300 ± 60,
    b = 350, e = −20 the designs with a > 330 fail (they do not assemble over the cycle),
    each counted with its reason."""
    path = long_crank(tmp_path)
    mc = monte_carlo(
        path,
        ["a=±60"],
        ["slide.stroke"],
        samples=16,
        dist="uniform",
        seed=0,
        limits=["slide.stroke <= 0.61"],
        options=SERIAL,
    )
    a = mc.parameters[:, 0]
    cannot = 350.0 < a + 20.0
    assert 0 < cannot.sum() < 16
    assert mc.failed == cannot.sum()
    assert [s != "ok" for s in mc.status] == list(cannot)
    assert sum(c for _, c in mc.reasons) == mc.failed
    assert all("cannot assemble" in r for r, _ in mc.reasons)
    assert np.all(np.isnan(mc.values[cannot, 0]))
    assert mc.spreads[0].n == 16 - mc.failed
    lim = mc.limits[0]
    ok_strokes = np.array([stroke(a, 350.0, -20.0) for a in a[~cannot]])
    assert 0 < lim.outside == np.count_nonzero(ok_strokes > 0.61)
    assert lim.analysed == 16 - mc.failed
    assert mc.share_lost == pytest.approx((lim.outside + mc.failed) / 16)


@pytest.mark.parametrize(
    ("vary", "of", "named"),
    [
        (["aa=±1"], None, "--vary aa=±1: the file has no parameter 'aa' (did you mean 'a'?)"),
        (["a=±0"], None, "--vary a=±0: the tolerance must be a positive number"),
        (["a=±x"], None, "--vary a=±x: the tolerance must be a positive number"),
        (["a"], None, "--vary 'a': expected NAME=±TOL"),
        (["a=±1", "a=±2"], None, "--vary a: named twice"),
        (["a=±1"], ["slide.strok"], "--of 'slide.strok': no quantity or parameter 'slide.strok'"),
    ],
)
def test_bad_input_is_one_line_naming_it(vary, of, named):
    with pytest.raises(SensitivityError) as info:
        sensitivity(SLIDER, vary, of, options=SERIAL)
    text = str(info.value)
    assert named in text and "\n" not in text


def test_a_tolerance_in_percent_is_of_the_value_and_refused_for_zero():
    (t,) = parse_tolerances(["b=±2%"], {"b": -350.0})
    assert t.half == pytest.approx(7.0) and t.relative
    assert t.sd("normal") == pytest.approx(7.0 / 3) and t.sd("uniform") == pytest.approx(
        7.0 / math.sqrt(3)
    )
    with pytest.raises(SensitivityError, match="is 0 in the file"):
        parse_tolerances(["e=±1%"], {"e": 0.0})


def test_a_kink_within_two_steps_is_flagged_and_a_smooth_quantity_is_not():
    """Q = max(p − 1.5h, 0) at p = 0: D(h) = 0 (its true slope at p), D(2h) = 1/8: the
    estimate |D(h) − D(2h)|/3 says the difference is not to be trusted, and the derivative
    is flagged; Q = 3p, exactly linear, is not."""
    from kinetostatics.batch.sensitivity import Tolerance, _derivative

    tol = Tolerance("x", 0.0, 1.0, False, "±1")
    h = tol.step
    at = {"-2h": -2 * h, "-h": -h, "+h": h, "+2h": 2 * h, "-t": -1.0, "+t": 1.0}
    kink = _derivative("q", tol, 0.0, {k: max(v - 1.5 * h, 0.0) for k, v in at.items()})
    assert kink.value == 0.0 and kink.error == pytest.approx(1 / 24, rel=1e-9)
    assert kink.flagged
    line = _derivative("q", tol, 0.0, {k: 3 * v for k, v in at.items()})
    assert line.value == pytest.approx(3.0, rel=1e-12) and not line.flagged
    assert (line.low, line.high, line.linear) == pytest.approx((-3.0, 3.0, 3.0))


def test_failed_reasons_alike_but_for_their_numbers_are_one_group():
    from kinetostatics.batch.tolerance import _reasons

    texts = [
        "RRP dyad {rod, slider} cannot assemble at motor = 70.15°: gap 0.01093 mm",
        "RRP dyad {rod, slider} cannot assemble at motor = 47.9794°: gap 2.3e-06 mm",
        "the sketch is 0.3 L_ref away",
        "RRP dyad {rod, slider} cannot assemble at motor = 60.2°: gap 6e-06 mm",
    ]
    assert _reasons(texts) == ((texts[0], 3), (texts[2], 1))


def test_a_tolerance_end_that_fails_is_reported_not_drawn_as_a_number(tmp_path):
    """a = 300 ± 40 of a crank that turns fully only up to a = 330: the design at p + t
    fails; the derivative (at ±h, ±2h) stands, the tornado's high end is empty, and the
    failed design is named with its reason."""
    path = long_crank(tmp_path)
    s = sensitivity(path, ["a=±40"], ["slide.stroke"], options=SERIAL)
    (d,) = s.of("slide.stroke")
    assert d.value == pytest.approx(stroke_gradient(300.0, 350.0, -20.0)[0], rel=1e-7)
    assert d.low == pytest.approx(stroke(260.0, 350.0, -20.0), rel=1e-12)
    assert math.isnan(d.high)
    assert [v for v, _ in s.failed] == ["a+t"]
    assert "cannot assemble" in s.failed[0][1]
