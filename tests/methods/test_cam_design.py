"""The cam's design (methods/cam_design.py) against closed forms written out here: the
harmonic law of a translating offset roller follower, its pressure angle
tan α = (s′ − e)/(s + √(r_p² − e²)), the least base radius substituted back, the pitch
curve's radius of curvature from its parametric form; an oscillating roller follower's
pressure angle through the relative instant centre of cam and arm (Kennedy), and its least
base radius by bisection; the shipped cam files."""

import json
import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.methods.cam_design import cam_design
from tests.helpers import ROOT

H, BETA = 0.020, math.radians(150)  # a harmonic rise of 20 mm over 150°, dwell 30°, …
RR, E = 0.010, 0.008  # roller, offset

TRANSLATING = """
name: harmonic translating roller
units: {{length: mm, angle: deg, speed: rpm, mass: kg, force: N}}
parameters: {{rb: {rb!r}, rr: 10, e: {e!r}, y0: sqrt((rb + rr)**2 - e**2)}}
gravity: [0, 0]
links:
  ground: {{points: {{O: [0, 0], G: [{sign}*e, 0]}}}}
  cam: {{points: {{O: [0, 0], K: [20, 0]}}}}
  follower: {{points: {{C: [0, 0]}}, com: [0, 0], mass: 0.3, inertia: 1e-4}}
joints:
  O: {{type: revolute, links: [ground, cam]}}
  guide: {{type: prismatic, links: [ground, follower], axis: {{point: G, direction: [0, 1]}},
          point: C}}
  contact:
    type: cam
    links: [cam, follower]
    centre: O
    point: C
    follower: roller
    radius: rr
    base_radius: rb
    rotation: {rotation}
    translating: {{direction: [0, 1], offset: e}}
    motion:
      - {{rise: 20, over: 150, law: harmonic}}
      - {{dwell: 30}}
      - {{return: 20, over: 150, law: harmonic}}
      - {{dwell: 30}}
drivers:
  motor: {{joint: O, points: [x, K], motion: {{speed: {speed}}}}}
loads:
  preload: {{type: force, link: follower, point: C, value: [0, -50]}}
sketch:
  follower.C: [{sign}*e, y0]
analysis: {{start: 0, sweep: 360, positions: {n}}}
"""


def _translating(rb=0.030, e=E, rotation="ccw", n=360):
    sign = 1 if rotation == "ccw" else -1
    text = TRANSLATING.format(
        rb=rb * 1e3, e=e * 1e3, rotation=rotation, sign=sign, n=n, speed=100 * sign
    )
    return ks.loads(text)


def _harmonic_law(theta):
    """s, s′, s″ of the harmonic rise, dwell, harmonic return, dwell."""
    t = np.mod(theta, 2 * np.pi)
    s, s1, s2 = (np.zeros_like(t) for _ in range(3))
    rise = t < BETA
    u = t[rise] / BETA
    s[rise] = H * (1 - np.cos(np.pi * u)) / 2
    s1[rise] = H * np.pi / (2 * BETA) * np.sin(np.pi * u)
    s2[rise] = H * np.pi**2 / (2 * BETA**2) * np.cos(np.pi * u)
    top = (t >= BETA) & (t < BETA + math.radians(30))
    s[top] = H
    back = (t >= BETA + math.radians(30)) & (t < 2 * BETA + math.radians(30))
    u = (t[back] - BETA - math.radians(30)) / BETA
    s[back] = H - H * (1 - np.cos(np.pi * u)) / 2
    s1[back] = -H * np.pi / (2 * BETA) * np.sin(np.pi * u)
    s2[back] = -H * np.pi**2 / (2 * BETA**2) * np.cos(np.pi * u)
    return s, s1, s2


def _alpha(theta, rb, e=E):
    s, s1, _ = _harmonic_law(theta)
    return np.arctan2(s1 - e, s + math.sqrt((rb + RR) ** 2 - e**2))


