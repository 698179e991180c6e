"""The gear chapter (methods/gears.py) against textbook values and independent formulas.

Expected values come from the textbook (m = 5, z = 20, α = 20°: r = 50 mm, r_b = 46.985 mm,
r_a = 55 mm, r_f = 43.75 mm, p = 15.708 mm, p_b = 14.761 mm, s = 7.854 mm; z_min = 17 at
20° and 32 at 14.5°; the greatest contact ratio of standard 20° teeth, 4h_a*/(π sin 2α) =
1.981, reached as both gears grow) or from formulas the module does not use: the contact
ratio as the length of the path of contact over the base pitch, the working pressure angle
by a bracketing root finder.  Lengths are compared on the scale of a micrometre.
"""

from __future__ import annotations

import json
import math

import pytest
from scipy.optimize import brentq

import kinetostatics as ks
from kinetostatics.io import dump
from kinetostatics.joints.gearing import GearData
from kinetostatics.methods.gears import gear_geometry, involute, pair_geometry
from tests.helpers import variant

MM = 1e-3
UM = 1e-6  # the tolerance of a length, m
ALPHA = math.radians(20.0)


def _pair(z1, z2, m=5.0, mesh="external", shift=(0.0, 0.0), alpha=ALPHA, addendum=1.0):
    radii = (0.5 * m * z1 * MM, 0.5 * m * z2 * MM)
    return GearData("mesh", mesh, ("one", "two"), (z1, z2), radii, alpha, addendum, 0.25, shift)


def _rack(z, m=5.0, shift=0.0, alpha=ALPHA):
    data = (None, z), (None, 0.5 * m * z * MM), alpha, 1.0, 0.25, (0.0, shift)
    return GearData("mesh", "rack", ("rack", "pinion"), *data)


def _path_of_contact(g) -> float:
    """ε_α as the length of the path of contact over the base pitch (external or internal)."""
    w1, w2 = g.wheels
    far = [math.sqrt(w.r_a**2 - w.r_b**2) for w in (w1, w2)]
    sin_a = math.sin(g.working_alpha)
    if w2.annulus:
        length = far[0] - far[1] + g.working_centre_distance * sin_a
    else:
        length = far[0] + far[1] - g.working_centre_distance * sin_a
    return length / g.base_pitch


def test_the_textbook_gear_m5_z20():
    g = pair_geometry(_pair(20, 40))
    w = g.wheels[0]
    assert g.module == pytest.approx(5 * MM, abs=1e-12)
    assert w.r == pytest.approx(50.0 * MM, abs=UM)
    assert w.r_b == pytest.approx(46.985 * MM, abs=UM)
    assert w.r_a == pytest.approx(55.0 * MM, abs=UM)
    assert w.r_f == pytest.approx(43.75 * MM, abs=UM)
    assert g.pitch == pytest.approx(15.708 * MM, abs=UM)
    assert g.base_pitch == pytest.approx(14.761 * MM, abs=UM)
    assert w.s == pytest.approx(7.854 * MM, abs=UM)
    assert not w.undercut


def test_the_formulas_print_each_value():
    formulas = dict(pair_geometry(_pair(20, 40)).formulas)
    assert formulas["r_b1"] == "r_b1 = r_1 cos α = 46.985 mm"
    assert formulas["r_a1"] == "r_a1 = r_1 + (h_a* + x_1)m = 55 mm"
    assert formulas["r_f1"] == "r_f1 = r_1 − (h_a* + c* − x_1)m = 43.75 mm"
    assert formulas["a"] == "a = m(z_1 + z_2)/2 = 150 mm"
    assert formulas["z_min"].endswith("≈ 17")
    # in the file's unit: metres
    assert dict(pair_geometry(_pair(20, 40), "m").formulas)["r_1"].endswith("= 0.05 m")


def test_the_pair_20_40_centre_distance_and_contact_ratio():
    g = pair_geometry(_pair(20, 40))
    assert g.centre_distance == pytest.approx(150.0 * MM, abs=UM)
    assert g.centre_distance_file == pytest.approx(150.0 * MM, abs=UM)
    assert g.working_alpha == pytest.approx(ALPHA, abs=1e-15)
    # the formula of the brief, written out here
    tan = math.tan
    aa1, aa2 = math.acos(50 * math.cos(ALPHA) / 55), math.acos(100 * math.cos(ALPHA) / 105)
    by_angles = (20 * (tan(aa1) - tan(ALPHA)) + 40 * (tan(aa2) - tan(ALPHA))) / (2 * math.pi)
    assert g.contact_ratio == pytest.approx(by_angles, abs=1e-12)
    assert g.contact_ratio == pytest.approx(_path_of_contact(g), abs=1e-12)
    assert g.contact_ratio == pytest.approx(1.64, abs=0.005)


