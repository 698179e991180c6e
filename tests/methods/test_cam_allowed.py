"""The allowable pressure angle [α] as a key of the cam joint, ``design:
{pressure_angle_max: …}`` (issue 38): read in the file's angle unit, used by the cam's
design (and so by methods.json and the report's chapter) in place of the textbook's 30°,
the caller's value above both.  The least base radius for the file's [α] is checked against
the closed form of a translating offset roller follower written out here, and for an
oscillating roller follower against the pipeline's own pressure-angle column at that base
radius; a value outside (0°, 90°) or a stray key is refused at its key."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.errors import ModelError
from kinetostatics.io.dump import dump
from kinetostatics.methods.cam_design import cam_design
from kinetostatics.methods.stage import methods_stage
from tests.methods.test_cam_design import (
    A_,
    L_,
    OSCILLATING,
    RR,
    TRANSLATING,
    E,
    _beta0,
    _harmonic_law,
)


def _with_design(text: str, design: str) -> str:
    return text.replace("    rotation: ", f"    design: {design}\n    rotation: ", 1)


def _translating(design: str, rb=0.030, n=360) -> str:
    text = TRANSLATING.format(rb=rb * 1e3, e=E * 1e3, rotation="ccw", sign=1, n=n, speed=100)
    return _with_design(text, design)


def _oscillating(design: str, rb=0.040) -> str:
    b = _beta0(rb)
    cx, cy = L_ * math.cos(b), L_ * math.sin(b)
    text = OSCILLATING.format(
        a=A_ * 1e3, arm=L_ * 1e3, rb=rb * 1e3, cx=cx * 1e3, cy=cy * 1e3,
        px=(A_ + cx) * 1e3, py=cy * 1e3,
    )  # fmt: skip
    return _with_design(text, design)


def test_the_files_allowed_angle_gives_the_textbook_least_base_radius():
    """r_p,min = max √((|s′ − e|/tan[α] − s)² + e²) at the file's [α] = 20°, r_b,min =
    r_p,min − r_r (dense grid of the closed form, here where the bracket is positive)."""
    (cam,) = cam_design(ks.loads(_translating("{pressure_angle_max: 20}")))
    assert cam.allowed == 20.0 and cam.allowed_from == "file" and cam.method == "closed form"
    theta = np.linspace(0, 2 * np.pi, 2_000_001)
    s, s1, _ = _harmonic_law(theta)
    d = np.abs(s1 - E) / math.tan(math.radians(20)) - s
    rp = math.sqrt(d.max() ** 2 + E**2)
    assert abs(cam.base_radius_min - (rp - RR)) <= 1e-9 * rp
    # the file's 30 mm base radius exceeds 20° (the largest |α| there is about 22.8°)
    assert cam.peak > 20.0 and not cam.satisfied and cam.base_radius_min > 0.030
    # the caller's value wins, and without the key the textbook's 30° is taken
    file = ks.loads(_translating("{pressure_angle_max: 20}"))
    (caller,) = cam_design(file, pressure_angle_max=30)
    (plain,) = cam_design(ks.loads(_translating("{pressure_angle_max: 30}").replace(
        "    design: {pressure_angle_max: 30}\n", "")))  # fmt: skip
    assert (caller.allowed, caller.allowed_from) == (30.0, "caller")
    assert (plain.allowed, plain.allowed_from) == (30.0, "default")
    assert caller.base_radius_min == pytest.approx(plain.base_radius_min, rel=1e-12)
    assert plain.base_radius_min < cam.base_radius_min  # a larger [α] allows a smaller cam


def test_oscillating_least_base_radius_for_the_files_angle_against_the_pipeline():
    """At the r_b,min the design finds for the file's [α] = 40°, the pipeline's own
    pressure-angle column (the contact's normal against the roller centre's velocity, at
    720 positions) stays within 40°, and 1 % below it exceeds 40°."""
    (cam,) = cam_design(ks.loads(_oscillating("{pressure_angle_max: 40}")))
    assert cam.allowed == 40.0 and cam.allowed_from == "file" and cam.method == "bisection"
    rb = cam.base_radius_min

    def largest(r):
        text = _oscillating("{pressure_angle_max: 40}", rb=r).replace(
            "positions: 360", "positions: 720"
        )
        return np.max(np.abs(ks.analyze(ks.loads(text))["contact.pressure_angle"]))

    assert 40.0 - 0.05 <= largest(rb) <= 40.0 + 1e-9
    assert largest(0.99 * rb) > 40.0


def test_methods_json_and_the_dump_keep_the_files_angle():
    model = ks.loads(_translating("{pressure_angle_max: 25}"))
    result = ks.analyze(model, kinematics_only=True)
    entry = methods_stage(result, [("1", 0)], parts=["cam_design"])["cam_design"]["contact"]
    assert entry["allowed"] == 25.0 and entry["allowed_from"] == "file"
    # the dump writes SI (rad): read back in that unit, the same [α]
    again = ks.loads(dump(model))
    (joint,) = [j for j in again.joints if j.name == "contact"]
    assert joint.allowed == pytest.approx(math.radians(25), rel=1e-12)


@pytest.mark.parametrize(
    "design, message",
    [
        ("{pressure_angle_max: 90}", "strictly between 0° and 90°, got 90°"),
        ("{pressure_angle_max: 0}", "strictly between 0° and 90°, got 0°"),
        ("{pressure_angle_max: 30, base: 2}", "base"),
        ("{}", "pressure_angle_max"),
    ],
)
def test_a_wrong_design_is_refused_at_its_key(design, message):
    with pytest.raises(ModelError) as err:
        ks.loads(_translating(design))
    text = str(err.value)
    assert message in text and re.search(r":\d+:\d+: joints\.contact\.design", text)
