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
from kinetostatics.dynamics.flywheel import design
from kinetostatics.model import EffortLaw
from tests.helpers import ROOT, variant
from tests.oracles import slider_crank_closed_form as cf

SWITCHED = ROOT / "tests" / "dynamics" / "switched_pendulum.yaml"
F, X1, X2 = 5.0, -0.1, 0.1  # the push: N along +x on x_tip in [X1, X2] (m)
J_O, MGR, TIP = 0.02 + 2 * 0.3**2, 2 * 9.81 * 0.3, 0.5


# -- a pendulum with a force that switches on and off with the position --------------
@pytest.fixture(scope="module")
def pendulum():
    return simulate(ks.load(SWITCHED), 3.0)  # the default RK45, rtol 1e-8


def test_switched_pendulum_conserves_energy_across_the_switches(pendulum):
    cols, _ = pendulum.table(points=301)
    x = TIP * np.cos(np.radians(cols["hinge.angle"]))
    assert x.min() < X2 < x.max()  # it enters and leaves the band
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
        sol = solve_ivp(
            lambda tt, yy, on=on: [
                yy[1],
                (-MGR * np.cos(yy[0]) - on * F * TIP * np.sin(yy[0])) / J_O,
            ],
            (t, t_end),
            y,
            method="DOP853",
            rtol=1e-13,
            atol=1e-13,
            dense_output=True,
            events=edge,
        )
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
    assert np.min(TIP * np.cos(ref[0])) > X1  # the far edge is never reached
    assert np.max(np.abs(ours[:, 0] - ref[0])) <= 1e-6
    assert np.max(np.abs(ours[:, 1] - ref[1])) <= 1e-6 * np.max(np.abs(ref[1]))


# -- the slotting machine with its flywheel under a constant moment -----------------
Q, H = 1000.0, 0.100  # the cutting force (N) over 0.9 H (m) per cycle


def flywheel_run(until, **options):
    """The slotting machine set free with its designed flywheel under the constant moment
    that does exactly the cutting work per turn, M_d = Q·0.9H/2π, started at ω_m at the
    start of cutting: frictionless, each cycle returns to the state it started from."""
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    fw = design(model)
    free = with_effort(
        model, fw.driver, EffortLaw("constant", value=fw.sense * Q * 0.9 * H / (2 * np.pi))
    )
    sim = simulate(
        free,
        until,
        initial={fw.driver: (fw.at_max, fw.sense * fw.omega_m)},
        inertia={fw.driver: fw.inertia_net},
        friction=False,
        mark=fw.at_max,
        **options,
    )
    return sim, fw


@pytest.fixture(scope="module")
def slotting():
    return flywheel_run(2.06)  # the defaults: RK45, rtol 1e-8


def test_slotting_machine_energy_across_the_cutting_switches(slotting):
    sim, fw = slotting
    assert len(sim.marks) == 3 and sim.marks[0] == 0.0  # two full turns
    period = sim.marks[1]
    t = np.concatenate(
        [np.linspace(k * period + 0.53, (k + 1) * period - 0.01, 40) for k in range(2)]
    )  # the idle part of each turn
    t = np.concatenate(([0.0], t, sim.marks[1:]))
    cols, _ = sim.table(t)
    e = cols["energy.kinetic"] + cols["energy.potential"] - cols["work.drivers"]
    done = np.concatenate(([0], np.repeat([1, 2], 40), [1, 2]))  # cuts completed
    assert np.max(np.abs(e - (e[0] - Q * 0.9 * H * done))) <= 1e-6 * e[0]


@pytest.fixture(scope="module")
def tight():
    return flywheel_run(2.06, method="DOP853", rtol=1e-12)


def test_slotting_machine_speed_returns_each_turn_and_is_continuous_at_the_switches(
    slotting, tight
):
    for (sim, fw), rel in ((slotting, 1e-6), (tight, 1e-9)):
        t = np.linspace(0.0, sim.t_end, 20001)
        w = np.abs(sim.sample(t)[:, 1])
        assert w.max() <= fw.omega_m * (1 + rel)  # the start is the top speed
        ends = np.abs(sim.sample(sim.marks)[:, 1])
        assert ends == pytest.approx(fw.omega_m, rel=rel)
        switches = [e["t"] for e in sim.events if e["kind"] == "switch"]
        assert len(switches) >= 10
        for te in switches:  # |ω̇| < 2 rad/s²: no jump in ω
            before, after = sim.sample([te - 1e-7, te + 1e-7])[:, 1]
            assert abs(after - before) <= 1e-6