@pytest.fixture(scope="module")
def translating():
    (record,) = cam_design(_translating())
    return record


def test_the_law_is_the_harmonic_closed_form(translating):
    phi = np.radians(translating.angle)
    s, s1, s2 = _harmonic_law(phi)
    assert translating.lift_units == ("m", "m/rad", "m/rad^2")
    assert np.max(np.abs(translating.lift - s)) <= 1e-12 * H
    assert np.max(np.abs(translating.lift_d1 - s1)) <= 1e-12 * np.max(np.abs(s1))
    # s″ jumps at the ends of a harmonic segment: compare inside the segments
    inside = np.all(np.abs(translating.angle[:, None] - [0, 150, 180, 330, 360]) > 1e-9, axis=1)
    assert np.max(np.abs(translating.lift_d2 - s2)[inside]) <= 1e-12 * np.max(np.abs(s2))


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_pressure_angle_is_the_closed_form_and_the_pipelines_column(rotation):
    model = _translating(rotation=rotation)
    (record,) = cam_design(model)
    expected = np.degrees(_alpha(np.radians(record.angle), 0.030))
    assert np.max(np.abs(record.pressure_angle - expected)) <= 1e-9 * np.max(np.abs(expected))
    result = ks.analyze(model)
    (again,) = cam_design(result, samples=len(result["angle"]))
    column = result["contact.pressure_angle"]
    np.testing.assert_allclose(again.angle[:-1], result["contact.cam_angle"], atol=1e-9)
    assert np.max(np.abs(again.pressure_angle[:-1] - column)) <= 1e-9 * np.max(np.abs(column))


def test_the_largest_pressure_angle_and_where(translating):
    theta = np.linspace(0, 2 * np.pi, 400_001)
    dense = np.abs(np.degrees(_alpha(theta, 0.030)))
    k = np.argmax(dense)
    assert translating.peak >= dense[k] - 1e-12
    assert translating.peak - dense[k] <= 1e-6
    assert abs(translating.peak_at - math.degrees(theta[k])) <= 2e-3
    assert translating.satisfied == (translating.peak <= 30.0)


def test_the_least_base_radius_substituted_back_gives_the_allowed_angle(translating):
    """At r_b,min the largest |α| is [α] = 30°: from the record (refined) to 1e-9, never
    exceeded on a dense grid of the closed form, nor by the pipeline's column."""
    rb = translating.base_radius_min
    assert translating.method == "closed form"
    theta = np.linspace(0, 2 * np.pi, 400_001)
    dense = np.max(np.abs(np.degrees(_alpha(theta, rb))))
    assert dense <= 30.0 + 1e-9 and dense >= 30.0 - 1e-6
    (at_min,) = cam_design(_translating(rb=rb))
    assert abs(at_min.peak - 30.0) <= 1e-9 * 30.0
    (below,) = cam_design(_translating(rb=rb * (1 - 1e-6)))
    assert below.peak > 30.0 and not below.satisfied
    column = ks.analyze(_translating(rb=rb, n=720))["contact.pressure_angle"]
    assert np.max(np.abs(column)) <= 30.0 + 1e-9


def test_the_least_base_radius_against_the_textbook_formula(translating):
    """r_p,min = max √((|s′ − e|/tan[α] − s)² + e²), r_b,min = r_p,min − r_r (on a dense grid
    here, where the bracket is positive)."""
    theta = np.linspace(0, 2 * np.pi, 2_000_001)
    s, s1, _ = _harmonic_law(theta)
    d = np.abs(s1 - E) / math.tan(math.radians(30)) - s
    assert d.max() > 0
    rp = math.sqrt(d.max() ** 2 + E**2)
    assert abs(translating.base_radius_min - (rp - RR)) <= 1e-9 * rp


