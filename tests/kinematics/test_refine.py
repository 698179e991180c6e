"""The events' safeguarded Newton (kinematics/events.py ``refine``) on a function of time
alone: the state at a time is the time itself (``state_at`` replaced), so that the count
of evaluations is the iteration's own."""

import numpy as np
import pytest

from kinetostatics.kinematics import events


def _count(monkeypatch, root: float, t0: float, lo: float, hi: float, sign_lo: float):
    """(root found, evaluations) of g(t) = (t − r) − 5 (t − r)² (concave: Newton from the
    right overshoots to the left of r) in the bracket [lo, hi]."""
    calls = []

    def state_at(system, drive, t, *near):
        calls.append(t.copy())
        return t[:, None], np.ones((len(t), 1)), np.zeros((len(t), 1))

    monkeypatch.setattr(events, "state_at", state_at)

    def f(q, qd, qdd):
        d = q[:, 0] - root
        return d - 5.0 * d * d, 1.0 - 10.0 * d

    one = np.zeros((1, 1))
    t, _ = events.refine(
        None, None, f, np.array([t0]), np.array([t0]), one, one, one,
        bracket=(np.array([lo]), np.array([hi]), np.array([sign_lo])),
    )  # fmt: skip
    return float(t[0]), len(calls)


@pytest.mark.parametrize("gap", [0.0, 1e-13, 1e-9])
def test_a_root_at_the_brackets_end_converges_as_newton_does(monkeypatch, gap):
    # the root on (or within round-off of) the bracket's lower end, where the run starts
    # at a limit position: each Newton step from the right lands just left of it, outside
    # the bracket; bisection from there took ~15 evaluations, Newton's own rate ~5
    root = 0.0 + gap
    t, n = _count(monkeypatch, root, 0.00276, 0.0, 0.01, -1.0)
    assert abs(t - root) <= 1e-14
    assert n <= 6


def test_a_step_far_outside_the_bracket_still_bisects(monkeypatch):
    # a first guess far from the root in a bracket that holds it: every point stays inside
    # and the root is found
    t, n = _count(monkeypatch, 0.3, 0.39, 0.0, 0.4, -1.0)
    assert abs(t - 0.3) <= 1e-14 and n <= 64


def test_outside_mirrors_a_small_overshoot_and_bisects_a_large_one():
    t, lo, hi = np.array([0.01, 0.01]), np.array([0.0, 0.0]), np.array([1.0, 1.0])
    step = np.array([-0.001, -0.5])  # past lo by 10 % and by 50x of t's distance from it
    np.testing.assert_allclose(events._outside(t, step, lo, hi), [0.001, 0.5])
