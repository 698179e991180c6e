"""The closed-form path's own helpers against NumPy's."""

from __future__ import annotations

import numpy as np
import pytest

from kinetostatics.kinematics.closed_path import _branch_signs, _evenly


@pytest.mark.parametrize("seed", range(4))
def test_the_auxiliary_times_are_numpy_s_linspace(seed):
    """``_evenly`` is ``np.linspace`` (endpoint included) to the bit, signs of zero too,
    over spans of every scale, a span of zero and a step that underflows."""
    rng = np.random.default_rng(seed)
    spans = [(0.0, 0.0), (-1e-310, 1e-310), (0.0, 5e-324), (-3.0, -3.0)]
    spans += [
        (-rng.random() * s, rng.random() * s) for s in (1e-300, 1e-9, 1.0, 1e3) for _ in range(50)
    ]
    for lo, hi in spans:
        for num in (2, 3, 14, 361):
            a, b = np.linspace(lo, hi, num), _evenly(lo, hi, num)
            assert np.array_equal(a, b) and np.array_equal(np.signbit(a), np.signbit(b))


def test_a_path_without_change_points_keeps_each_group_s_sign():
    """No group with a change point: +1 for every group at every time, in the shape of
    the general rule's (variants, times, groups)."""
    t = np.linspace(-1.0, 2.0, 7)[None].repeat(2, axis=0)
    flips = [np.full((2, 0), np.nan) for _ in range(3)]
    signs = _branch_signs(flips, t)
    assert signs.shape == (2, 7, 3) and np.all(signs == 1.0)
    flips[1] = np.array([[0.5], [np.nan]])  # one change point, in the first variant only
    signs = _branch_signs(flips, t)
    assert np.array_equal(signs[0, :, 1], np.where((t[0] >= 0.5), -1.0, 1.0))
    assert np.all(signs[1] == 1.0) and np.all(signs[:, :, [0, 2]] == 1.0)
