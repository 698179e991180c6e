"""The cam pair (joints/cam.py) against closed forms: the follower follows its law,
the pressure angle of an offset translating roller follower, the power balance,
Coulomb friction at the contact, and the speed at which a preloaded follower leaves
the cam.  Expected values come from the laws' formulas written out here."""

import math
import re
import warnings

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.errors import JointWarning, ModelError
from kinetostatics.outputs import plotting
from tests.helpers import ROOT

W300 = 300 * 2 * math.pi / 60


def _cycloidal(u, h, b):
    return (
        h * (u - np.sin(2 * np.pi * u) / (2 * np.pi)),
        h / b * (1 - np.cos(2 * np.pi * u)),
        h / b**2 * 2 * np.pi * np.sin(2 * np.pi * u),
    )


def _harmonic(u, h, b):
    return (
        h * (1 - np.cos(np.pi * u)) / 2,
        h * np.pi / 2 * np.sin(np.pi * u) / b,
        h * np.pi**2 / 2 * np.cos(np.pi * u) / b**2,
    )


def _poly345(u, h, b):
    return (
        h * (10 * u**3 - 15 * u**4 + 6 * u**5),
        h * (30 * u**2 - 60 * u**3 + 30 * u**4) / b,
        h * (60 * u - 180 * u**2 + 120 * u**3) / b**2,
    )


def _law(theta, parts):
    """s, s', s'' of a list of (start°, span°, curve or None, lift, sign)."""
    t = np.mod(theta, 2 * np.pi)
    out = [np.zeros_like(t) for _ in range(3)]
    base = 0.0
    for start, span, curve, h, sign in parts:
        a, b = np.radians(start), np.radians(span)
        m = (t >= a) & (t < a + b)
        if curve is None:
            out[0][m] = base
            continue
        y = curve((t[m] - a) / b, h, b)
        out[0][m] = base + sign * y[0]
        out[1][m], out[2][m] = sign * y[1], sign * y[2]
        base += sign * h
    return out


ROLLER = [(0, 120, _cycloidal, 0.02, 1), (120, 60, None, 0, 0), (180, 120, _poly345, 0.02, -1)]
ROLLER += [(300, 60, None, 0, 0)]


@pytest.fixture(scope="module")
def roller():
    return ks.analyze(ks.load(ROOT / "mechanisms" / "cam_roller.yaml"))


def test_translating_follower_follows_its_law(roller):
    th = np.radians(roller["angle"])
    s, s1, s2 = _law(th, ROLLER)
    y0 = math.sqrt(0.052**2 - 0.01**2)
    assert np.max(np.abs(roller["follower.C.y"] - y0 - s)) <= 1e-9 * 0.02
    assert np.max(np.abs(roller["follower.C.vy"] - W300 * s1)) <= 1e-9 * np.max(W300 * s1)
    assert np.max(np.abs(roller["follower.C.ay"] - W300**2 * s2)) <= 1e-9 * np.max(W300**2 * s2)
    np.testing.assert_allclose(roller["contact.lift"], s, atol=1e-15)
    np.testing.assert_allclose(roller["contact.cam_angle"], roller["angle"], atol=1e-9)


def test_pressure_angle_of_the_offset_roller_follower(roller):
    """tan α = (s' − e)/(s + √(r_p² − e²)), the cam turning ccw, the offset e on the side
    where its surface moves along the rise."""
    s, s1, _ = _law(np.radians(roller["angle"]), ROLLER)
    e, rp = 0.010, 0.052
    alpha = np.degrees(np.arctan2(s1 - e, s + math.sqrt(rp**2 - e**2)))
    assert np.max(np.abs(roller["contact.pressure_angle"] - alpha)) <= 1e-9 * np.max(np.abs(alpha))


def test_contact_force_passes_the_power_balance(roller):
    assert roller.checks.power.value <= 1e-9
    assert roller.checks.power_friction.value <= 1e-9
    flat = ks.analyze(ks.load(ROOT / "mechanisms" / "cam_flat_oscillating.yaml"))
    assert flat.checks.power.value <= 1e-9 and flat.checks.power_friction.value <= 1e-9


