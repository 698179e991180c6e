"""The relative-motion terms of the higher pairs (``relative_motion`` of the gear pair, the
rack and the cam; issue 38) against rigid-body kinematics written out here.

At any poses of the two links (the centre distance not held: the general terms) and any
rates that satisfy the pair's own velocity and acceleration rows (Φ_q q̇ = 0,
Φ_q q̈ = γ: the only thing the terms may assume), the terms sum to the relative velocity
and acceleration of the two links' material points at the pair's point,
v_P(j) − v_P(i) and a_P(j) − a_P(i), each computed from the links' own rates.  While the
distance is held the only term is the normal acceleration of rolling, whose closed form
(ω_i² r_i + ω_j² r_j for gears on fixed centres, ω² r for a pinion over a still rack) is
checked on the shipped geared five-bar and rack-and-rocker files; the cam's on the shipped
cam files (the pitch curve's radius from the pipeline's ``curvature_radius`` column)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.analysis.pipeline import analyze
from kinetostatics.base.geometry import perp
from kinetostatics.joints.gear import Gear
from kinetostatics.joints.rack import Rack
from tests.helpers import ROOT

TOL = 1e-12


def _joint(stem, kind):
    model = ks.load(ROOT / "mechanisms" / f"{stem}.yaml")
    return next(j for j in model.joints if isinstance(j, kind))


def _point(q, v, a, p):
    r = p - q[:2]
    return v[:2] + v[2] * perp(r), a[:2] + a[2] * perp(r) - v[2] ** 2 * r


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def _consistent(joint, rng):
    """Poses off the held distance and rates that satisfy the pair's rows: ω_j and α_j
    are solved from Φ_q q̇ = 0 and Φ_q q̈ = γ."""
    qi = np.array([0.01, -0.02, 0.3]) + rng.normal(scale=[0.01, 0.01, 0.5])
    qj = np.array([0.16, 0.03, -0.7]) + rng.normal(scale=[0.01, 0.01, 0.5])
    vi, vj, ai, aj = (rng.normal(size=3) for _ in range(4))
    Ji, Jj = (J[0] for J in joint.jacobian(qi, qj))
    vj[2] = -(Ji @ vi + Jj[:2] @ vj[:2]) / Jj[2]
    gamma = joint.acceleration_rhs(qi, qj, vi, vj)[0]
    aj[2] = (gamma - Ji @ ai - Jj[:2] @ aj[:2]) / Jj[2]
    return qi, qj, vi, vj, ai, aj


@pytest.mark.parametrize("stem, kind", [("geared_fivebar", Gear), ("rack_rocker", Rack)])
def test_the_terms_are_the_relative_motion_of_the_material_points(stem, kind):
    joint = _joint(stem, kind)
    rng = np.random.default_rng(38)
    for _ in range(20):
        qi, qj, vi, vj, ai, aj = _consistent(joint, rng)
        m = joint.relative_motion(qi, qj, vi, vj, ai, aj, ("1", "2"))
        (vpi, api), (vpj, apj) = _point(qi, vi, ai, m.point), _point(qj, vj, aj, m.point)
        v = sum((t.vector for t in m.velocity), np.zeros(2))
        a = sum((t.vector for t in m.acceleration), np.zeros(2))
        assert len(m.velocity) == 1 and len(m.acceleration) == 3  # the distance changes
        scale_v = max(np.hypot(*vpi), np.hypot(*vpj))
        scale_a = max(
            np.hypot(*api), np.hypot(*apj), *(np.hypot(*t.vector) for t in m.acceleration)
        )
        assert np.hypot(*(v - (vpj - vpi))) <= TOL * scale_v
        assert np.hypot(*(a - (apj - api))) <= TOL * scale_a


def test_gears_on_fixed_centres_have_only_the_normal_term_of_rolling():
    """The geared five-bar's two cranks on the frame: a_PjPi = ω1² r1 + ω2² r2 (r = 75 mm
    both), along the line of centres towards O2."""
    result = analyze(ks.load(ROOT / "mechanisms" / "geared_fivebar.yaml"), kinematics_only=True)
    system = result.system
    k = next(n for n, j in enumerate(system.joints) if isinstance(j, Gear))
    joint = system.joints[k]
    i, j = (int(e) for e in system.ends[k])
    r = 0.075
    for row in (5, len(result.t) // 3, 2 * len(result.t) // 3):
        q, v, a = (np.asarray(x[row]).reshape(-1, 3) for x in (result.q, result.qd, result.qdd))
        m = joint.relative_motion(q[i], q[j], v[i], v[j], a[i], a[j], ("1", "2"))
        assert m.velocity == () and len(m.acceleration) == 1
        (term,) = m.acceleration
        w1, w2 = v[i, 2], v[j, 2]
        assert np.hypot(*term.vector) == pytest.approx(w1**2 * r + w2**2 * r, rel=1e-9)
        O1, O2 = (c.centre for c in joint.glyph(q[i], q[j]).circles)
        assert np.dot(term.vector, O2 - O1) > 0 and abs(_cross(term.vector, O2 - O1)) <= (
            1e-9 * np.hypot(*term.vector) * np.hypot(*(O2 - O1))
        )


def test_a_rollers_terms_from_the_pipelines_columns():
    """The shipped roller cam (the cam turning about O on the frame, the follower sliding in
    a guide on the frame): the roller centre C's velocity relative to the cam is
    v_r = v_C − ω × OC, along the pitch curve's tangent (normal to the contact normal);
    its normal term is v_r²/ρ_p with ρ_p = the profile's ``curvature_radius`` + r_r; its
    Coriolis term 2ω·v_r."""
    from kinetostatics.joints.cam import Cam

    result = analyze(ks.load(ROOT / "mechanisms" / "cam_roller.yaml"), kinematics_only=True)
    system = result.system
    k = next(n for n, j in enumerate(system.joints) if isinstance(j, Cam))
    joint = system.joints[k]
    i, j = (int(e) for e in system.ends[k])
    rr = joint.synthesis.radius
    for row in (7, len(result.t) // 5, len(result.t) // 2 + 3):
        q, v, a = (np.asarray(x[row]).reshape(-1, 3) for x in (result.q, result.qd, result.qdd))
        m = joint.relative_motion(q[i], q[j], v[i], v[j], a[i], a[j], ("1", "2"))
        C = np.array([result["follower.C.x"][row], result["follower.C.y"][row]])
        vC = np.array([result["follower.C.vx"][row], result["follower.C.vy"][row]])
        w = result["cam.omega"][row]
        pivot = np.array([result["cam.O.x"][row], result["cam.O.y"][row]])
        v_r = vC - w * perp(C - pivot)
        assert np.allclose(m.point, C, rtol=0, atol=1e-12)
        (vel,) = m.velocity
        normal, tangential, coriolis = m.acceleration
        assert np.hypot(*(vel.vector - v_r)) <= 1e-9 * np.hypot(*v_r)
        rho = result["contact.curvature_radius"][row] + rr
        speed = np.hypot(*v_r)
        assert np.hypot(*normal.vector) == pytest.approx(speed**2 / abs(rho), rel=1e-9)
        assert np.hypot(*coriolis.vector) == pytest.approx(2 * abs(w) * speed, rel=1e-9)
        assert abs(np.dot(coriolis.vector, v_r)) <= 1e-9 * np.hypot(*coriolis.vector) * speed
