"""What the cycle's stage shares between its steps (issue 40) gives the answers it gave
without sharing: the nodes with friction on the frictionless nodes' motion equal the
pipeline run again at those times (an identity, column by column), the switches of
several rate functions refined together equal each refined alone, and the first guess
of a root from the cubic Hermite interpolant is a cubic's root exactly (a closed form).
"""

from __future__ import annotations

import warnings

import numpy as np

import kinetostatics as ks
from kinetostatics.analysis.cuts import quiet_analyze
from kinetostatics.analysis.pipeline import with_friction
from kinetostatics.analysis.switches import (
    exact_roots,
    exact_roots_of,
    friction_rates,
    reversal_rates,
)
from kinetostatics.kinematics.events import _hermite_guess
from tests.helpers import ROOT


def _analysed(name: str):
    return ks.analyze(ks.load(ROOT / "mechanisms" / f"{name}.yaml"))


def test_the_nodes_with_friction_on_the_frictionless_motion_are_the_pipeline_s():
    r = _analysed("slotting_machine")
    times = np.sort(r.t[::17] + 0.31 * (r.t[1] - r.t[0]))
    plain = quiet_analyze(r.system, times=times, friction=False, events=False)
    assert "friction.status" not in plain.columns
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = with_friction(plain)
    want = quiet_analyze(r.system, times=times, friction=True, events=False)
    assert set(got.columns) == set(want.columns)
    for name in want.columns:
        a, b = np.asarray(got[name], float), np.asarray(want[name], float)
        scale = max(float(np.max(np.abs(b[np.isfinite(b)]), initial=0.0)), 1e-300)
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        ok = np.isfinite(b)
        assert np.max(np.abs(a[ok] - b[ok]), initial=0.0) <= 1e-12 * scale, name
    assert np.allclose(got.lam_friction, want.lam_friction, rtol=0, atol=1e-9)


def test_switches_refined_together_are_those_refined_alone():
    r = _analysed("slotting_machine")
    groups = [reversal_rates(r), friction_rates(r)]
    assert all(groups)
    together = exact_roots_of(r, groups)
    period = float(r.t[-1] - r.t[0])
    for rates, got in zip(groups, together):
        alone = exact_roots(r, rates)  # itself one refine; compare with one per rate
        each = [t for rate in rates for t in exact_roots(r, [rate])]
        assert len(got) == len(alone) == len(each) > 0
        for a, b in ((got, each), (alone, each)):
            assert np.max(np.abs(np.sort(a) - np.sort(b))) <= 1e-12 * period


def test_the_hermite_guess_of_a_cubic_is_its_root():
    # f(t) = (t − 0.3)(t² + 1) on brackets around 0.3: values and slopes at the ends
    f = lambda t: (t - 0.3) * (t * t + 1)  # noqa: E731
    df = lambda t: (t * t + 1) + 2 * t * (t - 0.3)  # noqa: E731
    ta, tb = np.array([0.0, 0.25, -1.0]), np.array([1.0, 0.4, 2.0])
    sign_a = np.sign(f(ta))
    got = _hermite_guess(ta, tb, f(ta), f(tb), df(ta), df(tb), sign_a)
    assert np.max(np.abs(got - 0.3)) <= 1e-14