@pytest.mark.parametrize("name,f", [("cam_roller", 0.01), ("cam_flat_oscillating", 0.08)])
def test_coulomb_friction_is_tangential_and_f_times_the_normal_force(name, f):
    r = ks.analyze(ks.load(ROOT / "mechanisms" / f"{name}.yaml"))
    e, n = r["contact.friction"], r["contact.F_friction"]
    total = np.hypot(r["contact.Fx_friction"], r["contact.Fy_friction"])
    np.testing.assert_allclose(np.abs(e), f * np.abs(n), rtol=1e-12)
    # the friction force is along the tangent: |F_total|² = N² + e²
    np.testing.assert_allclose(total, np.hypot(n, e), rtol=1e-9)
    assert np.all(r["contact.F_friction"] > 0) and np.all(r["contact.status"] == 0)


def test_oscillating_flat_follower_follows_its_law():
    r = ks.analyze(ks.load(ROOT / "mechanisms" / "cam_flat_oscillating.yaml"))
    h = math.radians(15)
    parts = [(0, 120, _cycloidal, h, 1), (120, 40, None, 0, 0), (160, 120, _harmonic, h, -1)]
    s, s1, s2 = _law(np.radians(r["angle"]), parts + [(280, 80, None, 0, 0)])
    w = 200 * 2 * math.pi / 60
    assert np.max(np.abs(-np.radians(r["arm.theta"]) - s)) <= 1e-9 * h  # rise: cw
    assert np.max(np.abs(-r["arm.omega"] - w * s1)) <= 1e-9 * np.max(w * s1)
    assert np.max(np.abs(-r["arm.alpha"] - w * w * s2)) <= 1e-9 * np.max(w * w * s2)
    # the face runs f = 10 mm from the pivot A: the contact point X moves along
    # perp(X − A), at α from the face normal with tan |α| = f / √(|X − A|² − f²)
    for row in (0, 50, 100, 200):
        geo = plotting.mechanism_geometry(r, row)
        xa = np.hypot(*(geo.joints["contact"] - geo.points["ground.A"]))
        alpha = math.degrees(math.atan2(0.010, math.sqrt(xa**2 - 0.010**2)))
        assert abs(abs(r["contact.pressure_angle"][row]) - alpha) <= 1e-9 * alpha


SEPARATION = """
name: separation
units: {{length: mm, angle: deg, speed: rpm, mass: kg, force: N}}
gravity: [0, 0]
links:
  ground: {{points: {{O: [0, 0], G: [0, 0]}}}}
  cam: {{points: {{O: [0, 0], K: [20, 0]}}}}
  follower: {{points: {{C: [0, 0]}}, com: [0, 0], mass: {m}, inertia: 1e-4}}
joints:
  O: {{type: revolute, links: [ground, cam]}}
  guide: {{type: prismatic, links: [ground, follower], axis: {{point: G, direction: [0, 1]}},
          point: C}}
  contact:
    type: cam
    links: [cam, follower]
    centre: O
    point: C
    follower: {follower}
    {radius}
    base_radius: 40
    translating: {{direction: [0, 1]}}
    motion:
      - {{rise: {h}, over: 120, law: harmonic}}
      - {{dwell: 60}}
      - {{return: {h}, over: 120, law: harmonic}}
      - {{dwell: 60}}
drivers:
  motor: {{joint: O, points: [x, K], motion: {{speed: {rpm!r}}}}}
loads:
  preload: {{type: force, link: follower, point: C, value: [0, {f0}]}}
sketch:
  follower.C: [0, {y0}]
analysis: {{start: 0, sweep: 360, positions: 360}}
"""