def _pitch_radius(theta, rb, e, sigma=1):
    """ρ = |P′|³/(P′ × P″) of the pitch curve P = exp(−iσθ) F(θ) written out."""
    s, s1, s2 = _harmonic_law(theta)
    F = e + 1j * (math.sqrt((rb + RR) ** 2 - e**2) + s)
    F1, F2 = 1j * s1, 1j * s2
    Q = np.exp(-1j * sigma * theta)
    P1 = Q * (F1 - 1j * sigma * F)
    P2 = Q * (F2 - 2j * sigma * F1 - F)
    cross = (np.conj(P1) * P2).imag  # P′ × P″
    # the profile is convex where the curve turns the way the pitch point goes round O:
    # the sign of P × P′ at θ = 0, one number (at a dwell P′ ⊥ P: its dot product, which
    # this once read, is round-off whose sign the CPU decides)
    turn = np.sign((np.conj(Q[0] * F[0]) * P1[0]).imag)
    assert turn != 0
    return turn * np.abs(P1) ** 3 / cross


def test_least_radius_of_curvature_and_roller_limit(translating):
    theta = np.linspace(0, 2 * np.pi, 400_001)
    rho = _pitch_radius(theta, 0.030, E)
    convex = rho[rho > 0]
    assert abs(translating.curvature_min - convex.min()) <= 1e-6 * convex.min()
    assert translating.roller_limit == translating.curvature_min
    assert translating.roller_radius == RR < translating.roller_limit


def test_pitch_curve_and_profile_points(translating):
    """The pitch curve is P(θ) = exp(−iθ) F(θ), F = e + i(√(r_p² − e²) + s) (the cam turning
    ccw), at θ = 0°, 1°, …; the working profile lies r_r inside it, along its normal."""
    theta = np.radians(np.arange(360.0))
    s, _, _ = _harmonic_law(theta)
    P = np.exp(-1j * theta) * (E + 1j * (math.sqrt((0.030 + RR) ** 2 - E**2) + s))
    pitch, profile = translating.pitch_curve, translating.profile
    assert pitch.shape == profile.shape == (360, 2)
    assert np.max(np.abs(pitch[:, 0] + 1j * pitch[:, 1] - P)) <= 1e-12
    np.testing.assert_allclose(np.hypot(*(pitch - profile).T), RR, rtol=1e-12)
    assert np.all(np.hypot(*profile.T) < np.hypot(*pitch.T))


def test_a_dwell_is_a_circle_arc_of_its_radius():
    """On a dwell the pitch curve is an arc about O: ρ = |F| = √((√(r_p² − e²) + s)² + e²),
    without offset r_b + r_r + s."""
    for e in (0.0, E):
        (cam,) = [j for j in _translating(e=e).joints if j.profile_design() is not None]
        chart = cam.profile_design()
        top = np.radians([151.0, 165.0, 179.0])
        low = np.radians([331.0, 345.0, 359.0])
        d0 = math.sqrt((0.030 + RR) ** 2 - e**2)
        np.testing.assert_allclose(chart.pitch_radius(top), math.hypot(d0 + H, e), rtol=1e-9)
        np.testing.assert_allclose(chart.pitch_radius(low), math.hypot(d0, e), rtol=1e-9)
        if e == 0.0:
            np.testing.assert_allclose(chart.pitch_radius(top), 0.030 + H + RR, rtol=1e-9)


OSCILLATING = """
name: oscillating roller
units: {{length: mm, angle: deg, speed: rpm, mass: kg, force: N}}
gravity: [0, 0]
links:
  ground: {{points: {{O: [0, 0], A: [{a}, 0]}}}}
  cam: {{points: {{O: [0, 0], K: [20, 0]}}}}
  arm: {{points: {{A: [0, 0], C: [{cx!r}, {cy!r}]}}, com: [0, 0], mass: 0.3, inertia: 1e-4}}
joints:
  O: {{type: revolute, links: [ground, cam]}}
  A: {{type: revolute, links: [ground, arm]}}
  contact:
    type: cam
    links: [cam, arm]
    centre: O
    point: C
    follower: roller
    radius: 8
    base_radius: {rb!r}
    rotation: ccw
    oscillating: {{pivot: [{a}, 0], arm: {arm}, rise: cw}}
    motion:
      - {{rise: 20, over: 120, law: cycloidal}}
      - {{dwell: 60}}
      - {{return: 20, over: 120, law: harmonic}}
      - {{dwell: 60}}
drivers:
  motor: {{joint: O, points: [x, K], motion: {{speed: 100}}}}
loads:
  hold: {{type: force, link: arm, point: C, value: [0, -40]}}
sketch:
  arm.C: [{px!r}, {py!r}]
analysis: {{start: 0, sweep: 360, positions: 360}}
"""
A_, L_ = 0.100, 0.080