def test_the_greatest_contact_ratio_of_standard_teeth_is_1_981():
    """Textbook: as z_1, z_2 → ∞, ε_α → 4h_a*/(π sin 2α) = 1.981 at 20°; a rack and a
    pinion with many teeth reach the same limit, and a rack is the limit of a gear."""
    limit = 4.0 / (math.pi * math.sin(2 * ALPHA))
    assert limit == pytest.approx(1.981, abs=5e-4)
    assert pair_geometry(_pair(10**6, 10**6)).contact_ratio == pytest.approx(limit, abs=1e-4)
    assert pair_geometry(_rack(10**6)).contact_ratio == pytest.approx(limit, abs=1e-4)
    rack = pair_geometry(_rack(20)).contact_ratio
    assert pair_geometry(_pair(20, 10**6)).contact_ratio == pytest.approx(rack, abs=1e-4)
    # and the rack term by itself: the rack's addendum line over sin α, over the base pitch
    w = pair_geometry(_rack(20)).wheels[0]
    rack_side = 1.0 * 5 * MM / math.sin(ALPHA)
    pinion_side = math.sqrt(w.r_a**2 - w.r_b**2) - w.r * math.sin(ALPHA)
    assert rack == pytest.approx((rack_side + pinion_side) / (math.pi * 5 * MM * math.cos(ALPHA)))


def test_undercut_limit_and_least_shift():
    g = pair_geometry(_pair(12, 40))
    assert g.z_min == 17
    assert g.z_min_exact == pytest.approx(2 / math.sin(ALPHA) ** 2, rel=1e-12)
    assert g.wheels[0].x_min == pytest.approx(5 / 17, abs=1e-12)
    assert g.wheels[0].undercut and not g.wheels[1].undercut
    notes = [t.format(**dict(v)) for t, v in g.notes]
    assert any("undercut" in n and "0.29412" in n for n in notes)
    shifted = pair_geometry(_pair(12, 40, shift=(0.3, -0.3)))
    assert not shifted.wheels[0].undercut
    # 14.5°: the textbook's 32 teeth
    assert pair_geometry(_pair(20, 40, alpha=math.radians(14.5))).z_min == 32


def test_a_shifted_pair_works_at_the_angle_of_the_involute_equation():
    z1, z2, x1, x2, m = 12, 30, 0.5, 0.2, 4.0
    g = pair_geometry(_pair(z1, z2, m=m, shift=(x1, x2)))
    target = math.tan(ALPHA) - ALPHA + 2 * math.tan(ALPHA) * (x1 + x2) / (z1 + z2)
    alpha_w = brentq(lambda a: math.tan(a) - a - target, 0.1, 1.2, xtol=1e-15)
    assert g.working_alpha == pytest.approx(alpha_w, abs=1e-12)
    a = m * (z1 + z2) / 2 * MM
    a_w = a * math.cos(ALPHA) / math.cos(alpha_w)
    assert g.centre_distance == pytest.approx(a, abs=UM)
    assert g.working_centre_distance == pytest.approx(a_w, abs=UM)
    assert g.working_centre_distance > g.centre_distance
    dy = x1 + x2 - (a_w - a) / (m * MM)
    assert g.tip_reduction == pytest.approx(dy, abs=1e-12)
    w1, w2 = g.wheels
    assert w1.r_a == pytest.approx((24 + (1 + x1 - dy) * 4) * MM, abs=UM)
    assert w1.r_f == pytest.approx((24 - (1.25 - x1) * 4) * MM, abs=UM)
    assert w1.s == pytest.approx((2 * math.pi + 2 * x1 * 4 * math.tan(ALPHA)) * MM, abs=UM)
    # the tip clearance is standard: a' = r_a1 + c* m + r_f2
    assert w1.r_a + 0.25 * m * MM + w2.r_f == pytest.approx(a_w, abs=UM)
    assert g.contact_ratio == pytest.approx(_path_of_contact(g), abs=1e-12)
    assert "α' =" in dict(g.formulas)["alpha_w"]
    # a height-modified pair (x_1 + x_2 = 0) keeps α and a
    h = pair_geometry(_pair(z1, z2, m=m, shift=(0.4, -0.4)))
    assert (h.working_alpha, h.working_centre_distance) == (ALPHA, h.centre_distance)


def test_an_internal_pair():
    g = pair_geometry(_pair(20, 60, mesh="internal"))
    pinion, annulus = g.wheels
    assert annulus.annulus and not pinion.annulus
    assert g.centre_distance == pytest.approx(100 * MM, abs=UM)
    assert annulus.r_a == pytest.approx(145 * MM, abs=UM)
    assert annulus.r_f == pytest.approx(156.25 * MM, abs=UM)
    assert annulus.x_min is None and annulus.undercut is None
    assert g.contact_ratio == pytest.approx(_path_of_contact(g), abs=1e-12)
    assert "z_2(tan α_a2 − tan α)" in dict(g.formulas)["epsilon"]
    assert " − " in dict(g.formulas)["epsilon"]


