"""Forward dynamics from the inverse-dynamics engine (kinetostatics.dynamics).

Energy is conserved without friction or load (a pendulum, a coasting
slider-crank) to the integrator's tolerance; a constant-torque start-up of the
slider-crank matches an independent integration of Lagrange's equation built
from the closed-form kinematics; a mixed case (prescribed crank, free arm)
matches its hand-written equation of motion; friction: breakaway from rest and
the consistent acceleration.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp, trapezoid
from scipy.special import ellipk

import kinetostatics as ks
from kinetostatics.analysis.pipeline import kinetics
from kinetostatics.dynamics import Dynamics, equivalent, simulate
from kinetostatics.io import dump
from kinetostatics.kinematics.positions import derivatives
from kinetostatics.model import EffortLaw
from tests.helpers import ROOT, variant
from tests.oracles import slider_crank_closed_form as cf

PENDULUM = ROOT / "tests" / "dynamics" / "pendulum.yaml"
NO_FRICTION = dict(
    fr1=(r", friction: \{radius: [\d.]+\}", ""), fr2=(r"    friction: \{coefficient: 0.10\}\n", "")
)
NO_LOAD = dict(load=(r"loads:\n(?:(?:  |    |      ).*\n)*", ""))


def free_slider_crank(effort: str, friction=False, load=False) -> ks.Model:
    edits = dict(motion=(r"motion: \{speed: 300\}", f"effort: {effort}"))
    if not friction:
        edits.update(NO_FRICTION)
    if not load:
        edits.update(NO_LOAD)
    return variant("slider_crank", **edits)


def test_pendulum_conserves_energy_and_has_the_exact_period():
    model = ks.load(PENDULUM)
    sim = simulate(model, 14.0, method="DOP853", rtol=1e-10)
    cols, _ = sim.table(points=401)
    e = cols["energy.total"]
    swing = np.ptp(cols["energy.kinetic"])
    assert np.max(np.abs(e - e[0])) <= 1e-8 * swing  # ~12 periods
    # period of a compound pendulum of amplitude 30° about the vertical
    j_o, mgl = 0.02 + 2 * 0.3**2, 2 * 9.81 * 0.3
    period = 4 * ellipk(np.sin(np.radians(30) / 2) ** 2) / np.sqrt(mgl / j_o)
    t = np.linspace(0, 14, 140_001)
    w = sim.sample(t)[:, 1]
    k = np.nonzero((w[:-1] < 0) & (w[1:] >= 0))[0]  # through the lowest speed
    up = t[k] - w[k] * (t[k + 1] - t[k]) / (w[k + 1] - w[k])
    assert len(up) >= 11
    assert np.diff(up).mean() == pytest.approx(period, rel=1e-6)


def test_coasting_slider_crank_conserves_energy_over_many_cycles():
    model = free_slider_crank("0")
    sim = simulate(model, 1.2, initial={"motor": (0.0, 80.0)}, method="DOP853", rtol=1e-9)
    cols, _ = sim.table(points=241)
    assert cols["motor.angle"][-1] > 10 * 360  # > 10 revolutions
    e = cols["energy.total"]
    assert np.max(np.abs(e - e[0])) <= 3e-7 * e.max()  # ~ rtol × steps
    assert np.ptp(cols["motor.speed"]) > 1.0  # the speed does vary
    assert np.all(cols["work.drivers"] == 0.0)


def lagrange(torque: float, t_end: float):
    """J_e(φ) φ̈ + ½ J_e'(φ) φ̇² = τ + Σ m g·v_S (per unit φ̇), by hand from the closed form."""
    p = cf.SliderCrank(omega1=1.0)

    def rhs(t, y):
        k = cf.kinematics(p, y[0])  # velocities per unit crank speed, a = d v/dφ
        j_e = (
            p.m1 * (k["S1_vx"] ** 2 + k["S1_vy"] ** 2)
            + p.J1
            + p.m2 * (k["S2_vx"] ** 2 + k["S2_vy"] ** 2)
            + p.J2 * k["omega2"] ** 2
            + p.m3 * k["vB"] ** 2
        )
        dj_e = 2 * (
            p.m1 * (k["S1_vx"] * k["S1_ax"] + k["S1_vy"] * k["S1_ay"])
            + p.m2 * (k["S2_vx"] * k["S2_ax"] + k["S2_vy"] * k["S2_ay"])
            + p.J2 * k["omega2"] * k["alpha2"]
            + p.m3 * k["vB"] * k["aB"]
        )
        gravity = (
            p.m1 * (p.g[0] * k["S1_vx"] + p.g[1] * k["S1_vy"])
            + p.m2 * (p.g[0] * k["S2_vx"] + p.g[1] * k["S2_vy"])
            + p.m3 * p.g[0] * k["vB"]
        )
        return [y[1], (torque + gravity - 0.5 * dj_e * y[1] ** 2) / j_e]

    return solve_ivp(
        rhs, (0, t_end), [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-13, dense_output=True
    )


def test_constant_torque_start_up_matches_lagrange():
    model = free_slider_crank("5")
    sim = simulate(model, 0.5, method="DOP853", rtol=1e-11)
    ref = lagrange(5.0, 0.5)
    t = np.linspace(0, 0.5, 51)
    ours, exact = sim.sample(t), ref.sol(t)
    assert exact[1, -1] > 40  # it spun up (rad/s)
    assert np.max(np.abs(ours[:, 0] - exact[0])) <= 1e-8 * exact[0, -1]
    assert np.max(np.abs(ours[:, 1] - exact[1])) <= 1e-8 * exact[1].max()
    assert sim.events[0]["kind"] == "rest" and sim.events[0]["sense"] == 1.0
    cols, _ = sim.table(t)
    # energy balance: the drivers' work (integrated with the state) = ΔT + ΔV
    e = cols["energy.total"]
    assert np.max(np.abs(e - e[0] - cols["work.drivers"])) <= 1e-8 * e.max()


def test_mixed_case_prescribed_crank_free_arm():
    """A pendulum on a crank pin turning at 60 rpm: (J + m l²) θ̈ = m l u × (g − a_A)."""
    model = ks.load(ROOT / "tests" / "dynamics" / "driven_pendulum.yaml")
    sim = simulate(model, 2.0, method="DOP853", rtol=1e-10)
    r, w, m, arm, j = 0.1, 2 * np.pi, 1.0, 0.2, 0.01

    def rhs(t, y):
        u = np.array([np.cos(y[0]), np.sin(y[0])])
        a = -r * w**2 * np.array([np.cos(w * t), np.sin(w * t)])
        rel = np.array([0.0, -9.81]) - a
        return [y[1], m * arm * (u[0] * rel[1] - u[1] * rel[0]) / (j + m * arm * arm)]

    ref = solve_ivp(
        rhs, (0, 2), [-np.pi / 2, w], method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True
    )
    t = np.linspace(0, 2, 41)
    psi = sim.sample(t)[:, 0]
    theta = psi + w * t + np.pi  # arm angle = hinge angle + angle of A -> O
    assert np.max(np.abs(theta - ref.sol(t)[0])) < 1e-7


def test_equivalent_inertia_and_torque_reproduce_the_inverse_dynamics():
    system = ks.build_system(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"))
    base = ks.analyze(system, friction=False)
    k = np.arange(0, 360, 11)
    q, phi = base.q[k], base.coordinate[k]
    w, alpha = 31.4, -120.0
    eq = equivalent(system, q, phi, speed=w, extremes=base.extremes)
    p = cf.SliderCrank(omega1=1.0)
    c = cf.kinematics(p, phi)
    j_e = (
        p.m1 * (c["S1_vx"] ** 2 + c["S1_vy"] ** 2)
        + p.J1
        + p.m2 * (c["S2_vx"] ** 2 + c["S2_vy"] ** 2)
        + p.J2 * c["omega2"] ** 2
        + p.m3 * c["vB"] ** 2
    )
    np.testing.assert_allclose(eq["inertia"], j_e, rtol=1e-10)
    qd, qdd, lu = derivatives(system, q, np.full((len(k), 1), w), np.full((len(k), 1), alpha))
    tau = kinetics(system, q, qd, qdd, phi[:, None], lu=lu, ref_speed=w, extremes=base.extremes).x0[
        :, -1
    ]
    np.testing.assert_allclose(
        eq["inertia"] * alpha + 0.5 * eq["inertia_derivative"] * w**2 - eq["torque"],
        tau,
        rtol=1e-10,
        atol=1e-10 * np.abs(tau).max(),
    )


def test_effort_laws_from_yaml_and_their_values():
    base = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    for spec, psi, w, expected in (
        ("{table: {at: [0, 180], value: [10, 30]}}", np.radians(90), 0.0, 20.0),
        ("{table: {at: [0, 180], value: [10, 30]}}", np.radians(270), 0.0, 20.0),
        ("{motor: {torque: 12, speed: 300, slip: 0.05}}", 0.0, 0.95 * 10 * np.pi, 24.0),
        ("{curve: {speed: [0, 300], torque: [40, 0]}}", 0.0, 5 * np.pi, 20.0),
    ):
        model = ks.loads(base.replace("motion: {speed: 300}", f"effort: {spec}"), file="e.yaml")
        law = model.drivers[0].effort
        assert isinstance(law, EffortLaw)
        assert float(law(psi, w)) == pytest.approx(expected)
        assert ks.loads(dump(model)).drivers[0].effort == law  # round trip
    with pytest.raises(ks.ModelError, match="exactly one of table"):
        ks.loads(base.replace("motion: {speed: 300}", "effort: {}"), file="e.yaml")
    with pytest.raises(ks.ModelError, match="slip: must be positive"):
        ks.loads(
            base.replace(
                "motion: {speed: 300}", "effort: {motor: {torque: 1, speed: 300, slip: 0}}"
            ),
            file="e.yaml",
        )


def test_motor_curve_start_up_settles_at_the_speed_where_the_curve_meets_the_load():
    """Under τ(ω) = M[1 + (ω_n − ω)/(s ω_n)] and a constant load torque T_L on the crank
    (no gravity), the speed settles where τ(ω) = T_L."""
    m, s, rpm, load = 2.0, 0.1, 480.0, 1.0
    model = variant(
        "slider_crank",
        **NO_FRICTION,
        motion=(
            r"motion: \{speed: 300\}",
            f"effort: {{motor: {{torque: {m}, speed: {rpm}, slip: {s}}}}}",
        ),
        gravity=(r"gravity: \[0, -9.81\]", "gravity: [0, 0]"),
        load=(
            r"loads:\n(?:(?:  |    |      ).*\n)*",
            f"loads:\n  brake: {{type: torque, link: crank, value: {-load}}}\n",
        ),
    )
    sim = simulate(model, 1.6, rtol=1e-8, mark=0.0)
    w_n = rpm * np.pi / 30
    t = np.linspace(sim.marks[-2], sim.marks[-1], 20001)  # the last whole revolution
    w = sim.sample(t)[:, 1]
    # the work balance over a whole cycle fixes the angle-average of ω: ∫ω² dt / ∫ω dt
    assert trapezoid(w**2, t) / trapezoid(w, t) == pytest.approx(
        w_n * (1 + s * (1 - load / m)), rel=3e-5
    )  # the start-up has decayed
    assert np.ptp(w) > 0.5 * w.mean()  # while the speed fluctuates strongly


def test_friction_breakaway_and_consistent_acceleration():
    dyn = Dynamics(free_slider_crank("0", friction=True))
    check = dyn.breakaway(0.0, [0.0])
    need_pos, need_neg = check["to_start_positive"], check["to_start_negative"]
    h = Dynamics(free_slider_crank("0")).breakaway(0.0, [0.0])["to_start_positive"]
    assert need_neg < h < need_pos  # friction holds either way
    stuck = simulate(free_slider_crank(f"{h + 0.5 * (need_pos - h)}", friction=True), 0.2)
    assert stuck.stuck and stuck.events[0]["sense"] == 0.0
    assert simulate(free_slider_crank(f"{h + 0.5 * (need_pos - h)}"), 0.01).events[0]["sense"] == 1
    model = free_slider_crank(f"{need_pos + 2.0}", friction=True)
    dyn = Dynamics(model)
    sim = simulate(dyn, 0.3, rtol=1e-8)
    assert sim.events[0]["sense"] == 1.0 and not sim.stuck
    # at a moving state the solved acceleration makes the consistent friction effort = applied
    y = sim.sample([0.3])[0]
    ev = dyn.state(0.3, y)
    applied = need_pos + 2.0
    assert dyn._required_friction(ev, ev.accel)[0] == pytest.approx(applied, rel=1e-10)
    frictionless_acc = (applied - ev.tau0[0]) / ev.dtau[0, 0]
    assert ev.accel[0] < frictionless_acc  # friction slows the start-up


def test_free_coordinates_are_checked():
    with pytest.raises(ks.StructureError, match="nothing to simulate"):
        Dynamics(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"))
    text = (ROOT / "tests" / "dynamics" / "driven_pendulum.yaml").read_text()
    with pytest.raises(ks.StructureError, match="one free coordinate and no prescribed"):
        Dynamics(
            ks.loads(
                text.replace("links: [crank, arm]}", "links: [crank, arm], friction: {radius: 1}}")
            )
        )
    with pytest.raises(ks.StructureError, match="one driver per degree of freedom"):
        Dynamics(ks.loads(text.replace("  motor: {joint: O, motion: {speed: 60}}\n", "")))


def test_cli_simulate_writes_csv_and_plot(tmp_path, capsys):
    from kinetostatics.cli import main

    assert (
        main(["simulate", str(PENDULUM), "--until", "1", "--out", str(tmp_path), "--points", "11"])
        == 0
    )
    lines = (tmp_path / "simulation.csv").read_text().splitlines()
    assert lines[1].split(",")[:5] == [
        "time",
        "hinge.angle",
        "hinge.speed",
        "hinge.acceleration",
        "hinge.torque",
    ]
    assert len(lines) == 2 + 11
    assert (tmp_path / "simulation.png").stat().st_size > 0
    assert (
        main(
            [
                "simulate",
                str(ROOT / "mechanisms" / "slider_crank.yaml"),
                "--until",
                "1",
                "--out",
                str(tmp_path),
            ]
        )
        == 2
    )
    assert "nothing to simulate" in capsys.readouterr().err
