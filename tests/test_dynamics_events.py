"""Forward dynamics across load switches (kinetostatics.dynamics.simulate).

Every integration piece holds its loads fixed, ends at the switch located on its
own dense output and the next piece starts from the state there; the speed
extremes (δ) are those of the solution itself.  Expected values are independent:
energy identities with the loads' work in closed form (F·Δx on a band, the
cutting force over 0.9 H, the slider's stroke), a hand-written equation of motion
integrated piecewise between exactly located switches, and the cycle's own
periodicity (constant mean moment = cutting work / 2π, started at ω_m).
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import kinetostatics as ks
from kinetostatics.dynamics import simulate, speed_fluctuation, with_effort
from kinetostatics.flywheel import design
from kinetostatics.model import EffortLaw

from .helpers import ROOT, variant
from .oracles import slider_crank_closed_form as cf

SWITCHED = ROOT / "tests" / "dynamics" / "switched_pendulum.yaml"
F, X1, X2 = 5.0, -0.1, 0.1                 # the push: N along +x on x_tip in [X1, X2] (m)
J_O, MGR, TIP = 0.02 + 2 * 0.3 ** 2, 2 * 9.81 * 0.3, 0.5


# -- a pendulum with a force that switches on and off with the position --------------
@pytest.fixture(scope="module")
def pendulum():
    return simulate(ks.load(SWITCHED), 3.0)             # the default RK45, rtol 1e-8


def test_switched_pendulum_conserves_energy_across_the_switches(pendulum):
    cols, _ = pendulum.table(points=301)
    x = TIP * np.cos(np.radians(cols["hinge.angle"]))
    assert x.min() < X2 < x.max()                        # it enters and leaves the band
    assert sum(e["kind"] == "switch" for e in pendulum.events) >= 6
    work = F * (np.clip(x, X1, X2) - np.clip(x[0], X1, X2))
    e = cols["energy.kinetic"] + cols["energy.potential"] - work
    assert np.max(np.abs(e - e[0])) <= 1e-6 * np.ptp(cols["energy.kinetic"])


def reference_pendulum(t_end):
    """J_O ψ̈ = −m g r cos ψ − F·TIP sin ψ·[x_tip < X2], written by hand and integrated
    piecewise: each piece stops at the band edge (x_tip = X2, crossed in the sense
    that leaves its side) and the next starts from the state there on the other side."""
    def edge(t, y):
        return TIP * np.cos(y[0]) - X2
    edge.terminal = True
    t, y, on, pieces = 0.0, np.array([np.radians(-60.0), 0.0]), 0.0, []
    while True:
        edge.direction = 1.0 if on else -1.0
        sol = solve_ivp(lambda tt, yy, on=on: [yy[1], (-MGR * np.cos(yy[0])
                                                      - on * F * TIP * np.sin(yy[0])) / J_O],
                        (t, t_end), y, method="DOP853", rtol=1e-13, atol=1e-13,
                        dense_output=True, events=edge)
        pieces.append((t, sol.sol))
        if sol.status != 1:
            break
        t, y, on = float(sol.t_events[0][-1]), sol.y_events[0][-1], 1.0 - on

    def state(tt):
        starts = np.array([p[0] for p in pieces])
        k = np.clip(np.searchsorted(starts, tt, side="right") - 1, 0, len(pieces) - 1)
        return np.array([pieces[i][1](x) for i, x in zip(k, tt)]).T
    return state, len(pieces) - 1


def test_switched_pendulum_restarts_from_the_exact_state(pendulum):
    state, switches = reference_pendulum(3.0)
    assert switches >= 6
    t = np.linspace(0.0, 3.0, 601)
    ours, ref = pendulum.sample(t), state(t)
    assert np.min(TIP * np.cos(ref[0])) > X1             # the far edge is never reached
    assert np.max(np.abs(ours[:, 0] - ref[0])) <= 1e-6
    assert np.max(np.abs(ours[:, 1] - ref[1])) <= 1e-6 * np.max(np.abs(ref[1]))