def _beta0(rb, kappa=-1):
    """The arm's angle at the prime circle, on the side where the rise moves it outwards."""
    c = ((rb + 0.008) ** 2 - A_**2 - L_**2) / (2 * L_ * A_)
    for b in (math.acos(c), -math.acos(c)):
        if kappa * (-math.sin(b) * A_) > 0:
            return b
    raise AssertionError


def _oscillating(rb=0.040):
    b = _beta0(rb)
    cx, cy = L_ * math.cos(b), L_ * math.sin(b)
    text = OSCILLATING.format(
        a=A_ * 1e3, arm=L_ * 1e3, rb=rb * 1e3, cx=cx * 1e3, cy=cy * 1e3,
        px=(A_ + cx) * 1e3, py=cy * 1e3,
    )  # fmt: skip
    return ks.loads(text)


def test_oscillating_pressure_angle_through_the_instant_centre():
    """The contact normal passes through the relative instant centre I of cam (ω₁ = 1 about
    O) and arm (ω₂ = dβ/dθ about A) on the line OA: I = ω₂ A / (ω₂ − ω₁); |α| is the angle
    between the line from the roller centre C to I and C's velocity, ⟂ AC."""
    model = _oscillating()
    (record,) = cam_design(model)
    assert record.motion == "oscillating" and record.lift_units == ("rad", "1", "1/rad")
    result = ks.analyze(model)
    C = result["arm.C.x"] + 1j * result["arm.C.y"]
    w2 = result["arm.omega"] / (100 * 2 * math.pi / 60)
    centre = w2 * A_ / (w2 - 1)
    m = 1j * (C - A_)
    k = C - centre
    expected = np.degrees(np.arctan(np.abs((np.conj(m) * k).imag) / np.abs((np.conj(m) * k).real)))
    (again,) = cam_design(result, samples=len(result["angle"]))
    got = np.abs(again.pressure_angle[:-1])
    assert np.max(np.abs(got - expected)) <= 1e-7 * np.max(expected)
    column = result["contact.pressure_angle"]
    np.testing.assert_allclose(again.angle[:-1], result["contact.cam_angle"], atol=1e-9)
    assert np.max(np.abs(again.pressure_angle[:-1] - column)) <= 1e-9 * np.max(np.abs(column))


def test_oscillating_least_base_radius_by_bisection():
    (record,) = cam_design(_oscillating(), pressure_angle_max=35.0)
    rb = record.base_radius_min
    assert record.method == "bisection" and 0 < rb
    (at_min,) = cam_design(_oscillating(rb=rb), pressure_angle_max=35.0)
    assert abs(at_min.peak - 35.0) <= 1e-9 * 35.0
    (below,) = cam_design(_oscillating(rb=rb * (1 - 1e-6)), pressure_angle_max=35.0)
    assert below.peak > 35.0


@pytest.mark.parametrize("name", ["cam_roller", "cam_flat_oscillating"])
def test_shipped_cam_files_give_records(name):
    """JSON-safe records whose pressure angle is the pipeline's column at its rows (the
    flat face's too: its convention is the column's)."""
    result = ks.analyze(ks.load(ROOT / "mechanisms" / f"{name}.yaml"))
    (record,) = cam_design(result, samples=len(result["angle"]))
    data = json.loads(json.dumps(record.to_dict(), allow_nan=False))
    assert data["joint"] == "contact" and len(data["angle"]) == len(result["angle"]) + 1
    assert data["curvature_min"] > 0 and data["satisfied"] is True
    column = result["contact.pressure_angle"]
    assert np.max(np.abs(record.pressure_angle[:-1] - column)) <= 1e-9 * np.max(np.abs(column))
    assert record.peak >= np.max(np.abs(column)) - 1e-12