def speed_extremes_attained(sim, d):
    """speed_fluctuation's ω_min and ω_max are values the solution takes: a fine grid
    (1e-8 s) around the sampled extreme comes within |ω̇|·1e-8 s of them from the
    inside (the minimum is at most, the maximum at least, the grid's)."""
    t = np.linspace(d["t0"], d["t1"], 20001)
    w = np.abs(sim.sample(t)[:, 1])
    for k, key in ((int(np.argmin(w)), "omega_min"), (int(np.argmax(w)), "omega_max")):
        fine = np.linspace(t[max(k - 1, 0)], t[min(k + 1, len(t) - 1)], 20001)
        wf = np.abs(sim.sample(fine)[:, 1])
        best = wf.min() if key == "omega_min" else wf.max()
        sign = 1.0 if key == "omega_max" else -1.0
        assert -1e-12 <= sign * (d[key] - best) <= 5e-8


def cycles(sim):
    return [speed_fluctuation(sim, a, b) for a, b in zip(sim.marks[:-1], sim.marks[1:])]


def test_speed_extremes_are_those_of_the_solution_and_repeat_each_turn(slotting, tight):
    for (sim, _), rel in ((slotting, 1e-6), (tight, 1e-9)):
        c = cycles(sim)
        assert len(c) == 2
        for d in c:
            speed_extremes_attained(sim, d)
        assert c[1]["omega_max"] == pytest.approx(c[0]["omega_max"], rel=rel)
        assert c[1]["omega_min"] == pytest.approx(c[0]["omega_min"], rel=rel)
        assert c[1]["delta"] == pytest.approx(c[0]["delta"], abs=rel)


def test_speed_fluctuation_does_not_depend_on_the_integrator(slotting, tight):
    ours, ref = cycles(slotting[0]), cycles(tight[0])
    assert [d["delta"] for d in ours] == pytest.approx([d["delta"] for d in ref], abs=3e-8)


# -- the slider-crank under a constant torque against its working-stroke resistance ---
def test_slider_crank_energy_across_the_working_stroke_switches():
    """T + V − W_drivers = E₀ − Q·S·(working strokes completed) on every return stroke:
    the resistance Q acts over the whole stroke S = √((a+b)² − e²) − √((b−a)² − e²)."""
    model = variant("slider_crank", motion=(r"motion: \{speed: 300\}", "effort: 40"))
    sim = simulate(model, 0.35, friction=False)
    t = np.linspace(0.0, 0.35, 351)
    cols, _ = sim.table(t)
    p = cf.SliderCrank(omega1=1.0)
    phi = np.radians(cols["motor.angle"])
    v = cf.kinematics(p, phi)["vB"] * cols["motor.speed"]  # closed-form slider speed
    assert cols["motor.speed"].min() >= 0
    done = np.concatenate(([0], np.cumsum((v[:-1] > 0) & (v[1:] <= 0))))  # right dead centres
    back = v < 0
    stroke = np.sqrt((p.a + p.b) ** 2 - p.e**2) - np.sqrt((p.b - p.a) ** 2 - p.e**2)
    e = cols["energy.kinetic"] + cols["energy.potential"] - cols["work.drivers"]
    assert done[-1] >= 3 and back.sum() > 100
    assert np.max(np.abs(e - (e[0] - 1000.0 * stroke * done))[back]) <= (
        1e-6 * cols["energy.kinetic"].max()
    )


def test_a_stop_on_a_load_switch_is_not_run_past():
    """Started exactly where the cutting force switches on and stopped one turn later, at
    the same switch: the piece ends at the switch and the stop there is still taken (it
    lies at the next piece's start, where an event function's root is not seen)."""
    model = ks.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    fw = design(model)
    on = fw.at_max  # the largest stored energy: where cutting starts (the moment jumps)
    assert any(abs(on - e) < 1e-9 for e in fw.events)
    free = with_effort(model, fw.driver, EffortLaw("constant", value=fw.sense * fw.mean_torque))
    period = 2 * np.pi / fw.omega_m
    stop = on + fw.sense * 2 * np.pi
    sim = simulate(
        free,
        6 * period,
        initial={fw.driver: (on, fw.sense * fw.omega_m)},
        inertia={fw.driver: fw.inertia_net},
        stop_at=stop,
        mark=on,
        ref_speed=fw.omega_m,
        method="RK45",
        rtol=1e-8,
        friction=False,
    )
    assert sim.status == "stopped"
    assert sim.t_end == pytest.approx(period, rel=0.05)  # one turn at about ω_m
    assert sim.events[-1]["kind"] == "stop"
