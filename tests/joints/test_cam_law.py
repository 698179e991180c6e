"""The cam's follower law (joints/_camlaw.py) segment by segment against the curves'
closed forms written out here: s, s', s'', s''' at every segment end, within round-off
of it (the segment that starts there), just before and after it, and at random
angles over several turns; each angle alone (a Python float, a one-element array),
in small arrays and in one large array (the law evaluates up to ``SMALL`` angles one
by one in Python floats and more grouped by segment: every path is held to the
formulas)."""

import math

import numpy as np
import pytest

from kinetostatics.joints._camlaw import CURVES, SMALL, CamLaw, Segment

TWO_PI = 2 * math.pi


def _y(curve, u):
    """y, y', y'', y''' of a normalised curve at u (the textbook's formulas)."""
    p, s1, c1 = math.pi, math.sin(math.pi * u), math.cos(math.pi * u)
    s2, c2 = math.sin(2 * math.pi * u), math.cos(2 * math.pi * u)
    return {
        "harmonic": ((1 - c1) / 2, p / 2 * s1, p**2 / 2 * c1, -(p**3) / 2 * s1),
        "cycloidal": (u - s2 / (2 * p), 1 - c2, 2 * p * s2, 4 * p**2 * c2),
        "polynomial": (
            10 * u**3 - 15 * u**4 + 6 * u**5,
            30 * u**2 - 60 * u**3 + 30 * u**4,
            60 * u - 180 * u**2 + 120 * u**3,
            60 - 360 * u + 360 * u**2,
        ),
        "polynomial7": (
            35 * u**4 - 84 * u**5 + 70 * u**6 - 20 * u**7,
            140 * u**3 - 420 * u**4 + 420 * u**5 - 140 * u**6,
            420 * u**2 - 1680 * u**3 + 2100 * u**4 - 840 * u**5,
            840 * u - 5040 * u**2 + 8400 * u**3 - 4200 * u**4,
        ),
    }[curve]


def _parts(curve, other):
    """(kind, lift, span°, curve): a rise, a dwell, two returns meeting without a dwell
    (the second by ``other``), a dwell; spans that are no round numbers of radians."""
    h = 0.0125
    return [
        ("rise", h, 97.5, curve),
        ("dwell", 0.0, 41.25, ""),
        ("return", h / 3, 66.0, curve),
        ("return", 2 * h / 3, 85.75, other),
        ("dwell", 0.0, 69.5, ""),
    ]


def _expected(parts, theta):
    """s, s', s'', s''' at θ: the segment that holds it, and the one that starts at an
    end for an angle within 1e-12 rad of that end (360° − 1e-14 is 0°)."""
    t = math.fmod(theta, TWO_PI) + (TWO_PI if theta < 0 else 0.0)
    if t > TWO_PI - 1e-12:
        t -= TWO_PI
    start, base = 0.0, 0.0
    for k, (kind, h, span, curve) in enumerate(parts):
        b = math.radians(span)
        end = start + b
        sign = {"rise": 1.0, "return": -1.0, "dwell": 0.0}[kind]
        if t < end - 1e-12 or k == len(parts) - 1:
            if kind == "dwell":
                return base, 0.0, 0.0, 0.0
            y = _y(curve, (t - start) / b)
            return tuple(sign * h * y[n] / b**n + (base if n == 0 else 0.0) for n in range(4))
        start, base = end, base + sign * h
    raise AssertionError("not reached")


def _angles(law, rng):
    ends = law.breaks
    near = [ends + d for d in (0.0, -3e-13, 3e-13, -1e-7, 1e-7, -1e-3, 1e-3)]
    th = np.concatenate(near + [[TWO_PI - 1e-14, -1e-14], rng.uniform(-2 * TWO_PI, 3 * TWO_PI, 60)])
    return np.concatenate((th, th[:20] + TWO_PI, th[20:40] - 2 * TWO_PI))


@pytest.mark.parametrize("curve", sorted(CURVES))
def test_the_law_is_its_curves_at_every_end_and_between(curve):
    kinds = sorted(CURVES)
    other = kinds[(kinds.index(curve) + 1) % len(kinds)]
    parts = _parts(curve, other)
    law = CamLaw(segments=tuple(Segment(k, h, math.radians(s), c) for k, h, s, c in parts))
    assert math.isclose(law.breaks[-1], TWO_PI, rel_tol=1e-15)
    th = _angles(law, np.random.default_rng(36))
    want = np.array([_expected(parts, float(t)) for t in th]).T  # (4, n)
    # each derivative on the scale of its unit: the largest |h y⁽ⁿ⁾/βⁿ| of the segments
    scale = np.max(np.abs(want), axis=1)
    assert np.all(scale > 0)

    def check(got, which, where):
        got = np.asarray(got, float)
        err = np.max(np.abs(got - want[:, which].reshape(got.shape)), axis=-1)
        assert np.all(err <= 1e-12 * scale), (where, err / scale)

    check(np.array(law.value(th)), slice(None), "one array")
    assert len(th) > SMALL
    for size in range(2, SMALL + 1):
        for lo in range(0, len(th), size):
            k = slice(lo, lo + size)
            check(np.array(law.value(th[k])), k, f"{size} angles from {lo}")
    for n, t in enumerate(th):
        got = law.value(float(t))
        assert all(np.shape(v) == () for v in got)
        check(np.array(got)[:, None], [n], f"θ = {t!r}")
        check(np.array(law.value(np.array([t]))), [n], f"[θ] = [{t!r}]")


def test_the_law_keeps_the_shape_of_its_angles():
    law = CamLaw(segments=(Segment("rise", 0.01, math.pi, "cycloidal"),
                           Segment("return", 0.01, math.pi, "harmonic")))  # fmt: skip
    for shape in [(), (0,), (1,), (3,), (2, 3), (3, 5), (1, 1, 9)]:
        th = np.random.default_rng(1).uniform(0, 7, shape)
        out = law.value(th)
        assert len(out) == 4 and all(v.shape == shape for v in out)
        flat = np.array(law.value(th.ravel()))
        np.testing.assert_array_equal(np.array(out).reshape(4, -1), flat)


@pytest.mark.parametrize("curve", sorted(CURVES))
def test_the_derivatives_are_those_of_the_lift(curve):
    """s', s'', s''' against central differences of s, s', s'' inside the segments."""
    parts = _parts(curve, curve)
    law = CamLaw(segments=tuple(Segment(k, h, math.radians(s), c) for k, h, s, c in parts))
    ends = law.breaks
    th = np.concatenate([np.linspace(a + 1e-3, b - 1e-3, 40) for a, b in zip(ends, ends[1:])])
    d = 1e-5
    up, down, mid = law.value(th + d), law.value(th - d), law.value(th)
    for n in range(1, 4):
        fd = (up[n - 1] - down[n - 1]) / (2 * d)
        scale = np.max(np.abs(mid[n]))
        assert np.max(np.abs(fd - mid[n])) <= 1e-6 * scale, n
