"""Andrews' squeezer mechanism (mechanisms/andrews_squeezer.yaml) against the published
reference of the Bari test set (tests/andrews_reference.py; docs/benchmarks.md): the
consistent initial configuration, the accelerations and the multipliers (reactions at the
pin E) at rest, the state at t = 0.03 s by forward dynamics and its energy balance."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics import Dynamics, simulate
from kinetostatics.kinetics.inverse import kinetics
from tests import andrews_reference as ref
from tests.helpers import ROOT

PATH = ROOT / "mechanisms" / "andrews_squeezer.yaml"
RTOL = 1e-9  # DOP853: the angles at 0.03 s to 2.7e-8 rad (docs/benchmarks.md)


@pytest.fixture(scope="module")
def model():
    return ks.load(PATH)


@pytest.fixture(scope="module")
def at_rest(model):
    dyn = Dynamics(model)
    y0 = np.zeros(dyn.n_y)
    y0[: dyn.n_f] = dyn.start()
    return dyn, dyn.state(0.0, y0)


def test_the_consistent_initial_configuration(at_rest):
    dyn, ev = at_rest
    angles = ref.relative_angles(dyn.system, ev.q)
    assert np.max(np.abs(angles - ref.INITIAL)) <= 1e-13


def test_the_accelerations_at_rest(at_rest):
    dyn, ev = at_rest
    qdd = ev.qdd0 + ev.accel @ ev.dqdd
    acc = ref.relative_angles(dyn.system, qdd)
    scale = np.max(np.abs(ref.INITIAL_ACCELERATION))
    assert np.max(np.abs(acc - ref.INITIAL_ACCELERATION)) <= 1e-11 * scale


def test_the_reactions_at_rest_are_the_multipliers(at_rest):
    """The source's g1, g2 say that E of the chain body1–body2 is E of body3 (λ1, λ2),
    g3..g6 that it is E of body4 and of body6: the force of body2 on body3 at E is
    (λ1, λ2), on body4 and body6 it is 0; the torque the crank needs is the drive's."""
    dyn, ev = at_rest
    qdd = ev.qdd0 + ev.accel @ ev.dqdd
    kin = kinetics(dyn.system, ev.q[None], ev.qd[None], qdd[None], ev.psi[None], ref_speed=1.0)
    system, x0 = dyn.system, kin.x0[0]
    qe = np.concatenate((ev.q, np.zeros(3)))
    force = {}
    for k, j in enumerate(system.model.joints):
        i_, j_ = system.ends[k]
        r = j.reaction(x0[system.rows_of(k)], qe[3 * i_ : 3 * i_ + 3], qe[3 * j_ : 3 * j_ + 3])
        force[j.name] = np.array([r["Fx"], r["Fy"]])
    lam = ref.INITIAL_LAMBDA
    assert np.max(np.abs(force["E_body3"] - lam[:2])) <= 1e-9 * np.max(np.abs(lam))
    assert np.max(np.abs(force["E_body4"])) <= 1e-9 * np.max(np.abs(lam))
    assert np.max(np.abs(force["E_body6"])) <= 1e-9 * np.max(np.abs(lam))
    assert x0[system.n_joint_rows] == pytest.approx(0.033, rel=1e-11)


@pytest.fixture(scope="module")
def run(model):
    return simulate(model, ref.T_END, method="DOP853", rtol=RTOL)


def test_the_state_at_0_03_s(run):
    q, qd = ref.state_at(run, ref.T_END)
    system = run.dynamics.system
    err = ref.relative_angles(system, q) - ref.FINAL
    assert np.max(np.abs(err)) <= 3e-7  # rad: 7 digits of β = 15.81 (measured 2.7e-8)
    speed = ref.relative_angles(system, qd) - ref.FINAL_SPEED
    assert np.max(np.abs(speed)) <= 1e-7 * np.max(np.abs(ref.FINAL_SPEED))  # measured 7.5e-9


def test_the_energy_balance_of_the_run(run):
    """The drive's work goes into kinetic energy and the spring's: W = ΔT + ΔE_spring."""
    cols, _ = run.table(points=61)
    e = cols["energy.total"]
    assert np.all(cols["energy.potential"] == 0.0)  # no gravity
    assert np.ptp(cols["energy.elastic"]) > 0.1 * np.max(cols["energy.kinetic"])
    work = cols["work.drivers"]
    assert work[-1] == pytest.approx(0.033 * (ref.FINAL[0] - ref.INITIAL[0]), rel=1e-6)
    assert np.max(np.abs(e - e[0] - work)) <= 1e-6 * np.max(np.abs(work))
