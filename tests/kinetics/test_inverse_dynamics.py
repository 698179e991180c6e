"""Inverse dynamics at arbitrary driver states (positions_near + kinetics)."""

import numpy as np

import kinetostatics as ks
from kinetostatics.analysis.pipeline import kinetics
from kinetostatics.kinematics.positions import derivatives, positions_near
from kinetostatics.kinematics.schedule import schedule
from kinetostatics.structure.system import phi as residual
from tests.oracles import slider_crank_closed_form as cf


def test_torque_increment_is_equivalent_inertia_times_crank_acceleration():
    """τ(φ, ω, α) − τ(φ, ω, 0) = J_e(φ) α, J_e = Σ m (v_S/ω)² + J (ω_k/ω)² (closed form)."""
    system = ks.build_system(ks.load("mechanisms/slider_crank.yaml"))
    base = ks.analyze(system, friction=False)
    phi = np.radians(np.arange(0, 360, 7.0))
    w, alpha = 31.4, 250.0
    q = positions_near(system, phi[:, None], base.q[np.arange(0, 360, 7)], schedule(system))
    taus = []
    for acc in (0.0, alpha):
        psi = phi[:, None]
        qd, qdd, lu = derivatives(system, q, np.full_like(psi, w), np.full_like(psi, acc))
        kin = kinetics(system, q, qd, qdd, psi, lu=lu, ref_speed=w, extremes=base.extremes)
        taus.append(kin.x0[:, -1])
    p = cf.SliderCrank(omega1=1.0)
    k = cf.kinematics(p, phi)
    j_e = (
        p.m1 * (k["S1_vx"] ** 2 + k["S1_vy"] ** 2)
        + p.J1
        + p.m2 * (k["S2_vx"] ** 2 + k["S2_vy"] ** 2)
        + p.J2 * k["omega2"] ** 2
        + p.m3 * k["vB"] ** 2
    )
    np.testing.assert_allclose(taus[1] - taus[0], j_e * alpha, rtol=1e-10)


def test_positions_near_follows_the_guess_branch():
    system = ks.build_system(ks.load("tests/hard/fourbar_change_point.yaml"))
    r = ks.analyze(system, positions=np.radians([100.0]))
    q = positions_near(system, np.radians([[101.0]]), r.q, schedule(system))
    assert np.max(np.abs(q - r.q)) < 0.05  # one degree away: a nearby pose
    assert np.max(np.abs(residual(system, q, np.radians([[101.0]])))) < 1e-12


def test_inverse_dynamics_of_a_motion_record_is_frozen_and_balances_power():
    """The stages' records: the Motion of the kinematic stage gives, through the four stages,
    a frozen Kinetics whose power terms are a read-only mapping that balances (the drive's
    input equals the rates of kinetic and potential energy plus the external loads' and the
    friction loss: the work–energy theorem); kinetics() from the loose arrays is the same."""
    import dataclasses

    import pytest

    from kinetostatics.kinematics.motion import motion_at
    from kinetostatics.kinetics.inverse import inverse_dynamics

    system = ks.build_system(ks.load("mechanisms/slotting_machine.yaml"))
    base = ks.analyze(system, friction=False)
    sched = schedule(system)
    motion = motion_at(system, sched, base.t[::6], base.q[::6])
    kin = inverse_dynamics(
        system, motion, ref_speed=sched.reference, extremes=base.extremes, friction=True
    )
    with pytest.raises(dataclasses.FrozenInstanceError):
        kin.power = None
    with pytest.raises(dataclasses.FrozenInstanceError):
        motion.q = None
    p = kin.power
    assert list(p)[:4] == ["input", "kinetic", "potential", "external"]
    assert {"friction", "residual_friction"} <= set(p) and "elastic" not in p
    scale = np.max(np.abs(p["input_friction"]))
    balance = p.kinetic + p.potential + p.external + p.friction
    assert np.max(np.abs(p.input_friction - balance)) <= 1e-9 * scale
    assert kin.friction.solution is kin.friction["solution"]
    old = kinetics(
        system,
        motion.q,
        motion.qd,
        motion.qdd,
        motion.psi,
        lu=motion.lu,
        ref_speed=sched.reference,
        extremes=base.extremes,
        friction=True,
    )
    np.testing.assert_allclose(old.friction.solution.x, kin.friction.solution.x, rtol=1e-12)


def test_a_singular_equilibrium_names_each_position_once():
    """Nodes of the cycle integral on both sides of one dead centre print the same angle:
    the warning listed "175.411°, 175.411°, 357.453°, 357.453°"; each text once, and "and
    N more" counts distinct positions."""
    import warnings

    import pytest

    from kinetostatics.errors import SingularEquilibriumWarning
    from kinetostatics.kinetics.inverse import _warn_singular_equilibrium
    from kinetostatics.structure.system import build_system
    from tests.helpers import ROOT

    system = build_system(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"))
    coord = np.radians([175.4110001, 175.4110002, 357.453, 357.4530001, 10.0])
    with pytest.warns(SingularEquilibriumWarning) as got:
        _warn_singular_equilibrium(system, np.array([True, True, True, True, False]), coord)
    text = str(got[0].message)
    assert "= 175.411°, 357.453°: " in text
    coord = np.radians(np.repeat(np.arange(10.0, 110.0, 10.0), 2))
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        _warn_singular_equilibrium(system, np.ones(20, dtype=bool), coord)
    assert "= 10°, 20°, 30°, 40°, 50°, 60°, 70°, 80° and 2 more: " in str(got[0].message)