def test_a_rack_pair_with_a_shifted_pinion():
    g = pair_geometry(_rack(12, m=4.0, shift=0.4))
    (w,) = g.wheels
    assert g.centre_distance == pytest.approx((24 + 1.6) * MM, abs=UM)
    assert g.working_alpha == ALPHA
    assert w.r_a == pytest.approx((24 + 1.4 * 4) * MM, abs=UM)
    rack_side = (1.0 - 0.4) * 4 * MM / math.sin(ALPHA)
    pinion_side = math.sqrt(w.r_a**2 - w.r_b**2) - w.r * math.sin(ALPHA)
    pb = math.pi * 4 * MM * math.cos(ALPHA)
    assert g.contact_ratio == pytest.approx((rack_side + pinion_side) / pb, abs=1e-12)
    assert not w.undercut  # 0.4 ≥ 5/17


def test_involute():
    assert involute(ALPHA) == pytest.approx(0.014904, abs=1e-6)  # the table's inv 20°


@pytest.mark.parametrize(
    "name", ["geared_fivebar", "rack_rocker", "jaw_crusher", "ammunition_swing"]
)
def test_the_shipped_geared_files_give_records(name):
    gears = gear_geometry(ks.load(f"mechanisms/{name}.yaml"))
    assert len(gears.pairs) == 1 and not gears.incomplete
    record = json.loads(json.dumps(gears.to_dict()))
    pair = record["pairs"]["mesh"]
    assert pair["contact_ratio"] > 1.2
    assert pair["formulas"]["p_b"].startswith("p_b = p cos α = ")


def test_the_jaw_crushers_pinion_is_the_textbook_gear():
    (g,) = gear_geometry(ks.load("mechanisms/jaw_crusher.yaml")).pairs
    pinion = g.wheels[0]
    assert pinion.teeth == 20
    assert pinion.r_b == pytest.approx(46.985 * MM, abs=UM)
    assert pinion.r_f == pytest.approx(43.75 * MM, abs=UM)
    assert dict(g.formulas)["r_b1"] == "r_b1 = r_1 cos α = 46.985 mm"


def test_a_result_gives_its_models_gears():
    model = ks.load("mechanisms/geared_fivebar.yaml")
    result = ks.analyze(model, kinematics_only=True)
    assert gear_geometry(result) == gear_geometry(model)


def test_a_file_without_gears_has_none():
    assert gear_geometry(ks.load("mechanisms/slider_crank.yaml")).to_dict() == {
        "pairs": {},
        "incomplete": {},
    }


def test_a_pinion_without_teeth_is_incomplete():
    model = variant(
        "rack_rocker", module=(r"module: m\n", "radius: r\n"), teeth=(r"    teeth: z\n", "")
    )
    gears = gear_geometry(model)
    assert not gears.pairs and "teeth" in dict(gears.incomplete)["mesh"]


def test_the_tooth_form_keys():
    model = variant(
        "geared_fivebar",
        keys=(r"    mesh: external\n", "    mesh: external\n    addendum: 0.8\n    clearance: 0.3\n"
                                       "    shift: [0.5, -0.5]\n"),
    )  # fmt: skip
    data = next(j.gear_data() for j in model.joints if j.name == "mesh")
    assert (data.addendum, data.clearance, data.shift) == (0.8, 0.3, (0.5, -0.5))
    again = ks.loads(dump(model), file="again.yaml")
    assert next(j.gear_data() for j in again.joints if j.name == "mesh") == data
    g = pair_geometry(data)
    assert g.wheels[0].r_a == pytest.approx((75 + 1.3 * 5) * MM, abs=UM)
    assert g.z_min == 14  # 1.6/sin²20° = 13.7: the short tooth's 14
    rack = variant("rack_rocker", keys=(r"    teeth: z\n", "    teeth: z\n    shift: 0.25\n"))
    assert next(j.gear_data() for j in rack.joints if j.name == "mesh").shift == (0.0, 0.25)


@pytest.mark.parametrize(
    ("added", "message"),
    [
        ("    addendum: 0\n", "must be positive"),
        ("    clearance: 1.5\n", "clearance coefficient must be at most 1"),
        ("    shift: [0.5]\n", "expected a list of 2 profile shift coefficients"),
        ("    shift: [0.5, 4]\n", "must be from -3 to 3"),
        ("    shift: [-1.5, -1.5]\n", "the pair has no working pressure angle"),
    ],
)
def test_the_tooth_form_keys_are_checked(added, message):
    with pytest.raises(ks.ModelError, match=message):
        variant("geared_fivebar", keys=(r"    mesh: external\n", "    mesh: external\n" + added))


def test_an_internal_mesh_takes_no_shift():
    text = "    mesh: internal\n    shift: [0.2, 0.0]\n"
    with pytest.raises(ks.ModelError, match="not for an internal mesh"):
        variant(
            "geared_fivebar",
            keys=(r"    mesh: external\n", text),
            teeth=(r"teeth: \[z, z\]", "teeth: [z, 2*z]"),
        )
