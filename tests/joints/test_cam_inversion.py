"""The inversion of a cam's profile (joints/_camprofile.py, ``Synthesis.invert``): the
cam angle θ at which the pitch point's polar angle ψ (or a flat face's normal angle ν)
is a given value.  Held against six Newton steps from the table written out here on
the full formulas of ``pitch`` and ``support`` (``invert`` skips the steps that can no
longer move θ, and ``angle`` evaluates only a and a'), and against the profile itself:
a(θ) is the target, over several turns, for every follower and placement."""

import math

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.joints._camlaw import CamLaw, Segment
from kinetostatics.joints._camprofile import Synthesis
from tests.helpers import ROOT

LAW = CamLaw(
    segments=(
        Segment("rise", 0.012, math.radians(110), "harmonic"),
        Segment("dwell", 0.0, math.radians(50)),
        Segment("return", 0.012, math.radians(120), "polynomial7"),
        Segment("dwell", 0.0, math.radians(80)),
    )
)
ULPS = 8 * np.spacing(2 * math.pi)
SWING = CamLaw(segments=tuple(Segment(s.kind, s.lift * 15, s.span, s.curve) for s in LAW.segments))


def _shipped(name):
    model = ks.load(ROOT / "mechanisms" / name)
    return next(j for j in model.joints if type(j).__name__ == "Cam").synthesis


SYNTHESES = {
    "roller, translating, offset (shipped)": lambda: _shipped("cam_roller.yaml"),
    "flat, oscillating (shipped)": lambda: _shipped("cam_flat_oscillating.yaml"),
    "knife, translating, cw": lambda: Synthesis(
        LAW, "knife", 0.0, 0.04, -1, (0.0, 1.0), -0.008, None, 0.0, 1
    ),
    "flat, translating": lambda: Synthesis(
        LAW, "flat", 0.0, 0.04, 1, (0.6, 0.8), 0.0, None, 0.0, 1
    ),
    "roller, oscillating, cw rise": lambda: Synthesis(
        SWING, "roller", 0.01, 0.04, 1, None, 0.0, (0.09, 0.02), 0.07, -1
    ),
}


def _wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def _a(syn, theta):
    """(a, a') from the full formulas: ``pitch`` (ψ, ψ') or ``support`` (ν, ν')."""
    r = syn.support(theta) if syn.flat else syn.pitch(theta)[0]
    return r[0], r[1]


def _six_newton_steps(syn, tables, target):
    th, b, a0, _ = tables
    sg = 1.0 if _a(syn, np.array([0.0]))[1][0] > 0 else -1.0
    x = sg * (target - a0)
    turns = np.floor(x / (2 * math.pi))
    theta = np.interp(x - 2 * math.pi * turns, b, th)
    for _ in range(6):
        a, a1 = _a(syn, theta)
        theta = theta - _wrap(a - target) / a1
    return theta, turns


@pytest.mark.parametrize("name", sorted(SYNTHESES))
def test_invert_is_newton_on_the_profile(name):
    syn = SYNTHESES[name]()
    tables = syn.tables()
    assert not isinstance(tables, str), tables
    theta = np.linspace(0.0, 2 * math.pi, 361)
    a, a1 = syn.angle(theta)
    full = _a(syn, theta)
    assert np.max(np.abs(_wrap(a - full[0]))) <= 1e-12 * 2 * math.pi
    assert np.max(np.abs(a1 - full[1])) <= 1e-12 * np.max(np.abs(full[1]))
    rng = np.random.default_rng(7)
    base = tables[2]
    for shape in [(), (1,), (2,), (5,), (9,), (360,)]:
        target = base + rng.uniform(-3 * math.pi, 5 * math.pi, shape)
        got, turns = syn.invert(tables, target)
        want, want_turns = _six_newton_steps(syn, tables, target)
        assert np.shape(got) == shape
        np.testing.assert_array_equal(turns, want_turns)
        # a few ulps of 2π: one step fewer would already be within 1e-12 rad
        assert np.max(np.abs(got - want), initial=0.0) <= ULPS, (shape, got - want)
        # and θ is where the profile's angle is the target
        residual = _wrap(_a(syn, np.atleast_1d(got))[0] - np.atleast_1d(target))
        assert np.max(np.abs(residual)) <= 1e-12 * 2 * math.pi, shape