def test_a_file_without_a_cam_has_no_record_and_bad_arguments_are_refused():
    model = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    assert cam_design(model) == ()
    with pytest.raises(ValueError, match="pressure_angle_max = 90.0: .* below 90"):
        cam_design(model, pressure_angle_max=90.0)
    with pytest.raises(ValueError, match="samples = 0"):
        cam_design(model, samples=0)
    with pytest.raises(ValueError, match="samples = 1.5: expected a whole number"):
        cam_design(model, samples=1.5)


FLAT = """
name: translating flat face
units: {length: mm, angle: deg, speed: rpm, mass: kg, force: N}
gravity: [0, 0]
links:
  ground: {points: {O: [0, 0], G: [0, 0]}}
  cam: {points: {O: [0, 0], K: [20, 0]}}
  follower: {points: {C: [0, 0]}, com: [0, 0], mass: 0.3, inertia: 1e-4}
joints:
  O: {type: revolute, links: [ground, cam]}
  guide: {type: prismatic, links: [ground, follower], axis: {point: G, direction: [0, 1]},
          point: C}
  contact:
    type: cam
    links: [cam, follower]
    centre: O
    point: C
    follower: flat
    face_normal: [0, -1]
    base_radius: 30
    translating: {direction: [0, 1]}
    motion:
      - {rise: 20, over: 150, law: harmonic}
      - {dwell: 30}
      - {return: 20, over: 150, law: harmonic}
      - {dwell: 30}
drivers:
  motor: {joint: O, points: [x, K], motion: {speed: 100}}
sketch:
  follower.C: [0, 30]
"""


def test_translating_flat_face_has_no_pressure_angle_and_its_textbook_curvature():
    """α ≡ 0 (the face's normal is the guide's direction), so [α] bounds no base radius; the
    profile's radius of curvature is r_b + s + s″: r_b on the low dwell, r_b + h − hπ²/(2β²)
    where the harmonic return starts."""
    model = ks.loads(FLAT)
    (record,) = cam_design(model)
    assert record.follower == "flat" and record.roller_limit is None
    assert np.max(np.abs(record.pressure_angle)) <= 1e-12 and record.peak <= 1e-12
    assert record.base_radius_min is None and record.method.startswith("none")
    theta = np.linspace(0, 2 * np.pi, 100_001)
    s, _, s2 = _harmonic_law(theta)
    assert abs(record.curvature_min - np.min(0.030 + s + s2)) <= 1e-9 * 0.030
    (chart,) = [j.profile_design() for j in model.joints if j.profile_design() is not None]
    rho = chart.pitch_radius(np.radians([180.0, 90.0]))
    np.testing.assert_allclose(rho[0], 0.030 + H - H * math.pi**2 / (2 * BETA**2), rtol=1e-9)
    u = 90 / 150
    s, s2 = (
        H * (1 - math.cos(math.pi * u)) / 2,
        H * math.pi**2 / (2 * BETA**2) * math.cos(math.pi * u),
    )
    np.testing.assert_allclose(rho[1], 0.030 + s + s2, rtol=1e-9)


def test_a_largest_value_next_to_the_turns_end_is_found():
    """0° and 360° are one cam angle: a peak just before 360° is refined on that side even
    when the sample at 0° is the largest (the same value)."""
    from kinetostatics.methods.cam_design import _peak

    grid = np.linspace(0, 2 * np.pi, 7)
    value, at = _peak(lambda th: np.cos(th + 1e-4), grid)
    assert abs(value - 1.0) <= 1e-15 and abs(at - (2 * np.pi - 1e-4)) <= 1e-7
