"""Regression tests for the follow-up defects: each fails on the code before its fix.

Expected values come from closed forms, power identities and geometry, not from
the program's own output."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics import flywheel

from .helpers import ROOT, variant


# -- 3. efficiency 0/0 ----------------------------------------------------------------------

def _massless_slider_crank():
    """The shipped slider-crank without masses and gravity: only the working-stroke
    resistance loads it, so on the return stroke both efforts are exactly 0."""
    return variant("slider_crank", g=(r"gravity: \[0, -9.81\]", "gravity: [0, 0]"),
                   m1=(r"mass: 2\n    inertia: 0.006", "mass: 0\n    inertia: 0"),
                   m2=(r"mass: 3\n    inertia: 0.031", "mass: 0\n    inertia: 0"),
                   m3=(r"mass: 4", "mass: 0"))


def test_efficiency_undefined_where_no_effort_goes_through_the_drive():
    # 30°: the slider moves in −x (return stroke, x_B' = −a sin φ − ... < 0), nothing loads
    # the linkage: torque = torque_friction = 0 and η = 0/0 is undefined; 200°: working stroke
    r = ks.analyze(_massless_slider_crank(), positions=np.radians([30.0, 200.0]))
    assert r["motor.torque"][0] == 0.0 and r["motor.torque_friction"][0] == 0.0
    assert np.isnan(r["motor.efficiency"][0])
    eta = r["motor.torque"][1] / r["motor.torque_friction"][1]
    assert 0.0 < eta < 1.0 and r["motor.efficiency"][1] == pytest.approx(eta, rel=1e-15)
    fc = r.checks.friction
    assert dict(fc.detail)["efficiency_undefined"] == 1
    assert "efficiency undefined at 1" in r.checks.line()
    assert r.checks.ok                                 # counted, not a failure


# -- 4. flywheel delta ----------------------------------------------------------------------

@pytest.mark.parametrize("delta", [1.0, 1.5])
def test_flywheel_delta_below_one_as_in_a_file(delta):
    model = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    with pytest.raises(ValueError, match="delta"):
        flywheel.design(model, delta=delta)
