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