def _separation(rpm, follower="roller"):
    m, h, f0 = 0.5, 20.0, 40.0
    radius = "radius: 10" if follower == "roller" else ""
    y0 = 50 if follower == "roller" else 40
    text = SEPARATION.format(
        m=m, h=h, f0=-f0, rpm=float(rpm), follower=follower, radius=radius, y0=y0
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ks.analyze(ks.loads(text))
    return r, [w for w in caught if issubclass(w.category, JointWarning)]


def test_separation_speed_against_its_closed_form():
    """Follower of mass m, preload F0, frictionless, no gravity: m s̈ = F cos α − F0 with
    s̈ = ω² s''(θ), so the contact force F = (m ω² s'' + F0)/cos α turns negative first
    where s'' is most negative.  A harmonic return of h over β starts with
    s'' = −h π²/(2β²) (the rise ends with the same value, approached but not reached),
    so ω_sep = (β/π) √(2 F0 / (m h))."""
    m, h, f0, b = 0.5, 0.020, 40.0, math.radians(120)
    w_sep = b / math.pi * math.sqrt(2 * f0 / (m * h))
    rpm = w_sep * 60 / (2 * math.pi)
    slow, caught = _separation(0.9999 * rpm)
    assert not caught and np.all(slow["contact.status"] == 0)
    # the force along the guide is m ω² s'' + F0 at every row (F cos α)
    w = 0.9999 * w_sep
    s2 = _law(
        np.radians(slow["angle"]),
        [
            (0, 120, _harmonic, h, 1),
            (120, 60, None, 0, 0),
            (180, 120, _harmonic, h, -1),
            (300, 60, None, 0, 0),
        ],
    )[2]
    np.testing.assert_allclose(slow["contact.Fy"], m * w**2 * s2 + f0, rtol=0, atol=1e-9 * f0)
    fast, caught = _separation(1.0001 * rpm)
    rows = np.nonzero(fast["contact.status"])[0]
    assert list(np.round(fast["angle"][rows], 9)) == [180.0]
    assert len(caught) == 1 and "cam angles 180°" in str(caught[0].message)
    # the root in ω² of the force at 180° from the two runs is the closed form
    a0, a1 = slow["contact.F"][180], fast["contact.F"][180]
    w0, w1 = (0.9999 * w_sep) ** 2, (1.0001 * w_sep) ** 2
    root = w0 - a0 * (w1 - w0) / (a1 - a0)
    assert abs(math.sqrt(root) - w_sep) <= 1e-9 * w_sep


def test_knife_edge_and_table_law():
    """A table of lifts is interpolated: at its points the follower is exactly there."""
    ang = np.arange(0, 360, 10.0)
    lift = 10 * (1 - np.cos(np.radians(ang)))
    text = _separation(100, "knife")[0]  # a knife edge runs too
    assert text.checks.power.value <= 1e-9
    src = SEPARATION.format(m=0.5, h=20, f0=-40, rpm=100.0, follower="knife", radius="", y0=40)
    table = f"motion: {{angle: {[float(a) for a in ang]}, lift: {[float(x) for x in lift]}}}"
    src = re.sub(r"motion:\n(      - .*\n)+", table + "\n", src)
    r = ks.analyze(ks.loads(src))
    at = np.isin(np.round(r["angle"], 9), ang)
    expected = 0.010 * (1 - np.cos(np.radians(ang)))
    assert at.sum() == 36
    np.testing.assert_allclose(r["follower.C.y"][at] - 0.040, expected, atol=1e-15)


def test_undercut_and_bad_keys_are_model_errors():
    src = SEPARATION.format(
        m=0.5, h=20, f0=-40, rpm=100.0, follower="roller", radius="radius: 60", y0=100
    )
    src = src.replace("base_radius: 40", "base_radius: 8").replace("over: 120", "over: 40")
    src = src.replace("dwell: 60", "dwell: 140")
    with pytest.raises(ModelError, match=r"undercut at cam angle [0-9.]+°"):
        ks.loads(src)
    bad = SEPARATION.format(m=0.5, h=20, f0=-40, rpm=100.0, follower="rolller", radius="", y0=40)
    with pytest.raises(ModelError, match="follower must be knife, roller or flat, got 'rolller'"):
        ks.loads(bad)


def test_the_profile_is_made_when_the_cam_is_built_and_only_the_last_poses_are_kept():
    """What the profile derives from the cam's fields alone (the sense its pitch point
    turns, the inversion tables, the outline drawn) is a field set when the synthesis is
    built; the one thing kept later, Φ at the last poses, stays out of the pickle.  The
    roller centre at cam angle 0, where the rise starts (lift 0), is on the prime circle:
    |F| = √(e² + (√(r_p² − e²))²) = r_p = base + roller."""
    import dataclasses
    import pickle

    model = ks.load(ROOT / "mechanisms" / "cam_roller.yaml")
    cam = next(j for j in model.joints if j.kind == "cam")
    s = cam.synthesis
    assert {"turn", "inversion", "outline"} <= set(vars(s))
    assert s.turn in (1.0, -1.0) and not isinstance(s.inversion, str)
    profile, pitch = s.outline  # a roller: the profile and the pitch curve
    assert math.hypot(*pitch[0]) == pytest.approx(s.base + s.radius, rel=1e-12)
    assert np.all(np.hypot(*profile.T) < np.hypot(*pitch.T))  # the profile inside, by r
    q = np.zeros(3)
    cam.residual(q, np.array([0.0, s.base + s.radius + 0.01, 0.0]))
    assert cam._memo and pickle.loads(pickle.dumps(cam))._memo == {}
    # a batch stacks variants whose cam differs: built, its profile left to each variant
    stacked = dataclasses.replace(s, base=np.array([[s.base], [1.1 * s.base]]))
    assert stacked.inversion is None and stacked.outline is None
