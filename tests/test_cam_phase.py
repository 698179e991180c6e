"""Issue 36: a cam must run in phase with its law, and its profile checks must see every
segment; its separation warning is one line; a large friction coefficient is solved fast.

The files in ``tests/cases/`` are the issue's reproducers."""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.errors import ModelError

from .conftest import ROOT

CASES = ROOT / "tests" / "cases"
RB, RR, D, L = 40.0, 15.0, 120.0, 100.0  # the rocker cam's base circle, roller, pivot, arm
XC = ((RB + RR) ** 2 - L**2 + D**2) / (2 * D)  # the roller centre at zero lift
YC = math.sqrt((RB + RR) ** 2 - XC**2)


def _message(name):
    with pytest.raises(ModelError) as info:
        ks.analyze(ks.load(CASES / name))
    assert len(info.value.problems) == 1
    return str(info.value)


def test_a_roller_sketched_on_the_mirror_side_is_a_model_error():
    """The arm reaches the prime circle at (xc, ±yc); the rise (cw) moves the roller
    outwards from (xc, +yc) only, so that is where the law puts it at cam angle 0."""
    text = _message("cam_sketch_mirror.yaml")
    assert "joints.contact: cam joint 'contact': the follower is out of phase" in text
    assert "while the cam is at 0°" in text and "instead of 0°" in text
    x, y = (float(v) for v in text.split("near [")[1].split("]")[0].split(","))
    assert abs(x - XC) <= 1e-4 and abs(y - YC) <= 1e-4  # printed to 6 digits
    assert "sketch the follower point arm.C" in text


def test_a_rise_of_the_wrong_sense_is_a_model_error():
    """With ``rise: ccw`` the law puts the roller at (xc, −yc) at cam angle 0, the
    mirror of where it is sketched and assembled."""
    text = _message("cam_rise_wrong_sense.yaml")
    assert "out of phase with its law" in text and "while the cam is at 0°" in text
    x, y = (float(v) for v in text.split("near [")[1].split("]")[0].split(","))
    assert abs(x - XC) <= 1e-4 and abs(y + YC) <= 1e-4
    assert "reverse `oscillating.rise`" in text


def test_the_cli_refuses_an_out_of_phase_cam_in_one_line(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["run", str(CASES / "cam_sketch_mirror.yaml"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "out of phase" in err[0] and "Traceback" not in err[0]
    assert not out.exists()


@pytest.mark.filterwarnings("ignore::kinetostatics.errors.JointWarning")
def test_the_intended_rocker_cam_runs_in_phase():
    """Its contact's cam angle is the cam's rotation at every row; at the law's zero the
    roller centre is at (xc, yc), on the prime circle."""
    r = ks.analyze(ks.load(CASES / "cam_rocker_right.yaml"))
    np.testing.assert_allclose(
        np.mod(r["contact.cam_angle"] - r["cam.theta"] + 180, 360) - 180, 0, atol=1e-9
    )
    row = int(np.argmin(np.abs(np.mod(r["cam.theta"] + 180, 360) - 180)))
    assert abs(r["cam.theta"][row]) <= 1e-12
    assert math.hypot(r["arm.C.x"][row] - XC / 1e3, r["arm.C.y"][row] - YC / 1e3) <= 1e-12


def test_an_offset_that_is_not_the_guides_is_a_model_error():
    """The guide at 15 mm from the cam centre, ``offset: 10``: refused, naming both."""
    text = (ROOT / "mechanisms" / "cam_roller.yaml").read_text()
    text = text.replace("points: {O: [0, 0], G: [e, 0]}", "points: {O: [0, 0], G: [15, 0]}")
    with pytest.raises(ModelError) as info:
        ks.analyze(ks.loads(text))
    assert "the follower point runs 15 mm from the cam centre across its guide, not at " in str(
        info.value
    ) and "`translating.offset: 10` mm" in str(info.value)
